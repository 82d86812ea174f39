#include "analysis/OperatorDynamics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {

// The mass terms in one pass (a column of packed coefficients A_p each): Mr = sum A_p phi_p,
// dMr/dt = sum A_p dphi_p/dt, and per term coef_p = A_p . w (w: packed 1/2 etad etad^T, so that
// coef_p = 1/2 etad^T Mr_p etad). For more than six reduced coordinates (fewer: fusedAccelerations).
void massPass(int m, const double* mass, const double* grad, const double* phi, const double* etad, const double* w,
              int terms, double* Mp, double* Mdp, double* coef) {
  const int packed = m * (m + 1) / 2;
  for (int j = 0; j < packed; ++j) Mp[j] = Mdp[j] = 0.0;
  for (int p = 0; p < terms; ++p, mass += packed, grad += m) {
    double rate = 0.0;
    for (int i = 0; i < m; ++i) rate += grad[i] * etad[i];
    const double value = phi[p];
    double quadratic = 0.0;
    for (int j = 0; j < packed; ++j) {
      Mp[j] += mass[j] * value;
      Mdp[j] += mass[j] * rate;
      quadratic += mass[j] * w[j];
    }
    coef[p] = quadratic;
  }
}

// Everything one right-hand side reads from the operators, with the Chebyshev tables of this call.
struct TermPass {
  const int* offsets;  // per term, its M entries into the tables
  const double *T, *dT;
  int terms, massTerms, dampingTerms;
  const double *mass, *damping;  // packed columns per term
  const double* scalar;          // per term: -U_p + sum_l a_l(t) phi_lp
};

// Mr(zeta) zetadd = f in one pass over the terms, nothing stored per term: each term's value and
// gradient (prefix and suffix products of its Chebyshev factors), then its share of Mr, dMr/dt,
// Cr and of the generalised force -grad U + sum a_k grad phi_k + 1/2 grad(zetad^T Mr zetad);
// then - dMr/dt zetad - Cr zetad and a fixed-size Cholesky. False: Mr not positive definite.
template <int M>
bool fusedAccelerations(const TermPass& in, const double* zetad, double* zetadd) {
  constexpr int K = M * (M + 1) / 2;
  double w[K], Mp[K] = {}, Mdp[K] = {}, Cp[K] = {}, force[M] = {};
  for (int a = 0, k = 0; a < M; ++a)
    for (int b = a; b < M; ++b, ++k) w[k] = (a == b ? 0.5 : 1.0) * zetad[a] * zetad[b];
  const int* off = in.offsets;
  for (int p = 0; p < in.terms; ++p, off += M) {
    double left[M + 1], g[M];
    left[0] = 1.0;
    for (int i = 0; i < M; ++i) left[i + 1] = left[i] * in.T[off[i]];
    const double value = left[M];
    double right = 1.0;
    for (int i = M - 1; i >= 0; --i) {
      g[i] = left[i] * in.dT[off[i]] * right;
      right *= in.T[off[i]];
    }
    double c = in.scalar[p];
    if (p < in.massTerms) {
      const double* A = in.mass + static_cast<long>(p) * K;
      double rate = 0.0, quadratic = 0.0;
      for (int i = 0; i < M; ++i) rate += g[i] * zetad[i];
      for (int j = 0; j < K; ++j) {
        Mp[j] += A[j] * value;
        Mdp[j] += A[j] * rate;
        quadratic += A[j] * w[j];
      }
      c += quadratic;
    }
    if (p < in.dampingTerms) {
      const double* D = in.damping + static_cast<long>(p) * K;
      for (int j = 0; j < K; ++j) Cp[j] += D[j] * value;
    }
    for (int i = 0; i < M; ++i) force[i] += g[i] * c;
  }
  Eigen::Matrix<double, M, M> Mr, Mdot, Cr;
  for (int a = 0, k = 0; a < M; ++a)
    for (int b = a; b < M; ++b, ++k) {
      Mr(a, b) = Mr(b, a) = Mp[k];
      Mdot(a, b) = Mdot(b, a) = Mdp[k];
      Cr(a, b) = Cr(b, a) = Cp[k];
    }
  const Eigen::Map<const Eigen::Matrix<double, M, 1>> v(zetad);
  Eigen::Matrix<double, M, 1> f = Eigen::Map<Eigen::Matrix<double, M, 1>>(force) - Mdot * v;
  if (in.dampingTerms) f -= Cr * v;
  const Eigen::LLT<Eigen::Matrix<double, M, M>> llt(Mr);
  if (llt.info() != Eigen::Success) return false;
  Eigen::Map<Eigen::Matrix<double, M, 1>> out(zetadd);
  out = llt.solve(f);
  return true;
}

}  // namespace

