// The element keyword table (dat-format.md section 2).
#include <algorithm>
#include <cctype>
#include <string_view>

#include "core/elements/Element.hpp"
#include "core/elements/PlanarBeam.hpp"
#include "core/elements/PlanarHinge.hpp"
#include "core/elements/PlanarTruss.hpp"

namespace flexmb::core {

int ElementTypeInfo::numCoords() const {
  int n = 0;
  for (NodeKind k : slots) n += (k == NodeKind::Position) ? 2 : 1;
  return n;
}

const std::vector<ElementTypeInfo>& elementTypes() {
  using enum NodeKind;
  static const std::vector<ElementTypeInfo> types = [] {
    const std::vector<std::string> beamDefs = {"elongation", "bending p", "bending q"};
    const std::vector<ParameterSpec> beamParams = {
        {"EA", "N", "axial stiffness (EDAMP: axial damping coefficient)"},
        {"EI", "N m^2", "bending stiffness (EDAMP: bending damping coefficient)"}};
    std::vector<ElementTypeInfo> t;
    t.push_back({"PLBEAM",
                 "planar flexible beam; elongation l - l0 (SPACAR95) or with bending correction "
                 "(Eq. 3a, SPACAR 2013+), bending at p and q (Eq. 3b, 3c)",
                 {Position, Orientation, Position, Orientation},
                 beamDefs,
                 beamParams,
                 &PlanarBeam::create});
    t.push_back({"PLBEAMNL",
                 "planar flexible beam, elongation always with the bending correction (Eq. 3a)",
                 {Position, Orientation, Position, Orientation},
                 beamDefs,
                 beamParams,
                 &PlanarBeam::createNonlinear});
    t.push_back({"PLTRUSS",
                 "planar truss, elongation l - l0",
                 {Position, Position},
                 {"elongation"},
                 {{"EA", "N", "axial stiffness (EDAMP: axial damping coefficient)"}},
                 &PlanarTruss::create});
    t.push_back({"PLHINGE",
                 "planar hinge, relative rotation of node q with respect to node p (Eq. 5)",
                 {Orientation, Orientation},
                 {"relative rotation"},
                 {{"k", "N m/rad", "rotational stiffness (EDAMP: N m s/rad damping coefficient)"}},
                 &PlanarHinge::create});
    return t;
  }();
  return types;
}

const ElementTypeInfo* findElementType(std::string_view keyword) {
  auto eq = [](std::string_view a, std::string_view b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](char c, char d) {
             return std::toupper(static_cast<unsigned char>(c)) ==
                    std::toupper(static_cast<unsigned char>(d));
           });
  };
  for (const ElementTypeInfo& t : elementTypes())
    if (eq(t.keyword, keyword)) return &t;
  return nullptr;
}

}  // namespace flexmb::core
