// Lowest eigenpairs of the generalised symmetric eigenproblem A v = lambda B v (paper Eq. 21:
// A = K + G symmetric, possibly indefinite (buckled / mechanism modes) or singular (rigid-body modes);
// B = M symmetric positive definite; lambda = omega^2). Solvers know nothing of mechanics.
//
// Methods
//   solveArpack : ARPACK (arpack-ng) dsaupd/dseupd, mode 3 (shift-invert), bmat 'G', which 'LM', on a
//                 ShiftInvertOperator (Spectra-style plug-in: dense LU or sparse UMFPACK provided here).
//                 It returns the nev eigenvalues NEAREST TO THE SHIFT sigma. With the default shift just
//                 below zero these are the lowest ones, provided no negative (buckled) eigenvalue lies
//                 further below sigma than the nev-th positive one lies above it (no inertia count is
//                 made); pass a more negative `shift` for strongly buckled systems.
//   solveDense  : Eigen::GeneralizedSelfAdjointEigenSolver (Cholesky of B), the algebraically lowest nev.
//   solveLowest : dense matrices in; dense when n < max(denseBelow, 2*nev+2), else ARPACK + DenseShiftInvert.
//
// Default shift: sigma = -1e-3 * s, s = median_i(A_ii / B_ii) (over B_ii > 0);
// if that median is not positive, s = median |A_ii / B_ii|; if that is 0, s = 1. Never exactly 0.
// If A - sigma B is singular the shift is moved further down (sigma - 1e-6*s*10^k, k = 0..3; a note is
// left in `message`); if every attempt fails the status is Singular.
//
// Classification (identical for ARPACK and dense, both see the same nev eigenvalues):
//   scale    = max(|median_i(A_ii/B_ii)|, max_i |lambda_i| over the returned eigenvalues)
//   rigid    : |lambda| <= 1e-8 * scale          (rigid-body or mechanism mode; omega = 0)
//   unstable : lambda  <  -1e-8 * scale          (clearly negative: buckled; omega = 0)
//   omega    = sqrt(max(lambda, 0)) otherwise.
// Residual of mode i: ||A v - lambda B v|| / max(||A v||, |lambda| ||B v||, tiny), tiny = scale * ||B v||
// for rigid modes (lambda ~ 0 and A v ~ round-off carry no scale of their own, so they are measured
// against the spectrum scale), tiny = 1e-8 * scale * ||B v|| otherwise (inactive, since |lambda| > that).
//
// Errors: wrong sizes, nev < 1, nev >= n (ARPACK / solveLowest) or nev > n (solveDense), maxIterations < 1
// throw std::invalid_argument. Symmetry of A and B is assumed, not checked. Non-convergence is a status
// (NotConverged, with the converged subset returned); a singular pencil factorisation or a B that is
// not positive definite (dense) is Singular.
// ARPACK keeps Fortran SAVE state: solveArpack serialises all ARPACK calls of the process with a mutex and
// uses a deterministic start vector, so equal inputs give bit-identical results.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCore>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace flexmb::solvers {

struct EigenOptions {
  int nev = 6;                  // number of lowest eigenvalues wanted
  std::optional<double> shift;  // default: automatic small negative shift (see above), never exactly 0
  int maxIterations = 1000;     // ARPACK implicit restarts (iparam[2])
  double tolerance = 0.0;       // ARPACK tol (0 = machine precision)
  int denseBelow = 0;           // solveLowest: dense solver when n < max(denseBelow, 2*nev+2)
  // Without a given shift: move the automatic shift towards the lowest eigenvalues first (a few
  // rounds of inverse iteration and Rayleigh quotients, sigma = -0.1 * rho). For pencils whose
  // diagonal ratios say little about the lowest eigenvalues (nodal coordinates: axial stiffness
  // over nodal mass lies many decades above the bending modes), where the diagonal shift would cost
  // accuracy and restarts.
  bool lowestShift = false;
};

enum class EigenStatus { Converged, NotConverged, Singular };

struct EigenResult {
  EigenStatus status = EigenStatus::Singular;
  std::string message;                 // empty when Converged without remarks
  Eigen::VectorXd lambda;              // ascending
  Eigen::MatrixXd vectors;             // B-orthonormal columns
  Eigen::VectorXd omega;               // rad/s: sqrt(max(lambda,0)); rigid and unstable modes report 0
  std::vector<bool> rigid;             // |lambda| <= 1e-8*scale: rigid-body / mechanism mode
  std::vector<bool> unstable;          // lambda < -1e-8*scale (buckled)
  double maxResidual = 0.0;            // max_i relative residual (see above)
  double maxOrthogonalityError = 0.0;  // max |V^T B V - I|
  int converged = 0;                   // ARPACK iparam[4]; dense: number returned
  int iterations = 0;                  // ARPACK iparam[2] on return (restarts; maxIterations+1 when it ran out)
  double shift = 0.0;                  // shift actually used (ARPACK); dense: 0
  double scale = 0.0;                  // spectrum scale used for the rigid / unstable flags
  std::string method;                  // "arpack-shift-invert" or "dense"
  Eigen::VectorXd hz() const;          // omega / 2pi
};

