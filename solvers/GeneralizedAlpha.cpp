#include "solvers/GeneralizedAlpha.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "text/NumberText.hpp"

namespace flexmb::solvers {

GeneralizedAlphaParameters::GeneralizedAlphaParameters(double rho)
    : alphaM((2.0 * rho - 1.0) / (rho + 1.0)),
      alphaF(rho / (rho + 1.0)),
      gamma(0.5 + alphaF - alphaM),
      beta(0.25 * (gamma + 0.5) * (gamma + 0.5)) {}

double GeneralizedAlphaParameters::errorCoefficient() const {
  // q_{n+1} = q_n + h qd_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}) with a_n ~ qdd(t_n + (alpha_m -
  // alpha_f) h): the h^3 qddd term is (beta + (alpha_m - alpha_f)/2) where the exact one is 1/6.
  return beta + 0.5 * (alphaM - alphaF) - 1.0 / 6.0;
}

FirstOrderAsSecondOrder::FirstOrderAsSecondOrder(OdeRhs f, OdeJacobian jacobian, int m, OdeStepHook accepted)
    : f_(std::move(f)), jac_(std::move(jacobian)), accepted_(std::move(accepted)), m_(m) {
  y_.resize(2 * m);
  dy_.resize(2 * m);
  J_.resize(2 * m, 2 * m);
  S_.resize(m, m);
  x_.resize(m);
}

void FirstOrderAsSecondOrder::acceleration(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                           Eigen::VectorXd& qdd) {
  y_ << q, qd;
  f_(t, y_, dy_);
  if (!dy_.allFinite()) throw RhsError("non-finite accelerations at t = " + text::shortest(t));
  qdd = dy_.tail(m_);
}

void FirstOrderAsSecondOrder::jacobian(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                       const Eigen::VectorXd& qdd) {
  y_ << q, qd;
  dy_ << qd, qdd;
  jac_(t, y_, dy_, J_);
  if (!J_.allFinite()) throw RhsError("non-finite Jacobian at t = " + text::shortest(t));
}

bool FirstOrderAsSecondOrder::factorize(double betaP, double gammaP) {
  S_.setIdentity();
  S_ -= betaP * J_.bottomLeftCorner(m_, m_);
  S_ -= gammaP * J_.bottomRightCorner(m_, m_);
  lu_.compute(S_);
  return std::isfinite(lu_.rcond()) && lu_.rcond() > 1e3 * std::numeric_limits<double>::epsilon();
}

void FirstOrderAsSecondOrder::solve(Eigen::VectorXd& r) {
  x_.noalias() = lu_.solve(r);
  r = x_;
}

void FirstOrderAsSecondOrder::accept(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  if (!accepted_) return;
  y_ << q, qd;
  accepted_(t, y_);
}

GeneralizedAlpha::GeneralizedAlpha(GeneralizedAlphaOptions options) : opt_(std::move(options)) {
  if (!(opt_.rhoInf >= 0.0 && opt_.rhoInf <= 1.0))
    throw std::invalid_argument("generalized-alpha: rho_inf must lie in [0, 1] (got " + text::shortest(opt_.rhoInf) +
                                ")");
  if (!(opt_.relTol > 0.0) || !std::isfinite(opt_.relTol))
    throw std::invalid_argument("generalized-alpha: relTol must be positive");
  if (!(opt_.absTol > 0.0) || !std::isfinite(opt_.absTol))
    throw std::invalid_argument("generalized-alpha: absTol must be positive");
  if (opt_.absTols.size() && !((opt_.absTols.array() > 0.0).all() && opt_.absTols.allFinite()))
    throw std::invalid_argument("generalized-alpha: absTols must be positive");
  if (!(opt_.maxStep >= 0.0) || !(opt_.initialStep >= 0.0))
    throw std::invalid_argument("generalized-alpha: step sizes must be >= 0");
  if (opt_.fixedStep && !(opt_.maxStep > 0.0))
    throw std::invalid_argument("generalized-alpha: fixed steps need a step size (maxStep)");
  if (opt_.maxNewtonIterations < 1) throw std::invalid_argument("generalized-alpha: maxNewtonIterations must be >= 1");
}

namespace {

// Weighted RMS of v against atol_i + rtol |ref_i| (atol: at least v's size).
double weightedRms(const Eigen::VectorXd& v, const Eigen::VectorXd& ref, double rtol, const Eigen::VectorXd& atol) {
  if (v.size() == 0) return 0.0;
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const double w = atol[i] + rtol * std::fabs(ref[i]);
    s += (v[i] / w) * (v[i] / w);
  }
  return std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace

namespace {

// One integration: the state of the run and its steps as methods (as Ode45Run), so the main loop
// reads as the algorithm. Every vector a step needs is allocated once, in the constructor (the step
// loop allocates nothing).
class GeneralizedAlphaRun {
 public:
  using VectorXd = Eigen::VectorXd;

