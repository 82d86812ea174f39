// SPACAR files as users have them (issue 10): SPACAR95 block structure and time, restart states,
// SPACAR Light's 2013+ writing, ESIG, numbers, every SPACAR keyword known, and the generated
// language reference. Each test reads a small file written for it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/elements/PlanarBeam.hpp"
#include "core/elements/PlanarTruss.hpp"
#include "core/kinematics/KinematicCheck.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/KeywordTable.hpp"
#include "io/formats/RestartWriter.hpp"

using namespace flexmb;
using core::Dialect;

namespace {

const std::string kData = std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/";

int xIndex(const core::Model& m, int node, int comp) {
  return m.nodes.at(m.nodeByLabel.at(node)).firstCoord + comp - 1;
}
int eIndex(const core::Model& m, int element, int comp) {
  return m.elements.at(m.elementByLabel.at(element)).firstDef + comp - 1;
}

std::string errorOf(const std::string& text) {
  try {
    io::readDatStagesString(text, "t.dat");
  } catch (const io::DatError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The ESIG prestress of an element's deformations, in their order.
std::vector<double> prestressOf(const core::Model& m, int element) {
  const core::ElementEntry& el = m.elements.at(m.elementByLabel.at(element));
  std::vector<double> row;
  for (int j = 0; j < el.type->numDeformations(); ++j) row.push_back(m.sigma0[el.firstDef + j]);
  return row;
}

// How many of the notes contain part.
int notesWith(const core::Model& m, const std::string& part) {
  int n = 0;
  for (const auto& note : m.notes) n += contains(note, part) ? 1 : 0;
  return n;
}

const core::Rheonomic& inputOf(const core::Model& m, int node, int comp) {
  const int xi = xIndex(m, node, comp);
  for (const auto& r : m.inputX)
    if (r.index == xi) return r;
  throw std::runtime_error("no input");
}

}  // namespace

// Item 1: the manual's style, one block with everything and one END; a later block restates a
// role (no error), changes the input rate and continues from where the first block ended.
TEST(Spacar95Blocks, OneBlockHoldsEverythingAndALaterBlockContinues) {
  const auto stages = io::readDatStages(kData + "manual_style_s95.dat");
  ASSERT_EQ(stages.size(), 2u);
  const core::Model& m1 = stages[0].model;
  EXPECT_EQ(m1.dialect, Dialect::Spacar95);
  EXPECT_TRUE(stages[0].runs);
  EXPECT_DOUBLE_EQ(m1.settings.t0, 0.0);
  EXPECT_DOUBLE_EQ(m1.settings.tEnd, 0.5);
  EXPECT_EQ(m1.settings.outputIntervals, 20);
  EXPECT_EQ(m1.numDofs(), 3);
  EXPECT_EQ(m1.lumpedMasses.size(), 2u);  // MASS 3 on x and y
  EXPECT_TRUE(m1.elements.at(1).hasStiffness);
  EXPECT_DOUBLE_EQ(m1.elements.at(0).inertia.rhoA, 1.0);
  const core::Rheonomic& r1 = inputOf(m1, 12, 1);
  EXPECT_DOUBLE_EQ(r1.v, 2 * M_PI);
  EXPECT_DOUBLE_EQ(r1.tRef, 0.0);

  const core::Model& m2 = stages[1].model;
  EXPECT_TRUE(stages[1].runs);
  EXPECT_DOUBLE_EQ(m2.settings.t0, 0.5);  // continues at the end of the first block
  EXPECT_DOUBLE_EQ(m2.settings.tEnd, 0.75);
  EXPECT_EQ(m2.settings.outputIntervals, 20);
  EXPECT_EQ(m2.numDofs(), m1.numDofs());
  const core::Rheonomic& r2 = inputOf(m2, 12, 1);
  EXPECT_DOUBLE_EQ(r2.tRef, 0.5);
  EXPECT_NEAR(r2.x0, 2 * M_PI * 0.5, 1e-15);  // the value where block 1 ended
  EXPECT_DOUBLE_EQ(r2.v, M_PI);               // the new rate from t = 0.5 on
  double x, v, a;
  r2.evaluate(0.75, x, v, a);
  EXPECT_NEAR(x, M_PI + M_PI * 0.25, 1e-14);

  // The model of the whole file (readDatFile) is the last stage.
  EXPECT_DOUBLE_EQ(io::readDatFile(kData + "manual_style_s95.dat").settings.t0, 0.5);
}

TEST(Spacar95Blocks, LaterBlocksKeepTopologyAndState) {
  const std::string base = "PLTRUSS 1 1 2\nXY 2 1 0\nFIX 1\nDYNX 2 1 2\nMASS 2 1\nTIMESTEP 10 1\nEND\n";
  EXPECT_TRUE(contains(errorOf(base + "PLTRUSS 2 2 3\nEND\n"), "belongs to the first block"));
  EXPECT_TRUE(contains(errorOf(base + "XY 2 2 0\nEND\n"), "belongs to the first block"));
  EXPECT_TRUE(contains(errorOf(base + "ED 1 1 0.5\nEND\n"), "the state continues"));
  EXPECT_TRUE(contains(errorOf(base + "FIX 2 1\nEND\n"), "it was made dynamic"));  // a changed role
  // A block without TIMESTEP only changes data (no analysis of its own).
  const auto stages = io::readDatStagesString(base + "DYNX 2 1 2\nFORCE 2 0 -1\nEND\nTIMESTEP 5 2\nEND\nEOF\n");
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_TRUE(stages[0].runs);
  EXPECT_FALSE(stages[1].runs);
  EXPECT_TRUE(stages[2].runs);
  EXPECT_DOUBLE_EQ(stages[2].model.settings.t0, 1.0);
  EXPECT_DOUBLE_EQ(stages[2].model.settings.tEnd, 3.0);
  EXPECT_DOUBLE_EQ(stages[2].model.f0[xIndex(stages[2].model, 2, 2)], -1.0);
}

// Item 2: TIMESTEP n Tp from TIME; inputs move as x + v (t - TIME) + a (t - TIME)^2 / 2.
TEST(Spacar95Time, TimestepIsAPeriodFromTime) {
  const std::string text =
      "PLTRUSS 1 1 2\nXY 2 1 0.5\nFIX 1\nINPUTX 2 1\nDYNX 2 2\nRLSE 1 1\nMASS 2 1\nXD 2 1 0.2\nXDD 2 1 -0.4\n"
      "TIME 2.0\nTIMESTEP 15 1.5\nEND\nEOF\n";
  const auto stages = io::readDatStagesString(text);
  ASSERT_EQ(stages.size(), 1u);
  const core::Model& m = stages[0].model;
  EXPECT_DOUBLE_EQ(m.settings.t0, 2.0);
  EXPECT_DOUBLE_EQ(m.settings.tEnd, 3.5);
  EXPECT_EQ(m.settings.outputIntervals, 15);
  double x, v, a;
  inputOf(m, 2, 1).evaluate(3.0, x, v, a);
  EXPECT_NEAR(x, 1.0 + 0.2 * 1.0 - 0.4 * 0.5, 1e-15);
  EXPECT_NEAR(v, 0.2 - 0.4, 1e-15);
  EXPECT_DOUBLE_EQ(a, -0.4);
  inputOf(m, 2, 1).evaluate(2.0, x, v, a);
  EXPECT_DOUBLE_EQ(x, 1.0);  // the value X at TIME
  // SPACAR 2013+: TIMESTEP T n is the end time, INPUTX x v a from t = 0.
  const auto m13 = io::readDatString(
      "PLTRUSS 1 1 2\nX 2 1 0.5\nFIX 1\nINPUTX 2 1\nDYNX 2 2\nEND\nHALT\nXM 2 1\nINPUTX 2 1 1.0 0.2\n"
      "TIMESTEP 1.5 15\nEND\nEND\n");
  EXPECT_DOUBLE_EQ(m13.settings.t0, 0.0);
  EXPECT_DOUBLE_EQ(m13.settings.tEnd, 1.5);
  inputOf(m13, 2, 1).evaluate(1.0, x, v, a);
  EXPECT_NEAR(x, 1.2, 1e-15);
}

// Item 1, SPACAR 2013+: END HALT ... END END keeps its meaning; the dynamic block is the last stage.
TEST(Spacar2013Blocks, EndHaltEndEndUnchanged) {
  const auto stages = io::readDatStages(kData + "two_link_2013.dat");
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_FALSE(stages[0].runs);
  EXPECT_EQ(stages[1].model.dialect, Dialect::Spacar2013);
  EXPECT_TRUE(contains(errorOf("PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nEND\nHALT\nFIX 2\nEND\nEND\n"),
                       "belongs to the kinematic block"));
  EXPECT_TRUE(contains(errorOf("PLTRUSS 1 1 2\nX 2 1 0\nESTIFF 1 1\nEND\nHALT\nEND\nEND\n"),
                       "belongs to a dynamic/static block"));
}

// Item 4: a file written the way SPACAR Light writes it (tabs, '#' comments, OUTLEVEL at the top,
// %20.15f numbers, ITERSTEP with six fields, DELXF and XF, END HALT, END END, VISUALIZATION).
TEST(Spacar2013Light, SpacarLightStyleFile) {
  const core::Model m = io::readDatFile(kData + "spacarlight_style_2013.dat");
  EXPECT_EQ(m.dialect, Dialect::Spacar2013);
  EXPECT_EQ(m.settings.maxIterations, 10);
  EXPECT_EQ(m.settings.loadSteps, 9);
  EXPECT_DOUBLE_EQ(m.settings.kinematicTol, 5e-7);
  EXPECT_EQ(m.settings.initialLoadSteps, 9);
  EXPECT_EQ(m.settings.outputLevel, 0);
  EXPECT_EQ(m.settings.transferFunctionLevel, 1);
  EXPECT_DOUBLE_EQ(m.delf[xIndex(m, 5, 2)], -1.0);
  EXPECT_DOUBLE_EQ(m.f0[xIndex(m, 5, 1)], 0.5);
  EXPECT_EQ(m.numDofs(), 6);
}

// SPACAR Light writes its VISUALIZATION section after END END, where SPACAR reads no more input:
// the cross-sections and colours there reach the pictures (they were dropped), and a malformed
// line there is a note, as in a section after a single END.
TEST(Spacar2013Light, VisualizationAfterEndEndIsRead) {
  const core::Model m = io::readDatFile(kData + "spacarlight_style_2013.dat");
  ASSERT_EQ(m.appearance.count(1), 1u);
  const core::ElementAppearance& look = m.appearance.at(1);
  EXPECT_EQ(look.section, core::ElementAppearance::Section::Rectangle);
  EXPECT_DOUBLE_EQ(look.width, 0.01);
  EXPECT_DOUBLE_EQ(look.thickness, 0.001);
  EXPECT_TRUE(look.hasColor);
  EXPECT_DOUBLE_EQ(look.color[0], 0.5);
  const std::string kin = "PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nDYNE 1 1\nEND\nHALT\nESTIFF 1 1\n";
  // The CROSSTYPE line is line 14 after END END and two blank lines, line 11 after one END.
  for (const auto& [ending, where] : {std::pair<std::string, std::string>{"END\nEND\n\n\n", "v.dat:14:"},
                                      std::pair<std::string, std::string>{"END\n", "v.dat:11:"}}) {
    const core::Model v = io::readDatString(kin + ending + "VISUALIZATION\nBEAMPROPS 1\nCROSSTYPE HEXAGON\n", "v.dat");
    bool noted = false;
    for (const auto& n : v.notes)
      noted = noted || n.find(where + " VISUALIZATION: CROSSTYPE must be") != std::string::npos;
    EXPECT_TRUE(noted) << ending;
  }
}

// SPACAR Light fixes the warping node ((i-1)*3+3) of every fixed node also when no BEAMW uses it,
// oopspa writes `FIX n 1` for it and an X line for every keypoint's position node, used or not, and
// SPACAR runs those files: statements that fix or place a node no element uses change nothing, so
// they are notes (issue 24: one rule). An input, a degree of freedom, a load or a mass there would
// be lost: errors.
TEST(Spacar2013Light, FixOrCoordinatesOfAnUnusedNodeAreNotes) {
  const std::string text = "PLTRUSS 1 1 2\nX 2 1 0\nX 7 3 4\nFIX 1\nFIX 3  #warping\nFIX 6 1\nDYNE 1 1\nEND\nHALT\n";
  const core::Model m = io::readDatString(text, "t.dat");
  const core::Model plain = io::readDatString("PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nDYNE 1 1\nEND\nHALT\n", "t.dat");
  EXPECT_EQ(m.numDofs(), plain.numDofs());
  EXPECT_EQ(m.xRole, plain.xRole);
  EXPECT_EQ(m.x0, plain.x0);
  EXPECT_EQ(m.nodeByLabel.count(3), 0u);
  ASSERT_EQ(m.notes.size(), 3u);
  EXPECT_TRUE(contains(m.notes[0], "coordinates of node 7 (line 3): node 7 is not used by any element; ignored"))
      << m.notes[0];
  EXPECT_TRUE(contains(m.notes[1], "FIX 3 (line 5): node 3 is not used by any element; ignored")) << m.notes[1];
  EXPECT_TRUE(contains(m.notes[2], "FIX 6 1 (line 6)")) << m.notes[2];
  for (const std::string& lost : {std::string("INPUTX 3 1"), std::string("DYNX 3 1")})
    EXPECT_TRUE(contains(errorOf("PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\n" + lost + "\nDYNE 1 1\nEND\nHALT\n"),
                         "node 3 is not used by any element"))
        << lost;
  const std::string kin = "PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nDYNE 1 1\nEND\nHALT\n";
  EXPECT_TRUE(contains(errorOf(kin + "DELXF 55 0 -1\nEND\nEND\n"),
                       "t.dat:7: DELXF: node 55 is not used by any element: the load would act on nothing"))
      << errorOf(kin + "DELXF 55 0 -1\nEND\nEND\n");
  EXPECT_TRUE(contains(errorOf(kin + "XM 55 1\nEND\nEND\n"), "the mass would belong to nothing"));
}

// A position node the elements use without a coordinate statement sits at the origin, as in SPACAR
// ([C S95]: nodes default to 0 0 0): legal, but a warning naming the node and the element.
TEST(Spacar2013Light, APositionNodeWithoutCoordinatesIsAWarning) {
  const core::Model m = io::readDatString(
      "PLTRUSS 1 1 2\nPLTRUSS 2 2 3\nX 2 1 0\nX 1 0 0\nFIX 1\nDYNE 1 1\nDYNE 2 1\n"
      "END\nHALT\n",
      "t.dat");
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_TRUE(contains(m.warnings[0], "node 3 (node q of PLTRUSS 2, line 2) has no X line: it is placed at the origin"))
      << m.warnings[0];
  // Orientation nodes default to angle 0 (Euler parameters 1 0 0 0) as every SPACAR file expects.
  EXPECT_TRUE(io::readDatString("PLBEAM 1 1 2 3 4\nX 1 0 0\nX 3 1 0\nFIX 1\nFIX 2\nDYNE 1 1 2 3\nEND\nHALT\n", "t.dat")
                  .warnings.empty());
}

// The keyword reference a new user reads (issue 24): planar notes list planar elements only, the EM
// signature matches its description, ESTIFF says what cy and cz are.
TEST(KeywordTable, ElementListsAndSignaturesAgreeWithTheirDescriptions) {
  std::ostringstream o;
  io::printKeywords(o);
  const std::string text = o.str();
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.find("planar elements:") != std::string::npos) {
      const std::string list = line.substr(line.find("planar elements:"));
      for (const char* spatial : {" BEAM", " TRUSS", " HINGE", " RBEAM"})
        EXPECT_EQ(list.find(spatial), std::string::npos) << line;
      EXPECT_NE(list.find("PLBEAM"), std::string::npos) << line;
    }
    if (line.find("spatial elements:") != std::string::npos) {
      EXPECT_EQ(line.find("PLBEAM", line.find("spatial elements:")), std::string::npos) << line;
    }
    if (line.rfind("  EM ", 0) == 0) {
      EXPECT_NE(line.find("EM e rhoA [rhoI|Jxx [Jyy [Jzz [Jyz [Jw]]]]]"), std::string::npos) << line;
      EXPECT_NE(line.find("rhoA Jxx Jyy Jzz Jyz"), std::string::npos) << line;
    }
    if (line.rfind("  ESTIFF ", 0) == 0) {
      EXPECT_NE(line.find("cy cz: shear flexibility"), std::string::npos) << line;
    }
  }
  EXPECT_NE(text.find("planar elements:"), std::string::npos);
}

