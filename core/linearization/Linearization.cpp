#include "core/linearization/Linearization.hpp"

#include <algorithm>
#include <stdexcept>

namespace flexmb::core {

Linearization::Linearization(const Model& model, std::optional<Eigen::MatrixXd> basis)
    : Linearization(std::make_unique<Workspace>(model), nullptr, std::move(basis)) {}

Linearization::Linearization(Workspace& workspace, std::optional<Eigen::MatrixXd> basis)
    : Linearization(nullptr, &workspace, std::move(basis)) {}

Linearization::Linearization(std::unique_ptr<Workspace> own, Workspace* shared, std::optional<Eigen::MatrixXd> basis)
    : own_(std::move(own)),
      model_((shared ? *shared : *own_).model()),
      coords_(model_.numDofs(), std::move(basis)),
      m_(coords_.size()),
      gtf_((shared ? *shared : *own_).kinematics()),
      inertia_((shared ? *shared : *own_).inertia()),
      stresses_((shared ? *shared : *own_).stresses()),
      steps_((shared ? *shared : *own_).steps()),
      nodal_((shared ? *shared : *own_).nodal()) {
  active_.resize(model_.ne);
  for (int k = 0; k < model_.ne; ++k) active_[k] = stresses_.isActive(k) ? 1 : 0;
  defDof_.assign(model_.ne, -1);
  defCalc_.assign(model_.ne, -1);
  for (int j = 0; j < model_.numDofs(); ++j)
    if (model_.dofs[j].isDeformation) defDof_[model_.dofs[j].index] = j;
  for (int k = 0; k < model_.ne; ++k)
    if (active_[k] && model_.eRole[k] == Role::Calculable) defCalc_[k] = nCalc_++;
}

void Linearization::dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const { coords_.toFull(eta, q); }

void Linearization::appliedForces(double t, double loadFactor, Eigen::VectorXd& f, double initialFactor) const {
  loadFactor_ = loadFactor;  // the moment load stiffness of geometricStiffness follows them
  initialFactor_ = initialFactor;
  appliedLoads(model_, inertia_, t, loadFactor, gtf_.x(), f, initialFactor);
}

void Linearization::staticForces(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q) {
  dofs(eta, q_);
  gtf_.solvePositions(t, q_);
  forcesInPlace(t, f, Q);
}

void Linearization::forcesInPlace(double t, const Eigen::VectorXd& f, Eigen::VectorXd& Q) {
  stresses_.evaluate(t, gtf_.e(), nullptr, sigma_);
  r_ = f;
  gtf_.addTransposedJacobianProduct(sigma_, r_, -1.0);
  generalizedForces(Q);
}

void Linearization::staticResidual(double t, const Eigen::VectorXd& eta, double loadFactor, double initialFactor,
                                   Eigen::VectorXd& Q) {
  dofs(eta, q_);
  gtf_.solvePositions(t, q_);
  appliedForces(t, loadFactor, f_, initialFactor);
  forcesInPlace(t, f_, Q);
}

bool Linearization::staticTangent(double t, const Eigen::VectorXd& eta, double loadFactor, double initialFactor,
                                  Eigen::VectorXd& Q) {
  if (basis()) throw std::logic_error("Linearization::staticTangent: full models only (no basis)");
  staticResidual(t, eta, loadFactor, initialFactor, Q);
  geometricStiffness(scratch_, false);  // K_x and G_x (Eq. 16) with the reaction stresses of r_
  if (!constrainedTangent_) constrainedTangent_ = std::make_unique<ConstrainedTangent>(model_, nodal_.K());
  return constrainedTangent_->factorize(nodal_, gtf_);
}

void Linearization::solveStaticTangent(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  if (!constrainedTangent_) throw std::logic_error("Linearization::solveStaticTangent before staticTangent");
  constrainedTangent_->solve(b, x);
}

bool Linearization::factorizeMass() {
  if (basis()) throw std::logic_error("Linearization::factorizeMass: full models only (no basis)");
  nodal_.assembleMass(gtf_.x());
  if (!constrainedMass_) constrainedMass_ = std::make_unique<ConstrainedTangent>(model_, nodal_.M());
  return constrainedMass_->factorizeMass(nodal_, gtf_);
}

void Linearization::solveMass(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  if (!constrainedMass_) throw std::logic_error("Linearization::solveMass before factorizeMass");
  X.resize(B.rows(), B.cols());
  Eigen::VectorXd b, x;
  for (Eigen::Index j = 0; j < B.cols(); ++j) {
    b = B.col(j);
    constrainedMass_->solve(b, x);
    X.col(j) = x;
  }
}

void Linearization::iterationMatrix(double t, const Eigen::VectorXd& eta) {
  if (basis()) throw std::logic_error("Linearization::iterationMatrix: full models only (no basis)");
  staticResidual(t, eta, 0.0, 1.0, scratch_.Q);
  geometricStiffness(scratch_, false);  // K_x, G_x (and D_x) with the reaction stresses of r_
  nodal_.assembleMass(gtf_.x());
  if (!iteration_) iteration_ = std::make_unique<ConstrainedTangent>(model_, nodal_.K());
  iteration_->keep(nodal_, gtf_);
  iterationTime_ = t;
  gtf_.velocities(t, Eigen::VectorXd::Zero(model_.numDofs()), iterationRest_);
}

bool Linearization::factorizeIteration(double betaP, double gammaP) {
  if (!iteration_) throw std::logic_error("Linearization::factorizeIteration before iterationMatrix");
  return iteration_->factorizeWeighted(betaP, gammaP);
}

void Linearization::solveIteration(const Eigen::VectorXd& r, Eigen::VectorXd& x) {
  if (!iteration_) throw std::logic_error("Linearization::solveIteration before iterationMatrix");
  // Mbar r = F_q^T M_x (F_q r): the nodal load M_x F_q r in the saddle-point right-hand side.
  gtf_.velocities(iterationTime_, r, nodalVelocity_);
  nodalVelocity_ -= iterationRest_;
  iteration_->massProduct(nodalVelocity_, nodalLoad_);
  iteration_->solveNodal(nodalLoad_, x);
}

void Linearization::generalizedForces(Eigen::VectorXd& Q) {
  // Q = (F_q V)^T r without F_q (one transposed solve instead of n_q): J^T lambda = r_c gives the
  // DYNE components (lambda on their rows: F_q e_j solves J dx_c = e_j), r - D_x^T lambda the DYNX
  // ones (their columns add the known-coordinate coupling).
  lambda_.setZero(model_.ne);
  gtf_.addConstraintStresses(r_, lambda_);
  work_ = r_;
  gtf_.addTransposedJacobianProduct(lambda_, work_, -1.0);
  const int nq = model_.numDofs();
  qf_.resize(nq);
  for (int j = 0; j < nq; ++j) {
    const auto& d = model_.dofs[j];
    qf_[j] = d.isDeformation ? lambda_[d.index] : work_[d.index];
  }
  if (basis())
    Q.noalias() = basis()->transpose() * qf_;
  else
    Q = qf_;
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

void Linearization::updateTransfer() {
  // F_q V depends on the configuration alone: statics asks for it at one equilibrium up to three
  // times (force scale, Newton tangent, atRest), each an m-column kinematic solve and a copy.
  if (transferX_.size() == gtf_.x().size() && transferX_ == gtf_.x()) return;
  gtf_.firstOrder(basis(), FqV_);
  transferRows_ = false;  // the row-major copy when a projection needs it
  transferX_ = gtf_.x();
}

void Linearization::project(const NodalMatrices::Sparse& X, Eigen::MatrixXd& out) {
  const double* v = X.valuePtr();
  if (std::all_of(v, v + X.nonZeros(), [](double a) { return a == 0.0; })) {  // unloaded, unstressed G_x
    out.setZero(m_, m_);
    return;
  }
  // X A by rows: entry X(r, c) adds X(r, c) A(c, :) to row r, a contiguous axpy of length m in
  // the row-major copies (the column-major sparse-dense product strides through A per entry).
  const auto& Frows = transferRows();
  XArows_.setZero(FqV_.rows(), m_);
  for (int c = 0; c < X.outerSize(); ++c)
    for (int p = X.outerIndexPtr()[c]; p < X.outerIndexPtr()[c + 1]; ++p)
      if (v[p] != 0.0) XArows_.row(X.innerIndexPtr()[p]) += v[p] * Frows.row(c);
  // X symmetric: half a product (the lower triangle), mirrored.
  out.resize(m_, m_);
  // Eigen 3.4's triangular product binds a reference to its operands' first coefficient, null when
  // they are empty (UBSan; a model without degrees of freedom): the empty or zero result directly.
  if (m_ == 0 || FqV_.rows() == 0) {
    out.setZero();
    return;
  }
  out.triangularView<Eigen::Lower>() = FqV_.transpose() * XArows_;
  out.triangularView<Eigen::StrictlyUpper>() = out.transpose();
}

bool Linearization::deformationProjection(bool damping, Eigen::MatrixXd& out, bool diagonalOnly) {
  // The dense rows cost n_c m^2 against the nodal projection's n_x m^2 / 2.
  if (basis() || m_ == 0 || 4 * nCalc_ > model_.nx) return false;
  // E_q's calculable rows D_c F_q, element by element from the Jacobians.
  Ec_.setZero(nCalc_, m_);
  for (const auto& E : model_.elements) {
    const int nd = E.impl->numDeformations();
    const DefJac& J = gtf_.elementJacobian(static_cast<int>(&E - model_.elements.data()));
    for (int i = 0; i < nd; ++i) {
      const int c = defCalc_[E.firstDef + i];
      if (c < 0) continue;
      for (std::size_t k = 0; k < E.coords.size(); ++k)
        if (J(i, static_cast<int>(k)) != 0.0) Ec_.row(c) += J(i, static_cast<int>(k)) * FqV_.row(E.coords[k]);
    }
  }
  // sum over element pairs (i, j) of S_ij row_i^T row_j: unit rows add entries, a unit and a
  // calculable row add a row and a column, two calculable rows go into S Ec for one product.
  if (diagonalOnly)
    out.setZero(m_, 1);
  else
    out.setZero(m_, m_);
  SEc_.setZero(nCalc_, m_);
  for (const auto& E : model_.elements) {
    if (damping ? !E.hasDamping : !E.hasStiffness) continue;
    const DefMat& S = damping ? E.Sd : E.S;
    const int nd = E.impl->numDeformations();
    for (int i = 0; i < nd; ++i) {
      const int ki = E.firstDef + i;
      if (!active_[ki]) continue;
      const int di = defDof_[ki], ci = defCalc_[ki];
      if (di < 0 && ci < 0) continue;  // a fixed or input deformation: a zero row
      for (int j = 0; j < nd; ++j) {
        const int kj = E.firstDef + j;
        const double sij = S(i, j);
        if (!active_[kj] || sij == 0.0) continue;
        const int dj = defDof_[kj], cj = defCalc_[kj];
        if (ci >= 0 && cj >= 0) {
          SEc_.row(ci) += sij * Ec_.row(cj);
        } else if (di >= 0 && dj >= 0) {
          if (!diagonalOnly)
            out(di, dj) += sij;
          else if (di == dj)
            out(di, 0) += sij;
        } else if (di >= 0 && cj >= 0) {
          if (!diagonalOnly)
            out.row(di) += sij * Ec_.row(cj);
          else
            out(di, 0) += sij * Ec_(cj, di);
        } else if (ci >= 0 && dj >= 0) {
          if (!diagonalOnly)
            out.col(dj) += sij * Ec_.row(ci).transpose();
          else
            out(dj, 0) += sij * Ec_(ci, dj);
        }
      }
    }
  }
  if (nCalc_ == 0) return true;
  if (diagonalOnly)
    out.col(0) += (Ec_.cwiseProduct(SEc_)).colwise().sum().transpose();
  else {  // the lower triangle, mirrored: exactly symmetric, as the nodal projection
    out.triangularView<Eigen::Lower>() += Ec_.transpose() * SEc_;
    out.triangularView<Eigen::StrictlyUpper>() = out.transpose();
  }
  return true;
}

void Linearization::stiffnessDiagonal(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f,
                                      Eigen::VectorXd& Q, Eigen::VectorXd& diagonal) {
  staticForces(t, eta, f, Q);
  updateTransfer();
  geometricStiffness(scratch_, false);
  if (deformationProjection(false, Gq_, true)) {
    diagonal = Gq_.col(0);
    return;
  }
  const NodalMatrices::Sparse& X = nodal_.K();
  const auto& Frows = transferRows();
  XArows_.setZero(FqV_.rows(), m_);
  const double* v = X.valuePtr();
  for (int c = 0; c < X.outerSize(); ++c)
    for (int p = X.outerIndexPtr()[c]; p < X.outerIndexPtr()[c + 1]; ++p)
      if (v[p] != 0.0) XArows_.row(X.innerIndexPtr()[p]) += v[p] * Frows.row(c);
  diagonal.resize(m_);
  for (int j = 0; j < m_; ++j) diagonal[j] = FqV_.col(j).dot(XArows_.col(j));
}

void Linearization::tangent(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q,
                            Eigen::MatrixXd& T) {
  staticForces(t, eta, f, Q);
  updateTransfer();
  geometricStiffness(scratch_, false);
  if (deformationProjection(false, T)) {
    project(nodal_.G(), Gq_);
    T += Gq_;
    if (nodal_.hasMomentStiffness()) addMomentStiffness(T);
    return;
  }
  KG_ = nodal_.K();
  Eigen::Map<Eigen::VectorXd>(KG_.valuePtr(), KG_.nonZeros()) +=
      Eigen::Map<const Eigen::VectorXd>(nodal_.G().valuePtr(), nodal_.G().nonZeros());
  project(KG_, T);
  if (nodal_.hasMomentStiffness()) addMomentStiffness(T);
}

void Linearization::addMomentStiffness(Eigen::MatrixXd& out) {
  for (const auto& mo : model_.moments) {
    const int at = model_.nodes[mo.node].firstCoord;
    const auto& W = nodal_.W();
    Eigen::Matrix4d Wb;  // the node's block of W_x
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) Wb(r, c) = W.coeff(at + r, at + c);
    WA_.noalias() = Wb * FqV_.middleRows(at, 4);
    out.noalias() += FqV_.middleRows(at, 4).transpose() * WA_;
  }
}

void Linearization::geometricStiffness(LinearizedSystem& out, bool projectG) {
  // Reaction stresses: D_x^T sigma~ = f on the calculable coordinates (r_ = f - D_x^T sigma).
  out.sigma = sigma_;
  gtf_.addConstraintStresses(r_, out.sigma);
  nodal_.assembleGeometric(gtf_.x(), out.sigma, steps_, initialFactor_, loadFactor_);
  nodal_.assembleStiffness(gtf_, active_);
  if (!projectG) return;
  project(nodal_.G(), out.G);
  if (nodal_.hasMomentStiffness()) {
    out.Gskew.setZero(m_, m_);
    addMomentStiffness(out.Gskew);
  } else {
    out.Gskew.resize(0, 0);
  }
}

void Linearization::initialRest(LinearizedSystem& out, Eigen::VectorXd& eta, bool withMass) {
  const double t0 = model_.settings.t0;
  const Eigen::VectorXd q0 = gtf_.initialDofs();
  gtf_.solvePositions(t0, q0);
  Eigen::VectorXd f;
  appliedForces(t0, 0.0, f);
  eta = basis() ? Eigen::VectorXd::Zero(m_) : q0;
  atRest(t0, eta, f, out, withMass);
}

void Linearization::atRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, LinearizedSystem& out,
                           bool withMass) {
  staticForces(t, eta, f, out.Q);
  updateTransfer();
  geometricStiffness(out);
  if (!deformationProjection(false, out.K)) project(nodal_.K(), out.K);
  if (!nodal_.hasDamping())
    out.D.resize(0, 0);  // no damping: left empty, as C and N
  else if (!deformationProjection(true, out.D))
    project(nodal_.D(), out.D);
  out.C.resize(0, 0);  // Eq. 16a: C = N = 0 at rest, left empty (no m^2 zeros each per equilibrium)
  out.N.resize(0, 0);
  if (withMass) {
    nodal_.assembleMass(gtf_.x());
    project(nodal_.M(), out.M);
  }
}

