// Tests of solvers::Bdf (SUNDIALS CVODE BDF) against closed-form solutions: a stiff pair of damped
// oscillators with the analytic Jacobian and with difference quotients, output times, statistics,
// recoverable and unrecoverable failures, the accepted-step hook, argument checks.
#include "solvers/Bdf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "solvers/Ode45.hpp"
#include "solvers/tests/OdeTrace.hpp"

using namespace flexmb::solvers;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

using test::recorder;
using test::Trace;

// Two decoupled damped oscillators x'' + 2 zeta w x' + w^2 x = 0, y = [x1, x2, v1, v2]: a slow
// lightly damped one (1 Hz) and a stiff one (w = 1e4 rad/s, zeta = 0.5), as a flexible model's
// slow mode and its stiff, irrelevant one.
struct StiffPair {
  double w[2] = {2 * M_PI, 1e4};
  double zeta[2] = {0.05, 0.5};
  VectorXd y0() const {
    VectorXd y(4);
    y << 1.0, 0.1, 0.0, 0.0;
    return y;
  }
  void rhs(const VectorXd& y, VectorXd& dy) const {
    for (int i = 0; i < 2; ++i) {
      dy[i] = y[2 + i];
      dy[2 + i] = -w[i] * w[i] * y[i] - 2 * zeta[i] * w[i] * y[2 + i];
    }
  }
  void jacobian(Eigen::Ref<MatrixXd> J) const {
    J.setZero();
    for (int i = 0; i < 2; ++i) {
      J(i, 2 + i) = 1.0;
      J(2 + i, i) = -w[i] * w[i];
      J(2 + i, 2 + i) = -2 * zeta[i] * w[i];
    }
  }
  // Exact x_i(t) from x(0) = x0, x'(0) = 0 (underdamped).
  double exact(int i, double t, double x0) const {
    const double s = zeta[i] * w[i], wd = w[i] * std::sqrt(1 - zeta[i] * zeta[i]);
    return x0 * std::exp(-s * t) * (std::cos(wd * t) + s / wd * std::sin(wd * t));
  }
};

std::vector<double> grid(double t0, double t1, int intervals) {
  std::vector<double> g;
  for (int i = 0; i <= intervals; ++i) g.push_back(t0 + (t1 - t0) * i / intervals);
  return g;
}

Trace runPair(bool analytic, double relTol, double absTol, const std::vector<double>& tspan) {
  const StiffPair p;
  BdfOptions o;
  o.relTol = relTol;
  o.absTol = absTol;
  Trace r;
  OdeJacobian jac;
  if (analytic) jac = [&](double, const VectorXd&, const VectorXd&, Eigen::Ref<MatrixXd> J) { p.jacobian(J); };
  r.res =
      Bdf(o).integrate([&](double, const VectorXd& y, VectorXd& dy) { p.rhs(y, dy); }, jac, tspan, p.y0(), recorder(r));
  return r;
}

double worstError(const Trace& r) {
  const StiffPair p;
  double worst = 0.0;
  for (size_t k = 0; k < r.t.size(); ++k)
    worst =
        std::max({worst, std::abs(r.y[k][0] - p.exact(0, r.t[k], 1.0)), std::abs(r.y[k][1] - p.exact(1, r.t[k], 0.1))});
  return worst;
}

}  // namespace

// The stiff pair against its exact solution, with the analytic Jacobian: the error shrinks with the
// tolerance (BDF is convergent at orders up to 5), no right-hand side is spent on Jacobians, and the
// outputs are exactly at the requested times, tf included.
TEST(Bdf, StiffOscillatorsAgainstExactSolution) {
  const std::vector<double> tspan = grid(0.0, 2.0, 40);
  double previous = INFINITY;
  for (double tol : {1e-4, 1e-6, 1e-8}) {
    const Trace r = runPair(true, tol, 1e-3 * tol, tspan);
    ASSERT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
    ASSERT_EQ(r.t.size(), tspan.size());
    for (size_t k = 0; k < tspan.size(); ++k) EXPECT_EQ(r.t[k], tspan[k]);
    const double err = worstError(r);
    // The global error over 2 periods is a modest multiple of the local tolerance (measured: 35x,
    // 15x, 33x at RelTol 1e-4, 1e-6, 1e-8), and it decreases with the tolerance.
    EXPECT_LT(err, 500 * tol) << "RelTol " << tol;
    EXPECT_LT(err, previous) << "RelTol " << tol;
    previous = err;
    const OdeStats& s = r.res.stats;
    EXPECT_EQ(s.njacfevals, 0);
    EXPECT_GT(s.njacevals, 0);
    EXPECT_GE(s.nlinsetups, s.njacevals);
    EXPECT_GT(s.nsteps, 0);
    EXPECT_GE(s.nfevals, s.nsteps);
    EXPECT_EQ(r.res.tLast, 2.0);
  }
}

