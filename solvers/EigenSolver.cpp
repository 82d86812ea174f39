// Lowest eigenpairs of A v = lambda B v: ARPACK shift-invert (mode 3) and dense fallback. See EigenSolver.hpp.
#include "solvers/EigenSolver.hpp"

#include "solvers/ArpackCommon.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/UmfPackSupport>

#include <arpack.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace flexmb::solvers {

namespace {

constexpr double kFlagTol = 1e-8;  // rigid / unstable threshold relative to the spectrum scale

using Apply = std::function<void(const double*, double*)>;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  const double hi = v[mid];
  if (v.size() % 2 == 1) return hi;
  const double lo = *std::max_element(v.begin(), v.begin() + mid);
  return 0.5 * (lo + hi);
}

// Sorts (lambda, vectors) ascending, fills flags, omega, residuals and orthogonality.
void finalize(EigenResult& r, const Apply& applyA, const Apply& applyB, double diagScale) {
  const Eigen::Index k = r.lambda.size();
  const Eigen::Index n = r.vectors.rows();
  // ascending order (stable, so equal values keep ARPACK's order)
  std::vector<Eigen::Index> idx(static_cast<std::size_t>(k));
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](Eigen::Index i, Eigen::Index j) { return r.lambda[i] < r.lambda[j]; });
  Eigen::VectorXd lam(k);
  Eigen::MatrixXd vec(n, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    lam[j] = r.lambda[idx[static_cast<std::size_t>(j)]];
    vec.col(j) = r.vectors.col(idx[static_cast<std::size_t>(j)]);
  }
  r.lambda = std::move(lam);
  r.vectors = std::move(vec);

  double scale = diagScale;
  for (Eigen::Index j = 0; j < k; ++j) scale = std::max(scale, std::abs(r.lambda[j]));
  r.scale = scale;
  const double thr = kFlagTol * scale;

  r.omega.resize(k);
  r.rigid.assign(static_cast<std::size_t>(k), false);
  r.unstable.assign(static_cast<std::size_t>(k), false);
  Eigen::MatrixXd BV(n, k);
  Eigen::VectorXd Av(n);
  r.maxResidual = 0.0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const double l = r.lambda[j];
    const bool rigid = std::abs(l) <= thr;
    const bool unstable = !rigid && l < -thr;
    r.rigid[static_cast<std::size_t>(j)] = rigid;
    r.unstable[static_cast<std::size_t>(j)] = unstable;
    r.omega[j] = (rigid || unstable) ? 0.0 : std::sqrt(std::max(l, 0.0));

    applyA(r.vectors.col(j).data(), Av.data());
    applyB(r.vectors.col(j).data(), BV.col(j).data());
    const double nBv = BV.col(j).norm();
    const double num = (Av - l * BV.col(j)).norm();
    // rigid modes (lambda ~ 0, A v ~ round-off) are measured against the spectrum scale
    double den = std::max({Av.norm(), std::abs(l) * nBv, (rigid ? scale : thr) * nBv});
    if (!(den > 0.0)) den = std::numeric_limits<double>::min();
    const double res = num / den;
    r.maxResidual = std::isfinite(res) ? std::max(r.maxResidual, res) : std::numeric_limits<double>::infinity();
  }
  if (k > 0) {
    const Eigen::MatrixXd G = r.vectors.transpose() * BV - Eigen::MatrixXd::Identity(k, k);
    r.maxOrthogonalityError = G.cwiseAbs().maxCoeff();
  } else {
    r.maxOrthogonalityError = 0.0;
  }
}

std::string arpackAupdMessage(int info) {
  switch (info) {
    case 1:
      return "maximum number of iterations taken";
    case 3:
      return "no shifts could be applied during an implicit restart (try a larger ncv)";
    case -1:
      return "n must be positive";
    case -2:
      return "nev must be positive";
    case -3:
      return "ncv must be greater than nev and at most n";
    case -4:
      return "maximum number of iterations must be positive";
    case -5:
      return "invalid 'which'";
    case -6:
      return "invalid bmat";
    case -7:
      return "lworkl too small";
    case -8:
      return "error in the tridiagonal eigenvalue computation (LAPACK dsteqr)";
    case -9:
      return "starting vector is zero";
    case -10:
      return "invalid mode";
    case -11:
      return "mode 1 with bmat 'G' incompatible";
    case -12:
      return "invalid iparam[0]";
    case -13:
      return "nev and which = 'BE' incompatible";
    case -9999:
      return "could not build a Lanczos factorization (is B positive definite?)";
    default:
      return "ARPACK error";
  }
}

