#include "solvers/ChebyshevBasis.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace flexmb::solvers {

namespace {

void checkBox(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  if (lo.size() != hi.size() || lo.size() == 0) throw std::invalid_argument("ChebyshevBasis: box sizes differ");
  for (int i = 0; i < lo.size(); ++i)
    if (!(lo[i] < hi[i]) || !std::isfinite(lo[i]) || !std::isfinite(hi[i]))
      throw std::invalid_argument("ChebyshevBasis: empty or infinite box in variable " + std::to_string(i + 1));
}

// Every term's value and (grad != null) gradient: prefix products left_i = prod_{j<i} T_j; the
// gradient's entry j is left_j * dT_j * right_j. off: each term's M offsets into the tables.
template <int M>
void termsKernel(const int* off, int P, const double* T, const double* dT, double* phi, double* grad) {
  for (int p = 0; p < P; ++p, off += M) {
    double left[M + 1];
    left[0] = 1.0;
    for (int i = 0; i < M; ++i) left[i + 1] = left[i] * T[off[i]];
    phi[p] = left[M];
    if (!grad) continue;
    double right = 1.0;
    double* g = grad + static_cast<long>(p) * M;
    for (int i = M - 1; i >= 0; --i) {
      g[i] = left[i] * dT[off[i]] * right;
      right *= T[off[i]];
    }
  }
}

}  // namespace

ChebyshevBasis::ChebyshevBasis(Eigen::VectorXd lo, Eigen::VectorXd hi, const std::vector<int>& degrees)
    : lo_(std::move(lo)), hi_(std::move(hi)) {
  checkBox(lo_, hi_);
  const int m = variables();
  if (static_cast<int>(degrees.size()) != m) throw std::invalid_argument("ChebyshevBasis: one degree per variable");
  std::vector<std::vector<int>> terms;
  std::vector<int> k(m, 0);
  // Depth-first over k with sum k_i / p_i <= 1 (a variable of degree 0 stays at 0).
  std::function<void(int, double)> add = [&](int i, double used) {
    if (i == m) {
      terms.push_back(k);
      return;
    }
    for (int d = 0; d <= degrees[i]; ++d) {
      const double share = degrees[i] > 0 ? static_cast<double>(d) / degrees[i] : 0.0;
      if (used + share > 1.0 + 1e-12) break;
      k[i] = d;
      add(i + 1, used + share);
    }
    k[i] = 0;
  };
  add(0, 0.0);
  exponents_.resize(static_cast<int>(terms.size()), m);
  for (size_t p = 0; p < terms.size(); ++p)
    for (int i = 0; i < m; ++i) exponents_(static_cast<int>(p), i) = terms[p][i];
  setOffsets();
}

ChebyshevBasis::ChebyshevBasis(Eigen::VectorXd lo, Eigen::VectorXd hi, Eigen::MatrixXi exponents)
    : lo_(std::move(lo)), hi_(std::move(hi)), exponents_(std::move(exponents)) {
  checkBox(lo_, hi_);
  if (exponents_.cols() != variables() || exponents_.rows() == 0 || exponents_.minCoeff() < 0)
    throw std::invalid_argument("ChebyshevBasis: exponents do not fit the box");
  setOffsets();
}

void ChebyshevBasis::setOffsets() {
  const int m = variables();
  maxDegree_ = exponents_.size() ? exponents_.maxCoeff() : 0;
  degreeOf_.assign(static_cast<size_t>(m), 0);
  for (int i = 0; i < m; ++i) degreeOf_[static_cast<size_t>(i)] = exponents_.col(i).maxCoeff();
  offsets_.assign(exponents_.size(), 0);
  for (int p = 0; p < size(); ++p)
    for (int i = 0; i < m; ++i) offsets_[p * m + i] = exponents_(p, i) + i * (maxDegree_ + 1);
}

int ChebyshevBasis::outside(const Eigen::Ref<const Eigen::VectorXd>& eta, double slack) const {
  for (int i = 0; i < variables(); ++i) {
    const double w = slack * (hi_[i] - lo_[i]);
    if (!(eta[i] >= lo_[i] - w && eta[i] <= hi_[i] + w)) return i;
  }
  return -1;
}

