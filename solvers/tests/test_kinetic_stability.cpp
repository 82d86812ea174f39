// The kinetic stability criterion against closed forms: Ziegler's double pendulum under a follower
// force (flutter at P = (7/2 - sqrt 2) k/l), a split double eigenvalue, divergence; ARPACK against
// the dense eigensolver on a chain with a circulatory load.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "solvers/KineticStability.hpp"

using namespace flexmb::solvers;

namespace {

// Ziegler's pendulum (two rigid bars l, joint springs k, masses 2m and m, a follower force P at the
// tip), linearised, with m = k = l = 1: M = [3 1; 1 1], A = [2 - P, P - 1; -1, 1].
KineticStability ziegler(double P) {
  Eigen::Matrix2d M, A;
  M << 3, 1, 1, 1;
  A << 2 - P, P - 1, -1, 1;
  return kineticStability(A, M, 2);
}

// Two identical chains of n unit masses between unit springs (fixed at the start), x and y, with a
// circulatory coupling p between x_i and y_i (A = [S, pI; -pI, S], as an isotropic rod under a dead
// torque) and a diagonal offset d: lambda = eig(S) + d +- i p exactly (S and the coupling commute).
void twinChains(int n, double p, double d, Eigen::MatrixXd& A, Eigen::MatrixXd& M, Eigen::VectorXd& s) {
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    S(i, i) = (i + 1 < n ? 2.0 : 1.0) + d;
    if (i + 1 < n) S(i, i + 1) = S(i + 1, i) = -1.0;
  }
  A.setZero(2 * n, 2 * n);
  A.topLeftCorner(n, n) = S;
  A.bottomRightCorner(n, n) = S;
  A.topRightCorner(n, n) = p * Eigen::MatrixXd::Identity(n, n);
  A.bottomLeftCorner(n, n) = -p * Eigen::MatrixXd::Identity(n, n);
  M = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  s = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S).eigenvalues();
}

}  // namespace

TEST(KineticStability, ZieglerPendulumFluttersAtItsClosedFormLoad) {
  const double Pcr = 3.5 - std::sqrt(2.0);
  EXPECT_EQ(ziegler(0.0).verdict, KineticVerdict::Stable);
  EXPECT_EQ(ziegler(Pcr - 1e-6).verdict, KineticVerdict::Stable);
  const KineticStability past = ziegler(Pcr + 1e-6);
  EXPECT_EQ(past.verdict, KineticVerdict::Flutter) << past.describe();
  // The symmetric part of A at P = 2.5 is indefinite, yet the pendulum is merely fluttering, not diverging:
  // the energy criterion and the kinetic one differ for circulatory loads.
  const KineticStability far = ziegler(2.5);
  EXPECT_EQ(far.verdict, KineticVerdict::Flutter);
  EXPECT_NE(far.describe().find("flutter"), std::string::npos);
  // Bisection on the verdict finds the closed form.
  double lo = 1.0, hi = 3.0;
  for (int i = 0; i < 60; ++i) (ziegler(0.5 * (lo + hi)).stable() ? lo : hi) = 0.5 * (lo + hi);
  EXPECT_NEAR(0.5 * (lo + hi), Pcr, 1e-7);
}

TEST(KineticStability, ACirculatoryTermSplitsADoubleEigenvalueIntoFlutter) {
  // A = I + eps J (J antisymmetric): lambda = 1 +- i eps, flutter for any eps > 0 (Nikolai's paradox
  // in two dimensions); eps = 0 is stable.
  for (double eps : {0.0, 1e-4, 1e-1}) {
    Eigen::Matrix2d A, M = Eigen::Matrix2d::Identity();
    A << 1, eps, -eps, 1;
    const KineticStability r = kineticStability(A, M, 2);
    ASSERT_EQ(r.lambda.size(), 2);
    EXPECT_EQ(r.verdict, eps > 0 ? KineticVerdict::Flutter : KineticVerdict::Stable) << "eps " << eps;
    EXPECT_NEAR(std::abs(r.lambda[0].imag()), eps, 1e-12);
    EXPECT_NEAR(r.lambda[0].real(), 1.0, 1e-12);
  }
}

TEST(KineticStability, ANegativeRealEigenvalueIsDivergence) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), M = Eigen::Matrix3d::Identity();
  A.diagonal() << -2.0, 1.0, 5.0;
  const KineticStability r = kineticStability(A, M, 3);
  EXPECT_EQ(r.verdict, KineticVerdict::Divergence);
  EXPECT_NEAR(r.lambda[r.critical].real(), -2.0, 1e-12);
  EXPECT_NE(r.describe().find("divergence"), std::string::npos);
}

TEST(KineticStability, ArpackAgreesWithTheDenseEigensolverAndTheClosedForm) {
  for (double p : {0.0, 1e-4, 1e-2}) {
    Eigen::MatrixXd A, M;
    Eigen::VectorXd s;
    twinChains(150, p, 0.0, A, M, s);
    const KineticStability arpack = kineticStability(A, M, 8, 60);
    const KineticStability dense = kineticStability(A, M, 8, 1000);
    EXPECT_EQ(arpack.method, "arpack") << arpack.message;
    EXPECT_EQ(dense.method, "dense");
    const KineticVerdict expected = p > 0 ? KineticVerdict::Flutter : KineticVerdict::Stable;
    EXPECT_EQ(arpack.verdict, expected) << "p " << p << ": " << arpack.describe();
    EXPECT_EQ(dense.verdict, expected) << "p " << p << ": " << dense.describe();
    for (const KineticStability* r : {&arpack, &dense}) {
      ASSERT_GE(r->lambda.size(), 8) << r->method;
      for (int i = 0; i < 8; ++i) {  // lambda = s_k +- i p, each twice when p = 0
        EXPECT_NEAR(r->lambda[i].real(), s[i / 2], 1e-10) << r->method << " " << i;
        EXPECT_NEAR(std::abs(r->lambda[i].imag()), p, 1e-10) << r->method << " " << i;
      }
    }
  }
  // Offset below zero: the lowest eigenvalues negative, divergence for both.
  Eigen::MatrixXd A, M;
  Eigen::VectorXd s;
  twinChains(150, 0.0, -1e-3, A, M, s);
  EXPECT_EQ(kineticStability(A, M, 8, 60).verdict, KineticVerdict::Divergence);
  EXPECT_EQ(kineticStability(A, M, 8, 1000).verdict, KineticVerdict::Divergence);
}

TEST(KineticStability, BadInput) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3), M = Eigen::MatrixXd::Identity(2, 2);
  EXPECT_THROW(kineticStability(A, M), std::invalid_argument);
  M = -Eigen::MatrixXd::Identity(3, 3);
  const KineticStability r = kineticStability(A, M);
  EXPECT_EQ(r.verdict, KineticVerdict::Undecided);
  EXPECT_NE(r.message.find("not positive definite"), std::string::npos);
}
