// What static reports for a designer (issue 53 item 1; analysis/StaticDesign.hpp) against beam theory:
//  - a cantilever's compliance at its tip and its middle: L/(EA), L^3/(3EI), L^2/(2EI), L/(EI)
//    (planar 3 x 3; spatial 6 x 6 with both bending planes and torsion L/(GIt));
//  - the support reactions balance the applied loads: sum of forces and of moments about the
//    support (in the deformed configuration) vanish, planar and spatial;
//  - the largest von Mises stress of a cantilever under a tip load is M c/I at the clamp (rectangle);
//    a circle under bending and torsion sqrt((M r/I)^2 + 3 (T r/Ip)^2); a square and a 1:10
//    rectangle under pure torsion sqrt(3) T/(k2 b h^2) with Roark's k2 = 0.208 and 0.312;
//  - the parallel leaf stage translates with compliance L^3/(24 EI), the cross-spring pivot turns with
//    L/(2 EI) (the shipped models without gravity);
//  - the .sbd variables under SPACAR Light's names have the shapes documented;
//  - a sweep's table has the same per configuration: a cantilever whose tip is held at a lateral
//    offset d carries P = 3 EI d / L^3 with M c / I at the clamp and reactions -P, -P L; one whose
//    tip is pulled along x through a first element with a rigid elongation (its axial force a
//    reaction stress) has the clamp's reaction -P and the stress P / A.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/StaticDesign.hpp"
#include "analysis/Statics.hpp"
#include "analysis/Study.hpp"
#include "analysis/Sweep.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

constexpr double kEA = 8.4e6, kEI = 2.8, kL = 1.0;

// A planar cantilever of n PLBEAMs along x (length kL), clamped at node 1 / 101, tip load (fx, fy)
// at node n+1 over one load step, a 20 x 2 mm rectangle (width 0.02 along y: the plane's normal).
std::string planarCantilever(int n, double fx, double fy) {
  std::ostringstream s;
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 100 + k << " " << k + 1 << " " << 101 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << kL * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 101\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 1 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " 0.312 1.04e-7\nESTIFF " << k << " " << kEA << " " << kEI << "\n";
  s << "DELXF " << n + 1 << " " << fx << " " << fy << "\nITERSTEP 10 1\nEND\nEND\n";
  s << "VISUALIZATION\nBEAMPROPS";
  for (int k = 1; k <= n; ++k) s << " " << k;
  s << "\nCROSSTYPE RECT\nCROSSDIM 0.02 0.002\n";
  return s.str();
}

// A spatial cantilever of n BEAMs along x, local y = global y; position nodes 1, 3, ..., orientation
// nodes 2, 4, ...; tip force F and moment M (DELXF on the tip's nodes).
constexpr double kGIt = 1.3, kEIy = 2.0, kEIz = 5.0;
std::string spatialCantilever(int n, const Eigen::Vector3d& F, const Eigen::Vector3d& M, const std::string& section) {
  std::ostringstream s;
  for (int k = 1; k <= n; ++k)
    s << "BEAM " << k << " " << 2 * k - 1 << " " << 2 * k << " " << 2 * k + 1 << " " << 2 * k + 2 << " 0 1 0\n";
  for (int k = 0; k <= n; ++k) s << "X " << 2 * k + 1 << " " << kL * k / n << " 0 0\n";
  s << "FIX 1\nFIX 2\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 1 2 3 4 5 6\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k)
    s << "EM " << k << " 0.3 1e-6 1e-6\nESTIFF " << k << " " << kEA << " " << kGIt << " " << kEIy << " " << kEIz
      << "\n";
  s << "DELXF " << 2 * n + 1 << " " << F[0] << " " << F[1] << " " << F[2] << "\n";
  s << "DELXF " << 2 * n + 2 << " " << M[0] << " " << M[1] << " " << M[2] << "\n";
  s << "ITERSTEP 10 2\nEND\nEND\n";
  if (!section.empty()) {
    s << "VISUALIZATION\nBEAMPROPS";
    for (int k = 1; k <= n; ++k) s << " " << k;
    s << "\n" << section;
  }
  return s.str();
}

analysis::StaticRun run(const core::Model& m) {
  analysis::StaticOptions o;
  o.nev = 0;
  return analysis::staticAnalysis(m, o);
}

