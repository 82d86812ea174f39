// The implicit integrator on the paper's models: the analytic Jacobian of the first-order equations
// of motion (analysis::StateJacobian, from the linearisation of Eq. 15) against central differences
// of EquationsOfMotion::rhs, full and reduced; and BDF runs (analysis::simulate with
// Integrator::Bdf) against ode45 on the straight guidance and a short manipulator run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "analysis/Reduction.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/StateJacobian.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"
#include "solvers/Ode45.hpp"

using namespace flexmb;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

// The state y = [eta; etad] an ode45 run reaches at time t (a moving state under load), with output
// times 1 ms apart (they bound ode45's first trial step, as the models' TIMESTEP does).
VectorXd stateAt(const core::Model& m, const std::optional<MatrixXd>& V, double t) {
  core::EquationsOfMotion eom(m, V);
  solvers::Ode45Options o;
  o.relTol = 1e-6;
  o.absTol = VectorXd::Constant(1, 1e-9);
  std::vector<double> tspan;
  const int intervals = static_cast<int>(std::lround((t - m.settings.t0) / 1e-3));
  for (int i = 0; i <= intervals; ++i) tspan.push_back(m.settings.t0 + (t - m.settings.t0) * i / intervals);
  VectorXd last;
  const auto r = solvers::Ode45(o).integrate([&](double tt, const VectorXd& y, VectorXd& dy) { eom.rhs(tt, y, dy); },
                                             tspan, eom.initialState(),
                                             [&](double, const VectorXd& y) {
                                               last = y;
                                               return true;
                                             });
  EXPECT_EQ(r.status, solvers::OdeStatus::Success) << r.message;
  return last;
}

struct JacobianCase {
  std::string name;
  std::string file;
  double t;
  std::optional<analysis::ReductionOptions> reduction;
};

struct Blocks {
  double stiffness = 0, damping = 0;  // relative errors of the d(etadd)/d(eta) and d(etadd)/d(etad) blocks
  double upper = 0;                   // max |J - [0 I]| of the analytic upper blocks (exact)
  double shareN = 0, shareG = 0;      // |N| / |K + N + G|, |G| / |K + N + G|
};

// Analytic J against central differences of rhs, column by column. The step of an eta column is
// relEta times the largest |eta| of the state, of an etad column relRate times the largest |etad|.
Blocks compare(const JacobianCase& c, double relEta, double relRate) {
  const core::Model m = io::readDatFile(dat(c.file));
  std::optional<MatrixXd> V;
  if (c.reduction) V = analysis::buildBasis(m, *c.reduction).V;
  const VectorXd y = stateAt(m, V, c.t);
  core::EquationsOfMotion eom(m, V);
  eom.kinematics().setRelativeTolerance(1e-15);
  const int n = static_cast<int>(y.size()), k = n / 2;
  VectorXd f(n);
  eom.rhs(c.t, y, f);
  analysis::StateJacobian jac(m, V);
  jac.kinematics().setRelativeTolerance(1e-15);
  MatrixXd J(n, n);
  jac.evaluate(c.t, y, f, J);

  Blocks b;
  MatrixXd fd(n, n);
  const double etaScale = std::max(y.head(k).lpNorm<Eigen::Infinity>(), 1e-6);
  const double rateScale = std::max(y.tail(k).lpNorm<Eigen::Infinity>(), 1e-6);
  VectorXd yp = y, ym = y, fp(n), fm(n);
  for (int j = 0; j < n; ++j) {
    const double h = j < k ? relEta * etaScale : relRate * rateScale;
    yp[j] += h;
    ym[j] -= h;
    eom.rhs(c.t, yp, fp);
    eom.rhs(c.t, ym, fm);
    fd.col(j) = (fp - fm) / (2 * h);
    yp[j] = ym[j] = y[j];
  }
  // The shares of N and G in K + N + G: a Jacobian without them would miss the bound below.
  core::Linearization lin(m, V);
  core::LinearizedSystem sys;
  lin.inMotion(c.t, y.head(k), y.tail(k), f.tail(k), sys);
  const double total = (sys.K + sys.N + sys.G).norm();
  b.shareN = sys.N.norm() / total;
  b.shareG = sys.G.norm() / total;
  b.stiffness = (J.bottomLeftCorner(k, k) - fd.bottomLeftCorner(k, k)).norm() / fd.bottomLeftCorner(k, k).norm();
  b.damping = (J.bottomRightCorner(k, k) - fd.bottomRightCorner(k, k)).norm() /
              std::max(fd.bottomRightCorner(k, k).norm(), 1e-300);
  MatrixXd upper(k, n);
  upper << MatrixXd::Zero(k, k), MatrixXd::Identity(k, k);
  b.upper = (J.topRows(k) - upper).cwiseAbs().maxCoeff();
  std::printf("%s (%d states): stiffness block %.2e, damping block %.2e (N share %.1e, G share %.1e)\n", c.name.c_str(),
              n, b.stiffness, b.damping, b.shareN, b.shareG);
  return b;
}

