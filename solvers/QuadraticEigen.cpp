#include "solvers/QuadraticEigen.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace flexmb::solvers {

QuadraticModes quadraticModes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C, const Eigen::MatrixXd& K, int nev) {
  QuadraticModes out;
  const Eigen::Index n = M.rows();
  if (M.cols() != n || C.rows() != n || C.cols() != n || K.rows() != n || K.cols() != n || nev < 1) {
    out.message = "quadraticModes: inconsistent sizes or nev < 1";
    return out;
  }
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(M);
  if (!(std::abs(lu.determinant()) > 0.0) || lu.rcond() < 1e-14) {
    out.message = "mass matrix singular";
    return out;
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -lu.solve(K);
  A.bottomRightCorner(n, n) = -lu.solve(C);
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  if (es.info() != Eigen::Success) {
    out.message = "eigensolver did not converge";
    return out;
  }
  const Eigen::VectorXcd s = es.eigenvalues();
  double scale = 0.0;
  for (Eigen::Index i = 0; i < s.size(); ++i) scale = std::max(scale, std::abs(s[i]));
  const double tiny = 1e-9 * std::max(scale, 1e-300);
  std::vector<double> w, z;
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const double re = s[i].real(), im = s[i].imag(), mag = std::abs(s[i]);
    if (im > tiny) {  // one of each conjugate pair
      w.push_back(mag);
      z.push_back(-re / mag);
    } else if (std::abs(im) <= tiny) {
      if (mag <= tiny)
        w.push_back(0.0), z.push_back(0.0);
      else if (re > 0)
        w.push_back(-re), z.push_back(0.0);
      else
        w.push_back(-re), z.push_back(1.0);
    }
  }
  std::vector<size_t> order(w.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return std::abs(w[a]) < std::abs(w[b]); });
  const int k = std::min<int>(nev, static_cast<int>(order.size()));
  out.omega.resize(k);
  out.damping.resize(k);
  for (int i = 0; i < k; ++i) out.omega[i] = w[order[i]], out.damping[i] = z[order[i]];
  out.ok = true;
  return out;
}

}  // namespace flexmb::solvers
