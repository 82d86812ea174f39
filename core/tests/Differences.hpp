#pragma once
// Central differences and relative errors: the references every analytic derivative in the core
// tests is compared with.
#include <Eigen/Core>
#include <algorithm>

namespace flexmb::core::test {

// Central differences (step h) of a vector function fn(x) at `at`, column by column:
// column j = (fn(at + h e_j) - fn(at - h e_j)) / 2h.
template <class Fn>
Eigen::MatrixXd centralDifferences(Fn&& fn, const Eigen::VectorXd& at, double h) {
  Eigen::MatrixXd J;
  for (int j = 0; j < at.size(); ++j) {
    Eigen::VectorXd p = at, m = at;
    p[j] += h;
    m[j] -= h;
    const Eigen::VectorXd fp = fn(p), fm = fn(m);
    if (j == 0) J.resize(fp.size(), at.size());
    J.col(j) = (fp - fm) / (2 * h);
  }
  return J;
}

// |a - ref| / max(|ref|, floor) in the Frobenius norm.
inline double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& ref, double floor) {
  return (a - ref).norm() / std::max(ref.norm(), floor);
}

// Largest entry of |a - ref| over the largest entry of either (not below `floor`); 0 for two empty
// arrays.
template <class A, class B>
double maxRelativeError(const A& a, const B& ref, double floor = 1e-9) {
  if (a.size() == 0 && ref.size() == 0) return 0.0;
  const double scale = std::max({a.cwiseAbs().maxCoeff(), ref.cwiseAbs().maxCoeff(), floor});
  return (a - ref).cwiseAbs().maxCoeff() / scale;
}

}  // namespace flexmb::core::test
