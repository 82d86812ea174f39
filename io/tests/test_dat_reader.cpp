// io::DatReader on complete models of both dialects, the block rules, lexing, dialect detection,
// time functions and the keyword table.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/elements/PlanarBeam.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/ExpressionFunction.hpp"
#include "io/formats/KeywordTable.hpp"

using namespace flexmb;
using core::Dialect;
using core::ElongationDefinition;
using core::Role;

namespace {

const std::string kData = std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/";

ElongationDefinition elongationOf(const core::Model& m, int label) {
  const auto& el = m.elements.at(m.elementByLabel.at(label));
  const auto* beam = dynamic_cast<const core::PlanarBeam*>(el.impl.get());
  EXPECT_NE(beam, nullptr);
  return beam ? beam->elongation() : ElongationDefinition::Plain;
}

int xIndex(const core::Model& m, int node, int comp) {
  return m.nodes.at(m.nodeByLabel.at(node)).firstCoord + comp - 1;
}
int eIndex(const core::Model& m, int element, int comp) {
  return m.elements.at(m.elementByLabel.at(element)).firstDef + comp - 1;
}

// A small neutral model (no dialect-specific keyword) with one dynamic block.
std::string neutral(const std::string& dynamic, const std::string& kinematicExtra = "") {
  return "PLBEAM 1 1 2 3 4\nX 3 1 0\nFIX 1\nFIX 2\nDYNE 1 2 3\n" + kinematicExtra + "END\nHALT\n" + dynamic +
         "END\nEND\n";
}

}  // namespace

