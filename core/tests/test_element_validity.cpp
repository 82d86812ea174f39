// Element validity (Element::validity, core::firstInvalidElement): the PLBEAM bending of Eq. 3b/3c,
// e2 = l0 sin theta_p and e3 = -l0 sin theta_q, describes a node rotation theta against the chord
// only while cos theta > 0. Beyond 90 degrees the element is in a spurious state; a rigid rotation
// of the whole element is not a deformation and must stay valid however large.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/elements/PlanarBeam.hpp"
#include "core/elements/PlanarHinge.hpp"
#include "core/elements/PlanarTruss.hpp"
#include "core/kinematics/ElementValidity.hpp"
#include "core/model/ModelBuilder.hpp"

using namespace flexmb::core;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

ElemVec coords(std::initializer_list<double> v) {
  ElemVec x(static_cast<int>(v.size()));
  int k = 0;
  for (double d : v) x[k++] = d;
  return x;
}

// Rigid motion of beam coordinates [xp, yp, phip, xq, yq, phiq]: rotation by a about (cx, cy),
// then a translation (tx, ty).
ElemVec rigid(const ElemVec& x, double a, double cx, double cy, double tx, double ty) {
  const double c = std::cos(a), s = std::sin(a);
  ElemVec y = x;
  for (int k : {0, 3}) {
    const double dx = x[k] - cx, dy = x[k + 1] - cy;
    y[k] = cx + c * dx - s * dy + tx;
    y[k + 1] = cy + s * dx + c * dy + ty;
    y[k + 2] = x[k + 2] + a;
  }
  return y;
}

// Reference geometries: along x with BETA 0, and a general one (chord at an angle, BETA values that
// differ from the chord angle and from each other, as a .dat file may give them).
std::vector<ElemVec> references() { return {coords({0, 0, 0, 1, 0, 0}), coords({0.3, -0.2, 1.1, 1.0, 0.5, -2.0})}; }

}  // namespace

TEST(ElementValidity, BeamNodeRotationAgainstChord) {
  for (const ElemVec& x0 : references()) {
    const PlanarBeam beam(x0, ElongationDefinition::BendingCorrected);
    for (int node : {0, 1}) {  // p, q
      const int slot = node == 0 ? 1 : 3, coord = node == 0 ? 2 : 5;
      for (double deg : {0.0, 60.0, 89.0, -60.0, -89.0, 91.0, 170.0, -91.0, -170.0}) {
        ElemVec x = x0;
        x[coord] += deg * kDeg;
        const ElementValidity v = beam.validity(x);
        EXPECT_EQ(v.valid, std::abs(deg) < 90.0) << "node " << node << ", " << deg << " degrees";
        if (!v.valid) {
          EXPECT_EQ(v.slot, slot) << deg;
          EXPECT_NEAR(v.rotation / kDeg, deg, 1e-9) << deg;
          ASSERT_NE(v.limit, nullptr);
          EXPECT_NE(std::string(v.limit).find("Eq. 3"), std::string::npos) << v.limit;
        }
      }
    }
  }
}

// The same node rotation, measured against the moved chord: turning the chord by 100 degrees with
// both nodes fixed in orientation leaves each node at -100 degrees against it.
TEST(ElementValidity, BeamChordTurnedUnderFixedNodes) {
  const ElemVec x0 = coords({0, 0, 0, 1, 0, 0});
  const PlanarBeam beam(x0, ElongationDefinition::Plain);
  for (double deg : {60.0, 100.0}) {
    ElemVec x = x0;
    x[3] = std::cos(deg * kDeg);
    x[4] = std::sin(deg * kDeg);
    const ElementValidity v = beam.validity(x);
    EXPECT_EQ(v.valid, deg < 90.0) << deg;
    if (!v.valid) {
      EXPECT_NEAR(v.rotation / kDeg, -deg, 1e-9);
    }
  }
}

TEST(ElementValidity, BeamRigidRotationStaysValid) {
  for (const ElemVec& x0 : references()) {
    const PlanarBeam beam(x0, ElongationDefinition::BendingCorrected);
    for (double deg : {90.0, 170.0, -170.0, 180.0, 300.0, 720.0 + 170.0}) {
      EXPECT_TRUE(beam.validity(rigid(x0, deg * kDeg, 0.0, 0.0, 0.0, 0.0)).valid) << deg;
      EXPECT_TRUE(beam.validity(rigid(x0, deg * kDeg, -0.7, 2.0, 3.0, -1.0)).valid) << deg;
    }
    // Rigidly rotated by 170 degrees and then bent at q by 60 (valid) or 120 degrees (invalid).
    for (double bend : {60.0, 120.0}) {
      ElemVec x = rigid(x0, 170.0 * kDeg, 0.5, 0.5, 0.0, 0.0);
      x[5] += bend * kDeg;
      const ElementValidity v = beam.validity(x);
      EXPECT_EQ(v.valid, bend < 90.0) << bend;
      if (!v.valid) {
        EXPECT_NEAR(v.rotation / kDeg, bend, 1e-9);
      }
    }
  }
}

