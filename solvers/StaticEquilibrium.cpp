#include "solvers/StaticEquilibrium.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flexmb::solvers {

namespace {
bool positiveDefinite(const Eigen::LDLT<Eigen::MatrixXd>& ldlt) {
  return ldlt.info() == Eigen::Success && ldlt.isPositive() &&
         ldlt.vectorD().minCoeff() > 1e-14 * ldlt.vectorD().cwiseAbs().maxCoeff();
}
}  // namespace

bool isSymmetric(const Eigen::MatrixXd& T) {
  const double scale = T.cwiseAbs().maxCoeff();
  return (T - T.transpose()).cwiseAbs().maxCoeff() <= 1e-14 * scale;
}

bool isPositiveDefinite(const Eigen::MatrixXd& T) {
  if (isSymmetric(T)) return positiveDefinite(Eigen::LDLT<Eigen::MatrixXd>(T));
  return positiveDefinite(Eigen::LDLT<Eigen::MatrixXd>(0.5 * (T + T.transpose())));
}

TangentKind DenseStaticProblem::linearize(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) {
  f_(eta, Q, &T_);
  if (!T_.allFinite()) throw std::runtime_error("non-finite tangent");
  const bool symmetric = isSymmetric(T_);
  // A symmetric positive definite tangent (the usual case) by Cholesky, with the pivots' test of
  // positiveDefinite (D = diag(L)^2); anything else by LDLT.
  byCholesky_ = false;
  if (symmetric) {
    llt_.compute(T_);
    if (llt_.info() == Eigen::Success) {
      const Eigen::VectorXd d = llt_.matrixLLT().diagonal().array().square();
      if (d.size() == 0 || d.minCoeff() > 1e-14 * d.maxCoeff()) {
        spd_ = byCholesky_ = true;
        return TangentKind::PositiveDefinite;
      }
    }
  }
  // A non-symmetric tangent (moments on Euler parameters) is classified by its symmetric part and
  // solved by LU.
  if (symmetric)
    ldlt_.compute(T_);
  else
    ldlt_.compute(0.5 * (T_ + T_.transpose()));
  const bool definite = positiveDefinite(ldlt_);
  spd_ = definite && symmetric;
  if (spd_) return TangentKind::PositiveDefinite;
  lu_.compute(T_);
  if (!lu_.isInvertible()) return TangentKind::Singular;
  return definite ? TangentKind::PositiveDefinite : TangentKind::Indefinite;
}

void DenseStaticProblem::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (byCholesky_)
    x = llt_.solve(b);
  else if (spd_)
    x = ldlt_.solve(b);
  else
    x = lu_.solve(b);
}

namespace {
enum class Evaluation { Residual, Tangent };

// Evaluates; false (with the reason) when the problem throws or returns non-finite values.
bool evaluate(StaticProblem& p, Evaluation what, const Eigen::VectorXd& eta, Eigen::VectorXd& Q, TangentKind& kind,
              std::string& error) {
  try {
    if (what == Evaluation::Tangent)
      kind = p.linearize(eta, Q);
    else
      p.residual(eta, Q);
    if (!Q.allFinite()) {
      error = "non-finite residual";
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
}
}  // namespace

StaticResult solveEquilibrium(StaticProblem& problem, Eigen::VectorXd& eta, double forceScale, const NewtonOptions& o) {
  StaticResult r;
  const int n = static_cast<int>(eta.size());
  Eigen::VectorXd Q(n), Qtrial(n), step(n), trial(n), next(n);
  std::string error;
  TangentKind kind = TangentKind::Unknown;
  if (!evaluate(problem, Evaluation::Tangent, eta, Q, kind, error)) {
    r.status = StaticStatus::Failed;
    r.message = "cannot evaluate the starting configuration: " + error;
    return r;
  }
  const double scale = std::max(forceScale, 1e-300);
  for (r.iterations = 0; r.iterations <= o.maxIterations; ++r.iterations) {
    r.residual = Q.lpNorm<Eigen::Infinity>();
    if (kind == TangentKind::Singular) {
      r.status = StaticStatus::SingularTangent;
      std::ostringstream s;
      s << "singular tangent stiffness after " << r.iterations << " iterations (residual " << r.residual
        << "): a limit point or a mechanism; reduce the load step or check the supports";
      r.message = s.str();
      return r;
    }
    problem.solve(Q, step);
    if (kind != TangentKind::Unknown) r.stable = kind == TangentKind::PositiveDefinite;
    if (r.residual <= o.relativeTolerance * scale ||
        step.lpNorm<Eigen::Infinity>() <= o.stepTolerance * std::max(1.0, eta.lpNorm<Eigen::Infinity>())) {
      r.status = StaticStatus::Converged;
      return r;
    }
    if (r.iterations == o.maxIterations) break;
    // Step cutting: accept the first fraction that passes the residual test or, when asked, the
    // correction test (NewtonOptions); the latter linearises at the trial, which is then kept.
    const Evaluation atTrial = o.correctionMonotonicity ? Evaluation::Tangent : Evaluation::Residual;
    const double stepNorm = step.norm();
    double alpha = 1.0;
    bool accepted = false;
    TangentKind trialKind = TangentKind::Unknown;
    for (int cut = 0; cut <= o.maxCuts; ++cut, alpha *= 0.5) {
      trial = eta + alpha * step;
      if (!evaluate(problem, atTrial, trial, Qtrial, trialKind, error)) continue;
      accepted = Qtrial.lpNorm<Eigen::Infinity>() < r.residual;
      if (!accepted && o.correctionMonotonicity && trialKind != TangentKind::Singular) {
        problem.solve(Qtrial, next);
        accepted = next.allFinite() && next.norm() <= (1.0 - 0.25 * alpha) * stepNorm;
      }
      if (accepted) break;
    }
    if (!accepted) {
      r.status = StaticStatus::NotConverged;
      std::ostringstream s;
      s << "Newton stalled after " << r.iterations << " iterations (residual " << r.residual
        << "): no step length reduces the residual" << (error.empty() ? "" : " (" + error + ")")
        << "; a limit point is near: use smaller load steps";
      r.message = s.str();
      return r;
    }
    eta = trial;
    if (atTrial == Evaluation::Tangent) {
      Q = Qtrial;
      kind = trialKind;
    } else if (!evaluate(problem, Evaluation::Tangent, eta, Q, kind, error)) {
      r.status = StaticStatus::Failed;
      r.message = error;
      return r;
    }
  }
  r.status = StaticStatus::NotConverged;
  std::ostringstream s;
  s << "Newton did not converge in " << o.maxIterations << " iterations (residual " << r.residual << ")";
  r.message = s.str();
  return r;
}

StaticResult solveEquilibrium(const DenseStaticProblem::Function& problem, Eigen::VectorXd& eta, double forceScale,
                              const NewtonOptions& options) {
  DenseStaticProblem p(problem);
  return solveEquilibrium(p, eta, forceScale, options);
}

}  // namespace flexmb::solvers
