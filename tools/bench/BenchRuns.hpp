#pragma once
// How flexmb_bench integrates. A run that stands for `flexmb simulate` goes through simulate's own
// recipe, analysis::simulate with SimulationOptions (recipeOptions), stopped at a wall-time cap
// through SimulationOptions::interrupt (runCapped). The one variant simulate cannot run stays the
// bench's own: CVODE with its difference-quotient Jacobian (runCvodeDifferenceQuotients).
#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "analysis/Simulation.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::bench {

// simulate's options for a bench run, each set as the command line sets it: the integrator, BDF's
// highest order (0: simulate's default, --bdf-order 2) and generalized-alpha's rho_inf (NaN:
// simulate's default, --rho-inf 0.8), the tolerances, the file's span, output times and step bound
// (simulate's without --t-end, --intervals, --max-step), the basis (none: the full model), no
// operators, the automatic dynamics form, no progress line, the states kept, no accuracy check and
// no reduction error estimate (the bench asks for them where it reports them).
analysis::SimulationOptions recipeOptions(const core::Model& model, analysis::Integrator integrator, double relTol,
                                          double absTol, const std::optional<Eigen::MatrixXd>& basis = std::nullopt,
                                          int bdfMaxOrder = 0, double rhoInf = NAN);

constexpr double kNoCap = INFINITY;

// One run of the recipe. The cap: a watchdog thread sets SimulationOptions::interrupt after
// capSeconds and the run stops at its next check, keeping what it reached (as after Ctrl-C).
struct CappedRun {
  core::Trajectory trajectory;
  double wall = NAN;    // seconds: simulate's set-up (equations of motion, Jacobian) and integration
  bool capped = false;  // stopped at the cap
  std::string reason;   // why it did not complete: "stopped at the N s cap ...", the stop reason, a set-up error
  bool completed() const { return reason.empty(); }
};
CappedRun runCapped(const core::Model& model, analysis::SimulationOptions options, double capSeconds);

// CVODE's BDF (orders 1-maxOrder) with its difference-quotient Jacobian (2m right-hand sides per
// Jacobian) on the full model. Not the recipe: simulate's bdf always gives CVODE the analytic
// Jacobian of Eq. 15 (analysis::StateJacobian) and SimulationOptions has no setting for difference
// quotients; the bench keeps this variant to measure what the analytic Jacobian saves. Otherwise as
// simulate's bdf: the same right-hand side with the kinematics anchored at the accepted states
// (analysis::AnchoredDynamics), the same tolerances, step bound and output times, simulate's
// kinematic tolerance; the cap is checked every 256 right-hand sides.
struct OwnRun {
  double relTol = 0.0;
  std::string reason;  // why it stopped ("" when it completed)
  long fevals = 0;     // every right-hand side, the difference-quotient ones included
  long jacFevals = 0;  // those spent on Jacobians
  long nsteps = 0, nfailed = 0, njac = 0;
  double wall = NAN;  // seconds: set-up and integration, the states stored at the output times
  std::vector<double> t;
  std::vector<Eigen::VectorXd> y;
};
OwnRun runCvodeDifferenceQuotients(const core::Model& model, double relTol, double absTol, int maxOrder,
                                   double capSeconds);

// The run's states as simulate keeps them (the output quantities at its output times, evaluated
// afterwards at simulate's kinematic tolerance) and the accuracy check's windows from them.
core::Trajectory statesOf(const core::Model& model, const OwnRun& run, analysis::DeferredAccuracy& windows);

}  // namespace flexmb::bench
