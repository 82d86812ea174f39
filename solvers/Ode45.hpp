// Ode45: MATLAB's ode45 (Dormand-Prince 5(4), FSAL, local extrapolation) reproduced step by step.
// The contract: the same accepted and rejected steps and function-evaluation counts as MATLAB's.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "solvers/OdeTypes.hpp"

namespace flexmb::solvers {

struct Ode45Options {
  double relTol = 1e-3;      // raised to 100*eps if smaller
  Eigen::VectorXd absTol;    // empty -> 1e-6 for all; size 1 -> scalar; size n -> per component
  double maxStep = 0.0;      // 0 -> 0.1*|tf-t0|; a user value is clipped to |tf-t0|
  double initialStep = 0.0;  // 0 -> automatic rule of docs/theory/ode45.md
  int refine = 4;            // used when tspan has exactly 2 entries
  // Called after every accepted step (after its hook and outputs) with the new state, the step
  // size and h |lambda|, |lambda| = |f(ynew) - f(y6)| / |ynew - y6| estimating the dominant
  // eigenvalue of df/dy from the two stages at t + h (Hairer's stiffness test of DOPRI5, Hairer &
  // Wanner, Solving ODEs II, Sec. IV.2): near 3.3 and above, the step sits at the stability
  // boundary. Returning false stops the run there (status Stopped, every output up to t given).
  // Empty: nothing is computed (MATLAB's ode45 has no such test; the steps do not depend on it).
  std::function<bool(double t, const Eigen::VectorXd& y, double h, double hLambda)> stepMonitor;
};

class Ode45 {
 public:
  explicit Ode45(Ode45Options options = {});

  // tspan = [t0, tf]: Refine output (1 + refine*nsteps points); longer and monotonic: output exactly
  // at those times via the interpolant. tf < t0 integrates backwards.
  // A right-hand side that throws RhsError at a trial state rejects the attempt like an infinite
  // error estimate (the step shrinks tenfold, then halves); the run stops (RhsFailed, with the
  // reason) where it fails at the initial state or at the minimum step. RhsAbort stops at once.
  // MATLAB's counts are untouched: its right-hand sides do not fail.
  // accepted: called with (t0, y0) after f(t0, y0) and with every accepted (tnew, ynew), right after
  // its FSAL evaluation f(tnew, ynew), which is therefore the last evaluation before the call.
  // retry: called with the accepted (t, y) before a step is attempted again whose rejected attempt was
  // far off the solution: its right-hand side failed or its error estimate exceeded 1 (100% relative;
  // ordinary rejections, e.g. of a stiff model's steps at its stability limit, stay far below).
  OdeResult integrate(const OdeRhs& f, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                      const OdeObserver& observer, const OdeStepHook& accepted = {},
                      const OdeStepHook& retry = {}) const;

  // "14 successful steps\n2 failed attempts\n97 function evaluations\n", and "(2 of the failed
  // attempts: the right-hand side failed at a trial state)\n" when that happened.
  static std::string formatStats(const OdeStats& s);

  const Ode45Options& options() const { return opt_; }

 private:
  Ode45Options opt_;
};

}  // namespace flexmb::solvers
