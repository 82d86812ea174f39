#pragma once
// Sparse LU for the kinematic Jacobian (KLU, SuiteSparse). KLU analyses the pattern once and
// pivots (klu_factor) on the first factorisation and whenever the old pivots go bad
// (min |u_kk| / max |u_kk| <= 1e-10, or a zero or non-finite pivot). Eigen's KLU wrapper re-runs
// klu_factor (allocating) on every call, hence this small class.
// Solves do not call klu_solve: the factors live in a layout made for solving (rows as dot
// products, small diagonal blocks dense and unrolled, two right-hand sides per vector register),
// about 3x fewer instructions on kinematic Jacobians. Refactorisations with the old pivot order do
// not call klu_refactor either (it and copying its factors over were the largest single cost of a
// full-model evaluation): klu_refactor's left-looking loop over index maps made when KLU pivots,
// small blocks as dense unrolled LUs, writes the factor values straight into that layout (no copy,
// no allocation; KLU's numeric object is brought up to date only for solveTransposed). ~27% fewer
// instructions per factorisation on the full guidance model, ~50% on the kinematic Jacobian alone.
#include <memory>
#include <vector>

namespace flexmb::core {

class SparseLU {
 public:
  SparseLU();
  ~SparseLU();
  SparseLU(const SparseLU&) = delete;
  SparseLU& operator=(const SparseLU&) = delete;

  // Without KLU's own row scaling (for a matrix the caller has equilibrated: saves a pass per
  // factorisation). Call before factorize.
  void disableScaling();
  // Compressed-column pattern (n x n); the arrays must stay alive and keep their pattern.
  void analyze(int n, const int* colPtr, const int* rowIdx);
  // Uses the analysis (KLU's symbolic object, the pattern) of `analysed` instead of analysing the
  // same pattern again: the factorisations stay this object's own. KLU only reads the symbolic
  // object, so several SparseLUs may factorise and solve on one; the pattern arrays of `analysed`
  // must stay alive. Call before factorize.
  void shareAnalysis(const SparseLU& analysed);
  // Factorise with the values ax (same pattern). Returns false when singular.
  bool factorize(const double* ax);
  // Solves A X = B in place for nrhs columns (leading dimension n). Allocation-free; uses a
  // workspace of the object (not thread-safe, as klu_solve's).
  void solve(double* b, int nrhs) const;
  // Solves A^T X = B in place.
  void solveTransposed(double* b, int nrhs) const;
  double reciprocalCondition() const;            // crude estimate from the last factorisation
  long factorNonzeros() const;                   // entries of L + U of the last factorisation (0 before one)
  long pivotings() const { return pivotings_; }  // factorisations with fresh pivoting (klu_factor)
  int size() const { return n_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int n_ = 0;
  long pivotings_ = 0;
};

}  // namespace flexmb::core
