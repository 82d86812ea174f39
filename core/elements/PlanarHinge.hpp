#pragma once
// PLHINGE: planar hinge between two orientation nodes, x = [phip, phiq],
// e1 = (phiq - phip) - (phiq0 - phip0), so that e1 = 0 initially (Eq. 5). S = k. No mass.
#include "core/elements/Element.hpp"

namespace flexmb::core {

class PlanarHinge final : public Element {
 public:
  explicit PlanarHinge(const ElemVec& x0);
  static std::unique_ptr<Element> create(const ElemVec& x0, const ElementOptions& options);

  int numCoords() const override { return 2; }
  int numDeformations() const override { return 1; }

  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  // Ends: phi_p and phi_q; e1 = phi_q - phi_p - delta0 (Eq. 5) is its own inverse.
  int endOfCoordinate(int i) const override { return i; }
  bool place(const DefVec& e, int to, ElemVec& x) const override {
    if (to == 1)
      x[1] = x[0] + e[0] + delta0_;
    else
      x[0] = x[1] - e[0] - delta0_;
    return true;
  }
  // params = [k] (N m/rad): S = k.
  void constitutive(std::span<const double> params, DefMat& S) const override;

  // Restart: delta0 such that e1 = e at x (a hinge has no length; length0 is not used).
  void setReference(const ElemVec& x, const DefVec& e, double) override { delta0_ = (x[1] - x[0]) - e[0]; }

 private:
  double delta0_ = 0.0;  // phiq0 - phip0
};

}  // namespace flexmb::core
