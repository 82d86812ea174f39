// Design studies (analysis/Study.hpp): variant expansion, task shares, the per-variant analyses and
// their summary quantities against theory, failures recorded with their reason, resume bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "analysis/Study.hpp"
#include "io/formats/DatReader.hpp"
#include "io/templates/ModelTemplate.hpp"

using namespace flexmb;
using analysis::StudyAnalyses;

namespace {
// The static analysis of a study (flexmb static's options).
analysis::StaticOptions statics(int nev = 6, int loadSteps = 0, int buckling = 0) {
  analysis::StaticOptions o;
  o.nev = nev, o.loadSteps = loadSteps, o.buckling = buckling;
  return o;
}

double quantity(const analysis::VariantResults& r, const std::string& name) {
  for (const auto& [n, v] : r.quantities)
    if (n == name) return v;
  ADD_FAILURE() << "no quantity " << name;
  return NAN;
}

// The tutorial cantilever (datfiles/cantilever.dat): L = 1, EI = 2.8, EA = 8.4e6, rhoA = 0.312,
// tip load 0.1 N along -y.
core::Model cantilever() { return io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/cantilever.dat"); }

// A spatial cantilever of n BEAMs along x with a tip force F (DELXF, one step).
std::string spatialCantilever(int n, double Fx, double Fy) {
  std::ostringstream s;
  for (int i = 1; i <= n + 1; ++i) s << "X " << 2 * i - 1 << " " << static_cast<double>(i - 1) / n << " 0 0\n";
  for (int e = 1; e <= n; ++e)
    s << "BEAM " << e << " " << 2 * e - 1 << " " << 2 * e << " " << 2 * e + 1 << " " << 2 * e + 2 << " 0 1 0\n";
  for (int e = 1; e <= n; ++e) s << "DYNE " << e << " 1 2 3 4 5 6\n";
  s << "FIX 1\nFIX 2\nEND\nHALT\n";
  for (int e = 1; e <= n; ++e) s << "ESTIFF " << e << " 1e7 1 2 3 0 0\nEM " << e << " 1 1e-3 1e-3 1e-3 0\n";
  s << "DELXF " << 2 * n + 1 << " " << Fx << " " << Fy << " 0\nITERSTEP 50 1\nEND\nEND\n";
  return s.str();
}

// Tangent stiffness along a cantilever (length L) bent by a tip load P across: the axial compliance
// L/EA plus the lever of the bent shape, int_0^L (y(L) - y(s))^2 ds / EI = (P/(6 EI))^2 (68/35) L^7 / EI.
double bentAxialStiffness(double L, double EA, double EI, double P) {
  const double a = P / (6 * EI);
  return 1.0 / (L / EA + a * a * 68.0 / 35.0 * std::pow(L, 7) / EI);
}

}  // namespace

TEST(Study, GridExpansionIsNestedLoopsInOrder) {
  const std::vector<io::ParameterAxis> grid = {{"t", {1, 2, 3}}, {"w", {10, 20}}};
  const auto v = analysis::expandVariants(nullptr, grid);
  ASSERT_EQ(v.size(), 6u);
  EXPECT_EQ(v[0].name, "v0001");
  EXPECT_EQ(v[5].number, 6);
  EXPECT_EQ(v[5].name, "v0006");
  EXPECT_EQ(v[1].values, (io::ParameterValues{{"t", 1}, {"w", 20}}));  // the last axis fastest
  EXPECT_EQ(v[2].values, (io::ParameterValues{{"t", 2}, {"w", 10}}));
}

TEST(Study, TableRowsTimesGrid) {
  const io::ParameterTable t = io::parseParameterTable("name,L\nshort,0.1\nlong,0.2\n", "p.csv");
  const auto v = analysis::expandVariants(&t, {{"t", {1, 2}}});
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[0].name, "short_1");
  EXPECT_EQ(v[3].name, "long_2");
  EXPECT_EQ(v[3].values, (io::ParameterValues{{"L", 0.2}, {"t", 2}}));
  const io::ParameterTable u = io::parseParameterTable("t\n1\n2\n3\n", "p.csv");
  const auto w = analysis::expandVariants(&u, {});
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[2].name, "v0003");
  EXPECT_EQ(w[2].values, (io::ParameterValues{{"t", 3}}));
}

