#include "core/dynamics/SaddlePointAccelerations.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace flexmb::core {

SaddlePointAccelerations::SaddlePointAccelerations(const Model& model, const Inertia& inertia)
    : model_(model), inertia_(inertia) {
  freeOf_.assign(model.nx, -1);
  for (int i = 0; i < model.nx; ++i)
    if (model.xRole[i] == Role::Calculable || model.xRole[i] == Role::Dynamic) {
      freeOf_[i] = nf_++;
      freeCoord_.push_back(i);
    }
  rowOf_.assign(model.ne, -1);
  for (int k = 0; k < model.ne; ++k)
    if (model.eRole[k] == Role::Fixed || model.eRole[k] == Role::Input) rowOf_[k] = nr_++;
  n_ = nf_ + nr_;
  inputCoords_ = !model.inputX.empty();
  inputDefs_ = !model.inputE.empty();

  // Entries (col, row, owner): owner < 0 marks the diagonal, otherwise a mass or Jacobian slot that
  // is resolved after sorting.
  struct Entry {
    int col, row;
    int kind;   // 0 diagonal, 1 mass, 2 Jacobian (upper), 3 Jacobian (transposed)
    int owner;  // free index, massive-element position, element
    int local;  // slot within the owner
  };
  std::vector<Entry> entries;
  for (int f = 0; f < nf_; ++f) entries.push_back({f, f, 0, f, 0});
  const auto& massive = inertia.massiveElements();
  std::vector<std::vector<int>> massSlotOf(massive.size()), jacSlotOf(model.elements.size());
  for (size_t k = 0; k < massive.size(); ++k) {
    const auto& E = model.elements[massive[k]];
    const int nc = static_cast<int>(E.coords.size());
    massSlotOf[k].assign(nc * nc, -1);
    for (int b = 0; b < nc; ++b)
      for (int a = 0; a < nc; ++a) {
        const int fa = freeOf_[E.coords[a]], fb = freeOf_[E.coords[b]];
        if (fa >= 0 && fb >= 0) entries.push_back({fb, fa, 1, static_cast<int>(k), a + b * nc});
      }
  }
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nd = E.impl->numDeformations(), nc = static_cast<int>(E.coords.size());
    jacSlotOf[el].assign(2 * nd * nc, -1);
    for (int i = 0; i < nd; ++i) {
      const int r = rowOf_[E.firstDef + i];
      if (r < 0) continue;
      for (int j = 0; j < nc; ++j) {
        const int f = freeOf_[E.coords[j]];
        if (f < 0) continue;
        entries.push_back({f, nf_ + r, 2, static_cast<int>(el), 2 * (i * nc + j)});
        entries.push_back({nf_ + r, f, 3, static_cast<int>(el), 2 * (i * nc + j) + 1});
      }
    }
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return std::tie(a.col, a.row) < std::tie(b.col, b.row); });
  colPtr_.assign(n_ + 1, 0);
  diagSlot_.assign(nf_, -1);
  for (size_t k = 0; k < entries.size(); ++k) {
    const Entry& e = entries[k];
    if (k == 0 || entries[k - 1].col != e.col || entries[k - 1].row != e.row) {
      rowIdx_.push_back(e.row);
      ++colPtr_[e.col + 1];
    }
    const int slot = static_cast<int>(rowIdx_.size()) - 1;
    if (e.kind == 0)
      diagSlot_[e.owner] = slot;
    else if (e.kind == 1)
      massSlotOf[e.owner][e.local] = slot;
    else
      jacSlotOf[e.owner][e.local] = slot;
  }
  for (int c = 0; c < n_; ++c) colPtr_[c + 1] += colPtr_[c];
  // Flat lists for assemble: per massive element its (slot, entry of M_e), per element its
  // (slot, transposed slot, entry of D_e), both in element order.
  massRange_.assign(1, 0);
  for (size_t k = 0; k < massive.size(); ++k) {
    const int nc = static_cast<int>(model.elements[massive[k]].coords.size());
    for (int local = 0; local < nc * nc; ++local)
      if (massSlotOf[k][local] >= 0) massSlot_.push_back(massSlotOf[k][local]), massLocal_.push_back(local);
    massRange_.push_back(static_cast<int>(massSlot_.size()));
  }
  jacRange_.assign(1, 0);
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nd = E.impl->numDeformations(), nc = static_cast<int>(E.coords.size());
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nc; ++j) {
        const int s = jacSlotOf[el][2 * (i * nc + j)];
        if (s < 0) continue;
        jacSlot_.push_back(s);
        jacSlotT_.push_back(jacSlotOf[el][2 * (i * nc + j) + 1]);
        jacLocal_.push_back(i + j * nd);  // column-major, leading dimension nd
      }
    jacRange_.push_back(static_cast<int>(jacSlot_.size()));
  }
  values_.assign(rowIdx_.size(), 0.0);
  slotScale_.assign(rowIdx_.size(), 1.0);
  scale_.assign(n_, 1.0);
  lu_.disableScaling();  // equilibrated by scale_ (chooseScaling)
  if (n_ > 0) lu_.analyze(n_, colPtr_.data(), rowIdx_.data());
  b_.setZero(n_);
  xddKnown_.setZero(model.nx);
  eddInput_.setZero(model.ne);
  Mk_.setZero(model.nx);
}

