// Tests of solvers::Ode45 against MATLAB's reference counts and closed-form solutions.
#include "solvers/Ode45.hpp"
#include "solvers/tests/OdeTrace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "solvers/tests/OdeTrace.hpp"

using namespace flexmb::solvers;
using Eigen::VectorXd;

namespace {

using test::Trace;

Trace run(const OdeRhs& f, const std::vector<double>& tspan, const VectorXd& y0, Ode45Options o = {}) {
  Trace r;
  r.res = Ode45(o).integrate(f, tspan, y0, test::recorder(r));
  return r;
}

// y' = -2y + t, y(0) = 0: y = t/2 - 1/4 + exp(-2t)/4.
void linearRhs(double t, const VectorXd& y, VectorXd& dy) { dy[0] = -2.0 * y[0] + t; }
double linearExact(double t) { return t / 2 - 0.25 + std::exp(-2 * t) / 4; }

void vdp(double, const VectorXd& y, VectorXd& dy) {  // Van der Pol, mu = 1
  dy[0] = y[1];
  dy[1] = (1 - y[0] * y[0]) * y[1] - y[0];
}
void oscillator(double, const VectorXd& y, VectorXd& dy) {  // x'' = -x
  dy[0] = y[1];
  dy[1] = -y[0];
}

VectorXd vec(std::initializer_list<double> v) {
  VectorXd x(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double d : v) x[i++] = d;
  return x;
}

void expectCounts(const Trace& r, long nsteps, long nfailed, long nfevals, std::size_t rows) {
  EXPECT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
  EXPECT_EQ(r.res.stats.nsteps, nsteps);
  EXPECT_EQ(r.res.stats.nfailed, nfailed);
  EXPECT_EQ(r.res.stats.nfevals, nfevals);
  EXPECT_EQ(r.t.size(), rows);
  EXPECT_EQ(r.res.stats.nfevals, 1 + 6 * (r.res.stats.nsteps + r.res.stats.nfailed));
}

}  // namespace

// 1. Reference rows of docs/theory/ode45.md.
TEST(Ode45, ReferenceLinearScalar) {
  const Trace r = run(linearRhs, {0.0, 10.0}, vec({0.0}));
  expectCounts(r, 14, 2, 97, 57);
  EXPECT_EQ(Ode45::formatStats(r.res.stats), "14 successful steps\n2 failed attempts\n97 function evaluations\n");
  EXPECT_EQ(r.t.front(), 0.0);
  EXPECT_EQ(r.t.back(), 10.0);  // last step stretched exactly onto tf
  EXPECT_EQ(r.res.tLast, 10.0);
}

TEST(Ode45, ReferenceLinearFirstStepHistory) {
  // docs/theory/ode45.md: h = 1 rejected, h = 0.37478 rejected, accepted at h = 0.18739. So 1 + 3*6 = 19 rhs calls
  // happen before the first output after t0, and that step ends at 0.18739 (row 4 with Refine = 4).
  long calls = 0;
  std::vector<long> callsAtRow;
  std::vector<double> ts;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) { ++calls, linearRhs(t, y, dy); };
  Ode45().integrate(f, {0.0, 10.0}, vec({0.0}), [&](double t, const VectorXd&) {
    ts.push_back(t);
    callsAtRow.push_back(calls);
    return true;
  });
  ASSERT_GE(ts.size(), 5u);
  EXPECT_EQ(callsAtRow[0], 1);
  EXPECT_EQ(callsAtRow[1], 19);
  EXPECT_NEAR(ts[4], 0.18739, 5e-6);
  for (int j = 1; j < 4; ++j) EXPECT_NEAR(ts[j], j * ts[4] / 4, 1e-15);
  EXPECT_EQ(callsAtRow[5], 25);  // the second step is accepted at once
}

TEST(Ode45, ReferenceVanDerPolDefaults) {
  const Trace r = run(vdp, {0.0, 20.0}, vec({2.0, 0.0}));
  expectCounts(r, 59, 10, 415, 237);
}

TEST(Ode45, ReferenceVanDerPolTight) {
  Ode45Options o;
  o.relTol = 1e-6;
  o.absTol = vec({1e-9});
  const Trace r = run(vdp, {0.0, 20.0}, vec({2.0, 0.0}), o);
  expectCounts(r, 204, 32, 1417, 817);
  // Per-component absTol of the same value must give the same steps.
  o.absTol = vec({1e-9, 1e-9});
  const Trace r2 = run(vdp, {0.0, 20.0}, vec({2.0, 0.0}), o);
  expectCounts(r2, 204, 32, 1417, 817);
}

