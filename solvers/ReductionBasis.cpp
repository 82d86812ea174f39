#include "solvers/ReductionBasis.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace flexmb::solvers {
namespace {

std::string str(long v) { return std::to_string(v); }

std::string shape(const Eigen::MatrixXd& A) { return str(A.rows()) + " x " + str(A.cols()); }

[[noreturn]] void fail(const std::string& msg) { throw std::invalid_argument(msg); }

}  // namespace

// ---------------------------------------------------------------------------------------------
// Partition

void Partition::validate(int nq) const {
  if (nq < 0) fail("Partition: nq must be >= 0, got " + str(nq));
  std::vector<int> owner(static_cast<std::size_t>(nq), -1);  // -1 unused, 0 large, 1 small
  auto mark = [&](const std::vector<int>& list, int kind, const char* name) {
    for (int i : list) {
      if (i < 0 || i >= nq)
        fail(std::string("Partition: ") + name + " index " + str(i) + " out of range [0, " + str(nq) + ")");
      int& o = owner[static_cast<std::size_t>(i)];
      if (o == kind) fail(std::string("Partition: duplicate ") + name + " index " + str(i));
      if (o != -1) fail("Partition: index " + str(i) + " is both large and small");
      o = kind;
    }
  };
  mark(large, 0, "large");
  mark(small, 1, "small");
  for (int i = 0; i < nq; ++i)
    if (owner[static_cast<std::size_t>(i)] == -1)
      fail("Partition: index " + str(i) + " is neither large nor small (nq = " + str(nq) + ")");
}

Partition Partition::make(int nq, std::vector<int> large) {
  if (nq < 0) fail("Partition: nq must be >= 0, got " + str(nq));
  std::vector<char> isLarge(static_cast<std::size_t>(nq), 0);
  for (int i : large) {
    if (i < 0 || i >= nq) fail("Partition: large index " + str(i) + " out of range [0, " + str(nq) + ")");
    if (isLarge[static_cast<std::size_t>(i)]) fail("Partition: duplicate large index " + str(i));
    isLarge[static_cast<std::size_t>(i)] = 1;
  }
  Partition p;
  p.large = std::move(large);
  for (int i = 0; i < nq; ++i)
    if (!isLarge[static_cast<std::size_t>(i)]) p.small.push_back(i);
  return p;
}

Partition Partition::make(int nq, std::vector<int> large, std::vector<int> small) {
  Partition p;
  p.large = std::move(large);
  p.small = std::move(small);
  p.validate(nq);
  return p;
}

Eigen::MatrixXd assembleBasis(const Partition& p, const Eigen::MatrixXd& Vs) {
  const int nq = p.size();
  p.validate(nq);
  if (Vs.rows() != p.nSmall())
    fail("assembleBasis: Vs is " + shape(Vs) + " but the partition has " + str(p.nSmall()) +
         " small coordinates (rows of Vs)");
  const Eigen::Index nl = p.nLarge();
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(nq, nl + Vs.cols());
  for (Eigen::Index j = 0; j < nl; ++j) V(p.large[static_cast<std::size_t>(j)], j) = 1.0;
  // No rows to copy without reduced columns: Eigen's row() of a matrix without columns offsets its null
  // data pointer (undefined behaviour, UBSan's pointer-overflow check in the sanitizer pass).
  if (Vs.cols() > 0)
    for (Eigen::Index i = 0; i < Vs.rows(); ++i)
      V.row(p.small[static_cast<std::size_t>(i)]).tail(Vs.cols()) = Vs.row(i);
  return V;
}

Eigen::MatrixXd restrictToSmall(const Partition& p, const Eigen::MatrixXd& A) {
  const int nq = p.size();
  p.validate(nq);
  if (A.rows() != nq || A.cols() != nq)
    fail("restrictToSmall: matrix is " + shape(A) + " but the partition has nq = " + str(nq));
  const Eigen::Index ns = p.nSmall();
  Eigen::MatrixXd B(ns, ns);
  for (Eigen::Index j = 0; j < ns; ++j)
    for (Eigen::Index i = 0; i < ns; ++i)
      B(i, j) = A(p.small[static_cast<std::size_t>(i)], p.small[static_cast<std::size_t>(j)]);
  return B;
}

// ---------------------------------------------------------------------------------------------
// Normalisation and sign

void normaliseColumn(Eigen::Ref<Eigen::VectorXd> v) {
  if (v.size() == 0) fail("normaliseColumn: empty vector");
  if (!v.allFinite()) fail("normaliseColumn: vector has non-finite entries");
  const double n = v.norm();
  if (!(n > 0.0)) fail("normaliseColumn: zero vector cannot be normalised");
  v /= n;
  const double mx = v.cwiseAbs().maxCoeff();
  const double tol = (1.0 - 1e-10) * mx;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (std::abs(v[i]) >= tol) {
      if (v[i] < 0.0) v = -v;
      break;
    }
  }
}

Eigen::MatrixXd modalBasis(const Eigen::MatrixXd& modes, int r) {
  if (r < 0) fail("modalBasis: r must be >= 0, got " + str(r));
  if (r > modes.cols())
    fail("modalBasis: r = " + str(r) + " modes requested but only " + str(modes.cols()) + " available");
  if (r > 0 && modes.rows() == 0) fail("modalBasis: modes have 0 rows");
  Eigen::MatrixXd Vs = modes.leftCols(r);
  for (Eigen::Index k = 0; k < r; ++k) {
    if (!Vs.col(k).allFinite()) fail("modalBasis: mode " + str(k) + " has non-finite entries");
    if (!(Vs.col(k).norm() > 0.0)) fail("modalBasis: mode " + str(k) + " is a zero vector");
    normaliseColumn(Vs.col(k));
  }
  return Vs;
}

