// Mesh refinement (io::ReadOptions::refine, core::refineModel) through the analyses: the paper's
// 5-element guidance refined by 8 against the hand-written 40-element file (same leaves, masses,
// stiffnesses and load; its numbering differs, so results are compared at the shared original
// nodes), the static deflection converging with the refinement, and a spatial model's frequencies
// converging towards a finer mesh with its mass unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "analysis/Modes.hpp"
#include "analysis/ModesJob.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/Statics.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

io::ReadOptions refined(int parts) {
  io::ReadOptions o;
  o.refine = parts;
  return o;
}

// The guidance's node labels and the 40-element file's labels of the same points.
std::map<int, int> sharedNodes() {
  std::map<int, int> m;
  for (int k = 0; k < 6; ++k) {
    m[1 + k] = 1 + 8 * k;       // left flexure, positions
    m[11 + k] = 1001 + 8 * k;   // right flexure, positions
    m[101 + k] = 2001 + 8 * k;  // left flexure, orientations
    m[111 + k] = 3001 + 8 * k;  // right flexure, orientations
  }
  return m;
}

// The largest difference of x (a vector of model a) and y (of model b) over the shared nodes.
double sharedDifference(const core::Model& a, const Eigen::VectorXd& x, const core::Model& b,
                        const Eigen::VectorXd& y) {
  double d = 0.0;
  for (const auto& [la, lb] : sharedNodes()) {
    const core::Node& na = a.nodes[a.nodeByLabel.at(la)];
    const core::Node& nb = b.nodes[b.nodeByLabel.at(lb)];
    for (int c = 0; c < na.dim(); ++c) d = std::max(d, std::abs(x[na.firstCoord + c] - y[nb.firstCoord + c]));
  }
  return d;
}

// The guidance with a constant force on the body instead of the pulse (a static load): `node` is
// the loaded node's label in the text.
std::string withStaticLoad(std::string text, int node) {
  const size_t at = text.find("XFT ");
  const size_t end = text.find('\n', at);
  text.replace(at, end - at, "XF " + std::to_string(node) + " 20 0");
  return text;
}

std::string fileText(const std::string& name) { return io::readDatText(dat(name)); }
}  // namespace

TEST(Refinement, GuidanceByEightIsTheFortyElementFile) {
  // The file is the guidance with each flexure beam split in 8 equal parts and the same properties.
  const core::Model forty = io::readDatFile(dat("tests/straight_guidance_40.dat"));
  const core::Model r = io::readDatFile(dat("straight_guidance.dat"), refined(8));
  ASSERT_EQ(r.elements.size(), forty.elements.size());
  ASSERT_EQ(r.nodes.size(), forty.nodes.size());
  ASSERT_EQ(r.numDofs(), forty.numDofs());
  for (const auto& [la, lb] : sharedNodes()) {
    const core::Node& na = r.nodes[r.nodeByLabel.at(la)];
    const core::Node& nb = forty.nodes[forty.nodeByLabel.at(lb)];
    for (int c = 0; c < na.dim(); ++c) EXPECT_NEAR(r.x0[na.firstCoord + c], forty.x0[nb.firstCoord + c], 1e-16);
  }
  // The natural frequencies: the same pencil in another numbering.
  const analysis::InitialModes a = analysis::initialModes(r, std::nullopt, 6);
  const analysis::InitialModes b = analysis::initialModes(forty, std::nullopt, 6);
  ASSERT_EQ(a.frequencies.omega.size(), 6);
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(a.frequencies.omega[i], b.frequencies.omega[i], 1e-9 * b.frequencies.omega[i]) << "mode " << i + 1;
  // The static deflection under a constant force on the body.
  const core::Model rs =
      io::readDatString(withStaticLoad(fileText("straight_guidance.dat"), 6), "guidance_static.dat", refined(8));
  const core::Model fs =
      io::readDatString(withStaticLoad(fileText("tests/straight_guidance_40.dat"), 41), "guidance_40_static.dat");
  const analysis::StaticRun sa = analysis::staticAnalysis(rs, 0);
  const analysis::StaticRun sb = analysis::staticAnalysis(fs, 0);
  ASSERT_TRUE(sa.completed && sb.completed);
  const double deflection = sa.steps.back().x[rs.nodes[rs.nodeByLabel.at(6)].firstCoord] - rs.x0[0];
  EXPECT_GT(deflection, 1e-3);  // a visible deflection (20 N on leaves of 0.525 N m^2)
  EXPECT_LT(sharedDifference(rs, sa.steps.back().x, fs, sb.steps.back().x), 1e-12);
  // A short simulation from rest under the constant force, with tolerances far below the
  // differences a wrong model would make: the same motion at the shared nodes.
  analysis::SimulationOptions o;
  o.tEnd = 2e-4;
  o.relTol = 1e-10;
  o.absTol = 1e-12;
  const core::Trajectory ta = analysis::simulate(rs, o);
  const core::Trajectory tb = analysis::simulate(fs, o);
  ASSERT_EQ(ta.time.size(), tb.time.size());
  const int x6 = rs.nodes[rs.nodeByLabel.at(6)].firstCoord;
  const double moved = ta.states.back().x[x6] - rs.x0[x6];
  EXPECT_GT(moved, 1e-7);  // F t^2 / (2 m) = 2.7e-7 m
  double d = 0.0;
  for (size_t k = 0; k < ta.states.size(); ++k)
    d = std::max(d, sharedDifference(rs, ta.states[k].x, fs, tb.states[k].x));
  EXPECT_LT(d, 1e-6 * moved);  // found 1e-14 m: round-off (frequencies and statics check the rest)
}