void ChebyshevBasis::tables(const Eigen::Ref<const Eigen::VectorXd>& eta, Scratch& s) const {
  const int m = variables(), n = maxDegree_ + 1;
  if (s.T.rows() != n || s.T.cols() != m) {
    s.T.resize(n, m);  // column i: T_0..T_p of variable i (contiguous)
    s.dT.resize(n, m);
    s.left.resize(m + 1);
  }
  // T_{k+1} = 2 xi T_k - T_{k-1};  T'_{k+1} = 2 T_k + 2 xi T'_k - T'_{k-1} (d/d xi), times d xi/d eta.
  for (int i = 0; i < m; ++i) {
    const double scale = 2.0 / (hi_[i] - lo_[i]);
    const double xi = (2.0 * eta[i] - lo_[i] - hi_[i]) / (hi_[i] - lo_[i]);
    double* T = &s.T(0, i);
    double* dT = &s.dT(0, i);
    const int used = degreeOf_[static_cast<size_t>(i)] + 1;  // no term reads beyond its own highest degree
    T[0] = 1.0;
    dT[0] = 0.0;
    if (used > 1) {
      T[1] = xi;
      dT[1] = scale;
    }
    for (int k = 1; k + 1 < used; ++k) {
      T[k + 1] = 2.0 * xi * T[k] - T[k - 1];
      dT[k + 1] = 2.0 * scale * T[k] + 2.0 * xi * dT[k] - dT[k - 1];
    }
  }
}

void ChebyshevBasis::evaluate(const Eigen::Ref<const Eigen::VectorXd>& eta, Scratch& s, Eigen::Ref<Eigen::VectorXd> phi,
                              Eigen::MatrixXd* gradT, int count) const {
  const int m = variables(), P = count < 0 ? size() : std::min(count, size());
  tables(eta, s);
  double* grad = gradT ? gradT->data() : nullptr;
  switch (m) {  // fixed-size loops for the usual reduced sizes
    case 1:
      return termsKernel<1>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 2:
      return termsKernel<2>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 3:
      return termsKernel<3>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 4:
      return termsKernel<4>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 5:
      return termsKernel<5>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 6:
      return termsKernel<6>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 7:
      return termsKernel<7>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    case 8:
      return termsKernel<8>(offsets_.data(), P, s.T.data(), s.dT.data(), phi.data(), grad);
    default:
      break;
  }
  const int* off = offsets_.data();
  double* left = s.left.data();
  for (int p = 0; p < P; ++p, off += m) {
    // Prefix products left_i = prod_{j<i} T_j; the gradient's entry j is left_j * dT_j * right_j.
    left[0] = 1.0;
    for (int i = 0; i < m; ++i) left[i + 1] = left[i] * s.T.data()[off[i]];
    phi[p] = left[m];
    if (!grad) continue;
    double right = 1.0;
    double* g = grad + static_cast<long>(p) * m;
    for (int i = m - 1; i >= 0; --i) {
      g[i] = left[i] * s.dT.data()[off[i]] * right;
      right *= s.T.data()[off[i]];
    }
  }
}

void ChebyshevBasis::pathDerivatives(const Eigen::Ref<const Eigen::VectorXd>& eta,
                                     const Eigen::Ref<const Eigen::VectorXd>& v,
                                     const Eigen::Ref<const Eigen::VectorXd>& a, Scratch& s,
                                     Eigen::Ref<Eigen::VectorXd> phi, Eigen::Ref<Eigen::VectorXd> rate,
                                     Eigen::Ref<Eigen::VectorXd> acceleration, int count) const {
  const int m = variables(), P = count < 0 ? size() : std::min(count, size());
  tables(eta, s);
  if (s.d2T.rows() != s.T.rows() || s.d2T.cols() != m) s.d2T.resize(s.T.rows(), m);
  // T''_{k+1} = 4 T'_k + 2 xi T''_k - T''_{k-1} (d/d xi), times (d xi / d eta)^2.
  for (int i = 0; i < m; ++i) {
    const double scale = 2.0 / (hi_[i] - lo_[i]);
    const double xi = (2.0 * eta[i] - lo_[i] - hi_[i]) / (hi_[i] - lo_[i]);
    const double* dT = &s.dT(0, i);
    double* d2T = &s.d2T(0, i);
    const int used = degreeOf_[static_cast<size_t>(i)] + 1;
    d2T[0] = 0.0;
    if (used > 1) d2T[1] = 0.0;
    for (int k = 1; k + 1 < used; ++k) d2T[k + 1] = 4.0 * scale * dT[k] + 2.0 * xi * d2T[k] - d2T[k - 1];
  }
  // Each factor along the path: f + t f' v_i + t^2/2 (f'' v_i^2 + f' a_i); products truncated at t^2.
  const int* off = offsets_.data();
  for (int p = 0; p < P; ++p, off += m) {
    double c0 = 1.0, c1 = 0.0, c2 = 0.0;
    for (int i = 0; i < m; ++i) {
      const int o = off[i];
      const double f0 = s.T.data()[o], f1 = s.dT.data()[o] * v[i],
                   f2 = 0.5 * (s.d2T.data()[o] * v[i] * v[i] + s.dT.data()[o] * a[i]);
      c2 = c0 * f2 + c1 * f1 + c2 * f0;
      c1 = c0 * f1 + c1 * f0;
      c0 *= f0;
    }
    phi[p] = c0;
    rate[p] = c1;
    acceleration[p] = 2.0 * c2;
  }
}