void checkSizes(Eigen::Index n, const EigenOptions& opt, bool allowAll, const char* who) {
  std::ostringstream os;
  if (n < 1)
    os << who << ": empty problem";
  else if (opt.nev < 1)
    os << who << ": nev must be >= 1 (got " << opt.nev << ")";
  else if (allowAll ? opt.nev > n : opt.nev >= n)
    os << who << ": nev = " << opt.nev << (allowAll ? " > n = " : " >= n = ") << n;
  else if (opt.maxIterations < 1)
    os << who << ": maxIterations must be >= 1";
  else if (opt.shift && !std::isfinite(*opt.shift))
    os << who << ": shift must be finite";
  const std::string s = os.str();
  if (!s.empty()) throw std::invalid_argument(s);
}

void checkPencil(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const char* who) {
  if (A.rows() != A.cols() || B.rows() != B.cols() || A.rows() != B.rows()) {
    std::ostringstream os;
    os << who << ": A (" << A.rows() << "x" << A.cols() << ") and B (" << B.rows() << "x" << B.cols()
       << ") must be square and of equal size";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

std::mutex& arpackMutex() {
  static std::mutex m;
  return m;
}

void fillStartVector(double* x, int n) {
  for (int i = 0; i < n; ++i) x[i] = 1.0 + 0.5 * std::sin(0.7 * i + 0.3);
}

double diagonalScale(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  std::vector<double> r, ra;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (b[i] > 0.0 && std::isfinite(a[i]) && std::isfinite(b[i])) {
      r.push_back(a[i] / b[i]);
      ra.push_back(std::abs(a[i] / b[i]));
    }
  }
  const double m = median(r);
  if (m > 0.0) return m;
  const double ma = median(ra);
  return ma > 0.0 ? ma : 0.0;
}

Eigen::VectorXd EigenResult::hz() const { return omega / (2.0 * 3.14159265358979323846); }

// ---------------------------------------------------------------------------------------------------
void ShiftInvertOperator::diagonals(double* aDiag, double* bDiag) const {
  const int n = size();
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n), y(n);
  for (int i = 0; i < n; ++i) {
    e[i] = 1.0;
    applyA(e.data(), y.data());
    aDiag[i] = y[i];
    applyB(e.data(), y.data());
    bDiag[i] = y[i];
    e[i] = 0.0;
  }
}

// ---------------------------------------------------------------------------------------------------
DenseShiftInvert::DenseShiftInvert(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) : A_(A), B_(B) {
  checkPencil(A, B, "DenseShiftInvert");
}

bool DenseShiftInvert::factorize(double sigma) {
  factored_ = false;
  if (!std::isfinite(sigma)) return false;
  lu_.compute(A_ - sigma * B_);
  const Eigen::VectorXd piv = lu_.matrixLU().diagonal();
  for (Eigen::Index i = 0; i < piv.size(); ++i)
    if (!std::isfinite(piv[i]) || piv[i] == 0.0) return false;
  const double rc = lu_.rcond();
  if (!(rc > std::numeric_limits<double>::epsilon())) return false;
  factored_ = true;
  return true;
}

void DenseShiftInvert::solve(const double* in, double* out) const {
  if (!factored_) throw std::logic_error("DenseShiftInvert::solve before a successful factorize");
  const Eigen::Index n = A_.rows();
  Eigen::Map<Eigen::VectorXd>(out, n) = lu_.solve(Eigen::Map<const Eigen::VectorXd>(in, n));
}

void DenseShiftInvert::applyB(const double* in, double* out) const {
  const Eigen::Index n = A_.rows();
  Eigen::Map<Eigen::VectorXd>(out, n).noalias() = B_ * Eigen::Map<const Eigen::VectorXd>(in, n);
}

