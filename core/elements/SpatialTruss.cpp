#include "core/elements/SpatialTruss.hpp"

#include <stdexcept>

#include "core/elements/SpatialPrimitives.hpp"

#include "core/elements/Bar.hpp"

namespace flexmb::core {

using namespace spatial;
using Vec6 = Eigen::Matrix<double, 6, 1>;

SpatialTruss::SpatialTruss(const ElemVec& x0) {
  if (x0.size() != 6) throw std::invalid_argument("spatial truss: expected 6 initial coordinates");
  l0_ = (x0.segment<3>(3) - x0.segment<3>(0)).norm();
  if (!(l0_ > 0.0)) throw std::invalid_argument("end nodes coincide (zero length)");
}

std::unique_ptr<Element> SpatialTruss::create(const ElemVec& x0, const ElementOptions&) {
  return std::make_unique<SpatialTruss>(x0);
}

void SpatialTruss::deformations(const ElemVec& x, DefVec& e) const {
  e.resize(1);
  e[0] = (x.segment<3>(3) - x.segment<3>(0)).norm() - l0_;
}

void SpatialTruss::jacobian(const ElemVec& x, DefJac& De) const {
  Scalar<6> l;
  chordLength<6>(Vec6(x), 0, 3, 1, l);
  De.resize(1, 6);
  De.row(0) = l.g.transpose();
}

void SpatialTruss::secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const {
  Scalar<6> l;
  chordLength<6>(Vec6(x), 0, 3, 2, l);
  const Vec6 vv = v;
  d2.resize(1);
  d2[0] = vv.dot(l.H * vv);
}

void SpatialTruss::stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const {
  Scalar<6> l;
  chordLength<6>(Vec6(x), 0, 3, 2, l);
  H = sigma[0] * l.H;
}

void SpatialTruss::constitutive(std::span<const double> params, DefMat& S) const { bar::constitutive(params, l0_, S); }

void SpatialTruss::mass(const ElemVec&, const ElementInertia& in, ElemMat& M) const { bar::mass(in.rhoA, l0_, 3, M); }

void SpatialTruss::gravityForces3(const ElemVec&, const ElementInertia& in, const double* g, ElemVec& f) const {
  const double m2 = 0.5 * in.rhoA * l0_;
  f.resize(6);
  for (int i = 0; i < 3; ++i) f[i] = f[i + 3] = m2 * g[i];
}

}  // namespace flexmb::core