analysis::ReductionOptions modal(int r) {
  analysis::ReductionOptions o;
  o.method = "modal";
  o.modes = r;
  return o;
}

}  // namespace

// J = [[0, I], [-M^-1 (K + N + G), -M^-1 (C + D)]] at moving states under load. Central-difference
// steps 1e-5 of the state's scale for eta: the truncation error falls 100x per decade of step and
// round-off takes over below (measured: 1e-10 ... 5e-8). etadd is quadratic in etad (xd is linear in
// it, the convective terms and h quadratic), so central differences along etad are exact but for
// round-off, and a large step (0.1 of the scale) keeps that small (measured: 9e-12 ... 1e-8).
// N and G are 5e-4 ... 4e-2 of K + N + G here, so leaving either out fails the 1e-6 bound.
TEST(BdfDynamics, AnalyticJacobianMatchesDifferencesOfTheRhs) {
  const std::vector<JacobianCase> cases = {
      {"guidance full", "straight_guidance.dat", 0.05, std::nullopt},
      {"guidance MODAL-3", "straight_guidance.dat", 0.05, modal(3)},
      {"manipulator full", "manipulator.dat", 0.1, std::nullopt},
      {"manipulator MODAL-2", "manipulator.dat", 0.1, modal(2)},
  };
  for (const auto& c : cases) {
    const Blocks b = compare(c, 1e-5, 1e-1);
    EXPECT_LT(b.stiffness, 1e-6) << c.name;
    EXPECT_LT(b.damping, 1e-6) << c.name;
    EXPECT_LT(b.upper, 1e-12) << c.name;
    EXPECT_GT(std::min(b.shareN, b.shareG), 100 * 1e-6) << c.name << ": the test would not see N or G";
  }
}

namespace {

struct Response {
  std::vector<double> time;
  std::vector<Eigen::Vector2d> p;  // position of the response node
};

Response response(const core::Model& m, const core::Trajectory& t, int node) {
  const int first = m.nodes[m.nodeByLabel.at(node)].firstCoord;
  Response r;
  r.time = t.time;
  for (const auto& s : t.states) r.p.emplace_back(s.x[first], s.x[first + 1]);
  return r;
}

// max |a - b| over the output times (x only or the distance), divided by scale.
double difference(const Response& a, const Response& b, bool xOnly, double scale) {
  EXPECT_EQ(a.time.size(), b.time.size());
  double worst = 0.0;
  for (size_t i = 0; i < a.time.size() && i < b.time.size(); ++i) {
    EXPECT_EQ(a.time[i], b.time[i]);
    worst = std::max(worst, xOnly ? std::abs(a.p[i].x() - b.p[i].x()) : (a.p[i] - b.p[i]).norm());
  }
  return worst / scale;
}

core::Trajectory run(const core::Model& m, analysis::Integrator integrator, double relTol, int order = 2,
                     std::optional<double> tEnd = std::nullopt, std::optional<int> intervals = std::nullopt,
                     std::optional<MatrixXd> basis = std::nullopt) {
  analysis::SimulationOptions o;
  o.integrator = integrator;
  o.relTol = relTol;
  o.absTol = 1e-3 * relTol;
  o.bdfMaxOrder = order;
  o.tEnd = tEnd;
  o.intervals = intervals;
  o.basis = std::move(basis);
  core::Trajectory t = analysis::simulate(m, o);
  EXPECT_TRUE(t.completed) << t.stopReason;
  EXPECT_EQ(t.integrator, integrator == analysis::Integrator::Bdf ? "bdf" : "ode45");
  if (integrator == analysis::Integrator::Bdf) {
    EXPECT_GT(t.njacevals, 0);
    EXPECT_GE(t.nlinsetups, t.njacevals);
  }
  std::printf("  %s RelTol %.0e%s: %ld steps, %ld failed, %ld evaluations, %ld Jacobians\n", t.integrator.c_str(),
              relTol,
              integrator == analysis::Integrator::Bdf ? (" (order <= " + std::to_string(order) + ")").c_str() : "",
              t.nsteps, t.nfailed, t.nfevals, t.njacevals);
  return t;
}

}  // namespace