void DenseShiftInvert::applyA(const double* in, double* out) const {
  const Eigen::Index n = A_.rows();
  Eigen::Map<Eigen::VectorXd>(out, n).noalias() = A_ * Eigen::Map<const Eigen::VectorXd>(in, n);
}

void DenseShiftInvert::diagonals(double* aDiag, double* bDiag) const {
  const Eigen::Index n = A_.rows();
  Eigen::Map<Eigen::VectorXd>(aDiag, n) = A_.diagonal();
  Eigen::Map<Eigen::VectorXd>(bDiag, n) = B_.diagonal();
}

// ---------------------------------------------------------------------------------------------------
struct SparseShiftInvert::Impl {
  Eigen::SparseMatrix<double> A, B, C;  // C = A - sigma B; UmfPackLU keeps a reference to it
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  bool factored = false;
};

SparseShiftInvert::SparseShiftInvert(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B)
    : impl_(std::make_unique<Impl>()) {
  if (A.rows() != A.cols() || B.rows() != B.cols() || A.rows() != B.rows())
    throw std::invalid_argument("SparseShiftInvert: A and B must be square and of equal size");
  impl_->A = A;
  impl_->B = B;
  impl_->A.makeCompressed();
  impl_->B.makeCompressed();
}

SparseShiftInvert::~SparseShiftInvert() = default;

int SparseShiftInvert::size() const { return static_cast<int>(impl_->A.rows()); }

bool SparseShiftInvert::factorize(double sigma) {
  Impl& m = *impl_;
  m.factored = false;
  if (!std::isfinite(sigma)) return false;
  m.C = m.A - sigma * m.B;
  m.C.makeCompressed();
  m.lu.compute(m.C);
  if (m.lu.info() != Eigen::Success) return false;  // includes UMFPACK_WARNING_singular_matrix
  // a numerically singular (but not exactly) matrix shows up as a non-finite solution
  const Eigen::VectorXd probe = Eigen::VectorXd::Ones(m.A.rows());
  const Eigen::VectorXd x = m.lu.solve(probe);
  if (m.lu.info() != Eigen::Success || !x.allFinite()) return false;
  m.factored = true;
  return true;
}

void SparseShiftInvert::solve(const double* in, double* out) const {
  if (!impl_->factored) throw std::logic_error("SparseShiftInvert::solve before a successful factorize");
  const Eigen::Index n = impl_->A.rows();
  if (in == out) {
    const Eigen::VectorXd tmp = Eigen::Map<const Eigen::VectorXd>(in, n);
    Eigen::Map<Eigen::VectorXd>(out, n) = impl_->lu.solve(tmp);
  } else {
    Eigen::Map<Eigen::VectorXd>(out, n) = impl_->lu.solve(Eigen::Map<const Eigen::VectorXd>(in, n));
  }
}

void SparseShiftInvert::applyB(const double* in, double* out) const {
  const Eigen::Index n = impl_->A.rows();
  Eigen::Map<Eigen::VectorXd>(out, n).noalias() = impl_->B * Eigen::Map<const Eigen::VectorXd>(in, n);
}

void SparseShiftInvert::applyA(const double* in, double* out) const {
  const Eigen::Index n = impl_->A.rows();
  Eigen::Map<Eigen::VectorXd>(out, n).noalias() = impl_->A * Eigen::Map<const Eigen::VectorXd>(in, n);
}

void SparseShiftInvert::diagonals(double* aDiag, double* bDiag) const {
  const Eigen::Index n = impl_->A.rows();
  Eigen::Map<Eigen::VectorXd>(aDiag, n) = impl_->A.diagonal();
  Eigen::Map<Eigen::VectorXd>(bDiag, n) = impl_->B.diagonal();
}

// ---------------------------------------------------------------------------------------------------
struct ConstrainedShiftInvert::Impl {
  Eigen::SparseMatrix<double> A, B, C, W;  // W = [A - sigma B, C^T; C, 0]
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> cct;  // C C^T, for the residual projection
  bool factored = false;
  mutable Eigen::VectorXd rhs, sol, mu;
};

