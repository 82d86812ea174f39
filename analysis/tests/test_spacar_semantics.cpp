// SPACAR's semantics in the analyses (issue 10): SPACAR95 blocks run in sequence carrying the state,
// SPACAR95 time origin, restart from the echoed end-of-run state, and load steps whose DEL*
// increments are totals reached at the last step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "analysis/Simulation.hpp"
#include "analysis/Statics.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/RestartWriter.hpp"

using namespace flexmb;

namespace {

std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

int xIndex(const core::Model& m, int node, int comp) {
  return m.nodes.at(m.nodeByLabel.at(node)).firstCoord + comp - 1;
}

std::vector<const core::Model*> running(const std::vector<io::AnalysisStage>& stages) {
  std::vector<const core::Model*> r;
  for (const auto& s : stages)
    if (s.runs) r.push_back(&s.model);
  return r;
}

// Largest difference of x and e between two trajectories at their common output times.
struct Difference {
  double x = 0.0, e = 0.0;
  int compared = 0;
};
Difference compare(const core::Trajectory& a, const core::Trajectory& b) {
  Difference d;
  for (size_t i = 0; i < a.time.size(); ++i)
    for (size_t j = 0; j < b.time.size(); ++j)
      if (std::abs(a.time[i] - b.time[j]) < 1e-9) {
        d.x = std::max(d.x, (a.states[i].x - b.states[j].x).cwiseAbs().maxCoeff());
        d.e = std::max(d.e, (a.states[i].e - b.states[j].e).cwiseAbs().maxCoeff());
        ++d.compared;
      }
  return d;
}

// The run from the echo (second) against one run of the first model to tEnd with `intervals`
// output intervals.
Difference continuedAgainstOneRun(const core::Model& first, const core::Model& second,
                                  const analysis::SimulationOptions& o, double tEnd, int intervals) {
  const core::Trajectory b = analysis::simulate(second, o);
  EXPECT_TRUE(b.completed) << b.stopReason;
  analysis::SimulationOptions full = o;
  full.tEnd = tEnd;
  full.intervals = intervals;
  const core::Trajectory c = analysis::simulate(first, full);
  EXPECT_TRUE(c.completed) << c.stopReason;
  return compare(b, c);
}

std::string readAll(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  std::string s;
  if (!f) return s;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
  std::fclose(f);
  return s;
}

// A flexible pendulum in SPACAR 2013+ form: two PLBEAMs hanging from a hinge, gravity, a tip mass.
const char* kPendulum2013 =
    "# flexible double pendulum (SPACAR 2013+)\n"
    "PLBEAM 1 1 11 2 12\nPLBEAM 2 2 12 3 13\nPLHINGE 3 10 11\n"
    "X 1 0 0\nX 2 0.5 0\nX 3 1.0 0\n"
    "FIX 1\nFIX 10\nDYNE 3 1\nDYNE 1 2 3\nDYNE 2 2 3\n"
    "END\nHALT\n"
    "EM 1 0.4 1e-4\nEM 2 0.4 1e-4\nXM 3 0.1\nESTIFF 1 1e6 40\nESTIFF 2 1e6 40\nEDAMP 1 0 0.01\nEDAMP 2 0 0.01\n"
    "GRAVITY 0 -9.81\nERROR 1e-8 1e-6\nTIMESTEP 1.0 20\nEND\nEND\n";

}  // namespace

// Item 3 acceptance: 0 to 5 s, then a restart from the echoed state to 10 s, equals one run 0 to
// 10 s to the integrator's tolerance (positions and deformations). SPACAR95: the slider-crank.
TEST(Restart, Spacar95RestartFromEchoEqualsOneRun) {
  const core::Model first = io::readDatFile(dat("slider_crank_s95.dat"));
  ASSERT_DOUBLE_EQ(first.settings.tEnd, 5.0);
  analysis::SimulationOptions o;
  const core::Trajectory a = analysis::simulate(first, o);
  ASSERT_TRUE(a.completed) << a.stopReason;
  const std::string echo = io::restartText(first, a.time.back(), a.states.back());
  // The echo also writes the accelerations of the dynamic deformations (EDD), as the SPACAR95
  // manual's echo does; reading it back accepts them (the equations of motion give them).
  int echoed = 0;
  for (const auto& el : first.elements)
    for (int k = 0; el.impl && k < el.impl->numDeformations(); ++k) {
      const int di = el.firstDef + k;
      if (first.eRole[di] != core::Role::Dynamic) continue;
      const std::string key = "EDD " + std::to_string(el.label) + " " + std::to_string(k + 1) + " ";
      const std::size_t at = echo.find(key);
      ASSERT_NE(at, std::string::npos) << "no " << key << "in the echo:\n" << echo;
      const double v = std::stod(echo.substr(at + key.size()));
      EXPECT_NEAR(v, a.states.back().edd[di], 1e-12 * std::max(1.0, std::abs(v))) << key;
      ++echoed;
    }
  EXPECT_EQ(echoed, 4);
  const auto stages = io::readDatStagesString(echo, "echo.dat");
  ASSERT_EQ(stages.size(), 1u);
  const core::Model& second = stages[0].model;
  EXPECT_TRUE(second.restartState);
  EXPECT_EQ(second.dialect, core::Dialect::Spacar95);
  EXPECT_DOUBLE_EQ(second.settings.t0, 5.0);
  EXPECT_DOUBLE_EQ(second.settings.tEnd, 10.0);
  const Difference d = continuedAgainstOneRun(first, second, o, 10.0, 1000);
  EXPECT_EQ(d.compared, 501);
  // EPSINT 1e-6 (relative and absolute); positions ~0.5 m, the crank angle grows to ~40 rad.
  EXPECT_LT(d.x, 1e-5) << "positions differ by " << d.x;
  EXPECT_LT(d.e, 1e-5) << "deformations differ by " << d.e;
  std::printf("  SPACAR95 restart at 5 s vs one run to 10 s: max |dx| = %.3g, max |de| = %.3g\n", d.x, d.e);
}

