#pragma once
// The derivative queries of an element whose deformations come with their gradients and Hessians
// from one evaluation: Derived::evaluate(x, order, d) fills d.e[i] with the value of deformation i,
// with order >= 1 also its gradient and with order >= 2 its Hessian (spatial::Scalar, closed forms
// from SpatialPrimitives.hpp). This base answers deformations, jacobian, deformationsAndJacobian,
// secondDerivative and stressWeightedHessian from it, each asking for the lowest order it needs.
// Fixed sizes (NC coordinates, ND deformations): nothing is allocated.
#include <Eigen/Core>

#include "core/elements/Element.hpp"
#include "core/elements/SpatialPrimitives.hpp"

namespace flexmb::core {

template <class Derived, int NC, int ND>
class EvaluatedElement : public Element {
 public:
  using Vec = Eigen::Matrix<double, NC, 1>;
  using Mat = Eigen::Matrix<double, NC, NC>;
  // The deformations with their derivatives up to the order evaluated.
  struct Defs {
    spatial::Scalar<NC> e[ND];
  };

  int numCoords() const final { return NC; }
  int numDeformations() const final { return ND; }

  void deformations(const ElemVec& x, DefVec& e) const final {
    Defs d;
    self().evaluate(x, 0, d);
    values(d, e);
  }
  void jacobian(const ElemVec& x, DefJac& De) const final {
    Defs d;
    self().evaluate(x, 1, d);
    gradients(d, De);
  }
  // One evaluation for both: a value does not depend on the order evaluated.
  void deformationsAndJacobian(const ElemVec& x, DefVec& e, DefJac& De) const final {
    Defs d;
    self().evaluate(x, 1, d);
    values(d, e);
    gradients(d, De);
  }
  // d2_i = v^T H_i v.
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const final {
    Defs d;
    self().evaluate(x, 2, d);
    const Vec vv = v;
    d2.resize(ND);
    for (int i = 0; i < ND; ++i) d2[i] = vv.dot(d.e[i].H * vv);
  }
  // H = sum_i sigma_i H_i (Eq. 16c), skipping the deformations without stress.
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const final {
    Defs d;
    self().evaluate(x, 2, d);
    Mat Hs = Mat::Zero();
    for (int i = 0; i < ND; ++i)
      if (sigma[i] != 0.0) Hs += sigma[i] * d.e[i].H;
    H = Hs;
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  static void values(const Defs& d, DefVec& e) {
    e.resize(ND);
    for (int i = 0; i < ND; ++i) e[i] = d.e[i].v;
  }
  static void gradients(const Defs& d, DefJac& De) {
    De.resize(ND, NC);
    for (int i = 0; i < ND; ++i) De.row(i) = d.e[i].g.transpose();
  }
};

}  // namespace flexmb::core