// Operator interface: the solver only sees these small objects, so another factorisation plugs in.
class ShiftInvertOperator {
 public:
  virtual ~ShiftInvertOperator() = default;
  virtual int size() const = 0;
  virtual bool factorize(double sigma) = 0;                      // A - sigma B; false if singular
  virtual void solve(const double* in, double* out) const = 0;   // (A - sigma B)^{-1} in
  virtual void applyB(const double* in, double* out) const = 0;  // B in
  virtual void applyA(const double* in, double* out) const = 0;  // A in (residuals)
  // Diagonals of A and B (for the automatic shift and the spectrum scale). The default builds them
  // from size() applications of applyA / applyB to unit vectors; implementations override it.
  virtual void diagonals(double* aDiag, double* bDiag) const;
  // Residuals are measured after this projection (constrained pencils: the part of A v - lambda B v
  // that the constraint forces C^T mu cannot balance). Default: none.
  virtual void projectResidual(double* /*v*/) const {}
};

// Dense A, B (copied); Eigen PartialPivLU of A - sigma B (indefinite allowed). Singular when a pivot is
// zero / not finite or the reciprocal condition estimate is below machine epsilon.
class DenseShiftInvert final : public ShiftInvertOperator {
 public:
  DenseShiftInvert(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);
  int size() const override { return static_cast<int>(A_.rows()); }
  bool factorize(double sigma) override;
  void solve(const double* in, double* out) const override;
  void applyB(const double* in, double* out) const override;
  void applyA(const double* in, double* out) const override;
  void diagonals(double* aDiag, double* bDiag) const override;

 private:
  Eigen::MatrixXd A_, B_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  bool factored_ = false;
};

// Sparse A, B (copied, full storage of both triangles); UMFPACK LU of A - sigma B via Eigen's UmfPackLU
// (kept out of this header). Singular when UMFPACK reports a singular matrix or a probe solve
// (right-hand side of ones) is not finite.
class SparseShiftInvert final : public ShiftInvertOperator {
 public:
  SparseShiftInvert(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B);
  ~SparseShiftInvert() override;
  SparseShiftInvert(const SparseShiftInvert&) = delete;
  SparseShiftInvert& operator=(const SparseShiftInvert&) = delete;
  int size() const override;
  bool factorize(double sigma) override;
  void solve(const double* in, double* out) const override;
  void applyB(const double* in, double* out) const override;
  void applyA(const double* in, double* out) const override;
  void diagonals(double* aDiag, double* bDiag) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The pencil (A, B) on the null space of a constraint matrix C (r x n, full row rank): eigenpairs of
//   A v = lambda B v + C^T mu,  C v = 0,
// i.e. of (N^T A N, N^T B N) for any basis N of null(C), without forming N (paper Eq. 21 in nodal
// coordinates: A = K_x + G_x, B = M_x, C the Jacobian of the fixed and input deformations). The
// shift-invert solve is one sparse LU (UMFPACK) of the saddle-point matrix [A - sigma B, C^T; C, 0].
// B needs to be positive definite only on null(C). Eigenvectors satisfy C v = 0, v^T B v = 1;
// residuals are measured after projecting out range(C^T) (Euclidean projector, sparse Cholesky of C C^T).
class ConstrainedShiftInvert final : public ShiftInvertOperator {
 public:
  ConstrainedShiftInvert(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B,
                         const Eigen::SparseMatrix<double>& C);
  ~ConstrainedShiftInvert() override;
  ConstrainedShiftInvert(const ConstrainedShiftInvert&) = delete;
  ConstrainedShiftInvert& operator=(const ConstrainedShiftInvert&) = delete;
  int size() const override;
  bool factorize(double sigma) override;
  void solve(const double* in, double* out) const override;
  void applyB(const double* in, double* out) const override;
  void applyA(const double* in, double* out) const override;
  void diagonals(double* aDiag, double* bDiag) const override;
  void projectResidual(double* v) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

EigenResult solveArpack(ShiftInvertOperator& op, const EigenOptions& opt);
EigenResult solveDense(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const EigenOptions& opt);
EigenResult solveLowest(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const EigenOptions& opt);

// Modal assurance criterion between the columns of U and V, optional weighting W (e.g. M; nullptr = I):
// MAC_ij = (u_i^T W v_j)^2 / ((u_i^T W u_i)(v_j^T W v_j)); 0 where a denominator vanishes.
// Result is U.cols() x V.cols(). Sign- and scale-invariant.
Eigen::MatrixXd modalAssurance(const Eigen::MatrixXd& U, const Eigen::MatrixXd& V, const Eigen::MatrixXd* W = nullptr);

// Mode tracking: p (size current.cols()) so that mode j of `current` continues mode p[j] of `previous`.
// Greedy assignment: repeatedly take the largest remaining MAC entry (ties: lowest previous index, then
// lowest current index), assign that pair and remove its row and column. Modes of `current` left over
// when `previous` has fewer columns get -1. Greedy is not a global optimum of the summed MAC, but for
// well-separated modes (MAC near 1 on the continued pairs) it gives the same answer.
std::vector<int> trackModes(const Eigen::MatrixXd& previous, const Eigen::MatrixXd& current,
                            const Eigen::MatrixXd* W = nullptr);

}  // namespace flexmb::solvers