TEST(Spacar2013Light, IterstepFieldsAndWholeNumbersWithDecimals) {
  const std::string kin = "PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nDYNE 1 1\nEND\nHALT\n";
  const core::Model m = io::readDatString(kin + "ESTIFF 1 1\nITERSTEP 1000.000000 9 5e-7 1 3 0\nEND\nEND\n");
  EXPECT_EQ(m.settings.maxIterations, 1000);
  EXPECT_EQ(m.settings.initialLoadSteps, 0);  // SPACAR Light writes 0 without initial loads
  EXPECT_EQ(io::readDatString(kin + "ITERSTEP 10 2\nEND\nEND\n").settings.initialLoadSteps, 0);
  EXPECT_EQ(io::readDatString(kin + "TIMESTEP 1 1.0E1\nEND\nEND\n").settings.outputIntervals, 10);
  EXPECT_TRUE(
      contains(errorOf(kin + "ITERSTEP 2.5 9\nEND\nEND\n"), "expected an integer for maximum iterations, found '2.5'"));
  EXPECT_TRUE(contains(errorOf(kin + "ITERSTEP 10 9 5e-7 1 3 9 4\nEND\nEND\n"), "expected 2 to 6"));
  EXPECT_TRUE(contains(errorOf(kin + "ITERSTEP 10 9 5e-7 1 3 -1\nEND\nEND\n"), "non-negative integer"));
  EXPECT_TRUE(contains(errorOf(kin + "OUTLEVEL 1 0.5\nEND\nEND\n"), "expected an integer for transfer functions"));
}

