#include "core/dynamics/Inertia.hpp"

namespace flexmb::core {

Inertia::Inertia(const Model& model) : model_(model) {
  for (size_t el = 0; el < model.elements.size(); ++el)
    if (model.elements[el].inertia.any()) massive_.push_back(static_cast<int>(el));
  blocks_.resize(massive_.size());
  lumped_ = Eigen::VectorXd::Zero(model.nx);
  for (const auto& m : model.lumpedMasses) lumped_[m.coord] += m.value;
  for (int i = 0; i < model.nx; ++i)
    if (lumped_[i] != 0.0) lumpedCoords_.push_back(i);
}

void Inertia::update(const Eigen::VectorXd& x) {
  ElemVec xe;
  for (size_t k = 0; k < massive_.size(); ++k) {
    const auto& E = model_.elements[massive_[k]];
    E.gather(x, xe);
    E.impl->mass(xe, E.inertia, blocks_[k]);
  }
}

void Inertia::updateWithVelocityForces(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, Eigen::VectorXd& y,
                                       Eigen::VectorXd* d2) {
  ElemVec xe, ve, he;
  DefVec de;
  for (size_t k = 0; k < massive_.size(); ++k) {
    const auto& E = model_.elements[massive_[k]];
    E.gather(x, xe);
    E.gather(xd, ve);
    if (ve.isZero(0.0)) {
      E.impl->mass(xe, E.inertia, blocks_[k]);
      if (d2) d2->segment(E.firstDef, E.impl->numDeformations()).setZero();
      continue;
    }
    E.impl->dynamicTerms(xe, ve, E.inertia, blocks_[k], he, de);
    for (size_t j = 0; j < E.coords.size(); ++j) y[E.coords[j]] += he[j];
    if (d2)
      for (int i = 0; i < de.size(); ++i) (*d2)[E.firstDef + i] = de[i];
  }
}

void Inertia::multiply(const Eigen::VectorXd& v, Eigen::VectorXd& y) const {
  y = lumped_.cwiseProduct(v);
  ElemVec ve, ye;
  Eigen::Matrix<double, 6, 1> v6, y6;
  for (size_t k = 0; k < massive_.size(); ++k) {
    const auto& E = model_.elements[massive_[k]];
    const int* c = E.coords.data();
    if (E.coords.size() == 6) {  // planar beams: a fixed-size product
      for (int b = 0; b < 6; ++b) v6[b] = v[c[b]];
      y6.noalias() = Eigen::Map<const Eigen::Matrix<double, 6, 6>>(blocks_[k].data()) * v6;
      for (int a = 0; a < 6; ++a) y[c[a]] += y6[a];
      continue;
    }
    E.gather(v, ve);
    ye.noalias() = blocks_[k] * ve;
    for (size_t a = 0; a < E.coords.size(); ++a) y[c[a]] += ye[a];
  }
}

namespace {
// Sum over the massive elements of Fe^T Me Fe, Fe the element's rows of F (n x m): per element small
// products, M columns fixed at compile time where the basis is narrow (unrolled and vectorised),
// else dynamic with fixed maximum sizes (no allocation, no packing).
template <int M>
void addElementProjections(const Model& model, const std::vector<int>& massive, const std::vector<ElemMat>& blocks,
                           const Eigen::MatrixXd& F, Eigen::MatrixXd& Mbar) {
  constexpr int MaxM = M == Eigen::Dynamic ? Inertia::kMaxProjectedColumns : M;
  // The number of columns is M where fixed (the caller dispatches on F.cols()): the compiler then
  // knows every loop bound below (with a run-time m it warned of reads past acc, -Warray-bounds).
  const int m = M == Eigen::Dynamic ? static_cast<int>(F.cols()) : M;
  using Acc = Eigen::Matrix<double, M, M, 0, MaxM, MaxM>;
  using Rows6 = Eigen::Matrix<double, 6, M, 0, 6, MaxM>;
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, M, 0, kMaxElemCoords, MaxM>;
  Acc acc = Acc::Zero(m, m);
  Rows6 Fe6(6, m), T6(6, m);
  Rows Fe, T;
  for (size_t k = 0; k < massive.size(); ++k) {
    const auto& E = model.elements[massive[k]];
    const int n = static_cast<int>(E.coords.size());
    const int* c = E.coords.data();
    if (n == 6) {  // planar beams
      for (int j = 0; j < m; ++j)
        for (int b = 0; b < 6; ++b) Fe6(b, j) = F(c[b], j);
      T6.noalias() = Eigen::Map<const Eigen::Matrix<double, 6, 6>>(blocks[k].data()).lazyProduct(Fe6);
      for (int b = 0; b < m; ++b)  // the upper triangle (Mbar is symmetric)
        for (int a = 0; a <= b; ++a) acc(a, b) += Fe6.col(a).dot(T6.col(b));
      continue;
    }
    Fe.resize(n, m);
    for (int j = 0; j < m; ++j)
      for (int b = 0; b < n; ++b) Fe(b, j) = F(c[b], j);
    T.noalias() = blocks[k].lazyProduct(Fe);
    for (int b = 0; b < m; ++b)
      for (int a = 0; a <= b; ++a) acc(a, b) += Fe.col(a).dot(T.col(b));
  }
  for (int b = 0; b < m; ++b)  // the lower triangle mirrored from the upper one
    for (int a = 0; a < m; ++a) Mbar(a, b) += a <= b ? acc(a, b) : acc(b, a);
}
}  // namespace

void Inertia::projectedMass(const Eigen::MatrixXd& F, Eigen::MatrixXd& Mbar) {
  const int m = static_cast<int>(F.cols());
  if (m > kMaxProjectedColumns) {  // wide bases (the projected full model): through M F
    multiply(F, wide_);
    Mbar.noalias() = F.transpose() * wide_;
    return;
  }
  Mbar.setZero(m, m);
  for (int i : lumpedCoords_)
    for (int b = 0; b < m; ++b)
      for (int a = 0; a < m; ++a) Mbar(a, b) += lumped_[i] * (F(i, a) * F(i, b));  // symmetric bits
  switch (m) {
    case 1:
      return addElementProjections<1>(model_, massive_, blocks_, F, Mbar);
    case 2:
      return addElementProjections<2>(model_, massive_, blocks_, F, Mbar);
    case 3:
      return addElementProjections<3>(model_, massive_, blocks_, F, Mbar);
    case 4:
      return addElementProjections<4>(model_, massive_, blocks_, F, Mbar);
    case 5:
      return addElementProjections<5>(model_, massive_, blocks_, F, Mbar);
    case 6:
      return addElementProjections<6>(model_, massive_, blocks_, F, Mbar);
    default:
      return addElementProjections<Eigen::Dynamic>(model_, massive_, blocks_, F, Mbar);
  }
}

void Inertia::multiply(const Eigen::MatrixXd& F, Eigen::MatrixXd& Y) const {
  // Per element: gather its rows of F (n x m), one small product, scatter-add. Plain loops: an
  // Eigen indexed view copies the index list (an allocation per element).
  Y.resize(F.rows(), F.cols());
  Y.noalias() = lumped_.asDiagonal() * F;
  const Eigen::Index m = F.cols();
  for (size_t k = 0; k < massive_.size(); ++k) {
    const auto& E = model_.elements[massive_[k]];
    const ElemMat& Me = blocks_[k];
    const int n = static_cast<int>(E.coords.size());
    const int* c = E.coords.data();
    if (n == 6) {  // planar beams: fixed-size (vectorised) products
      const Eigen::Map<const Eigen::Matrix<double, 6, 6>> M6(Me.data());
      Eigen::Matrix<double, 6, 1> fe, ye;
      for (Eigen::Index j = 0; j < m; ++j) {
        const double* f = F.col(j).data();
        double* y = Y.col(j).data();
        for (int b = 0; b < 6; ++b) fe[b] = f[c[b]];
        ye.noalias() = M6 * fe;
        for (int a = 0; a < 6; ++a) y[c[a]] += ye[a];
      }
      continue;
    }
    ElemVec fe(n), ye(n);
    for (Eigen::Index j = 0; j < m; ++j) {
      const double* f = F.col(j).data();
      double* y = Y.col(j).data();
      for (int b = 0; b < n; ++b) fe[b] = f[c[b]];
      ye.noalias() = Me * fe;
      for (int a = 0; a < n; ++a) y[c[a]] += ye[a];
    }
  }
}

void Inertia::addVelocityForces(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, Eigen::VectorXd& y) const {
  ElemVec xe, ve, he;
  for (int el : massive_) {
    const auto& E = model_.elements[el];
    E.gather(xd, ve);
    if (ve.isZero(0.0)) continue;
    E.gather(x, xe);
    E.impl->velocityForces(xe, ve, E.inertia, he);
    for (size_t j = 0; j < E.coords.size(); ++j) y[E.coords[j]] += he[j];
  }
}

void Inertia::addGravity(const Eigen::VectorXd& x, Eigen::VectorXd& y, double scale) const {
  if (!model_.hasGravity || scale == 0.0) return;
  const double g[3] = {scale * model_.gravity[0], scale * model_.gravity[1], scale * model_.gravity[2]};
  for (const auto& n : model_.nodes) {
    if (!isTranslational(n.kind)) continue;
    for (int c = 0; c < n.dim(); ++c) y[n.firstCoord + c] += lumped_[n.firstCoord + c] * g[c];
  }
  ElemVec xe, fe;
  for (int el : massive_) {
    const auto& E = model_.elements[el];
    E.gather(x, xe);
    E.impl->gravityForces3(xe, E.inertia, g, fe);
    for (size_t j = 0; j < E.coords.size(); ++j) y[E.coords[j]] += fe[j];
  }
}

Eigen::MatrixXd Inertia::dense() const {
  Eigen::MatrixXd M = lumped_.asDiagonal();
  for (size_t k = 0; k < massive_.size(); ++k) {
    const auto& E = model_.elements[massive_[k]];
    for (size_t i = 0; i < E.coords.size(); ++i)
      for (size_t j = 0; j < E.coords.size(); ++j) M(E.coords[i], E.coords[j]) += blocks_[k](i, j);
  }
  return M;
}

double Inertia::kineticEnergy(const Eigen::VectorXd& xd) const {
  Eigen::VectorXd Mv;
  multiply(xd, Mv);
  return 0.5 * xd.dot(Mv);
}

namespace {
// The element's entries of column j of a nodal matrix.
void gatherColumn(const ElementEntry& E, const Eigen::MatrixXd& A, int j, ElemVec& out) {
  out.resize(static_cast<int>(E.coords.size()));
  for (size_t k = 0; k < E.coords.size(); ++k) out[k] = A(E.coords[k], j);
}
void scatterColumn(const ElementEntry& E, const ElemVec& v, int j, Eigen::MatrixXd& Y) {
  for (size_t k = 0; k < E.coords.size(); ++k) Y(E.coords[k], j) += v[k];
}
// Y += d force(x)/dx A for one element (force: its nodal force function of its coordinates).
template <class Fn>
void addDirectional(const ElementEntry& E, int el, const ElemVec& xe, Fn&& force, const Eigen::MatrixXd& A,
                    const ElementSteps& steps, Eigen::MatrixXd& Y) {
  ElemVec ae, d;
  for (int j = 0; j < A.cols(); ++j) {
    gatherColumn(E, A, j, ae);
    const double h = steps.step(el, ae);
    if (h == 0.0) continue;
    directionalDerivative(force, xe, ae, h, d);
    scatterColumn(E, d, j, Y);
  }
}
}  // namespace

void Inertia::addVelocityForceJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::MatrixXd& W,
                                       Eigen::MatrixXd& Y) const {
  ElemVec xe, ve, we, v, hp, hm;
  for (int el : massive_) {
    const auto& E = model_.elements[el];
    E.gather(xd, ve);
    const double vn = ve.norm();
    if (vn == 0.0) continue;  // h is quadratic: its derivative vanishes with the velocity
    E.gather(x, xe);
    for (int j = 0; j < W.cols(); ++j) {
      gatherColumn(E, W, j, we);
      const double wn = we.norm();
      if (wn == 0.0) continue;
      // h(v + s w) - h(v - s w) = 4 s B(v, w) and dh/dxd w = 2 B(v, w).
      const double s = vn / wn;
      v = ve + s * we;
      E.impl->velocityForces(xe, v, E.inertia, hp);
      v = ve - s * we;
      E.impl->velocityForces(xe, v, E.inertia, hm);
      hp = (hp - hm) / (2.0 * s);
      scatterColumn(E, hp, j, Y);
    }
  }
}

