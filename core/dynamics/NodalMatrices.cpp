#include "core/dynamics/NodalMatrices.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/dynamics/Inertia.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"

namespace flexmb::core {

namespace {
int findSlot(const Eigen::SparseMatrix<double>& A, int row, int col) {
  const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
  const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  if (it == end || *it != row) throw std::logic_error("NodalMatrices: entry outside the pattern");
  return static_cast<int>(it - A.innerIndexPtr());
}
}  // namespace

NodalMatrices::NodalMatrices(const Model& model) : model_(model) {
  const int nx = model.nx;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < nx; ++i) t.emplace_back(i, i, 0.0);
  for (const auto& E : model.elements)
    for (int r : E.coords)
      for (int c : E.coords) t.emplace_back(r, c, 0.0);
  for (const auto& mo : model.moments) {
    const int at = model.nodes[mo.node].firstCoord;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) t.emplace_back(at + r, at + c, 0.0);
  }
  pattern_.resize(nx, nx);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
  slot_.resize(model.elements.size());
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nc = static_cast<int>(E.coords.size());
    slot_[el].resize(static_cast<size_t>(nc) * nc);
    for (int j = 0; j < nc; ++j)
      for (int i = 0; i < nc; ++i)
        slot_[el][static_cast<size_t>(j) * nc + i] = findSlot(pattern_, E.coords[i], E.coords[j]);
    if (E.inertia.any()) massive_.push_back(static_cast<int>(el));
    hasDamping_ = hasDamping_ || E.hasDamping;
  }
  diagSlot_.resize(nx);
  for (int i = 0; i < nx; ++i) diagSlot_[i] = findSlot(pattern_, i, i);
  for (const auto& mo : model.moments) {
    const int at = model.nodes[mo.node].firstCoord;
    std::array<int, 16> s{};
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) s[c * 4 + r] = findSlot(pattern_, at + r, at + c);
    momentSlot_.push_back(s);
  }
  K_ = pattern_;
  D_ = pattern_;
  G_ = pattern_;
  W_ = pattern_;
  M_ = pattern_;
}

void NodalMatrices::addBlock(Sparse& A, int el, const ElemMat& B) const {
  const auto& s = slot_[el];
  const int nc = static_cast<int>(B.rows());
  double* v = A.valuePtr();
  for (int j = 0; j < nc; ++j)
    for (int i = 0; i < nc; ++i) v[s[static_cast<size_t>(j) * nc + i]] += B(i, j);
}

void NodalMatrices::assembleStiffness(const GeometricTransferFunctions& gtf, const std::vector<char>& active) {
  clear(K_);
  if (hasDamping_) clear(D_);
  DefMat Sa;
  DefJac SJ;
  ElemMat Ke;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const int nd = E.impl->numDeformations();
    const DefJac& J = gtf.elementJacobian(static_cast<int>(el));
    for (int pass = 0; pass < 2; ++pass) {
      const bool damping = pass == 1;
      if (damping ? !E.hasDamping : !E.hasStiffness) continue;
      Sa = damping ? E.Sd : E.S;
      bool any = false;
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) {
          if (!active[E.firstDef + i] || !active[E.firstDef + j]) Sa(i, j) = 0.0;
          any |= Sa(i, j) != 0.0;
        }
      if (!any) continue;
      SJ.noalias() = Sa * J;
      Ke.noalias() = J.transpose() * SJ;
      addBlock(damping ? D_ : K_, static_cast<int>(el), Ke);
    }
  }
}

void NodalMatrices::assembleGeometric(const Eigen::VectorXd& x, const Eigen::VectorXd& sigma, const ElementSteps& steps,
                                      double initialFactor, double loadFactor) {
  clear(G_);
  ElemVec xe, unit, d;
  DefVec se;
  ElemMat He, Ye;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const int nd = E.impl->numDeformations();
    se = sigma.segment(E.firstDef, nd);
    if (se.isZero(0.0)) continue;
    E.gather(x, xe);
    E.impl->stressWeightedHessian(xe, se, He);
    addBlock(G_, static_cast<int>(el), He);
  }
  // Load stiffness of gravity on distributed masses: -dg/dx, element by element along the unit
  // directions of its coordinates (the element's own Richardson steps, as Inertia uses).
  // Gravity is an initial load: it scales with initialFactor as in appliedLoads.
  if (model_.hasGravity && initialFactor != 0.0) {
    const double g[3] = {initialFactor * model_.gravity[0], initialFactor * model_.gravity[1],
                         initialFactor * model_.gravity[2]};
    for (int el : massive_) {
      const auto& E = model_.elements[el];
      const int nc = static_cast<int>(E.coords.size());
      E.gather(x, xe);
      const Element& impl = *E.impl;
      auto force = [&](const ElemVec& xx, ElemVec& out) { impl.gravityForces3(xx, E.inertia, g, out); };
      Ye.resize(nc, nc);
      for (int k = 0; k < nc; ++k) {
        unit.setZero(nc);
        unit[k] = 1.0;
        directionalDerivative(force, xe, unit, steps.step(el, unit), d);
        Ye.col(k) = -d;
      }
      addBlock(G_, el, Ye);
    }
  }
  // Symmetrise in place (the pattern is symmetric): G = (G + G^T)/2. Gravity's load stiffness is
  // the Hessian of a potential; symmetrising removes the noise of its difference quotients.
  if (model_.hasGravity) {
    const int n = static_cast<int>(G_.cols());
    double* v = G_.valuePtr();
    for (int c = 0; c < n; ++c)
      for (int p = G_.outerIndexPtr()[c]; p < G_.outerIndexPtr()[c + 1]; ++p) {
        const int r = G_.innerIndexPtr()[p];
        if (r >= c) continue;
        const int q = findSlot(G_, c, r);
        const double s = 0.5 * (v[p] + v[q]);
        v[p] = v[q] = s;
      }
  }
  // W = -dm/dx of the moments: skew, kept apart (see the header).
  hasMoments_ = false;
  for (size_t k = 0; k < model_.moments.size(); ++k) {
    const auto& mo = model_.moments[k];
    const Eigen::Vector3d M = initialFactor * mo.value + loadFactor * mo.increment;
    const Eigen::Matrix4d Z = momentMatrix(M);
    hasMoments_ = hasMoments_ || !M.isZero(0.0);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) W_.valuePtr()[momentSlot_[k][c * 4 + r]] = -Z(r, c);
  }
}

void NodalMatrices::assembleMass(const Eigen::VectorXd& x) {
  clear(M_);
  for (const auto& m : model_.lumpedMasses) M_.valuePtr()[diagSlot_[m.coord]] += m.value;
  ElemVec xe;
  ElemMat Me;
  for (int el : massive_) {
    const auto& E = model_.elements[el];
    E.gather(x, xe);
    E.impl->mass(xe, E.inertia, Me);
    addBlock(M_, el, Me);
  }
}

}  // namespace flexmb::core