ConstrainedShiftInvert::ConstrainedShiftInvert(const Eigen::SparseMatrix<double>& A,
                                               const Eigen::SparseMatrix<double>& B,
                                               const Eigen::SparseMatrix<double>& C)
    : impl_(std::make_unique<Impl>()) {
  if (A.rows() != A.cols() || B.rows() != B.cols() || A.rows() != B.rows() || C.cols() != A.rows())
    throw std::invalid_argument("ConstrainedShiftInvert: A, B must be n x n and C r x n");
  impl_->A = A;
  impl_->B = B;
  impl_->C = C;
  impl_->A.makeCompressed();
  impl_->B.makeCompressed();
  impl_->C.makeCompressed();
  if (C.rows() > 0) {
    const Eigen::SparseMatrix<double> cct = impl_->C * impl_->C.transpose();
    impl_->cct.compute(cct);
    if (impl_->cct.info() != Eigen::Success)
      throw std::invalid_argument("ConstrainedShiftInvert: C C^T is not positive definite (C rank deficient)");
  }
}

ConstrainedShiftInvert::~ConstrainedShiftInvert() = default;

int ConstrainedShiftInvert::size() const { return static_cast<int>(impl_->A.rows()); }

bool ConstrainedShiftInvert::factorize(double sigma) {
  Impl& m = *impl_;
  m.factored = false;
  if (!std::isfinite(sigma)) return false;
  const Eigen::Index n = m.A.rows(), r = m.C.rows();
  const Eigen::SparseMatrix<double> S = m.A - sigma * m.B;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(S.nonZeros() + 2 * m.C.nonZeros()));
  for (Eigen::Index c = 0; c < S.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(S, c); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  for (Eigen::Index c = 0; c < m.C.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(m.C, c); it; ++it) {
      t.emplace_back(n + it.row(), it.col(), it.value());
      t.emplace_back(it.col(), n + it.row(), it.value());
    }
  m.W.resize(n + r, n + r);
  m.W.setFromTriplets(t.begin(), t.end());
  m.W.makeCompressed();
  m.lu.compute(m.W);
  if (m.lu.info() != Eigen::Success) return false;
  m.rhs = Eigen::VectorXd::Ones(n + r);
  m.sol = m.lu.solve(m.rhs);
  if (m.lu.info() != Eigen::Success || !m.sol.allFinite()) return false;
  m.factored = true;
  return true;
}

void ConstrainedShiftInvert::solve(const double* in, double* out) const {
  const Impl& m = *impl_;
  if (!m.factored) throw std::logic_error("ConstrainedShiftInvert::solve before a successful factorize");
  const Eigen::Index n = m.A.rows();
  m.rhs.setZero(m.W.rows());
  m.rhs.head(n) = Eigen::Map<const Eigen::VectorXd>(in, n);
  m.sol = m.lu.solve(m.rhs);
  Eigen::Map<Eigen::VectorXd>(out, n) = m.sol.head(n);
}

void ConstrainedShiftInvert::applyB(const double* in, double* out) const {
  const Eigen::Index n = impl_->A.rows();
  Eigen::Map<Eigen::VectorXd>(out, n).noalias() = impl_->B * Eigen::Map<const Eigen::VectorXd>(in, n);
}

void ConstrainedShiftInvert::applyA(const double* in, double* out) const {
  const Eigen::Index n = impl_->A.rows();
  Eigen::Map<Eigen::VectorXd>(out, n).noalias() = impl_->A * Eigen::Map<const Eigen::VectorXd>(in, n);
}

void ConstrainedShiftInvert::diagonals(double* aDiag, double* bDiag) const {
  const Eigen::Index n = impl_->A.rows();
  Eigen::Map<Eigen::VectorXd>(aDiag, n) = impl_->A.diagonal();
  Eigen::Map<Eigen::VectorXd>(bDiag, n) = impl_->B.diagonal();
}