// ESIG lists a value per deformation in the element's deformation order, as ESTIFF and EM list
// theirs (SPACAR's reading: its .sbd of oopspa's `ESIG 1 1.000000` on a HINGE holds [1 0 0], see
// io/README.md); values left off at the end are 0 and a later line replaces the row. flexmb's former
// ESIG e i s survives where nothing else fits (ESIG e 1 s, one deformation: a note); two values on
// an element with more deformations, the first a deformation number, are read SPACAR's way with a
// warning. The ESIG line is line 9.
TEST(Spacar2013Light, EsigListsAValuePerDeformation) {
  const std::string kin = "PLTRUSS 1 1 2\nPLBEAM 2 2 3 4 5\nX 1 0 0\nX 2 1 0\nX 4 2 0\nFIX 1\nEND\nHALT\n";
  auto read = [&](const std::string& esig) { return io::readDatString(kin + esig + "END\nEND\n", "t.dat"); };
  auto error = [&](const std::string& esig) { return errorOf(kin + esig + "END\nEND\n"); };
  using Row = std::vector<double>;
  {
    const core::Model m = read("ESIG 1 -5.0\n");
    EXPECT_EQ(prestressOf(m, 1), Row{-5.0});
    EXPECT_EQ(prestressOf(m, 2), (Row{0, 0, 0}));
    EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
    EXPECT_TRUE(m.notes.empty()) << m.notes.front();
  }
  EXPECT_EQ(prestressOf(read("ESIG 2 0 0 7.5\n"), 2), (Row{0, 0, 7.5}));
  EXPECT_EQ(prestressOf(read("ESIG 2 7.5\n"), 2), (Row{7.5, 0, 0}));  // was an error
  {
    const core::Model m = read("ESIG 2 1.5 7.5\n");  // was an error; 1.5 is no deformation number
    EXPECT_EQ(prestressOf(m, 2), (Row{1.5, 7.5, 0}));
    EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
  }
  {
    const core::Model m = read("ESIG 2 3 7.5\n");  // flexmb's former reading: 7.5 on deformation 3
    EXPECT_EQ(prestressOf(m, 2), (Row{3, 7.5, 0}));
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_TRUE(contains(m.warnings[0], "line 9: ESIG 2 3 7.5 is read as SPACAR reads it")) << m.warnings[0];
    EXPECT_TRUE(contains(m.warnings[0], "(elongation 3, bending p 7.5)")) << m.warnings[0];
    EXPECT_TRUE(contains(m.warnings[0], "write ESIG 2 0 0 7.5")) << m.warnings[0];
  }
  {
    const std::string e = error("ESIG 2 1 2 3 4\n");
    EXPECT_TRUE(contains(e, "t.dat:9: ESIG: PLBEAM 2 has 3 deformations")) << e;
    EXPECT_TRUE(contains(e, "ESIG gives 4 values")) << e;
  }
  {
    const core::Model m = read("ESIG 1 1 -5\n");  // flexmb's former ESIG e 1 s, one deformation
    EXPECT_EQ(prestressOf(m, 1), Row{-5.0});
    EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
    ASSERT_EQ(m.notes.size(), 1u);
    EXPECT_TRUE(contains(m.notes[0], "ESIG 1 1 -5 (line 9): flexmb's former form ESIG e 1 s")) << m.notes[0];
    EXPECT_TRUE(contains(m.notes[0], "SPACAR's form is ESIG 1 -5")) << m.notes[0];
  }
  {
    const std::string e = error("ESIG 1 2 -5\n");
    EXPECT_TRUE(contains(e, "t.dat:9: ESIG: PLTRUSS 1 has 1 deformation (1 elongation), ESIG gives 2 values")) << e;
    EXPECT_TRUE(contains(e, "write ESIG 1 s")) << e;
  }
  EXPECT_EQ(prestressOf(read("ESIG 2 0 0 7.5\nESIG 2 1\n"), 2), (Row{1, 0, 0}));  // the later line replaces
  EXPECT_TRUE(contains(error("ESIG 2 1 x\n"), "expected a number for stress, found 'x'")) << error("ESIG 2 1 x\n");
  EXPECT_TRUE(contains(error("ESIG 9 1\n"), "element 9 is not defined"));
}