// The worse of the two nodes is reported.
TEST(ElementValidity, BeamReportsTheNodeTurnedFurthest) {
  const ElemVec x0 = coords({0, 0, 0, 1, 0, 0});
  const PlanarBeam beam(x0, ElongationDefinition::BendingCorrected);
  ElemVec x = x0;
  x[2] = 100.0 * kDeg;
  x[5] = -150.0 * kDeg;
  const ElementValidity v = beam.validity(x);
  EXPECT_FALSE(v.valid);
  EXPECT_EQ(v.slot, 3);
  EXPECT_NEAR(v.rotation / kDeg, -150.0, 1e-9);
}

// Truss and hinge measure their deformations exactly at any rotation: always valid.
TEST(ElementValidity, TrussAndHingeAlwaysValid) {
  const PlanarTruss truss(coords({0, 0, 1, 0}));
  EXPECT_TRUE(truss.validity(coords({0, 0, -1, 0.1})).valid);
  const PlanarHinge hinge(coords({0, 0}));
  EXPECT_TRUE(hinge.validity(coords({0, 3.0})).valid);
}

// Model level: a cantilever of two PLBEAMs (labels 7 and 8, position nodes 1-3, orientation nodes
// 101-103). The message names the element as in the .dat file, its keyword, the node and the angle.
TEST(ElementValidity, FirstInvalidElementNamesElementNodeAndAngle) {
  ModelBuilder b("validity.dat");
  const ElementTypeInfo* beam = findElementType("PLBEAM");
  ASSERT_NE(beam, nullptr);
  const std::vector<int> n7 = {1, 101, 2, 102}, n8 = {2, 102, 3, 103};
  b.addElement(*beam, 7, n7, 1);
  b.addElement(*beam, 8, n8, 2);
  for (int k = 1; k <= 3; ++k) {
    const std::vector<double> xy = {0.5 * (k - 1), 0.0};
    b.setCoordinates(k, xy, 2 + k);
  }
  b.setCoordinateRole(1, {}, Role::Fixed, 6);
  b.setCoordinateRole(101, {}, Role::Fixed, 7);
  const std::vector<int> bend = {2, 3};
  b.setDeformationRole(7, bend, Role::Dynamic, 8);
  b.setDeformationRole(8, bend, Role::Dynamic, 9);
  const Model m = b.finalize({});

  Eigen::VectorXd x = m.x0;
  EXPECT_FALSE(firstInvalidElement(m, x).has_value());
  // The whole cantilever turned rigidly by 170 degrees about the clamp: still valid.
  Eigen::VectorXd xr = x;
  const double a = 170.0 * kDeg;
  for (int k = 1; k <= 3; ++k) {
    const int i = m.nodes[m.nodeByLabel.at(k)].firstCoord;
    const double px = x[i], py = x[i + 1];
    xr[i] = std::cos(a) * px - std::sin(a) * py;
    xr[i + 1] = std::sin(a) * px + std::cos(a) * py;
    xr[m.nodes[m.nodeByLabel.at(100 + k)].firstCoord] += a;
  }
  EXPECT_FALSE(firstInvalidElement(m, xr).has_value());
  // Tip orientation node 103 turned by 120 degrees: element 8 is out of range at node 103.
  x[m.nodes[m.nodeByLabel.at(103)].firstCoord] = 120.0 * kDeg;
  const auto bad = firstInvalidElement(m, x);
  ASSERT_TRUE(bad.has_value());
  EXPECT_EQ(m.elements[bad->element].label, 8);
  EXPECT_NE(bad->message.find("element 8 (PLBEAM)"), std::string::npos) << bad->message;
  EXPECT_NE(bad->message.find("node 103"), std::string::npos) << bad->message;
  EXPECT_NE(bad->message.find("rotated 120.0 degrees"), std::string::npos) << bad->message;
  EXPECT_NE(bad->message.find("l0 sin theta"), std::string::npos) << bad->message;
}