double reaction(const std::vector<std::pair<std::string, double>>& r, const std::string& name) {
  for (const auto& [n, v] : r)
    if (n == name) return v;
  ADD_FAILURE() << "no reaction " << name;
  return NAN;
}

}  // namespace

TEST(StaticDesign, PlanarCantileverComplianceIsBeamTheory) {
  const core::Model m = io::readDatString(planarCantilever(4, 0.0, 0.0), "cantilever.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const auto c = analysis::nodeCompliances(m, r.steps.front(), {5, 3, 103});
  ASSERT_EQ(c.size(), 3u);
  // The tip: its position node named, its orientation node (105) joined.
  ASSERT_EQ(c[0].names, (std::vector<std::string>{"x", "y", "angle"}));
  const Eigen::MatrixXd& C = c[0].C;
  ASSERT_EQ(C.rows(), 3);
  EXPECT_NEAR(C(0, 0), kL / kEA, 1e-9 * kL / kEA);
  EXPECT_NEAR(C(1, 1), std::pow(kL, 3) / (3 * kEI), 1e-9);
  EXPECT_NEAR(C(1, 2), kL * kL / (2 * kEI), 1e-9);
  EXPECT_NEAR(C(2, 1), kL * kL / (2 * kEI), 1e-9);
  EXPECT_NEAR(C(2, 2), kL / kEI, 1e-9);
  EXPECT_NEAR(C(0, 1), 0.0, 1e-12);
  // The middle, named by position (3) or by orientation (103): the same a = L/2.
  const double a = kL / 2;
  for (int k : {1, 2}) {
    EXPECT_NEAR(c[k].C(1, 1), std::pow(a, 3) / (3 * kEI), 1e-9) << k;
    EXPECT_NEAR(c[k].C(2, 2), a / kEI, 1e-9) << k;
  }
  EXPECT_EQ(analysis::checkComplianceNodes(m, {5, 7}).find("node 7") != std::string::npos, true);
}

TEST(StaticDesign, SpatialCantileverComplianceIsBeamTheory) {
  const core::Model m =
      io::readDatString(spatialCantilever(4, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), ""), "c3d.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const auto c = analysis::nodeCompliances(m, r.steps.front(), {9});
  ASSERT_EQ(c.size(), 1u);
  ASSERT_EQ(c[0].names, (std::vector<std::string>{"x", "y", "z", "rx", "ry", "rz"}));
  const Eigen::MatrixXd& C = c[0].C;
  ASSERT_EQ(C.rows(), 6);
  const double L = kL, L2 = L * L, L3 = L2 * L;
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 6);
  expected(0, 0) = L / kEA;
  expected(1, 1) = L3 / (3 * kEIz), expected(1, 5) = expected(5, 1) = L2 / (2 * kEIz), expected(5, 5) = L / kEIz;
  expected(2, 2) = L3 / (3 * kEIy), expected(2, 4) = expected(4, 2) = -L2 / (2 * kEIy), expected(4, 4) = L / kEIy;
  expected(3, 3) = L / kGIt;
  EXPECT_LT((C - expected).cwiseAbs().maxCoeff(), 1e-9) << C;
}

