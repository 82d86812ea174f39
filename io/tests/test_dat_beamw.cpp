// BEAMW as SPACAR Light writes it (core/elements/BEAMW.md section 1): its cross-spring pivot reads
// with SPACAR's meaning (free warping coordinates are degrees of freedom, deformations 7 and 8 are
// always released) and passes the kinematic check; roles and bad input name file, line and reason;
// the section values SPACAR Light and oopspa write for BEAM and TRUSS beyond their own layout are
// ignored with a note naming file and line; result names of warping coordinates.
#include <gtest/gtest.h>

#include <string>

#include "core/kinematics/KinematicCheck.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/ResultWriter.hpp"

using namespace flexmb;
using core::Role;

namespace {

std::string errorOf(const std::string& text) {
  try {
    io::readDatString(text, "t.dat");
  } catch (const io::DatError& e) {
    return e.what();
  }
  return "";
}
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
int xIndex(const core::Model& m, int node, int comp = 1) {
  return m.nodes.at(m.nodeByLabel.at(node)).firstCoord + comp - 1;
}
int eIndex(const core::Model& m, int element, int comp) {
  return m.elements.at(m.elementByLabel.at(element)).firstDef + comp - 1;
}

// Two BEAMWs in a row along x, clamped at node 1 (position 1, orientation 2, warping 3).
const std::string kTwo =
    "X 1 0 0 0\nX 4 0.5 0 0\nX 7 1 0 0\n"
    "BEAMW 1 1 2 3 4 5 6 0 0 1\nBEAMW 2 4 5 6 7 8 9 0 0 1\n";
std::string twoBeams(const std::string& roles, const std::string& dynamic = "") {
  return kTwo + roles + "END\nHALT\n" + dynamic + "END\nEND\n";
}
const std::string kStiff = "ESTIFF 1 1e6 2 3 4 0 0 0.5\nESTIFF 2 1e6 2 3 4 0 0 0.5\n";

}  // namespace

TEST(DatBeamW, SpacarLightPivotReadsWithSpacarsMeaning) {
  const core::Model m = io::readDatFile(FLEXMB_SOURCE_DIR "/datfiles/spatial/cross_spring_pivot_beamw.dat");
  // 24 nodes: 8 position, 8 orientation, 8 warping; 64 coordinates, 7 x 8 + 8 L2MIN1 deformations.
  int warping = 0, freeWarping = 0;
  for (const auto& n : m.nodes)
    if (n.kind == core::NodeKind::Warping) {
      ++warping;
      freeWarping += m.xRole[n.firstCoord] == Role::Dynamic;
    }
  EXPECT_EQ(warping, 8);
  EXPECT_EQ(freeWarping, 4);  // the intermediate nodes 15, 18, 21, 24; 3, 6, 9, 12 are fixed
  for (int w : {15, 18, 21, 24}) EXPECT_EQ(m.xRole[xIndex(m, w)], Role::Dynamic) << w;
  for (int w : {3, 6, 9, 12}) EXPECT_EQ(m.xRole[xIndex(m, w)], Role::Fixed) << w;
  EXPECT_EQ(m.nx, 64);
  // 7 x 8 BEAMW deformations and an L2MIN1 for each orientation node with a calculable parameter:
  // 6 of 8 (those of the clamps, 2 and 11, are fixed and drop out).
  EXPECT_EQ(m.ne, 7 * 8 + 6);
  for (int e = 1; e <= 7; ++e) {
    EXPECT_EQ(m.eRole[eIndex(m, e, 7)], Role::Calculable) << e;
    EXPECT_EQ(m.eRole[eIndex(m, e, 8)], Role::Calculable) << e;
  }
  EXPECT_EQ(m.numDofs(), 34);  // 30 DYNE and 4 warping coordinates
  const core::KinematicReport r = core::checkKinematics(m);
  EXPECT_TRUE(r.wellPosed()) << core::formatReport(r);
  EXPECT_EQ(r.xCalculable, 42);
  EXPECT_EQ(r.eFixed + r.eInput + r.eDynamic, 42);
  EXPECT_EQ(r.rank, 42);
  EXPECT_EQ(r.warpingNodes, 8);
  EXPECT_TRUE(contains(core::formatReport(r), "8 position, 8 orientation, 8 warping"));
  // Its section values are read whole.
  const auto& leaf = m.elements[m.elementByLabel.at(1)];
  ASSERT_EQ(leaf.stiffnessParams.size(), 7u);
  EXPECT_DOUBLE_EQ(leaf.stiffnessParams[6], 0.000001458333333);
  EXPECT_DOUBLE_EQ(leaf.inertia.jw, 0.000000000000054);
  EXPECT_TRUE(m.notes.empty()) << m.notes.front();
}