void ConstrainedShiftInvert::projectResidual(double* v) const {
  const Impl& m = *impl_;
  if (m.C.rows() == 0) return;
  Eigen::Map<Eigen::VectorXd> x(v, m.A.rows());
  m.mu = m.cct.solve(m.C * x);
  x -= m.C.transpose() * m.mu;
}

// ---------------------------------------------------------------------------------------------------
namespace {

// The lowest shift: inverse iteration at sigma, Rayleigh quotient rho, sigma <- -0.1 |rho| while it
// moves down; op stays factorised at the shift returned. `s`: the pencil's diagonal scale.
double lowestShift(ShiftInvertOperator& op, double sigma, double s) {
  const int n = op.size();
  // Inverse iteration at sigma, Rayleigh quotient rho, sigma <- -0.1 |rho| while it moves down.
  Eigen::VectorXd x(n), t(n), y(n), ax(n);
  fillStartVector(x.data(), n);
  for (int round = 0; round < 12; ++round) {
    for (int it = 0; it < 3; ++it) {
      op.applyB(x.data(), t.data());
      op.solve(t.data(), y.data());
      const double nrm = y.norm();
      if (!(nrm > 0.0) || !std::isfinite(nrm)) break;
      x = y / nrm;
    }
    op.applyA(x.data(), ax.data());
    op.applyB(x.data(), t.data());
    const double bx = x.dot(t);
    if (!(bx > 0.0)) break;
    const double rho = std::abs(x.dot(ax) / bx);
    const double next = -0.1 * rho;
    if (!(rho > 1e-12 * s) || !std::isfinite(rho) || next <= 0.5 * sigma) break;  // no real progress
    if (!op.factorize(next)) {
      op.factorize(sigma);
      break;
    }
    sigma = next;
  }
  return sigma;
}

}  // namespace