OperatorDynamics::OperatorDynamics(const core::Model& model, const ReducedOperators& ops)
    : ops_(ops),
      m_(ops.size()),
      basis_(ops.lower, ops.upper, ops.exponents),
      nPacked_(ops.size() * (ops.size() + 1) / 2),
      nU_(static_cast<int>(ops.potential.size())),
      nM_(static_cast<int>(ops.mass.cols())),
      nC_(static_cast<int>(ops.damping.cols())),
      nL_(static_cast<int>(ops.loadFields.rows())),
      llt_(ops.size()) {
  for (const OperatorLoad& l : ops.loads) {
    const std::vector<core::TimeLoad>* list = l.kind == OperatorLoad::Kind::NodalForce ? &model.timeForces
                                              : l.kind == OperatorLoad::Kind::Stress   ? &model.timeStresses
                                                                                       : &model.references;
    const auto it =
        std::find_if(list->begin(), list->end(), [&](const core::TimeLoad& t) { return t.index == l.index; });
    if (it == list->end())
      throw std::invalid_argument(std::string("the operators have a ") + operatorLoadKeyword(l.kind) +
                                  " load the model does not have");
    loadFunctions_.push_back(it->f);
  }
  const int P = ops.terms();
  phi_.setZero(P);
  coef_.setZero(P);
  scalar_.setZero(P);
  grad_.setZero(m_, P);
  weights_.resize(nPacked_);
  Mpacked_.resize(nPacked_);
  packed_.resize(nPacked_);
  force_.resize(m_);
  etadd_.resize(m_);
  M_.resize(m_, m_);
  Md_.resize(m_, m_);
  MD_.resize(nPacked_, 2);
  C_.resize(m_, m_);
  lastEta_.resize(m_);
  zeta_.resize(m_);
  zetad_.resize(m_);
  shifted_.resize(m_);
  f0_.resize(2 * m_);
  f1_.resize(2 * m_);
}

void OperatorDynamics::evaluate(const Eigen::Ref<const Eigen::VectorXd>& eta, bool gradient) {
  basis_.evaluate(eta, scratch_, phi_, gradient ? &grad_ : nullptr, static_cast<int>(phi_.size()));
}

void OperatorDynamics::unpack(const Eigen::Ref<const Eigen::VectorXd>& packed, Eigen::MatrixXd& S) const {
  int k = 0;
  for (int a = 0; a < m_; ++a)
    for (int b = a; b < m_; ++b) S(a, b) = S(b, a) = packed[k++];
}

template <int M>
bool OperatorDynamics::rhsFixed(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  using Vector = Eigen::Matrix<double, M, 1>;
  const Eigen::Map<const Eigen::Matrix<double, M, M>> R(ops_.rotation.data());
  const Vector zeta = R.transpose() * (y.template head<M>() - Eigen::Map<const Vector>(ops_.centre.data()));
  const Vector zetad = R.transpose() * y.template segment<M>(M);
  lastOutside_ = basis_.outside(zeta);
  if (lastOutside_ >= 0) {
    lastEta_ = zeta;
    return false;
  }
  basis_.tables(zeta, scratch_);
  loadScalars(t);
  const TermPass in{
      basis_.termOffsets(), scratch_.T.data(),   scratch_.dT.data(), static_cast<int>(scalar_.size()), nM_, nC_,
      ops_.mass.data(),     ops_.damping.data(), scalar_.data()};
  Vector zetadd;
  if (!fusedAccelerations<M>(in, zetad.data(), zetadd.data())) {
    lastEta_ = zeta;
    lastOutside_ = m_;  // not positive definite: treated as outside the range
    return false;
  }
  dydt.resize(2 * M);
  dydt.template head<M>() = y.template segment<M>(M);
  dydt.template segment<M>(M).noalias() = R * zetadd;
  return true;
}

void OperatorDynamics::loadScalars(double t) {
  scalar_.setZero();
  scalar_.head(nU_) = -ops_.potential;
  for (size_t l = 0; l < loadFunctions_.size(); ++l)
    scalar_.head(nL_).noalias() += loadFunctions_[l]->value(t) * ops_.loadFields.col(static_cast<Eigen::Index>(l));
}