TEST(StaticDesign, PlanarReactionsBalanceTheLoads) {
  const double fx = 3.0, fy = -0.2;
  const core::Model m = io::readDatString(planarCantilever(4, fx, fy), "cantilever.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const analysis::StaticStep& last = r.steps.back();
  const auto R = analysis::supportReactions(m, last);
  ASSERT_EQ(R.size(), 3u);
  EXPECT_NEAR(reaction(R, "R.F.node1.x") + fx, 0.0, 1e-9);
  EXPECT_NEAR(reaction(R, "R.F.node1.y") + fy, 0.0, 1e-9);
  // Moments about the clamp: the tip's deformed position.
  const double xt = last.x[m.nodes[m.nodeByLabel.at(5)].firstCoord],
               yt = last.x[m.nodes[m.nodeByLabel.at(5)].firstCoord + 1];
  EXPECT_GT(std::abs(yt), 1e-3);  // bent: the moment arm is not the initial one
  EXPECT_NEAR(reaction(R, "R.M.node101.angle") + (xt * fy - yt * fx), 0.0, 1e-9);
}

TEST(StaticDesign, SpatialReactionsBalanceTheLoads) {
  const Eigen::Vector3d F(0.5, -0.3, 0.4), M(0.05, 0.1, -0.08);
  const core::Model m = io::readDatString(spatialCantilever(6, F, M, ""), "c3d.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const analysis::StaticStep& last = r.steps.back();
  const auto R = analysis::supportReactions(m, last);
  ASSERT_EQ(R.size(), 6u);
  Eigen::Vector3d RF, RM;
  for (int c = 0; c < 3; ++c) {
    RF[c] = reaction(R, std::string("R.F.node1.") + "xyz"[c]);
    RM[c] = reaction(R, std::string("R.M.node2.") + "xyz"[c]);
  }
  const Eigen::Vector3d tip = last.x.segment<3>(m.nodes[m.nodeByLabel.at(13)].firstCoord);
  EXPECT_GT((tip - Eigen::Vector3d(kL, 0, 0)).norm(), 1e-2);
  EXPECT_LT((RF + F).norm(), 1e-9) << RF.transpose();
  EXPECT_LT((RM + M + tip.cross(F)).norm(), 1e-9) << RM.transpose();
}

TEST(StaticDesign, CantileverStressIsMcOverI) {
  const double P = 0.01;  // small: the arm stays L to 1e-5
  const core::Model m = io::readDatString(planarCantilever(4, 0.0, -P), "cantilever.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const double w = 0.02, t = 0.002, I = w * t * t * t / 12;
  const analysis::ElementStress top = analysis::largestStress(m, r.steps.back());
  ASSERT_GE(top.element, 0);
  EXPECT_EQ(m.elements[top.element].label, 1);
  EXPECT_NEAR(top.vonMises, P * kL * (t / 2) / I, 1e-4 * P * kL * (t / 2) / I);
  // Each element's largest stress is at its end nearer the clamp: M = P (L - x_p).
  const auto all = analysis::elementStresses(m, r.steps.back());
  ASSERT_EQ(all.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const double expected = P * (kL - 0.25 * k) * (t / 2) / I;
    EXPECT_NEAR(all[k].vonMises, expected, 1e-5 * expected) << k;
  }
  // The table: a column per element; the main table's max_stress.
  const io::CsvTable st = analysis::stressTable(m, r);
  EXPECT_EQ(st.columns.back(), "stress_PLBEAM4");
  const io::CsvTable main = analysis::staticTable(m, r, 0);
  const auto at = std::find(main.columns.begin(), main.columns.end(), "max_stress") - main.columns.begin();
  ASSERT_LT(static_cast<size_t>(at), main.columns.size());
  EXPECT_DOUBLE_EQ(main.rows.back()[static_cast<size_t>(at)], top.vonMises);
  EXPECT_EQ(main.rows.back()[static_cast<size_t>(at) + 1], 1.0);
}

TEST(StaticDesign, SectionVonMisesAgainstClosedForms) {
  core::ElementAppearance circle;
  circle.section = core::ElementAppearance::Section::Circle;
  circle.width = 0.01;
  const double r = 0.005, I = M_PI * std::pow(0.01, 4) / 64, Ip = 2 * I;
  analysis::SectionLoads L;
  L.My = 3.0, L.Mz = 4.0, L.T = 2.0;
  EXPECT_NEAR(analysis::sectionVonMises(circle, L), std::sqrt(std::pow(5.0 * r / I, 2) + 3 * std::pow(2.0 * r / Ip, 2)),
              1e-6);
  // Pure torsion of rectangles: tau_max = T / (k2 b h^2) at the middle of the long side (Roark).
  core::ElementAppearance rect;
  rect.section = core::ElementAppearance::Section::Rectangle;
  analysis::SectionLoads T;
  T.T = 1.0;
  for (const auto& [b, k2] : {std::pair{1.0, 0.208}, std::pair{10.0, 0.312}}) {
    rect.width = 0.01 * b, rect.thickness = 0.01;
    const double h = 0.01;
    const double expected = std::sqrt(3.0) / (k2 * (b * h) * h * h);
    EXPECT_NEAR(analysis::sectionVonMises(rect, T), expected, 3e-3 * expected) << b;
  }
  // Axial force and bending about both axes: the corner, N/A + My (t/2)/Iy + Mz (w/2)/Iz.
  rect.width = 0.03, rect.thickness = 0.01;
  analysis::SectionLoads NM;
  NM.N = 100.0, NM.My = 2.0, NM.Mz = -1.0;
  const double w = 0.03, t = 0.01;
  EXPECT_NEAR(analysis::sectionVonMises(rect, NM),
              100.0 / (w * t) + 2.0 * (t / 2) / (w * t * t * t / 12) + 1.0 * (w / 2) / (t * w * w * w / 12), 1e-3);
}

TEST(StaticDesign, SpacarVariablesHaveTheDocumentedShapes) {
  const Eigen::Vector3d F(0.0, 0.0, -0.01);  // small: the arm stays L to 1e-4
  const core::Model m =
      io::readDatString(spatialCantilever(4, F, Eigen::Vector3d::Zero(), "CROSSTYPE CIRC\nCROSSDIM 0.01\n"), "c.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const auto compliances = analysis::runCompliances(m, r, {9});
  const auto vars = analysis::spacarDesignVariables(m, r, compliances);
  std::map<std::string, const io::SpacarVariable*> byName;
  for (const auto& v : vars) byName[v.name] = &v;
  for (const char* n : {"stressmax", "stressel", "Freac", "Mreac", "CMglob_node9"}) ASSERT_TRUE(byName.count(n)) << n;
  const std::size_t tdef = 3;  // load steps 0, 1, 2
  EXPECT_EQ(byName["stressmax"]->dims, (std::vector<std::size_t>{1, tdef}));
  EXPECT_EQ(byName["stressel"]->dims, (std::vector<std::size_t>{4, tdef}));
  EXPECT_EQ(byName["Freac"]->dims, (std::vector<std::size_t>{3, tdef, 10}));
  EXPECT_EQ(byName["CMglob_node9"]->dims, (std::vector<std::size_t>{6, 6, tdef}));
  // Freac(3, last step, node 1) = -F_z; the largest stress M r / I at the clamp.
  EXPECT_NEAR(byName["Freac"]->data[2 * 3 + 2], 0.01, 1e-12);
  const double I = M_PI * std::pow(0.01, 4) / 64;
  EXPECT_NEAR(byName["stressmax"]->data[2], 0.01 * kL * 0.005 / I, 1e-3 * 0.01 * kL * 0.005 / I);
  // CMglob(3, 3, 1) = L^3 / (3 EIy).
  EXPECT_NEAR(byName["CMglob_node9"]->data[2 * 6 + 2], std::pow(kL, 3) / (3 * kEIy), 1e-9);
}

namespace {
// A shipped model without its GRAVITY line (the compliances of the bare flexure).
core::Model withoutGravity(const std::string& file) {
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/" + file);
  std::string text, line;
  while (std::getline(in, line))
    if (line.rfind("GRAVITY", 0) != 0) text += line + "\n";
  return io::readDatString(text, file);
}
constexpr double kLeafEI = 210e9 * 0.05 * 0.0002 * 0.0002 * 0.0002 / 12;  // the shipped leaves' E w t^3/12
}  // namespace

TEST(StaticDesign, ParallelLeafStageTranslatesWithCompliance1Over24EIOverL3) {
  // Two 50 mm leaves clamped at both ends (stage rigid): k = 2 x 12 EI/L^3 along x.
  const core::Model m = withoutGravity("parallel_leaf_stage.dat");
  const analysis::StaticRun r = run(m);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const auto c = analysis::nodeCompliances(m, r.steps.front(), {45});
  ASSERT_EQ(c.size(), 1u);
  ASSERT_EQ(c[0].C.rows(), 6);
  const double expected = std::pow(0.05, 3) / (24 * kLeafEI);
  EXPECT_NEAR(c[0].C(0, 0) / expected, 1.0, 1e-3) << c[0].C(0, 0);
}

TEST(StaticDesign, CrossSpringPivotTurnsWithComplianceLOver2EI) {
  // Leaves of L = 0.1 sqrt(2) crossing at their middles: each end turning about the crossing point
  // takes M = EI theta / L per leaf (clamped-guided with the end's lateral motion theta L/2).
  const core::Model m = withoutGravity("cross_spring_pivot.dat");
  analysis::StaticOptions o;
  o.nev = 0, o.loadSteps = 1;
  const analysis::StaticRun r = analysis::staticAnalysis(m, o);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const auto c = analysis::nodeCompliances(m, r.steps.front(), {3});
  ASSERT_EQ(c.size(), 1u);
  ASSERT_EQ(c[0].names.back(), "rz");
  const double expected = std::hypot(0.1, 0.1) / (2 * kLeafEI);
  EXPECT_NEAR(c[0].C(5, 5) / expected, 1.0, 1e-6) << c[0].C(5, 5);
}

TEST(StaticDesign, StudyReportsTheLargestStress) {
  const core::Model m = io::readDatString(planarCantilever(4, 0.0, -0.01), "cantilever.dat");
  analysis::StudyAnalyses a;
  analysis::StaticOptions o;
  o.nev = 0;
  a.statics = o;
  const analysis::VariantResults v = analysis::runVariant(m, a);
  ASSERT_TRUE(v.failure.empty()) << v.failure;
  const double I = 0.02 * 0.002 * 0.002 * 0.002 / 12, expected = 0.01 * kL * 0.001 / I;
  bool found = false;
  for (const auto& [name, value] : v.quantities)
    if (name == "max_stress") {
      found = true;
      EXPECT_NEAR(value, expected, 1e-4 * expected);
    }
  EXPECT_TRUE(found);
}

namespace {

// Column `name` of a table, every row.
std::vector<double> column(const io::CsvTable& t, const std::string& name) {
  const auto at = std::find(t.columns.begin(), t.columns.end(), name) - t.columns.begin();
  std::vector<double> v;
  if (static_cast<size_t>(at) == t.columns.size()) return v;
  for (const auto& row : t.rows) v.push_back(row[static_cast<size_t>(at)]);
  return v;
}

}  // namespace

TEST(StaticDesign, SweepReportsStressAndReactionsPerConfiguration) {
  const double w = 0.02, t = 0.002, I = w * t * t * t / 12, A = w * t;
  // Bending: the tip (node 5) held at y = d; P = 3 EI d / L^3.
  const core::Model bent = io::readDatString(planarCantilever(4, 0.0, 0.0), "bent.dat");
  analysis::SweepOptions o;
  o.node = 5, o.component = 2, o.from = 0.0, o.to = 1e-3, o.steps = 3, o.nev = 2;
  const analysis::SweepResult r = analysis::sweep(bent, o);
  ASSERT_TRUE(r.completed) << r.stopReason;
  const io::CsvTable table = analysis::sweepTable(bent, r);
  const auto load = column(table, "load"), stress = column(table, "max_stress"),
             element = column(table, "max_stress_element"), ry = column(table, "R.F.node1.y"),
             mz = column(table, "R.M.node101.angle");
  ASSERT_EQ(stress.size(), 3u);
  ASSERT_EQ(ry.size(), 3u);
  ASSERT_EQ(mz.size(), 3u);
  const double P = load.back();
  EXPECT_NEAR(P, 3 * kEI * 1e-3 / (kL * kL * kL), 1e-4 * P);
  EXPECT_NEAR(stress.back(), P * kL * (t / 2) / I, 1e-4 * P * kL * (t / 2) / I);
  EXPECT_EQ(element.back(), 1.0);
  EXPECT_NEAR(ry.back(), -P, 1e-9 * P);
  EXPECT_NEAR(mz.back(), -P * kL, 1e-5 * P * kL);
  EXPECT_EQ(stress.front(), 0.0);  // at the start nothing holds the tip
  // Axial: the first element's elongation rigid, the tip pulled along x by d; the others stretch.
  std::string text = planarCantilever(4, 0.0, 0.0);
  const std::string dyne1 = "DYNE 1 1 2 3\n";
  ASSERT_NE(text.find(dyne1), std::string::npos);
  text.replace(text.find(dyne1), dyne1.size(), "DYNE 1 2 3\n");
  const core::Model pulled = io::readDatString(text, "pulled.dat");
  o.component = 1, o.from = kL, o.to = kL + 1e-6;
  const analysis::SweepResult ra = analysis::sweep(pulled, o);
  ASSERT_TRUE(ra.completed) << ra.stopReason;
  const io::CsvTable ta = analysis::sweepTable(pulled, ra);
  const double Pa = column(ta, "load").back();
  EXPECT_NEAR(Pa, kEA * 1e-6 / (0.75 * kL), 1e-6 * Pa);  // three elements of L/4 in series
  EXPECT_NEAR(column(ta, "R.F.node1.x").back(), -Pa, 1e-9 * Pa);
  EXPECT_NEAR(column(ta, "max_stress").back(), Pa / A, 1e-6 * Pa / A);
}