EigenResult solveArpack(ShiftInvertOperator& op, const EigenOptions& opt) {
  const int n = op.size();
  checkSizes(n, opt, /*allowAll=*/false, "solveArpack");
  const int nev = opt.nev;

  EigenResult r;
  r.method = "arpack-shift-invert";
  r.lambda.resize(0);
  r.vectors.resize(n, 0);
  r.omega.resize(0);

  Eigen::VectorXd ad(n), bd(n);
  op.diagonals(ad.data(), bd.data());
  const double ds = diagonalScale(ad, bd);  // 0 if no usable diagonal
  const double s = ds > 0.0 ? ds : 1.0;
  r.scale = ds;

  // factorise A - sigma B, moving the shift down if singular
  const double sigma0 = opt.shift ? *opt.shift : -1e-3 * s;
  double sigma = sigma0;
  bool ok = op.factorize(sigma);
  for (int k = 0; !ok && k < 4; ++k) {
    sigma = sigma0 - 1e-6 * s * std::pow(10.0, k);
    ok = op.factorize(sigma);
  }
  r.shift = sigma;
  if (!ok) {
    std::ostringstream os;
    os << "A - sigma B is singular at sigma = " << sigma0 << " and at 4 shifts below it (down to " << sigma << ")";
    r.status = EigenStatus::Singular;
    r.message = os.str();
    return r;
  }
  if (opt.lowestShift && !opt.shift) {
    sigma = lowestShift(op, sigma, s);
    r.shift = sigma;
  }
  std::string note;
  if (sigma != sigma0 && !opt.lowestShift) {
    std::ostringstream os;
    os << "A - sigma B singular at sigma = " << sigma0 << "; shift moved to " << sigma << ". ";
    note = os.str();
  }

  const int ncv = std::min(n, std::max(2 * nev + 1, 20));
  const int lworkl = ncv * (ncv + 8);
  std::vector<double> resid(static_cast<std::size_t>(n)), v(static_cast<std::size_t>(n) * ncv),
      workd(3 * static_cast<std::size_t>(n)), workl(static_cast<std::size_t>(lworkl)), tmp(static_cast<std::size_t>(n));
  fillStartVector(resid.data(), n);
  a_int iparam[11] = {0};
  a_int ipntr[14] = {0};
  iparam[0] = 1;                  // exact shifts
  iparam[2] = opt.maxIterations;  // max implicit restarts
  iparam[3] = 1;                  // block size
  iparam[6] = 3;                  // mode 3: shift-invert, OP = (A - sigma B)^-1 B
  a_int ido = 0, info = 1;        // info = 1: use resid as start vector

  std::lock_guard<std::mutex> lock(arpackMutex());
  for (;;) {
    arpack::saupd(ido, arpack::bmat::generalized, n, arpack::which::largest_magnitude, nev, opt.tolerance, resid.data(),
                  ncv, v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info);
    double* x = workd.data() + ipntr[0] - 1;
    double* y = workd.data() + ipntr[1] - 1;
    if (ido == -1) {  // y = OP x = (A - sigma B)^-1 B x
      op.applyB(x, tmp.data());
      op.solve(tmp.data(), y);
    } else if (ido == 1) {  // y = (A - sigma B)^-1 z, z = B x supplied
      const double* z = workd.data() + ipntr[2] - 1;
      op.solve(z, y);
    } else if (ido == 2) {  // y = B x
      op.applyB(x, y);
    } else {
      break;  // 99: done (or error in info)
    }
  }
  r.iterations = iparam[2];

  if (info < 0) {
    std::ostringstream os;
    os << note << "ARPACK dsaupd info = " << info << ": " << arpackAupdMessage(info);
    r.status = EigenStatus::NotConverged;
    r.message = os.str();
    r.converged = 0;
    return r;
  }
  const int nconv = std::min<int>(iparam[4], nev);
  r.converged = iparam[4];
  if (nconv > 0) {
    std::vector<a_int> select(static_cast<std::size_t>(ncv), 1);
    std::vector<double> d(static_cast<std::size_t>(nev)), z(static_cast<std::size_t>(n) * nev);
    a_int info2 = 0;
    arpack::seupd(1, arpack::howmny::ritz_vectors, select.data(), d.data(), z.data(), n, sigma,
                  arpack::bmat::generalized, n, arpack::which::largest_magnitude, nev, opt.tolerance, resid.data(), ncv,
                  v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info2);
    if (info2 != 0) {
      std::ostringstream os;
      os << note << "ARPACK dseupd info = " << info2;
      r.status = EigenStatus::NotConverged;
      r.message = os.str();
      return r;
    }
    const int got = std::min<int>(iparam[4], nconv);
    r.lambda = Eigen::Map<const Eigen::VectorXd>(d.data(), got);
    r.vectors = Eigen::Map<const Eigen::MatrixXd>(z.data(), n, got);
  }

  finalize(
      r,
      [&](const double* in, double* out) {
        op.applyA(in, out);
        op.projectResidual(out);
      },
      [&](const double* in, double* out) {
        op.applyB(in, out);
        op.projectResidual(out);
      },
      ds);

  if (info == 0 && r.lambda.size() >= nev && r.lambda.allFinite()) {
    r.status = EigenStatus::Converged;
    r.message = note;
    if (!r.message.empty() && r.message.back() == ' ') r.message.pop_back();
  } else {
    std::ostringstream os;
    os << note << "ARPACK: " << r.lambda.size() << " of " << nev << " eigenvalues converged";
    if (info != 0) os << " (dsaupd info = " << info << ": " << arpackAupdMessage(info) << ")";
    os << " after " << r.iterations << " iterations";
    if (!r.lambda.allFinite()) os << "; non-finite eigenvalues";
    r.status = EigenStatus::NotConverged;
    r.message = os.str();
  }
  return r;
}