void Linearization::nodalAtRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, bool withMass) {
  dofs(eta, q_);
  gtf_.solvePositions(t, q_);
  stresses_.evaluate(t, gtf_.e(), nullptr, sigma_);
  r_ = f;
  gtf_.addTransposedJacobianProduct(sigma_, r_, -1.0);
  gtf_.addConstraintStresses(r_, sigma_);
  nodal_.assembleGeometric(gtf_.x(), sigma_, steps_, initialFactor_, loadFactor_);
  nodal_.assembleStiffness(gtf_, active_);
  if (withMass) nodal_.assembleMass(gtf_.x());
}

void Linearization::inMotion(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& etad,
                             const Eigen::VectorXd& etadd, LinearizedSystem& out) {
  dofs(eta, q_);
  dofs(etad, qd_);
  gtf_.solvePositions(t, q_);
  updateTransfer();
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
  project(nodal_.K(), out.K);
  if (nodal_.hasDamping())
    project(nodal_.D(), out.D);
  else
    out.D.setZero(m_, m_);
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

void Linearization::constrainedPencil(ConstrainedPencil& out) const {
  if (basis()) throw std::logic_error("Linearization::constrainedPencil: full models only (no basis)");
  const int nx = model_.nx;
  std::vector<int> fidx(nx, -1);
  out.free.clear();
  for (int i = 0; i < nx; ++i)
    if (model_.xRole[i] == Role::Calculable || model_.xRole[i] == Role::Dynamic) {
      fidx[i] = static_cast<int>(out.free.size());
      out.free.push_back(i);
    }
  const int nf = static_cast<int>(out.free.size());
  using T = Eigen::Triplet<double>;
  std::vector<T> tk, tm;
  auto restrict = [&](const NodalMatrices::Sparse& A, std::vector<T>& t, const NodalMatrices::Sparse* B) {
    for (int c = 0; c < nx; ++c) {
      if (fidx[c] < 0) continue;
      for (NodalMatrices::Sparse::InnerIterator it(A, c); it; ++it)
        if (fidx[it.row()] >= 0) t.emplace_back(fidx[it.row()], fidx[c], it.value());
      if (B)
        for (NodalMatrices::Sparse::InnerIterator it(*B, c); it; ++it)
          if (fidx[it.row()] >= 0) t.emplace_back(fidx[it.row()], fidx[c], it.value());
    }
  };
  restrict(nodal_.K(), tk, &nodal_.G());
  restrict(nodal_.M(), tm, nullptr);
  out.K.resize(nf, nf);
  out.K.setFromTriplets(tk.begin(), tk.end());
  out.M.resize(nf, nf);
  out.M.setFromTriplets(tm.begin(), tm.end());
  // Constraint rows and the DYNE rows of P from the element Jacobians.
  std::vector<int> crow(model_.ne, -1), prow(model_.ne, -1);
  int r = 0;
  for (int k = 0; k < model_.ne; ++k)
    if (model_.eRole[k] == Role::Fixed || model_.eRole[k] == Role::Input) crow[k] = r++;
  std::vector<T> tc, tp;
  for (int j = 0; j < model_.numDofs(); ++j) {
    const auto& d = model_.dofs[j];
    if (d.isDeformation)
      prow[d.index] = j;
    else if (fidx[d.index] >= 0)
      tp.emplace_back(j, fidx[d.index], 1.0);
  }
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& J = gtf_.elementJacobian(static_cast<int>(el));
    for (int i = 0; i < J.rows(); ++i) {
      const int k = E.firstDef + i;
      if (crow[k] < 0 && prow[k] < 0) continue;
      for (int c = 0; c < J.cols(); ++c) {
        const int fc = fidx[E.coords[c]];
        if (fc < 0 || J(i, c) == 0.0) continue;
        if (crow[k] >= 0)
          tc.emplace_back(crow[k], fc, J(i, c));
        else
          tp.emplace_back(prow[k], fc, J(i, c));
      }
    }
  }
  out.C.resize(r, nf);
  out.C.setFromTriplets(tc.begin(), tc.end());
  out.P.resize(model_.numDofs(), nf);
  out.P.setFromTriplets(tp.begin(), tp.end());
}

void placeAt(Linearization& lin, const EquilibriumPoint& at) {
  GeometricTransferFunctions& k = lin.kinematics();
  k.setRelativeTolerance(std::min(lin.model().settings.kinematicTol, 1e-12));
  k.setInputLoadFactor(at.loadFactor, at.initialFactor);
  if (at.x && at.x->size() == lin.model().nx) k.setConfiguration(*at.x);
  Eigen::VectorXd q;
  lin.dofs(at.eta, q);
  k.solvePositions(at.t, q);
}

void linearizeAt(Linearization& lin, const EquilibriumPoint& at, LinearizedSystem& out, bool withMass) {
  placeAt(lin, at);
  Eigen::VectorXd f;
  lin.appliedForces(at.t, at.loadFactor, f, at.initialFactor);
  lin.atRest(at.t, at.eta, f, out, withMass);
}

}  // namespace flexmb::core
