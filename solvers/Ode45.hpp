// Ode45: MATLAB's ode45 (Dormand-Prince 5(4), FSAL, local extrapolation) reproduced step by step.
// The contract is ../shared/spec/ode45.md: same accepted/rejected steps and function-evaluation counts.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "solvers/OdeTypes.hpp"

namespace flexmb::solvers {

struct Ode45Options {
  double relTol = 1e-3;          // raised to 100*eps if smaller
  Eigen::VectorXd absTol;        // empty -> 1e-6 for all; size 1 -> scalar; size n -> per component
  double maxStep = 0.0;          // 0 -> 0.1*|tf-t0|; a user value is clipped to |tf-t0|
  double initialStep = 0.0;      // 0 -> automatic rule of ode45.md
  int refine = 4;                // used when tspan has exactly 2 entries
};

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
