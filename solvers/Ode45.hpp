// Ode45: MATLAB's ode45 (Dormand-Prince 5(4), FSAL, local extrapolation) reproduced step by step.
// The contract is ../shared/spec/ode45.md: same accepted/rejected steps and function-evaluation counts.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace flexmb::solvers {

struct Ode45Options {
  double relTol = 1e-3;          // raised to 100*eps if smaller
  Eigen::VectorXd absTol;        // empty -> 1e-6 for all; size 1 -> scalar; size n -> per component
  double maxStep = 0.0;          // 0 -> 0.1*|tf-t0|; a user value is clipped to |tf-t0|
  double initialStep = 0.0;      // 0 -> automatic rule of ode45.md
  int refine = 4;                // used when tspan has exactly 2 entries
};

struct OdeStats {
  long nsteps = 0, nfailed = 0, nfevals = 0;
};

enum class OdeStatus { Success, StepSizeUnderflow, RhsFailed, Stopped };

struct OdeResult {
  OdeStatus status = OdeStatus::Success;
  std::string message;  // empty on success, else the time and the reason
  double tLast = 0.0;   // last time reached (end of the last successful step)
  OdeStats stats;
};

// Thrown by a right-hand side to report failure; Ode45 catches it and stops cleanly.
class RhsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// dydt is preallocated with the size of y.
using OdeRhs = std::function<void(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt)>;
// Called for every output point in order of integration, including t0; return false to stop.
using OdeObserver = std::function<bool(double t, const Eigen::VectorXd& y)>;

class Ode45 {
 public:
  explicit Ode45(Ode45Options options = {});

  // tspan = [t0, tf]: Refine output (1 + refine*nsteps points); longer and monotonic: output exactly
  // at those times via the interpolant. tf < t0 integrates backwards.
  OdeResult integrate(const OdeRhs& f, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                      const OdeObserver& observer) const;

  // "14 successful steps\n2 failed attempts\n97 function evaluations\n"
  static std::string formatStats(const OdeStats& s);

  const Ode45Options& options() const { return opt_; }

 private:
  Ode45Options opt_;
};

}  // namespace flexmb::solvers