// oopspa's writer prints ESIG's value after the element number, and SPACAR stored `ESIG 1 1.000000`
// on a spatial HINGE as the pre-torque of its rotation (oopspa bcad60f: the .sbd's ESIG(1,:) is
// [1 0 0 ...]). The line below is oopspa's, tabs and all.
TEST(Spacar2013Light, OopspaEsigOnAHingeIsTheRotationsPrestress) {
  const core::Model m =
      io::readDatString("HINGE 1 1 2 0 0 1\nFIX 1\nRLSE 1 1\nEND\nHALT\n ESIG \t   1 \t 1.000000\nEND\nEND\n", "t.dat");
  EXPECT_EQ(prestressOf(m, 1), (std::vector<double>{1, 0, 0}));
  EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
  EXPECT_EQ(notesWith(m, "ESIG"), 0);
}

// oopspa writes an EM, ESTIFF (and EDAMP) line with the element number alone for every element
// without the property, and SPACAR runs those files: such a line sets nothing, as if it were absent
// (no stiffness, no inertia: a DYNE deformation of the element is listed among check's mechanism
// degrees of freedom), with one note per keyword naming the elements and lines. ESIG with the
// element alone likewise. The element must exist; a full line for the same element keeps its values.
TEST(Spacar2013Light, ValueLinesWithTheElementAloneSetNothing) {
  // A HINGE and a BEAM; the dynamic block starts at line 11.
  const std::string kin =
      "HINGE 1 1 2 0 0 1\nBEAM 2 3 2 4 5 0 1 0\nX 3 0 0 0\nX 4 1 0 0\nFIX 1\nFIX 3\nDYNE 1 1\nDYNE 2\n"
      "END\nHALT\n";
  {
    const core::Model m =
        io::readDatString(kin + "ESTIFF 1\nESTIFF 2\nEM 1\nEM 2\nEDAMP 1\n ESIG \t 2 \t\nEND\nEND\n", "t.dat");
    for (int e : {1, 2}) {
      const core::ElementEntry& el = m.elements.at(m.elementByLabel.at(e));
      EXPECT_FALSE(el.hasStiffness) << e;
      EXPECT_FALSE(el.hasDamping) << e;
      EXPECT_FALSE(el.inertia.any()) << e;
      EXPECT_TRUE(el.stiffnessParams.empty()) << e;
      EXPECT_TRUE(el.inertiaParams.empty()) << e;
    }
    EXPECT_EQ(m.sigma0.norm(), 0.0);
    EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
    ASSERT_EQ(m.notes.size(), 4u);
    EXPECT_EQ(notesWith(m,
                        "t.dat:11: ESTIFF without values for elements 1, 2 (lines 11, 12): nothing set, as if "
                        "the lines were absent (oopspa writes such lines"),
              1);
    EXPECT_EQ(notesWith(m, "t.dat:13: EM without values for elements 1, 2 (lines 13, 14): nothing set"), 1);
    EXPECT_EQ(notesWith(m, "t.dat:15: EDAMP without values for element 1: nothing set, as if the line were absent"), 1);
    EXPECT_EQ(notesWith(m, "t.dat:16: ESIG without values for element 2: nothing set"), 1);
  }
  {
    // Full lines before (and after) empty ones keep their values.
    const core::Model m = io::readDatString(kin +
                                                "ESTIFF 2 100 2 3 4 0 0\nEM 2 1.5 0.01 0.02 0.03 0\nESTIFF 2\nEM 2\n"
                                                "ESIG 1 0.5\nESIG 1\nESTIFF 1\nESTIFF 1 7\nEND\nEND\n",
                                            "t.dat");
    const core::ElementEntry& beam = m.elements.at(m.elementByLabel.at(2));
    EXPECT_TRUE(beam.hasStiffness);
    EXPECT_EQ(beam.stiffnessParams, (std::vector<double>{100, 2, 3, 4, 0, 0}));
    EXPECT_DOUBLE_EQ(beam.inertia.rhoA, 1.5);
    EXPECT_EQ(prestressOf(m, 1), (std::vector<double>{0.5, 0, 0}));
    const core::ElementEntry& hinge = m.elements.at(m.elementByLabel.at(1));
    EXPECT_TRUE(hinge.hasStiffness);
    EXPECT_EQ(hinge.stiffnessParams, std::vector<double>{7});
    EXPECT_EQ(notesWith(m, "t.dat:13: ESTIFF without values for elements 2, 1 (lines 13, 17)"), 1);
  }
  // An element that does not exist stays an error, with its line.
  {
    const std::string e = errorOf(kin + "EM 9\nEND\nEND\n");
    EXPECT_TRUE(contains(e, "t.dat:11: EM: element 9 is not defined")) << e;
  }
  EXPECT_TRUE(contains(errorOf(kin + "ESTIFF 2\nESIG 9\nEND\nEND\n"), "t.dat:12: ESIG: element 9 is not defined"));
  // Planar: an empty ESTIFF on a DYNE truss is no short line (nothing is given, nothing refused).
  const core::Model planar =
      io::readDatString("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nDYNE 1 1\nEND\nHALT\nESTIFF 1\nEND\nEND\n", "t.dat");
  EXPECT_FALSE(planar.elements.at(0).hasStiffness);
  EXPECT_EQ(notesWith(planar, "t.dat:8: ESTIFF without values for element 1: nothing set"), 1);
  // Not a bare element number: the layout's own error. SPACAR95's EMASS and EDAMPP stay strict.
  EXPECT_TRUE(contains(errorOf(kin + "EM 1.5\nEND\nEND\n"), "EM: expected 2 to 7 numbers"));
  EXPECT_TRUE(
      contains(errorOf("PLTRUSS 1 1 2\nXY 1 0 0\nXY 2 1 0\nFIX 1\nEMASS 1\nEND\n"), "EMASS: expected 2 numbers"));
}

