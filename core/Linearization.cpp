#include "core/Linearization.hpp"

namespace flexmb::core {

Linearization::Linearization(const Model& model, std::optional<Eigen::MatrixXd> basis)
    : model_(model), coords_(model.numDofs(), std::move(basis)), m_(coords_.size()),
      gtf_(model), inertia_(model), stresses_(model), steps_(model) {}

void Linearization::dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const { coords_.toFull(eta, q); }

void Linearization::appliedForces(double t, double loadFactor, Eigen::VectorXd& f, double initialFactor) const {
  loadFactor_ = loadFactor;  // the moment load stiffness of geometricStiffness follows them
  initialFactor_ = initialFactor;
  appliedLoads(model_, inertia_, t, loadFactor, gtf_.x(), f, initialFactor);
}

void Linearization::staticForces(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f,
                                 Eigen::VectorXd& Q) {
  dofs(eta, q_);
  gtf_.solvePositions(t, q_);
  gtf_.firstOrder(basis(), FqV_);
  stresses_.evaluate(t, gtf_.e(), nullptr, sigma_);
  r_ = f;
  gtf_.addTransposedJacobianProduct(sigma_, r_, -1.0);
  Q.noalias() = FqV_.transpose() * r_;
}

void Linearization::constitutiveProduct(const Eigen::MatrixXd& L, const Eigen::MatrixXd& R, bool damping,
                                        Eigen::MatrixXd& out) const {
  out.setZero(m_, m_);
  for (const auto& E : model_.elements) {
    if (damping ? !E.hasDamping : !E.hasStiffness) continue;
    const DefMat& S = damping ? E.Sd : E.S;
    const int nd = E.impl->numDeformations();
    for (int i = 0; i < nd; ++i) {
      if (!stresses_.isActive(E.firstDef + i)) continue;
      for (int j = 0; j < nd; ++j) {
        if (!stresses_.isActive(E.firstDef + j) || S(i, j) == 0.0) continue;
        out.noalias() += S(i, j) * L.row(E.firstDef + i).transpose() * R.row(E.firstDef + j);
      }
    }
  }
}

void Linearization::geometricStiffness(LinearizedSystem& out) {
  // Reaction stresses: D_x^T sigma~ = f on the calculable coordinates (r_ = f - D_x^T sigma).
  out.sigma = sigma_;
  gtf_.addConstraintStresses(r_, out.sigma);
  // H F_q V with H = sum of element stress-weighted Hessians.
  HF_.setZero(model_.nx, m_);
  ElemVec xe;
  DefVec se;
  ElemMat He;
  for (const auto& E : model_.elements) {
    const int nd = E.impl->numDeformations(), nc = static_cast<int>(E.coords.size());
    se.resize(nd);
    bool any = false;
    for (int i = 0; i < nd; ++i) {
      se[i] = out.sigma[E.firstDef + i];
      any |= se[i] != 0.0;
    }
    if (!any) continue;
    E.gather(gtf_.x(), xe);
    E.impl->stressWeightedHessian(xe, se, He);
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < nc; ++j)
        if (He(i, j) != 0.0) HF_.row(E.coords[i]) += He(i, j) * FqV_.row(E.coords[j]);
  }
  // Load stiffness of gravity on distributed masses: -(dg/dx) F_q V.
  if (model_.hasGravity || !model_.moments.empty()) {
    Y_.setZero(model_.nx, m_);
    inertia_.addGravityJacobian(gtf_.x(), FqV_, steps_, Y_);
    addMomentLoadJacobian(model_, initialFactor_, loadFactor_, FqV_, Y_);  // spatial global moments
    HF_ -= Y_;
  }
  out.G.noalias() = FqV_.transpose() * HF_;
  out.G = 0.5 * (out.G + out.G.transpose()).eval();
}

void Linearization::atRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f,
                           LinearizedSystem& out, bool withMass) {
  staticForces(t, eta, f, out.Q);
  geometricStiffness(out);
  gtf_.deformationFirstOrder(FqV_, EqV_);
  constitutiveProduct(EqV_, EqV_, false, out.K);
  constitutiveProduct(EqV_, EqV_, true, out.D);
  out.C.setZero(m_, m_);  // Eq. 16a
  out.N.setZero(m_, m_);
  if (withMass) {
    inertia_.update(gtf_.x());
    inertia_.multiply(FqV_, MF_);
    out.M.noalias() = FqV_.transpose() * MF_;
    out.M = 0.5 * (out.M + out.M.transpose()).eval();
  }
}