TEST(DatBeamW, RolesOfWarpingCoordinatesAndDeformations) {
  // Free warping coordinates are degrees of freedom after the DYNX ones, before DYNE.
  const core::Model m =
      io::readDatString(twoBeams("FIX 1\nFIX 2\nFIX 3\nDYNE 1\nDYNE 2 1 2 3 4 5 6\nDYNX 7 1\n"), "t.dat");
  ASSERT_EQ(m.numDofs(), 1 + 2 + 12);
  EXPECT_FALSE(m.dofs[0].isDeformation);
  EXPECT_EQ(m.dofs[0].index, xIndex(m, 7, 1));
  EXPECT_EQ(m.dofs[1].index, xIndex(m, 6));
  EXPECT_EQ(m.dofs[2].index, xIndex(m, 9));
  EXPECT_TRUE(m.dofs[3].isDeformation);
  // DYNE e without components: deformations 1..6; 7 and 8 are released whatever the file says.
  for (int c = 1; c <= 6; ++c) EXPECT_EQ(m.eRole[eIndex(m, 1, c)], Role::Dynamic) << c;
  EXPECT_EQ(m.eRole[eIndex(m, 1, 7)], Role::Calculable);
  EXPECT_EQ(m.eRole[eIndex(m, 2, 8)], Role::Calculable);
  EXPECT_EQ(m.coordName(xIndex(m, 6)), "x(node 6, warping)");
  // RLSE of 7 and 8 is what they are anyway; INPUTX and DYNX name warping coordinates like others.
  const core::Model r = io::readDatString(
      twoBeams("FIX 1\nFIX 2\nINPUTX 3\nDYNE 1\nRLSE 1 7 8\nDYNE 2\nDYNX 9\n", "INPUTX 3 1 0.5\n"), "t.dat");
  EXPECT_EQ(r.xRole[xIndex(r, 3)], Role::Input);
  EXPECT_EQ(r.xRole[xIndex(r, 9)], Role::Dynamic);
  EXPECT_EQ(r.numDofs(), 2 + 12);
  // DYNE or INPUTE of 7 or 8: an error that says why and what to do.
  const std::string e1 = errorOf(twoBeams("FIX 1\nFIX 2\nDYNE 1 1 2 3 4 5 6 7\n"));
  EXPECT_TRUE(contains(e1, "t.dat:8: DYNE")) << e1;
  EXPECT_TRUE(contains(e1, "e(BEAMW 1, 7 warping p) is always released")) << e1;
  EXPECT_TRUE(contains(e1, "FIX or INPUTX the warping node")) << e1;
  EXPECT_TRUE(contains(errorOf(twoBeams("FIX 1\nFIX 2\nINPUTE 2 8\n")), "cannot be INPUTE"));
  // A warping slot given a node another element uses as an orientation node.
  const std::string e2 = errorOf(kTwo + "BEAMW 3 7 8 5 10 11 12 0 0 1\nEND\nHALT\nEND\nEND\n");
  EXPECT_TRUE(contains(e2,
                       "node 5 is used as a warping node here (BEAMW 3, warping p) but as an orientation node by "
                       "BEAMW 1 (orientation q)"))
      << e2;
  EXPECT_TRUE(contains(errorOf(twoBeams("FIX 3 2\n")), "a warping node (component 1: rate of twist)"));
}

