#pragma once
// Newton's method for static equilibrium Q(eta) = 0 with tangent T = -dQ/deta (Kbar + Gbar), with
// step cutting when an iterate is not accepted or the problem fails to evaluate. Knows nothing of
// mechanics: the caller supplies the residual and a factorised tangent (StaticProblem), dense
// (DenseStaticProblem) or any other factorisation.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <functional>
#include <string>

namespace flexmb::solvers {

struct NewtonOptions {
  double relativeTolerance = 1e-10;  // on ||Q|| relative to the reference force scale
  double stepTolerance = 1e-12;      // on ||d eta|| relative to max(1, ||eta||)
  int maxIterations = 50;
  int maxCuts = 10;  // halvings of a step that is not accepted
  // Step acceptance. Always: ||Q(eta + a step)||_inf < ||Q(eta)||_inf. With correctionMonotonicity
  // also when the Newton correction at the trial, with the trial's own tangent, is shorter:
  // |T(trial)^-1 Q(trial)|_2 <= (1 - a/4) |step|_2 (Deuflhard's restricted monotonicity test on
  // the next correction instead of the simplified one). In a closed loop of axially stiff members
  // (spatial leaf springs) the full Newton step closes the loop only to second order: the
  // released member's axial force raises ||Q||_inf by four decades, and the simplified correction
  // with the old tangent, which lacks that force's geometric stiffness, is 17x the step; the next
  // Newton correction is 100x smaller than the step. The residual test alone cuts every step to
  // a few percent and Newton crawls. Off by default: planar load paths stay as they were.
  bool correctionMonotonicity = false;
};

enum class StaticStatus { Converged, NotConverged, SingularTangent, Failed };

struct StaticResult {
  StaticStatus status = StaticStatus::Converged;
  std::string message;
  int iterations = 0;
  double residual = 0.0;
  // Tangent positive definite at the solution. Set from the last factorisation when it knows its
  // definiteness (DenseStaticProblem); otherwise left true for the caller to establish.
  bool stable = true;
};

// What a factorisation says about the tangent.
enum class TangentKind { PositiveDefinite, Indefinite, Unknown, Singular };

// The problem Newton sees. Both evaluations may throw (a failed kinematic solve): the solver
// treats that as a step to cut. A residual evaluation leaves the last factorisation intact.
class StaticProblem {
 public:
  virtual ~StaticProblem() = default;
  // Q(eta).
  virtual void residual(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) = 0;
  // Q(eta) and the factorised tangent T(eta) for solve().
  virtual TangentKind linearize(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) = 0;
  // x = T^-1 b with the last linearisation.
  virtual void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
};

// T is positive definite (x^T T x > 0): the LDLT of its symmetric part succeeds with pivots above
// 1e-14 of the largest (the stability test of an equilibrium).
bool isPositiveDefinite(const Eigen::MatrixXd& T);
// T equals its transpose to 1e-14 of its largest entry.
bool isSymmetric(const Eigen::MatrixXd& T);

// A dense tangent from a callable: LDLT when symmetric and positive definite (pivots above 1e-14 of
// the largest), else full-pivot LU (a non-symmetric tangent is classified by its symmetric part).
class DenseStaticProblem final : public StaticProblem {
 public:
  // Residual Q(eta); when T is non-null also the tangent T = -dQ/deta.
  using Function = std::function<void(const Eigen::VectorXd& eta, Eigen::VectorXd& Q, Eigen::MatrixXd* T)>;
  explicit DenseStaticProblem(Function f) : f_(std::move(f)) {}
  void residual(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) override { f_(eta, Q, nullptr); }
  TangentKind linearize(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) override;
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;

 private:
  Function f_;
  Eigen::MatrixXd T_;
  Eigen::LLT<Eigen::MatrixXd> llt_;  // tried first: blocked, several times faster than LDLT
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
  Eigen::FullPivLU<Eigen::MatrixXd> lu_;
  bool spd_ = false, byCholesky_ = false;
};

// forceScale: a typical generalised force magnitude (e.g. of the applied load) for the residual test.
StaticResult solveEquilibrium(StaticProblem& problem, Eigen::VectorXd& eta, double forceScale,
                              const NewtonOptions& options = {});
// The same on a dense callable (DenseStaticProblem).
StaticResult solveEquilibrium(const DenseStaticProblem::Function& problem, Eigen::VectorXd& eta, double forceScale,
                              const NewtonOptions& options = {});

}  // namespace flexmb::solvers