TEST(DatReader, Spacar2013ModelParsedFully) {
  const core::Model m = io::readDatFile(kData + "two_link_2013.dat");
  EXPECT_EQ(m.dialect, Dialect::Spacar2013);
  EXPECT_EQ(m.sourceFile, kData + "two_link_2013.dat");
  ASSERT_EQ(m.elements.size(), 4u);
  ASSERT_EQ(m.nodes.size(), 8u);
  EXPECT_EQ(m.nx, 12);
  EXPECT_EQ(m.ne, 8);

  // Node kinds and x indices in order of first use.
  const int expectLabel[] = {1, 2, 3, 4, 5, 6, 7, 8};
  const int expectFirst[] = {0, 2, 3, 5, 6, 8, 9, 10};
  const core::NodeKind P = core::NodeKind::Position, O = core::NodeKind::Orientation;
  const core::NodeKind expectKind[] = {P, O, P, O, P, O, O, P};
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(m.nodes[i].label, expectLabel[i]);
    EXPECT_EQ(m.nodes[i].firstCoord, expectFirst[i]);
    EXPECT_EQ(m.nodes[i].kind, expectKind[i]) << "node " << expectLabel[i];
  }
  EXPECT_EQ(m.nodes[m.nodeByLabel.at(7)].line, 5);  // first used by the PLHINGE on line 5

  // Elements: types, deformation indices, coordinate lists.
  EXPECT_EQ(m.elements[0].type->keyword, "PLBEAM");
  EXPECT_EQ(m.elements[2].type->keyword, "PLHINGE");
  EXPECT_EQ(m.elements[3].type->keyword, "PLTRUSS");
  EXPECT_EQ(m.elements[1].firstDef, 3);
  EXPECT_EQ(m.elements[2].firstDef, 6);
  EXPECT_EQ(m.elements[3].firstDef, 7);
  EXPECT_EQ(m.elements[1].coords, (std::vector<int>{3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(m.elements[2].coords, (std::vector<int>{9, 2}));
  EXPECT_EQ(m.elements[3].coords, (std::vector<int>{6, 7, 10, 11}));
  EXPECT_EQ(m.elements[3].line, 6);

  // Initial coordinates.
  Eigen::VectorXd x0(12);
  x0 << 0, 0, 0, 0.5, 0, 0, 1.0, 0, 0, 0, 1.0, 1.0;
  EXPECT_TRUE(m.x0.isApprox(x0)) << m.x0.transpose();

  // Roles.
  EXPECT_EQ(m.xRole[xIndex(m, 1, 1)], Role::Fixed);
  EXPECT_EQ(m.xRole[xIndex(m, 1, 2)], Role::Fixed);
  EXPECT_EQ(m.xRole[xIndex(m, 7, 1)], Role::Fixed);
  EXPECT_EQ(m.xRole[xIndex(m, 8, 1)], Role::Fixed);
  EXPECT_EQ(m.xRole[xIndex(m, 8, 2)], Role::Input);
  EXPECT_EQ(m.xRole[xIndex(m, 6, 1)], Role::Dynamic);
  EXPECT_EQ(m.xRole[xIndex(m, 3, 1)], Role::Calculable);
  EXPECT_EQ(m.xRole[xIndex(m, 2, 1)], Role::Calculable);
  EXPECT_EQ(m.eRole[eIndex(m, 1, 1)], Role::Fixed);
  EXPECT_EQ(m.eRole[eIndex(m, 1, 2)], Role::Dynamic);
  EXPECT_EQ(m.eRole[eIndex(m, 2, 3)], Role::Dynamic);
  EXPECT_EQ(m.eRole[eIndex(m, 3, 1)], Role::Dynamic);
  EXPECT_EQ(m.eRole[eIndex(m, 4, 1)], Role::Calculable);

  // q = DYNX coordinates, then DYNE deformations, each in file order.
  ASSERT_EQ(m.numDofs(), 6);
  EXPECT_FALSE(m.dofs[0].isDeformation);
  EXPECT_EQ(m.dofs[0].index, xIndex(m, 6, 1));
  const int expectDefs[] = {eIndex(m, 3, 1), eIndex(m, 1, 2), eIndex(m, 1, 3), eIndex(m, 2, 2), eIndex(m, 2, 3)};
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(m.dofs[k + 1].isDeformation);
    EXPECT_EQ(m.dofs[k + 1].index, expectDefs[k]);
  }

  // Constitutive matrices: beam l0 = 0.5, S = diag(EA/l0, EI/l0^3 [[4, -2], [-2, 4]]).
  const auto& b1 = m.elements[0];
  ASSERT_TRUE(b1.hasStiffness);
  EXPECT_DOUBLE_EQ(b1.S(0, 0), 1e6 / 0.5);
  EXPECT_DOUBLE_EQ(b1.S(1, 1), 4 * 100 / (0.5 * 0.5 * 0.5));
  EXPECT_DOUBLE_EQ(b1.S(1, 2), -2 * 100 / (0.5 * 0.5 * 0.5));
  EXPECT_DOUBLE_EQ(m.elements[1].S(2, 2), 4 * 100 / 0.125);  // "1.0d2" Fortran exponent
  EXPECT_DOUBLE_EQ(m.elements[2].S(0, 0), 5e3);
  EXPECT_TRUE(m.elements[2].hasDamping);
  EXPECT_DOUBLE_EQ(m.elements[2].Sd(0, 0), 1.5);
  EXPECT_FALSE(m.elements[0].hasDamping);
  EXPECT_DOUBLE_EQ(m.elements[3].S(0, 0), 2e5 / 1.0);  // truss from (1,0) to (1,1)

  // Inertia.
  EXPECT_DOUBLE_EQ(m.elements[0].inertia.rhoA, 2.0);
  EXPECT_DOUBLE_EQ(m.elements[0].inertia.rhoI, 0.01);
  EXPECT_DOUBLE_EQ(m.elements[1].inertia.rhoI, 0.0);
  EXPECT_FALSE(m.elements[3].inertia.any());
  ASSERT_EQ(m.lumpedMasses.size(), 3u);
  EXPECT_EQ(m.lumpedMasses[0].coord, xIndex(m, 5, 1));
  EXPECT_EQ(m.lumpedMasses[1].coord, xIndex(m, 5, 2));
  EXPECT_DOUBLE_EQ(m.lumpedMasses[1].value, 3.0);
  EXPECT_EQ(m.lumpedMasses[2].coord, xIndex(m, 6, 1));
  EXPECT_DOUBLE_EQ(m.lumpedMasses[2].value, 0.2);

  // Loads.
  EXPECT_DOUBLE_EQ(m.f0[xIndex(m, 5, 2)], -10.0);
  EXPECT_DOUBLE_EQ(m.f0.cwiseAbs().sum(), 10.0);
  EXPECT_TRUE(m.hasGravity);
  EXPECT_DOUBLE_EQ(m.gravity[1], -9.81);
  ASSERT_EQ(m.timeForces.size(), 1u);
  EXPECT_EQ(m.timeForces[0].index, xIndex(m, 5, 1));
  const auto& f = *m.timeForces[0].f;
  const double pi = std::acos(-1.0);
  for (double t : {0.0, 0.025, 0.05, 0.0731, 0.099}) {
    const double expect = 50.0 * (1.0 - std::cos(20.0 * pi * t));
    EXPECT_NEAR(f.value(t), expect, 1e-12) << "t = " << t;
  }
  EXPECT_NEAR(f.value(0.05), 100.0, 1e-12);
  EXPECT_EQ(f.value(0.1), 0.0);
  EXPECT_EQ(f.value(0.5), 0.0);
  EXPECT_EQ(f.text(), "t<0.1 ? 50*(1-cos(20*_pi*t)) : 0");
  EXPECT_DOUBLE_EQ(m.sigma0[eIndex(m, 4, 1)], 12.5);

  // Initial deformations (NaN where not given) and inputs.
  EXPECT_DOUBLE_EQ(m.e0[eIndex(m, 3, 1)], 0.1);
  EXPECT_DOUBLE_EQ(m.ed0[eIndex(m, 3, 1)], 0.5);
  EXPECT_TRUE(std::isnan(m.edd0[eIndex(m, 3, 1)]));
  EXPECT_TRUE(std::isnan(m.e0[eIndex(m, 1, 2)]));
  ASSERT_EQ(m.inputX.size(), 1u);
  EXPECT_EQ(m.inputX[0].index, xIndex(m, 8, 2));
  EXPECT_DOUBLE_EQ(m.inputX[0].x0, 1.0);
  EXPECT_DOUBLE_EQ(m.inputX[0].v, 0.2);
  EXPECT_DOUBLE_EQ(m.inputX[0].a, 0.05);
  EXPECT_TRUE(m.inputE.empty());

  // Settings: TIMESTEP T n in SPACAR 2013+.
  EXPECT_TRUE(m.settings.timestepGiven);
  EXPECT_DOUBLE_EQ(m.settings.tEnd, 0.7);
  EXPECT_EQ(m.settings.outputIntervals, 70);
  EXPECT_DOUBLE_EQ(m.settings.absTol, 1e-7);
  EXPECT_DOUBLE_EQ(m.settings.relTol, 1e-4);
  EXPECT_EQ(m.settings.maxIterations, 20);
  EXPECT_EQ(m.settings.loadSteps, 5);
  EXPECT_DOUBLE_EQ(m.settings.kinematicTol, 1e-9);
  EXPECT_DOUBLE_EQ(m.settings.t0, 0.0);

  // Elongation: bending corrected in SPACAR 2013+.
  EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::BendingCorrected);
}

