#include "core/dynamics/EquationsOfMotion.hpp"

#include <Eigen/QR>
#include <cmath>

namespace flexmb::core {

EquationsOfMotion::EquationsOfMotion(const Model& model, std::optional<Eigen::MatrixXd> basis, DynamicsForm form)
    : EquationsOfMotion(std::make_unique<Workspace>(model), nullptr, std::move(basis), form) {}

EquationsOfMotion::EquationsOfMotion(Workspace& workspace, std::optional<Eigen::MatrixXd> basis, DynamicsForm form)
    : EquationsOfMotion(nullptr, &workspace, std::move(basis), form) {}

EquationsOfMotion::EquationsOfMotion(std::unique_ptr<Workspace> own, Workspace* shared,
                                     std::optional<Eigen::MatrixXd> basis, DynamicsForm form)
    : own_(std::move(own)),
      model_((shared ? *shared : *own_).model()),
      coords_(model_.numDofs(), std::move(basis)),
      m_(coords_.size()),
      gtf_((shared ? *shared : *own_).kinematics()),
      inertia_((shared ? *shared : *own_).inertia()),
      stresses_((shared ? *shared : *own_).stresses()),
      rheonomic_(!model_.inputX.empty() || !model_.inputE.empty()),
      llt_(m_) {
  const Model& model = model_;
  const int nq = model.numDofs(), nx = model.nx, ne = model.ne;
  const bool full = coords_.basis() == nullptr;
  if (full && (form == DynamicsForm::SaddlePoint || (form == DynamicsForm::Automatic && nq >= kSaddlePointDofs)))
    saddle_.emplace(model, inertia_);
  q_.setZero(nq);
  qd_.setZero(nq);
  xd_.setZero(nx);
  g_.setZero(nx);
  xdd_.setZero(nx);
  ed_.setZero(ne);
  sigma_.setZero(ne);
  fn_.setZero(nx);
  Mg_.setZero(nx);
  hn_.setZero(nx);
  rhsEta_.setZero(m_);
  etadd_.setZero(m_);
  d2_.setZero(ne);
  etaPrev_.setZero(m_);
  etadPrev_.setZero(m_);
  std::vector<char> massive(model.elements.size(), 0);
  for (int el : inertia_.massiveElements()) massive[el] = 1;
  for (size_t el = 0; el < model.elements.size(); ++el)
    if (!massive[el]) massless_.push_back(static_cast<int>(el));
  if (!saddle_) {
    FqV_.setZero(nx, m_);
    Mbar_.setZero(m_, m_);
  }
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
  predictorCurvature(eta);
  gtf_.solvePositions(t, q_);
  if (!saddle_) gtf_.firstOrder(basis(), FqV_);
  moving_ = rheonomic_ || !qd_.isZero(0.0);
  if (moving_) {
    // xd = F_q V etad: a product where F_q V is at hand, else one solve (rheonomic rates need F_t).
    if (!saddle_ && !rheonomic_)
      xd_.noalias() = FqV_ * etad;
    else
      gtf_.velocities(t, qd_, xd_);
    moving_ = !xd_.isZero(0.0);
  } else {
    xd_.setZero();
  }
}

void EquationsOfMotion::predictorCurvature(const Eigen::Ref<const Eigen::VectorXd>& eta) {
  // Second-order kinematic prediction when eta moved (nearly) along the last velocity, d eta = s
  // etad, as between the stages of an explicit integrator; otherwise the linear one.
  if (!curvatureSet_) return;
  curvatureSet_ = false;
  const double vv = etadPrev_.squaredNorm();
  if (vv == 0.0) return;
  double dv = 0.0, dd = 0.0;
  for (int j = 0; j < m_; ++j) {
    const double d = eta[j] - etaPrev_[j];
    dv += d * etadPrev_[j];
    dd += d * d;
  }
  const double s = dv / vv;
  // |d eta - s etad|^2 = dd - s dv: use the curvature when d eta is within ~25% of the direction.
  if (dd > 0.0 && dd - s * dv <= 0.0625 * dd) gtf_.usePredictorCurvature(s);
}

void EquationsOfMotion::convectiveAccelerations(double t) {
  // The projected form needs g = xdd at etadd = 0 (one solve with the convective terms of the mass
  // pass); the saddle-point form has them in its constraint rows.
  if (moving_ || rheonomic_)
    gtf_.accelerationOffsetFrom(t, d2_, g_);
  else
    g_.setZero();
}

void EquationsOfMotion::nodalForces(double t, bool projected) {
  const Eigen::VectorXd& x = gtf_.x();
  // Nodal force vector f - h - D_x^T sigma (Eq. 13 before projection).
  appliedLoads(model_, inertia_, t, 0.0, x, fn_);
  // USERSIG: the user's stresses and nodal forces at this state, added where XFT and ESIGT are
  // (same order of additions, so that the same loads give the same bits).
  UserFunctions* user = model_.userFunctions && model_.userFunctions->hasLoads() ? model_.userFunctions.get() : nullptr;
  if ((stresses_.hasDamping() || user) && moving_)
    gtf_.deformationRates(xd_, ed_);
  else
    ed_.setZero();
  if (user) {
    user->loads(t, x, xd_, gtf_.e(), ed_, userSigma_, userForces_);
    fn_ += userForces_;
  }
  if (inertia_.hasMass()) {
    if (moving_) fn_ -= hn_;             // h from the mass pass (accelerations)
    if (projected && !g_.isZero(0.0)) {  // projected form: - M g (Eq. 13's M (F_qq qd) qd)
      inertia_.multiply(g_, Mg_);
      fn_ -= Mg_;
    }
  }
  stresses_.evaluate(t, gtf_.e(), stresses_.hasDamping() ? &ed_ : nullptr, sigma_);
  if (user) sigma_ += userSigma_;
  gtf_.addTransposedJacobianProduct(sigma_, fn_, -1.0);
}

void EquationsOfMotion::projectedSystem() {
  inertia_.projectedMass(FqV_, Mbar_);
  rhsEta_.noalias() = FqV_.transpose() * fn_;
}

void EquationsOfMotion::massState() {
  const Eigen::VectorXd& x = gtf_.x();
  if (!moving_) {
    inertia_.update(x);
    d2_.setZero();
    return;
  }
  if (inertia_.hasMass()) {
    hn_.setZero();
    inertia_.updateWithVelocityForces(x, xd_, hn_, &d2_);
  }
  // The convective D2e[xd, xd] of the elements without mass (the massive ones came with their mass).
  ElemVec xe, ve;
  DefVec d2;
  for (int el : massless_) {
    const auto& E = model_.elements[el];
    E.gather(xd_, ve);
    if (ve.isZero(0.0)) {
      d2_.segment(E.firstDef, E.impl->numDeformations()).setZero();
      continue;
    }
    E.gather(x, xe);
    E.impl->secondDerivative(xe, ve, d2);
    for (int i = 0; i < d2.size(); ++i) d2_[E.firstDef + i] = d2[i];
  }
}

void EquationsOfMotion::accelerations(double t) {
  massState();

  if (!saddle_) convectiveAccelerations(t);
  nodalForces(t, !saddle_);
  if (saddle_) {
    if (!saddle_->solve(t, gtf_, d2_, fn_, etadd_, xdd_))
      throw KinematicsError(t, 0, 0.0, "singular mass matrix on the degrees of freedom (massless degree of freedom?)");
    return;
  }
  projectedSystem();
  llt_.compute(Mbar_);
  if (llt_.info() != Eigen::Success)
    throw KinematicsError(t, 0, 0.0, "reduced mass matrix is not positive definite (massless degree of freedom?)");
  etadd_ = rhsEta_;
  llt_.solveInPlace(etadd_);
}

void EquationsOfMotion::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  ++evaluations_;
  kinematicState(t, y);
  accelerations(t);
  // The convective terms of this state serve the next kinematic prediction (Eq. 8b).
  curvatureSet_ = moving_;
  if (moving_) {
    gtf_.setPredictorCurvature(d2_);
    etaPrev_ = y.head(m_);
    etadPrev_ = y.tail(m_);
  }
  dydt.resize(2 * m_);
  dydt.head(m_) = y.tail(m_);
  dydt.tail(m_) = etadd_;
}