// A restart echo writes ESIG as a value per deformation, every deformation of the element, so
// reading it back gives the same prestress without the two-value warning.
TEST(Spacar2013Light, RestartEchoWritesEsigPerDeformation) {
  const core::Model m = io::readDatString(
      "PLTRUSS 1 1 2\nPLBEAM 2 2 3 4 5\nX 1 0 0\nX 2 1 0\nX 4 2 0\nFIX 1\nEND\nHALT\n"
      "ESIG 1 -5\nESIG 2 0 0 7.5\nTIMESTEP 1 10\nITERSTEP 20 1\nEND\nEND\n",
      "t.dat");
  core::StateOutputs state;
  state.x = m.x0;
  state.xd = Eigen::VectorXd::Zero(m.nx);
  state.e = Eigen::VectorXd::Zero(m.ne);
  state.ed = Eigen::VectorXd::Zero(m.ne);
  const std::string text = io::restartText(m, 0.0, state);
  EXPECT_TRUE(contains(text, "\nESIG 1 -5\n")) << text;
  EXPECT_TRUE(contains(text, "\nESIG 2 0 0 7.5\n")) << text;
  const core::Model back = io::readDatString(text, "echo.dat");
  EXPECT_EQ(back.sigma0, m.sigma0);
  EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
  EXPECT_EQ(notesWith(back, "ESIG"), 0);
}

