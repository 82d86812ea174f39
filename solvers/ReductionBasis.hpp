// Reduction bases of Boer et al. 2013, Section 3 (Eq. 17-23): q = V eta.
//
// Only matrices here, no mechanics: the caller computes the eigenmodes of the q_s subproblem
// (Eq. 21) in one or several configurations and passes them in.
//
//   * Partition (Eq. 20): q is split into "large" coordinates q_l (e.g. hinge rotations), which keep
//     identity columns (V_l = I), and "small" coordinates q_s, which get a reduced basis V_s.
//   * assembleBasis: V = blockdiag(I_l, V_s) written in the ORIGINAL ordering of q.
//   * restrictToSmall: the q_s block of a square nq x nq matrix (K_s, G_s, M_s of Eq. 21).
//   * modalBasis (Eq. 21): the first r modes, normalised, with a fixed sign.
//   * svdModalBasis (Eq. 22-23): weighted modes of n configurations, concatenated, SVD, dominant
//     left singular vectors.
//
// Sign convention (modalBasis and svdModalBasis): every returned column has unit Euclidean length
// and its largest-magnitude entry is positive. "Largest" is taken with a relative tolerance of
// 1e-10 so that ties broken only by round-off do not flip signs: the first index i (lowest index)
// with |v_i| >= (1 - 1e-10) max_j |v_j| is made positive.
//
// Errors: inconsistent sizes, invalid indices or parameters throw std::invalid_argument with a
// message naming the offending argument (and, for svdModalBasis, the configuration and mode).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace flexmb::solvers {

// Split of the nq coordinates into large (identity columns) and small (reduced) ones.
// `large` keeps the order given by the caller (column j < n_l of V is the unit vector of large[j]);
// `small` is ascending when built by make(nq, large); its order is the row order of V_s.
struct Partition {
  std::vector<int> large;
  std::vector<int> small;

  int size() const { return static_cast<int>(large.size() + small.size()); }  // = nq
  int nLarge() const { return static_cast<int>(large.size()); }
  int nSmall() const { return static_cast<int>(small.size()); }

  // large indices in [0, nq), no duplicates; small = the remaining indices, ascending.
  static Partition make(int nq, std::vector<int> large);
  // Both lists given: they must be disjoint, free of duplicates, in [0, nq) and cover all indices.
  static Partition make(int nq, std::vector<int> large, std::vector<int> small);

  // Throws std::invalid_argument unless large and small form a partition of {0, ..., nq-1}.
  void validate(int nq) const;
};

// V (nq x (n_l + cols(Vs))): column j < n_l is the unit vector e_{large[j]}; column n_l + k carries
// Vs(i, k) in row small[i]. Requires Vs.rows() == n_s (Vs may have 0 columns).
Eigen::MatrixXd assembleBasis(const Partition& p, const Eigen::MatrixXd& Vs);

// A(small, small): the n_s x n_s block of a square nq x nq matrix (Eq. 21's K_s, G_s, M_s).
Eigen::MatrixXd restrictToSmall(const Partition& p, const Eigen::MatrixXd& A);

// Normalise one vector to unit length and apply the sign convention above (in place).
// Throws std::invalid_argument if the vector is zero or not finite.
void normaliseColumn(Eigen::Ref<Eigen::VectorXd> v);

// Modal basis (Eq. 21): the first r columns of `modes` (eigenvectors of the q_s subproblem, ascending
// frequency), each normalised to unit length with the sign convention. 0 <= r <= modes.cols();
// zero or non-finite columns throw.
Eigen::MatrixXd modalBasis(const Eigen::MatrixXd& modes, int r);

// Mass-normalised modal basis (Eq. 21, as MATLAB's eig(K, M) returns the modes, which is what the
// paper's counts were made with): the first r columns of `modes`, each scaled so that v^T M v = 1,
// with the sign convention above (largest-magnitude entry positive). M (n_s x n_s) must be symmetric
// positive definite on the modes; a column with v^T M v <= 0 or non-finite throws.
// The scaling matters for the reduced simulation: ode45's absolute tolerance acts on eta.
Eigen::MatrixXd massNormalisedModalBasis(const Eigen::MatrixXd& modes, const Eigen::MatrixXd& M, int r);

struct SvdModalResult {
  Eigen::MatrixXd Vs;                    // n_s x kept, orthonormal columns, sign convention applied
  Eigen::VectorXd singularValues;        // all min(n_s, n*r) singular values of Q, descending
  Eigen::VectorXd scaledSingularValues;  // sigma_k / sum(sigma), sums to 1
  int kept = 0;
};

// SVD-modal basis (Eq. 22-23). For configuration i: modes[i] (n_s x >= r, ascending frequency) and
// omegas[i] (size >= r, rad/s). Q^(i) = normalised first r modes * diag(omega_k^-a);
// Q = [Q^(1) ... Q^(n)] (n_s x n r); thin SVD Q = U S W^T.
// Kept: exactly `count` left singular vectors if count > 0 (count <= min(n_s, n r)); otherwise those
// whose share sigma_k / sum(sigma) is strictly greater than `threshold` (0 <= threshold < 1); if none
// qualifies, std::invalid_argument is thrown.
// a is any finite real; with a != 0 every used omega must be > 0 (rigid modes, omega = 0, throw,
// naming the configuration and the mode, 0-based). With a == 0 the omegas are not used (but their
// sizes are still checked).
SvdModalResult svdModalBasis(const std::vector<Eigen::MatrixXd>& modes, const std::vector<Eigen::VectorXd>& omegas,
                             int r, double a, double threshold = 0.01, int count = 0);

}  // namespace flexmb::solvers