  GeneralizedAlphaRun(const GeneralizedAlphaOptions& opt, SecondOrderSystem& sys, const std::vector<double>& tspan,
                      const VectorXd& y0, const OdeObserver& observer)
      : opt_(opt), sys_(sys), tspan_(tspan), y0_(y0), observer_(observer), p_(opt.rhoInf), m_(sys.size()) {
    checkTimeSpan(tspan, "generalized-alpha");
    if (m_ <= 0 || y0.size() != 2 * m_)
      throw std::invalid_argument("generalized-alpha: y0 must hold [q; qd] of the system");
    if (!y0.allFinite()) throw std::invalid_argument("generalized-alpha: y0 is not finite");
    if (opt.absTols.size() && opt.absTols.size() != m_)
      throw std::invalid_argument("generalized-alpha: absTols must hold one value per component of q");
    atol_.resize(2 * m_);  // q's, and the same for qd (the Newton test)
    atol_.head(m_) = opt.absTols.size() ? opt.absTols : Eigen::VectorXd::Constant(m_, opt.absTol);
    atol_.tail(m_) = atol_.head(m_);
    t0_ = tspan.front(), tf_ = tspan.back(), span_ = std::fabs(tf_ - t0_);
    tdir_ = tf_ > t0_ ? 1.0 : -1.0;
    hmax_ = opt.maxStep > 0.0 ? std::min(span_, opt.maxStep) : 0.1 * span_;
    if (span_ / hmax_ > 1e9)
      throw std::invalid_argument("generalized-alpha: the step size limit " + text::shortest(hmax_) +
                                  " needs more than " + "1e9 steps over " + text::shortest(span_) + " s");
    hmin_ = 16.0 * spacingOfDoublesAt(std::max(std::fabs(t0_), std::fabs(tf_)));
    errC_ = std::fabs(p_.errorCoefficient());
    mix_ = (1.0 - p_.alphaF) / (1.0 - p_.alphaM);
    everyStep_ = tspan.size() == 2;
    res_.tLast = t0_;
    q_ = y0.head(m_), v_ = y0.tail(m_), acc_.resize(m_), a_.resize(m_);
    for (VectorXd* w : {&accN_, &aN_, &vN_, &qN_, &f_, &r_, &aUse_, &err_, &qPrev_, &vPrev_, &accPrev_}) w->resize(m_);
    for (VectorXd* w : {&dqv_, &ref_, &yOut_}) w->resize(2 * m_);
  }

