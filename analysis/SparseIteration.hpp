#pragma once
// The equations of motion of a full model as solvers::GeneralizedAlpha sees them: accelerations from
// the caller's right-hand side (anchored kinematics, as every implicit run evaluates them), the
// iteration matrix M + gammaP D + betaP (K + G) in the sparse saddle-point form of
// core::Linearization::iterationMatrix: an iteration matrix costs a few right-hand sides (measured on
// the elbow with 2 x 10 BEAMs: tools/bench/README.md), where the dense Jacobian of Eq. 15
// (StateJacobian: C and N through second-order kinematics and four projections) costs hundreds.
#include <Eigen/Core>
#include <functional>

#include "core/dynamics/Workspace.hpp"
#include "core/linearization/Linearization.hpp"
#include "solvers/GeneralizedAlpha.hpp"

namespace flexmb::analysis {

class SparseIteration : public solvers::SecondOrderSystem {
 public:
  // rhs: y' = f(t, y) of the run, y = [q; qd]; accepted: the run's accepted-state hook (anchoring);
  // anchor: the configuration the iteration matrix's kinematics start from (the last accepted one).
  SparseIteration(core::Workspace& workspace, solvers::OdeRhs rhs, solvers::OdeStepHook accepted,
                  std::function<const Eigen::VectorXd&()> anchor, double kinematicTolerance);

  int size() const override { return m_; }
  void acceleration(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& qdd) override;
  void jacobian(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) override;
  bool factorize(double betaP, double gammaP) override;
  void solve(Eigen::VectorXd& r) override;
  void accept(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) override;

 private:
  core::Linearization lin_;
  solvers::OdeRhs rhs_;
  solvers::OdeStepHook accepted_;
  std::function<const Eigen::VectorXd&()> anchor_;
  int m_;
  Eigen::VectorXd y_, dy_, x_;
};

}  // namespace flexmb::analysis
