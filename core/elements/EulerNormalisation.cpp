#include "core/elements/EulerNormalisation.hpp"

#include "core/elements/EulerParameters.hpp"

namespace flexmb::core {

using namespace euler;

namespace {
Mat3 tensor(const ElementInertia& in) {
  Mat3 J;
  J << in.jxx, in.jxy, in.jxz, in.jxy, in.jyy, in.jyz, in.jxz, in.jyz, in.jzz;
  return J;
}
}  // namespace

std::unique_ptr<Element> EulerNormalisation::create(const ElemVec&, const ElementOptions&) {
  return std::make_unique<EulerNormalisation>();
}

void EulerNormalisation::deformations(const ElemVec& x, DefVec& e) const {
  e.resize(1);
  e[0] = x.squaredNorm() - 1.0;
}

void EulerNormalisation::jacobian(const ElemVec& x, DefJac& De) const {
  De.resize(1, 4);
  De.row(0) = 2.0 * x.transpose();
}

void EulerNormalisation::secondDerivative(const ElemVec&, const ElemVec& v, DefVec& d2) const {
  d2.resize(1);
  d2[0] = 2.0 * v.squaredNorm();
}

void EulerNormalisation::stressWeightedHessian(const ElemVec&, const DefVec& sigma, ElemMat& H) const {
  H = (2.0 * sigma[0]) * Mat4::Identity();
}

void EulerNormalisation::constitutive(std::span<const double>, DefMat& S) const { S.setZero(1, 1); }

void EulerNormalisation::mass(const ElemVec& x, const ElementInertia& in, ElemMat& M) const {
  const Mat34 G = bodyRateMatrix(Vec4(x));
  M = 4.0 * G.transpose() * tensor(in) * G;
}

void EulerNormalisation::velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& in,
                                        ElemVec& h) const {
  const Vec4 l = x, ld = xd;
  h = 8.0 * bodyRateMatrix(ld).transpose() * (tensor(in) * (bodyRateMatrix(l) * ld));
}

}  // namespace flexmb::core
