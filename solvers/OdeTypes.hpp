// What the time integrators (Ode45, Bdf) share: the right-hand side and observer callables, the
// statistics, the outcome of a run and the exceptions a right-hand side reports failure with.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace flexmb::solvers {

struct OdeStats {
  long nsteps = 0, nfailed = 0, nfevals = 0;
  // Failed attempts (counted in nfailed) whose right-hand side failed at a trial state (Ode45).
  long nrhsfailed = 0;
  // Implicit integrators only (0 for Ode45): Jacobian evaluations (analytic or difference quotients),
  // the right-hand-side evaluations among nfevals spent on difference-quotient Jacobians, and the
  // linear-solver set-ups (LU factorisations of I - gamma J).
  long njacevals = 0, njacfevals = 0, nlinsetups = 0;
};

enum class OdeStatus {
  Success,
  StepSizeUnderflow,   // the tolerance cannot be met: the step fell to the minimum step size
  RhsFailed,           // the right-hand side failed (repeatedly, for an implicit integrator)
  Stopped,             // the observer (or an abort from the right-hand side) asked to stop
  ConvergenceFailure,  // implicit: the corrector (Newton) did not converge, even at the minimum step
  JacobianFailed,      // implicit: the Jacobian or the linear solver failed (singular matrix)
  SolverFailure        // implicit: any other failure the integrator reported (the message says which)
};

struct OdeResult {
  OdeStatus status = OdeStatus::Success;
  std::string message;  // empty on success, else the time and the reason
  double tLast = 0.0;   // last time reached (end of the last successful step)
  OdeStats stats;
};

// Thrown by a right-hand side (or a Jacobian) to report failure. Ode45 stops cleanly; an implicit
// integrator treats it as recoverable (it retries with a smaller step: a trial state far from the
// solution may fail where the solution does not) and stops when the failures repeat.
class RhsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// A failure that must stop every integrator at once (Ctrl-C, a failing user function).
class RhsAbort : public RhsError {
 public:
  using RhsError::RhsError;
};

// dydt is preallocated with the size of y.
using OdeRhs = std::function<void(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt)>;
// Called for every output point in order of integration, including t0; return false to stop.
using OdeObserver = std::function<bool(double t, const Eigen::VectorXd& y)>;
// Called with a state (t, y) of the solution: the accepted ones (t0 included) or the one a rejected
// step is retried from. Throwing RhsError stops the run (status RhsFailed) with its message.
using OdeStepHook = std::function<void(double t, const Eigen::VectorXd& y)>;

// MATLAB's eps(t): the spacing of doubles at |t| (eps(0) is the smallest subnormal). The integrators'
// minimum step is 16 eps(t).
inline double spacingOfDoublesAt(double t) {
  const double a = std::fabs(t);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

// The output times an integrator accepts: at least two, distinct finite end points, strictly
// monotonic. Throws std::invalid_argument naming the integrator (`who`).
inline void checkTimeSpan(const std::vector<double>& tspan, const char* who) {
  const std::string w(who);
  if (tspan.size() < 2) throw std::invalid_argument(w + ": tspan needs at least 2 entries");
  const double t0 = tspan.front(), tf = tspan.back();
  if (!(t0 != tf) || !std::isfinite(t0) || !std::isfinite(tf))
    throw std::invalid_argument(w + ": tspan must have distinct finite end points");
  const double tdir = tf > t0 ? 1.0 : -1.0;
  for (std::size_t i = 1; i < tspan.size(); ++i)
    if (!(tdir * (tspan[i] - tspan[i - 1]) > 0.0))
      throw std::invalid_argument(w + ": tspan must be strictly monotonic");
}

}  // namespace flexmb::solvers
