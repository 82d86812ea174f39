#include "analysis/StateJacobian.hpp"

#include "core/kinematics/GeometricTransferFunctions.hpp"

namespace flexmb::analysis {

StateJacobian::StateJacobian(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis)
    : lin_(model, basis), m_(lin_.size()), llt_(m_) {
  initialise();
}

StateJacobian::StateJacobian(core::Workspace& workspace, const std::optional<Eigen::MatrixXd>& basis)
    : lin_(workspace, basis), m_(lin_.size()), llt_(m_) {
  initialise();
}

void StateJacobian::initialise() {
  eta_.setZero(m_);
  etad_.setZero(m_);
  etadd_.setZero(m_);
  stiffness_.setZero(m_, m_);
  damping_.setZero(m_, m_);
}

void StateJacobian::evaluate(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& dydt,
                             Eigen::Ref<Eigen::MatrixXd> J) {
  const int m = m_;
  eta_ = y.head(m);
  etad_ = y.tail(m);
  etadd_ = dydt.tail(m);
  lin_.inMotion(t, eta_, etad_, etadd_, sys_);  // Eq. 15 about the state
  llt_.compute(sys_.M);
  if (llt_.info() != Eigen::Success)
    throw core::KinematicsError(t, 0, 0.0,
                                "reduced mass matrix is not positive definite (massless degree of freedom?)");
  stiffness_ = sys_.K;
  stiffness_ += sys_.N;
  stiffness_ += sys_.G;
  if (sys_.Gskew.size()) stiffness_ += sys_.Gskew;  // moments on Euler parameters
  damping_ = sys_.C;
  damping_ += sys_.D;
  llt_.solveInPlace(stiffness_);
  llt_.solveInPlace(damping_);
  // d(etad)/d(eta) = 0, d(etad)/d(etad) = I; d(etadd)/d(eta) = -M^-1 (K + N + G),
  // d(etadd)/d(etad) = -M^-1 (C + D).
  J.topLeftCorner(m, m).setZero();
  J.topRightCorner(m, m).setIdentity();
  J.bottomLeftCorner(m, m) = -stiffness_;
  J.bottomRightCorner(m, m) = -damping_;
}

}  // namespace flexmb::analysis
