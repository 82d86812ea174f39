#include "core/elements/PlanarTruss.hpp"

#include <cmath>
#include <stdexcept>

#include "core/elements/Bar.hpp"

namespace flexmb::core {

PlanarTruss::PlanarTruss(const ElemVec& x0) {
  if (x0.size() != 4) throw std::invalid_argument("planar truss: expected 4 initial coordinates");
  l0_ = std::hypot(x0[2] - x0[0], x0[3] - x0[1]);
  if (!(l0_ > 0.0)) throw std::invalid_argument("planar truss: end nodes coincide (zero length)");
}

std::unique_ptr<Element> PlanarTruss::create(const ElemVec& x0, const ElementOptions&) {
  return std::make_unique<PlanarTruss>(x0);
}

void PlanarTruss::deformations(const ElemVec& x, DefVec& e) const {
  e.resize(1);
  e[0] = std::sqrt((x[2] - x[0]) * (x[2] - x[0]) + (x[3] - x[1]) * (x[3] - x[1])) - l0_;
}

void PlanarTruss::jacobian(const ElemVec& x, DefJac& De) const {
  const double dx = x[2] - x[0], dy = x[3] - x[1];
  const double il = 1.0 / std::sqrt(dx * dx + dy * dy);
  const double ex = dx * il, ey = dy * il;
  De.resize(1, 4);
  De << -ex, -ey, ex, ey;
}

void PlanarTruss::secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const {
  const double dx = x[2] - x[0], dy = x[3] - x[1];
  const double l = std::sqrt(dx * dx + dy * dy);
  // v^T (n n^T / l) v on delta d = vq - vp, n = (-dy, dx)/l
  const double nv = (-dy * (v[2] - v[0]) + dx * (v[3] - v[1])) / l;
  d2.resize(1);
  d2[0] = nv * nv / l;
}

void PlanarTruss::stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const {
  const double dx = x[2] - x[0], dy = x[3] - x[1];
  const double l = std::sqrt(dx * dx + dy * dy);
  const double nx = -dy / l, ny = dx / l;
  const double k = sigma[0] / l;
  const double a = k * nx * nx, b = k * nx * ny, c = k * ny * ny;
  H.resize(4, 4);
  H << a, b, -a, -b, b, c, -b, -c, -a, -b, a, b, -b, -c, b, c;
}

void PlanarTruss::constitutive(std::span<const double> params, DefMat& S) const { bar::constitutive(params, l0_, S); }

void PlanarTruss::mass(const ElemVec&, const ElementInertia& inertia, ElemMat& M) const {
  bar::mass(inertia.rhoA, l0_, 2, M);
}

void PlanarTruss::velocityForces(const ElemVec&, const ElemVec&, const ElementInertia&, ElemVec& h) const {
  h.setZero(4);
}

void PlanarTruss::gravityForces(const ElemVec&, const ElementInertia& inertia, double gx, double gy, ElemVec& f) const {
  const double m2 = 0.5 * inertia.rhoA * l0_;
  f.resize(4);
  f << m2 * gx, m2 * gy, m2 * gx, m2 * gy;
}

}  // namespace flexmb::core