// A spatial echo (issue 52 item 3): X where the state is, XREF the original coordinates, so that the
// elements read back have the run's reference lengths and triads and the state's deformations;
// orientation inertia, moments and gravity come back, L2MIN1 is not written (the reader adds it).
TEST(Spacar2013Light, SpatialRestartEchoKeepsTheElementReferences) {
  const core::Model m = io::readDatString(
      "BEAM 1 1 2 3 4 0 1 1\nBEAM 2 3 4 5 6 0 1 1\nX 1 0 0 0\nX 3 0.5 0 0\nX 5 1 0.1 0\nFIX 1\nFIX 2\n"
      "DYNE 1\nDYNE 2\nEND\nHALT\nEM 1 2 0.01 0.02 0.03\nEM 2 2 0.01 0.02 0.03\nESTIFF 1 1e6 1e3 1e3 1e3\n"
      "ESTIFF 2 1e6 1e3 1e3 1e3\nXM 6 0.1 0 0 0.2 0 0.3\nXF 6 0 0 1.5\nGRAVITY 0 0 -9.81\n"
      "TIMESTEP 1 10\nEND\nEND\n",
      "t.dat");
  core::StateOutputs state;
  state.x = m.x0;
  const double c = std::cos(0.05), s = std::sin(0.05);  // the tip and the middle moved and turned
  for (int node : {3, 5}) {
    const auto& n = m.nodes[m.nodeByLabel.at(node)];
    state.x[n.firstCoord + 2] += 0.01 * node;
    const auto& o = m.nodes[m.nodeByLabel.at(node + 1)];
    state.x[o.firstCoord] = c, state.x[o.firstCoord + 1] = s * 0.6, state.x[o.firstCoord + 3] = s * 0.8;
  }
  state.xd = Eigen::VectorXd::Zero(m.nx);
  state.e = Eigen::VectorXd::Zero(m.ne);
  for (const auto& el : m.elements) {
    core::ElemVec xe;
    el.gather(state.x, xe);
    core::DefVec e(el.type->numDeformations());
    el.impl->deformations(xe, e);
    state.e.segment(el.firstDef, e.size()) = e;
  }
  state.ed = Eigen::VectorXd::Constant(m.ne, 0.25);
  const std::string text = io::restartText(m, 0.5, state);
  EXPECT_TRUE(contains(text, "\nBEAM 1 1 2 3 4 0 1 1\n")) << text;
  EXPECT_TRUE(contains(text, "\nXREF 5 1 0.1 0\n")) << text;
  EXPECT_FALSE(contains(text, "L2MIN1")) << text;
  EXPECT_FALSE(contains(text, "LENGTH0")) << text;
  const core::Model back = io::readDatString(text, "echo.dat");
  ASSERT_EQ(back.nx, m.nx);
  ASSERT_EQ(back.ne, m.ne);
  EXPECT_EQ(back.x0, state.x);
  EXPECT_EQ(back.xRef, m.x0);
  for (size_t i = 0; i < m.elements.size(); ++i) {
    const auto& a = m.elements[i];
    const auto& b = back.elements[i];
    ASSERT_EQ(a.type, b.type);
    EXPECT_EQ(a.impl->referenceLength(), b.impl->referenceLength());
    Eigen::Matrix3d fa, fb;
    for (int end : {0, 1})
      if (a.impl->elementFrame(end, fa)) {
        ASSERT_TRUE(b.impl->elementFrame(end, fb));
        EXPECT_EQ(fa, fb) << "element " << a.label << " end " << end;
      }
    core::ElemVec xe;
    b.gather(back.x0, xe);
    core::DefVec e(b.type->numDeformations());
    b.impl->deformations(xe, e);
    for (int d = 0; d < e.size(); ++d) EXPECT_NEAR(e[d], state.e[b.firstDef + d], 1e-15);
    EXPECT_EQ(a.inertia.jxx, b.inertia.jxx);
    EXPECT_EQ(a.inertia.jzz, b.inertia.jzz);
  }
  for (int di = 0; di < m.ne; ++di)
    if (m.eRole[di] == core::Role::Dynamic) {
      EXPECT_EQ(back.e0[di], state.e[di]);
      EXPECT_EQ(back.ed0[di], 0.25);
    }
  ASSERT_EQ(back.moments.size(), 1u);
  EXPECT_EQ(back.moments[0].value, m.moments[0].value);
  EXPECT_EQ(back.gravity[2], -9.81);
  EXPECT_EQ(back.settings.t0, 0.5);
}

