#pragma once
// Euler-parameter kinematics of spatial orientation nodes (docs/theory/spatial-elements.md section 1.2-1.3).
// lambda = (l0, v), v = (l1, l2, l3); nothing is normalised here (the L2MIN1 constraint does it).
//   R(lambda) = (l0^2 - v.v) I + 2 v v^T + 2 l0 [v]x    body -> global
//   E(lambda) = [-v, l0 I + [v]x]   global angular velocity  w  = 2 E lambdad
//   G(lambda) = [-v, l0 I - [v]x]   body angular velocity    w' = 2 G lambdad
// R is a homogeneous quadratic form in lambda, so d2(R a)[u, u] = 2 R(u) a exactly.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace flexmb::core::euler {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat34 = Eigen::Matrix<double, 3, 4>;

inline Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0;
  return s;
}

inline Mat3 rotation(const Vec4& l) {
  const Vec3 v = l.tail<3>();
  return (l[0] * l[0] - v.squaredNorm()) * Mat3::Identity() + 2.0 * v * v.transpose() + 2.0 * l[0] * skew(v);
}

inline Mat34 globalRateMatrix(const Vec4& l) {  // E
  Mat34 E;
  E.col(0) = -l.tail<3>();
  E.rightCols<3>() = l[0] * Mat3::Identity() + skew(l.tail<3>());
  return E;
}

inline Mat34 bodyRateMatrix(const Vec4& l) {  // G
  Mat34 G;
  G.col(0) = -l.tail<3>();
  G.rightCols<3>() = l[0] * Mat3::Identity() - skew(l.tail<3>());
  return G;
}

// d(R(lambda) a)/d lambda (3 x 4).
inline Mat34 rotatedJacobian(const Vec4& l, const Vec3& a) {
  const double l0 = l[0];
  const Vec3 v = l.tail<3>();
  Mat34 J;
  J.col(0) = 2.0 * (l0 * a + v.cross(a));
  J.rightCols<3>() = 2.0 * (v.dot(a) * Mat3::Identity() + v * a.transpose() - a * v.transpose() - l0 * skew(a));
  return J;
}

// c^T R(lambda) a = lambda^T Q(a, c) lambda (symmetric 4 x 4): the Hessian of c^T R a is 2 Q.
inline Mat4 quadraticForm(const Vec3& a, const Vec3& c) {
  Mat4 Q;
  const double ac = a.dot(c);
  const Vec3 x = a.cross(c);
  Q(0, 0) = ac;
  Q.block<3, 1>(1, 0) = x;
  Q.block<1, 3>(0, 1) = x.transpose();
  Q.block<3, 3>(1, 1) = a * c.transpose() + c * a.transpose() - ac * Mat3::Identity();
  return Q;
}

// Euler parameters of a rotation matrix (Shepperd's method, l0 >= 0).
inline Vec4 fromRotation(const Mat3& R) {
  const double tr = R.trace();
  Vec4 l;
  if (tr >= R(0, 0) && tr >= R(1, 1) && tr >= R(2, 2)) {
    l[0] = 0.5 * std::sqrt(1.0 + tr);
    const double f = 0.25 / l[0];
    l[1] = f * (R(2, 1) - R(1, 2));
    l[2] = f * (R(0, 2) - R(2, 0));
    l[3] = f * (R(1, 0) - R(0, 1));
  } else {
    int i = 0;
    if (R(1, 1) > R(i, i)) i = 1;
    if (R(2, 2) > R(i, i)) i = 2;
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double s = 0.5 * std::sqrt(1.0 + R(i, i) - R(j, j) - R(k, k));
    const double f = 0.25 / s;
    l[1 + i] = s;
    l[0] = f * (R(k, j) - R(j, k));
    l[1 + j] = f * (R(j, i) + R(i, j));
    l[1 + k] = f * (R(k, i) + R(i, k));
    if (l[0] < 0.0) l = -l;
  }
  return l;
}

// Initial element frame from the chord (or axis) ex and a direction y (docs/theory/spatial-elements.md 1.4):
// e_y0 = y orthogonalised against ex; throws when y is (nearly) parallel to ex.
Mat3 elementFrame(const Vec3& ex, const Vec3& y);
// A frame for a hinge axis: the axis and Gram-Schmidt of the global axis least parallel to it.
Mat3 axisFrame(const Vec3& axis);

}  // namespace flexmb::core::euler
