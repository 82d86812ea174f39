#pragma once
// Directional derivatives of element functions that the element interface provides only up to
// second order: the configuration dependence of the inertia and gravity forces and the third
// derivatives of D, which the linearised equations of a moving system need (paper Eq. 15, ref.
// [13]). Central differences with one Richardson step (truncation O(h^4)) on the element's own
// analytic functions; steps are relative to each coordinate's scale (element length, or 1 rad).
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::core {

class ElementSteps {
 public:
  explicit ElementSteps(const Model& model);
  // Step h for direction a on element el: the largest scaled component of h a is 1e-3.
  double step(int el, const ElemVec& a) const;

 private:
  std::vector<ElemVec> scale_;  // per element coordinate: the element length or 1 (angles)
};

// d = d/ds g(x + s a) at s = 0; g(const ElemVec&, Out&) evaluates the element function.
template <class Fn, class Out>
void directionalDerivative(Fn&& g, const ElemVec& x, const ElemVec& a, double h, Out& d) {
  ElemVec xp, xm;
  Out gp, gm, coarse;
  auto central = [&](double s, Out& out) {
    xp = x + s * a;
    xm = x - s * a;
    g(xp, gp);
    g(xm, gm);
    out = (gp - gm) / (2.0 * s);
  };
  central(h, coarse);
  central(0.5 * h, d);
  d = (4.0 * d - coarse) / 3.0;
}

}  // namespace flexmb::core