// ---------------------------------------------------------------------------------------------------
EigenResult solveDense(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const EigenOptions& opt) {
  checkPencil(A, B, "solveDense");
  const Eigen::Index n = A.rows();
  checkSizes(n, opt, /*allowAll=*/true, "solveDense");
  EigenResult r;
  r.method = "dense";
  r.vectors.resize(n, 0);
  const double ds = diagonalScale(A.diagonal(), B.diagonal());
  r.scale = ds;

  Eigen::LLT<Eigen::MatrixXd> llt(B);
  if (llt.info() != Eigen::Success) {
    r.status = EigenStatus::Singular;
    r.message = "solveDense: B is not positive definite (Cholesky failed)";
    return r;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(A, B, Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
  if (es.info() != Eigen::Success) {
    r.status = EigenStatus::NotConverged;
    r.message = "solveDense: GeneralizedSelfAdjointEigenSolver did not converge";
    return r;
  }
  r.lambda = es.eigenvalues().head(opt.nev);
  r.vectors = es.eigenvectors().leftCols(opt.nev);
  r.converged = opt.nev;
  finalize(
      r,
      [&](const double* in, double* out) {
        Eigen::Map<Eigen::VectorXd>(out, n).noalias() = A * Eigen::Map<const Eigen::VectorXd>(in, n);
      },
      [&](const double* in, double* out) {
        Eigen::Map<Eigen::VectorXd>(out, n).noalias() = B * Eigen::Map<const Eigen::VectorXd>(in, n);
      },
      ds);
  r.status = EigenStatus::Converged;
  return r;
}

EigenResult solveLowest(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const EigenOptions& opt) {
  checkPencil(A, B, "solveLowest");
  const Eigen::Index n = A.rows();
  checkSizes(n, opt, /*allowAll=*/false, "solveLowest");
  if (n < std::max<Eigen::Index>(opt.denseBelow, 2 * opt.nev + 2)) return solveDense(A, B, opt);
  DenseShiftInvert op(A, B);
  return solveArpack(op, opt);
}

// ---------------------------------------------------------------------------------------------------
Eigen::MatrixXd modalAssurance(const Eigen::MatrixXd& U, const Eigen::MatrixXd& V, const Eigen::MatrixXd* W) {
  if (U.rows() != V.rows()) throw std::invalid_argument("modalAssurance: U and V must have the same number of rows");
  if (W && (W->rows() != U.rows() || W->cols() != U.rows()))
    throw std::invalid_argument("modalAssurance: W must be square with U.rows() rows");
  const Eigen::MatrixXd WV = W ? Eigen::MatrixXd((*W) * V) : V;
  const Eigen::MatrixXd WU = W ? Eigen::MatrixXd((*W) * U) : U;
  const Eigen::MatrixXd cross = U.transpose() * WV;
  Eigen::MatrixXd mac(U.cols(), V.cols());
  for (Eigen::Index i = 0; i < U.cols(); ++i) {
    const double du = U.col(i).dot(WU.col(i));
    for (Eigen::Index j = 0; j < V.cols(); ++j) {
      const double dv = V.col(j).dot(WV.col(j));
      const double den = du * dv;
      mac(i, j) = den != 0.0 ? cross(i, j) * cross(i, j) / den : 0.0;
    }
  }
  return mac;
}

std::vector<int> trackModes(const Eigen::MatrixXd& previous, const Eigen::MatrixXd& current, const Eigen::MatrixXd* W) {
  const Eigen::MatrixXd mac = modalAssurance(previous, current, W);
  const Eigen::Index np = mac.rows(), nc = mac.cols();
  std::vector<int> p(static_cast<std::size_t>(nc), -1);
  std::vector<bool> rowUsed(static_cast<std::size_t>(np), false), colUsed(static_cast<std::size_t>(nc), false);
  const Eigen::Index pairs = std::min(np, nc);
  for (Eigen::Index step = 0; step < pairs; ++step) {
    double best = -1.0;
    Eigen::Index bi = -1, bj = -1;
    for (Eigen::Index i = 0; i < np; ++i) {
      if (rowUsed[static_cast<std::size_t>(i)]) continue;
      for (Eigen::Index j = 0; j < nc; ++j) {
        if (colUsed[static_cast<std::size_t>(j)]) continue;
        const double m = std::isfinite(mac(i, j)) ? mac(i, j) : 0.0;
        if (m > best) {
          best = m;
          bi = i;
          bj = j;
        }
      }
    }
    rowUsed[static_cast<std::size_t>(bi)] = true;
    colUsed[static_cast<std::size_t>(bj)] = true;
    p[static_cast<std::size_t>(bj)] = static_cast<int>(bi);
  }
  return p;
}

}  // namespace flexmb::solvers
