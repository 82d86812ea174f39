// The element keyword table (docs/theory/dat-format.md section 2).
#include <algorithm>
#include <cctype>
#include <string_view>

#include "core/elements/Element.hpp"
#include "core/elements/EulerNormalisation.hpp"
#include "core/elements/PlanarBeam.hpp"
#include "core/elements/PlanarHinge.hpp"
#include "core/elements/PlanarTruss.hpp"
#include "core/elements/RigidBeam.hpp"
#include "core/elements/SpatialBeam.hpp"
#include "core/elements/SpatialHinge.hpp"
#include "core/elements/SpatialTruss.hpp"
#include "core/elements/SpatialWarpingBeam.hpp"

namespace flexmb::core {

int ElementTypeInfo::numCoords() const {
  int n = 0;
  for (NodeKind k : slots) n += nodeKindDim(k);
  return n;
}

bool ElementTypeInfo::isLargeRotation(int deformation) const {
  return std::find(largeRotations.begin(), largeRotations.end(), deformation) != largeRotations.end();
}

namespace {
// SPACAR type codes (`it`; io/results.md has the evidence): SPACAR's own where they are known
// (BEAM 1, TRUSS 2, HINGE 3, the Euler-parameter normalisation 4, PLBEAM 5, PLTRUSS 7). The NL variants differ only in
// the elongation, which SPACAR keeps as a per-element flag, not as a type: they share their element's code. Types whose
// SPACAR code is unknown get flexmb's own codes from 101, clear of every code SPACAR's tools use (1-18).
constexpr int kOwnTypeIds = 100;
}  // namespace

double ElementInertia::*ElementInertia::field(std::string_view name) {
  static const std::pair<std::string_view, double ElementInertia::*> fields[] = {
      {"rhoA", &ElementInertia::rhoA}, {"rhoI", &ElementInertia::rhoI}, {"Jxx", &ElementInertia::jxx},
      {"Jyy", &ElementInertia::jyy},   {"Jzz", &ElementInertia::jzz},   {"Jyz", &ElementInertia::jyz},
      {"Jw", &ElementInertia::jw}};
  for (const auto& [n, f] : fields)
    if (n == name) return f;
  return nullptr;
}

bool ElementTypeInfo::isAlwaysReleased(int deformation) const {
  return std::find(alwaysReleased.begin(), alwaysReleased.end(), deformation) != alwaysReleased.end();
}

const std::vector<ElementTypeInfo>& elementTypes() {
  using enum NodeKind;
  using K = DeformationKind;
  static const std::vector<ElementTypeInfo> types = [] {
    const std::vector<std::string> beamDefs = {"elongation", "bending p", "bending q"};
    const std::vector<ParameterSpec> beamParams = {
        {"EA", "N", "axial stiffness (EDAMP: axial damping coefficient)"},
        {"EI", "N m^2", "bending stiffness (EDAMP: bending damping coefficient)"}};
    std::vector<ElementTypeInfo> t;
    {
      ElementTypeInfo b{"PLBEAM",
                        "planar flexible beam; elongation l - l0 (SPACAR95) or with bending correction "
                        "(Eq. 3a, SPACAR 2013+), bending at p and q (Eq. 3b, 3c)",
                        {Position, Orientation, Position, Orientation},
                        beamDefs,
                        beamParams,
                        &PlanarBeam::create};
      b.spacarTypeId = 5;
      b.drawnCurved = true;
      b.deformationKinds = {K::Elongation, K::Bending, K::Bending};
      t.push_back(b);
      b.keyword = "PLBEAMNL";
      b.description = "planar flexible beam, elongation always with the bending correction (Eq. 3a)";
      b.create = &PlanarBeam::createNonlinear;
      t.push_back(b);
    }
    {
      ElementTypeInfo tr{"PLTRUSS",
                         "planar truss, elongation l - l0",
                         {Position, Position},
                         {"elongation"},
                         {{"EA", "N", "axial stiffness (EDAMP: axial damping coefficient)"}},
                         &PlanarTruss::create};
      tr.spacarTypeId = 7;
      tr.deformationKinds = {K::Elongation};
      t.push_back(tr);
    }
    {
      ElementTypeInfo h{"PLHINGE",
                        "planar hinge, relative rotation of node q with respect to node p (Eq. 5)",
                        {Orientation, Orientation},
                        {"relative rotation"},
                        {{"k", "N m/rad", "rotational stiffness (EDAMP: N m s/rad damping coefficient)"}},
                        &PlanarHinge::create};
      h.spacarTypeId = kOwnTypeIds + 1;
      h.largeRotations = {0};
      h.deformationKinds = {K::Rotation};
      t.push_back(h);
    }

    // Spatial elements (docs/theory/spatial-elements.md): position nodes x y z, orientation nodes with four
    // Euler parameters.
    const std::vector<ParameterSpec> yAxis = {{"y1", "-", "initial cross-section y axis, x component"},
                                              {"y2", "-", "y component"},
                                              {"y3", "-", "z component"}};
    const std::vector<std::string> spatialBeamDefs = {"elongation",  "torsion",     "bending y p",
                                                      "bending y q", "bending z p", "bending z q"};
    const std::vector<ParameterSpec> spatialBeamParams = {
        {"EA", "N", "axial stiffness"},
        {"GIt", "N m^2", "torsional stiffness"},
        {"EIy", "N m^2", "bending stiffness about the local y axis (deformations 3, 4)"},
        {"EIz", "N m^2", "bending stiffness about the local z axis (deformations 5, 6)"},
        {"cy", "m^2", "shear flexibility EIy/(k G A) (optional, 0: Euler-Bernoulli)"},
        {"cz", "m^2", "shear flexibility EIz/(k G A) (optional)"}};
    const std::vector<ParameterSpec> spatialBeamMass = {
        {"rhoA", "kg/m", "mass per length"},
        {"Jxx", "kg m", "polar mass moment of inertia per length (local x)"},
        {"Jyy", "kg m", "mass moment of inertia per length about local y"},
        {"Jzz", "kg m", "mass moment of inertia per length about local z"},
        {"Jyz", "kg m", "product of inertia per length (y z)"}};
    const std::vector<ParameterSpec> rhoAOnly = {{"rhoA", "kg/m", "mass per length"}};
    // BEAMW's layouts: BEAM's with the warping stiffness and inertia last. SPACAR Light and oopspa
    // write these for every beam and truss; the values an element has no use for are ignored.
    std::vector<ParameterSpec> sectionParams = spatialBeamParams, sectionMass = spatialBeamMass;
    sectionParams.push_back({"ECw", "N m^4", "warping stiffness E Cw (BEAMW; thin rectangle w x t: Cw = w^3 t^3/144)"});
    sectionMass.push_back({"Jw", "kg m^3", "warping inertia rho Cw per length (BEAMW)"});
    const std::vector<DeformationKind> spatialBeamKinds = {K::Elongation, K::Torsion,  K::BendingY,
                                                           K::BendingY,   K::BendingZ, K::BendingZ};
    auto tail = [](const std::vector<ParameterSpec>& all, size_t from) {
      return std::vector<ParameterSpec>(all.begin() + static_cast<std::ptrdiff_t>(from), all.end());
    };
    {
      ElementTypeInfo b{"BEAM",
                        "spatial flexible beam: elongation l - l0, torsion, bending about the local y "
                        "and z axes at p and q (l0 sin theta, as PLBEAM); y1 y2 y3: initial "
                        "cross-section y axis",
                        {SpatialPosition, EulerParameters, SpatialPosition, EulerParameters},
                        spatialBeamDefs,
                        spatialBeamParams,
                        nullptr};
      b.vector = yAxis;
      b.createWithVector = &SpatialBeam::create;
      b.inertia = spatialBeamMass;
      b.spacarTypeId = 1;
      b.ignoredStiffness = tail(sectionParams, spatialBeamParams.size());
      b.ignoredInertia = tail(sectionMass, spatialBeamMass.size());
      b.drawnCurved = true;
      b.deformationKinds = spatialBeamKinds;
      t.push_back(b);
      b.keyword = "BEAMNL";
      b.description = "spatial flexible beam with the bending-corrected elongation (Eq. 3a in both planes)";
      b.createWithVector = &SpatialBeam::createNonlinear;
      t.push_back(b);
    }
    {
      // core/elements/BEAMW.md: Vlasov's non-uniform torsion with the rate of twist as the
      // coordinate of a warping node at each end.
      ElementTypeInfo w{"BEAMW",
                        "spatial flexible beam with warping (restrained torsion, Vlasov): BEAM's six "
                        "deformations and two warping deformations, each end with a position, an "
                        "orientation and a warping node (one coordinate, the rate of twist; a degree of "
                        "freedom unless FIX or INPUTX); y1 y2 y3: initial cross-section y axis",
                        {SpatialPosition, EulerParameters, Warping, SpatialPosition, EulerParameters, Warping},
                        spatialBeamDefs,
                        sectionParams,
                        nullptr};
      w.deformationNames.push_back("warping p");
      w.deformationNames.push_back("warping q");
      w.deformationKinds = spatialBeamKinds;
      w.deformationKinds.insert(w.deformationKinds.end(), {K::Warping, K::Warping});
      w.vector = yAxis;
      w.createWithVector = &SpatialWarpingBeam::create;
      w.inertia = sectionMass;
      w.requiredStiffness = 7;
      w.alwaysReleased = {6, 7};
      w.spacarTypeId = 18;  // SPACAR's code of BEAMW (spadraw takes its node q from ln(:, 4))
      t.push_back(w);
    }
    {
      ElementTypeInfo tr{"TRUSS",        "spatial truss, elongation l - l0", {SpatialPosition, SpatialPosition},
                         {"elongation"}, {{"EA", "N", "axial stiffness"}},   &SpatialTruss::create};
      tr.inertia = rhoAOnly;
      tr.spacarTypeId = 2;
      tr.deformationKinds = {K::Elongation};
      tr.ignoredStiffness = tail(sectionParams, 1);
      tr.ignoredInertia = tail(sectionMass, 1);
      t.push_back(tr);
    }
    {
      ElementTypeInfo h{"HINGE",
                        "spatial hinge: rotation of orientation q relative to p about the axis a1 a2 "
                        "a3, and two tilts of the axis (normally fixed)",
                        {EulerParameters, EulerParameters},
                        {"rotation", "tilt y", "tilt z"},
                        {{"St", "N m/rad", "rotational stiffness about the axis"},
                         {"S2", "N m/rad", "tilt stiffness about local y (optional)"},
                         {"S3", "N m/rad", "tilt stiffness about local z (optional)"}},
                        nullptr};
      h.vector = {{"a1", "-", "hinge axis, x component"}, {"a2", "-", "y component"}, {"a3", "-", "z component"}};
      h.createWithVector = &SpatialHinge::create;
      h.spacarTypeId = 3;      // SPACAR's own slidercrank.sbd (oopspa bcad60f): its HINGEs are IT 3
      h.largeRotations = {0};  // the rotation about the axis; the tilts stay small
      h.deformationKinds = {K::Rotation, K::Other, K::Other};
      t.push_back(h);
    }
    {
      ElementTypeInfo r{"RBEAM",
                        "rigid spatial beam from node p with orientation to node q (three fixed "
                        "deformations: length and two lateral offsets in the frame of p)",
                        {SpatialPosition, EulerParameters, SpatialPosition},
                        {"elongation", "lateral y", "lateral z"},
                        {},
                        nullptr};
      r.vector = yAxis;
      r.createWithVector = &RigidBeam::create;
      r.inertia = rhoAOnly;
      r.spacarTypeId = kOwnTypeIds + 3;
      r.deformationKinds = {K::Elongation, K::Other, K::Other};
      t.push_back(r);
    }
    return t;
  }();
  return types;
}

const ElementTypeInfo& normalisationType() {
  static const ElementTypeInfo n = [] {
    ElementTypeInfo i{"L2MIN1",
                      "normalisation of the Euler parameters of an orientation node, lambda^T lambda "
                      "- 1 (created by flexmb for every orientation node)",
                      {NodeKind::EulerParameters},
                      {"normalisation"},
                      {},
                      &EulerNormalisation::create};
    i.internal = true;
    i.spacarTypeId = 4;  // SPACAR writes one such element of code 4 per orientation node (slidercrank.sbd)
    return i;
  }();
  return n;
}

const ElementTypeInfo* findElementType(std::string_view keyword) {
  auto eq = [](std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char c, char d) {
             return std::toupper(static_cast<unsigned char>(c)) == std::toupper(static_cast<unsigned char>(d));
           });
  };
  for (const ElementTypeInfo& t : elementTypes())
    if (eq(t.keyword, keyword)) return &t;
  return nullptr;
}

}  // namespace flexmb::core
