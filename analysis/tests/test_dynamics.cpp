// Dynamics (Eq. 13) against independent values: the exact large-amplitude pendulum period
// (complete elliptic integral) and conservation of total energy in free, undamped motion.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/Statics.hpp"
#include "analysis/tests/EnergyDrift.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/tests/Energy.hpp"
#include "core/tests/ShortRun.hpp"
#include "io/formats/DatReader.hpp"
#include "solvers/Ode45.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

std::string num(double v) {  // full precision for model texts (std::to_string keeps 6 decimals)
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// K(k) by the arithmetic-geometric mean: K = pi / (2 AGM(1, sqrt(1 - k^2))).
double ellipticK(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  for (int i = 0; i < 40; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return M_PI / (2.0 * a);
}

using flexmb::core::test::totalEnergy;

// Integrates from y0 and returns the largest relative deviation of the total energy.
double energyDrift(const core::Model& m, const Eigen::VectorXd& y0, double tEnd, double relTol) {
  if (const char* s = std::getenv("FLEXMB_ENERGY_TEND")) tEnd = std::atof(s);  // for profiling only
  core::EquationsOfMotion eom(m), probe(m);
  core::Inertia inertia(m);
  solvers::OdeResult r;
  const double worst = flexmb::test::largestEnergyDeviation(
      eom, probe, y0, tEnd, relTol, [&](const core::StateOutputs& s) { return totalEnergy(m, inertia, s); }, r);
  std::printf("  %s", solvers::Ode45::formatStats(r.stats).c_str());
  EXPECT_EQ(r.status, solvers::OdeStatus::Success) << r.message;
  return worst;
}
}  // namespace

TEST(Dynamics, RigidPendulumMatchesEllipticIntegralPeriod) {
  const double L = 0.8, g = 9.81, theta0 = 2.0;  // large amplitude: 115 degrees
  const std::string text =
      "PLBEAM 1  1 2  3 4\n"
      "PLHINGE 2  5 2\n"
      "X 1 0 0\nX 3 0 " +
      std::to_string(-L) +
      "\n"
      "FIX 1\nFIX 5\nDYNE 2 1\nEND\nHALT\n"
      "XM 3 1.5\nGRAVITY 0 " +
      std::to_string(-g) +
      "\n"
      "STARTDE 2 1 " +
      std::to_string(theta0) +
      " 0\n"
      "TIMESTEP 5.0 5000\nERROR 1e-12 1e-10\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "pendulum.dat");
  const core::Trajectory tr = analysis::simulate(m, {});
  ASSERT_TRUE(tr.completed) << tr.stopReason;
  const int hinge = m.elements[m.elementByLabel.at(2)].firstDef;
  // Zero crossings of the angle by cubic Hermite interpolation of (theta, thetad).
  std::vector<double> crossings;
  for (size_t i = 1; i < tr.time.size(); ++i) {
    const double a = tr.states[i - 1].e[hinge], b = tr.states[i].e[hinge];
    if ((a > 0) == (b > 0)) continue;
    const double t0 = tr.time[i - 1], h = tr.time[i] - t0;
    const double da = tr.states[i - 1].ed[hinge] * h, db = tr.states[i].ed[hinge] * h;
    double s = a / (a - b);
    for (int it = 0; it < 20; ++it) {
      const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
      const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
      const double p = h00 * a + h10 * da + h01 * b + h11 * db;
      const double dp =
          (6 * s * s - 6 * s) * a + (3 * s * s - 4 * s + 1) * da + (-6 * s * s + 6 * s) * b + (3 * s * s - 2 * s) * db;
      s -= p / dp;
    }
    crossings.push_back(t0 + s * h);
  }
  ASSERT_GE(crossings.size(), 3u);
  const double period = crossings[2] - crossings[0];
  const double exact = 4.0 * std::sqrt(L / g) * ellipticK(std::sin(theta0 / 2));
  EXPECT_NEAR(period / exact, 1.0, 1e-6) << "period " << period << " exact " << exact;
  std::printf("pendulum (115 degrees): period %.12f s, exact %.12f s, relative error %.2e\n", period, exact,
              period / exact - 1);
}

TEST(Dynamics, StraightGuidanceConservesEnergyAfterInitialDeflection) {
  core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  m.timeForces.clear();  // free, unforced: released from a deflected, stressed state
  // Released from the nonlinear static equilibrium under a 40 N tip load (about 2.5 cm at the
  // body): geometrically nonlinear, and the high modes take part only as (w1/wk)^2.
  {
    core::Model loaded = m;
    loaded.f0[m.nodes[m.nodeByLabel.at(6)].firstCoord] = 40.0;
    core::Linearization lin(loaded);
    Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size());
    const auto res = analysis::equilibrium(lin, 0.0, 0.0, eta);
    ASSERT_EQ(res.status, solvers::StaticStatus::Converged) << res.message;
    for (size_t j = 0; j < m.dofs.size(); ++j) m.e0[m.dofs[j].index] = eta[j];
    EXPECT_GT(lin.kinematics().x()[m.nodes[m.nodeByLabel.at(6)].firstCoord], 0.02);
  }
  core::EquationsOfMotion eom(m);
  // Slow by design (8 min under the sanitizers): the short run covers the first tenth of the second
  // (analysis/CMakeLists.txt, core/tests/ShortRun.hpp).
  const double tEnd = flexmb::test::shortRun() ? 0.1 : 1.0;
  const double drift = energyDrift(m, eom.initialState(), tEnd, 1e-10);
  EXPECT_LT(drift, 1e-7);
  std::printf("straight guidance: relative energy drift over %g s at RelTol 1e-10: %.3e\n", tEnd, drift);
}

