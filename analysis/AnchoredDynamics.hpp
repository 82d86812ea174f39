#pragma once
// The equations of motion as an implicit integrator (solvers::Bdf) evaluates them. The kinematic
// Newton solve inside every evaluation (Eq. 7) warm-starts from the previous one. An implicit
// integrator evaluates at trial states far from the solution (diverging corrector iterates, large
// predicted steps, difference-quotient columns); from such a warm start Newton fails at good states
// or converges to another assembly branch, and the right-hand side is no longer a function of y
// alone (measured: CVODE stopped in 4 of 8 benchmark runs without this; tools/bench/README.md).
// So every evaluation starts from the configuration of the last accepted state, the anchor.
#include <Eigen/Core>

#include "analysis/StateJacobian.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"

namespace flexmb::analysis {

class AnchoredDynamics {
 public:
  // jacobian may be null (the integrator then forms difference quotients of rhs).
  AnchoredDynamics(core::EquationsOfMotion& eom, StateJacobian* jacobian);

  // An accepted state: solves its kinematics (from the previous anchor) and makes that configuration
  // the warm start of every later evaluation. Throws core::KinematicsError.
  void accept(double t, const Eigen::VectorXd& y);
  // dy/dt and J = df/dy (StateJacobian) from the anchor. Throw what EquationsOfMotion and
  // StateJacobian throw.
  void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt);
  void jacobian(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& dydt, Eigen::Ref<Eigen::MatrixXd> J);

  const Eigen::VectorXd& anchor() const { return anchor_; }

 private:
  core::EquationsOfMotion& eom_;
  StateJacobian* jacobian_;
  Eigen::VectorXd anchor_, eta_, q_;
};

}  // namespace flexmb::analysis
