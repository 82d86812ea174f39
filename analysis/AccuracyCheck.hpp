#pragma once
// The a-posteriori accuracy check of a simulation (issue 24): is the result converged, i.e. would a
// tighter tolerance change it? The integrators control the local error of each step, not the
// global error of the run: on a stiff full model at a loose tolerance (the manipulator at RelTol
// 1e-2) a run can end far from the solution and still report every step accepted.
//
// The check integrates three short windows of the run again, each from the run's own state at its
// start, with the same integrator at a 10x tighter tolerance, and compares the nodal coordinates
// at the window's end (positions relative to the model size, angles in rad). The difference is the
// error the run made within the window (the reference's is about 10x smaller: RelTol means the
// global error of ode45 and galpha; at 100x the estimates agreed to two digits on the guidance,
// manipulator and elbow at up to 30x the cost, issue 48); its largest rate per
// second times the span estimates the run's global error (errors made along the run add up; a
// damped model forgets them, an unstable one amplifies them: it is an estimate, not a bound).
// Cost: the windows cover a tenth of the span (a stiff full model's steps are bounded by
// stability, not accuracy, so the tighter tolerance costs little more per second; an
// accuracy-bound reduced model needs about 10^(1/5) = 1.6x the steps per second at ode45's order).
//
// Why not the alternatives: the embedded pair's error estimates summed over the steps count the
// stiff components' tolerance-level noise at every one of 10^5 stability-bound steps (a warning
// on every full model) and miss the drift of the slow motion; the energy balance needs a
// conservative model (the paper's two are driven by a force and by controllers).
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct SimulationOptions;

// A stretch of the run between two of its output times: the states y = [eta; etad] and the nodal
// coordinates at both ends (the window's kinematics start from xa; the reference's end is solved
// from xb, near it: a mechanism may have turned far from its initial configuration).
struct AccuracyWindow {
  double ta = 0.0, tb = 0.0;
  Eigen::VectorXd ya, yb, xa, xb;
};

// Picks the windows from the output times as the run passes them: three, centred at 1/6, 1/2 and
// 5/6 of the span, each from the first output time at or after its start to the first one at least
// a thirtieth of the span later (a coarse output grid makes them longer).
class AccuracyWindowRecorder {
 public:
  AccuracyWindowRecorder(double t0, double tEnd);
  void observe(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& x);
  // Whether observe at t would keep the state (a window's start or end): a run that computes x
  // only where needed asks first.
  bool wantsAt(double t) const;
  std::vector<AccuracyWindow> complete() const;

 private:
  struct Slot {
    double start = 0.0;
    AccuracyWindow window;
    bool started = false, ended = false;
  };
  double length_;
  std::vector<Slot> slots_;
};

// The run's tolerance divided by this is the reference's.
constexpr double kAccuracyReferenceFactor = 10.0;

// Runs the windows again (options: the run's, with its integrator, basis and tolerances) and
// estimates the global error over [t0, tEnd]. limit: the estimate above which the run is not
// converged, 10 RelTol (a converged run's error is of the order of its tolerance) but at least 1e-6.
// Never throws for a numerical failure: a check that cannot run returns checked = false with the
// reason in note, and the run it checks stands. galphaFrom: where an auto run switched to galpha;
// its windows from there on are run again with galpha, the integrator that made them (auto would
// restart ode45, which at the tighter tolerance can stay accuracy-bound for the whole window:
// 11 s of ode45 on the elbow's windows where galpha takes 0.1 s).
core::AccuracyEstimate checkAccuracy(const core::Model& model, const SimulationOptions& options, double t0, double tEnd,
                                     const std::vector<AccuracyWindow>& windows,
                                     double galphaFrom = std::numeric_limits<double>::infinity());

// The check's result in one line for the screen and the manifest: "converged: ...", "NOT
// CONVERGED: ..." or "not checked: <reason>".
std::string describeAccuracy(const core::AccuracyEstimate& a);

}  // namespace flexmb::analysis