// The straight guidance (0.2 s, 200 output intervals): BDF against ode45 at RelTol 1e-8, whose own
// error is ~1e-11 of the deflection (tools/bench/README.md). The tolerances follow BDF's measured
// global errors: order <= 2 about 30 x RelTol (3.1e-6 at 1e-7), order <= 5 about 0.01 x RelTol
// (1.3e-8 at 1e-6). And BDF needs far fewer evaluations than ode45 on this stiff full model.
TEST(BdfDynamics, GuidanceAgreesWithOde45) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const core::Trajectory ref = run(m, analysis::Integrator::Ode45, 1e-8);
  const Response r0 = response(m, ref, 6);
  double deflection = 0.0;
  for (const auto& p : r0.p) deflection = std::max(deflection, std::abs(p.x() - r0.p.front().x()));
  ASSERT_GT(deflection, 0.08);
  const core::Trajectory bdf2 = run(m, analysis::Integrator::Bdf, 1e-7);
  const double d2 = difference(r0, response(m, bdf2, 6), true, deflection);
  const core::Trajectory bdf5 = run(m, analysis::Integrator::Bdf, 1e-6, 5);
  const double d5 = difference(r0, response(m, bdf5, 6), true, deflection);
  std::printf("  difference / deflection: order <= 2 %.2e, order <= 5 %.2e\n", d2, d5);
  EXPECT_LT(d2, 1e-5);
  EXPECT_LT(d5, 1e-7);
  const core::Trajectory ode = run(m, analysis::Integrator::Ode45, 1e-7);
  EXPECT_LT(3 * bdf2.nfevals, ode.nfevals);
}

// The manipulator over its first 0.1 s (hinges accelerating, Eq. 25): tip position against ode45 at
// RelTol 1e-8, relative to the reach 1.22 m (measured: order <= 2 3.1e-9 at RelTol 1e-7, order <= 5
// 1.0e-12 at RelTol 1e-6; over 0.2 s 2.0e-8 and 2.3e-11).
TEST(BdfDynamics, ShortManipulatorRunAgreesWithOde45) {
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  const core::Trajectory ref = run(m, analysis::Integrator::Ode45, 1e-8, 2, 0.1, 100);
  const Response r0 = response(m, ref, 9);
  const double d2 = difference(r0, response(m, run(m, analysis::Integrator::Bdf, 1e-7, 2, 0.1, 100), 9), false, 1.22);
  const double d5 = difference(r0, response(m, run(m, analysis::Integrator::Bdf, 1e-6, 5, 0.1, 100), 9), false, 1.22);
  std::printf("  tip difference / reach: order <= 2 %.2e, order <= 5 %.2e\n", d2, d5);
  EXPECT_LT(d2, 3e-8);
  EXPECT_LT(d5, 1e-10);
}

// A reduced model (MODAL-3 guidance, Eq. 19): BDF with the reduced Jacobian against ode45 on the
// same reduced model at RelTol 1e-9 (measured at RelTol 1e-7: order <= 2 2.0e-6, order <= 5 4.6e-9
// of the 0.083 m deflection).
TEST(BdfDynamics, ReducedGuidanceAgreesWithOde45) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const MatrixXd V = analysis::buildBasis(m, modal(3)).V;
  const Response r0 = response(m, run(m, analysis::Integrator::Ode45, 1e-9, 2, std::nullopt, std::nullopt, V), 6);
  const Response r1 = response(m, run(m, analysis::Integrator::Bdf, 1e-7, 2, std::nullopt, std::nullopt, V), 6);
  const Response r2 = response(m, run(m, analysis::Integrator::Bdf, 1e-7, 5, std::nullopt, std::nullopt, V), 6);
  const double d2 = difference(r0, r1, true, 0.083), d5 = difference(r0, r2, true, 0.083);
  std::printf("  difference / 0.083 m: order <= 2 %.2e, order <= 5 %.2e\n", d2, d5);
  EXPECT_LT(d2, 1e-5);
  EXPECT_LT(d5, 1e-7);
}