TEST(DatReader, Spacar95ModelParsedFully) {
  // Three SPACAR95 blocks: the kinematic one, a dynamic one that runs (TIMESTEP), one that changes
  // settings only. The model of the run is the second stage; the last one holds every block.
  const auto stages = io::readDatStages(kData + "slider_s95.dat");
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_FALSE(stages[0].runs);
  EXPECT_TRUE(stages[1].runs);
  EXPECT_FALSE(stages[2].runs);
  const core::Model& m = stages[1].model;
  EXPECT_EQ(m.dialect, Dialect::Spacar95);
  ASSERT_EQ(m.elements.size(), 2u);
  ASSERT_EQ(m.nodes.size(), 5u);
  EXPECT_EQ(m.nx, 8);
  EXPECT_EQ(m.ne, 4);
  Eigen::VectorXd x0(8);
  x0 << 0, 0, 0.25, 0.1, 0, 0, 0.3, 0;
  EXPECT_TRUE(m.x0.isApprox(x0)) << m.x0.transpose();

  EXPECT_EQ(m.xRole[xIndex(m, 2, 1)], Role::Input);
  EXPECT_EQ(m.xRole[xIndex(m, 5, 2)], Role::Fixed);
  EXPECT_EQ(m.xRole[xIndex(m, 5, 1)], Role::Dynamic);
  EXPECT_EQ(m.xRole[xIndex(m, 4, 1)], Role::Calculable);
  EXPECT_EQ(m.eRole[eIndex(m, 2, 1)], Role::Calculable);
  ASSERT_EQ(m.numDofs(), 4);
  EXPECT_FALSE(m.dofs[0].isDeformation);
  EXPECT_EQ(m.dofs[0].index, xIndex(m, 5, 1));
  for (int k = 1; k <= 3; ++k) {
    EXPECT_TRUE(m.dofs[k].isDeformation);
    EXPECT_EQ(m.dofs[k].index, eIndex(m, 1, k));
  }

  // Beam l0 = 0.1; truss l0 = 0.2.
  EXPECT_DOUBLE_EQ(m.elements[0].S(0, 0), 2e7 / 0.1);
  EXPECT_NEAR(m.elements[0].S(1, 1), 4 * 150 / 1e-3, 1e-6);
  EXPECT_DOUBLE_EQ(m.elements[1].S(0, 0), 1e6 / 0.2);
  EXPECT_DOUBLE_EQ(m.elements[1].Sd(0, 0), 10 / 0.2);
  EXPECT_DOUBLE_EQ(m.elements[0].inertia.rhoA, 0.5);
  EXPECT_DOUBLE_EQ(m.elements[1].inertia.rhoA, 0.25);
  ASSERT_EQ(m.lumpedMasses.size(), 2u);
  EXPECT_DOUBLE_EQ(m.lumpedMasses[0].value, 1.5);
  EXPECT_DOUBLE_EQ(m.f0[xIndex(m, 5, 1)], -2.5);
  EXPECT_DOUBLE_EQ(m.f0[xIndex(m, 5, 2)], 0.0);
  EXPECT_FALSE(m.hasGravity);

  // Input: x0 defaults to the initial coordinate (BETA 2 0.25); XD/XDD give v and a.
  ASSERT_EQ(m.inputX.size(), 1u);
  EXPECT_DOUBLE_EQ(m.inputX[0].x0, 0.25);
  EXPECT_DOUBLE_EQ(m.inputX[0].v, 6.2832);
  EXPECT_DOUBLE_EQ(m.inputX[0].a, 0.5);
  double x, xd, xdd;
  m.inputX[0].evaluate(2.0, x, xd, xdd);
  EXPECT_DOUBLE_EQ(x, 0.25 + 6.2832 * 2 + 0.5 * 0.5 * 4);
  EXPECT_DOUBLE_EQ(xd, 6.2832 + 0.5 * 2);
  EXPECT_DOUBLE_EQ(xdd, 0.5);
  EXPECT_DOUBLE_EQ(m.e0[eIndex(m, 1, 1)], 0.001);
  EXPECT_DOUBLE_EQ(m.ed0[eIndex(m, 1, 2)], 0.01);
  EXPECT_TRUE(std::isnan(m.e0[eIndex(m, 1, 2)]));

  // Settings: TIMESTEP n Tp in SPACAR95 (a period from the current time 0).
  EXPECT_DOUBLE_EQ(m.settings.t0, 0.0);
  EXPECT_DOUBLE_EQ(m.settings.tEnd, 2.0);
  EXPECT_EQ(m.settings.outputIntervals, 100);
  EXPECT_DOUBLE_EQ(m.settings.relTol, 1e-5);
  EXPECT_DOUBLE_EQ(m.settings.absTol, 1e-5);
  EXPECT_DOUBLE_EQ(m.settings.hmax, 0.01);
  // The third block is read too: its settings and TIME (which resets the clock; the input continues
  // from its value and rate at the end of the run, 2 s).
  const core::Model& last = io::readDatFile(kData + "slider_s95.dat");
  EXPECT_DOUBLE_EQ(last.settings.kinematicTol, 1e-8);
  EXPECT_EQ(last.settings.maxIterations, 15);
  EXPECT_DOUBLE_EQ(last.settings.t0, 0.5);
  ASSERT_EQ(last.inputX.size(), 1u);
  EXPECT_DOUBLE_EQ(last.inputX[0].tRef, 0.5);
  EXPECT_DOUBLE_EQ(last.inputX[0].x0, 0.25 + 6.2832 * 2 + 0.5 * 0.5 * 4);
  EXPECT_DOUBLE_EQ(last.inputX[0].v, 6.2832 + 0.5 * 2);

  EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::Plain);
}

