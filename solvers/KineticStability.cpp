// The kinetic stability criterion on the eigenvalues of A v = lambda M v nearest zero. See the header.
#include "solvers/KineticStability.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <arpack.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "solvers/ArpackCommon.hpp"

namespace flexmb::solvers {

namespace {

constexpr double kKineticTol = 1e-8;  // relative to the spectrum scale, as EigenSolver's flags

// The nev eigenvalues nearest zero, by a dense general eigensolver on L^-1 A L^-T (M = L L^T).
bool denseNearestZero(const Eigen::MatrixXd& A, const Eigen::LLT<Eigen::MatrixXd>& llt, int nev,
                      Eigen::VectorXcd& lambda, std::string& message) {
  Eigen::MatrixXd S = llt.matrixL().solve(A);
  S = llt.matrixL().solve(S.transpose()).transpose();
  Eigen::EigenSolver<Eigen::MatrixXd> es(S, false);
  if (es.info() != Eigen::Success) {
    message = "the dense eigensolver did not converge";
    return false;
  }
  std::vector<std::complex<double>> v(es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size());
  std::sort(v.begin(), v.end(), [](auto a, auto b) { return std::abs(a) < std::abs(b); });
  std::size_t k = std::min(v.size(), static_cast<std::size_t>(nev));
  if (k < v.size() && k > 0 && v[k - 1].imag() != 0.0 && v[k].imag() == -v[k - 1].imag()) ++k;  // complete a pair
  lambda = Eigen::Map<const Eigen::VectorXcd>(v.data(), static_cast<Eigen::Index>(k));
  return true;
}

// ARPACK, regular mode on OP = (A - sigma M)^-1 M: its largest Ritz values mu are the lambda = sigma
// + 1/mu nearest sigma. False (with the reason) when ARPACK does not deliver nev converged values.
bool arpackNearestZero(const Eigen::MatrixXd& A, const Eigen::MatrixXd& M, double sigma, int nev,
                       Eigen::VectorXcd& lambda, std::string& message) {
  const int n = static_cast<int>(A.rows());
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(A - sigma * M);
  const int ncv = std::min(n, std::max(2 * nev + 1, 20));
  const int lworkl = 3 * ncv * ncv + 6 * ncv;
  std::vector<double> resid(static_cast<std::size_t>(n)), v(static_cast<std::size_t>(n) * ncv),
      workd(3 * static_cast<std::size_t>(n)), workl(static_cast<std::size_t>(lworkl));
  fillStartVector(resid.data(), n);
  a_int iparam[11] = {0};
  a_int ipntr[14] = {0};
  iparam[0] = 1;     // exact shifts
  iparam[2] = 1000;  // implicit restarts
  iparam[3] = 1;
  iparam[6] = 1;  // regular mode: OP x supplied by us
  a_int ido = 0, info = 1;
  Eigen::VectorXd tmp(n);
  std::lock_guard<std::mutex> lock(arpackMutex());
  for (;;) {
    arpack::naupd(ido, arpack::bmat::identity, n, arpack::which::largest_magnitude, nev, 0.0, resid.data(), ncv,
                  v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info);
    if (ido != -1 && ido != 1) break;
    const Eigen::Map<const Eigen::VectorXd> x(workd.data() + ipntr[0] - 1, n);
    Eigen::Map<Eigen::VectorXd> y(workd.data() + ipntr[1] - 1, n);
    tmp.noalias() = M * x;
    y = lu.solve(tmp);
  }
  if (info < 0 || iparam[4] < nev) {
    std::ostringstream os;
    os << "ARPACK dnaupd: " << iparam[4] << " of " << nev << " eigenvalues converged (info " << info << ")";
    message = os.str();
    return false;
  }
  std::vector<a_int> select(static_cast<std::size_t>(ncv), 1);
  std::vector<double> dr(static_cast<std::size_t>(nev) + 1), di(static_cast<std::size_t>(nev) + 1),
      z(static_cast<std::size_t>(n) * (nev + 1)), workev(3 * static_cast<std::size_t>(ncv));
  a_int info2 = 0;
  arpack::neupd(0, arpack::howmny::ritz_vectors, select.data(), dr.data(), di.data(), z.data(), n, 0.0, 0.0,
                workev.data(), arpack::bmat::identity, n, arpack::which::largest_magnitude, nev, 0.0, resid.data(), ncv,
                v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info2);
  if (info2 != 0) {
    message = "ARPACK dneupd info " + std::to_string(info2);
    return false;
  }
  const int got = std::min<int>(static_cast<int>(iparam[4]), nev + 1);
  std::vector<std::complex<double>> l;
  for (int i = 0; i < got; ++i) {
    const std::complex<double> mu(dr[static_cast<std::size_t>(i)], di[static_cast<std::size_t>(i)]);
    if (mu == 0.0) continue;
    l.push_back(sigma + 1.0 / mu);
  }
  std::sort(l.begin(), l.end(), [](auto a, auto b) { return std::abs(a) < std::abs(b); });
  lambda = Eigen::Map<const Eigen::VectorXcd>(l.data(), static_cast<Eigen::Index>(l.size()));
  return lambda.allFinite();
}

}  // namespace

std::string KineticStability::describe() const {
  std::ostringstream os;
  os.precision(4);
  switch (verdict) {
    case KineticVerdict::Stable:
      return "stable";
    case KineticVerdict::Undecided:
      return "undecided (" + message + ")";
    case KineticVerdict::Divergence:
      os << "divergence (lambda = " << lambda[critical].real() << " (rad/s)^2)";
      return os.str();
    case KineticVerdict::Flutter:
      os << "flutter (lambda = " << lambda[critical].real() << " +- " << std::abs(lambda[critical].imag())
         << "i (rad/s)^2)";
      return os.str();
  }
  return "";
}

KineticStability kineticStability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& M, int nev,
                                  Eigen::Index denseBelow) {
  if (A.rows() != A.cols() || M.rows() != M.cols() || A.rows() != M.rows())
    throw std::invalid_argument("kineticStability: A and M must be square and of one size");
  if (nev < 1) throw std::invalid_argument("kineticStability: nev must be at least 1");
  KineticStability r;
  const Eigen::Index n = A.rows();
  if (n == 0) {
    r.verdict = KineticVerdict::Stable;
    return r;
  }
  if (!A.allFinite() || !M.allFinite()) {
    r.message = "non-finite matrices";
    return r;
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) {
    r.message = "the mass matrix is not positive definite";
    return r;
  }
  const double diagonal = diagonalScale(A.diagonal(), M.diagonal());
  bool done = false;
  if (n >= std::max<Eigen::Index>(denseBelow, 2 * nev + 4)) {
    const double sigma = -1e-3 * (diagonal > 0.0 ? diagonal : 1.0);
    done = arpackNearestZero(A, M, sigma, nev, r.lambda, r.message);
    r.method = "arpack";
    if (!done) r.message += "; dense eigensolver used instead";
  }
  if (!done) {
    std::string why;
    if (!denseNearestZero(A, llt, nev, r.lambda, why)) {
      r.message = why;
      return r;
    }
    r.method = "dense";
  }
  r.scale = diagonal;
  for (const auto& l : r.lambda) r.scale = std::max(r.scale, std::abs(l));
  const double tol = kKineticTol * r.scale;
  r.verdict = KineticVerdict::Stable;
  for (Eigen::Index i = 0; i < r.lambda.size(); ++i) {
    const auto l = r.lambda[i];
    if (std::abs(l.imag()) <= tol && l.real() < -tol) {  // divergence decides over flutter
      r.verdict = KineticVerdict::Divergence;
      r.critical = static_cast<int>(i);
      break;
    }
    if (std::abs(l.imag()) > tol && r.verdict == KineticVerdict::Stable) {
      r.verdict = KineticVerdict::Flutter;
      r.critical = static_cast<int>(i);
    }
  }
  return r;
}

}  // namespace flexmb::solvers