// 2. Accuracy against closed forms.
TEST(Ode45, AccuracyLinearTight) {
  Ode45Options o;
  o.relTol = 1e-10;
  o.absTol = vec({1e-12});
  const Trace r = run(linearRhs, {0.0, 10.0}, vec({0.0}), o);
  ASSERT_EQ(r.res.status, OdeStatus::Success);
  EXPECT_EQ(r.t.back(), 10.0);
  EXPECT_LT(std::abs(r.y.back()[0] - linearExact(10.0)), 1e-8);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.t.size(); ++i) worst = std::max(worst, std::abs(r.y[i][0] - linearExact(r.t[i])));
  EXPECT_LT(worst, 1e-8);
  // Default tolerances are visibly less accurate (the test can tell them apart).
  const Trace d = run(linearRhs, {0.0, 10.0}, vec({0.0}));
  double worstDefault = 0.0;
  for (std::size_t i = 0; i < d.t.size(); ++i)
    worstDefault = std::max(worstDefault, std::abs(d.y[i][0] - linearExact(d.t[i])));
  EXPECT_GT(worstDefault, 1e-6);
}

TEST(Ode45, AccuracyHarmonicOscillator) {
  Ode45Options o;
  o.relTol = 1e-12;
  o.absTol = vec({1e-14});
  const Trace r = run(oscillator, {0.0, 10.0}, vec({1.0, 0.0}), o);
  ASSERT_EQ(r.res.status, OdeStatus::Success);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.t.size(); i += 4)  // step ends (5th-order values)
    worst = std::max({worst, std::abs(r.y[i][0] - std::cos(r.t[i])), std::abs(r.y[i][1] + std::sin(r.t[i]))});
  EXPECT_LT(worst, 1e-8);
  double worstInterp = 0.0;  // refine points through the 4th-order interpolant
  for (std::size_t i = 0; i < r.t.size(); ++i)
    worstInterp = std::max(worstInterp, std::abs(r.y[i][0] - std::cos(r.t[i])));
  EXPECT_LT(worstInterp, 1e-8);
}

// 3. Output at requested times.
TEST(Ode45, RequestedOutputTimes) {
  std::vector<double> ts;
  for (int i = 0; i <= 10; ++i) ts.push_back(i);
  const Trace r = run(linearRhs, ts, vec({0.0}));
  ASSERT_EQ(r.res.status, OdeStatus::Success);
  ASSERT_EQ(r.t.size(), 11u);
  for (int i = 0; i <= 10; ++i) {
    EXPECT_EQ(r.t[i], ts[i]);
    EXPECT_NEAR(r.y[i][0], linearExact(ts[i]), 1e-3 * std::abs(linearExact(ts[i])) + 1e-4) << "t=" << ts[i];
  }
  // The steps are those of the [0, 10] run.
  EXPECT_EQ(r.res.stats.nsteps, 14);
  EXPECT_EQ(r.res.stats.nfailed, 2);
  EXPECT_EQ(r.res.stats.nfevals, 97);
}

TEST(Ode45, RequestedTimesMatchRefineInterpolant) {
  // Refine points of a step beyond t = 1, asked for explicitly, are reproduced (tspan(2) >= 1 keeps the
  // initial step of the [0, 10] run, so the steps are the same).
  const Trace r = run(linearRhs, {0.0, 10.0}, vec({0.0}));
  std::size_t m = 0;
  while (r.t[4 * m] < 1.0) ++m;
  const Trace q = run(linearRhs, {0.0, r.t[4 * m + 1], r.t[4 * m + 2], r.t[4 * m + 3], 10.0}, vec({0.0}));
  ASSERT_EQ(q.t.size(), 5u);
  for (int j = 1; j <= 3; ++j) EXPECT_EQ(q.y[j][0], r.y[4 * m + j][0]);
  EXPECT_EQ(q.y.back()[0], r.y.back()[0]);
  EXPECT_EQ(q.res.stats.nfevals, 97);
}

TEST(Ode45, RefineOneGivesStepEnds) {
  Ode45Options o;
  o.refine = 1;
  const Trace r = run(linearRhs, {0.0, 10.0}, vec({0.0}), o);
  expectCounts(r, 14, 2, 97, 15);
  const Trace r4 = run(linearRhs, {0.0, 10.0}, vec({0.0}));
  for (std::size_t i = 0; i < r.t.size(); ++i) EXPECT_EQ(r.t[i], r4.t[4 * i]);
}

