#pragma once
// Closed-form value, gradient and Hessian of the scalar building blocks of the spatial
// deformations (docs/theory/spatial-elements.md section 1.3): the chord length l = |x_q - x_p|, the projection
// (R_k a) . (x_q - x_p) of a rotated body vector on the chord vector, and the product
// (R_p a) . (R_q b) of two rotated body vectors. A deformation is a combination of them, so its
// derivatives are combinations of theirs (exact; checked against finite differences in tests).
#include <Eigen/Core>

#include "core/elements/EulerParameters.hpp"

namespace flexmb::core::spatial {

using euler::Mat3;
using euler::Mat34;
using euler::Mat4;
using euler::Vec3;
using euler::Vec4;

// How much of a scalar to compute: 0 value, 1 with gradient, 2 with Hessian.
template <int N>
struct Scalar {
  double v = 0.0;
  Eigen::Matrix<double, N, 1> g;
  Eigen::Matrix<double, N, N> H;
  void clear(int order) {
    v = 0.0;
    if (order >= 1) g.setZero();
    if (order >= 2) H.setZero();
  }
  // this = s, as far as order (what s holds)
  void assign(const Scalar& s, int order) {
    v = s.v;
    if (order >= 1) g = s.g;
    if (order >= 2) H = s.H;
  }
  // this += c * s
  void add(double c, const Scalar& s, int order) {
    v += c * s.v;
    if (order >= 1) g.noalias() += c * s.g;
    if (order >= 2) H.noalias() += c * s.H;
  }
};

template <int N>
inline Vec3 pos(const Eigen::Matrix<double, N, 1>& x, int at) {
  return x.template segment<3>(at);
}
template <int N>
inline Vec4 par(const Eigen::Matrix<double, N, 1>& x, int at) {
  return x.template segment<4>(at);
}

// l = |x_q - x_p|
template <int N>
void chordLength(const Eigen::Matrix<double, N, 1>& x, int xp, int xq, int order, Scalar<N>& s) {
  s.clear(order);
  const Vec3 d = pos<N>(x, xq) - pos<N>(x, xp);
  const double l = d.norm();
  s.v = l;
  if (order < 1) return;
  const Vec3 e = d / l;
  s.g.template segment<3>(xq) = e;
  s.g.template segment<3>(xp) = -e;
  if (order < 2) return;
  const Mat3 P = (Mat3::Identity() - e * e.transpose()) / l;
  s.H.template block<3, 3>(xq, xq) = P;
  s.H.template block<3, 3>(xp, xp) = P;
  s.H.template block<3, 3>(xp, xq) = -P;
  s.H.template block<3, 3>(xq, xp) = -P;
}

// h = (R(lambda_k) a) . (x_q - x_p), the orientation node k at lk.
template <int N>
void rotatedOnChord(const Eigen::Matrix<double, N, 1>& x, int lk, const Vec3& a, int xp, int xq, int order,
                    Scalar<N>& s) {
  s.clear(order);
  const Vec4 l = par<N>(x, lk);
  const Vec3 d = pos<N>(x, xq) - pos<N>(x, xp);
  const Vec3 ra = euler::rotation(l) * a;
  s.v = ra.dot(d);
  if (order < 1) return;
  const Mat34 J = euler::rotatedJacobian(l, a);
  s.g.template segment<3>(xq) = ra;
  s.g.template segment<3>(xp) = -ra;
  s.g.template segment<4>(lk) = J.transpose() * d;
  if (order < 2) return;
  s.H.template block<4, 4>(lk, lk) = 2.0 * euler::quadraticForm(a, d);
  s.H.template block<3, 4>(xq, lk) = J;
  s.H.template block<4, 3>(lk, xq) = J.transpose();
  s.H.template block<3, 4>(xp, lk) = -J;
  s.H.template block<4, 3>(lk, xp) = -J.transpose();
}

// g = (R(lambda_p) a) . (R(lambda_q) b)
template <int N>
void rotatedProduct(const Eigen::Matrix<double, N, 1>& x, int lp, const Vec3& a, int lq, const Vec3& b, int order,
                    Scalar<N>& s) {
  s.clear(order);
  const Vec4 Lp = par<N>(x, lp), Lq = par<N>(x, lq);
  const Vec3 ra = euler::rotation(Lp) * a, rb = euler::rotation(Lq) * b;
  s.v = ra.dot(rb);
  if (order < 1) return;
  const Mat34 Jp = euler::rotatedJacobian(Lp, a), Jq = euler::rotatedJacobian(Lq, b);
  s.g.template segment<4>(lp) = Jp.transpose() * rb;
  s.g.template segment<4>(lq) = Jq.transpose() * ra;
  if (order < 2) return;
  s.H.template block<4, 4>(lp, lp) = 2.0 * euler::quadraticForm(a, rb);
  s.H.template block<4, 4>(lq, lq) = 2.0 * euler::quadraticForm(b, ra);
  s.H.template block<4, 4>(lp, lq) = Jp.transpose() * Jq;
  s.H.template block<4, 4>(lq, lp) = Jq.transpose() * Jp;
}

// out = (c / l) * h, l the chord length (both with derivatives up to order).
template <int N>
void perLength(const Scalar<N>& h, const Scalar<N>& l, double c, int order, Scalar<N>& out) {
  const double il = 1.0 / l.v;
  out.v = c * h.v * il;
  if (order < 1) return;
  out.g = (c * il) * h.g - (c * h.v * il * il) * l.g;
  if (order < 2) return;
  out.H = (c * il) * h.H - (c * il * il) * (h.g * l.g.transpose() + l.g * h.g.transpose()) +
          (2.0 * c * h.v * il * il * il) * (l.g * l.g.transpose()) - (c * h.v * il * il) * l.H;
}

}  // namespace flexmb::core::spatial