TEST(Study, ExpansionErrors) {
  const io::ParameterTable t = io::parseParameterTable("t\n1\n", "p.csv");
  EXPECT_THROW(analysis::expandVariants(&t, {{"t", {1}}}), std::invalid_argument);
  EXPECT_THROW(analysis::expandVariants(nullptr, {{"t", {1}}, {"t", {2}}}), std::invalid_argument);
  EXPECT_THROW(analysis::expandVariants(nullptr, {}), std::invalid_argument);
  const io::ParameterAxis big{"a", std::vector<double>(1001, 1.0)};
  EXPECT_THROW(analysis::expandVariants(nullptr, {big, big}), std::invalid_argument);  // 1e6 + 2001 > limit
  const io::ParameterTable named = io::parseParameterTable("name,t\nv0002,1\nx,2\n", "p.csv");
  EXPECT_NO_THROW(analysis::expandVariants(&named, {}));  // every row named: no generated names
  const io::ParameterTable clash = io::parseParameterTable("name,t\nv0002,1\n,2\n", "p.csv");
  EXPECT_THROW(analysis::expandVariants(&clash, {}), std::invalid_argument);  // row 2 is v0002 too
}

TEST(Study, TaskSharesPartitionTheVariants) {
  for (int of : {1, 2, 3, 7, 25}) {
    std::multiset<int> all;
    for (int task = 0; task < of; ++task)
      for (int k : analysis::taskShare(20, task, of)) all.insert(k);
    EXPECT_EQ(all.size(), 20u) << of;
    for (int k = 0; k < 20; ++k) EXPECT_EQ(all.count(k), 1u) << of;
  }
  EXPECT_EQ(analysis::taskShare(10, 1, 3), (std::vector<int>{1, 4, 7}));
  EXPECT_THROW(analysis::taskShare(10, 3, 3), std::invalid_argument);
  EXPECT_THROW(analysis::taskShare(10, 0, 0), std::invalid_argument);
}

TEST(Study, CantileverQuantitiesAgainstBeamTheory) {
  const core::Model m = cantilever();
  StudyAnalyses a;
  a.check = true;
  a.modes = 3;
  a.statics = statics(2, 0, 1);
  const auto r = analysis::runVariant(m, a);
  ASSERT_EQ(r.failure, "");
  EXPECT_EQ(quantity(r, "dofs"), 12);
  ASSERT_TRUE(r.check);
  EXPECT_EQ(r.check->xCalculable, 12);
  EXPECT_EQ(quantity(r, "rank"), 12);  // every calculable coordinate determined
  // f1 = 1.8751^2 / (2 pi) sqrt(EI / (rhoA L^4)) (Euler-Bernoulli).
  const double f1 = 1.87510407 * 1.87510407 / (2 * M_PI) * std::sqrt(2.8 / 0.312);
  EXPECT_NEAR(quantity(r, "f1_Hz") / f1, 1.0, 2e-3);
  EXPECT_NEAR(quantity(r, "static_f1_Hz") / f1, 1.0, 5e-3);
  // Tip deflection P L^3 / (3 EI) and the tip's tangent stiffness 3 EI / L^3 across; along the beam
  // the bent shape y(s) = P s^2 (3L - s) / (6 EI) makes a lever: C = L/EA + int (y(L) - y(s))^2 ds / EI.
  EXPECT_NEAR(quantity(r, "max_displacement") / (0.1 / (3 * 2.8)), 1.0, 2e-3);
  EXPECT_NEAR(quantity(r, "k_node5_y") / (3 * 2.8), 1.0, 2e-3);
  EXPECT_NEAR(quantity(r, "k_node5_x") / bentAxialStiffness(1.0, 8.4e6, 2.8, 0.1), 1.0, 2e-3);
  EXPECT_NEAR(quantity(r, "max_bending_moment") / (0.1 * 1.0), 1.0, 2e-3);  // P L at the root
  EXPECT_EQ(quantity(r, "static_steps"), 2);  // SPACAR's load steps 0 (unloaded) and 1 (the XF)
  // A tip load across the cantilever is far from buckling it.
  EXPECT_GT(quantity(r, "buckling1"), 1e3);
}

