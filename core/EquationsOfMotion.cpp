#include "core/EquationsOfMotion.hpp"

#include <cmath>
#include <Eigen/QR>

namespace flexmb::core {

EquationsOfMotion::EquationsOfMotion(const Model& model, std::optional<Eigen::MatrixXd> basis)
    : model_(model), coords_(model.numDofs(), std::move(basis)), m_(coords_.size()),
      gtf_(model), inertia_(model), stresses_(model),
      rheonomic_(!model.inputX.empty() || !model.inputE.empty()), llt_(m_) {
  const int nq = model.numDofs(), nx = model.nx, ne = model.ne;
  q_.setZero(nq);
  qd_.setZero(nq);
  xd_.setZero(nx);
  g_.setZero(nx);
  ed_.setZero(ne);
  sigma_.setZero(ne);
  fn_.setZero(nx);
  Mg_.setZero(nx);
  rhsEta_.setZero(m_);
  etadd_.setZero(m_);
  FqV_.setZero(nx, m_);
  MF_.setZero(nx, m_);
  Mbar_.setZero(m_, m_);
}

void EquationsOfMotion::dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const { coords_.toFull(eta, q); }

Eigen::VectorXd EquationsOfMotion::initialState() {
  const int nq = model_.numDofs();
  Eigen::VectorXd q0 = gtf_.initialDofs(), qd0 = Eigen::VectorXd::Zero(nq);
  for (int j = 0; j < nq; ++j) {
    const auto& d = model_.dofs[j];
    if (d.isDeformation && model_.ed0.size() && !std::isnan(model_.ed0[d.index])) qd0[j] = model_.ed0[d.index];
    if (!d.isDeformation && model_.xd0.size() && !std::isnan(model_.xd0[d.index])) qd0[j] = model_.xd0[d.index];
  }
  // Least squares onto the basis (exact when q0, qd0 lie in its span, e.g. zero).
  Eigen::VectorXd y(2 * m_);
  y << coords_.fromFull(q0), coords_.fromFull(qd0);
  return y;
}

void EquationsOfMotion::kinematicState(double t, const Eigen::VectorXd& y) {
  const auto eta = y.head(m_);
  const auto etad = y.tail(m_);
  coords_.toFull(eta, q_);
  coords_.toFull(etad, qd_);
  gtf_.solvePositions(t, q_);
  gtf_.firstOrder(basis(), FqV_);
  if (rheonomic_ || !qd_.isZero(0.0)) {
    gtf_.velocities(t, qd_, xd_);
    gtf_.accelerationOffset(t, xd_, g_);
  } else {
    xd_.setZero();
    g_.setZero();
  }
}

void EquationsOfMotion::generalisedForces(double t, Eigen::VectorXd& rhsEta) {
  const Eigen::VectorXd& x = gtf_.x();
  const bool moving = !xd_.isZero(0.0);
  // Nodal force vector f - h - M g - D_x^T sigma (Eq. 13 before projection).
  appliedLoads(model_, inertia_, t, 0.0, x, fn_);
  // USERSIG: the user's stresses and nodal forces at this state, added where XFT and ESIGT are
  // (same order of additions, so that the same loads give the same bits).
  UserFunctions* user = model_.userFunctions && model_.userFunctions->hasLoads() ? model_.userFunctions.get() : nullptr;
  if ((stresses_.hasDamping() || user) && moving) gtf_.deformationRates(xd_, ed_);
  else ed_.setZero();
  if (user) {
    user->loads(t, x, xd_, gtf_.e(), ed_, userSigma_, userForces_);
    fn_ += userForces_;
  }
  if (inertia_.hasMass()) {
    if (moving) {
      Mg_.setZero();
      inertia_.addVelocityForces(x, xd_, Mg_);
      fn_ -= Mg_;
    }
    if (!g_.isZero(0.0)) {
      inertia_.multiply(g_, Mg_);
      fn_ -= Mg_;
    }
  }
  stresses_.evaluate(t, gtf_.e(), stresses_.hasDamping() ? &ed_ : nullptr, sigma_);
  if (user) sigma_ += userSigma_;
  gtf_.addTransposedJacobianProduct(sigma_, fn_, -1.0);
  rhsEta.noalias() = FqV_.transpose() * fn_;
}

void EquationsOfMotion::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  ++evaluations_;
  kinematicState(t, y);
  inertia_.update(gtf_.x());
  inertia_.multiply(FqV_, MF_);
  Mbar_.noalias() = FqV_.transpose() * MF_;
  generalisedForces(t, rhsEta_);
  llt_.compute(Mbar_);
  if (llt_.info() != Eigen::Success)
    throw KinematicsError(t, 0, 0.0, "reduced mass matrix is not positive definite (massless degree of freedom?)");
  etadd_ = rhsEta_;
  llt_.solveInPlace(etadd_);
  dydt.resize(2 * m_);
  dydt.head(m_) = y.tail(m_);
  dydt.tail(m_) = etadd_;
}

void EquationsOfMotion::residual(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& etadd,
                                 Eigen::VectorXd& R) {
  kinematicState(t, y);
  inertia_.update(gtf_.x());
  inertia_.multiply(FqV_, MF_);
  Mbar_.noalias() = FqV_.transpose() * MF_;
  generalisedForces(t, rhsEta_);
  R.noalias() = Mbar_ * etadd;
  R -= rhsEta_;
}

void EquationsOfMotion::outputs(double t, const Eigen::VectorXd& y, StateOutputs& out) {
  Eigen::VectorXd dydt(2 * m_);
  rhs(t, y, dydt);
  --evaluations_;  // output evaluations are not integrator evaluations
  out.x = gtf_.x();
  out.xd = xd_;
  out.xdd = g_;
  out.xdd.noalias() += FqV_ * etadd_;
  out.e = gtf_.e();
  gtf_.deformationRates(xd_, out.ed);
  gtf_.deformationAccelerations(xd_, out.xdd, out.edd);
  out.sig = sigma_;
}

}  // namespace flexmb::core