// 4. Counting rule.
TEST(Ode45, FevalCountingRule) {
  for (double rtol : {1e-2, 1e-3, 1e-5, 1e-8, 1e-11}) {
    Ode45Options o;
    o.relTol = rtol;
    o.absTol = vec({rtol * 1e-3});
    for (auto* f : {&vdp, &oscillator}) {
      const Trace r = run(*f, {0.0, 7.0}, vec({2.0, 0.0}), o);
      ASSERT_EQ(r.res.status, OdeStatus::Success);
      EXPECT_EQ(r.res.stats.nfevals, 1 + 6 * (r.res.stats.nsteps + r.res.stats.nfailed)) << rtol;
      EXPECT_EQ(r.t.size(), 1u + 4u * r.res.stats.nsteps);
    }
  }
}

// 5. Failing right-hand sides.
// A right-hand side that fails from some time on: the steps creep up to that time and the run stops
// there (the solution itself runs into the failure), with the reason and the results before it.
TEST(Ode45, RhsErrorOnTheSolutionStopsCleanly) {
  auto f = [](double t, const VectorXd& y, VectorXd& dy) {
    if (t > 0.5) throw RhsError("Newton did not converge");
    vdp(t, y, dy);
  };
  const Trace r = run(f, {0.0, 2.0}, vec({2.0, 0.0}));
  EXPECT_EQ(r.res.status, OdeStatus::RhsFailed);
  EXPECT_NE(r.res.message.find("Newton did not converge"), std::string::npos) << r.res.message;
  EXPECT_NE(r.res.message.find("t = 0.5"), std::string::npos) << r.res.message;
  ASSERT_FALSE(r.t.empty());
  EXPECT_LE(r.t.back(), 0.5);
  EXPECT_GT(r.t.back(), 0.5 - 1e-12);  // crept up to the failure
  EXPECT_EQ(r.t.back(), r.res.tLast);
  EXPECT_EQ(r.t.size(), 1u + 4u * r.res.stats.nsteps);
  EXPECT_GT(r.res.stats.nrhsfailed, 0);
  EXPECT_LE(r.res.stats.nrhsfailed, r.res.stats.nfailed);
  EXPECT_LT(r.res.stats.nfevals, 2000);  // the creep is geometric, not a crawl
  // The diagnostic says where (the last accepted state), that the minimum step was reached, and why.
  EXPECT_NE(r.res.message.find("accepted state at t = "), std::string::npos) << r.res.message;
  EXPECT_NE(r.res.message.find("minimum step"), std::string::npos) << r.res.message;
  for (const auto& y : r.y) EXPECT_TRUE(y.allFinite());
}

// x'' = -w^2 x + F sin(t), w = 1000, at rest at t = 0: f(t0, y0) = 0, so ode45's first trial step is
// the whole first output interval, far beyond the stiff mode's stability limit. Its stages leave
// the region |x| < 1e-4 where this right-hand side (like a kinematic solve with no configuration
// there) can be evaluated; the solution stays within |x| < 2e-6. The failed attempts are rejected
// like infinite error estimates and the run completes on the exact solution.
TEST(Ode45, RhsFailingAtFarTrialStatesRejectsTheAttempt) {
  const double w = 1000.0, F = 1.0;
  int failures = 0;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    if (std::abs(y[0]) > 1e-4) {
      ++failures;
      throw RhsError("no configuration");
    }
    dy[0] = y[1];
    dy[1] = -w * w * y[0] + F * std::sin(t);
  };
  // x = F (sin t - sin(w t)/w) / (w^2 - 1)
  auto exact = [&](double t) { return F * (std::sin(t) - std::sin(w * t) / w) / (w * w - 1); };
  Ode45Options o;
  o.relTol = 1e-6;
  o.absTol = vec({1e-12});
  Trace r;
  int retries = 0;
  r.res = Ode45(o).integrate(
      f, {0.0, 0.5, 1.0}, vec({0.0, 0.0}),
      [&](double t, const VectorXd& y) {
        r.t.push_back(t);
        r.y.push_back(y);
        return true;
      },
      {}, [&](double t, const VectorXd& y) { retries += t == 0.0 && y.isZero(); });
  ASSERT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
  EXPECT_GE(r.res.stats.nrhsfailed, 1);
  EXPECT_GE(retries, r.res.stats.nrhsfailed);  // each such attempt restarts from the accepted state
  EXPECT_EQ(r.res.stats.nrhsfailed, failures);
  EXPECT_LE(r.res.stats.nrhsfailed, r.res.stats.nfailed);
  // Every call is counted, also the ones that failed (so the counting rule no longer holds exactly).
  EXPECT_LT(r.res.stats.nfevals, 1 + 6 * (r.res.stats.nsteps + r.res.stats.nfailed));
  ASSERT_EQ(r.t.size(), 3u);
  for (std::size_t i = 0; i < r.t.size(); ++i) EXPECT_NEAR(r.y[i][0], exact(r.t[i]), 1e-3 * 2e-6) << r.t[i];
  EXPECT_NE(Ode45::formatStats(r.res.stats).find("the right-hand side failed at a trial state"), std::string::npos);
}

