#include "solvers/GeneralizedAlpha.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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
  if (!(opt_.maxStep >= 0.0) || !(opt_.initialStep >= 0.0))
    throw std::invalid_argument("generalized-alpha: step sizes must be >= 0");
  if (opt_.fixedStep && !(opt_.maxStep > 0.0))
    throw std::invalid_argument("generalized-alpha: fixed steps need a step size (maxStep)");
  if (opt_.maxNewtonIterations < 1) throw std::invalid_argument("generalized-alpha: maxNewtonIterations must be >= 1");
}

namespace {

// Weighted RMS of v against atol + rtol |ref|.
double weightedRms(const Eigen::VectorXd& v, const Eigen::VectorXd& ref, double rtol, double atol) {
  if (v.size() == 0) return 0.0;
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const double w = atol + rtol * std::fabs(ref[i]);
    s += (v[i] / w) * (v[i] / w);
  }
  return std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace

OdeResult GeneralizedAlpha::integrate(SecondOrderSystem& sys, const std::vector<double>& tspan,
                                      const Eigen::VectorXd& y0, const OdeObserver& observer) const {
  checkTimeSpan(tspan, "generalized-alpha");
  const int m = sys.size();
  if (m <= 0 || y0.size() != 2 * m)
    throw std::invalid_argument("generalized-alpha: y0 must hold [q; qd] of the system");
  if (!y0.allFinite()) throw std::invalid_argument("generalized-alpha: y0 is not finite");
  const double t0 = tspan.front(), tf = tspan.back(), span = std::fabs(tf - t0);
  const double tdir = tf > t0 ? 1.0 : -1.0;
  const double hmax = opt_.maxStep > 0.0 ? std::min(span, opt_.maxStep) : 0.1 * span;
  if (span / hmax > 1e9)
    throw std::invalid_argument("generalized-alpha: the step size limit " + text::shortest(hmax) + " needs more than " +
                                "1e9 steps over " + text::shortest(span) + " s");
  const double hmin = 16.0 * spacingOfDoublesAt(std::max(std::fabs(t0), std::fabs(tf)));
  const GeneralizedAlphaParameters p(opt_.rhoInf);
  const double errC = std::fabs(p.errorCoefficient());
  const double mix = (1.0 - p.alphaF) / (1.0 - p.alphaM);  // d a_{n+1} / d qdd_{n+1}

  OdeResult res;
  res.tLast = t0;
  OdeStats& st = res.stats;
  auto stop = [&](OdeStatus s, const std::string& why) {
    res.status = s;
    res.message = why;
    return res;
  };

  Eigen::VectorXd q = y0.head(m), v = y0.tail(m), acc(m), a(m);
  try {
    sys.acceleration(t0, q, v, acc);
    ++st.nfevals;
    sys.accept(t0, q, v);
  } catch (const RhsError& e) {
    return stop(OdeStatus::RhsFailed,
                "generalized-alpha could not start at t = " + text::shortest(t0) + ": " + e.what());
  }
  a = acc;
  if (!observer(t0, y0)) return stop(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(t0));

  // Every vector a step needs, allocated once (the step loop allocates nothing).
  Eigen::VectorXd accN(m), aN(m), vN(m), qN(m), f(m), r(m), dqv(2 * m), ref(2 * m), yOut(2 * m), aUse(m), err(m);
  Eigen::VectorXd qPrev(m), vPrev(m), accPrev(m);
  double t = t0;
  double h = opt_.fixedStep ? hmax : std::min(hmax, opt_.initialStep > 0.0 ? opt_.initialStep : 1e-3 * span);
  double hAccepted = h;         // the step a_n belongs to
  double factorizedFor = -1.0;  // the step size of the current factorisation (-1: none)
  bool haveJacobian = false, jacobianFresh = false, refresh = false, lastRejected = false;
  std::size_t next = 1;
  const bool everyStep = tspan.size() == 2;
  std::string lastFailure;

  auto newJacobian = [&]() {
    sys.jacobian(t, q, v, acc);
    ++st.njacevals;
    haveJacobian = jacobianFresh = true;
    factorizedFor = -1.0;
  };

  while (tdir * (tf - t) > 0.0) {
    if (!opt_.fixedStep && h < hmin)
      return stop(OdeStatus::StepSizeUnderflow,
                  "generalized-alpha stopped at t = " + text::shortest(t) + ": the step fell below the minimum " +
                      text::shortest(hmin) + (lastFailure.empty() ? "" : " (last failure: " + lastFailure + ")") +
                      "; results up to there are kept");
    if (1.1 * h >= std::fabs(tf - t)) h = std::fabs(tf - t);  // land on tf
    const double tN = t + tdir * h, hs = tdir * h;
    // a_n belongs to the step it was made with; rescaled to this one (its shift is alpha_m - alpha_f steps).
    aUse = acc + (h / hAccepted) * (a - acc);
    const double betaP = hs * hs * p.beta * mix, gammaP = hs * p.gamma * mix;
    auto update = [&]() {
      aN = ((1.0 - p.alphaF) * accN + p.alphaF * acc - p.alphaM * aUse) / (1.0 - p.alphaM);
      vN = v + hs * ((1.0 - p.gamma) * aUse + p.gamma * aN);
      qN = q + hs * v + hs * hs * ((0.5 - p.beta) * aUse + p.beta * aN);
    };

    // Modified Newton on qdd_{n+1}, from qdd_n.
    bool converged = false;
    std::string failure;
    try {
      if (!haveJacobian || refresh) {
        newJacobian();
        refresh = false;
      }
      if (factorizedFor != h) {
        ++st.nlinsetups;
        if (!sys.factorize(betaP, gammaP)) throw RhsError("singular iteration matrix");
        factorizedFor = h;
      }
      accN = acc;
      double previous = 0.0;
      for (int k = 0; k < opt_.maxNewtonIterations; ++k) {
        update();
        sys.acceleration(tN, qN, vN, f);
        ++st.nfevals;
        r = accN - f;
        sys.solve(r);
        accN -= r;
        dqv << betaP * r, gammaP * r;
        ref << qN, vN;
        const double norm = weightedRms(dqv, ref, opt_.relTol, opt_.absTol);
        if (!std::isfinite(norm)) throw RhsError("the Newton iteration diverged");
        // Converged when the correction (in q and qd, against the tolerance) is small, or, once
        // the contraction rate is known, the remaining error it predicts (CVODE's test).
        const double rate = k == 0 ? 0.0 : norm / previous;
        if (k == 0 ? norm <= 0.1 : (norm <= 1e-3 || (rate < 0.9 && norm * rate / (1.0 - rate) <= 0.1))) {
          converged = true;
          if (k >= 3) refresh = true;  // slow: a new iteration matrix for the next step
          break;
        }
        if (rate >= 0.9) throw RhsError("the Newton iteration does not converge");
        previous = norm;
      }
      if (!converged) failure = "no Newton convergence in " + std::to_string(opt_.maxNewtonIterations) + " iterations";
    } catch (const RhsAbort& e) {
      res.tLast = t;
      return stop(OdeStatus::RhsFailed, std::string(e.what()) + " (at t = " + text::shortest(tN) + ")");
    } catch (const RhsError& e) {
      failure = e.what();
    }
    if (!converged) {
      ++st.nfailed;
      lastFailure = failure + " at t = " + text::shortest(tN);
      lastRejected = true;
      if (!jacobianFresh) {  // an old iteration matrix: a new one at the same step first
        refresh = true;
        continue;
      }
      if (opt_.fixedStep)
        return stop(OdeStatus::ConvergenceFailure, "generalized-alpha stopped at t = " + text::shortest(t) + ": " +
                                                       lastFailure + " with the fixed step " + text::shortest(h) +
                                                       "; results up to there are kept");
      h *= 0.25;
      continue;
    }
    update();  // q, qd at the converged accelerations

    double ratio = 2.0;
    if (!opt_.fixedStep) {
      err = (errC * hs * hs) * (aN - aUse);
      ref.head(m) = q.cwiseAbs().cwiseMax(qN.cwiseAbs());
      const double e = weightedRms(err, ref.head(m), opt_.relTol, opt_.absTol);
      ratio = e > 0.0 ? 0.9 * std::pow(e, -1.0 / 3.0) : 5.0;
      if (e > 1.0) {
        ++st.nfailed;
        lastRejected = true;
        lastFailure = "error test failed at t = " + text::shortest(tN);
        h *= std::max(0.2, ratio);
        continue;
      }
    }
    // Accepted.
    ++st.nsteps;
    const double tPrev = t;
    qPrev = q, vPrev = v, accPrev = acc;
    t = tN;
    q = qN;
    v = vN;
    acc = accN;
    a = aN;
    hAccepted = h;
    jacobianFresh = false;
    res.tLast = t;
    try {
      sys.accept(t, q, v);
    } catch (const RhsAbort& e) {
      return stop(OdeStatus::RhsFailed,
                  std::string(e.what()) + " (at the accepted state t = " + text::shortest(t) + ")");
    } catch (const RhsError& e) {
      return stop(OdeStatus::RhsFailed, "generalized-alpha stopped at the accepted state t = " + text::shortest(t) +
                                            ": " + e.what() + "; results up to there are kept");
    }
    const bool done = !(tdir * (tf - t) > 0.0);
    if (everyStep) {
      yOut << q, v;
      if (!observer(done ? tf : t, yOut))
        return stop(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(t));
    } else {
      while (next < tspan.size() && (tdir * (t - tspan[next]) >= 0.0 || (done && next + 1 == tspan.size()))) {
        const double tq = tspan[next++];
        if (tq == t || (done && next == tspan.size())) {
          yOut << q, v;
        } else {  // cubic Hermite on the step
          const double s = (tq - tPrev) / (t - tPrev), s2 = s * s, s3 = s2 * s;
          const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
          yOut.head(m) = h00 * qPrev + (h10 * hs) * vPrev + h01 * q + (h11 * hs) * v;
          yOut.tail(m) = h00 * vPrev + (h10 * hs) * accPrev + h01 * v + (h11 * hs) * acc;
        }
        if (!observer(tq, yOut))
          return stop(OdeStatus::Stopped, "stopped by the observer at t = " + text::shortest(tq));
      }
    }
    if (opt_.fixedStep) continue;
    // The next step: grown at most twofold (never right after a rejection); kept when the change
    // would be small, so the factorisation serves it too.
    if (lastRejected) ratio = std::min(ratio, 1.0);
    lastRejected = false;
    ratio = std::clamp(ratio, 0.2, 1.5);
    if (ratio < 1.0 || ratio > 1.25) h = std::min(hmax, h * ratio);
  }
  res.tLast = tf;
  return res;
}

}  // namespace flexmb::solvers
