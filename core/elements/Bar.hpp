#pragma once
// What every two-node bar (PLTRUSS, TRUSS) has in common, whatever its dimension: the axial
// stiffness and the consistent mass of a linear displacement field.
#include <span>

#include "core/elements/Element.hpp"

namespace flexmb::core::bar {

// params = [EA]: S = EA / l0 (a missing entry counts as 0).
inline void constitutive(std::span<const double> params, double l0, DefMat& S) {
  S.setZero(1, 1);
  S(0, 0) = (params.size() > 0 ? params[0] : 0.0) / l0;
}

// rhoA l0 / 6 [[2, 1], [1, 2]] (x) I_dim over the two ends' positions.
inline void mass(double rhoA, double l0, int dim, ElemMat& M) {
  const double a = rhoA * l0 / 3.0, b = rhoA * l0 / 6.0;
  M.setZero(2 * dim, 2 * dim);
  for (int i = 0; i < dim; ++i) {
    M(i, i) = M(i + dim, i + dim) = a;
    M(i, i + dim) = M(i + dim, i) = b;
  }
}

}  // namespace flexmb::core::bar
