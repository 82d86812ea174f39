#pragma once
// Section constants the spatial tests give their beams, as SPACAR Light computes them.
#include <algorithm>
#include <cmath>
#include <numbers>

namespace flexmb::test {

// St Venant torsion constant of a w x t rectangle (series solution, Roark), to 1e-4 in the sum as
// SPACAR Light does.
inline double torsionConstant(double w, double t) {
  const double a = std::min(w, t) / 2, b = std::max(w, t) / 2;
  double s = 0.0;
  for (int n = 1;; n += 2) {
    const double term = std::tanh(n * std::numbers::pi * b / (2 * a)) / std::pow(n, 5);
    s += term;
    if (n >= 3 && term / s < 1e-4) break;
  }
  return std::pow(2 * a, 3) * (2 * b) / 3 * (1 - 192 / std::pow(std::numbers::pi, 5) * (a / b) * s);
}

}  // namespace flexmb::test
