#include "analysis/AnchoredDynamics.hpp"

#include <stdexcept>

namespace flexmb::analysis {

AnchoredDynamics::AnchoredDynamics(core::EquationsOfMotion& eom, StateJacobian* jacobian)
    : eom_(eom), jacobian_(jacobian) {
  if (jacobian && jacobian->size() != eom.size())
    throw std::invalid_argument("AnchoredDynamics: the Jacobian and the equations of motion differ in size");
  eta_.setZero(eom.size());
  q_.setZero(eom.model().numDofs());
}

void AnchoredDynamics::accept(double t, const Eigen::VectorXd& y) {
  auto& gtf = eom_.kinematics();
  eta_ = y.head(eom_.size());
  eom_.dofs(eta_, q_);
  if (anchor_.size()) gtf.setConfiguration(anchor_);
  gtf.solvePositions(t, q_);
  anchor_ = gtf.x();
}

void AnchoredDynamics::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  if (anchor_.size()) eom_.kinematics().setConfiguration(anchor_);
  eom_.rhs(t, y, dydt);
}

void AnchoredDynamics::jacobian(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& dydt,
                                Eigen::Ref<Eigen::MatrixXd> J) {
  if (!jacobian_) throw std::logic_error("AnchoredDynamics::jacobian: no StateJacobian given");
  if (anchor_.size()) jacobian_->kinematics().setConfiguration(anchor_);
  jacobian_->evaluate(t, y, dydt, J);
}

}  // namespace flexmb::analysis