// oopspa's public .dat files that flexmb refused (issue 34): SPACAR Huge's own output for
// bcad60f_slidercrank.dat is in oopspa's history with it. io/tests/data/oopspa/README.md says where
// each file comes from. All four read now (ESIG after the element, element-only EM/ESTIFF lines).
TEST(Oopspa, PublicFilesRead) {
  const std::string dir = kData + "oopspa/";
  // Slider-cranks that run: a released hinge 1 (the crank) closed by FIX 7 on the slider. 0aa0916:
  // 29 coordinates, 7 fixed: 22 calculable = 15 fixed deformations (5 L2MIN1, the tilts of both
  // hinges, BEAM 4) + 7 DYNE (BEAM 2's six, hinge 3). 9f0b9ba: FIX 7 2 3 (21 calculable) and BEAM 2's
  // 5th deformation released: 15 + 6 DYNE. A hand count of the SPACAR files, not a SPACAR run.
  for (const auto& [file, dofs] : {std::pair<std::string, int>{"0aa0916_slidercrank.dat", 7},
                                   std::pair<std::string, int>{"9f0b9ba_slidercrank.dat", 6}}) {
    SCOPED_TRACE(file);
    const core::Model m = io::readDatFile(dir + file);
    EXPECT_EQ(prestressOf(m, 1), (std::vector<double>{1, 0, 0}));  // ESIG 1 1.000000 on HINGE 1
    EXPECT_EQ(notesWith(m, "ESIG"), 0);
    EXPECT_EQ(m.numDofs(), dofs);
    const core::KinematicReport r = core::checkKinematics(m);
    EXPECT_EQ(r.xCalculable, 15 + dofs);
    EXPECT_EQ(r.eFixed + r.eInput + r.eDynamic, 15 + dofs);
    EXPECT_TRUE(r.wellPosed()) << core::formatReport(r);
  }
  // bcad60f: they read, but are under-constrained (oopspa's early keypoint numbering: BEAM 2's node p
  // is tied to nothing). slidercrank.log, SPACAR's own: "Nr of unknown nodal coordinates NXC-NXO
  // ( 27)", "Nr of equations NEM ( 23)", "Under-constraint system configuration": the same counts.
  {
    const core::Model m = io::readDatFile(dir + "bcad60f_slidercrank.dat");
    EXPECT_EQ(prestressOf(m, 1), (std::vector<double>{1, 0, 0}));
    const core::KinematicReport r = core::checkKinematics(m);
    EXPECT_EQ(r.xCalculable, 27);
    EXPECT_EQ(r.eFixed + r.eInput + r.eDynamic, 23);
    EXPECT_FALSE(r.wellPosed());
    EXPECT_FALSE(r.underdetermined.empty()) << core::formatReport(r);
  }
  {
    const core::Model m = io::readDatFile(dir + "bcad60f_default.dat");
    EXPECT_EQ(notesWith(m, "bcad60f_default.dat:48: ESTIFF without values for elements 1, 3, 4 (lines 48, 50, 51)"), 1);
    EXPECT_EQ(notesWith(m, "bcad60f_default.dat:56: EM without values for elements 1, 3, 4 (lines 56, 58, 59)"), 1);
    for (int e : {1, 3, 4}) {
      const core::ElementEntry& el = m.elements.at(m.elementByLabel.at(e));
      EXPECT_FALSE(el.hasStiffness) << e;
      EXPECT_FALSE(el.inertia.any()) << e;
    }
    EXPECT_TRUE(m.elements.at(m.elementByLabel.at(2)).hasStiffness);
    const core::KinematicReport r = core::checkKinematics(m);
    EXPECT_EQ(r.xCalculable, 23);
    EXPECT_EQ(r.eFixed + r.eInput + r.eDynamic, 20);
    EXPECT_FALSE(r.wellPosed());
    EXPECT_FALSE(r.underdetermined.empty()) << core::formatReport(r);
  }
}

// Item 7: a decimal comma is an error naming the token and the likely mistake.
TEST(DatNumbers, DecimalCommaIsAnError) {
  const std::string kin = "PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nDYNX 2 1 2\nEND\nHALT\nXM 2 1\n";
  const std::string e1 = errorOf(kin + "GRAVITY 0 -9,81\nEND\nEND\n");
  EXPECT_TRUE(contains(e1, "t.dat:8: GRAVITY")) << e1;
  EXPECT_TRUE(contains(e1, "'-9,81'")) << e1;
  EXPECT_TRUE(contains(e1, "decimal comma? write -9.81")) << e1;
  const std::string e2 = errorOf("PLTRUSS 1 1 2\nX 2 1,5 0\nEND\n");
  EXPECT_TRUE(contains(e2, "write 1.5")) << e2;
  const std::string e3 = errorOf("PLTRUSS 1 1,2\nEND\n");  // never two silently split fields
  EXPECT_TRUE(contains(e3, "'1,2' holds a comma")) << e3;
}

// Item 6: every SPACAR keyword is known: supported, or "SPACAR keyword, not supported by flexmb yet".
TEST(DatKeywords, EverySpacarKeywordIsKnown) {
  const char* unsupported[] = {"BEAM",    "BEAMNL", "BEAMW",     "RBEAM",  "TRUSS", "HINGE",  "BEARING", "SURFACE",
                               "PINBODY", "TUBE",   "SCREW",     "LAMBDA", "XYZ",   "L2MIN1", "PLBELT",  "PLBEAR",
                               "PLWHEEL", "PLTUBE", "PLPINBODY", "NOMS",   "NOMF",  "REFES",  "REFEF",   "INPUTF",
                               "INX",     "OUTF",   "OUTX",      "OUTXP",  "LINE",  "ENHC"};
  for (const char* k : unsupported) {
    const auto infos = io::findKeywords(k);
    ASSERT_FALSE(infos.empty()) << k;
    if (infos.front()->action != io::Action::Unsupported) continue;  // supported by now (spatial work)
    const std::string err = errorOf(std::string(k) + " 1 1 2\nEND\n");
    EXPECT_TRUE(contains(err, "SPACAR keyword, not supported by flexmb yet (")) << k << ": " << err;
    EXPECT_FALSE(contains(err, "unknown")) << k << ": " << err;
  }
  for (const char* k :
       {"LENGTH0", "LGEOMY",    "DIR",    "EPSIND", "FORCEMODE", "ANIMATE",  "MATASC", "RESTART", "JOBID",
        "EOF",     "TIME",      "XY",     "BETA",   "E",         "ED",       "EDD",    "XD",      "XDD",
        "HMAX",    "MAXITERAT", "EPSKIN", "EPSINT", "OUTLEVEL",  "ITERSTEP", "ESIG"}) {
    const auto infos = io::findKeywords(k);
    ASSERT_FALSE(infos.empty()) << k;
    EXPECT_NE(infos.front()->action, io::Action::Unsupported) << k;
  }
}

