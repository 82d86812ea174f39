#pragma once
// Sparse LU for the kinematic Jacobian (KLU, SuiteSparse). The pattern is analysed once; later
// factorisations reuse the pivot sequence (klu_refactor, no allocation) and fall back to a fresh
// pivoting factorisation when the reciprocal pivot growth says the old pivots went bad.
// Eigen's KLU wrapper re-runs klu_factor (allocating) on every call, hence this small class.
// Solves do not call klu_solve: each factorisation also copies KLU's factors into a layout made
// for solving (rows as dot products, small diagonal blocks dense and unrolled, two right-hand
// sides per vector register), about 3x fewer instructions on kinematic Jacobians (SparseLU.cpp).
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
  // Factorise with the values ax (same pattern). Returns false when singular.
  bool factorize(const double* ax);
  // Solves A X = B in place for nrhs columns (leading dimension n). Allocation-free; uses a
  // workspace of the object (not thread-safe, as klu_solve's).
  void solve(double* b, int nrhs) const;
  // Solves A^T X = B in place.
  void solveTransposed(double* b, int nrhs) const;
  double reciprocalCondition() const;  // crude estimate from the last factorisation
  long factorNonzeros() const;         // entries of L + U of the last factorisation (0 before one)
  int size() const { return n_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int n_ = 0;
};

}  // namespace flexmb::core
