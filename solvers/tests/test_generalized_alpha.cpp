// Tests of solvers::GeneralizedAlpha on linear oscillators with closed-form solutions: order of
// accuracy 2, the spectral radius at infinite step against rho_inf, energy, the step-size control on a
// stiff pair, failures that keep the results, argument checks.
#include "solvers/GeneralizedAlpha.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

using namespace flexmb::solvers;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// Decoupled oscillators q_i'' + 2 zeta_i w_i q_i' + w_i^2 q_i = 0 as y' = f(y), y = [q; qd].
struct Oscillators {
  std::vector<double> w, zeta;
  int m() const { return static_cast<int>(w.size()); }
  OdeRhs rhs() const {
    return [this](double, const VectorXd& y, VectorXd& dy) {
      const int n = m();
      for (int i = 0; i < n; ++i) {
        dy[i] = y[n + i];
        dy[n + i] = -w[i] * w[i] * y[i] - 2 * zeta[i] * w[i] * y[n + i];
      }
    };
  }
  OdeJacobian jacobian() const {
    return [this](double, const VectorXd&, const VectorXd&, Eigen::Ref<MatrixXd> J) {
      const int n = m();
      J.setZero();
      for (int i = 0; i < n; ++i) {
        J(i, n + i) = 1.0;
        J(n + i, i) = -w[i] * w[i];
        J(n + i, n + i) = -2 * zeta[i] * w[i];
      }
    };
  }
};

struct AlphaRun {
  std::vector<double> t;
  std::vector<VectorXd> y;
  OdeResult result;
};

AlphaRun integrate(const Oscillators& o, GeneralizedAlphaOptions opt, const std::vector<double>& tspan,
                   const VectorXd& y0) {
  FirstOrderAsSecondOrder sys(o.rhs(), o.jacobian(), o.m());
  AlphaRun run;
  run.result = GeneralizedAlpha(opt).integrate(sys, tspan, y0, [&](double t, const VectorXd& y) {
    run.t.push_back(t);
    run.y.push_back(y);
    return true;
  });
  return run;
}

GeneralizedAlphaOptions fixed(double h, double rho) {
  GeneralizedAlphaOptions o;
  o.fixedStep = true;
  o.maxStep = h;
  o.rhoInf = rho;
  return o;
}

