// Ode45: see ../shared/spec/ode45.md (the contract) and Shampine & Reichelt, SIAM J. Sci. Comput. 1997.
#include "solvers/Ode45.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <utility>

namespace flexmb::solvers {
namespace {

// Dormand-Prince tableau (ode45.md "Tableau"). Row j holds the coefficients of stage j+1 (0-based
// k[0..j-1]); row 5 is b (ynew), which also defines the FSAL stage k[6] = f(tnew, ynew).
constexpr double C[7] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0};
constexpr double A[6][6] = {{1.0 / 5},
                            {3.0 / 40, 9.0 / 40},
                            {44.0 / 45, -56.0 / 15, 32.0 / 9},
                            {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
                            {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
                            {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
constexpr double E[7] = {71.0 / 57600, 0.0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525, -1.0 / 40};
// Free 4th-order interpolant (ode45.md "Interpolant"): y(t + s h) = y + h sum_j k_j (B_j . [s s^2 s^3 s^4]).
constexpr double BI[7][4] = {{1.0, -183.0 / 64, 37.0 / 12, -145.0 / 128},
                             {0.0, 0.0, 0.0, 0.0},
                             {0.0, 1500.0 / 371, -1000.0 / 159, 1000.0 / 371},
                             {0.0, -125.0 / 32, 125.0 / 12, -375.0 / 64},
                             {0.0, 9477.0 / 3392, -729.0 / 106, 25515.0 / 6784},
                             {0.0, -11.0 / 7, 11.0 / 3, -55.0 / 28},
                             {0.0, 3.0 / 2, -4.0, 5.0 / 2}};
constexpr double kPow = 1.0 / 5;

// MATLAB's eps(t): spacing of doubles at |t| (eps(0) is the smallest subnormal).
double epsAt(double t) {
  const double a = std::fabs(t);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

// Shortest round-trip text of v (so a time just below 1 does not print as 1).
std::string num(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

Ode45::Ode45(Ode45Options options) : opt_(std::move(options)) {
  if (!(opt_.relTol > 0.0)) throw std::invalid_argument("Ode45: relTol must be positive");
  if (!(opt_.maxStep >= 0.0)) throw std::invalid_argument("Ode45: maxStep must be >= 0");
  if (!(opt_.initialStep >= 0.0)) throw std::invalid_argument("Ode45: initialStep must be >= 0");
  if (opt_.refine < 1) throw std::invalid_argument("Ode45: refine must be >= 1");
  if (opt_.absTol.size() > 0 && !(opt_.absTol.minCoeff() > 0.0))
    throw std::invalid_argument("Ode45: absTol must be positive");
}

std::string Ode45::formatStats(const OdeStats& s) {
  std::string out = std::to_string(s.nsteps) + " successful steps\n" + std::to_string(s.nfailed) +
                    " failed attempts\n" + std::to_string(s.nfevals) + " function evaluations\n";
  if (s.nrhsfailed > 0)
    out +=
        "(" + std::to_string(s.nrhsfailed) + " of the failed attempts: the right-hand side failed at a trial state)\n";
  return out;
}

OdeResult Ode45::integrate(const OdeRhs& f, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                           const OdeObserver& observer, const OdeStepHook& accepted, const OdeStepHook& retry) const {
  using Eigen::VectorXd;
  const Eigen::Index n = y0.size();
  const std::size_t ntspan = tspan.size();
  if (ntspan < 2) throw std::invalid_argument("Ode45: tspan needs at least 2 entries");
  const double t0 = tspan.front(), tf = tspan.back();
  if (!(t0 != tf) || !std::isfinite(t0) || !std::isfinite(tf))
    throw std::invalid_argument("Ode45: tspan must have distinct finite end points");
  const double tdir = tf > t0 ? 1.0 : -1.0;
  for (std::size_t i = 1; i < ntspan; ++i)
    if (!(tdir * (tspan[i] - tspan[i - 1]) > 0.0))
      throw std::invalid_argument("Ode45: tspan must be strictly monotonic");
  if (opt_.absTol.size() != 0 && opt_.absTol.size() != 1 && opt_.absTol.size() != n)
    throw std::invalid_argument("Ode45: absTol must have size 0, 1 or y0.size()");
  if (!y0.allFinite()) throw std::invalid_argument("Ode45: y0 is not finite");

  // Options (ode45.md "Options and defaults").
  const double rtol = std::max(opt_.relTol, 100.0 * std::numeric_limits<double>::epsilon());
  VectorXd threshold(n);
  if (opt_.absTol.size() == 0)
    threshold.setConstant(1e-6 / rtol);
  else if (opt_.absTol.size() == 1)
    threshold.setConstant(opt_.absTol[0] / rtol);
  else
    threshold = opt_.absTol / rtol;
  const double span = std::fabs(tf - t0);
  const double hmax = opt_.maxStep > 0.0 ? std::min(span, opt_.maxStep) : 0.1 * span;
  const bool refineOutput = ntspan == 2;
  const int refine = opt_.refine;

  // All work vectors, allocated once.
  std::array<VectorXd, 7> k;
  for (auto& v : k) v.resize(n);
  VectorXd y = y0, ynew(n), ytmp(n), yout(n);

  OdeResult res;
  res.tLast = t0;
  OdeStats& st = res.stats;
  std::string failure;   // reason of a failed rhs evaluation
  bool aborted = false;  // the failure was an RhsAbort: stop at once

  // One rhs evaluation; false (with `failure` set) on RhsError or a non-finite input or value.
  auto eval = [&](double tt, const VectorXd& yy, VectorXd& dy) -> bool {
    if (!yy.allFinite()) {
      failure = "right-hand side failed at t = " + num(tt) + ": non-finite state y";
      return false;
    }
    ++st.nfevals;
    try {
      f(tt, yy, dy);
    } catch (const RhsAbort& e) {
      failure = "right-hand side failed at t = " + num(tt) + ": " + e.what();
      aborted = true;
      return false;
    } catch (const RhsError& e) {
      failure = "right-hand side failed at t = " + num(tt) + ": " + e.what();
      return false;
    }
    if (dy.size() != n || !dy.allFinite()) {
      failure = "right-hand side failed at t = " + num(tt) + ": " +
                (dy.size() != n ? "wrong size of dydt" : "non-finite value in dydt");
      return false;
    }
    return true;
  };
  auto fail = [&](OdeStatus s, std::string msg) {
    res.status = s;
    res.message = std::move(msg);
    return res;
  };
  // A right-hand side that fails at every trial state down to the minimum step: the solution itself
  // runs into the failure (MATLAB's ode45 has no such outcome: its right-hand sides do not fail).
  auto atMinimumStep = [&](double tt, double hh) {
    return " (trial steps from the accepted state at t = " + num(tt) + " failed down to the minimum step " + num(hh) +
           "; results up to there are kept. The model itself fails there, e.g. a singular "
           "configuration or a load it cannot carry)";
  };
  // The hooks may throw RhsError: the run stops with its message.
  auto hook = [&](const OdeStepHook& h, double tt, const VectorXd& yy) -> bool {
    if (!h) return true;
    try {
      h(tt, yy);
    } catch (const RhsError& e) {
      failure = e.what();
      return false;
    }
    return true;
  };
  auto stopped = [&](double tt) { return fail(OdeStatus::Stopped, "stopped by the observer at t = " + num(tt)); };

  double t = t0;
  // Step 1: f1 = f(t0, y0).
  if (!eval(t, y, k[0])) return fail(OdeStatus::RhsFailed, failure);
  if (!hook(accepted, t, y)) return fail(OdeStatus::RhsFailed, failure);
  if (!observer(t, y)) return stopped(t);

  // Step 2: initial step.
  double absh;
  {
    const double hmin = 16.0 * epsAt(t);
    if (opt_.initialStep > 0.0) {
      absh = std::min(hmax, std::max(hmin, opt_.initialStep));
    } else {
      absh = std::min(hmax, std::fabs(tspan[1] - tspan[0]));
      double rh = 0.0;
      for (Eigen::Index i = 0; i < n; ++i)
        rh = std::max(rh, std::fabs(k[0][i]) / std::max(std::fabs(y[i]), threshold[i]));
      rh /= 0.8 * std::pow(rtol, kPow);
      if (absh * rh > 1.0) absh = 1.0 / rh;
      absh = std::max(absh, hmin);
    }
  }

  std::size_t next = 1;  // next requested output time (tspan longer than 2)
  // Interpolated output at tq inside the step [t, t+h] (k[6] is the FSAL stage of the step).
  auto interp = [&](double tq, double h) {
    const double s = (tq - t) / h, s2 = s * s, s3 = s2 * s, s4 = s3 * s;
    yout = y;
    for (int j = 0; j < 7; ++j) {
      const double w = h * (BI[j][0] * s + BI[j][1] * s2 + BI[j][2] * s3 + BI[j][3] * s4);
      if (w != 0.0) yout += w * k[j];
    }
  };

  // out = sum_{i<m} A[row][i] k_i (zero coefficients skipped).
  auto combine = [&](int row, int m, VectorXd& out) {
    out = A[row][0] * k[0];
    for (int i = 1; i < m; ++i)
      if (A[row][i] != 0.0) out += A[row][i] * k[i];
  };

  // The last right-hand-side failure since a step was last accepted at its first attempt: the reason
  // a step-size underflow at the end of such a streak names (the solution running into a fold).
  std::string streakFailure;
  bool done = false;
  while (true) {
    // Step 3: clip the step, the 1.1 rule.
    const double hmin = 16.0 * epsAt(t);
    absh = std::min(hmax, std::max(hmin, absh));
    double h = tdir * absh;
    if (1.1 * absh >= std::fabs(tf - t)) {
      h = tf - t;
      absh = std::fabs(h);
      done = true;
    }
    bool nofailed = true;
    double err = 0.0, tnew;
    while (true) {
      // Step 4: stages k2..k6 (y + h*(sum_i a_ji k_i), the order of MATLAB's ode45), then tnew,
      // the purified h = tnew - t, ynew from b and the FSAL stage k7.
      bool rhsFailed = false;
      for (int j = 1; j <= 5 && !rhsFailed; ++j) {
        combine(j - 1, j, ytmp);
        ytmp = y + h * ytmp;
        rhsFailed = !eval(t + C[j] * h, ytmp, k[j]);
      }
      if (!rhsFailed) {
        tnew = done ? tf : t + h;
        h = tnew - t;
        combine(5, 6, ynew);
        ynew = y + h * ynew;
        rhsFailed = !eval(tnew, ynew, k[6]);
      }
      if (aborted) return fail(OdeStatus::RhsFailed, failure);

      if (!rhsFailed) {
        // Step 5: err = absh * max_i |sum_j E_j k_j,i| / max(|y_i|, |ynew_i|, threshold_i).
        double m = 0.0;
        for (Eigen::Index i = 0; i < n; ++i) {
          double e = 0.0;
          for (int j = 0; j < 7; ++j) e += E[j] * k[j][i];
          const double sc = std::max({std::fabs(y[i]), std::fabs(ynew[i]), threshold[i]});
          m = std::max(m, std::fabs(e) / sc);
        }
        err = absh * m;
        if (err <= rtol) break;
      }

      // Step 6: rejected. A failed right-hand side counts as an infinite error: a trial state far
      // off the solution (stages of a step much too large for the stiffest mode) may have no
      // configuration at all, where the solution has one.
      ++st.nfailed;
      if (rhsFailed) ++st.nrhsfailed, streakFailure = failure;
      if (absh <= hmin) {
        if (rhsFailed) return fail(OdeStatus::RhsFailed, failure + atMinimumStep(t, absh));
        return fail(OdeStatus::StepSizeUnderflow,
                    "step size underflow at t = " + num(t) + ": tolerance cannot be met (h = " + num(absh) +
                        " <= hmin = " + num(hmin) + ")" +
                        (streakFailure.empty()
                             ? ""
                             : "; since the step was last unconstrained, larger trial steps failed: " + streakFailure));
      }
      if (nofailed) {
        nofailed = false;
        const double shrink = rhsFailed ? 0.1 : std::max(0.1, 0.8 * std::pow(rtol / err, kPow));
        absh = std::max(hmin, absh * shrink);
      } else {
        absh = std::max(hmin, 0.5 * absh);
      }
      h = tdir * absh;
      done = false;
      // An attempt far off the solution (a failed right-hand side, or an error estimate of more than
      // 100% relative) may have left the caller's state (a warm start) anywhere: the caller resets it.
      if ((rhsFailed || err > 1.0) && !hook(retry, t, y)) return fail(OdeStatus::RhsFailed, failure);
    }

    // Step 7: accepted; emit output.
    ++st.nsteps;
    if (nofailed) streakFailure.clear();
    res.tLast = tnew;
    if (!hook(accepted, tnew, ynew)) return fail(OdeStatus::RhsFailed, failure);
    if (refineOutput) {
      for (int j = 1; j < refine; ++j) {  // interior points at s = j/refine
        const double tq = t + h * (static_cast<double>(j) / refine);
        interp(tq, h);
        if (!yout.allFinite()) return fail(OdeStatus::RhsFailed, "non-finite interpolated value at t = " + num(tq));
        if (!observer(tq, yout)) return stopped(tnew);
      }
      if (!observer(tnew, ynew)) return stopped(tnew);
    } else {
      while (next < ntspan && tdir * (tnew - tspan[next]) >= 0.0) {
        const double tq = tspan[next++];
        const VectorXd* out = &ynew;
        if (tq != tnew) {
          interp(tq, h);
          if (!yout.allFinite()) return fail(OdeStatus::RhsFailed, "non-finite interpolated value at t = " + num(tq));
          out = &yout;
        }
        if (!observer(tq, *out)) return stopped(tnew);
      }
    }
    if (done) break;

    // Growth only after a step without failure (MATLAB: absh / (1.25*(err/rtol)^(1/5)), factor <= 5).
    if (nofailed) {
      const double temp = 1.25 * std::pow(err / rtol, kPow);
      absh = temp > 0.2 ? absh / temp : 5.0 * absh;
    }
    t = tnew;
    y.swap(ynew);
    k[0].swap(k[6]);  // FSAL
  }
  return res;
}

}  // namespace flexmb::solvers