TEST(Refinement, StaticDeflectionConverges) {
  // The body's sideways deflection under a constant force, refined 1, 2, 4, 8: the differences
  // between successive meshes shrink (a beam's cubic is exact for end loads, so they are tiny).
  const std::string text = withStaticLoad(fileText("straight_guidance.dat"), 6);
  std::vector<double> u;
  for (int parts : {1, 2, 4, 8}) {
    const core::Model m = io::readDatString(text, "guidance_static.dat", refined(parts));
    const analysis::StaticRun s = analysis::staticAnalysis(m, 0);
    ASSERT_TRUE(s.completed);
    const int x6 = m.nodes[m.nodeByLabel.at(6)].firstCoord;
    u.push_back(s.steps.back().x[x6] - m.x0[x6]);
  }
  EXPECT_GT(u[0], 1e-3);
  for (size_t i = 2; i < u.size(); ++i)
    EXPECT_LE(std::abs(u[i] - u[i - 1]), std::abs(u[i - 1] - u[i - 2]) + 1e-15) << "refinement " << (1 << i);
  EXPECT_LT(std::abs(u[3] - u[0]), 1e-3 * u[0]);
}

TEST(Refinement, SpatialFrequenciesConvergeToTheFinerModel) {
  // The coarse cross-spring pivot (3 BEAMs per leaf, Euler-parameter nodes, the last beam of a leaf
  // released to close the loop, a rigid platform left whole) refined by 2 and by 4: each of its first
  // four frequencies comes closer to those of the file with 20 BEAMs per leaf at every refinement,
  // and the mass is unchanged (io/tests/test_mesh_refinement.cpp).
  std::vector<Eigen::VectorXd> f;
  for (int parts : {1, 2, 4}) {
    const core::Model m = io::readDatFile(dat("spatial/cross_spring_pivot_coarse.dat"), refined(parts));
    f.push_back(analysis::initialModes(m, std::nullopt, 4).frequencies.omega);
  }
  const Eigen::VectorXd fine =
      analysis::initialModes(io::readDatFile(dat("spatial/cross_spring_pivot.dat")), std::nullopt, 4).frequencies.omega;
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT(std::abs(f[1][i] - fine[i]), std::abs(f[0][i] - fine[i])) << "mode " << i + 1;
    EXPECT_LT(std::abs(f[2][i] - fine[i]), std::abs(f[1][i] - fine[i])) << "mode " << i + 1;
    EXPECT_LT(std::abs(f[2][i] - fine[i]), 2e-3 * fine[i]) << "mode " << i + 1;
  }
}

TEST(Refinement, WarpingBeamsConverge) {
  // The pivot with BEAMW leaves (a warping node at each end, its rate of twist a degree of freedom):
  // the new warping nodes are degrees of freedom too, and each refinement moves the first
  // frequencies less than the one before.
  std::vector<Eigen::VectorXd> f;
  std::vector<int> dofs;
  for (int parts : {1, 2, 4}) {
    const core::Model m = io::readDatFile(dat("spatial/cross_spring_pivot_beamw.dat"), refined(parts));
    dofs.push_back(m.numDofs());
    f.push_back(analysis::initialModes(m, std::nullopt, 3).frequencies.omega);
  }
  EXPECT_GT(dofs[1], dofs[0]);
  EXPECT_GT(dofs[2], dofs[1]);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(f[2][i] - f[1][i]), std::abs(f[1][i] - f[0][i])) << "mode " << i + 1;
    EXPECT_LT(std::abs(f[2][i] - f[0][i]), 1e-2 * f[0][i]) << "mode " << i + 1;
  }
}