TEST(DatReader, DialectDetectionAndOverride) {
  const std::string text = neutral("TIMESTEP 2 100\n");
  EXPECT_EQ(io::detectDialect(text), Dialect::Spacar2013);  // neither: SPACAR 2013+
  {
    const core::Model m = io::readDatString(text, "n.dat");
    EXPECT_EQ(m.dialect, Dialect::Spacar2013);
    EXPECT_DOUBLE_EQ(m.settings.tEnd, 2.0);
    EXPECT_EQ(m.settings.outputIntervals, 100);
    EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::BendingCorrected);
  }
  {
    io::ReadOptions o;
    o.dialect = Dialect::Spacar95;
    const core::Model m = io::readDatString(text, "n.dat", o);
    EXPECT_EQ(m.dialect, Dialect::Spacar95);
    EXPECT_DOUBLE_EQ(m.settings.tEnd, 100.0);
    EXPECT_EQ(m.settings.outputIntervals, 2);
    EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::Plain);
  }
  EXPECT_EQ(io::detectDialect(neutral("MASS 3 1\n")), Dialect::Spacar95);
  EXPECT_EQ(io::detectDialect(neutral("XM 3 1\n")), Dialect::Spacar2013);
  // The override also silences the mixing check.
  io::ReadOptions o;
  o.dialect = Dialect::Spacar2013;
  EXPECT_THROW(io::readDatString(neutral("MASS 3 1\nXM 3 2\n")), io::DatError);
  const core::Model m = io::readDatString(neutral("MASS 3 1\nXM 3 2\n"), "m.dat", o);
  EXPECT_DOUBLE_EQ(m.lumpedMasses.at(0).value, 2.0);  // the later statement wins
}

