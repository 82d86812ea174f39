#pragma once
// The total energy of a state, as the energy tests check it.
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/Inertia.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core::test {

// T + V: kinetic 1/2 xd^T M(x) xd plus elastic 1/2 e^T S e over the deformations that carry stress
// (dynamic and calculable; every deformation with allDeformations).
inline double totalEnergy(const Model& m, Inertia& inertia, const StateOutputs& s, bool allDeformations = false) {
  inertia.update(s.x);
  auto active = [&](int k) { return allDeformations || m.eRole[k] == Role::Dynamic || m.eRole[k] == Role::Calculable; };
  double V = 0.0;
  for (const auto& E : m.elements) {
    if (!E.hasStiffness) continue;
    const int nd = E.impl->numDeformations();
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) {
        const int a = E.firstDef + i, b = E.firstDef + j;
        if (active(a) && active(b)) V += 0.5 * s.e[a] * E.S(i, j) * s.e[b];
      }
  }
  return inertia.kineticEnergy(s.xd) + V;
}

}  // namespace flexmb::core::test