TEST(GeneralizedAlpha, ParametersAreChungAndHulberts) {
  const GeneralizedAlphaParameters p(0.5);
  EXPECT_DOUBLE_EQ(p.alphaM, 0.0);
  EXPECT_DOUBLE_EQ(p.alphaF, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(p.gamma, 0.5 + 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(p.beta, 0.25 * (p.gamma + 0.5) * (p.gamma + 0.5));
  const GeneralizedAlphaParameters trapezoidal(1.0);  // rho_inf = 1: the trapezoidal rule's 1/12
  EXPECT_DOUBLE_EQ(trapezoidal.errorCoefficient(), 1.0 / 12.0);
}

TEST(GeneralizedAlpha, IsSecondOrderAccurateOnALinearOscillator) {
  const Oscillators o{{2 * M_PI}, {0.05}};
  VectorXd y0(2);
  y0 << 1.0, 0.0;
  const double s = 0.05 * 2 * M_PI, wd = 2 * M_PI * std::sqrt(1 - 0.05 * 0.05);
  auto exact = [&](double t) { return std::exp(-s * t) * (std::cos(wd * t) + s / wd * std::sin(wd * t)); };
  for (double rho : {0.0, 0.5, 0.9, 1.0}) {
    double previous = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double h = 0.02 / (1 << k);
      const AlphaRun r = integrate(o, fixed(h, rho), {0.0, 1.0}, y0);
      ASSERT_EQ(r.result.status, OdeStatus::Success);
      ASSERT_DOUBLE_EQ(r.t.back(), 1.0);
      double error = 0.0;  // the largest over the run (at one time the error may pass through zero)
      for (size_t i = 0; i < r.t.size(); ++i) error = std::max(error, std::fabs(r.y[i][0] - exact(r.t[i])));
      if (k > 0) {
        const double order = std::log2(previous / error);
        EXPECT_NEAR(order, 2.0, 0.15) << "rho_inf " << rho << ", h " << h;
      }
      previous = error;
    }
  }
}

// The amplification at omega h -> infinity has spectral radius rho_inf: an undamped oscillator
// stepped at omega h = 1e6 loses its energy norm as rho_inf^n.
TEST(GeneralizedAlpha, DissipatesAtInfiniteStepAsRhoInfSays) {
  const double w = 1e6;
  const Oscillators o{{w}, {0.0}};
  VectorXd y0(2);
  y0 << 1.0, 0.0;
  for (double rho : {0.2, 0.5, 0.8}) {
    const int n = 200;
    const AlphaRun r = integrate(o, fixed(1.0, rho), {0.0, static_cast<double>(n)}, y0);
    ASSERT_EQ(r.result.status, OdeStatus::Success);
    auto amplitude = [&](const VectorXd& y) { return std::hypot(w * y[0], y[1]); };
    // Rate over the last 100 steps (the first ones carry the non-normal transient).
    const double rate = std::pow(amplitude(r.y[n]) / amplitude(r.y[n - 100]), 1.0 / 100);
    EXPECT_NEAR(rate, rho, 0.01) << "rho_inf " << rho;
  }
}

// Energy of an undamped oscillator: with rho_inf = 1 constant to round-off; with rho_inf < 1 the
// resolved mode (omega h = 0.05) keeps it to the method's O((omega h)^3) dissipation, while an
// unresolved one (omega h = 5000) loses it at rho_inf^2 per step.
TEST(GeneralizedAlpha, KeepsTheEnergyOfResolvedModesAndDampsTheUnresolved) {
  const Oscillators o{{1.0, 1e5}, {0.0, 0.0}};
  VectorXd y0(4);
  y0 << 1.0, 1e-5, 0.0, 0.0;
  auto energy = [&](const VectorXd& y, int i) { return 0.5 * (o.w[i] * o.w[i] * y[i] * y[i] + y[2 + i] * y[2 + i]); };
  const AlphaRun conservative = integrate(o, fixed(0.05, 1.0), {0.0, 20.0}, y0);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(energy(conservative.y.back(), i) / energy(y0, i), 1.0, 1e-9) << "mode " << i;
  const double rho = 0.7;
  const AlphaRun damped = integrate(o, fixed(0.05, rho), {0.0, 20.0}, y0);
  EXPECT_NEAR(energy(damped.y.back(), 0) / energy(y0, 0), 1.0, 2e-3);  // 400 steps, 3 periods
  // From step 20 to 40 (past the start's overshoot; a double root: up to (40/20)^2 more).
  EXPECT_LT(energy(damped.y[40], 1) / energy(damped.y[20], 1), 4 * std::pow(rho, 2 * 20));
  EXPECT_GT(energy(damped.y[40], 1) / energy(damped.y[20], 1), std::pow(rho, 2 * 20) / 4);
}

// A slow lightly damped mode and a stiff one at rest: the controller steps by the slow mode, and the
// error falls with the tolerance as a second-order method's with local error control does
// (tol^(2/3): 21x per factor 100).
TEST(GeneralizedAlpha, StepsByTheSlowModeOfAStiffPair) {
  const Oscillators o{{2 * M_PI, 1e5}, {0.05, 0.0}};
  VectorXd y0(4);
  y0 << 1.0, 0.0, 0.0, 0.0;
  std::vector<double> tspan;
  for (int i = 0; i <= 100; ++i) tspan.push_back(0.1 * i);
  const double s = 0.05 * 2 * M_PI, wd = 2 * M_PI * std::sqrt(1 - 0.05 * 0.05);
  double errors[2];
  long steps[2];
  for (int k = 0; k < 2; ++k) {
    GeneralizedAlphaOptions opt;
    opt.relTol = k == 0 ? 1e-3 : 1e-5;
    opt.absTol = opt.relTol;
    const AlphaRun r = integrate(o, opt, tspan, y0);
    ASSERT_EQ(r.result.status, OdeStatus::Success);
    ASSERT_EQ(r.t.size(), tspan.size());
    double worst = 0.0;
    for (size_t i = 0; i < r.t.size(); ++i) {
      const double t = r.t[i];
      worst = std::max(worst, std::fabs(r.y[i][0] - std::exp(-s * t) * (std::cos(wd * t) + s / wd * std::sin(wd * t))));
      EXPECT_LT(std::fabs(r.y[i][1]), 1e-12);  // the stiff mode stays at rest
    }
    errors[k] = worst;
    steps[k] = r.result.stats.nsteps;
    EXPECT_LT(r.result.stats.njacevals, 5);  // a linear system: the first matrix serves throughout
    EXPECT_LT(r.result.stats.nfailed, r.result.stats.nsteps / 4);
  }
  EXPECT_GT(errors[0] / errors[1], 10.0) << errors[0] << " -> " << errors[1];
  EXPECT_LT(errors[1], 0.02);
  EXPECT_LT(steps[1], 5000);  // ode45 would take ~ 10 s * 1e5 / 3.3 = 3e5 steps
}

// A right-hand side that fails from t = 0.5 on: the run stops there with the time and the reason,
// every output before it observed.
TEST(GeneralizedAlpha, AFailingRightHandSideStopsWithTheResultsSoFar) {
  const Oscillators o{{2 * M_PI}, {0.0}};
  const OdeRhs base = o.rhs();
  FirstOrderAsSecondOrder sys(
      [&](double t, const VectorXd& y, VectorXd& dy) {
        if (t > 0.5) throw RhsError("no solution here");
        base(t, y, dy);
      },
      o.jacobian(), 1);
  VectorXd y0(2);
  y0 << 1.0, 0.0;
  std::vector<double> seen;
  const OdeResult r =
      GeneralizedAlpha().integrate(sys, {0.0, 0.25, 0.5, 0.75, 1.0}, y0, [&](double t, const VectorXd&) {
        seen.push_back(t);
        return true;
      });
  EXPECT_EQ(r.status, OdeStatus::StepSizeUnderflow);
  EXPECT_NE(r.message.find("no solution here"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("results up to there are kept"), std::string::npos) << r.message;
  EXPECT_NEAR(r.tLast, 0.5, 1e-6);
  ASSERT_GE(seen.size(), 2u);  // 0 and 0.25; 0.5 only if a step ended exactly there
  EXPECT_LE(seen.back(), 0.5);
}

TEST(GeneralizedAlpha, RejectsBadSettings) {
  GeneralizedAlphaOptions o;
  o.rhoInf = 1.5;
  EXPECT_THROW(GeneralizedAlpha{o}, std::invalid_argument);
  o.rhoInf = -0.1;
  EXPECT_THROW(GeneralizedAlpha{o}, std::invalid_argument);
  o = {};
  o.fixedStep = true;
  EXPECT_THROW(GeneralizedAlpha{o}, std::invalid_argument);
  o = {};
  o.maxStep = 1e-12;
  const Oscillators osc{{1.0}, {0.0}};
  FirstOrderAsSecondOrder sys(osc.rhs(), osc.jacobian(), 1);
  VectorXd y0(2);
  y0 << 1.0, 0.0;
  try {
    GeneralizedAlpha(o).integrate(sys, {0.0, 10.0}, y0, [](double, const VectorXd&) { return true; });
    FAIL() << "a step limit of 1e-12 over 10 s must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("1e-12"), std::string::npos) << e.what();
  }
}

}  // namespace