// RhsAbort (Ctrl-C, a failing user function) is no trial-state failure: the run stops at once.
TEST(Ode45, RhsAbortStopsAtOnce) {
  int calls = 0;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    ++calls;
    if (t > 0.5) throw RhsAbort("interrupted");
    vdp(t, y, dy);
  };
  const Trace r = run(f, {0.0, 2.0}, vec({2.0, 0.0}));
  EXPECT_EQ(r.res.status, OdeStatus::RhsFailed);
  EXPECT_NE(r.res.message.find("interrupted"), std::string::npos) << r.res.message;
  EXPECT_EQ(r.res.stats.nrhsfailed, 0);
  EXPECT_EQ(r.res.stats.nfevals, calls);
  EXPECT_LT(r.t.back(), 0.5);
}

// The hooks: accepted sees (t0, y0) and then every accepted state right after its FSAL evaluation;
// retry sees the accepted state a step starts again from after an attempt far off the solution
// (RhsFailingAtFarTrialStatesRejectsTheAttempt). A throwing hook stops the run.
TEST(Ode45, StepHooks) {
  std::vector<double> acceptedT, retryT;
  double lastEvalT = std::numeric_limits<double>::quiet_NaN();
  VectorXd lastEvalY;
  bool hookAfterItsState = true;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    lastEvalT = t;
    lastEvalY = y;
    linearRhs(t, y, dy);
  };
  VectorXd lastAcceptedY;
  Trace r;
  r.res = Ode45().integrate(
      f, {0.0, 10.0}, vec({0.0}),
      [&](double t, const VectorXd& y) {
        r.t.push_back(t);
        r.y.push_back(y);
        return true;
      },
      [&](double t, const VectorXd& y) {
        hookAfterItsState &= t == lastEvalT && y == lastEvalY;
        acceptedT.push_back(t);
        lastAcceptedY = y;
      },
      [&](double t, const VectorXd& y) {
        retryT.push_back(t);
        hookAfterItsState &= !acceptedT.empty() && t == acceptedT.back() && y == lastAcceptedY;
      });
  expectCounts(r, 14, 2, 97, 57);  // the reference counts are untouched
  ASSERT_EQ(acceptedT.size(), 15u);
  EXPECT_EQ(acceptedT.front(), 0.0);
  EXPECT_EQ(acceptedT.back(), 10.0);
  for (std::size_t i = 0; i < acceptedT.size(); ++i) EXPECT_EQ(acceptedT[i], r.t[4 * i]);
  // Its two rejections (err/RelTol 44.3, then below 10) are ordinary, not far off the solution.
  EXPECT_TRUE(retryT.empty());
  EXPECT_TRUE(hookAfterItsState);

  const OdeResult stop = Ode45().integrate(
      linearRhs, {0.0, 10.0}, vec({0.0}), [](double, const VectorXd&) { return true; },
      [](double t, const VectorXd&) {
        if (t > 1.0) throw RhsError("anchor failed");
      });
  EXPECT_EQ(stop.status, OdeStatus::RhsFailed);
  EXPECT_NE(stop.message.find("anchor failed"), std::string::npos) << stop.message;
  EXPECT_GT(stop.tLast, 1.0);
}