// What the implicit integrator is for: the stiff mode (w = 1e4 rad/s) bounds an explicit method's
// step (h < ~3.3/w, >= 600 steps over 2 s) but not BDF's, which follows the slow mode.
TEST(Bdf, StiffModeDoesNotBoundTheStep) {
  const Trace b = runPair(true, 1e-6, 1e-9, {0.0, 2.0});
  ASSERT_EQ(b.res.status, OdeStatus::Success) << b.res.message;
  const StiffPair p;
  Ode45Options o;
  o.relTol = 1e-6;
  o.absTol = VectorXd::Constant(1, 1e-9);
  Trace e;
  e.res = Ode45(o).integrate([&](double, const VectorXd& y, VectorXd& dy) { p.rhs(y, dy); }, {0.0, 2.0}, p.y0(),
                             recorder(e));
  ASSERT_EQ(e.res.status, OdeStatus::Success);
  EXPECT_GT(e.res.stats.nsteps, 600);
  EXPECT_LT(5 * b.res.stats.nfevals, e.res.stats.nfevals)
      << "BDF " << b.res.stats.nfevals << ", ode45 " << e.res.stats.nfevals;
  // Two-point tspan: one output per accepted step, the last exactly at tf.
  EXPECT_EQ(static_cast<long>(b.t.size()), 1 + b.res.stats.nsteps);
  EXPECT_EQ(b.t.back(), 2.0);
  for (size_t k = 1; k < b.t.size(); ++k) EXPECT_GT(b.t[k], b.t[k - 1]);
}

// Without a Jacobian function CVODE builds it from difference quotients: n evaluations each,
// counted in nfevals and njacfevals; same solution within the tolerance.
TEST(Bdf, DifferenceQuotientJacobianAgrees) {
  const std::vector<double> tspan = grid(0.0, 2.0, 40);
  const Trace a = runPair(true, 1e-7, 1e-10, tspan);
  const Trace d = runPair(false, 1e-7, 1e-10, tspan);
  ASSERT_EQ(d.res.status, OdeStatus::Success) << d.res.message;
  EXPECT_EQ(d.res.stats.njacfevals, 4 * d.res.stats.njacevals);
  EXPECT_GT(d.res.stats.njacevals, 0);
  EXPECT_LT(worstError(d), 500 * 1e-7);
  for (size_t k = 0; k < tspan.size(); ++k) EXPECT_NEAR(a.y[k][0], d.y[k][0], 1e-4) << tspan[k];
}

TEST(Bdf, BackwardIntegration) {
  // y' = -2y + t from t = 3 back to 0: y = t/2 - 1/4 + exp(-2t)/4. Backwards the exp(-2t) part
  // grows by e^6 ~ 400, and the local errors with it (measured: 1.2e-7 at t = 0 with RelTol 1e-11).
  auto exact = [](double t) { return t / 2 - 0.25 + std::exp(-2 * t) / 4; };
  BdfOptions o;
  o.relTol = 1e-11;
  o.absTol = 1e-14;
  Trace r;
  r.res = Bdf(o).integrate([](double t, const VectorXd& y, VectorXd& dy) { dy[0] = -2 * y[0] + t; },
                           [](double, const VectorXd&, const VectorXd&, Eigen::Ref<MatrixXd> J) { J(0, 0) = -2; },
                           {3.0, 1.5, 0.0}, VectorXd::Constant(1, exact(3.0)), recorder(r));
  ASSERT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
  ASSERT_EQ(r.t.size(), 3u);
  EXPECT_EQ(r.t[2], 0.0);
  EXPECT_NEAR(r.y[1][0], exact(1.5), 1e-6);
  EXPECT_NEAR(r.y[2][0], exact(0.0), 1e-6);
}