TEST(DatReader, ElongationPerDialectAndOverride) {
  const std::string k = "PLBEAM 1 1 2 3 4\nPLBEAMNL 2 3 4 5 6\nX 3 1 0\nX 5 2 0\nFIX 1\nFIX 2\nEND\n";
  {
    const core::Model m = io::readDatString(k + "HALT\nXM 5 1\nEND\nEND\n");
    EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::BendingCorrected);
    EXPECT_EQ(elongationOf(m, 2), ElongationDefinition::BendingCorrected);
  }
  {
    const core::Model m = io::readDatString(k + "MASS 5 1\nEND\n");
    EXPECT_EQ(m.dialect, Dialect::Spacar95);
    EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::Plain);
    EXPECT_EQ(elongationOf(m, 2), ElongationDefinition::BendingCorrected);  // PLBEAMNL always
  }
  {
    io::ReadOptions o;
    o.elongation = ElongationDefinition::Plain;
    const core::Model m = io::readDatString(k + "HALT\nXM 5 1\nEND\nEND\n", "x.dat", o);
    EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::Plain);  // the override wins
    EXPECT_EQ(elongationOf(m, 2), ElongationDefinition::BendingCorrected);
  }
  {
    io::ReadOptions o;
    o.elongation = ElongationDefinition::BendingCorrected;
    const core::Model m = io::readDatString(k + "MASS 5 1\nEND\n", "x.dat", o);
    EXPECT_EQ(elongationOf(m, 1), ElongationDefinition::BendingCorrected);
  }
}