// A stiff damped probe (datfiles/tests/damped_probe.dat: a clamped pin of two PLBEAMs with large
// EDAMP under a tip force): ode45's step is bound by the damped modes (|lambda| ~ 6e11 1/s) while
// the tip creeps towards the static deflection P L^3 / (3 EI) with the Kelvin-Voigt time constant
// tau = EDAMP / ESTIFF of bending. Integrator::Auto starts with ode45, detects the stability bound
// within its first steps and finishes with generalized-alpha in a few hundred evaluations (its
// high frequencies are real and damped: the method's dissipation handles them as BDF's); its tip deflection
// equals a tight-tolerance BDF reference (order <= 5, RelTol 1e-9) within the file's tolerance and
// the creep law y(t) = y_s (1 - exp(-t / tau)) within 1 %. A default ode45 run over the first 0.2 us
// (thousands of steps at the stability limit) reports the bound (Trajectory::stiffBoundSteps) and
// formatStatistics says that galpha or auto would be faster.
TEST(BdfDynamics, AutoSwitchesToGeneralizedAlphaOnAStiffDampedProbe) {
  const core::Model m = io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/tests/damped_probe.dat");
  auto tip = [&](const core::Trajectory& t) {
    std::vector<double> y;
    const int first = m.nodes[m.nodeByLabel.at(3)].firstCoord;
    for (const auto& s : t.states) y.push_back(s.x[first + 1]);
    return y;
  };
  analysis::SimulationOptions a;
  a.integrator = analysis::Integrator::Auto;
  const core::Trajectory autoRun = analysis::simulate(m, a);
  ASSERT_TRUE(autoRun.completed) << autoRun.stopReason;
  EXPECT_EQ(autoRun.integrator, "ode45+galpha");
  EXPECT_LT(autoRun.switchedAt, 1e-6);
  EXPECT_GT(autoRun.stiffLambda, 1e9);
  EXPECT_LT(autoRun.nfevals, 3000);
  EXPECT_NE(analysis::formatStatistics(autoRun, a.integrator).find("galpha from there on"), std::string::npos);

  analysis::SimulationOptions r;
  r.integrator = analysis::Integrator::Bdf;
  r.relTol = 1e-9;
  r.absTol = 1e-16;
  r.bdfMaxOrder = 5;
  const core::Trajectory ref = analysis::simulate(m, r);
  ASSERT_TRUE(ref.completed) << ref.stopReason;
  const std::vector<double> ya = tip(autoRun), yr = tip(ref);
  ASSERT_EQ(ya.size(), yr.size());
  const double P = 0.1, L = 0.01, EI = 1.031e-2, ys = P * L * L * L / (3 * EI), tau = 1e-3 / EI;
  double worstRef = 0.0, worstTheory = 0.0;
  for (std::size_t k = 1; k < ya.size(); ++k) {
    const double creep = ys * (1.0 - std::exp(-autoRun.time[k] / tau));
    worstRef = std::max(worstRef, std::abs(ya[k] - yr[k]) / std::abs(yr.back()));
    worstTheory = std::max(worstTheory, std::abs(yr[k] - creep) / creep);
  }
  std::printf(
      "  auto: switched at t = %.3g s (|lambda| %.3g 1/s), %ld steps, %ld evaluations; reference %ld "
      "evaluations; auto vs reference %.2e, reference vs creep law %.2e\n",
      autoRun.switchedAt, autoRun.stiffLambda, autoRun.nsteps, autoRun.nfevals, ref.nfevals, worstRef, worstTheory);
  EXPECT_LT(worstRef, 1e-3);
  EXPECT_LT(worstTheory, 1e-2);

  analysis::SimulationOptions o;
  o.tEnd = 2e-7;
  o.intervals = 2;
  const core::Trajectory ode = analysis::simulate(m, o);
  ASSERT_TRUE(ode.completed) << ode.stopReason;
  EXPECT_EQ(ode.integrator, "ode45");
  EXPECT_GT(ode.stiffBoundSteps, 1000);
  EXPECT_LT(ode.stiffSince, 1e-6);
  EXPECT_NE(analysis::formatStatistics(ode, o.integrator).find("the integrator galpha or auto would be faster"),
            std::string::npos);
}