// The hook sees (t0, y0) and then every accepted state the integration continues from.
TEST(Bdf, AcceptedStepHook) {
  const StiffPair p;
  std::vector<double> seen;
  Trace r;
  r.res = Bdf().integrate([&](double, const VectorXd& y, VectorXd& dy) { p.rhs(y, dy); },
                          [&](double, const VectorXd&, const VectorXd&, Eigen::Ref<MatrixXd> J) { p.jacobian(J); },
                          {0.0, 1.0}, p.y0(), recorder(r), [&](double t, const VectorXd&) { seen.push_back(t); });
  ASSERT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
  ASSERT_EQ(static_cast<long>(seen.size()), r.res.stats.nsteps);  // t0 and every step but the last
  for (size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], r.t[k]);
  // A hook that fails stops the run with its message.
  Trace f;
  f.res = Bdf().integrate([&](double, const VectorXd& y, VectorXd& dy) { p.rhs(y, dy); }, {}, {0.0, 1.0}, p.y0(),
                          recorder(f),
                          [](double t, const VectorXd&) {
                            if (t > 0.2) throw RhsError("kinematics failed");
                          });
  EXPECT_EQ(f.res.status, OdeStatus::RhsFailed);
  EXPECT_NE(f.res.message.find("kinematics failed"), std::string::npos) << f.res.message;
  EXPECT_GT(f.res.tLast, 0.2);
  EXPECT_LT(f.t.back(), 0.5);
}

// A right-hand side that fails once at a trial state: CVODE retries with a smaller step and the run
// completes with the right solution.
TEST(Bdf, RecoversFromATransientRhsFailure) {
  const StiffPair p;
  bool failed = false;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    if (t > 0.3 && !failed) {
      failed = true;
      throw RhsError("Newton did not converge at a trial state");
    }
    p.rhs(y, dy);
  };
  BdfOptions o;
  o.relTol = 1e-7;
  o.absTol = 1e-10;
  Trace r;
  r.res = Bdf(o).integrate(
      f, [&](double, const VectorXd&, const VectorXd&, Eigen::Ref<MatrixXd> J) { p.jacobian(J); }, grid(0.0, 1.0, 10),
      p.y0(), recorder(r));
  ASSERT_TRUE(failed);
  ASSERT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
  EXPECT_LT(worstError(r), 500 * 1e-7);
}

// A right-hand side that fails from some time on: a clean stop with the time and the reason, the
// outputs before it kept.
TEST(Bdf, PersistentRhsFailureStopsCleanly) {
  const StiffPair p;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    if (t > 0.5) throw RhsError("Newton did not converge");
    p.rhs(y, dy);
  };
  Trace r;
  r.res = Bdf().integrate(f, {}, grid(0.0, 2.0, 20), p.y0(), recorder(r));
  EXPECT_NE(r.res.status, OdeStatus::Success);
  EXPECT_NE(r.res.message.find("Newton did not converge"), std::string::npos) << r.res.message;
  EXPECT_NE(r.res.message.find("t = 0.5"), std::string::npos) << r.res.message;
  ASSERT_FALSE(r.t.empty());
  EXPECT_LE(r.t.back(), 0.5);
  EXPECT_LE(r.res.tLast, 0.5);
  EXPECT_GT(r.res.tLast, 0.4);
}

// RhsAbort (Ctrl-C, a failing user function) stops at once: no retry.
TEST(Bdf, AbortStopsAtOnce) {
  const StiffPair p;
  long callsAfter = 0;
  bool aborted = false;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    if (aborted) ++callsAfter;
    if (t > 0.25) {
      aborted = true;
      throw RhsAbort("interrupted");
    }
    p.rhs(y, dy);
  };
  Trace r;
  r.res = Bdf().integrate(f, {}, grid(0.0, 1.0, 10), p.y0(), recorder(r));
  EXPECT_EQ(r.res.status, OdeStatus::RhsFailed);
  EXPECT_NE(r.res.message.find("interrupted"), std::string::npos) << r.res.message;
  EXPECT_EQ(callsAfter, 0);
}

TEST(Bdf, JacobianFailureIsRecoverableThenReported) {
  const StiffPair p;
  auto f = [&](double, const VectorXd& y, VectorXd& dy) { p.rhs(y, dy); };
  Trace r;
  r.res = Bdf().integrate(
      f,
      [](double, const VectorXd&, const VectorXd&, Eigen::Ref<MatrixXd>) { throw RhsError("singular configuration"); },
      grid(0.0, 1.0, 10), p.y0(), recorder(r));
  EXPECT_NE(r.res.status, OdeStatus::Success);
  EXPECT_NE(r.res.message.find("singular configuration"), std::string::npos) << r.res.message;
  EXPECT_EQ(r.t.size(), 1u);  // t0 only
}