// The same in SPACAR 2013+ form (XM/EM/XF/STARTDE/GRAVITY/ERROR/ITERSTEP): a flexible pendulum.
TEST(Restart, Spacar2013RestartFromEchoEqualsOneRun) {
  const core::Model first = io::readDatString(kPendulum2013, "pendulum.dat");
  analysis::SimulationOptions o;
  const core::Trajectory a = analysis::simulate(first, o);
  ASSERT_TRUE(a.completed) << a.stopReason;
  const std::string echo = io::restartText(first, a.time.back(), a.states.back());
  const auto stages = io::readDatStagesString(echo, "echo.dat");
  const core::Model& second = stages.back().model;
  EXPECT_EQ(second.dialect, core::Dialect::Spacar2013);
  EXPECT_DOUBLE_EQ(second.settings.t0, 1.0);
  EXPECT_DOUBLE_EQ(second.settings.tEnd, 2.0);
  const Difference d = continuedAgainstOneRun(first, second, o, 2.0, 40);
  EXPECT_EQ(d.compared, 21);
  EXPECT_LT(d.x, 1e-5) << d.x;
  EXPECT_LT(d.e, 1e-5) << d.e;
  std::printf("  SPACAR 2013+ restart at 1 s vs one run to 2 s: max |dx| = %.3g, max |de| = %.3g\n", d.x, d.e);
}

// Item 1: SPACAR95 blocks run in sequence and carry the state: two blocks of 2.5 s equal one of 5 s.
TEST(Spacar95Stages, TwoBlocksEqualOneRun) {
  std::string text = readAll(dat("slider_crank_s95.dat"));
  const auto cut = text.find("TIMESTEP  500   5.0");
  ASSERT_NE(cut, std::string::npos);
  text.replace(cut, 19, "TIMESTEP  250   2.5");
  const auto eof = text.rfind("EOF");
  text.insert(eof, "* a later block: a role restated, the same period again\nDYNE 3 1\nTIMESTEP 250 2.5\nEND\n");
  const auto stages = io::readDatStagesString(text, "two_blocks.dat");
  const auto runs = running(stages);
  ASSERT_EQ(runs.size(), 2u);
  analysis::SimulationOptions o;
  const core::Trajectory two = analysis::simulateStages(runs, o);
  ASSERT_TRUE(two.completed) << two.stopReason;
  EXPECT_EQ(two.time.size(), 501u);  // 2 x 250 intervals, the shared time once
  EXPECT_DOUBLE_EQ(two.time.back(), 5.0);
  const core::Trajectory one = analysis::simulate(io::readDatFile(dat("slider_crank_s95.dat")), o);
  const Difference d = compare(two, one);
  EXPECT_EQ(d.compared, 501);
  EXPECT_LT(d.x, 1e-5) << d.x;
  EXPECT_LT(d.e, 1e-5) << d.e;
}