bool OperatorDynamics::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  switch (m_) {  // one fused pass in fixed-size loops for the usual reduced sizes
    case 1:
      return rhsFixed<1>(t, y, dydt);
    case 2:
      return rhsFixed<2>(t, y, dydt);
    case 3:
      return rhsFixed<3>(t, y, dydt);
    case 4:
      return rhsFixed<4>(t, y, dydt);
    case 5:
      return rhsFixed<5>(t, y, dydt);
    case 6:
      return rhsFixed<6>(t, y, dydt);
    default:
      break;
  }
  // The operators' own coordinates zeta = R^T (eta - c) (the pilot's principal directions).
  shifted_ = y.head(m_) - ops_.centre;
  zeta_.noalias() = ops_.rotation.transpose() * shifted_;
  zetad_.noalias() = ops_.rotation.transpose() * y.tail(m_);
  const Eigen::VectorXd& eta = zeta_;
  const Eigen::VectorXd& etad = zetad_;
  lastOutside_ = basis_.outside(eta);
  if (lastOutside_ >= 0) {
    lastEta_ = eta;
    return false;
  }
  evaluate(eta, true);
  // One pass over the mass terms (a column of packed coefficients each): Mr, dMr/dt and, per term,
  // 1/2 etad^T Mr_p etad, whose gradient is the velocity terms' -1/2 grad(etad^T Mr etad).
  int k = 0;
  for (int a = 0; a < m_; ++a)
    for (int b = a; b < m_; ++b) weights_[k++] = (a == b ? 0.5 : 1.0) * etad[a] * etad[b];
  double* Mp = MD_.col(0).data();
  double* Mdp = MD_.col(1).data();
  massPass(m_, ops_.mass.data(), grad_.data(), phi_.data(), etad.data(), weights_.data(), nM_, Mp, Mdp, coef_.data());
  std::fill(coef_.data() + nM_, coef_.data() + coef_.size(), 0.0);
  unpack(MD_.col(0), M_);
  unpack(MD_.col(1), Md_);
  // Generalised force: -grad U + sum_k a_k(t) grad phi_k + 1/2 grad(etad^T Mr etad) in one pass
  // over the gradient table; then the rest of the velocity terms, - dMr/dt etad.
  loadScalars(t);
  coef_ += scalar_;
  force_.setZero();
  const int P = static_cast<int>(coef_.size());
  for (int p = 0; p < P; ++p) {
    const double c = coef_[p];
    const double* g = grad_.data() + static_cast<long>(p) * m_;
    for (int i = 0; i < m_; ++i) force_[i] += g[i] * c;
  }
  force_.noalias() -= Md_ * etad;
  if (nC_) {
    packed_.noalias() = ops_.damping * phi_.head(nC_);
    unpack(packed_, C_);
    force_.noalias() -= C_ * etad;
  }
  llt_.compute(M_);
  const bool definite = llt_.info() == Eigen::Success;
  if (definite) {
    etadd_ = force_;
    llt_.solveInPlace(etadd_);
  }
  if (!definite) {
    lastEta_ = eta;
    lastOutside_ = m_;  // not positive definite: treated as outside the range
    return false;
  }
  dydt.resize(2 * m_);
  dydt.head(m_) = y.tail(m_);
  dydt.tail(m_).noalias() = ops_.rotation * etadd_;
  return true;
}

bool OperatorDynamics::stateJacobian(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& units,
                                     Eigen::Ref<Eigen::MatrixXd> J) {
  if (!rhs(t, y, f0_)) return false;
  yStep_ = y;
  for (int j = 0; j < 2 * m_; ++j) {
    const double unit = units.size() == m_ ? units[j % m_] : 1.0;
    const double h = 1e-7 * std::max(std::abs(y[j]), unit);
    yStep_[j] = y[j] + h;
    if (!rhs(t, yStep_, f1_)) return false;
    J.col(j) = (f1_ - f0_) / h;
    yStep_[j] = y[j];
  }
  return true;
}

std::string OperatorDynamics::whereOutside() const {
  std::ostringstream s;
  if (lastOutside_ < 0) return "";
  if (lastOutside_ >= m_) {
    s << "the fitted mass matrix is not positive definite there";
    return s.str();
  }
  const int i = lastOutside_;
  s << "coordinate " << i + 1 << " of the operators' frame (zeta = R^T (eta - c)) = " << text::shortest(lastEta_[i])
    << " outside the trained [" << text::shortest(ops_.lower[i]) << ", " << text::shortest(ops_.upper[i]) << "]";
  return s.str();
}

void OperatorDynamics::massMatrix(const Eigen::VectorXd& eta, Eigen::MatrixXd& M) {
  evaluate(ops_.rotation.transpose() * (eta - ops_.centre), false);
  Mpacked_.noalias() = ops_.mass * phi_.head(nM_);
  unpack(Mpacked_, M_);
  M.noalias() = ops_.rotation * M_ * ops_.rotation.transpose();  // Mr in eta: R Mzeta R^T
}

