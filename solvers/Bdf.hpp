// Bdf: the implicit integrator for stiff problems: SUNDIALS CVODE (variable-order, variable-step
// BDF of order 1-5, Newton corrector, dense direct linear solver) behind the callables the
// explicit Ode45 takes, plus the Jacobian J = df/dy. Knows no mechanics: the caller supplies f, J
// and, optionally, a hook called at every accepted state.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "solvers/OdeTypes.hpp"

namespace flexmb::solvers {

struct BdfOptions {
  double relTol = 1e-3;      // CVODE's weighted RMS error test: |err_i| / (relTol |y_i| + absTol)
  double absTol = 1e-6;      // scalar, or per component of y:
  Eigen::VectorXd absTols;   // n values (empty: absTol for every component; CVodeSVtolerances)
  double maxStep = 0.0;      // 0 -> 0.1*|tf - t0| (as Ode45); a user value is clipped to |tf - t0|
  double initialStep = 0.0;  // 0 -> CVODE's estimate
  // 1 ... 5. Orders 1 and 2 are A-stable; 3-5 are not, and lightly damped stiff oscillations
  // (eigenvalues near the imaginary axis, as a flexible model's high-frequency modes) then bound the
  // step as they bound an explicit method's (measured on the paper's full models: tools/bench/README.md).
  int maxOrder = 5;
};

// J (n x n, preallocated) = df/dy at (t, y); fy = f(t, y) is given (the caller need not re-evaluate
// it). Throw RhsError when it cannot be evaluated there (CVODE retries with a smaller step).
using OdeJacobian =
    std::function<void(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& fy, Eigen::Ref<Eigen::MatrixXd> J)>;

class Bdf {
 public:
  // Throws std::invalid_argument for non-positive tolerances, a negative step or an order outside 1-5.
  explicit Bdf(BdfOptions options = {});

  // tspan = [t0, tf]: output at every accepted step; longer and monotonic: output exactly at those
  // times (CVODE's interpolation, CVodeGetDky; tf itself exactly). tf < t0 integrates backwards.
  // jacobian empty: CVODE's difference-quotient Jacobian (n evaluations of f each, counted in
  // nfevals and njacfevals). A right-hand side or Jacobian that throws RhsError is retried with a
  // smaller step; RhsAbort stops at once. Failures return a status and a message with the time
  // (the outputs before it have been observed); invalid arguments throw std::invalid_argument.
  OdeResult integrate(const OdeRhs& f, const OdeJacobian& jacobian, const std::vector<double>& tspan,
                      const Eigen::VectorXd& y0, const OdeObserver& observer,
                      const OdeStepHook& accepted = {}) const;  // (t0, y0) first, then every accepted state

  // Ode45's three lines, then "12 Jacobian evaluations\n40 linear-solver set-ups\n" (and the
  // evaluations spent on difference-quotient Jacobians when there were any).
  static std::string formatStats(const OdeStats& s);
  // "SUNDIALS CVODE 6.4.1"
  static std::string library();

  // The local tolerance (relative and absolute alike) whose run's global error is about relTol
  // (calibrated on the paper's and the spatial models: analysis::simulate maps the user's RelTol).
  static double localTolerance(double relTol);
  const BdfOptions& options() const { return opt_; }

 private:
  BdfOptions opt_;
};

}  // namespace flexmb::solvers
