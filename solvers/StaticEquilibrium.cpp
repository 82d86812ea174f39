#include "solvers/StaticEquilibrium.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <sstream>

namespace flexmb::solvers {

namespace {
bool evaluate(const StaticProblem& p, const Eigen::VectorXd& eta, Eigen::VectorXd& Q, Eigen::MatrixXd* T,
              std::string& error) {
  try {
    p(eta, Q, T);
    if (!Q.allFinite() || (T && !T->allFinite())) {
      error = "non-finite residual or tangent";
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
}
}  // namespace

StaticResult solveEquilibrium(const StaticProblem& problem, Eigen::VectorXd& eta, double forceScale,
                              const NewtonOptions& o) {
  StaticResult r;
  const int n = static_cast<int>(eta.size());
  Eigen::VectorXd Q(n), Qtrial(n), step(n), trial(n);
  Eigen::MatrixXd T(n, n);
  std::string error;
  if (!evaluate(problem, eta, Q, &T, error)) {
    r.status = StaticStatus::Failed;
    r.message = "cannot evaluate the starting configuration: " + error;
    return r;
  }
  const double scale = std::max(forceScale, 1e-300);
  for (r.iterations = 0; r.iterations <= o.maxIterations; ++r.iterations) {
    r.residual = Q.lpNorm<Eigen::Infinity>();
    Eigen::LDLT<Eigen::MatrixXd> ldlt(T);
    Eigen::FullPivLU<Eigen::MatrixXd> lu;
    const bool spd = ldlt.info() == Eigen::Success && ldlt.isPositive() &&
                     ldlt.vectorD().minCoeff() > 1e-14 * ldlt.vectorD().cwiseAbs().maxCoeff();
    if (spd) {
      step = ldlt.solve(Q);
    } else {
      lu.compute(T);
      if (!lu.isInvertible()) {
        r.status = StaticStatus::SingularTangent;
        std::ostringstream s;
        s << "singular tangent stiffness after " << r.iterations << " iterations (residual " << r.residual
          << "): a limit point or a mechanism; reduce the load step or check the supports";
        r.message = s.str();
        return r;
      }
      step = lu.solve(Q);
    }
    r.stable = spd;
    if (r.residual <= o.relativeTolerance * scale ||
        step.lpNorm<Eigen::Infinity>() <= o.stepTolerance * std::max(1.0, eta.lpNorm<Eigen::Infinity>())) {
      r.status = StaticStatus::Converged;
      return r;
    }
    if (r.iterations == o.maxIterations) break;
    // Step cutting: accept the first fraction that reduces ||Q|| (and evaluates).
    double alpha = 1.0;
    bool accepted = false;
    for (int cut = 0; cut <= o.maxCuts; ++cut, alpha *= 0.5) {
      trial = eta + alpha * step;
      if (evaluate(problem, trial, Qtrial, nullptr, error) && Qtrial.lpNorm<Eigen::Infinity>() < r.residual) {
        accepted = true;
        break;
      }
    }
    if (!accepted && spd && o.energyFallback) {
      // Fallback merit: the energy norm Q^T T^-1 Q. In a closed loop of axially stiff members
      // (spatial leaf springs) the predictor's second-order axial forces dominate ||Q||_inf
      // for any useful step; weighted by the compliance they are small against the bending
      // residual, so a fraction of the step still makes progress.
      const double merit = Q.dot(step);
      alpha = 1.0;
      for (int cut = 0; cut <= 3 * o.maxCuts; ++cut, alpha *= 0.5) {
        trial = eta + alpha * step;
        if (evaluate(problem, trial, Qtrial, nullptr, error) && Qtrial.dot(ldlt.solve(Qtrial)) < merit) {
          accepted = true;
          break;
        }
      }
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
    if (!evaluate(problem, eta, Q, &T, error)) {
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

}  // namespace flexmb::solvers
