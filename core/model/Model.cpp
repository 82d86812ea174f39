#include "core/model/Model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace flexmb::core {

const char* roleName(Role r) {
  switch (r) {
    case Role::Fixed:
      return "fixed";
    case Role::Input:
      return "input";
    case Role::Dynamic:
      return "dynamic";
    case Role::Calculable:
      return "calculable";
  }
  return "?";
}

void Rheonomic::evaluate(double t, double& x, double& xd, double& xdd) const {
  if (fx) {
    x = fx->value(t);
    xd = fv ? fv->value(t) : 0.0;
    xdd = fa ? fa->value(t) : 0.0;
    return;
  }
  const double dt = t - tRef;
  x = x0 + v * dt + 0.5 * a * dt * dt;
  xd = v + a * dt;
  xdd = a;
}

double Model::lengthScale() const {
  double L = 0.0;
  for (int i = 0; i < nx; ++i)
    if (isTranslational(nodes[xOwnerNode[i]].kind)) L = std::max(L, std::abs(x0[i]));
  return L;
}

std::string Model::coordName(int xIndex) const {
  const Node& n = nodes[xOwnerNode[xIndex]];
  const int comp = xIndex - n.firstCoord + 1;
  if (n.kind == NodeKind::Orientation) return "x(node " + std::to_string(n.label) + ", angle)";
  if (n.kind == NodeKind::Warping) return "x(node " + std::to_string(n.label) + ", warping)";
  if (n.kind == NodeKind::EulerParameters)
    return "x(node " + std::to_string(n.label) + ", lambda" + std::to_string(comp - 1) + ")";
  if (n.kind == NodeKind::SpatialPosition)
    return "x(node " + std::to_string(n.label) + ", " + (comp == 1 ? "x" : comp == 2 ? "y" : "z") + ")";
  return "x(node " + std::to_string(n.label) + ", " + (comp == 1 ? "x" : "y") + ")";
}

std::string Model::deformationName(int eIndex) const {
  const ElementEntry& el = elements[eOwnerElement[eIndex]];
  const int comp = eIndex - el.firstDef;
  return "e(" + el.type->keyword + " " + std::to_string(el.label) + ", " + std::to_string(comp + 1) + " " +
         el.type->deformationNames[comp] + ")";
}

}  // namespace flexmb::core