  OdeResult run() {
    if (auto stopped = start()) return *stopped;
    t_ = t0_;
    h_ = opt_.fixedStep ? hmax_ : std::min(hmax_, opt_.initialStep > 0.0 ? opt_.initialStep : 1e-3 * span_);
    hAccepted_ = h_;
    while (tdir_ * (tf_ - t_) > 0.0) {
      if (!opt_.fixedStep && h_ < hmin_)
        return stop(OdeStatus::StepSizeUnderflow,
                    "generalized-alpha stopped at t = " + text::shortest(t_) + ": the step fell below the minimum " +
                        text::shortest(hmin_) + (lastFailure_.empty() ? "" : " (last failure: " + lastFailure_ + ")") +
                        "; results up to there are kept");
      if (1.1 * h_ >= std::fabs(tf_ - t_)) h_ = std::fabs(tf_ - t_);  // land on tf
      beginStep();
      bool converged = false;
      std::string failure;
      try {
        converged = newton(failure);
      } catch (const RhsAbort& e) {
        res_.tLast = t_;
        return stop(OdeStatus::RhsFailed, std::string(e.what()) + " (at t = " + text::shortest(tN_) + ")");
      } catch (const RhsError& e) {
        failure = e.what();
      }
      if (!converged) {
        if (auto stopped = rejectNewton(failure)) return *stopped;
        continue;
      }
      update();  // q, qd at the converged accelerations
      double ratio = 2.0;
      if (!opt_.fixedStep && !errorTest(ratio)) continue;
      if (auto stopped = accept()) return *stopped;
      if (opt_.fixedStep) continue;
      nextStep(ratio);
    }
    res_.tLast = tf_;
    return res_;
  }

 private:
  OdeResult stop(OdeStatus s, const std::string& why) {
    res_.status = s;
    res_.message = why;
    return res_;
  }

  // The accelerations at t0, the first accepted state and the first output.
  std::optional<OdeResult> start() {
    try {
      sys_.acceleration(t0_, q_, v_, acc_);
      ++res_.stats.nfevals;
      sys_.accept(t0_, q_, v_);
    } catch (const RhsError& e) {
      return stop(OdeStatus::RhsFailed,
                  "generalized-alpha could not start at t = " + text::shortest(t0_) + ": " + e.what());
    }
    a_ = acc_;
    if (!observer_(t0_, y0_)) return stop(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(t0_));
    return std::nullopt;
  }

  // The step's end, its a_n and the update's derivatives.
  void beginStep() {
    tN_ = t_ + tdir_ * h_, hs_ = tdir_ * h_;
    // a_n belongs to the step it was made with; rescaled to this one (its shift is alpha_m - alpha_f steps).
    aUse_ = acc_ + (h_ / hAccepted_) * (a_ - acc_);
    betaP_ = hs_ * hs_ * p_.beta * mix_, gammaP_ = hs_ * p_.gamma * mix_;
  }

  // a_{n+1}, qd_{n+1}, q_{n+1} from qdd_{n+1} (accN_).
  void update() {
    aN_ = ((1.0 - p_.alphaF) * accN_ + p_.alphaF * acc_ - p_.alphaM * aUse_) / (1.0 - p_.alphaM);
    vN_ = v_ + hs_ * ((1.0 - p_.gamma) * aUse_ + p_.gamma * aN_);
    qN_ = q_ + hs_ * v_ + hs_ * hs_ * ((0.5 - p_.beta) * aUse_ + p_.beta * aN_);
  }

  void newJacobian() {
    sys_.jacobian(t_, q_, v_, acc_);
    ++res_.stats.njacevals;
    haveJacobian_ = jacobianFresh_ = true;
    factorizedFor_ = -1.0;
  }

