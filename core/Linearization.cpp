#include "core/Linearization.hpp"

namespace flexmb::core {

Linearization::Linearization(const Model& model, std::optional<Eigen::MatrixXd> basis)
    : model_(model), basis_(std::move(basis)), m_(basis_ ? static_cast<int>(basis_->cols()) : model.numDofs()),
      gtf_(model), inertia_(model), stresses_(model) {}

void Linearization::dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const {
  if (basis_) q.noalias() = *basis_ * eta;
  else q = eta;
}

void Linearization::appliedForces(double t, double loadFactor, Eigen::VectorXd& f) const {
  f = model_.f0;
  if (loadFactor != 0.0 && model_.delf.size() == f.size()) f += loadFactor * model_.delf;
  for (const auto& tf : model_.timeForces) f[tf.index] += tf.f->value(t);
  inertia_.addGravity(gtf_.x(), f);
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

void Linearization::constitutiveProduct(const Eigen::MatrixXd& EqV, bool damping, Eigen::MatrixXd& out) const {
  out.setZero(m_, m_);
  for (const auto& E : model_.elements) {
    if (damping ? !E.hasDamping : !E.hasStiffness) continue;
    const DefMat& S = damping ? E.Sd : E.S;
    const int nd = E.impl->numDeformations();
    for (int i = 0; i < nd; ++i) {
      if (!stresses_.isActive(E.firstDef + i)) continue;
      for (int j = 0; j < nd; ++j) {
        if (!stresses_.isActive(E.firstDef + j) || S(i, j) == 0.0) continue;
        out.noalias() += S(i, j) * EqV.row(E.firstDef + i).transpose() * EqV.row(E.firstDef + j);
      }
    }
  }
}

void Linearization::atRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f,
                           LinearizedSystem& out, bool withMass) {
  staticForces(t, eta, f, out.Q);
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
  out.G.noalias() = FqV_.transpose() * HF_;
  out.G = 0.5 * (out.G + out.G.transpose()).eval();
  gtf_.deformationFirstOrder(FqV_, EqV_);
  constitutiveProduct(EqV_, false, out.K);
  constitutiveProduct(EqV_, true, out.D);
  if (withMass) {
    inertia_.update(gtf_.x());
    inertia_.multiply(FqV_, MF_);
    out.M.noalias() = FqV_.transpose() * MF_;
    out.M = 0.5 * (out.M + out.M.transpose()).eval();
  }
}

}  // namespace flexmb::core