void Inertia::addConfigurationJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& xdd,
                                       const Eigen::MatrixXd& A, const ElementSteps& steps, Eigen::MatrixXd& Y) const {
  ElemVec xe, ve, acc;
  for (int el : massive_) {
    const auto& E = model_.elements[el];
    E.gather(x, xe);
    E.gather(xd, ve);
    E.gather(xdd, acc);
    const bool moving = !ve.isZero(0.0);
    if (!moving && acc.isZero(0.0)) continue;
    const Element& impl = *E.impl;
    ElemMat Me;
    ElemVec he;
    auto force = [&](const ElemVec& xx, ElemVec& out) {
      impl.mass(xx, E.inertia, Me);
      out.noalias() = Me * acc;
      if (moving) {
        impl.velocityForces(xx, ve, E.inertia, he);
        out += he;
      }
    };
    addDirectional(E, el, xe, force, A, steps, Y);
  }
}

void appliedLoads(const Model& model, const Inertia& inertia, double t, double loadFactor, const Eigen::VectorXd& x,
                  Eigen::VectorXd& f, double initialFactor) {
  nodalLoads(model, t, loadFactor, x, f, initialFactor);
  inertia.addGravity(x, f, initialFactor);  // gravity is an initial load (statics ramps it with XF)
}

void nodalLoads(const Model& model, double t, double loadFactor, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                double initialFactor) {
  f = model.f0;
  if (initialFactor != 1.0) f *= initialFactor;
  if (loadFactor != 0.0 && model.delf.size() == f.size()) f += loadFactor * model.delf;
  for (const auto& tf : model.timeForces) f[tf.index] += tf.f->value(t);
  for (const auto& mo : model.moments) {
    const int at = model.nodes[mo.node].firstCoord;
    f.segment<4>(at) += momentMatrix(initialFactor * mo.value + loadFactor * mo.increment) * x.segment<4>(at);
  }
}

Eigen::Matrix4d momentMatrix(const Eigen::Vector3d& M) {
  // 2 E(lambda)^T M = 2 Z(M) lambda, Z(M) = [[0, -M^T], [M, [M]x]] (docs/theory/spatial-elements.md 6.3).
  Eigen::Matrix4d Z;
  Z << 0.0, -M[0], -M[1], -M[2], M[0], 0.0, -M[2], M[1], M[1], M[2], 0.0, -M[0], M[2], -M[1], M[0], 0.0;
  return 2.0 * Z;
}

}  // namespace flexmb::core