Eigen::VectorXd ChebyshevBasis::arcsinePoint(const Eigen::Ref<const Eigen::VectorXd>& u) const {
  Eigen::VectorXd eta(variables());
  for (int i = 0; i < variables(); ++i)
    eta[i] = 0.5 * (lo_[i] + hi_[i]) - 0.5 * (hi_[i] - lo_[i]) * std::cos(M_PI * u[i]);
  return eta;
}

Eigen::VectorXd haltonPoint(long i, int m) {
  static const int primes[] = {2,   3,   5,   7,   11,  13,  17,  19,  23,  29,  31,  37,  41,  43,  47,  53,  59,
                               61,  67,  71,  73,  79,  83,  89,  97,  101, 103, 107, 109, 113, 127, 131, 137, 139,
                               149, 151, 157, 163, 167, 173, 179, 181, 191, 193, 197, 199, 211, 223, 227, 229};
  constexpr int kPrimes = sizeof(primes) / sizeof(primes[0]);
  if (m > kPrimes) throw std::invalid_argument("haltonPoint: at most 50 dimensions");
  Eigen::VectorXd u(m);
  for (int d = 0; d < m; ++d) {
    double f = 1.0, r = 0.0;
    for (long k = i; k > 0; k /= primes[d]) {
      f /= primes[d];
      r += f * static_cast<double>(k % primes[d]);
    }
    u[d] = r;
  }
  return u;
}

Eigen::MatrixXd fitChebyshev(const ChebyshevBasis& basis, const Eigen::MatrixXd& points, const Eigen::MatrixXd& values,
                             double valuesWeight, const Eigen::MatrixXd& gradients, double gradientWeight, int count) {
  const int n = static_cast<int>(points.rows()), m = basis.variables();
  const int P = count < 0 ? basis.size() : std::min(count, basis.size());
  const bool useValues = valuesWeight > 0.0, useGradients = gradientWeight > 0.0;
  const int k = static_cast<int>(useValues ? values.cols() : gradients.cols());
  if (points.cols() != m || (useValues && values.rows() != n) ||
      (useGradients && (gradients.rows() != n * m || gradients.cols() != k)) || (!useValues && !useGradients))
    throw std::invalid_argument("fitChebyshev: sizes do not match");
  // Without values the constant term has no equation: it is left out (coefficient 0).
  std::vector<int> cols;
  for (int p = 0; p < P; ++p)
    if (useValues || basis.exponents().row(p).sum() > 0) cols.push_back(p);
  const int rows = (useValues ? n : 0) + (useGradients ? n * m : 0);
  Eigen::MatrixXd A(rows, static_cast<int>(cols.size())), b(rows, k);
  ChebyshevBasis::Scratch s;
  Eigen::VectorXd phi(basis.size());
  Eigen::MatrixXd grad(m, basis.size());
  int r = 0;
  for (int i = 0; i < n; ++i) {
    basis.evaluate(points.row(i).transpose(), s, phi, &grad, P);
    if (useValues) {
      for (size_t c = 0; c < cols.size(); ++c) A(r, static_cast<int>(c)) = valuesWeight * phi[cols[c]];
      b.row(r++) = valuesWeight * values.row(i);
    }
    if (useGradients)
      for (int j = 0; j < m; ++j) {
        for (size_t c = 0; c < cols.size(); ++c) A(r, static_cast<int>(c)) = gradientWeight * grad(j, cols[c]);
        b.row(r++) = gradientWeight * gradients.row(i * m + j);
      }
  }
  const Eigen::MatrixXd x = A.colPivHouseholderQr().solve(b);
  Eigen::MatrixXd coef = Eigen::MatrixXd::Zero(P, k);
  for (size_t c = 0; c < cols.size(); ++c) coef.row(cols[c]) = x.row(static_cast<int>(c));
  return coef;
}

}  // namespace flexmb::solvers
