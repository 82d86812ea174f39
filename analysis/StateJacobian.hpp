#pragma once
// The Jacobian of the first-order equations of motion y' = [etad; etadd(t, eta, etad)] (Eq. 13, reduced
// Eq. 19) from the linearisation about the moving state (Eq. 15, core::Linearization::inMotion):
// M detadd + (C + D) detad + (K + N + G) deta = 0 gives
//   J = [[0, I], [-M^-1 (K + N + G), -M^-1 (C + D)]]   at (eta, etad, etadd),
// for an implicit integrator (solvers::Bdf) instead of 2m difference quotients of the right-hand side.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <optional>

#include "core/linearization/Linearization.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

class StateJacobian {
 public:
  // basis: q = V eta (empty: the full model), as for core::EquationsOfMotion.
  StateJacobian(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis);
  // On the workspace of the equations of motion it differentiates (core/dynamics/Workspace.hpp).
  StateJacobian(core::Workspace& workspace, const std::optional<Eigen::MatrixXd>& basis);

  int size() const { return m_; }  // dimension of eta; J is 2m x 2m
  // The kinematics of the linearisation (warm start, tolerance).
  core::GeometricTransferFunctions& kinematics() { return lin_.kinematics(); }

  // J at (t, y), where dydt = f(t, y) (its tail is etadd). Throws core::KinematicsError when the
  // kinematics fail or the mass matrix is not positive definite.
  void evaluate(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& dydt, Eigen::Ref<Eigen::MatrixXd> J);

 private:
  void initialise();
  core::Linearization lin_;
  int m_;
  core::LinearizedSystem sys_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd eta_, etad_, etadd_;
  Eigen::MatrixXd stiffness_, damping_;  // K + N + G, C + D
};

}  // namespace flexmb::analysis