Eigen::MatrixXd massNormalisedModalBasis(const Eigen::MatrixXd& modes, const Eigen::MatrixXd& M, int r) {
  if (M.rows() != modes.rows() || M.cols() != modes.rows())
    fail("massNormalisedModalBasis: M is " + shape(M) + " but the modes have " + str(modes.rows()) + " rows");
  Eigen::MatrixXd Vs = modalBasis(modes, r);  // checks, unit length and sign
  for (Eigen::Index k = 0; k < r; ++k) {
    const double m = Vs.col(k).dot(M * Vs.col(k));
    if (!(m > 0.0) || !std::isfinite(m))
      fail("massNormalisedModalBasis: mode " + str(k) + " has modal mass " + std::to_string(m) +
           " (M must be positive definite on the modes)");
    Vs.col(k) /= std::sqrt(m);  // positive factor: the sign convention is kept
  }
  return Vs;
}

// ---------------------------------------------------------------------------------------------
// SVD-modal basis

SvdModalResult svdModalBasis(const std::vector<Eigen::MatrixXd>& modes, const std::vector<Eigen::VectorXd>& omegas,
                             int r, double a, double threshold, int count) {
  const std::string fn = "svdModalBasis: ";
  if (modes.empty()) fail(fn + "no configurations given");
  if (omegas.size() != modes.size())
    fail(fn + str(static_cast<long>(modes.size())) + " mode sets but " + str(static_cast<long>(omegas.size())) +
         " frequency sets");
  if (r < 1) fail(fn + "r must be >= 1, got " + str(r));
  if (!std::isfinite(a)) fail(fn + "weight exponent a must be finite");
  if (!(threshold >= 0.0 && threshold < 1.0))
    fail(fn + "threshold must be in [0, 1), got " + std::to_string(threshold));
  if (count < 0) fail(fn + "count must be >= 0, got " + str(count));

  const Eigen::Index ns = modes.front().rows();
  if (ns == 0) fail(fn + "modes have 0 rows");
  const std::size_t n = modes.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::string cfg = "configuration " + str(static_cast<long>(i));
    if (modes[i].rows() != ns)
      fail(fn + cfg + ": modes have " + str(modes[i].rows()) + " rows, configuration 0 has " + str(ns));
    if (modes[i].cols() < r)
      fail(fn + cfg + ": " + str(modes[i].cols()) + " modes available, r = " + str(r) + " requested");
    if (omegas[i].size() < r)
      fail(fn + cfg + ": " + str(omegas[i].size()) + " frequencies given, r = " + str(r) + " needed");
  }

  const Eigen::Index nc = static_cast<Eigen::Index>(n) * r;
  Eigen::MatrixXd Q(ns, nc);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string cfg = "configuration " + str(static_cast<long>(i));
    for (int k = 0; k < r; ++k) {
      const std::string md = cfg + ", mode " + str(k);
      Eigen::VectorXd v = modes[i].col(k);
      if (!v.allFinite()) fail(fn + md + ": non-finite entries");
      if (!(v.norm() > 0.0)) fail(fn + md + ": zero vector");
      normaliseColumn(v);
      double w = 1.0;
      if (a != 0.0) {
        const double om = omegas[i][k];
        if (!(om > 0.0) || !std::isfinite(om))
          fail(fn + md + ": omega = " + std::to_string(om) + " cannot be weighted by omega^-a with a = " +
               std::to_string(a) + " (rigid or invalid mode; use a = 0 or leave the mode out)");
        w = std::pow(om, -a);
        if (!std::isfinite(w) || !(w > 0.0))
          fail(fn + md + ": weight omega^-a overflows (omega = " + std::to_string(om) + ", a = " + std::to_string(a) +
               ")");
      }
      Q.col(static_cast<Eigen::Index>(i) * r + k) = w * v;
    }
  }

  Eigen::BDCSVD<Eigen::MatrixXd> svd(Q, Eigen::ComputeThinU);
  if (svd.info() != Eigen::Success) fail(fn + "SVD did not converge");

  SvdModalResult res;
  res.singularValues = svd.singularValues();
  const double sum = res.singularValues.sum();
  if (!(sum > 0.0) || !std::isfinite(sum)) fail(fn + "singular values sum to " + std::to_string(sum));
  res.scaledSingularValues = res.singularValues / sum;
  const Eigen::Index nsv = res.singularValues.size();

  if (count > 0) {
    if (count > nsv)
      fail(fn + "count = " + str(count) + " exceeds the " + str(nsv) + " singular vectors available (min(n_s, n r))");
    res.kept = count;
  } else {
    int k = 0;
    while (k < nsv && res.scaledSingularValues[k] > threshold) ++k;
    if (k == 0)
      fail(fn + "no singular value share exceeds threshold " + std::to_string(threshold) + " (largest share " +
           std::to_string(res.scaledSingularValues[0]) + ")");
    res.kept = k;
  }
  res.Vs = svd.matrixU().leftCols(res.kept);
  for (Eigen::Index k = 0; k < res.kept; ++k) normaliseColumn(res.Vs.col(k));
  return res;
}

}  // namespace flexmb::solvers
