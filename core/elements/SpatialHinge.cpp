#include "core/elements/SpatialHinge.hpp"

#include <cmath>
#include <stdexcept>

#include "core/elements/EulerParameters.hpp"
#include "core/elements/SpatialPrimitives.hpp"

namespace flexmb::core {

namespace {
using namespace spatial;
using S8 = Scalar<8>;
using Vec8 = Eigen::Matrix<double, 8, 1>;
constexpr int LP = 0, LQ = 4;
}  // namespace

SpatialHinge::SpatialHinge(const ElemVec& x0, const double* axis) {
  if (x0.size() != 8) throw std::invalid_argument("spatial hinge: expected 8 initial coordinates");
  const Mat3 F = euler::axisFrame(Vec3(axis[0], axis[1], axis[2]));
  const Vec4 lp = x0.segment<4>(LP), lq = x0.segment<4>(LQ);
  if (!(lp.norm() > 0.0) || !(lq.norm() > 0.0)) throw std::invalid_argument("initial Euler parameters are zero");
  Ap_ = euler::rotation(lp.normalized()).transpose() * F;
  Aq_ = euler::rotation(lq.normalized()).transpose() * F;
}

std::unique_ptr<Element> SpatialHinge::create(const ElemVec& x0, const double* axis, const ElementOptions&) {
  return std::make_unique<SpatialHinge>(x0, axis);
}

void SpatialHinge::evaluate(const ElemVec& xe, int order, Defs& D) const {
  const Vec8 x = xe;
  S8 a, b, s, c;
  auto prod = [&](int i, int j, S8& out) { rotatedProduct<8>(x, LP, Ap_.col(i), LQ, Aq_.col(j), order, out); };
  // sine and cosine parts of the rotation about the axis (both scaled by 2)
  prod(2, 1, a);
  prod(1, 2, b);
  s.clear(order);
  s.add(1.0, a, order);
  s.add(-1.0, b, order);
  prod(1, 1, a);
  prod(2, 2, b);
  c.clear(order);
  c.add(1.0, a, order);
  c.add(1.0, b, order);
  S8& e1 = D.e[0];
  e1.clear(order);
  e1.v = std::atan2(s.v, c.v);
  if (order >= 1) {
    const double N = s.v * s.v + c.v * c.v;
    const Vec8 t = (c.v * s.g - s.v * c.g) / N;  // gradient of e1
    e1.g = t;
    if (order >= 2) {
      e1.H = (c.v * s.H - s.v * c.H + s.g * c.g.transpose() - c.g * s.g.transpose()) / N -
             t * (2.0 * (s.v * s.g + c.v * c.g)).transpose() / N;
      e1.H = (0.5 * (e1.H + e1.H.transpose())).eval();  // exact Hessian is symmetric
    }
  }
  // Tilts: the components of q's axis e_x^q across p's axis. Their Jacobian with respect to the
  // two tilt rotations has determinant 1 at every angle e1 (the symmetric form
  // (e_x^p.e_z^q - e_z^p.e_x^q)/2 scales with (1 + cos e1)/2 and is singular at a half turn).
  prod(2, 0, a);
  D.e[1].clear(order);
  D.e[1].add(-1.0, a, order);
  prod(1, 0, a);
  D.e[2].clear(order);
  D.e[2].add(1.0, a, order);
}

void SpatialHinge::constitutive(std::span<const double> p, DefMat& S) const {
  S.setZero(3, 3);
  for (size_t i = 0; i < p.size() && i < 3; ++i) S(i, i) = p[i];
}

}  // namespace flexmb::core