TEST(Study, SpatialCantileverStressesAndStiffness) {
  // Tip force across: the root moment is P L; along: the axial force is P.
  const core::Model across = io::readDatString(spatialCantilever(4, 0, -1e-3), "c.dat");
  StudyAnalyses a;
  a.statics = statics(0, 0, 0);
  a.stiffnessNodes = {9, 10};
  const auto r = analysis::runVariant(across, a);
  ASSERT_EQ(r.failure, "");
  // Bending in the x-y plane is about the section's local z (the y vector is global y).
  EXPECT_NEAR(quantity(r, "max_bending_moment_z"), 1e-3, 1e-3 * 1e-3);
  EXPECT_LT(quantity(r, "max_bending_moment_y"), 1e-9);
  EXPECT_LT(quantity(r, "max_torsion_moment"), 1e-9);
  EXPECT_LT(quantity(r, "max_axial_force"), 1e-6);               // P times the tip slope
  EXPECT_NEAR(quantity(r, "k_node9_y") / (3 * 3.0), 1.0, 1e-3);  // 3 EIz / L^3 (bending in the x-y plane)
  EXPECT_NEAR(quantity(r, "k_node9_z") / (3 * 2.0), 1.0, 1e-3);  // 3 EIy / L^3
  EXPECT_NEAR(quantity(r, "k_node9_x") / bentAxialStiffness(1.0, 1e7, 3.0, 1e-3), 1.0, 1e-3);
  EXPECT_NEAR(quantity(r, "k_node10_rx") / 1.0, 1.0, 1e-3);  // GIt / L
  // The tip's rotation with its displacement free: 4 EI/L - (6 EI/L^2)^2 / (12 EI/L^3) = EI / L.
  EXPECT_NEAR(quantity(r, "k_node10_rz") / 3.0, 1.0, 1e-3);
  EXPECT_NEAR(quantity(r, "k_node10_ry") / 2.0, 1.0, 1e-3);
  const core::Model along = io::readDatString(spatialCantilever(4, 2.0, 0), "c.dat");
  const auto s = analysis::runVariant(along, a);
  ASSERT_EQ(s.failure, "");
  EXPECT_NEAR(quantity(s, "max_axial_force"), 2.0, 2e-6);
}

TEST(Study, PivotRotationalStiffnessIsTwoEIOverL) {
  // The cross-spring pivot's tangent stiffness about z at the platform (Euler-parameter node 4)
  // against theory (2 EI/L, see SpatialModels.CrossSpringPivotRotationalStiffness) and against the
  // secant stiffness of its own static rotation.
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot.dat");
  std::ostringstream text;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("GRAVITY", 0) == 0 || line.rfind("DELXF", 0) == 0 || line.rfind("XF", 0) == 0) continue;
    if (line.rfind("ITERSTEP", 0) == 0) line = "ITERSTEP 10 1\nDELXF 4 0 0 1e-4";
    text << line << "\n";
  }
  const core::Model m = io::readDatString(text.str(), "pivot.dat");
  StudyAnalyses a;
  a.statics = statics(0, 0, 0);
  const auto r = analysis::runVariant(m, a);
  ASSERT_EQ(r.failure, "");
  const double ref = 2 * 7.0e-3 / (0.1 * std::sqrt(2.0));
  EXPECT_NEAR(quantity(r, "k_node4_rz") / ref, 1.0, 1e-3);
  const Eigen::VectorXd& x = r.statics->steps.back().x;
  const int at = m.nodes[m.nodeByLabel.at(4)].firstCoord;
  const double theta = 2 * std::atan2(x[at + 3], x[at]);
  EXPECT_NEAR(quantity(r, "k_node4_rz") / (1e-4 / theta), 1.0, 1e-4);
  EXPECT_NEAR(quantity(r, "max_bending_moment_y") / 5e-5, 1.0, 1e-3);  // each leaf carries half the moment
  // The support stiffnesses are orders of magnitude above the rotational one.
  EXPECT_GT(quantity(r, "k_node4_rx"), 1e3 * ref);
}

TEST(Study, FailuresAreRecordedWithTheirReason) {
  // Modes without mass: recorded, the later analyses do not run, the record says why.
  const core::Model m = io::readDatString(spatialCantilever(2, 0, -1), "c.dat");
  StudyAnalyses a;
  a.modes = 2;
  a.statics = statics();
  core::Model massless =
      io::readDatString(std::regex_replace(spatialCantilever(2, 0, -1), std::regex("EM [^\n]*\n"), ""), "c.dat");
  const auto r = analysis::runVariant(massless, a);
  EXPECT_NE(r.failure.find("no mass on 12 of 12 degrees of freedom"), std::string::npos) << r.failure;
  EXPECT_FALSE(r.statics);
  const analysis::Variant v{3, "v0003", {{"t", 1}}};
  const io::StudyRecord rec = analysis::summaryRecord(v, r);
  EXPECT_EQ(rec.status, "failed");
  EXPECT_EQ(rec.reason, r.failure);
  // A static analysis that stops (no stiffness: the load finds no equilibrium): failed, with the
  // load factor in the reason.
  StudyAnalyses s;
  s.statics = statics(0, 0, 0);
  const core::Model soft =
      io::readDatString(std::regex_replace(spatialCantilever(2, 0, -1), std::regex("ESTIFF [^\n]*\n"), ""), "c.dat");
  const auto q = analysis::runVariant(soft, s);
  EXPECT_EQ(q.failure.rfind("static: no equilibrium beyond load factor 0", 0), 0u) << q.failure;
  ASSERT_FALSE(q.notes.empty());
  EXPECT_NE(q.notes.front().find("without stiffness"), std::string::npos);
  EXPECT_EQ(quantity(q, "static_steps"), 0);
  // The derived quantities: evaluated from parameters and quantities; an unknown name fails.
  StudyAnalyses d;
  d.modes = 1;
  d.derived = {{"twice", "2*f1_Hz*t"}};
  const auto ok = analysis::runVariant(m, d, {{"t", 3}});
  ASSERT_EQ(ok.failure, "");
  EXPECT_DOUBLE_EQ(quantity(ok, "twice"), 6 * quantity(ok, "f1_Hz"));
  d.derived = {{"bad", "2*f9_Hz"}};
  const auto bad = analysis::runVariant(m, d, {{"t", 3}});
  EXPECT_NE(bad.failure.find("derived quantity bad: unknown name 'f9_Hz'"), std::string::npos) << bad.failure;
}

