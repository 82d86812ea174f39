#pragma once
// The co-rotated cubic of a spatial beam (SpatialBeam.hpp's field): the chord plus l0 times the
// Hermite shapes of the end tangents' turn away from it,
//   r(xi) = (1 - xi) x_p + xi x_q + l0 [xi (1 - xi)^2 (t_p - e_l) + xi^2 (xi - 1) (t_q - e_l)],
// t_k = R_k e_x (the end triads R_k, columns e_x e_y e_z), e_l the current chord's direction; the
// section's y axis interpolated between the ends and made normal to the tangent, z = t x y. With
// curved = false the straight chord with R_p's axes (an element with one triad). The pictures'
// one formula: Element::centreLine of the spatial beams, and the axes of other framed elements.
#include <Eigen/Core>

namespace flexmb::core {

// pts (and ys, zs when given, sized like pts): pts.cols() points at xi = k / (n - 1).
void coRotatedCurve(const Eigen::Vector3d& xp, const Eigen::Matrix3d& Rp, const Eigen::Vector3d& xq,
                    const Eigen::Matrix3d& Rq, double l0, bool curved, Eigen::Ref<Eigen::Matrix3Xd> pts,
                    Eigen::Matrix3Xd* ys, Eigen::Matrix3Xd* zs);

}  // namespace flexmb::core