void SaddlePointAccelerations::assemble(const GeometricTransferFunctions& gtf) {
  std::fill(values_.begin(), values_.end(), 0.0);
  const Eigen::VectorXd& lumped = inertia_.lumped();
  for (int f = 0; f < nf_; ++f) values_[diagSlot_[f]] = lumped[freeCoord_[f]] * slotScale_[diagSlot_[f]];
  for (size_t k = 0; k + 1 < massRange_.size(); ++k) {
    const double* Me = inertia_.block(k).data();  // column-major, leading dimension = its rows
    for (int p = massRange_[k]; p < massRange_[k + 1]; ++p)
      values_[massSlot_[p]] += Me[massLocal_[p]] * slotScale_[massSlot_[p]];
  }
  for (size_t el = 0; el + 1 < jacRange_.size(); ++el) {
    if (jacRange_[el] == jacRange_[el + 1]) continue;
    const double* De = gtf.elementJacobian(static_cast<int>(el)).data();
    for (int p = jacRange_[el]; p < jacRange_[el + 1]; ++p) {
      const double v = De[jacLocal_[p]] * slotScale_[jacSlot_[p]];
      values_[jacSlot_[p]] = v;
      values_[jacSlotT_[p]] = v;
    }
  }
}

void SaddlePointAccelerations::chooseScaling() {
  // Symmetric diagonal scaling from the first configuration: unit mass diagonal on the free
  // coordinates (translational and rotary masses differ by many decades), unit largest entry in
  // each constraint row, so that the pivots the factorisation compares are commensurate.
  std::vector<double> diag(nf_, 0.0);
  for (int f = 0; f < nf_; ++f) diag[f] = values_[diagSlot_[f]];
  const double maxDiag = nf_ ? *std::max_element(diag.begin(), diag.end()) : 0.0;
  for (int f = 0; f < nf_; ++f) {
    const double d = diag[f] > 1e-12 * maxDiag ? diag[f] : maxDiag;
    scale_[f] = d > 0.0 && std::isfinite(d) ? 1.0 / std::sqrt(d) : 1.0;
  }
  std::vector<double> rowMax(nr_, 0.0);
  for (int c = 0; c < nf_; ++c)
    for (int p = colPtr_[c]; p < colPtr_[c + 1]; ++p)
      if (rowIdx_[p] >= nf_)
        rowMax[rowIdx_[p] - nf_] = std::max(rowMax[rowIdx_[p] - nf_], std::abs(values_[p]) * scale_[c]);
  for (int r = 0; r < nr_; ++r) scale_[nf_ + r] = rowMax[r] > 0.0 && std::isfinite(rowMax[r]) ? 1.0 / rowMax[r] : 1.0;
  for (int c = 0; c < n_; ++c)
    for (int p = colPtr_[c]; p < colPtr_[c + 1]; ++p) slotScale_[p] = scale_[rowIdx_[p]] * scale_[c];
  scaled_ = true;
}

bool SaddlePointAccelerations::solve(double t, const GeometricTransferFunctions& gtf, const Eigen::VectorXd& d2,
                                     const Eigen::VectorXd& r, Eigen::VectorXd& qdd, Eigen::VectorXd& xdd) {
  if (!scaled_) {
    assemble(gtf);
    chooseScaling();
  }
  assemble(gtf);

  // Prescribed accelerations of the known coordinates and the input deformations.
  const bool rheonomic = inputCoords_ || inputDefs_;
  if (rheonomic) {
    xddKnown_.setZero();
    eddInput_.setZero();
    gtf.prescribedAccelerations(t, xddKnown_, eddInput_);
  }

  for (int f = 0; f < nf_; ++f) b_[f] = r[freeCoord_[f]];
  if (inputCoords_) {
    inertia_.multiply(xddKnown_, Mk_);
    for (int f = 0; f < nf_; ++f) b_[f] -= Mk_[freeCoord_[f]];
  }
  for (int k = 0; k < model_.ne; ++k)
    if (rowOf_[k] >= 0) b_[nf_ + rowOf_[k]] = eddInput_[k] - d2[k];
  if (inputCoords_) {
    // - D_R xdd_k: the known coordinates' share of the constraint accelerations.
    for (size_t el = 0; el < model_.elements.size(); ++el) {
      const auto& E = model_.elements[el];
      const DefJac& De = gtf.elementJacobian(static_cast<int>(el));
      for (int i = 0; i < De.rows(); ++i) {
        const int row = rowOf_[E.firstDef + i];
        if (row < 0) continue;
        double s = 0.0;
        for (int j = 0; j < De.cols(); ++j) s += De(i, j) * xddKnown_[E.coords[j]];
        b_[nf_ + row] -= s;
      }
    }
  }
  for (int i = 0; i < n_; ++i) b_[i] *= scale_[i];
  if (!lu_.factorize(values_.data())) return false;
  lu_.solve(b_.data(), 1);

  // xdd: prescribed on the known coordinates, solved on the free ones.
  if (rheonomic)
    xdd = xddKnown_;
  else
    xdd.setZero(model_.nx);
  for (int f = 0; f < nf_; ++f) xdd[freeCoord_[f]] = b_[f] * scale_[f];
  for (int j = 0; j < model_.numDofs(); ++j) {
    const auto& d = model_.dofs[j];
    if (!d.isDeformation) {
      qdd[j] = xdd[d.index];
      continue;
    }
    const int el = model_.eOwnerElement[d.index];
    const auto& E = model_.elements[el];
    const DefJac& De = gtf.elementJacobian(el);
    const int i = d.index - E.firstDef;
    double s = d2[d.index];
    for (int c = 0; c < De.cols(); ++c) s += De(i, c) * xdd[E.coords[c]];
    qdd[j] = s;
  }
  return true;
}

}  // namespace flexmb::core
