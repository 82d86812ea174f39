#pragma once
// HINGE (spatial-elements.md 5.1): relative rotation of orientation node q with respect to p about
// the hinge axis, and two tilts of the axis. x = [lambda_p (4), lambda_q (4)]. With the hinge triad
// e^k = R(lambda_k) A_k (A_k fixed at creation from the axis, e_x along it):
//   e1 = atan2(e_z^p.e_y^q - e_y^p.e_z^q, e_y^p.e_y^q + e_z^p.e_z^q)   rotation about the axis
//   e2 = (e_x^p.e_z^q - e_z^p.e_x^q)/2,  e3 = (e_y^p.e_x^q - e_x^p.e_y^q)/2   tilts about y and z
// For small angles e is the relative rotation vector in the hinge frame. e1 is the principal value
// in (-pi, pi] (no revolution counter: an element holds no state).
#include <Eigen/Core>

#include "core/elements/Element.hpp"

namespace flexmb::core {

class SpatialHinge final : public Element {
 public:
  SpatialHinge(const ElemVec& x0, const double* axis);
  static std::unique_ptr<Element> create(const ElemVec& x0, const double* axis, const ElementOptions& o);
  int numCoords() const override { return 8; }
  int numDeformations() const override { return 3; }
  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  // params = [St, (S2, S3)]: diagonal (rotational stiffness about the axis, optional tilts).
  void constitutive(std::span<const double> params, DefMat& S) const override;

 private:
  struct Defs;
  void evaluate(const ElemVec& x, int order, Defs& d) const;
  Eigen::Matrix3d Ap_, Aq_;
};

}  // namespace flexmb::core