TEST(DatReader, BlockRules) {
  const std::string kin = "PLBEAM 1 1 2 3 4\nX 3 1 0\nFIX 1\nFIX 2\nDYNE 1 2 3\n";
  // Kinematic block only: END, or END HALT.
  EXPECT_NO_THROW(io::readDatString(kin + "END\n"));
  EXPECT_NO_THROW(io::readDatString(kin + "END\nHALT\n"));
  EXPECT_NO_THROW(io::readDatString(kin + "END\nHALT\nEND\n"));
  EXPECT_NO_THROW(io::readDatString(kin + "END\nEOF\n"));
  // 2013+: END HALT ... END END; whatever follows is not read.
  {
    const core::Model m = io::readDatString(kin + "END\nHALT\nXM 3 2\nEND\nEND\nthis is not read \"\nPLBEEM\n");
    EXPECT_DOUBLE_EQ(m.lumpedMasses.at(0).value, 2.0);
  }
  // HALT after a dynamic block ends the input too.
  {
    const core::Model m = io::readDatString(kin + "END\nHALT\nXM 3 2\nEND\nHALT\nXM 3 5\nEND\n");
    EXPECT_DOUBLE_EQ(m.lumpedMasses.at(0).value, 2.0);
  }
  // SPACAR95: several dynamic blocks, each closed by END, then EOF or the end of the file.
  {
    const core::Model m = io::readDatString(kin + "END\nMASS 3 2\nEND\nTIMESTEP 10 1.5\nEND\nEOF\nnot read\n");
    EXPECT_DOUBLE_EQ(m.lumpedMasses.at(0).value, 2.0);
    EXPECT_DOUBLE_EQ(m.settings.tEnd, 1.5);
    EXPECT_EQ(m.settings.outputIntervals, 10);
  }
  {
    const core::Model m = io::readDatString(kin + "END\nMASS 3 2\nEND\nHMAX 0.5\nEND");
    EXPECT_DOUBLE_EQ(m.settings.hmax, 0.5);
  }
  // VISUALIZATION after the final END: skipped.
  EXPECT_NO_THROW(io::readDatString(kin + "END\nHALT\nXM 3 2\nEND\nEND\nVISUALIZATION\n%%\"\n"));
  EXPECT_NO_THROW(io::readDatString(kin + "END\nHALT\nXM 3 2\nEND\nVISUALIZATION\nx y z\n"));
  // INPUTX: role in the kinematic block, values in a dynamic block.
  {
    const core::Model m =
        io::readDatString("PLBEAM 1 1 2 3 4\nX 3 1 0\nFIX 1\nINPUTX 2\nEND\nHALT\nINPUTX 2 1 0.5 2\nEND\nEND\n");
    ASSERT_EQ(m.inputX.size(), 1u);
    EXPECT_DOUBLE_EQ(m.inputX[0].x0, 0.5);
    EXPECT_DOUBLE_EQ(m.inputX[0].v, 2.0);
    EXPECT_DOUBLE_EQ(m.inputX[0].a, 0.0);
  }
}

TEST(DatReader, LexicalRules) {
  // CRLF, tabs, lower case, all comment kinds, D exponents, blank lines.
  const std::string text =
      "* star comment in column 1\r\n"
      "\r\n"
      "plbeam\t1\t1\t2 3 4   % trailing comment\r\n"
      "x 3 1.0D0 0.0 # hash comment\r\n"
      "Fix 1 ; semicolon comment\r\n"
      "fix 2\r\n"
      "dyne 1 2 3\r\n"
      "end\r\n"
      "halt\r\n"
      "Estiff 1 2.5D+6 1.0e2\r\n"
      "xm 3 .5\r\n"
      "xft 3 1 \"2*t\" % comment after a quoted string with \"quotes\"\r\n"
      "end\r\n"
      "end\r\n";
  const core::Model m = io::readDatString(text);
  EXPECT_DOUBLE_EQ(m.x0[3], 1.0);
  EXPECT_DOUBLE_EQ(m.elements[0].S(0, 0), 2.5e6);
  EXPECT_DOUBLE_EQ(m.lumpedMasses.at(0).value, 0.5);
  EXPECT_DOUBLE_EQ(m.timeForces.at(0).f->value(3.0), 6.0);

  // A UTF-8 byte order mark is skipped; a role repeated with the same meaning is accepted; the
  // later coordinate statement wins.
  {
    const core::Model m3 = io::readDatString("\xEF\xBB\xBF" + neutral("", "FIX 1 1\nX 3 2 0\n"));
    EXPECT_DOUBLE_EQ(m3.x0[3], 2.0);
    EXPECT_EQ(m3.xRole[0], Role::Fixed);
  }

  // Comment characters inside a quoted string stay in the string (muParser then sees them).
  try {
    io::readDatString(neutral("XFT 3 1 \"t % 2 ; # x\"  % real comment\n"), "q.dat");
    FAIL() << "expected DatError";
  } catch (const io::DatError& e) {
    EXPECT_EQ(e.line(), 8);
    EXPECT_NE(std::string(e.what()).find("\"t % 2 ; # x\""), std::string::npos) << e.what();
    EXPECT_EQ(e.keyword(), "XFT");
  }
  // Quoted string spanning comment characters and blanks with a valid expression.
  {
    const core::Model m2 = io::readDatString(neutral("XFT 3 2 \"  t > 1 ? 3 : 4 \" ; c\n"));
    EXPECT_DOUBLE_EQ(m2.timeForces.at(0).f->value(2.0), 3.0);
    EXPECT_DOUBLE_EQ(m2.timeForces.at(0).f->value(0.0), 4.0);
  }
}