TEST(DatBeamW, BadInputNamesFileLineAndReason) {
  // Six stiffness values: the warping stiffness is missing.
  const std::string six = errorOf(
      twoBeams("FIX 1\nFIX 2\nFIX 3\nDYNE 1\nDYNE 2\n", "ESTIFF 1 1e6 2 3 4 0 0 0.5\nESTIFF 2 1e6 2 3 4 0 0\n"));
  EXPECT_TRUE(contains(six, "t.dat:14: ESTIFF")) << six;
  EXPECT_TRUE(contains(six,
                       "BEAMW 2 takes 7 stiffness parameters (EA, GIt, EIy, EIz, cy, cz, ECw), found 6: the 7th "
                       "value, ECw (warping stiffness E Cw"))
      << six;
  EXPECT_TRUE(contains(six, "is missing")) << six;
  EXPECT_TRUE(contains(errorOf(twoBeams("FIX 1\n", "ESTIFF 1 1 2 3 4 5 6 7 8\n")), "found 8"));
  // Zero length, a y vector along the chord, a missing y component: as for BEAM.
  const std::string zero = errorOf("X 1 0 0 0\nX 4 0 0 0\nBEAMW 1 1 2 3 4 5 6 0 0 1\nEND\nHALT\nEND\nEND\n");
  EXPECT_TRUE(contains(zero, "t.dat:3: BEAMW: BEAMW 1: end nodes coincide (zero length)")) << zero;
  const std::string along = errorOf("X 1 0 0 0\nX 4 1 0 0\nBEAMW 1 1 2 3 4 5 6 1 0 0\nEND\nHALT\nEND\nEND\n");
  EXPECT_TRUE(contains(along, "t.dat:3: BEAMW: BEAMW 1")) << along;
  EXPECT_TRUE(contains(errorOf("X 1 0 0 0\nX 4 1 0 0\nBEAMW 1 1 2 3 4 5 6 0 1\nEND\nHALT\n"),
                       "BEAMW: expected 10 numbers (element, node p, orientation p, warping p, node q, orientation q, "
                       "warping q, y1, y2, y3), found 9"));
  EXPECT_TRUE(contains(errorOf(twoBeams("FIX 1\n", "EM 1 1 2 3 4 0 -1\n")), "negative warping inertia -1"));
  // X of a warping node: one value, the initial rate of twist.
  EXPECT_TRUE(contains(errorOf(twoBeams("FIX 1\nX 3 0 0\n")), "expected 1 coordinate, found 2"));
  const core::Model m = io::readDatString(twoBeams("FIX 1\nFIX 2\nX 3 0.25\n", "EM 1 1 2 3 4 0 1e-9\n"), "t.dat");
  EXPECT_DOUBLE_EQ(m.x0[xIndex(m, 3)], 0.25);
  EXPECT_DOUBLE_EQ(m.elements[m.elementByLabel.at(1)].inertia.jw, 1e-9);
  EXPECT_DOUBLE_EQ(m.elements[m.elementByLabel.at(2)].inertia.jw, 0.0);
}