  // Modified Newton on qdd_{n+1}, from qdd_n: true when converged, else `failure` says why. Throws
  // RhsError (the step fails) and RhsAbort (the run stops).
  bool newton(std::string& failure) {
    if (!haveJacobian_ || refresh_) {
      newJacobian();
      refresh_ = false;
    }
    if (factorizedFor_ != h_) {
      ++res_.stats.nlinsetups;
      if (!sys_.factorize(betaP_, gammaP_)) throw RhsError("singular iteration matrix");
      factorizedFor_ = h_;
    }
    accN_ = acc_;
    double previous = 0.0;
    for (int k = 0; k < opt_.maxNewtonIterations; ++k) {
      update();
      sys_.acceleration(tN_, qN_, vN_, f_);
      ++res_.stats.nfevals;
      r_ = accN_ - f_;
      sys_.solve(r_);
      accN_ -= r_;
      dqv_ << betaP_ * r_, gammaP_ * r_;
      ref_ << qN_, vN_;
      const double norm = weightedRms(dqv_, ref_, opt_.relTol, atol_);
      if (!std::isfinite(norm)) throw RhsError("the Newton iteration diverged");
      // Converged when the correction (in q and qd, against the tolerance) is small, or, once
      // the contraction rate is known, the remaining error it predicts (CVODE's test).
      const double rate = k == 0 ? 0.0 : norm / previous;
      if (k == 0 ? norm <= 0.1 : (norm <= 1e-3 || (rate < 0.9 && norm * rate / (1.0 - rate) <= 0.1))) {
        if (k >= 3) refresh_ = true;  // slow: a new iteration matrix for the next step
        return true;
      }
      if (rate >= 0.9) throw RhsError("the Newton iteration does not converge");
      previous = norm;
    }
    failure = "no Newton convergence in " + std::to_string(opt_.maxNewtonIterations) + " iterations";
    return false;
  }

  // A failed Newton iteration: a new iteration matrix at the same step first, then a quarter of
  // the step; the run's end with fixed steps.
  std::optional<OdeResult> rejectNewton(const std::string& failure) {
    ++res_.stats.nfailed;
    lastFailure_ = failure + " at t = " + text::shortest(tN_);
    lastRejected_ = true;
    if (!jacobianFresh_) {
      refresh_ = true;
      return std::nullopt;
    }
    if (opt_.fixedStep)
      return stop(OdeStatus::ConvergenceFailure, "generalized-alpha stopped at t = " + text::shortest(t_) + ": " +
                                                     lastFailure_ + " with the fixed step " + text::shortest(h_) +
                                                     "; results up to there are kept");
    h_ *= 0.25;
    return std::nullopt;
  }

  // The local error test; false (the step shrunk) when it fails. `ratio`: the step's growth factor.
  bool errorTest(double& ratio) {
    err_ = (errC_ * hs_ * hs_) * (aN_ - aUse_);
    ref_.head(m_) = q_.cwiseAbs().cwiseMax(qN_.cwiseAbs());
    const double e = weightedRms(err_, ref_.head(m_), opt_.relTol, atol_);
    ratio = e > 0.0 ? 0.9 * std::pow(e, -1.0 / 3.0) : 5.0;
    if (e <= 1.0) return true;
    ++res_.stats.nfailed;
    lastRejected_ = true;
    lastFailure_ = "error test failed at t = " + text::shortest(tN_);
    h_ *= std::max(0.2, ratio);
    return false;
  }

  // The accepted step: the new state, the system's hook and the output.
  std::optional<OdeResult> accept() {
    ++res_.stats.nsteps;
    const double tPrev = t_;
    qPrev_ = q_, vPrev_ = v_, accPrev_ = acc_;
    t_ = tN_;
    q_ = qN_;
    v_ = vN_;
    acc_ = accN_;
    a_ = aN_;
    hAccepted_ = h_;
    jacobianFresh_ = false;
    res_.tLast = t_;
    try {
      sys_.accept(t_, q_, v_);
    } catch (const RhsAbort& e) {
      return stop(OdeStatus::RhsFailed,
                  std::string(e.what()) + " (at the accepted state t = " + text::shortest(t_) + ")");
    } catch (const RhsError& e) {
      return stop(OdeStatus::RhsFailed, "generalized-alpha stopped at the accepted state t = " + text::shortest(t_) +
                                            ": " + e.what() + "; results up to there are kept");
    }
    return output(tPrev);
  }