double OperatorDynamics::potential(const Eigen::VectorXd& eta) {
  evaluate(ops_.rotation.transpose() * (eta - ops_.centre), false);
  return ops_.potential.dot(phi_.head(nU_));
}

double OperatorDynamics::energy(const Eigen::VectorXd& y) {
  Eigen::MatrixXd M;
  massMatrix(y.head(m_), M);
  return 0.5 * y.tail(m_).dot(M * y.tail(m_)) + ops_.potential.dot(phi_.head(nU_));
}

OperatorOutputMap::OperatorOutputMap(const core::Model& model, const ReducedOperators& ops)
    : ops_(ops), stresses_(model), basis_(ops.lower, ops.upper, ops.exponents) {
  const int no = size(), m = ops.size(), P = static_cast<int>(ops.outputFields.rows());
  elementColumns_.resize(no);
  for (int k = 0; k < no; ++k) {
    if (ops.outputs[k].kind != core::OperatorOutput::Kind::Deformation) continue;
    const core::ElementEntry& E = model.elements[model.eOwnerElement[ops.outputs[k].index]];
    std::vector<int> cols;
    for (int i = 0; i < E.impl->numDeformations(); ++i) {
      const auto at = std::find_if(ops.outputs.begin(), ops.outputs.end(), [&](const core::OperatorOutput& q) {
        return q.kind == core::OperatorOutput::Kind::Deformation && q.index == E.firstDef + i;
      });
      if (at == ops.outputs.end()) {
        cols.clear();
        break;
      }
      cols.push_back(static_cast<int>(at - ops.outputs.begin()));
    }
    elementColumns_[k] = std::move(cols);
  }
  zeta_.resize(m);
  zetad_.resize(m);
  zetadd_.resize(m);
  phi_.resize(P);
  dphi_.resize(P);
  ddphi_.resize(P);
  int widest = 0;
  for (const auto& E : model.elements) widest = std::max(widest, E.impl->numDeformations());
  e_.resize(widest);
  ed_.resize(widest);
}

bool OperatorOutputMap::evaluate(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& etadd,
                                 core::TrackedOutputs& into) {
  const int m = ops_.size(), no = size(), P = static_cast<int>(ops_.outputFields.rows());
  zeta_.noalias() = ops_.rotation.transpose() * (y.head(m) - ops_.centre);
  if (basis_.outside(zeta_) >= 0) return false;
  zetad_.noalias() = ops_.rotation.transpose() * y.tail(m);
  zetadd_.noalias() = ops_.rotation.transpose() * etadd;
  basis_.pathDerivatives(zeta_, zetad_, zetadd_, scratch_, phi_, dphi_, ddphi_, P);
  Eigen::VectorXd value = ops_.outputFields.transpose() * phi_, rate = ops_.outputFields.transpose() * dphi_,
                  acceleration = ops_.outputFields.transpose() * ddphi_;
  Eigen::VectorXd stress = Eigen::VectorXd::Constant(no, std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < no; ++k) {
    const std::vector<int>& cols = elementColumns_[k];
    if (cols.empty()) continue;
    for (size_t j = 0; j < cols.size(); ++j)
      e_[static_cast<int>(j)] = value[cols[j]], ed_[static_cast<int>(j)] = rate[cols[j]];
    stress[k] = stresses_.stressOf(t, ops_.outputs[k].index, e_.data(), ed_.data());
  }
  into.value.push_back(std::move(value));
  into.rate.push_back(std::move(rate));
  into.acceleration.push_back(std::move(acceleration));
  into.stress.push_back(std::move(stress));
  ++into.fromOperators;
  return true;
}

void OperatorOutputMap::fromStates(const core::StateOutputs& s, core::TrackedOutputs& into) const {
  const int no = size();
  Eigen::VectorXd value(no), rate(no), acceleration(no),
      stress = Eigen::VectorXd::Constant(no, std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < no; ++k) {
    const int i = ops_.outputs[k].index;
    if (ops_.outputs[k].kind == core::OperatorOutput::Kind::Deformation) {
      value[k] = s.e[i], rate[k] = s.ed[i], acceleration[k] = s.edd[i];
      if (!elementColumns_[k].empty()) stress[k] = s.sig[i];
    } else {
      value[k] = s.x[i], rate[k] = s.xd[i], acceleration[k] = s.xdd[i];
    }
  }
  into.value.push_back(std::move(value));
  into.rate.push_back(std::move(rate));
  into.acceleration.push_back(std::move(acceleration));
  into.stress.push_back(std::move(stress));
  ++into.fromKinematics;
}

}  // namespace flexmb::analysis
