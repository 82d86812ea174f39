#include "core/linearization/ConstrainedTangent.hpp"

#include <algorithm>
#include <stdexcept>
#include <tuple>

#include "core/kinematics/GeometricTransferFunctions.hpp"

namespace flexmb::core {

ConstrainedTangent::ConstrainedTangent(const Model& model, const NodalMatrices::Sparse& pattern) : model_(model) {
  const int nx = model.nx;
  freeOf_.assign(nx, -1);
  for (int i = 0; i < nx; ++i)
    if (model.xRole[i] == Role::Calculable || model.xRole[i] == Role::Dynamic) freeOf_[i] = nf_++;
  std::vector<int> crow(model.ne, -1), elementOf(model.ne, -1), localRow(model.ne, -1);
  int nc = 0;
  for (int k = 0; k < model.ne; ++k)
    if (model.eRole[k] == Role::Fixed || model.eRole[k] == Role::Input) crow[k] = nc++;
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    for (int i = 0; i < E.impl->numDeformations(); ++i) {
      elementOf[E.firstDef + i] = static_cast<int>(el);
      localRow[E.firstDef + i] = i;
    }
  }
  n_ = nf_ + nc;

  // Entries (column, row, source): source >= 0 a nodal pattern index (H), else -1 - 2 e (C of
  // constraint entry e) or -2 - 2 e (its transpose).
  std::vector<std::tuple<int, int, int>> all;
  for (int c = 0; c < nx; ++c) {
    if (freeOf_[c] < 0) continue;
    for (int p = pattern.outerIndexPtr()[c]; p < pattern.outerIndexPtr()[c + 1]; ++p) {
      const int r = pattern.innerIndexPtr()[p];
      if (freeOf_[r] >= 0) all.emplace_back(freeOf_[c], freeOf_[r], p);
    }
  }
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    for (int i = 0; i < E.impl->numDeformations(); ++i) {
      const int row = crow[E.firstDef + i];
      if (row < 0) continue;
      for (size_t j = 0; j < E.coords.size(); ++j) {
        const int f = freeOf_[E.coords[j]];
        if (f < 0) continue;
        const int e = static_cast<int>(entries_.size());
        entries_.push_back({static_cast<int>(el), i, static_cast<int>(j), -1, -1});
        all.emplace_back(f, nf_ + row, -1 - 2 * e);
        all.emplace_back(nf_ + row, f, -2 - 2 * e);
      }
    }
  }
  std::sort(all.begin(), all.end());
  colPtr_.assign(n_ + 1, 0);
  hSlot_.assign(pattern.nonZeros(), -1);
  for (const auto& [col, row, source] : all) {
    if (!rowIdx_.empty() && colPtr_[col + 1] > 0 && rowIdx_.back() == row)
      throw std::logic_error("ConstrainedTangent: duplicate entry");  // an element lists a coordinate twice
    const int slot = static_cast<int>(rowIdx_.size());
    rowIdx_.push_back(row);
    ++colPtr_[col + 1];
    if (source >= 0)
      hSlot_[source] = slot;
    else if ((-source) % 2 == 1)
      entries_[(-1 - source) / 2].slotC = slot;
    else
      entries_[(-2 - source) / 2].slotCt = slot;
  }
  for (int c = 0; c < n_; ++c) colPtr_[c + 1] += colPtr_[c];
  values_.assign(rowIdx_.size(), 0.0);
  if (n_ > 0) lu_.analyze(n_, colPtr_.data(), rowIdx_.data());

  // P's rows: DYNE rows of the element Jacobians (copied at each factorisation), DYNX unit rows.
  for (const auto& d : model.dofs) {
    DofRow r;
    if (d.isDeformation) {
      r.element = elementOf[d.index];
      r.row = localRow[d.index];
      r.first = static_cast<int>(prowFree_.size());
      for (int c : model.elements[r.element].coords) prowFree_.push_back(freeOf_[c]);
    } else {
      r.freeIndex = freeOf_[d.index];
    }
    dofRows_.push_back(r);
  }
  prow_.assign(prowFree_.size(), 0.0);
  rhs_.setZero(n_);
  patternOuter_.assign(pattern.outerIndexPtr(), pattern.outerIndexPtr() + nx + 1);
  patternInner_.assign(pattern.innerIndexPtr(), pattern.innerIndexPtr() + pattern.nonZeros());
}

bool ConstrainedTangent::factorize(const NodalMatrices& nodal, const GeometricTransferFunctions& gtf) {
  const auto& K = nodal.K();
  const auto& G = nodal.G();
  if (K.nonZeros() != static_cast<Eigen::Index>(hSlot_.size()) || G.nonZeros() != K.nonZeros())
    throw std::logic_error("ConstrainedTangent: nodal matrices off the analysed pattern");
  std::fill(values_.begin(), values_.end(), 0.0);
  for (size_t p = 0; p < hSlot_.size(); ++p)
    if (hSlot_[p] >= 0) values_[hSlot_[p]] += K.valuePtr()[p] + G.valuePtr()[p];
  if (nodal.hasMomentStiffness()) {  // the moments' skew load stiffness W_x (not symmetric: LU)
    const double* w = nodal.W().valuePtr();
    for (size_t p = 0; p < hSlot_.size(); ++p)
      if (hSlot_[p] >= 0) values_[hSlot_[p]] += w[p];
  }
  return factorizeFilled(gtf);
}