  // Every step's end (tspan = [t0, tf]) or the requested times inside [tPrev, t].
  std::optional<OdeResult> output(double tPrev) {
    const bool done = !(tdir_ * (tf_ - t_) > 0.0);
    if (everyStep_) {
      yOut_ << q_, v_;
      if (!observer_(done ? tf_ : t_, yOut_))
        return stop(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(t_));
      return std::nullopt;
    }
    while (next_ < tspan_.size() && (tdir_ * (t_ - tspan_[next_]) >= 0.0 || (done && next_ + 1 == tspan_.size()))) {
      const double tq = tspan_[next_++];
      if (tq == t_ || (done && next_ == tspan_.size())) {
        yOut_ << q_, v_;
      } else {  // cubic Hermite on the step
        const double s = (tq - tPrev) / (t_ - tPrev), s2 = s * s, s3 = s2 * s;
        const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
        yOut_.head(m_) = h00 * qPrev_ + (h10 * hs_) * vPrev_ + h01 * q_ + (h11 * hs_) * v_;
        yOut_.tail(m_) = h00 * vPrev_ + (h10 * hs_) * accPrev_ + h01 * v_ + (h11 * hs_) * acc_;
      }
      if (!observer_(tq, yOut_))
        return stop(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(tq));
    }
    return std::nullopt;
  }

  // The next step: grown at most twofold (never right after a rejection); kept when the change
  // would be small, so the factorisation serves it too.
  void nextStep(double ratio) {
    if (lastRejected_) ratio = std::min(ratio, 1.0);
    lastRejected_ = false;
    ratio = std::clamp(ratio, 0.2, 1.5);
    if (ratio < 1.0 || ratio > 1.25) h_ = std::min(hmax_, h_ * ratio);
  }

  const GeneralizedAlphaOptions& opt_;
  SecondOrderSystem& sys_;
  const std::vector<double>& tspan_;
  const VectorXd& y0_;
  const OdeObserver& observer_;
  const GeneralizedAlphaParameters p_;
  const int m_;
  double t0_ = 0.0, tf_ = 0.0, span_ = 0.0, tdir_ = 1.0, hmax_ = 0.0, hmin_ = 0.0;
  double errC_ = 0.0, mix_ = 0.0;  // mix_: d a_{n+1} / d qdd_{n+1}
  bool everyStep_ = false;
  OdeResult res_;
  VectorXd q_, v_, acc_, a_;  // the accepted state: q, qd, qdd and the algorithmic accelerations
  VectorXd atol_;             // absolute tolerances of q and qd
  VectorXd accN_, aN_, vN_, qN_, f_, r_, dqv_, ref_, yOut_, aUse_, err_, qPrev_, vPrev_, accPrev_;
  double t_ = 0.0, h_ = 0.0, tN_ = 0.0, hs_ = 0.0, betaP_ = 0.0, gammaP_ = 0.0;
  double hAccepted_ = 0.0;       // the step a_n belongs to
  double factorizedFor_ = -1.0;  // the step size of the current factorisation (-1: none)
  bool haveJacobian_ = false, jacobianFresh_ = false, refresh_ = false, lastRejected_ = false;
  std::size_t next_ = 1;
  std::string lastFailure_;
};

}  // namespace

OdeResult GeneralizedAlpha::integrate(SecondOrderSystem& sys, const std::vector<double>& tspan,
                                      const Eigen::VectorXd& y0, const OdeObserver& observer) const {
  return GeneralizedAlphaRun(opt_, sys, tspan, y0, observer).run();
}

double GeneralizedAlpha::localTolerance(double relTol) {
  // A second-order method under local error control makes a global error of about A tau^(2/3) (steps
  // h ~ tau^(1/3), errors adding over them); tau = 5 RelTol^(3/2) puts it at 1-4 RelTol at RelTol
  // 1e-3 ... 1e-4 on the guidance (5, 20, 40 PLBEAMs per leaf), the manipulator and the elbow, with
  // the per-coordinate absolute tolerances of analysis::simulate (tools/bench/README.md, issue 48).
  return std::max(1e-13, std::min(relTol, 5.0 * relTol * std::sqrt(relTol)));
}

}  // namespace flexmb::solvers
