#include "core/elements/CoRotatedCurve.hpp"

#include <Eigen/Geometry>

namespace flexmb::core {

void coRotatedCurve(const Eigen::Vector3d& xp, const Eigen::Matrix3d& Rp, const Eigen::Vector3d& xq,
                    const Eigen::Matrix3d& Rq, double l0, bool curved, Eigen::Ref<Eigen::Matrix3Xd> pts,
                    Eigen::Matrix3Xd* ys, Eigen::Matrix3Xd* zs) {
  using Vec3 = Eigen::Vector3d;
  const Vec3 d = xq - xp;
  const double l = d.norm();
  const Vec3 el0 = l > 0 ? Vec3(d / l) : Vec3::UnitX();
  if (!(l0 > 0)) l0 = l;
  const Eigen::Matrix3d& Rend = curved ? Rq : Rp;
  const Eigen::Index n = pts.cols();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double xi = n > 1 ? static_cast<double>(k) / static_cast<double>(n - 1) : 0.0;
    Vec3 r = (1 - xi) * xp + xi * xq, t = d;
    if (curved) {
      const Vec3 tp = Rp.col(0) - el0, tq = Rq.col(0) - el0;
      r += l0 * (xi * (1 - xi) * (1 - xi) * tp + xi * xi * (xi - 1) * tq);
      t += l0 * ((1 - xi) * (1 - 3 * xi) * tp + xi * (3 * xi - 2) * tq);
    }
    pts.col(k) = r;
    if (!ys || !zs) continue;
    t = t.norm() > 0 ? Vec3(t.normalized()) : el0;
    Vec3 y = (1 - xi) * Rp.col(1) + xi * Rend.col(1);
    y -= y.dot(t) * t;
    if (!(y.norm() > 1e-12)) y = Rp.col(2).cross(t);
    y.normalize();
    ys->col(k) = y;
    zs->col(k) = t.cross(y);
  }
}

}  // namespace flexmb::core
