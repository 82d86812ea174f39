#include "core/elements/PlanarHinge.hpp"

#include <stdexcept>

namespace flexmb::core {

PlanarHinge::PlanarHinge(const ElemVec& x0) {
  if (x0.size() != 2) throw std::invalid_argument("planar hinge: expected 2 initial coordinates");
  delta0_ = x0[1] - x0[0];
}

std::unique_ptr<Element> PlanarHinge::create(const ElemVec& x0, const ElementOptions&) {
  return std::make_unique<PlanarHinge>(x0);
}

void PlanarHinge::deformations(const ElemVec& x, DefVec& e) const {
  e.resize(1);
  e[0] = (x[1] - x[0]) - delta0_;
}

void PlanarHinge::jacobian(const ElemVec&, DefJac& De) const {
  De.resize(1, 2);
  De << -1.0, 1.0;
}

void PlanarHinge::secondDerivative(const ElemVec&, const ElemVec&, DefVec& d2) const { d2.setZero(1); }

void PlanarHinge::stressWeightedHessian(const ElemVec&, const DefVec&, ElemMat& H) const { H.setZero(2, 2); }

void PlanarHinge::constitutive(std::span<const double> params, DefMat& S) const {
  S.setZero(1, 1);
  S(0, 0) = params.size() > 0 ? params[0] : 0.0;
}

}  // namespace flexmb::core
