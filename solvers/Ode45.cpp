// Ode45: MATLAB's ode45 step by step (the contract: its steps and counts) after Shampine & Reichelt, SIAM J. Sci.
// Comput. 1997.
#include "solvers/Ode45.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include "text/NumberText.hpp"

namespace flexmb::solvers {
namespace {

// Dormand-Prince tableau (docs/theory/ode45.md "Tableau"). Row j holds the coefficients of stage j+1 (0-based
// k[0..j-1]); row 5 is b (ynew), which also defines the FSAL stage k[6] = f(tnew, ynew).
constexpr double C[7] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0};
constexpr double A[6][6] = {{1.0 / 5},
                            {3.0 / 40, 9.0 / 40},
                            {44.0 / 45, -56.0 / 15, 32.0 / 9},
                            {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
                            {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
                            {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
constexpr double E[7] = {71.0 / 57600, 0.0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525, -1.0 / 40};
// Free 4th-order interpolant (docs/theory/ode45.md "Interpolant"):
// y(t + s h) = y + h sum_j k_j (B_j . [s s^2 s^3 s^4]).
constexpr double BI[7][4] = {{1.0, -183.0 / 64, 37.0 / 12, -145.0 / 128},
                             {0.0, 0.0, 0.0, 0.0},
                             {0.0, 1500.0 / 371, -1000.0 / 159, 1000.0 / 371},
                             {0.0, -125.0 / 32, 125.0 / 12, -375.0 / 64},
                             {0.0, 9477.0 / 3392, -729.0 / 106, 25515.0 / 6784},
                             {0.0, -11.0 / 7, 11.0 / 3, -55.0 / 28},
                             {0.0, 3.0 / 2, -4.0, 5.0 / 2}};
constexpr double kPow = 1.0 / 5;

using text::shortest;

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
  if (s.nrhsfailed > 0) {  // appended piecewise: "(" + std::string trips GCC 12's -Wrestrict (tools/README.md)
    out += '(';
    out += std::to_string(s.nrhsfailed);
    out += " of the failed attempts: the right-hand side failed at a trial state)\n";
  }
  return out;
}

namespace {

// One integration (docs/theory/ode45.md steps 1-7): the state of the run and its steps as methods, so the main
// loop reads as the algorithm. Work vectors are allocated once, in the constructor.
class Ode45Run {
 public:
  using VectorXd = Eigen::VectorXd;

  Ode45Run(const Ode45Options& opt, const OdeRhs& f, const std::vector<double>& tspan, const VectorXd& y0,
           const OdeObserver& observer, const OdeStepHook& accepted, const OdeStepHook& retry)
      : opt_(opt), f_(f), tspan_(tspan), observer_(observer), accepted_(accepted), retry_(retry), n_(y0.size()) {
    checkTimeSpan(tspan, "Ode45");
    t0_ = tspan.front(), tf_ = tspan.back();
    tdir_ = tf_ > t0_ ? 1.0 : -1.0;
    if (opt.absTol.size() != 0 && opt.absTol.size() != 1 && opt.absTol.size() != n_)
      throw std::invalid_argument("Ode45: absTol must have size 0, 1 or y0.size()");
    if (!y0.allFinite()) throw std::invalid_argument("Ode45: y0 is not finite");
    // Options (docs/theory/ode45.md "Options and defaults").
    rtol_ = std::max(opt.relTol, 100.0 * std::numeric_limits<double>::epsilon());
    threshold_.resize(n_);
    if (opt.absTol.size() == 0)
      threshold_.setConstant(1e-6 / rtol_);
    else if (opt.absTol.size() == 1)
      threshold_.setConstant(opt.absTol[0] / rtol_);
    else
      threshold_ = opt.absTol / rtol_;
    const double span = std::fabs(tf_ - t0_);
    hmax_ = opt.maxStep > 0.0 ? std::min(span, opt.maxStep) : 0.1 * span;
    refineOutput_ = tspan.size() == 2;
    for (auto& v : k_) v.resize(n_);
    y_ = y0;
    ynew_.resize(n_), ytmp_.resize(n_), yout_.resize(n_);
    res_.tLast = t0_;
  }

  OdeResult run() {
    t_ = t0_;
    // Step 1: f1 = f(t0, y0).
    if (!eval(t_, y_, k_[0])) return fail(OdeStatus::RhsFailed, failure_);
    if (!hook(accepted_, t_, y_)) return fail(OdeStatus::RhsFailed, failure_);
    if (!observer_(t_, y_)) return stopped(t_);
    absh_ = initialStep();
    bool done = false;
    while (true) {
      // Step 3: clip the step, the 1.1 rule.
      const double hmin = 16.0 * spacingOfDoublesAt(t_);
      absh_ = std::min(hmax_, std::max(hmin, absh_));
      h_ = tdir_ * absh_;
      if (1.1 * absh_ >= std::fabs(tf_ - t_)) {
        h_ = tf_ - t_;
        absh_ = std::fabs(h_);
        done = true;
      }
      nofailed_ = true;
      // Steps 4-6: attempts until one is accepted (or the run fails).
      while (true) {
        const bool rhsFailed = !attempt(done);
        if (aborted_) return fail(OdeStatus::RhsFailed, failure_);
        if (!rhsFailed && err_ <= rtol_) break;
        if (auto stop = reject(rhsFailed, hmin)) return *stop;
        done = false;
      }
      // Step 7: accepted; emit output.
      if (auto stop = accept()) return *stop;
      if (done) break;
      // Growth only after a step without failure (MATLAB: absh / (1.25*(err/rtol)^(1/5)), factor <= 5).
      if (nofailed_) {
        const double temp = 1.25 * std::pow(err_ / rtol_, kPow);
        absh_ = temp > 0.2 ? absh_ / temp : 5.0 * absh_;
      }
      t_ = tnew_;
      y_.swap(ynew_);
      k_[0].swap(k_[6]);  // FSAL
    }
    return res_;
  }

 private:
  // One rhs evaluation; false (with `failure_` set) on RhsError or a non-finite input or value.
  bool eval(double tt, const VectorXd& yy, VectorXd& dy) {
    if (!yy.allFinite()) {
      failure_ = "right-hand side failed at t = " + text::shortest(tt) + ": non-finite state y";
      return false;
    }
    ++res_.stats.nfevals;
    try {
      f_(tt, yy, dy);
    } catch (const RhsAbort& e) {
      failure_ = "right-hand side failed at t = " + text::shortest(tt) + ": " + e.what();
      aborted_ = true;
      return false;
    } catch (const RhsError& e) {
      failure_ = "right-hand side failed at t = " + text::shortest(tt) + ": " + e.what();
      return false;
    }
    if (dy.size() != n_ || !dy.allFinite()) {
      failure_ = "right-hand side failed at t = " + text::shortest(tt) + ": " +
                 (dy.size() != n_ ? "wrong size of dydt" : "non-finite value in dydt");
      return false;
    }
    return true;
  }

  OdeResult fail(OdeStatus s, std::string msg) {
    res_.status = s;
    res_.message = std::move(msg);
    return res_;
  }
  OdeResult stopped(double tt) {
    return fail(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(tt));
  }

  // A right-hand side that fails at every trial state down to the minimum step: the solution itself
  // runs into the failure (MATLAB's ode45 has no such outcome: its right-hand sides do not fail).
  static std::string atMinimumStep(double tt, double hh) {
    return " (trial steps from the accepted state at t = " + text::shortest(tt) + " failed down to the minimum step " +
           text::shortest(hh) +
           "; results up to there are kept. The model itself fails there, e.g. a singular "
           "configuration or a load it cannot carry)";
  }

  // The hooks may throw RhsError: the run stops with its message.
  bool hook(const OdeStepHook& h, double tt, const VectorXd& yy) {
    if (!h) return true;
    try {
      h(tt, yy);
    } catch (const RhsError& e) {
      failure_ = e.what();
      return false;
    }
    return true;
  }

  // Step 2: the initial step.
  double initialStep() const {
    const double hmin = 16.0 * spacingOfDoublesAt(t_);
    if (opt_.initialStep > 0.0) return std::min(hmax_, std::max(hmin, opt_.initialStep));
    double absh = std::min(hmax_, std::fabs(tspan_[1] - tspan_[0]));
    double rh = 0.0;
    for (Eigen::Index i = 0; i < n_; ++i)
      rh = std::max(rh, std::fabs(k_[0][i]) / std::max(std::fabs(y_[i]), threshold_[i]));
    rh /= 0.8 * std::pow(rtol_, kPow);
    if (absh * rh > 1.0) absh = 1.0 / rh;
    return std::max(absh, hmin);
  }

  // out = sum_{i<m} A[row][i] k_i (zero coefficients skipped).
  void combine(int row, int m, VectorXd& out) const {
    out = A[row][0] * k_[0];
    for (int i = 1; i < m; ++i)
      if (A[row][i] != 0.0) out += A[row][i] * k_[i];
  }

  // Step 4: stages k2..k6 (y + h*(sum_i a_ji k_i), the order of MATLAB's ode45), then tnew, the
  // purified h = tnew - t, ynew from b and the FSAL stage k7; step 5: the error estimate
  // err = absh * max_i |sum_j E_j k_j,i| / max(|y_i|, |ynew_i|, threshold_i). False when a stage's
  // right-hand side failed.
  bool attempt(bool done) {
    for (int j = 1; j <= 5; ++j) {
      combine(j - 1, j, ytmp_);
      ytmp_ = y_ + h_ * ytmp_;
      if (!eval(t_ + C[j] * h_, ytmp_, k_[j])) return false;
    }
    tnew_ = done ? tf_ : t_ + h_;
    h_ = tnew_ - t_;
    combine(5, 6, ynew_);
    ynew_ = y_ + h_ * ynew_;
    if (!eval(tnew_, ynew_, k_[6])) return false;
    double m = 0.0;
    for (Eigen::Index i = 0; i < n_; ++i) {
      double e = 0.0;
      for (int j = 0; j < 7; ++j) e += E[j] * k_[j][i];
      const double sc = std::max({std::fabs(y_[i]), std::fabs(ynew_[i]), threshold_[i]});
      m = std::max(m, std::fabs(e) / sc);
    }
    err_ = absh_ * m;
    return true;
  }

  // Step 6: rejected. A failed right-hand side counts as an infinite error: a trial state far off
  // the solution (stages of a step much too large for the stiffest mode) may have no configuration
  // at all, where the solution has one. The run's end when the step cannot shrink further.
  std::optional<OdeResult> reject(bool rhsFailed, double hmin) {
    ++res_.stats.nfailed;
    if (rhsFailed) ++res_.stats.nrhsfailed, streakFailure_ = failure_;
    if (absh_ <= hmin) {
      if (rhsFailed) return fail(OdeStatus::RhsFailed, failure_ + atMinimumStep(t_, absh_));
      return fail(OdeStatus::StepSizeUnderflow,
                  "step size underflow at t = " + text::shortest(t_) + ": tolerance cannot be met (h = " +
                      text::shortest(absh_) + " <= hmin = " + text::shortest(hmin) + ")" +
                      (streakFailure_.empty()
                           ? ""
                           : "; since the step was last unconstrained, larger trial steps failed: " + streakFailure_));
    }
    if (nofailed_) {
      nofailed_ = false;
      const double shrink = rhsFailed ? 0.1 : std::max(0.1, 0.8 * std::pow(rtol_ / err_, kPow));
      absh_ = std::max(hmin, absh_ * shrink);
    } else {
      absh_ = std::max(hmin, 0.5 * absh_);
    }
    h_ = tdir_ * absh_;
    // An attempt far off the solution (a failed right-hand side, or an error estimate of more than
    // 100% relative) may have left the caller's state (a warm start) anywhere: the caller resets it.
    if ((rhsFailed || err_ > 1.0) && !hook(retry_, t_, y_)) return fail(OdeStatus::RhsFailed, failure_);
    return std::nullopt;
  }

  // Interpolated output at tq inside the step [t, t+h] (k[6] is the FSAL stage of the step).
  void interp(double tq) {
    const double s = (tq - t_) / h_, s2 = s * s, s3 = s2 * s, s4 = s3 * s;
    yout_ = y_;
    for (int j = 0; j < 7; ++j) {
      const double w = h_ * (BI[j][0] * s + BI[j][1] * s2 + BI[j][2] * s3 + BI[j][3] * s4);
      if (w != 0.0) yout_ += w * k_[j];
    }
  }

  // Step 7: the accepted step's statistics, hook and output (Refine points or the requested times),
  // then the step monitor.
  std::optional<OdeResult> accept() {
    if (auto stop = acceptAndOutput()) return stop;
    if (opt_.stepMonitor && !opt_.stepMonitor(tnew_, ynew_, std::fabs(h_), stiffnessEstimate()))
      return fail(OdeStatus::Stopped, "stopped by the step monitor at t = " + text::shortest(tnew_));
    return std::nullopt;
  }

  // h |lambda| of Hairer's stiffness test: stages 6 (at y6, in ytmp_) and 7 (at ynew) share t + h.
  double stiffnessEstimate() const {
    const double num = (k_[6] - k_[5]).squaredNorm(), den = (ynew_ - ytmp_).squaredNorm();
    return den > 0.0 ? std::fabs(h_) * std::sqrt(num / den) : 0.0;
  }

  std::optional<OdeResult> acceptAndOutput() {
    ++res_.stats.nsteps;
    if (nofailed_) streakFailure_.clear();
    res_.tLast = tnew_;
    if (!hook(accepted_, tnew_, ynew_)) return fail(OdeStatus::RhsFailed, failure_);
    if (refineOutput_) {
      for (int j = 1; j < opt_.refine; ++j) {  // interior points at s = j/refine
        const double tq = t_ + h_ * (static_cast<double>(j) / opt_.refine);
        interp(tq);
        if (!yout_.allFinite())
          return fail(OdeStatus::RhsFailed, "non-finite interpolated value at t = " + text::shortest(tq));
        if (!observer_(tq, yout_)) return stopped(tnew_);
      }
      if (!observer_(tnew_, ynew_)) return stopped(tnew_);
      return std::nullopt;
    }
    while (next_ < tspan_.size() && tdir_ * (tnew_ - tspan_[next_]) >= 0.0) {
      const double tq = tspan_[next_++];
      const VectorXd* out = &ynew_;
      if (tq != tnew_) {
        interp(tq);
        if (!yout_.allFinite())
          return fail(OdeStatus::RhsFailed, "non-finite interpolated value at t = " + text::shortest(tq));
        out = &yout_;
      }
      if (!observer_(tq, *out)) return stopped(tnew_);
    }
    return std::nullopt;
  }

  const Ode45Options& opt_;
  const OdeRhs& f_;
  const std::vector<double>& tspan_;
  const OdeObserver& observer_;
  const OdeStepHook &accepted_, &retry_;
  const Eigen::Index n_;
  double t0_ = 0.0, tf_ = 0.0, tdir_ = 1.0, rtol_ = 0.0, hmax_ = 0.0;
  bool refineOutput_ = false;
  VectorXd threshold_;
  std::array<VectorXd, 7> k_;  // stages; k_[6] the FSAL stage of the last attempt
  VectorXd y_, ynew_, ytmp_, yout_;
  double t_ = 0.0, tnew_ = 0.0, h_ = 0.0, absh_ = 0.0, err_ = 0.0;
  bool nofailed_ = true;  // the current step has had no rejected attempt
  std::size_t next_ = 1;  // next requested output time (tspan longer than 2)
  OdeResult res_;
  std::string failure_;   // reason of a failed rhs evaluation
  bool aborted_ = false;  // the failure was an RhsAbort: stop at once
  // The last right-hand-side failure since a step was last accepted at its first attempt: the reason
  // a step-size underflow at the end of such a streak names (the solution running into a fold).
  std::string streakFailure_;
};

}  // namespace

OdeResult Ode45::integrate(const OdeRhs& f, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                           const OdeObserver& observer, const OdeStepHook& accepted, const OdeStepHook& retry) const {
  return Ode45Run(opt_, f, tspan, y0, observer, accepted, retry).run();
}

}  // namespace flexmb::solvers
