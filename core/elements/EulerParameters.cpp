#include "core/elements/EulerParameters.hpp"

#include <stdexcept>

namespace flexmb::core::euler {

Mat3 elementFrame(const Vec3& ex, const Vec3& y) {
  const double ny = y.norm();
  if (!(ny > 0.0)) throw std::invalid_argument("the orientation vector is zero");
  const Vec3 yn = y / ny;
  const double c = yn.dot(ex);
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  // SPACAR's limit for a vector along the element axis (docs/theory/spatial-elements.md 1.4).
  if (s < 1e-5) throw std::invalid_argument("the orientation vector is parallel to the element axis");
  Mat3 F;
  F.col(0) = ex;
  F.col(1) = (yn - c * ex) / s;
  F.col(2) = ex.cross(F.col(1));
  return F;
}

Mat3 axisFrame(const Vec3& axis) {
  const double n = axis.norm();
  if (!(n > 0.0)) throw std::invalid_argument("the axis vector is zero");
  const Vec3 ex = axis / n;
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(ex[i]) < std::abs(ex[k])) k = i;
  return elementFrame(ex, Vec3::Unit(k));
}

}  // namespace flexmb::core::euler