TEST(DatBeamW, SectionValuesOfOtherProgramsAreIgnoredWithANote) {
  // oopspa writes a 7-value ESTIFF and a 6-value EM for every BEAM and TRUSS; SPACAR Light a 6-value
  // EM on BEAM. The values after the element's own layout are ignored, with one note per keyword and
  // element type that names the file and the lines.
  const std::string kin =
      "X 1 0 0 0\nX 3 1 0 0\nX 5 1 1 0\nBEAM 1 1 2 3 4 0 0 1\nBEAM 2 3 4 5 6 0 0 1\nTRUSS 3 1 5\n"
      "FIX 1\nFIX 2\nDYNE 1\nDYNE 2\nRLSE 3\nEND\nHALT\n";
  const core::Model plain =
      io::readDatString(kin +
                            "ESTIFF 1 1e6 2 3 4 0.1 0.2\nESTIFF 2 1e6 2 3 4 0.1 0.2\nESTIFF 3 5e5\n"
                            "EM 1 1 2 3 4 0\nEM 2 1 2 3 4 0\nEM 3 0.5\nEND\nEND\n",
                        "plain.dat");
  EXPECT_TRUE(plain.notes.empty());
  const core::Model m = io::readDatString(kin +
                                              "ESTIFF 1 1e6 2 3 4 0.1 0.2 7\nESTIFF 2 1e6 2 3 4 0.1 0.2 7\n"
                                              "ESTIFF 3 5e5 1 2 3 4 5 6\nEM 1 1 2 3 4 0 9\nEM 2 1 2 3 4 0 9\n"
                                              "EM 3 0.5 1 2 3 4 5\nEND\nEND\n",
                                          "oop.dat");
  for (int e = 1; e <= 3; ++e) {
    const auto &a = m.elements[m.elementByLabel.at(e)], &b = plain.elements[plain.elementByLabel.at(e)];
    EXPECT_EQ(a.S, b.S) << e;
    EXPECT_EQ(a.stiffnessParams, b.stiffnessParams) << e;
    EXPECT_EQ(a.inertia.rhoA, b.inertia.rhoA) << e;
    EXPECT_EQ(a.inertia.jxx, b.inertia.jxx) << e;
    EXPECT_EQ(a.inertia.jw, 0.0) << e;
  }
  ASSERT_EQ(m.notes.size(), 4u);
  auto note = [&](const std::string& part) {
    for (const auto& n : m.notes)
      if (contains(n, part)) return n;
    return std::string();
  };
  const std::string beamK = note("ESTIFF on BEAM");
  EXPECT_TRUE(contains(beamK, "oop.dat:14: ESTIFF on BEAM: 7 values, the 7th (ECw) has no meaning for BEAM")) << beamK;
  EXPECT_TRUE(contains(beamK, "is ignored (lines 14, 15)")) << beamK;
  EXPECT_TRUE(contains(note("EM on BEAM"), "oop.dat:17: EM on BEAM: 6 values, the 6th (Jw) has no meaning for BEAM"))
      << note("EM on BEAM");
  EXPECT_TRUE(contains(note("ESTIFF on TRUSS"),
                       "oop.dat:16: ESTIFF on TRUSS: 7 values, the 2nd to 7th (GIt, EIy, EIz, cy, cz, ECw) have no "
                       "meaning for TRUSS"))
      << note("ESTIFF on TRUSS");
  EXPECT_TRUE(contains(note("EM on TRUSS"), "oop.dat:19: EM on TRUSS")) << note("EM on TRUSS");
  // More than BEAMW's layout is still an error.
  EXPECT_TRUE(contains(errorOf(kin + "ESTIFF 1 1 2 3 4 5 6 7 8\nEND\nEND\n"), "BEAM 1 takes 6 stiffness parameters"));
  EXPECT_TRUE(contains(errorOf(kin + "EM 3 1 2 3 4 5 6 7\nEND\nEND\n"), "expected 2 to 7 numbers"));
}

TEST(DatBeamW, ResultNamesOfWarpingCoordinates) {
  const core::Model m = io::readDatString(twoBeams("FIX 1\nFIX 2\nFIX 3\n"), "t.dat");
  const auto names = io::coordinateColumnNames(m);
  EXPECT_EQ(names[xIndex(m, 6)], "node6.w");
  EXPECT_EQ(names[xIndex(m, 4, 3)], "node4.z");
  EXPECT_EQ(names[xIndex(m, 5, 4)], "node5.lambda3");
  const auto enames = io::deformationColumnNames(m);
  EXPECT_TRUE(contains(enames[eIndex(m, 2, 8)], "BEAMW2.e8_warping")) << enames[eIndex(m, 2, 8)];
}
