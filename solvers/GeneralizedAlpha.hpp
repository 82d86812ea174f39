// GeneralizedAlpha: the implicit generalized-alpha method of Chung & Hulbert (J. Appl. Mech. 60, 1993)
// in the form of Arnold & Bruls (Multibody Syst. Dyn. 18, 2007) for second-order systems
// M(q) qdd = F(t, q, qd): second order, unconditionally stable for linear systems, with the
// high-frequency dissipation set by the spectral radius at infinity rho_inf (1: none, 0: annihilated
// in one step). Variable steps from a local error estimate, modified Newton with a reused iteration
// matrix. Knows no mechanics: the caller supplies a SecondOrderSystem.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include <string>
#include <vector>

#include "solvers/Bdf.hpp"
#include "solvers/OdeTypes.hpp"

namespace flexmb::solvers {

struct GeneralizedAlphaOptions {
  double rhoInf = 0.8;       // spectral radius at infinite step (0 ... 1)
  double relTol = 1e-3;      // weighted RMS error test on q: |err_i| / (relTol |q_i| + absTol)
  double absTol = 1e-6;      // scalar, or per component of q:
  Eigen::VectorXd absTols;   // m values (empty: absTol for every component)
  double maxStep = 0.0;      // 0 -> 0.1*|tf - t0| (as Ode45); a user value is clipped to |tf - t0|
  double initialStep = 0.0;  // 0 -> 1e-3 |tf - t0| (the controller grows it)
  // Constant steps of maxStep (no error control): the order and dissipation tests, and a user who
  // wants the field's fixed-step runs.
  bool fixedStep = false;
  int maxNewtonIterations = 6;
};

// The method's parameters from rho_inf (Chung & Hulbert, Eq. 25 and 17-18):
// alpha_m = (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1), gamma = 1/2 + alpha_f - alpha_m,
// beta = (gamma + 1/2)^2 / 4.
struct GeneralizedAlphaParameters {
  double alphaM, alphaF, gamma, beta;
  explicit GeneralizedAlphaParameters(double rhoInf);
  // The leading coefficient c of the local error of q, c h^2 (a_{n+1} - a_n) (a: the algorithmic
  // accelerations): beta + (alpha_m - alpha_f)/2 - 1/6 (Taylor expansion of the q update).
  double errorCoefficient() const;
};

// The system M(q) qdd = F(t, q, qd) as the integrator sees it. Its Newton iteration is
// on the accelerations: the residual r = qdd - a(t, q, qd) (accelerations, M already solved), the
// correction S^-1 M r with the iteration matrix S = M + gammaP (C + D) + betaP (K + G + N)
// (betaP, gammaP: dq/dqdd and dqd/dqdd of the update), taken at some earlier state.
class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual int size() const = 0;
  // qdd at (t, q, qd). Throws RhsError where it cannot be evaluated (the step is cut).
  virtual void acceleration(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& qdd) = 0;
  // Evaluates the matrices of S at (t, q, qd, qdd). Throws RhsError.
  virtual void jacobian(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) = 0;
  // Factorises S with the last jacobian's matrices; false when singular.
  virtual bool factorize(double betaP, double gammaP) = 0;
  // r <- S^-1 M r with the last factorisation.
  virtual void solve(Eigen::VectorXd& r) = 0;
  // An accepted state (t0 included). Throws RhsError to stop the run there.
  virtual void accept(double, const Eigen::VectorXd&, const Eigen::VectorXd&) {}
};

// A first-order y' = f(t, y), y = [q; qd] with f = [qd; qdd], and its Jacobian J = df/dy as a
// SecondOrderSystem: S = I - betaP J21 - gammaP J22 (M = I), dense LU.
class FirstOrderAsSecondOrder : public SecondOrderSystem {
 public:
  FirstOrderAsSecondOrder(OdeRhs f, OdeJacobian jacobian, int m, OdeStepHook accepted = {});
  int size() const override { return m_; }
  void acceleration(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& qdd) override;
  void jacobian(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) override;
  bool factorize(double betaP, double gammaP) override;
  void solve(Eigen::VectorXd& r) override;
  void accept(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) override;

 private:
  OdeRhs f_;
  OdeJacobian jac_;
  OdeStepHook accepted_;
  int m_;
  Eigen::VectorXd y_, dy_, x_;
  Eigen::MatrixXd J_, S_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

class GeneralizedAlpha {
 public:
  // Throws std::invalid_argument for rho_inf outside [0, 1], non-positive tolerances, a negative
  // step, or fixedStep without maxStep.
  explicit GeneralizedAlpha(GeneralizedAlphaOptions options = {});

  // y0 = [q0; qd0]; the observer sees y = [q; qd]. tspan = [t0, tf]: output at every accepted step;
  // longer: exactly at those times (cubic Hermite between the step's ends, q from q and qd, qd
  // from qd and qdd). A step whose Newton iteration fails or whose right-hand side throws RhsError
  // is retried with a fresh iteration matrix, then a quarter of the step; at the minimum step
  // (16 eps(t)) the run stops with the time and the reason, the outputs before it observed.
  // Invalid arguments (and a maxStep so small that the run would need more than 1e9 steps) throw
  // std::invalid_argument.
  OdeResult integrate(SecondOrderSystem& system, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                      const OdeObserver& observer) const;

  // As Bdf's, with the iteration matrices: "... Jacobian evaluations\n... linear-solver set-ups\n".
  static std::string formatStats(const OdeStats& s) { return Bdf::formatStats(s); }
  // The local tolerance (relative and absolute alike) whose run's global error is about relTol
  // (calibrated on the paper's and the spatial models: analysis::simulate maps the user's RelTol).
  static double localTolerance(double relTol);
  const GeneralizedAlphaOptions& options() const { return opt_; }

 private:
  GeneralizedAlphaOptions opt_;
};

}  // namespace flexmb::solvers
