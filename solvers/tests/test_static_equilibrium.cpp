// Newton's step acceptance for static equilibrium (solvers/StaticEquilibrium). The model problem
// is the pivot's difficulty in two unknowns: a soft coordinate u loaded by F and a stiff "axial"
// strain e = w - u^2/2 (stiffness K) that a linear step in u violates to second order:
//   V(u, w) = k u^2 / 2 + K (w - u^2/2)^2 / 2 - F u,  equilibrium u = F/k, w = u^2/2.
// From rest the Newton step is (F/k, 0): exactly the right u, but ||Q||_inf jumps from F to
// K u^2/2, so the residual test cuts the step to nothing and Newton stalls, while the Newton
// correction at the new point (its own tangent carries the axial force's geometric stiffness) is
// tiny: the correction test accepts it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solvers/StaticEquilibrium.hpp"

using namespace flexmb::solvers;

namespace {
struct StiffStrain {
  double k = 1.0, K = 1e6, F = 0.1;
  void operator()(const Eigen::VectorXd& x, Eigen::VectorXd& Q, Eigen::MatrixXd* T) const {
    const double u = x[0], w = x[1], e = w - 0.5 * u * u;
    Q.resize(2);
    Q << F - (k * u - K * e * u), -K * e;  // Q = -dV/dx
    if (T) {
      T->resize(2, 2);
      *T << k - K * e + K * u * u, -K * u, -K * u, K;
    }
  }
};
}  // namespace

TEST(StaticNewton, ResidualTestAloneStallsOnAStiffSecondOrderStrain) {
  const StiffStrain p;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const StaticResult r = solveEquilibrium(p, x, p.F);
  std::printf("residual test only: status %d after %d iterations, u = %.3g (exact %.3g)\n", static_cast<int>(r.status),
              r.iterations, x[0], p.F / p.k);
  EXPECT_NE(r.status, StaticStatus::Converged);
}

TEST(StaticNewton, CorrectionTestTakesTheFullStepsAndConvergesQuadratically) {
  for (const double K : {1e4, 1e6, 1e8}) {
    StiffStrain p;
    p.K = K;
    NewtonOptions o;
    o.correctionMonotonicity = true;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
    const StaticResult r = solveEquilibrium(p, x, p.F, o);
    ASSERT_EQ(r.status, StaticStatus::Converged) << r.message;
    std::printf("K = %.0e: correction test, %d iterations\n", K, r.iterations);
    EXPECT_LE(r.iterations, 3);
    EXPECT_NEAR(x[0], p.F / p.k, 1e-12);
    EXPECT_NEAR(x[1], 0.5 * x[0] * x[0], 1e-12);
    EXPECT_TRUE(r.stable);
  }
}

TEST(StaticNewton, CorrectionTestRejectsADivergingStep) {
  // Q = -atan(u) from u = 1.5: full Newton steps oscillate outwards (1.5, -1.69, 2.32, -5.1, ...);
  // the correction at -1.69 (4.0) is longer than the step (3.2), so the step is cut, and Newton
  // converges to 0 instead of running away.
  auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd& Q, Eigen::MatrixXd* T) {
    Q.setConstant(1, -std::atan(x[0]));
    if (T) T->setConstant(1, 1, 1.0 / (1.0 + x[0] * x[0]));
  };
  NewtonOptions o;
  o.correctionMonotonicity = true;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 1.5);
  const StaticResult r = solveEquilibrium(f, x, 1.0, o);
  ASSERT_EQ(r.status, StaticStatus::Converged) << r.message;
  EXPECT_LE(r.iterations, 8);
  EXPECT_NEAR(x[0], 0.0, 1e-12);
}

TEST(StaticNewton, SingularTangentIsReported) {
  auto f = [](const Eigen::VectorXd&, Eigen::VectorXd& Q, Eigen::MatrixXd* T) {
    Q = Eigen::VectorXd::Ones(2);
    if (T) T->setZero(2, 2);
  };
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const StaticResult r = solveEquilibrium(f, x, 1.0);
  EXPECT_EQ(r.status, StaticStatus::SingularTangent);
}

TEST(StaticNewton, PositiveDefinitenessOfTheTangent) {
  EXPECT_TRUE(isPositiveDefinite(Eigen::Matrix2d{{2.0, 1.0}, {1.0, 2.0}}));
  EXPECT_FALSE(isPositiveDefinite(Eigen::Matrix2d{{1.0, 2.0}, {2.0, 1.0}}));
  EXPECT_FALSE(isPositiveDefinite(Eigen::Matrix2d{{1.0, 0.0}, {0.0, 0.0}}));
}
