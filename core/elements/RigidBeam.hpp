#pragma once
// RBEAM (spatial-elements.md 5.2): rigid link from position node p with orientation Rp to a second
// position node q. x = [x_p (3), lambda_p (4), x_q (3)]. Three deformations, fixed by default:
//   e1 = l - l0,  e2 = e_y^p . d,  e3 = e_z^p . d   (d = x_q - x_p, e^p the element triad at p)
// which keep q at its initial place in the body frame of Rp. Mass (EM rhoA): rigid rod
// (rhoA l0/6) [[2I, I], [I, 2I]] on (x_p, x_q).
#include <Eigen/Core>

#include "core/elements/Element.hpp"

namespace flexmb::core {

class RigidBeam final : public Element {
 public:
  RigidBeam(const ElemVec& x0, const double* y);
  static std::unique_ptr<Element> create(const ElemVec& x0, const double* y, const ElementOptions& o);
  int numCoords() const override { return 10; }
  int numDeformations() const override { return 3; }
  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  void constitutive(std::span<const double> params, DefMat& S) const override;
  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void gravityForces3(const ElemVec& x, const ElementInertia& inertia, const double* g, ElemVec& f) const override;

 private:
  struct Defs;
  void evaluate(const ElemVec& x, int order, Defs& d) const;
  double l0_ = 0.0;
  Eigen::Matrix3d Ap_;
};

}  // namespace flexmb::core