void Linearization::inMotion(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& etad,
                             const Eigen::VectorXd& etadd, LinearizedSystem& out) {
  dofs(eta, q_);
  dofs(etad, qd_);
  gtf_.solvePositions(t, q_);
  gtf_.firstOrder(basis(), FqV_);
  const Eigen::VectorXd& x = gtf_.x();
  const Eigen::MatrixXd& A = FqV_;
  // The state: xd = F_q qd + F_t, xdd = A etadd + g (Eq. 8), stresses with their rates.
  gtf_.velocities(t, qd_, xd_);
  gtf_.accelerationOffset(t, xd_, xdd_);
  xdd_.noalias() += A * etadd;
  gtf_.deformationRates(xd_, ed_);
  stresses_.evaluate(t, gtf_.e(), &ed_, sigma_);
  inertia_.update(x);
  // Nodal residual r = f - M xdd - h - D_x^T sigma: the inertia forces act as loads in G.
  appliedForces(t, 0.0, r_);
  inertia_.multiply(xdd_, work_);
  r_ -= work_;
  work_.setZero(model_.nx);
  inertia_.addVelocityForces(x, xd_, work_);
  r_ -= work_;
  gtf_.addTransposedJacobianProduct(sigma_, r_, -1.0);
  out.Q.noalias() = A.transpose() * r_;
  geometricStiffness(out);

  gtf_.deformationFirstOrder(A, EqV_);
  constitutiveProduct(EqV_, EqV_, false, out.K);
  constitutiveProduct(EqV_, EqV_, true, out.D);
  inertia_.multiply(A, MF_);
  out.M.noalias() = A.transpose() * MF_;
  out.M = 0.5 * (out.M + out.M.transpose()).eval();

  // Velocity variation along dq at fixed qd (known coordinates held): differentiating
  // D_C,x xd = rates gives J dxd_c = -D2_C[A, xd]. Along dqd the acceleration varies by 2 dxd
  // (d/dqd of (F_qq qd) qd + 2 F_qt qd is twice d/dq of F_q qd + F_t).
  gtf_.secondDerivativeProduct(xd_, A, Y_);  // D2[xd, A_j], all deformations (kept for N)
  R_ = -Y_;
  gtf_.solveConstrained(R_, dxd_);
  // Acceleration variation along dq at fixed qd, qdd, from D_C,x xdd + D2_C[xd, xd] = rates:
  // J dxdd_c = -(D2_C[A, xdd] + 2 D2_C[xd, dxd] + D3_C[A, xd, xd]).
  gtf_.secondDerivativeProduct(xdd_, A, R_);
  gtf_.secondDerivativeProduct(xd_, dxd_, Z_);
  R_ += 2.0 * Z_;
  gtf_.thirdDerivativeProduct(xd_, A, steps_, Z_);
  R_ += Z_;
  R_ = -R_;
  gtf_.solveConstrained(R_, dxdd_);

  // C = A^T (M 2 dxd + dh/dxd A).
  inertia_.multiply(dxd_, HF_);
  HF_ *= 2.0;
  inertia_.addVelocityForceJacobian(x, xd_, A, HF_);
  out.C.noalias() = A.transpose() * HF_;
  // N = A^T (M dxdd + d(M xdd + h)/dx A + dh/dxd dxd) + (E_q V)^T S_d de_d/dq.
  inertia_.multiply(dxdd_, HF_);
  inertia_.addConfigurationJacobian(x, xd_, xdd_, A, steps_, HF_);
  inertia_.addVelocityForceJacobian(x, xd_, dxd_, HF_);
  out.N.noalias() = A.transpose() * HF_;
  if (stresses_.hasDamping()) {
    gtf_.deformationFirstOrder(dxd_, Ed_);  // de_d/dq = D2[A, xd] + D_x dxd
    Ed_ += Y_;
    constitutiveProduct(EqV_, Ed_, true, Z_);
    out.N += Z_;
  }
}

}  // namespace flexmb::core
