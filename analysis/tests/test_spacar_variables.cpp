// SPACAR result variables that real scripts read (issue 23; io/results.md): fx (applied nodal
// loads), fxgrav (gravity loads), and the element constants estiff / stif / em / edamp, each
// recomputed here independently of the code that writes it: the loads from the model file's
// numbers and the element masses, the constants from the file's text.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/SpacarOutput.hpp"
#include "analysis/Statics.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/SpacarResults.hpp"

using namespace flexmb;

namespace {

// A planar cantilever along x (two PLBEAMs of 0.5 m, rhoA 0.4 kg/m), a 0.1 kg tip mass, gravity
// -9.81 in y and a tip load DELXF (1, -2) N reached in 4 load steps. Element 7 (a hinge at the
// root, a label with a gap) has a stiffness and a damping but no mass.
const char* kCantilever =
    "PLBEAM 1 1 11 2 12\nPLBEAM 2 2 12 3 13\nPLHINGE 7 10 11\n"
    "X 1 0 0\nX 2 0.5 0\nX 3 1.0 0\n"
    "FIX 1\nFIX 10\nDYNE 1 2 3\nDYNE 2 1 2 3\nDYNE 7 1\n"
    "END\nHALT\n"
    "EM 1 0.4 1e-4\nEM 2 0.4\nXM 3 0.1\nESTIFF 1 1e6 40\nESTIFF 2 2e6 50\nESTIFF 7 300\n"
    "EDAMP 1 0 0.01\nEDAMP 7 0.5\nGRAVITY 0 -9.81\nDELXF 3 1 -2\nITERSTEP 30 4 1e-10\nEND\nEND\n";

int xIndex(const io::SpacarLayout& L, const core::Model& m, int node, int comp) {
  const int model = m.nodes[m.nodeByLabel.at(node)].firstCoord + comp - 1;
  for (int k = 0; k < m.nx; ++k)
    if (L.xOrder[k] == model) return k;
  return -1;
}

}  // namespace

TEST(SpacarVariables, FxIsTheAppliedLoadAndFxgravTheWeight) {
  const core::Model m = io::readDatString(kCantilever, "cantilever.dat");
  const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
  ASSERT_TRUE(run.completed) << run.stopReason;
  const io::SpacarResults r = analysis::spacarFromStatics(m, run, {});
  const io::SpacarLayout L = io::spacarLayout(m);
  ASSERT_EQ(r.steps.size(), 5u);  // load steps 0..4: gravity (an initial load) in all, DELXF k/4 in step k
  const double weight = 9.81 * (0.4 * 0.5 + 0.4 * 0.5 + 0.1);
  const int tipX = xIndex(L, m, 3, 1), tipY = xIndex(L, m, 3, 2);
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const io::SpacarStep& s = r.steps[k];
    const double f = static_cast<double>(k) / 4.0;  // DELXF's share at load step k
    ASSERT_EQ(s.fx.size(), m.nx);
    ASSERT_EQ(s.fxgrav.size(), m.nx);
    // fx: exactly the DELXF share at the tip, nothing elsewhere (gravity is not in it).
    for (int j = 0; j < m.nx; ++j) {
      const double expect = j == tipX ? 1.0 * f : j == tipY ? -2.0 * f : 0.0;
      EXPECT_NEAR(s.fx[j], expect, 1e-15) << "fx[" << j << "] at load step " << k;
    }
    // fxgrav: the weight in -y over the position coordinates, none in x.
    double sumX = 0, sumY = 0;
    for (const auto& n : m.nodes)
      if (n.dim() == 2) {
        sumX += s.fxgrav[xIndex(L, m, n.label, 1)];
        sumY += s.fxgrav[xIndex(L, m, n.label, 2)];
      }
    EXPECT_NEAR(sumX, 0.0, 1e-12);
    EXPECT_NEAR(sumY, -weight, 1e-12 * weight);
    // The point mass's own share sits on its node with about half of element 2's weight (exactly
    // half in the straight beam; the deflected beam, tip slope up to 0.025, moves 5e-5 of it).
    EXPECT_NEAR(s.fxgrav[tipY], -9.81 * (0.1 + 0.4 * 0.5 / 2), 2e-4);
    // fxt on a free coordinate is the applied load there (statics: no inertia).
    EXPECT_NEAR(s.fxt[tipY], s.fx[tipY] + s.fxgrav[tipY], 1e-9);
  }
}

TEST(SpacarVariables, ElementConstantsAreTheFilesValues) {
  const core::Model m = io::readDatString(kCantilever, "cantilever.dat");
  const Eigen::MatrixXd estiff = io::spacarElementConstants(m, io::ElementConstant::Stiffness, 7);
  const Eigen::MatrixXd stif = io::spacarElementConstants(m, io::ElementConstant::Stiffness, 7, 6);
  const Eigen::MatrixXd em = io::spacarElementConstants(m, io::ElementConstant::Mass, 7);
  const Eigen::MatrixXd edamp = io::spacarElementConstants(m, io::ElementConstant::Damping, 7);
  // Rows = element labels 1..7; columns = the most values any element gives (missing ones 0).
  Eigen::MatrixXd e(7, 2), d(7, 2), s = Eigen::MatrixXd::Zero(7, 6);
  e << 1e6, 40, 2e6, 50, 0, 0, 0, 0, 0, 0, 0, 0, 300, 0;
  d << 0, 0.01, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5, 0;
  s.leftCols(2) = e;
  EXPECT_EQ(estiff, e);
  EXPECT_EQ(stif, s);
  EXPECT_EQ(edamp, d);
  Eigen::MatrixXd mass = Eigen::MatrixXd::Zero(7, 2);
  mass(0, 0) = 0.4, mass(0, 1) = 1e-4, mass(1, 0) = 0.4;
  EXPECT_EQ(em, mass);

  // A spatial BEAM with 4 of its 6 ESTIFF values (as FlexibleInstrumentSimulation writes them):
  // stif keeps 6 columns (spatools reads the shear coefficients from columns 5:6), zeros after.
  const core::Model b = io::readDatString(
      "BEAM 1 1 2 3 4 0 1 0\nX 1 0 0 0\nX 3 0.1 0 0\nFIX 1\nFIX 2\nDYNX 3 1 2 3\nDYNX 4 2 3 4\n"
      "RLSE 1 1 2 3 4 5 6\nEND\nHALT\nEM 1 1.0 0.1\nESTIFF 1 0 0.0093 0.012 0.012\nEND\nEND\n",
      "fis_beam.dat");
  const Eigen::MatrixXd bs = io::spacarElementConstants(b, io::ElementConstant::Stiffness, 1, 6);
  ASSERT_EQ(bs.cols(), 6);
  EXPECT_EQ(bs(0, 1), 0.0093);
  EXPECT_EQ(bs(0, 3), 0.012);
  EXPECT_EQ(bs(0, 4), 0.0);
  EXPECT_EQ(io::spacarElementConstants(b, io::ElementConstant::Mass, 1)(0, 1), 0.1);
}