// Item 6 (issue 21 item 3): a mode-9 transfer block after END HALT is read into the model.
TEST(DatKeywords, Mode9TransferBlockIsRead) {
  const core::Model m = io::readDatFile(kData + "transfer_mode9_2013.dat");
  EXPECT_TRUE(m.notes.empty());
  ASSERT_EQ(m.transferInputs.size(), 1u);
  ASSERT_EQ(m.transferOutputs.size(), 2u);
  EXPECT_EQ(m.transferInputs[0].coord, xIndex(m, 3, 2));
  EXPECT_EQ(m.transferInputs[0].line, 15);
  EXPECT_EQ(m.transferOutputs[1].kind, core::TransferChannel::Kind::Velocity);
  EXPECT_TRUE(m.elements.at(0).hasStiffness);
  // Outside a transfer block a transfer keyword says where it belongs.
  EXPECT_TRUE(contains(errorOf("PLTRUSS 1 1 2\nX 2 1 0\nEND\nHALT\nOUTX 1 2 2\nEND\nEND\n"),
                       "t.dat:5: OUTX: a mode-9 transfer keyword"));
  // A transfer block holds transfer keywords only, and needs its END.
  EXPECT_TRUE(contains(errorOf("PLTRUSS 1 1 2\nX 2 1 0\nEND\nHALT\nXM 2 1\nEND\nHALT\nOUTX 1 2 2\nXM 2 1\nEND\nEND\n"),
                       "only mode-9 transfer keywords"));
  EXPECT_TRUE(contains(errorOf("PLTRUSS 1 1 2\nX 2 1 0\nEND\nHALT\nXM 2 1\nEND\nHALT\nOUTX 1 2 2\n"),
                       "inside the transfer block"));
}

// Item 3: SPACAR95's end-of-run state is read: LENGTH0 keeps the undeformed lengths of a deformed
// configuration, E gives the deformations there, the run settings are accepted and listed once.
TEST(Spacar95Restart, RestartStateKeywordsAreRead) {
  const core::Model m = io::readDatFile(kData + "restart_state_s95.dat");
  EXPECT_TRUE(m.restartState);
  EXPECT_DOUBLE_EQ(m.settings.t0, 3.0);
  EXPECT_DOUBLE_EQ(m.settings.tEnd, 4.0);
  EXPECT_DOUBLE_EQ(m.settings.hmax, 0.01);
  EXPECT_EQ(m.settings.maxIterations, 20);
  const auto* t1 = dynamic_cast<const core::PlanarTruss*>(m.elements.at(0).impl.get());
  const auto* t2 = dynamic_cast<const core::PlanarTruss*>(m.elements.at(1).impl.get());
  ASSERT_TRUE(t1 && t2);
  EXPECT_DOUBLE_EQ(t1->l0(), 1.0);
  EXPECT_DOUBLE_EQ(t2->l0(), 2.0);
  EXPECT_DOUBLE_EQ(m.e0[eIndex(m, 2, 1)], 0.004);
  // Stiffness from the undeformed length: EA / l0.
  EXPECT_DOUBLE_EQ(m.elements.at(1).S(0, 0), 500.0);
  ASSERT_EQ(m.notes.size(), 8u);
  for (const char* k : {"LGEOMY", "DIR", "EPSIND", "FORCEMODE", "ANIMATE", "MATASC", "RESTART", "JOBID"}) {
    int n = 0;
    for (const auto& note : m.notes) n += contains(note, std::string(k) + " (line") ? 1 : 0;
    EXPECT_EQ(n, 1) << k;
  }
}

// Restart references of a bent beam: the deformations at the given coordinates are the E values.
TEST(Spacar95Restart, BeamReferenceFromLength0AndE) {
  const std::string text =
      "PLBEAM 1 1 2 3 4\nXY 1 0 0\nBETA 2 0.3\nXY 3 0.8 0.6\nBETA 4 0.9\nFIX 1\nFIX 2\nDYNE 1 1 2 3\n"
      "LENGTH0 1 0.99\nE 1 1 0.01\nE 1 2 0.02\nE 1 3 -0.03\nTIMESTEP 1 1\nEND\nEOF\n";
  for (auto el : {core::ElongationDefinition::Plain, core::ElongationDefinition::BendingCorrected}) {
    io::ReadOptions o;
    o.elongation = el;
    const core::Model m = io::readDatString(text, "t.dat", o);
    const auto* beam = dynamic_cast<const core::PlanarBeam*>(m.elements.at(0).impl.get());
    ASSERT_TRUE(beam);
    EXPECT_DOUBLE_EQ(beam->l0(), 0.99);
    core::ElemVec x(6);
    x << 0, 0, 0.3, 0.8, 0.6, 0.9;
    core::DefVec e;
    beam->deformations(x, e);
    EXPECT_NEAR(e[1], 0.02, 1e-15);
    EXPECT_NEAR(e[2], -0.03, 1e-15);
  }
}

// Item 8: the committed language reference is the generated one.
TEST(KeywordTable, MarkdownReferenceIsCurrent) {
  std::ostringstream generated;
  io::printKeywordsMarkdown(generated);
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/io/dat-language.md");
  ASSERT_TRUE(in) << "io/dat-language.md is missing: run `flexmb keywords --markdown > io/dat-language.md`";
  std::stringstream committed;
  committed << in.rdbuf();
  EXPECT_TRUE(committed.str() == generated.str())
      << "io/dat-language.md differs from the keyword table: regenerate it with "
         "`flexmb keywords --markdown > io/dat-language.md`";
  // Every keyword of the table appears in it.
  for (const auto& k : io::keywordTable()) EXPECT_TRUE(contains(generated.str(), "| `" + k.name + "` |")) << k.name;
}