TEST(Ode45, NonFiniteRhsStopsCleanly) {
  auto f = [](double t, const VectorXd& y, VectorXd& dy) {
    vdp(t, y, dy);
    if (t > 0.5) dy[1] = std::numeric_limits<double>::quiet_NaN();
  };
  const Trace r = run(f, {0.0, 2.0}, vec({2.0, 0.0}));
  EXPECT_EQ(r.res.status, OdeStatus::RhsFailed);
  EXPECT_NE(r.res.message.find("t = 0.5"), std::string::npos) << r.res.message;
  EXPECT_NE(r.res.message.find("non-finite"), std::string::npos) << r.res.message;
  ASSERT_FALSE(r.t.empty());
  EXPECT_LE(r.t.back(), 0.5);
  for (const auto& y : r.y) EXPECT_TRUE(y.allFinite());
}

TEST(Ode45, FailureAtInitialPoint) {
  int calls = 0;
  auto f = [&](double, const VectorXd&, VectorXd&) {
    ++calls;
    throw RhsError("bad start");
  };
  const Trace r = run(f, {0.0, 1.0}, vec({1.0}));
  EXPECT_EQ(r.res.status, OdeStatus::RhsFailed);
  EXPECT_TRUE(r.t.empty());
  EXPECT_EQ(calls, 1);
}

// 6. Blow-up: y' = y^2, y(0) = 1, y = 1/(1-t).
TEST(Ode45, BlowUpTerminates) {
  auto f = [](double, const VectorXd& y, VectorXd& dy) { dy[0] = y[0] * y[0]; };
  const Trace r = run(f, {0.0, 2.0}, vec({1.0}));
  EXPECT_NE(r.res.status, OdeStatus::Success);
  EXPECT_LT(r.res.tLast, 1.0);
  EXPECT_GT(r.res.tLast, 0.99);
  EXPECT_FALSE(r.res.message.empty());
  EXPECT_NE(r.res.message.find("t = "), std::string::npos) << r.res.message;
  for (const auto& y : r.y) EXPECT_TRUE(y.allFinite());
  if (r.res.status == OdeStatus::StepSizeUnderflow) {
    EXPECT_NE(r.res.message.find("h = "), std::string::npos) << r.res.message;
  }
}

TEST(Ode45, UnderflowWithSingularRhs) {
  // y' = 1/(1-t)^2 with tight tolerance: y = 1/(1-t) as well, but through t only.
  auto f = [](double t, const VectorXd&, VectorXd& dy) { dy[0] = 1.0 / ((1 - t) * (1 - t)); };
  Ode45Options o;
  o.relTol = 1e-10;
  o.absTol = vec({1e-12});
  const Trace r = run(f, {0.0, 2.0}, vec({1.0}), o);
  EXPECT_NE(r.res.status, OdeStatus::Success);
  EXPECT_LT(r.res.tLast, 1.0);
  EXPECT_GT(r.res.tLast, 0.99);
  EXPECT_NE(r.res.message.find("t = 0.99"), std::string::npos) << r.res.message;
}

// 7. MaxStep.
TEST(Ode45, MaxStepHonoured) {
  Ode45Options o;
  o.maxStep = 0.01;
  const Trace r = run(oscillator, {0.0, 2.0}, vec({1.0, 0.0}), o);
  ASSERT_EQ(r.res.status, OdeStatus::Success);
  EXPECT_GE(r.res.stats.nsteps, 200);
  double hbig = 0.0;
  for (std::size_t i = 4; i < r.t.size(); i += 4) hbig = std::max(hbig, r.t[i] - r.t[i - 4]);
  EXPECT_LE(hbig, 0.01 * (1 + 1e-12));
  EXPECT_GT(hbig, 0.009);
  // Without the option the same problem takes far larger steps.
  const Trace d = run(oscillator, {0.0, 2.0}, vec({1.0, 0.0}));
  EXPECT_LT(5 * d.res.stats.nsteps, r.res.stats.nsteps);
}

// Extras: backward integration, observer stop, initial step, argument checks.
TEST(Ode45, BackwardIntegration) {
  Ode45Options o;
  o.relTol = 1e-10;
  o.absTol = vec({1e-12});
  // y' = -2y + t backwards from t = 3 to 0 (the solution grows backwards like exp(-2t)).
  const Trace r = run(linearRhs, {3.0, 0.0}, vec({linearExact(3.0)}), o);
  ASSERT_EQ(r.res.status, OdeStatus::Success) << r.res.message;
  EXPECT_EQ(r.t.back(), 0.0);
  for (std::size_t i = 1; i < r.t.size(); ++i) EXPECT_LT(r.t[i], r.t[i - 1]);
  EXPECT_NEAR(r.y.back()[0], 0.0, 1e-8);
  EXPECT_EQ(r.res.stats.nfevals, 1 + 6 * (r.res.stats.nsteps + r.res.stats.nfailed));
}