TEST(Dynamics, FreeSpinningFlexibleBeamConservesEnergy) {
  // Two flexible beams, nothing fixed: the first node's coordinates are DYNX, every deformation DYNE.
  const std::string text =
      "PLBEAM 1 1 11 2 12\nPLBEAM 2 2 12 3 13\n"
      "X 1 0 0\nX 2 0.5 0\nX 3 1.0 0\n"
      "DYNX 1 1 2\nDYNX 11\nDYNE 1 1 2 3\nDYNE 2 1 2 3\nEND\nHALT\n"
      "EM 1 2.0 1e-4\nEM 2 2.0 1e-4\nESTIFF 1 2e4 50\nESTIFF 2 2e4 50\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "spinning.dat");
  ASSERT_EQ(m.numDofs(), 9);
  core::EquationsOfMotion eom(m);
  Eigen::VectorXd y0 = eom.initialState();
  // Spin about node 1 at 6 rad/s with a translation, plus an initial bending deflection.
  y0[9 + 0] = 0.3;    // xd of node 1
  y0[9 + 1] = -0.2;   // yd of node 1
  y0[9 + 2] = 6.0;    // angular rate of node 11
  y0[3 + 1] = 5e-3;   // bending e2 of element 1
  y0[3 + 5] = -4e-3;  // bending e3 of element 2
  const double drift = energyDrift(m, y0, 1.0, 1e-10);
  EXPECT_LT(drift, 1e-7);
  std::printf("free spinning beam: relative energy drift over 1 s at RelTol 1e-10: %.3e\n", drift);
}

TEST(Dynamics, PendulumOnAcceleratingSupportStaysAtRelativeEquilibrium) {
  // Support node 1 prescribed x(t) = a t^2 / 2 (INPUTX with x, v, a); in the accelerating frame the
  // pendulum's equilibrium is tilted by theta = -atan(a / g). Started there at rest relative to the
  // support (support at rest at t = 0, so the relative rate is zero), it must stay there: this
  // checks the rheonomic velocity and acceleration terms of the transfer functions.
  const double L = 0.5, g = 9.81, a = 3.0, theta = -std::atan(a / g);
  const std::string text =
      "PLBEAM 1  1 2  3 4\nPLHINGE 2  5 2\n"
      "X 1 0 0\nX 3 0 " +
      std::to_string(-L) +
      "\n"
      "INPUTX 1 1\nFIX 1 2\nFIX 5\nDYNE 2 1\nEND\nHALT\n"
      "INPUTX 1 1 0 0 " +
      num(a) +
      "\n"
      "XM 3 2.0\nGRAVITY 0 " +
      std::to_string(-g) +
      "\n"
      "STARTDE 2 1 " +
      num(theta) +
      " 0\n"
      "TIMESTEP 1.0 20\nERROR 1e-12 1e-10\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "accelerating_support.dat");
  const core::Trajectory tr = analysis::simulate(m, {});
  ASSERT_TRUE(tr.completed) << tr.stopReason;
  const int hinge = m.elements[m.elementByLabel.at(2)].firstDef;
  const int supportX = m.nodes[m.nodeByLabel.at(1)].firstCoord;
  for (size_t i = 0; i < tr.time.size(); ++i) {
    const double t = tr.time[i];
    EXPECT_NEAR(tr.states[i].e[hinge], theta, 1e-7) << "t = " << t;
    EXPECT_NEAR(tr.states[i].x[supportX], 0.5 * a * t * t, 1e-12);
    EXPECT_NEAR(tr.states[i].xd[supportX], a * t, 1e-12);
    EXPECT_NEAR(tr.states[i].xdd[supportX], a, 1e-12);
  }
}

