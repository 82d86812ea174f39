#pragma once
// HINGE (docs/theory/spatial-elements.md 5.1): relative rotation of orientation node q with respect to p about
// the hinge axis, and two tilts of the axis. x = [lambda_p (4), lambda_q (4)]. With the hinge triad
// e^k = R(lambda_k) A_k (A_k fixed at creation from the axis, e_x along it):
//   e1 = atan2(e_z^p.e_y^q - e_y^p.e_z^q, e_y^p.e_y^q + e_z^p.e_z^q)   rotation about the axis
//   e2 = -e_z^p.e_x^q,  e3 = e_y^p.e_x^q   tilts of q's axis about p's local y and z
// For small angles e is the relative rotation vector in the hinge frame. The tilts are not the
// symmetric (e_x^p.e_z^q - e_z^p.e_x^q)/2 of docs/theory/spatial-elements.md 5.1: that form loses rank at a half
// turn about the axis (its tilt Jacobian scales with 1 + cos e1), so a hinge could not turn through
// pi; these agree with it to first order at e1 = 0 and keep rank 2 at every angle. e1 is the principal value
// in (-pi, pi] (an element holds no state); GeometricTransferFunctions adds the revolutions, so
// the angle (a DOF, an input or an output) runs on continuously through pi.
#include <Eigen/Core>

#include "core/elements/EvaluatedElement.hpp"

namespace flexmb::core {

class SpatialHinge final : public EvaluatedElement<SpatialHinge, 8, 3> {
 public:
  SpatialHinge(const ElemVec& x0, const double* axis);
  static std::unique_ptr<Element> create(const ElemVec& x0, const double* axis, const ElementOptions& o);
  // params = [St, (S2, S3)]: diagonal (rotational stiffness about the axis, optional tilts).
  void constitutive(std::span<const double> params, DefMat& S) const override;
  bool isPeriodicAngle(int i) const override { return i == 0; }

  bool elementFrame(int end, Eigen::Matrix3d& A) const override {
    if (end < 0 || end > 1) return false;
    A = end == 0 ? Ap_ : Aq_;
    return true;
  }

 private:
  friend class EvaluatedElement<SpatialHinge, 8, 3>;
  // e1..e3 of the header with their derivatives up to order (EvaluatedElement).
  void evaluate(const ElemVec& x, int order, Defs& d) const;
  Eigen::Matrix3d Ap_, Aq_;
};

}  // namespace flexmb::core
