#pragma once
// PLTRUSS: planar truss, x = [xp, yp, xq, yq], one deformation e1 = l - l0 (S = EA/l0).
// Inertia: linear position field r(xi) = (1-xi) rp + xi rq (rigid-rod consistent mass, constant,
// no rotary inertia, no velocity dependent forces).
#include <cmath>

#include "core/elements/Element.hpp"

namespace flexmb::core {

class PlanarTruss final : public Element {
 public:
  // Throws std::invalid_argument for coincident end nodes.
  explicit PlanarTruss(const ElemVec& x0);
  static std::unique_ptr<Element> create(const ElemVec& x0, const ElementOptions& options);

  int numCoords() const override { return 4; }
  int numDeformations() const override { return 1; }

  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  // params = [EA]: S = EA/l0.
  void constitutive(std::span<const double> params, DefMat& S) const override;

  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const override;
  void gravityForces(const ElemVec& x, const ElementInertia& inertia, double gx, double gy, ElemVec& f) const override;

  double l0() const { return l0_; }
  double referenceLength() const override { return l0_; }
  // Restart: l0 = length0, or l(x) - e1 when length0 is not given.
  void setReference(const ElemVec& x, const DefVec& e, double length0) override {
    l0_ = length0 > 0.0 ? length0 : std::hypot(x[2] - x[0], x[3] - x[1]) - e[0];
    if (!(l0_ > 0.0)) throw std::invalid_argument("planar truss: the reference length must be positive");
  }

 private:
  double l0_ = 0.0;
};

}  // namespace flexmb::core
