#pragma once
// L2MIN1: the normalisation constraint of an orientation node, e = lambda^T lambda - 1 (always
// fixed; created by flexmb for every orientation node with a calculable parameter). It also
// carries the rigid-body inertia of an XM inertia tensor on its node (body frame, tensor J):
// T = 1/2 w'^T J w', w' = 2 G lambdad, so M = 4 G^T J G and h = 8 G(lambdad)^T J G lambdad.
#include "core/elements/Element.hpp"

namespace flexmb::core {

class EulerNormalisation final : public Element {
 public:
  static std::unique_ptr<Element> create(const ElemVec& x0, const ElementOptions& options);
  int numCoords() const override { return 4; }
  int numDeformations() const override { return 1; }
  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  void constitutive(std::span<const double> params, DefMat& S) const override;
  // inertia: jxx jyy jzz jxy jxz jyz, the body-frame tensor.
  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const override;
};

}  // namespace flexmb::core
