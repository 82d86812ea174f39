#pragma once
// TRUSS: spatial truss, e1 = l - l0 (docs/theory/spatial-elements.md section 3). x = [x_p, x_q] (6).
// Mass: the constant rod matrix (rhoA l0/6) [[2I, I], [I, 2I]], exact for any rigid motion.
#include "core/elements/Element.hpp"

namespace flexmb::core {

class SpatialTruss final : public Element {
 public:
  explicit SpatialTruss(const ElemVec& x0);
  static std::unique_ptr<Element> create(const ElemVec& x0, const ElementOptions& options);
  int numCoords() const override { return 6; }
  int numDeformations() const override { return 1; }
  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  void constitutive(std::span<const double> params, DefMat& S) const override;  // [EA]: EA/l0
  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void gravityForces3(const ElemVec& x, const ElementInertia& inertia, const double* g, ElemVec& f) const override;

  double referenceLength() const override { return l0_; }

 private:
  double l0_ = 0.0;
};

}  // namespace flexmb::core