TEST(Bdf, NonFiniteRhsAndSingularSolutionStop) {
  // y' = y^2, y(0) = 1: y = 1/(1-t) blows up at t = 1.
  Trace r;
  r.res =
      Bdf().integrate([](double, const VectorXd& y, VectorXd& dy) { dy[0] = y[0] * y[0]; },
                      [](double, const VectorXd& y, const VectorXd&, Eigen::Ref<MatrixXd> J) { J(0, 0) = 2 * y[0]; },
                      {0.0, 2.0}, VectorXd::Constant(1, 1.0), recorder(r));
  EXPECT_NE(r.res.status, OdeStatus::Success);
  EXPECT_LT(r.res.tLast, 1.0);
  EXPECT_GT(r.res.tLast, 0.99);
  EXPECT_NE(r.res.message.find("t = 0.99"), std::string::npos) << r.res.message;
  for (const auto& y : r.y) EXPECT_TRUE(y.allFinite());
  // NaN from the right-hand side after t = 0.5.
  Trace n;
  n.res = Bdf().integrate(
      [](double t, const VectorXd& y, VectorXd& dy) {
        dy[0] = -y[0];
        if (t > 0.5) dy[0] = std::numeric_limits<double>::quiet_NaN();
      },
      {}, {0.0, 1.0}, VectorXd::Constant(1, 1.0), recorder(n));
  EXPECT_EQ(n.res.status, OdeStatus::RhsFailed);
  EXPECT_NE(n.res.message.find("non-finite"), std::string::npos) << n.res.message;
  EXPECT_LE(n.res.tLast, 0.5);
}

TEST(Bdf, ObserverCanStop) {
  int rows = 0;
  const OdeResult res =
      Bdf().integrate([](double, const VectorXd& y, VectorXd& dy) { dy[0] = -y[0]; }, {}, grid(0.0, 1.0, 10),
                      VectorXd::Constant(1, 1.0), [&](double, const VectorXd&) { return ++rows < 4; });
  EXPECT_EQ(res.status, OdeStatus::Stopped);
  EXPECT_EQ(rows, 4);
}

TEST(Bdf, MaxStepHonoured) {
  BdfOptions o;
  o.maxStep = 0.01;
  Trace r;
  r.res = Bdf(o).integrate([](double, const VectorXd& y, VectorXd& dy) { dy[0] = -y[0]; }, {}, {0.0, 1.0},
                           VectorXd::Constant(1, 1.0), recorder(r));
  ASSERT_EQ(r.res.status, OdeStatus::Success);
  for (size_t k = 1; k < r.t.size(); ++k) EXPECT_LE(r.t[k] - r.t[k - 1], 0.01 * (1 + 1e-12));
  EXPECT_GE(r.res.stats.nsteps, 100);
}

TEST(Bdf, RejectsBadArguments) {
  const auto f = [](double, const VectorXd& y, VectorXd& dy) { dy = -y; };
  const auto obs = [](double, const VectorXd&) { return true; };
  EXPECT_THROW(Bdf().integrate(f, {}, {0.0}, VectorXd::Ones(1), obs), std::invalid_argument);
  EXPECT_THROW(Bdf().integrate(f, {}, {0.0, 2.0, 1.0}, VectorXd::Ones(1), obs), std::invalid_argument);
  EXPECT_THROW(Bdf().integrate(f, {}, {0.0, 1.0}, VectorXd(), obs), std::invalid_argument);
  EXPECT_THROW(Bdf().integrate(f, {}, {0.0, 1.0}, VectorXd::Constant(1, NAN), obs), std::invalid_argument);
  using Change = void (*)(BdfOptions&);
  for (Change bad :
       std::initializer_list<Change>{[](BdfOptions& o) { o.relTol = 0; }, [](BdfOptions& o) { o.absTol = -1; },
                                     [](BdfOptions& o) { o.maxStep = -1; }, [](BdfOptions& o) { o.maxOrder = 6; },
                                     [](BdfOptions& o) { o.relTol = NAN; }}) {
    BdfOptions o;
    bad(o);
    EXPECT_THROW(Bdf{o}, std::invalid_argument);
  }
  EXPECT_NE(Bdf::library().find("CVODE 6."), std::string::npos);
}