TEST(DatReader, TimeFunctionKeywords) {
  const std::string text =
      "PLBEAM 1 1 2 3 4\nPLHINGE 2 5 2\nX 3 1 0\nFIX 1\nFIX 5\nINPUTX 3 2\nINPUTE 2\n"
      "DYNE 1 2 3\nEND\nHALT\n"
      "ESTIFF 1 1 1\n"
      "INPUTXT 3 2 \"sin(t)\" \"cos(t)\" \"-sin(t)\"\n"
      "INPUTET 2 1 \"t^2\" \"2*t\" \"2\"\n"
      "ESIGT 1 2 \"exp(-t)\"\n"
      "EREF 1 3 \"0.5*_pi*t\"\n"
      "END\nEND\n";
  const core::Model m = io::readDatString(text);
  ASSERT_EQ(m.inputX.size(), 1u);
  double x, xd, xdd;
  m.inputX[0].evaluate(0.3, x, xd, xdd);
  EXPECT_DOUBLE_EQ(x, std::sin(0.3));
  EXPECT_DOUBLE_EQ(xd, std::cos(0.3));
  EXPECT_DOUBLE_EQ(xdd, -std::sin(0.3));
  ASSERT_EQ(m.inputE.size(), 1u);
  EXPECT_EQ(m.inputE[0].index, eIndex(m, 2, 1));
  m.inputE[0].evaluate(1.5, x, xd, xdd);
  EXPECT_DOUBLE_EQ(x, 2.25);
  EXPECT_DOUBLE_EQ(xd, 3.0);
  EXPECT_DOUBLE_EQ(xdd, 2.0);
  ASSERT_EQ(m.timeStresses.size(), 1u);
  EXPECT_EQ(m.timeStresses[0].index, eIndex(m, 1, 2));
  EXPECT_DOUBLE_EQ(m.timeStresses[0].f->value(1.0), std::exp(-1.0));
  ASSERT_EQ(m.references.size(), 1u);
  EXPECT_EQ(m.references[0].index, eIndex(m, 1, 3));
  EXPECT_DOUBLE_EQ(m.references[0].f->value(2.0), std::acos(-1.0));
}

TEST(DatReader, InputValuesForDeformations) {
  // SPACAR95 E/ED/EDD on an input deformation give its motion; 2013+ INPUTE values likewise.
  const std::string kin = "PLBEAM 1 1 2 3 4\nPLHINGE 2 5 2\nX 3 1 0\nFIX 1\nFIX 5\nINPUTE 2 1\nEND\n";
  {
    const core::Model m = io::readDatString(kin + "E 2 1 0.1\nED 2 1 2\nEDD 2 1 -1\nEND\n");
    ASSERT_EQ(m.inputE.size(), 1u);
    EXPECT_DOUBLE_EQ(m.inputE[0].x0, 0.1);
    EXPECT_DOUBLE_EQ(m.inputE[0].v, 2.0);
    EXPECT_DOUBLE_EQ(m.inputE[0].a, -1.0);
    EXPECT_TRUE(std::isnan(m.e0[eIndex(m, 2, 1)]));
  }
  {
    const core::Model m = io::readDatString(kin + "HALT\nINPUTE 2 1 0.2 3\nEND\nEND\n");
    EXPECT_DOUBLE_EQ(m.inputE.at(0).x0, 0.2);
    EXPECT_DOUBLE_EQ(m.inputE.at(0).v, 3.0);
  }
  {
    // Defaults: a deformation input starts at 0 at rest.
    const core::Model m = io::readDatString(kin);
    EXPECT_DOUBLE_EQ(m.inputE.at(0).x0, 0.0);
    EXPECT_DOUBLE_EQ(m.inputE.at(0).v, 0.0);
  }
}

TEST(DatReader, StaticKeywords2013) {
  const core::Model m =
      io::readDatString(neutral("DELXF 3 1 2\nXF 3 1\nXF 3 0.5 0.25\nDELINPX 3 1 0.1\n", "INPUTX 3 1\nXY 3 1.5 0.5\n"));
  const int x3 = xIndex(m, 3, 1);
  EXPECT_DOUBLE_EQ(m.x0[x3], 1.5);
  EXPECT_DOUBLE_EQ(m.x0[x3 + 1], 0.5);
  EXPECT_DOUBLE_EQ(m.inputX.at(0).x0, 1.5);  // default: the initial coordinate
  EXPECT_DOUBLE_EQ(m.delf[x3], 1.0);
  EXPECT_DOUBLE_EQ(m.delf[x3 + 1], 2.0);
  EXPECT_DOUBLE_EQ(m.f0[x3], 1.5);  // forces add up
  EXPECT_DOUBLE_EQ(m.f0[x3 + 1], 0.25);
  EXPECT_DOUBLE_EQ(m.inputX.at(0).delta, 0.1);
}

