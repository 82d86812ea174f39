#pragma once
// Polynomials in m variables on a box lo <= eta <= hi: sums of products of Chebyshev polynomials
// T_k(xi_i), xi_i = (2 eta_i - lo_i - hi_i) / (hi_i - lo_i), over a set of exponent rows (the
// reduced operators' training on the analysis floor chooses theirs adaptively; the anisotropic
// total-degree set {k : sum_i k_i / p_i <= 1} is the simple alternative). The reduced operators
// are coefficient vectors on one such basis, so an evaluation costs O(terms x m) whatever the
// mesh. Fitting is weighted-free least squares on values and/or gradients; samples drawn from the
// arcsine (Chebyshev) density keep it well conditioned
// (Cohen & Migliorati, SMAI J. Comput. Math. 3, 2017).
#include <Eigen/Core>
#include <vector>

namespace flexmb::solvers {

class ChebyshevBasis {
 public:
  // Per-call tables (caller-owned, so that evaluation allocates nothing after the first call).
  struct Scratch {
    Eigen::MatrixXd T, dT;  // T_k(xi_i), d T_k / d eta_i: m x (p_max + 1)
    Eigen::MatrixXd d2T;    // d^2 T_k / d eta_i^2 (pathDerivatives only)
    Eigen::VectorXd left;   // prefix products of one term
  };

  ChebyshevBasis() = default;
  // The anisotropic total-degree set {k : sum_i k_i / p_i <= 1} of `degrees` p_i (each >= 0; lo < hi
  // componentwise).
  ChebyshevBasis(Eigen::VectorXd lo, Eigen::VectorXd hi, const std::vector<int>& degrees);
  // An explicit set (rows of `exponents`: one term's k_1..k_m), e.g. read back from a file.
  ChebyshevBasis(Eigen::VectorXd lo, Eigen::VectorXd hi, Eigen::MatrixXi exponents);

  int variables() const { return static_cast<int>(lo_.size()); }
  int size() const { return static_cast<int>(exponents_.rows()); }
  const Eigen::VectorXd& lower() const { return lo_; }
  const Eigen::VectorXd& upper() const { return hi_; }
  const Eigen::MatrixXi& exponents() const { return exponents_; }
  // The first variable outside the box (tolerance: `slack` of its width), or -1.
  int outside(const Eigen::Ref<const Eigen::VectorXd>& eta, double slack = 0.0) const;

  // phi_p(eta) for the first `count` terms (all: count < 0), and, when gradT is given, their
  // gradients as columns: gradT(j, p) = d phi_p / d eta_j (m x size()).
  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& eta, Scratch& s, Eigen::Ref<Eigen::VectorXd> phi,
                Eigen::MatrixXd* gradT, int count = -1) const;
  // The tables alone (s.T, s.dT at eta), for a caller that walks the terms itself: term p's factor
  // of variable i is s.T.data()[termOffsets()[p * m + i]] (its derivative: s.dT at the same entry).
  void tables(const Eigen::Ref<const Eigen::VectorXd>& eta, Scratch& s) const;
  const int* termOffsets() const { return offsets_.data(); }
  // Along a path eta(t) with rate v and acceleration a at eta: each of the first `count` terms' value,
  // first and second time derivative (grad phi . v and v^T H v + grad phi . a), exact: the factors'
  // second-order Taylor series in t multiplied out.
  void pathDerivatives(const Eigen::Ref<const Eigen::VectorXd>& eta, const Eigen::Ref<const Eigen::VectorXd>& v,
                       const Eigen::Ref<const Eigen::VectorXd>& a, Scratch& s, Eigen::Ref<Eigen::VectorXd> phi,
                       Eigen::Ref<Eigen::VectorXd> rate, Eigen::Ref<Eigen::VectorXd> acceleration,
                       int count = -1) const;

  // A sample point from u in [0, 1)^m under the arcsine density on the box.
  Eigen::VectorXd arcsinePoint(const Eigen::Ref<const Eigen::VectorXd>& u) const;

 private:
  void setOffsets();  // maxDegree_ and offsets_ from exponents_

  Eigen::VectorXd lo_, hi_;
  Eigen::MatrixXi exponents_;
  std::vector<int> offsets_;  // per term, k_i + i (p_max + 1): its entries in the tables (column i: variable i)
  int maxDegree_ = 0;
  std::vector<int> degreeOf_;  // per variable, its highest exponent in the set
};

// The i-th point (i >= 1) of the Halton sequence in m dimensions (bases: the first m primes).
Eigen::VectorXd haltonPoint(long i, int m);

// Least-squares coefficients (count x k; the first `count` terms, all when count < 0) so that sum_p c_p phi_p matches
// `values` (n x k) at the `points` (n x m) and, with gradients (n*m x k; row s*m + j: d/d eta_j at point s), their
// gradients too (weight `gradientWeight` per gradient row). With valuesWeight = 0 only gradients are
// fitted and the constant term is 0. Column-pivoting QR; throws std::invalid_argument on sizes.
Eigen::MatrixXd fitChebyshev(const ChebyshevBasis& basis, const Eigen::MatrixXd& points, const Eigen::MatrixXd& values,
                             double valuesWeight, const Eigen::MatrixXd& gradients, double gradientWeight,
                             int count = -1);

}  // namespace flexmb::solvers