TEST(Study, FingerprintsAndManifestStates) {
  StudyAnalyses a;
  a.modes = 6;
  const std::string f = analysis::variantFingerprint("X {t}", {{"t", 1}}, a, "0.1");
  EXPECT_EQ(f.size(), 16u);
  EXPECT_EQ(f, analysis::variantFingerprint("X {t}", {{"t", 1}}, a, "0.1"));
  EXPECT_NE(f, analysis::variantFingerprint("X {t} ", {{"t", 1}}, a, "0.1"));
  EXPECT_NE(f, analysis::variantFingerprint("X {t}", {{"t", 2}}, a, "0.1"));
  StudyAnalyses b = a;
  b.statics = statics();
  EXPECT_NE(f, analysis::variantFingerprint("X {t}", {{"t", 1}}, b, "0.1"));
  const std::string dir =
      (std::filesystem::temp_directory_path() / std::string("study_state_").append(std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(dir);
  const std::string manifest = dir + "/m_run.txt", summary = dir + "/m_summary.csv";
  EXPECT_EQ(analysis::variantState(manifest, f, summary), analysis::VariantState::NotRun);
  std::ofstream(manifest) << "flexmb run\nstatus: complete\nfingerprint: " << f << "\n";
  // A manifest beside a missing or empty summary (a power failure after an unsynced commit): run again.
  EXPECT_EQ(analysis::variantState(manifest, f, summary), analysis::VariantState::NotRun);
  std::ofstream(summary) << "";
  EXPECT_EQ(analysis::variantState(manifest, f, summary), analysis::VariantState::NotRun);
  std::ofstream(summary) << "variant,name,t,status,f1_Hz,reason\n1,v0001,1,ok,2.5,\n";
  EXPECT_EQ(analysis::variantState(manifest, f, summary), analysis::VariantState::Finished);
  EXPECT_EQ(analysis::variantState(manifest, "0000", summary), analysis::VariantState::Stale);
  std::ofstream(manifest) << "flexmb run\nstatus: failed: no mass\nfingerprint: " << f << "\n";
  EXPECT_EQ(analysis::variantState(manifest, f, summary), analysis::VariantState::FinishedFailed);
  std::filesystem::remove_all(dir);
}

TEST(Study, PivotTemplateAtTwoTenthsOfAMillimetreIsTheCoarsePivot) {
  // datfiles/spatial/cross_spring_pivot_study.dat computes the leaves' ESTIFF and EM from t; at
  // t = 0.2 mm the model is cross_spring_pivot_coarse.dat (GIt there from SPACAR Light's series,
  // 1e-6 apart), so every summary quantity agrees.
  const std::string dir = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/";
  const io::ModelTemplate t = io::ModelTemplate::fromFile(dir + "cross_spring_pivot_study.dat");
  t.check({"t"});
  const core::Model fromTemplate = io::readDatString(t.instantiate({{"t", 2e-4}}), "pivot.dat");
  const core::Model coarse = io::readDatFile(dir + "cross_spring_pivot_coarse.dat");
  StudyAnalyses a;
  a.modes = 6;
  a.statics = statics(6, 0, 2);
  const auto r = analysis::runVariant(fromTemplate, a), c = analysis::runVariant(coarse, a);
  ASSERT_EQ(r.failure, "");
  ASSERT_EQ(c.failure, "");
  ASSERT_EQ(r.quantities.size(), c.quantities.size());
  for (size_t i = 0; i < r.quantities.size(); ++i) {
    EXPECT_EQ(r.quantities[i].first, c.quantities[i].first);
    EXPECT_NEAR(r.quantities[i].second, c.quantities[i].second, 1e-5 * std::abs(c.quantities[i].second) + 1e-12)
        << r.quantities[i].first;
  }
}