// Issue 34 item 1: the accuracy check solves each window's kinematics from the run's own
// configuration (the crank of this slider-crank has turned three times; Newton from the initial
// configuration diverged and the completed run was discarded), and a check that cannot run is the
// check's failure, said with its reason, never the run's.
TEST(AccuracyCheck, WindowsFarFromTheInitialConfigurationAreCheckedAndAFailedCheckSaysWhy) {
  const core::Model m = io::readDatFile(dat("tests/slider_crank_manual_s95.dat"));
  analysis::SimulationOptions o;
  o.accuracyCheck = true;
  const core::Trajectory run = analysis::simulate(m, o);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_TRUE(run.accuracy.checked) << run.accuracy.note;
  EXPECT_EQ(run.accuracy.windows, 3);
  EXPECT_TRUE(run.accuracy.converged()) << analysis::describeAccuracy(run.accuracy);
  EXPECT_GT(std::abs(run.states.back().x[m.nodes[m.nodeByLabel.at(2)].firstCoord]), 3 * 2 * M_PI * 0.9)
      << "the crank must turn far from its initial configuration for this test to mean anything";
  // The same run's windows, recorded from its output states, checked again; then made nonsense.
  analysis::AccuracyWindowRecorder rec(m.settings.t0, m.settings.tEnd);
  for (size_t k = 0; k < run.time.size(); ++k) {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * m.numDofs());
    for (size_t j = 0; j < m.dofs.size(); ++j) {
      const auto& d = m.dofs[j];
      y[static_cast<Eigen::Index>(j)] = d.isDeformation ? run.states[k].e[d.index] : run.states[k].x[d.index];
      y[static_cast<Eigen::Index>(j + m.dofs.size())] =
          d.isDeformation ? run.states[k].ed[d.index] : run.states[k].xd[d.index];
    }
    rec.observe(run.time[k], y, run.states[k].x);
  }
  std::vector<analysis::AccuracyWindow> windows = rec.complete();
  ASSERT_EQ(windows.size(), 3u);
  // Sanity: the recorded windows check as the run's own check does.
  EXPECT_TRUE(analysis::checkAccuracy(m, o, m.settings.t0, m.settings.tEnd, windows).checked);
  // A window whose configurations are nonsense: the kinematics cannot be solved from there.
  for (auto& w : windows) w.xb.setConstant(1e6), w.xa.setConstant(1e6);
  const core::AccuracyEstimate a = analysis::checkAccuracy(m, o, m.settings.t0, m.settings.tEnd, windows);
  EXPECT_FALSE(a.checked);
  EXPECT_FALSE(a.note.empty());
  EXPECT_EQ(analysis::describeAccuracy(a).rfind("not checked: ", 0), 0u) << analysis::describeAccuracy(a);
}

// The accuracy check says which coordinate and kind its estimate comes from and judges positions
// (of the model size) and angles (rad) each against the limit (issue 48, item 5).
TEST(AccuracyCheck, NamesTheCoordinateAndJudgesPositionsAndAnglesEachOnTheirOwn) {
  const core::Model m = io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/straight_guidance.dat");
  analysis::SimulationOptions o;
  o.integrator = analysis::Integrator::GeneralizedAlpha;
  o.accuracyCheck = true;
  const core::Trajectory run = analysis::simulate(m, o);
  ASSERT_TRUE(run.completed);
  const core::AccuracyEstimate& a = run.accuracy;
  ASSERT_TRUE(a.checked) << a.note;
  EXPECT_GT(a.positionEstimate, 0.0);
  EXPECT_GT(a.angleEstimate, 0.0);
  EXPECT_DOUBLE_EQ(a.estimate, std::max(a.positionEstimate, a.angleEstimate));
  EXPECT_EQ(a.positionWhere.rfind("node ", 0), 0u) << a.positionWhere;
  EXPECT_TRUE(a.positionWhere.back() == 'x' || a.positionWhere.back() == 'y') << a.positionWhere;
  EXPECT_NE(a.angleWhere.find(" rotation"), std::string::npos) << a.angleWhere;
  const std::string said = analysis::describeAccuracy(a);
  EXPECT_NE(said.find("of the model size (" + a.positionWhere + ")"), std::string::npos) << said;
  EXPECT_NE(said.find(" rad (" + a.angleWhere + ")"), std::string::npos) << said;
  // Each kind on its own: positions within the limit do not hide angles beyond it, nor the reverse.
  core::AccuracyEstimate b = a;
  b.limit = 1.0;
  b.positionEstimate = 0.5, b.angleEstimate = 2.0;
  EXPECT_FALSE(b.converged());
  b.positionEstimate = 2.0, b.angleEstimate = 0.5;
  EXPECT_FALSE(b.converged());
  b.positionEstimate = 0.5;
  EXPECT_TRUE(b.converged());
}