TEST(Ode45, ObserverCanStop) {
  int rows = 0;
  const OdeResult res =
      Ode45().integrate(linearRhs, {0.0, 10.0}, vec({0.0}), [&](double, const VectorXd&) { return ++rows < 10; });
  EXPECT_EQ(res.status, OdeStatus::Stopped);
  EXPECT_EQ(rows, 10);
  EXPECT_EQ(res.stats.nsteps, 3);  // row 10 is the 2nd refine point of step 3
}

TEST(Ode45, UserInitialStep) {
  Ode45Options o;
  o.initialStep = 0.01;
  const Trace r = run(linearRhs, {0.0, 10.0}, vec({0.0}), o);
  ASSERT_EQ(r.res.status, OdeStatus::Success);
  EXPECT_DOUBLE_EQ(r.t[4], 0.01);  // first step accepted as given (smooth start, small step)
}

TEST(Ode45, RejectsBadArguments) {
  EXPECT_THROW(Ode45().integrate(linearRhs, {0.0}, vec({0.0}), [](double, const VectorXd&) { return true; }),
               std::invalid_argument);
  EXPECT_THROW(
      Ode45().integrate(linearRhs, {0.0, 2.0, 1.0, 3.0}, vec({0.0}), [](double, const VectorXd&) { return true; }),
      std::invalid_argument);
  Ode45Options o;
  o.absTol = vec({1e-6, 1e-6, 1e-6});
  EXPECT_THROW(Ode45(o).integrate(vdp, {0.0, 1.0}, vec({1.0, 0.0}), [](double, const VectorXd&) { return true; }),
               std::invalid_argument);
  o = {};
  o.relTol = 0.0;
  EXPECT_THROW(Ode45{o}, std::invalid_argument);
}

// The step monitor's h |lambda| (Hairer's stiffness estimate from the stages at t + h) on
// y' = lambda y: exactly h |lambda| for a linear problem. On a stiff one (lambda = -1e4 over 1 s, the
// solution gone after 1e-3 s) the steps sit at the stability boundary of Dormand-Prince (|h lambda|
// about 3.3) instead of growing; the monitor changes no step, and returning false stops the run
// with every output up to there given.
TEST(Ode45, StepMonitorEstimatesTheStiffestEigenvalue) {
  const double lambda = -1e4;
  auto f = [&](double, const VectorXd& y, VectorXd& dy) { dy[0] = lambda * y[0]; };
  Ode45Options o;
  long monitored = 0, late = 0;
  double worst = 0.0, sum = 0.0;
  o.stepMonitor = [&](double t, const VectorXd&, double h, double hLambda) {
    ++monitored;
    if (t > 0.01) {  // the transient (an accuracy-bound start) is over
      worst = std::max(worst, std::abs(hLambda / (h * std::abs(lambda)) - 1.0));
      sum += hLambda;
      ++late;
    }
    return true;
  };
  const Trace with = run(f, {0.0, 1.0}, vec({1.0}), o);
  const Trace without = run(f, {0.0, 1.0}, vec({1.0}));
  ASSERT_EQ(with.res.status, OdeStatus::Success);
  EXPECT_EQ(with.res.stats.nsteps, without.res.stats.nsteps);
  EXPECT_EQ(with.res.stats.nfevals, without.res.stats.nfevals);
  EXPECT_EQ(monitored, with.res.stats.nsteps);
  EXPECT_LT(worst, 1e-6);
  // Bound by stability: the controller hovers around the boundary (h |lambda| on average near 3.3),
  // about |lambda| / 3.3 steps per second.
  ASSERT_GT(late, 0);
  EXPECT_GT(sum / late, 2.8);
  EXPECT_LT(sum / late, 3.6);
  EXPECT_GT(with.res.stats.nsteps, 2000);

  o.stepMonitor = [](double t, const VectorXd&, double, double) { return t < 0.5; };
  const Trace stopped = run(f, {0.0, 1.0}, vec({1.0}), o);
  EXPECT_EQ(stopped.res.status, OdeStatus::Stopped);
  ASSERT_FALSE(stopped.t.empty());
  EXPECT_GE(stopped.t.back(), 0.5);
  EXPECT_LT(stopped.t.back(), 0.5 + 1e-3);
}
