#include "core/elements/RigidBeam.hpp"

#include <stdexcept>

#include "core/elements/EulerParameters.hpp"
#include "core/elements/SpatialPrimitives.hpp"

namespace flexmb::core {

namespace {
using namespace spatial;
using Vec10 = Eigen::Matrix<double, 10, 1>;
constexpr int XP = 0, LP = 3, XQ = 7;
}  // namespace

RigidBeam::RigidBeam(const ElemVec& x0, const double* y) {
  if (x0.size() != 10) throw std::invalid_argument("rigid beam: expected 10 initial coordinates");
  const Vec3 d = x0.segment<3>(XQ) - x0.segment<3>(XP);
  l0_ = d.norm();
  if (!(l0_ > 0.0)) throw std::invalid_argument("end nodes coincide (zero length)");
  const Vec4 lp = x0.segment<4>(LP);
  if (!(lp.norm() > 0.0)) throw std::invalid_argument("initial Euler parameters are zero");
  Ap_ = euler::rotation(lp.normalized()).transpose() * euler::elementFrame(d / l0_, Vec3(y[0], y[1], y[2]));
}

std::unique_ptr<Element> RigidBeam::create(const ElemVec& x0, const double* y, const ElementOptions&) {
  return std::make_unique<RigidBeam>(x0, y);
}

void RigidBeam::evaluate(const ElemVec& xe, int order, Defs& D) const {
  const Vec10 x = xe;
  chordLength<10>(x, XP, XQ, order, D.e[0]);
  D.e[0].v -= l0_;
  rotatedOnChord<10>(x, LP, Ap_.col(1), XP, XQ, order, D.e[1]);
  rotatedOnChord<10>(x, LP, Ap_.col(2), XP, XQ, order, D.e[2]);
}

void RigidBeam::constitutive(std::span<const double>, DefMat& S) const { S.setZero(3, 3); }

void RigidBeam::mass(const ElemVec&, const ElementInertia& in, ElemMat& M) const {
  const double a = in.rhoA * l0_ / 3.0, b = in.rhoA * l0_ / 6.0;
  M.setZero(10, 10);
  for (int i = 0; i < 3; ++i) {
    M(XP + i, XP + i) = M(XQ + i, XQ + i) = a;
    M(XP + i, XQ + i) = M(XQ + i, XP + i) = b;
  }
}

void RigidBeam::gravityForces3(const ElemVec&, const ElementInertia& in, const double* g, ElemVec& f) const {
  const double m2 = 0.5 * in.rhoA * l0_;
  f.setZero(10);
  for (int i = 0; i < 3; ++i) f[XP + i] = f[XQ + i] = m2 * g[i];
}

}  // namespace flexmb::core