void EquationsOfMotion::residual(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& etadd, Eigen::VectorXd& R) {
  kinematicState(t, y);
  if (saddle_) {
    // The residual is the projected Eq. 13: F_q on demand (the saddle-point form has none).
    Mbar_.resize(m_, m_);
    gtf_.firstOrder(basis(), FqV_);
  }
  massState();
  convectiveAccelerations(t);
  nodalForces(t, true);
  projectedSystem();
  R.noalias() = Mbar_ * etadd;
  R -= rhsEta_;
}

void EquationsOfMotion::outputs(double t, const Eigen::VectorXd& y, StateOutputs& out) {
  Eigen::VectorXd dydt(2 * m_);
  rhs(t, y, dydt);
  --evaluations_;  // output evaluations are not integrator evaluations
  out.x = gtf_.x();
  out.xd = xd_;
  if (saddle_) {
    out.xdd = xdd_;
  } else {
    out.xdd = g_;
    out.xdd.noalias() += FqV_ * etadd_;
  }
  out.e = gtf_.e();
  gtf_.deformationRates(xd_, out.ed);
  gtf_.deformationAccelerations(xd_, out.xdd, out.edd);
  out.sig = sigma_;
  if (model_.userFunctions && model_.userFunctions->hasLoads())
    out.userForces = userForces_;
  else
    out.userForces.resize(0);
}

}  // namespace flexmb::core