bool ConstrainedTangent::factorizeMass(const NodalMatrices& nodal, const GeometricTransferFunctions& gtf) {
  const auto& M = nodal.M();
  if (M.nonZeros() != static_cast<Eigen::Index>(hSlot_.size()))
    throw std::logic_error("ConstrainedTangent: nodal mass matrix off the analysed pattern");
  std::fill(values_.begin(), values_.end(), 0.0);
  for (size_t p = 0; p < hSlot_.size(); ++p)
    if (hSlot_[p] >= 0) values_[hSlot_[p]] += M.valuePtr()[p];
  return factorizeFilled(gtf);
}

bool ConstrainedTangent::factorizeFilled(const GeometricTransferFunctions& gtf) {
  fillJacobians(gtf);
  return lu_.factorize(values_.data());
}

void ConstrainedTangent::keep(const NodalMatrices& nodal, const GeometricTransferFunctions& gtf) {
  const std::size_t nnz = hSlot_.size();
  if (static_cast<std::size_t>(nodal.M().nonZeros()) != nnz || static_cast<std::size_t>(nodal.K().nonZeros()) != nnz)
    throw std::logic_error("ConstrainedTangent: nodal matrices off the analysed pattern");
  keptMass_.assign(nodal.M().valuePtr(), nodal.M().valuePtr() + nnz);
  keptStiffness_.assign(nodal.K().valuePtr(), nodal.K().valuePtr() + nnz);
  const double* g = nodal.G().valuePtr();
  for (std::size_t p = 0; p < nnz; ++p) keptStiffness_[p] += g[p];
  if (nodal.hasMomentStiffness())
    for (std::size_t p = 0; p < nnz; ++p) keptStiffness_[p] += nodal.W().valuePtr()[p];
  if (nodal.hasDamping())
    keptDamping_.assign(nodal.D().valuePtr(), nodal.D().valuePtr() + nnz);
  else
    keptDamping_.clear();
  fillJacobians(gtf);
}

bool ConstrainedTangent::factorizeWeighted(double betaP, double gammaP) {
  if (keptMass_.size() != hSlot_.size()) throw std::logic_error("ConstrainedTangent::factorizeWeighted before keep");
  for (std::size_t p = 0; p < hSlot_.size(); ++p) {
    if (hSlot_[p] < 0) continue;
    double v = keptMass_[p] + betaP * keptStiffness_[p];
    if (!keptDamping_.empty()) v += gammaP * keptDamping_[p];
    values_[hSlot_[p]] = v;
  }
  return lu_.factorize(values_.data());
}

void ConstrainedTangent::massProduct(const Eigen::VectorXd& z, Eigen::VectorXd& w) const {
  w.setZero(z.size());
  for (std::size_t c = 0; c + 1 < patternOuter_.size(); ++c)
    for (int p = patternOuter_[c]; p < patternOuter_[c + 1]; ++p) w[patternInner_[p]] += keptMass_[p] * z[c];
}

void ConstrainedTangent::solveNodal(const Eigen::VectorXd& w, Eigen::VectorXd& x) const {
  rhs_.setZero();
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (freeOf_[i] >= 0) rhs_[freeOf_[i]] = w[i];
  solveFilled(x);
}

void ConstrainedTangent::fillJacobians(const GeometricTransferFunctions& gtf) {
  for (const auto& e : entries_) {
    const double v = gtf.elementJacobian(e.element)(e.row, e.col);
    values_[e.slotC] = v;
    values_[e.slotCt] = v;
  }
  for (const auto& r : dofRows_) {
    if (r.element < 0) continue;
    const DefJac& J = gtf.elementJacobian(r.element);
    for (Eigen::Index c = 0; c < J.cols(); ++c) prow_[r.first + c] = J(r.row, c);
  }
}

void ConstrainedTangent::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  // rhs = [P^T b; 0]
  rhs_.setZero();
  const int nq = static_cast<int>(dofRows_.size());
  auto forEntry = [&](const DofRow& r, auto&& fn) {
    const int nc = static_cast<int>(model_.elements[r.element].coords.size());
    for (int c = 0; c < nc; ++c)
      if (prowFree_[r.first + c] >= 0) fn(prowFree_[r.first + c], prow_[r.first + c]);
  };
  for (int j = 0; j < nq; ++j) {
    const DofRow& r = dofRows_[j];
    if (r.element < 0)
      rhs_[r.freeIndex] += b[j];
    else
      forEntry(r, [&](int f, double v) { rhs_[f] += b[j] * v; });
  }
  solveFilled(x);
}

void ConstrainedTangent::solveFilled(Eigen::VectorXd& x) const {
  const int nq = static_cast<int>(dofRows_.size());
  auto forEntry = [&](const DofRow& r, auto&& fn) {
    const int nc = static_cast<int>(model_.elements[r.element].coords.size());
    for (int c = 0; c < nc; ++c)
      if (prowFree_[r.first + c] >= 0) fn(prowFree_[r.first + c], prow_[r.first + c]);
  };
  lu_.solve(rhs_.data(), 1);
  // x = P dx
  x.resize(nq);
  for (int j = 0; j < nq; ++j) {
    const DofRow& r = dofRows_[j];
    if (r.element < 0) {
      x[j] = rhs_[r.freeIndex];
    } else {
      double s = 0.0;
      forEntry(r, [&](int f, double v) { s += v * rhs_[f]; });
      x[j] = s;
    }
  }
}

}  // namespace flexmb::core