TEST(ExpressionFunction, EvaluatesAndReportsErrors) {
  io::ExpressionFunction f("t<0.1 ? 50*(1-cos(20*_pi*t)) : 0");
  EXPECT_NEAR(f.value(0.05), 100.0, 1e-12);
  EXPECT_NEAR(f.value(0.025), 50.0, 1e-12);
  EXPECT_EQ(f.value(0.2), 0.0);
  EXPECT_EQ(f.text(), "t<0.1 ? 50*(1-cos(20*_pi*t)) : 0");
  const auto g = io::ExpressionFunction::make("sqrt(t)+exp(0)");
  EXPECT_DOUBLE_EQ(g->value(4.0), 3.0);
  // _pi has full double precision (muParser's GCC build truncates it to 3.141592653589).
  EXPECT_EQ(io::ExpressionFunction("_pi").value(0.0), std::acos(-1.0));
  EXPECT_THROW(io::ExpressionFunction("sin(t"), io::ExpressionError);
  EXPECT_THROW(io::ExpressionFunction("2*x"), io::ExpressionError);
  EXPECT_THROW(io::ExpressionFunction(""), io::ExpressionError);
  EXPECT_THROW(io::ExpressionFunction("1,2"), io::ExpressionError);
  try {
    io::ExpressionFunction bad("2*x");
  } catch (const io::ExpressionError& e) {
    EXPECT_NE(std::string(e.what()).find("x"), std::string::npos) << e.what();
  }
}

TEST(KeywordTable, SuggestionsAndListing) {
  EXPECT_EQ(io::suggestKeyword("PLBEEM"), "PLBEAM");
  EXPECT_EQ(io::suggestKeyword("ESTIF"), "ESTIFF");
  EXPECT_EQ(io::suggestKeyword("timestp"), "TIMESTEP");
  EXPECT_EQ(io::suggestKeyword("QQQQQQQQ"), "");
  EXPECT_EQ(io::editDistance("kitten", "SITTING"), 3);
  // Element keywords come from the registry.
  for (const auto& t : core::elementTypes()) {
    const io::KeywordInfo* k = io::findKeyword(t.keyword, io::BlockKind::Kinematic);
    ASSERT_NE(k, nullptr) << t.keyword;
    EXPECT_EQ(k->elementType, &t);
  }
  EXPECT_NE(io::findKeyword("INPUTX", io::BlockKind::Kinematic), nullptr);
  EXPECT_NE(io::findKeyword("INPUTX", io::BlockKind::Dynamic), nullptr);
  EXPECT_EQ(io::findKeyword("ESTIFF", io::BlockKind::Kinematic), nullptr);
  const io::KeywordInfo* plbeam = io::findKeyword("plbeam", io::BlockKind::Kinematic);
  ASSERT_NE(plbeam, nullptr);
  EXPECT_EQ(io::KeywordInfo::expectation(plbeam->args),
            "expected 5 integers (element, node p, orientation p, node q, orientation q)");
  EXPECT_EQ(io::KeywordInfo::synopsis(plbeam->name, plbeam->args), "PLBEAM e p1 o1 p2 o2");

  std::ostringstream out;
  io::printKeywords(out);
  const std::string s = out.str();
  for (const char* needle :
       {"PLBEAM e p1 o1 p2 o2", "PLHINGE e o1 o2", "TIMESTEP T n", "TIMESTEP n T", "XFT n i \"f(t)\"", "USERINP",
        "not supported", "EMASS", "ITERSTEP", "VISUALIZATION", "INPUTX n [i ...]", "INPUTX n i x [v [a]]"})
    EXPECT_NE(s.find(needle), std::string::npos) << needle << "\n" << s;
  // Every keyword of the table respects the 8-character limit, bar SPACAR's own long names.
  for (const auto& k : io::keywordTable())
    if (k.name != "MAXITERAT" && k.name != "VISUALIZATION" && k.name != "PLPINBODY" && k.name != "FORCEMODE") {
      EXPECT_LE(k.name.size(), 8u) << k.name;
    }
}