// Items 1 and 2: a driven crank (input angle), one block with everything, a later block changes the
// rate from the current time on; TIME moves the time origin of x + v (t - TIME).
TEST(Spacar95Stages, InputRateChangesFromTheCurrentTime) {
  const auto stages = io::readDatStages(std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/manual_style_s95.dat");
  const auto runs = running(stages);
  ASSERT_EQ(runs.size(), 2u);
  const core::Trajectory tr = analysis::simulateStages(runs, {});
  ASSERT_TRUE(tr.completed) << tr.stopReason;
  ASSERT_EQ(tr.time.size(), 41u);
  const int crank = xIndex(*runs[0], 12, 1);
  for (size_t k = 0; k < tr.time.size(); ++k) {
    const double t = tr.time[k];
    const double expect = t <= 0.5 ? 2 * M_PI * t : M_PI + M_PI * (t - 0.5);
    EXPECT_NEAR(tr.states[k].x[crank], expect, 1e-12) << "t = " << t;
    EXPECT_NEAR(tr.states[k].xd[crank], t <= 0.5 + 1e-12 && k <= 20 ? 2 * M_PI : M_PI, 1e-12) << "t = " << t;
  }
  // TIME 2: the same motion shifted in time.
  std::string text = readAll(std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/manual_style_s95.dat");
  text.insert(text.find("TIMESTEP  20"), "TIME 2.0\n");
  const auto shiftedStages = io::readDatStagesString(text, "shifted.dat");
  const auto shifted = running(shiftedStages);
  const core::Trajectory ts = analysis::simulateStages(shifted, {});
  ASSERT_TRUE(ts.completed) << ts.stopReason;
  ASSERT_EQ(ts.time.size(), tr.time.size());
  EXPECT_DOUBLE_EQ(ts.time.front(), 2.0);
  EXPECT_DOUBLE_EQ(ts.time.back(), 2.75);
  for (size_t k = 0; k < ts.time.size(); ++k) {
    EXPECT_NEAR(ts.time[k], tr.time[k] + 2.0, 1e-12);
    EXPECT_NEAR((ts.states[k].x - tr.states[k].x).cwiseAbs().maxCoeff(), 0.0, 1e-6);
  }
}

namespace {
// Clamped-free beam of n PLBEAMs along +x, all deformations DYNE (2013+: Eq. 3a elongation), EI = 1,
// EA = 1e7, a tip load P perpendicular to the undeformed beam given as the DELXF total.
std::string elasticaCantilever(int n, double P, int steps, const std::string& load) {
  std::ostringstream s;
  s.precision(17);
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 100 + k << " " << k + 1 << " " << 101 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << static_cast<double>(k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 101\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 1 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "ESTIFF " << k << " 1e7 1\n";
  s << load << " " << n + 1 << " 0 " << -P << "\n";
  s << "ITERSTEP 50 " << steps << " 1e-10\nEND\nEND\n";
  return s.str();
}
}  // namespace

// Item 5 acceptance: DELXF over 10 steps reaches the elastica for the TOTAL load at the last step
// (P L^2 / EI = 10: tip deflection 0.81061 L, Bisshopp & Drucker), within 0.5% with 10 elements,
// the error falling at second order with refinement (5 / 10 / 20 elements).
TEST(LoadSteps, DelxfIsTheTotalReachedAtTheLastStep) {
  const double exact = 0.81061;
  double prev = 0.0;
  for (int n : {5, 10, 20}) {
    const core::Model m = io::readDatString(elasticaCantilever(n, 10.0, 10, "DELXF"), "elastica.dat");
    const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
    ASSERT_TRUE(run.completed) << run.stopReason;
    ASSERT_EQ(run.steps.size(), 11u);  // load steps 0..10
    EXPECT_EQ(run.loadSteps, 10);
    const int tipY = xIndex(m, n + 1, 2);
    // Equal parts: load step i carries i/10 of the total.
    for (int i = 0; i <= 10; ++i) {
      EXPECT_NEAR(run.steps[i].loadFactor, i / 10.0, 1e-15);
      EXPECT_EQ(run.steps[i].loadStep, i);
    }
    const double deflection = -run.steps.back().x[tipY];
    const double err = std::abs(deflection - exact) / exact;
    std::printf("  %2d elements: tip deflection %.6f L, relative error %.3e", n, deflection, err);
    if (n == 10) {
      EXPECT_LT(err, 0.005);
    }
    if (prev > 0.0) {
      const double order = std::log2(prev / err);
      std::printf(", order %.2f", order);
      EXPECT_GT(order, 1.6);
      EXPECT_LT(order, 2.6);
    }
    std::printf("\n");
    prev = err;
  }
}

// Item 5: XF with n steps ramps the initial load (load steps 0..n: the unloaded model and n distinct
// equilibria, the full load at the last);
// ITERSTEP's sixth field ramps the initial loads before the DEL* increments.
TEST(LoadSteps, InitialLoadsRampAndPrecedeTheIncrements) {
  const double exact = 0.81061;  // P L^2/EI = 10
  const core::Model xf = io::readDatString(elasticaCantilever(10, 10.0, 5, "XF"), "xf.dat");
  const auto schedule = analysis::loadSchedule(xf);
  ASSERT_EQ(schedule.size(), 6u);
  EXPECT_DOUBLE_EQ(schedule[0].initial, 0.0);
  const analysis::StaticRun r1 = analysis::staticAnalysis(xf, 0);
  ASSERT_TRUE(r1.completed) << r1.stopReason;
  ASSERT_EQ(r1.steps.size(), 6u);
  EXPECT_NEAR(r1.steps[0].x[xIndex(xf, 11, 2)], 0.0, 1e-15);
  const int tipY = xIndex(xf, 11, 2);
  for (size_t i = 1; i < r1.steps.size(); ++i)
    EXPECT_GT(-r1.steps[i].x[tipY], -r1.steps[i - 1].x[tipY] + 1e-3) << "distinct equilibria";
  EXPECT_NEAR(r1.steps.back().initialFactor, 1.0, 0.0);
  EXPECT_NEAR(-r1.steps.back().x[tipY] / exact, 1.0, 0.005);

  // XF (P = 4) ramped over 4 steps, then DELXF (total 6) over 3: the total P = 10 at the last step.
  std::string text = elasticaCantilever(10, 6.0, 3, "DELXF");
  text.insert(text.find("ITERSTEP"), "XF 11 0 -4\n");
  text.replace(text.find("ITERSTEP 50 3 1e-10"), 19, "ITERSTEP 50 3 1e-10 1 3 4");
  const core::Model both = io::readDatString(text, "both.dat");
  const auto sched = analysis::loadSchedule(both);
  ASSERT_EQ(sched.size(), 7u);
  EXPECT_DOUBLE_EQ(sched[1].initial, 0.5);
  EXPECT_DOUBLE_EQ(sched[1].increment, 0.0);
  EXPECT_DOUBLE_EQ(sched[4].initial, 1.0);
  EXPECT_NEAR(sched[4].increment, 1.0 / 3, 1e-15);
  const analysis::StaticRun r2 = analysis::staticAnalysis(both, 0);
  ASSERT_TRUE(r2.completed) << r2.stopReason;
  ASSERT_EQ(r2.steps.size(), 7u);
  EXPECT_NEAR(-r2.steps.back().x[tipY] / exact, 1.0, 0.005);
  // After the ramp of the initial loads (step 4) the beam carries P = 4 alone.
  const analysis::StaticRun p4 =
      analysis::staticAnalysis(io::readDatString(elasticaCantilever(10, 4.0, 1, "XF"), "p4.dat"), 0);
  ASSERT_TRUE(p4.completed) << p4.stopReason;
  EXPECT_NEAR(r2.steps[3].x[tipY], p4.steps.back().x[tipY], 1e-8);
  EXPECT_LT(-r2.steps[3].x[tipY], -r2.steps[4].x[tipY]);
  // The --steps override counts the increment steps.
  EXPECT_EQ(analysis::loadSchedule(both, 6).size(), 10u);
}

// Item 5: DELINPX is the total increment of an input coordinate at the last step.
TEST(LoadSteps, DelinpxIsTheTotal) {
  const std::string text =
      "PLTRUSS 1 1 2\nX 2 1 0\nFIX 1\nINPUTX 2 1\nFIX 2 2\nRLSE 1 1\nEND\nHALT\nESTIFF 1 10\n"
      "DELINPX 2 1 0.3\nITERSTEP 20 6\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "delinpx.dat");
  const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_EQ(run.steps.size(), 7u);  // load steps 0..6
  const int x2 = xIndex(m, 2, 1);
  for (int i = 0; i <= 6; ++i) EXPECT_NEAR(run.steps[i].x[x2], 1.0 + 0.3 * i / 6.0, 1e-12);
}

// A static file written the way SPACAR Light writes it (ITERSTEP 10 9 0.0000005 1 3 9, XF and
// DELXF): the tolerance 5e-7 bounds the kinematic Newton, which statics tightens so that the
// equilibrium iteration converges; 9 steps ramp XF, then 9 steps reach the DELXF total.
TEST(LoadSteps, SpacarLightStyleStaticFileRuns) {
  const core::Model m = io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/spacarlight_style_2013.dat");
  const analysis::StaticRun run = analysis::staticAnalysis(m, 2);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_EQ(run.steps.size(), 18u);
  EXPECT_DOUBLE_EQ(run.steps[8].initialFactor, 1.0);
  EXPECT_DOUBLE_EQ(run.steps[8].loadFactor, 0.0);
  EXPECT_DOUBLE_EQ(run.steps.back().loadFactor, 1.0);
  const int tipY = xIndex(m, 5, 2);
  EXPECT_LT(run.steps.back().x[tipY], run.steps[8].x[tipY]);  // the DELXF total pushes the tip down
}
