// Tests of solvers/ReductionBasis (Boer et al. 2013, Eq. 20-23): partition, assembly of V,
// restriction, modal and SVD-modal bases on constructed matrices with known answers.
#include "solvers/ReductionBasis.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace flexmb::solvers;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

MatrixXd randomMatrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  MatrixXd A(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) A(i, j) = d(gen);
  return A;
}

// n x n random orthogonal matrix (Q of a QR factorisation).
MatrixXd randomOrthogonal(Eigen::Index n, unsigned seed) {
  Eigen::HouseholderQR<MatrixXd> qr(randomMatrix(n, n, seed));
  return qr.householderQ() * MatrixXd::Identity(n, n);
}

// Orthogonal projector onto range(V) (V full column rank).
MatrixXd projector(const MatrixXd& V) {
  const MatrixXd G = V.transpose() * V;
  return V * G.ldlt().solve(V.transpose());
}

VectorXd vec(std::initializer_list<double> v) {
  VectorXd x(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double d : v) x[i++] = d;
  return x;
}

// Index of the entry picked by the sign convention: first with |v_i| >= (1 - 1e-10) max |v|.
Eigen::Index signIndex(const VectorXd& v) {
  const double mx = v.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (std::abs(v[i]) >= (1 - 1e-10) * mx) return i;
  return -1;
}

void expectSignConvention(const MatrixXd& V) {
  for (Eigen::Index k = 0; k < V.cols(); ++k) {
    EXPECT_NEAR(V.col(k).norm(), 1.0, 1e-14) << "column " << k;
    EXPECT_GT(V(signIndex(V.col(k)), k), 0.0) << "column " << k;
  }
}

template <class F>
std::string thrownMessage(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "<no std::invalid_argument thrown>";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Partition

TEST(ReductionBasisPartition, MakeComplementsLargeInOrder) {
  const Partition p = Partition::make(6, {4, 1});
  EXPECT_EQ(p.size(), 6);
  EXPECT_EQ(p.large, (std::vector<int>{4, 1}));  // caller's order kept
  EXPECT_EQ(p.small, (std::vector<int>{0, 2, 3, 5}));
  EXPECT_EQ(p.nLarge(), 2);
  EXPECT_EQ(p.nSmall(), 4);
  EXPECT_NO_THROW(p.validate(6));

  const Partition none = Partition::make(3, {});
  EXPECT_TRUE(none.large.empty());
  EXPECT_EQ(none.small, (std::vector<int>{0, 1, 2}));
  const Partition all = Partition::make(2, {0, 1});
  EXPECT_TRUE(all.small.empty());
  EXPECT_EQ(Partition::make(0, {}).size(), 0);
}

TEST(ReductionBasisPartition, ValidationThrows) {
  EXPECT_THROW(Partition::make(4, {1, 1}), std::invalid_argument);  // duplicate
  EXPECT_THROW(Partition::make(4, {4}), std::invalid_argument);     // out of range
  EXPECT_THROW(Partition::make(4, {-1}), std::invalid_argument);    // negative
  EXPECT_THROW(Partition::make(-1, {}), std::invalid_argument);     // bad nq
  EXPECT_NE(thrownMessage([] { Partition::make(4, {2, 0, 2}); }).find("duplicate large index 2"), std::string::npos);
  EXPECT_NE(thrownMessage([] { Partition::make(4, {7}); }).find("out of range"), std::string::npos);

  // Both lists given.
  EXPECT_NO_THROW(Partition::make(4, {3, 0}, {1, 2}));
  EXPECT_THROW(Partition::make(4, {0}, {1, 2}), std::invalid_argument);  // 3 missing
  EXPECT_NE(thrownMessage([] { Partition::make(4, {0}, {1, 2}); }).find("index 3 is neither"), std::string::npos);
  EXPECT_THROW(Partition::make(4, {0, 1}, {1, 2, 3}), std::invalid_argument);  // overlap
  EXPECT_THROW(Partition::make(4, {0}, {1, 2, 2, 3}), std::invalid_argument);  // duplicate small
  EXPECT_THROW(Partition::make(4, {0}, {1, 2, 3, 4}), std::invalid_argument);  // out of range

  // A hand-built inconsistent partition is rejected by the functions using it.
  Partition bad;
  bad.large = {0, 0};
  bad.small = {1};
  EXPECT_THROW(assembleBasis(bad, MatrixXd::Zero(1, 1)), std::invalid_argument);
  EXPECT_THROW(restrictToSmall(bad, MatrixXd::Zero(3, 3)), std::invalid_argument);
}

TEST(ReductionBasisPartition, AssembleBasisIdentityAtLargeVsAtSmall) {
  const Partition p = Partition::make(6, {4, 1});  // small = {0, 2, 3, 5}
  const MatrixXd Vs = randomMatrix(4, 3, 11);
  const MatrixXd V = assembleBasis(p, Vs);
  ASSERT_EQ(V.rows(), 6);
  ASSERT_EQ(V.cols(), 2 + 3);
  // Identity columns at the large indices, in the partition's order.
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 6; ++i) EXPECT_EQ(V(i, j), i == p.large[j] ? 1.0 : 0.0) << i << "," << j;
  // Vs scattered into the small rows; large rows are zero in the Vs columns.
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 4; ++i) EXPECT_EQ(V(p.small[i], 2 + k), Vs(i, k));
    EXPECT_EQ(V(4, 2 + k), 0.0);
    EXPECT_EQ(V(1, 2 + k), 0.0);
  }
  // q = V eta: q_l = eta_l, q_s = Vs eta_s.
  const VectorXd eta = vec({0.3, -0.7, 1.0, 2.0, -3.0});
  const VectorXd q = V * eta;
  EXPECT_EQ(q[4], 0.3);
  EXPECT_EQ(q[1], -0.7);
  const VectorXd qs = Vs * eta.tail(3);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(q[p.small[i]], qs[i], 1e-15);

  // Zero reduced columns: only the identity part (no row of the empty Vs is taken: clang's UBSan
  // reported the null-pointer offset of Vs.row(i) here, tools/README.md "Sanitizers").
  EXPECT_EQ(assembleBasis(p, MatrixXd(4, 0)).cols(), 2);
  // Wrong number of rows.
  EXPECT_THROW(assembleBasis(p, MatrixXd::Zero(5, 2)), std::invalid_argument);
}

TEST(ReductionBasisPartition, RestrictToSmallPicksBlock) {
  const Partition p = Partition::make(5, {0, 3});  // small = {1, 2, 4}
  MatrixXd A(5, 5);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) A(i, j) = 10 * i + j;
  const MatrixXd B = restrictToSmall(p, A);
  ASSERT_EQ(B.rows(), 3);
  ASSERT_EQ(B.cols(), 3);
  const int s[] = {1, 2, 4};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(B(i, j), 10 * s[i] + s[j]);
  EXPECT_THROW(restrictToSmall(p, MatrixXd::Zero(4, 4)), std::invalid_argument);
  EXPECT_THROW(restrictToSmall(p, MatrixXd::Zero(5, 4)), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Modal basis

TEST(ReductionBasisModal, UnitColumnsAndSignConvention) {
  MatrixXd modes = randomMatrix(7, 5, 3);
  modes.col(0) *= -25.0;
  modes.col(1) *= 1e-6;
  modes.col(2) *= -1.0;
  const MatrixXd Vs = modalBasis(modes, 3);
  ASSERT_EQ(Vs.rows(), 7);
  ASSERT_EQ(Vs.cols(), 3);
  expectSignConvention(Vs);
  // Each column is parallel to the original mode.
  for (int k = 0; k < 3; ++k) {
    const VectorXd m = modes.col(k).normalized();
    EXPECT_NEAR(std::abs(m.dot(Vs.col(k))), 1.0, 1e-14);
  }
  EXPECT_EQ(modalBasis(modes, 0).cols(), 0);
  // Deterministic: a sign flip of the input does not change the output.
  EXPECT_EQ(modalBasis(-modes, 3), Vs);
}

TEST(ReductionBasisModal, MassNormalisedColumnsAreMOrthonormal) {
  // Eigenvectors of a random pencil (K, M): mass-normalised columns satisfy V^T M V = I (as MATLAB's
  // eig(K, M) returns them), stay parallel to the modes and keep the sign convention.
  const MatrixXd R = randomMatrix(6, 6, 11), S = randomMatrix(6, 6, 12);
  const MatrixXd M = R * R.transpose() + 6.0 * MatrixXd::Identity(6, 6), K = S * S.transpose();
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(K, M);
  MatrixXd modes = es.eigenvectors();
  modes.col(0) *= -3.0;  // arbitrary scaling of the input must not matter
  modes.col(2) *= 1e-4;
  const MatrixXd Vs = massNormalisedModalBasis(modes, M, 4);
  ASSERT_EQ(Vs.cols(), 4);
  EXPECT_LT((Vs.transpose() * M * Vs - MatrixXd::Identity(4, 4)).cwiseAbs().maxCoeff(), 1e-12);
  const MatrixXd U = modalBasis(modes, 4);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(U.col(k).dot(Vs.col(k)) / Vs.col(k).norm(), 1.0, 1e-14) << k;
  EXPECT_THROW(massNormalisedModalBasis(modes, MatrixXd::Identity(5, 5), 2), std::invalid_argument);
  EXPECT_THROW(massNormalisedModalBasis(modes, -M, 2), std::invalid_argument);
}

TEST(ReductionBasisModal, SignTieBrokenByFirstIndex) {
  // Equal magnitudes up to round-off: the first index decides.
  MatrixXd modes(2, 3);
  modes << -1.0, -1.0 - 1e-14, 1.0,  //
      1.0, 1.0, -1.0 - 1e-14;
  const MatrixXd Vs = modalBasis(modes, 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(Vs(0, k), 0.0) << k;
    EXPECT_LT(Vs(1, k), 0.0) << k;
  }
}

TEST(ReductionBasisModal, Errors) {
  const MatrixXd modes = randomMatrix(4, 3, 5);
  EXPECT_THROW(modalBasis(modes, 4), std::invalid_argument);
  EXPECT_NE(thrownMessage([&] { modalBasis(modes, 4); }).find("only 3 available"), std::string::npos);
  EXPECT_THROW(modalBasis(modes, -1), std::invalid_argument);
  MatrixXd z = modes;
  z.col(1).setZero();
  EXPECT_THROW(modalBasis(z, 2), std::invalid_argument);
  EXPECT_NO_THROW(modalBasis(z, 1));
  z.col(1).setConstant(std::nan(""));
  EXPECT_THROW(modalBasis(z, 2), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// SVD-modal basis

TEST(ReductionBasisSvdModal, SingleConfigurationMatchesModalSpan) {
  const int ns = 9, r = 4;
  const MatrixXd modes = randomMatrix(ns, 6, 7);                  // not orthogonal, arbitrary scaling
  const VectorXd omegas = vec({0.0, 2.0, 5.0, 9.0, 30.0, 70.0});  // a rigid mode is fine with a = 0
  const MatrixXd Vm = modalBasis(modes, r);

  const SvdModalResult res = svdModalBasis({modes}, {omegas}, r, 0.0, 0.0, r);
  ASSERT_EQ(res.kept, r);
  ASSERT_EQ(res.Vs.rows(), ns);
  ASSERT_EQ(res.Vs.cols(), r);
  EXPECT_EQ(res.singularValues.size(), r);  // min(ns, n r)
  EXPECT_LT((projector(Vm) - projector(res.Vs)).norm(), 1e-10);
  // Orthonormal columns with the sign convention.
  EXPECT_LT((res.Vs.transpose() * res.Vs - MatrixXd::Identity(r, r)).norm(), 1e-13);
  expectSignConvention(res.Vs);

  // Threshold 0 without count keeps every (nonzero) singular vector: also r here.
  const SvdModalResult all = svdModalBasis({modes}, {omegas}, r, 0.0, 0.0, 0);
  EXPECT_EQ(all.kept, r);
  EXPECT_LT((projector(Vm) - projector(all.Vs)).norm(), 1e-10);

  // Deterministic.
  const SvdModalResult again = svdModalBasis({modes}, {omegas}, r, 0.0, 0.0, r);
  EXPECT_EQ(again.Vs, res.Vs);
  // Independent of the scaling and sign of the input modes.
  MatrixXd scaled = modes;
  scaled.col(0) *= -3.0;
  scaled.col(2) *= 1e3;
  const SvdModalResult sres = svdModalBasis({scaled}, {omegas}, r, 0.0, 0.0, r);
  EXPECT_LT((sres.Vs - res.Vs).norm(), 1e-12);
}

TEST(ReductionBasisSvdModal, IdenticalConfigurationsEqualShares) {
  const int ns = 8, r = 3, n = 5;
  const MatrixXd U = randomOrthogonal(ns, 13);
  MatrixXd modes = U.leftCols(4);
  modes.col(1) *= -2.5;  // normalisation must undo this
  const VectorXd omegas = vec({1.0, 3.0, 8.0, 20.0});
  const std::vector<MatrixXd> ms(n, modes);
  const std::vector<VectorXd> os(n, omegas);

  const SvdModalResult res = svdModalBasis(ms, os, r, 0.0);
  ASSERT_EQ(res.singularValues.size(), std::min(ns, n * r));
  EXPECT_NEAR(res.scaledSingularValues.sum(), 1.0, 1e-14);
  for (int k = 0; k < r; ++k) {
    EXPECT_NEAR(res.scaledSingularValues[k], 1.0 / r, 1e-12) << k;
    EXPECT_NEAR(res.singularValues[k], std::sqrt(double(n)), 1e-12) << k;
  }
  for (Eigen::Index k = r; k < res.singularValues.size(); ++k) EXPECT_LT(res.scaledSingularValues[k], 1e-14) << k;
  EXPECT_EQ(res.kept, r);  // default threshold 0.01
  EXPECT_LT((projector(res.Vs) - projector(U.leftCols(r))).norm(), 1e-10);
}

TEST(ReductionBasisSvdModal, KnownSingularValuesAndThreshold) {
  // Two configurations whose weighted modes are mutually orthogonal: the singular values of Q are
  // exactly the weights omega^-a (a = 1).
  const int ns = 7;
  const MatrixXd U = randomOrthogonal(ns, 21);
  // Configuration 0: u0, u1, u2 with weights 1, 0.5, 0.005. Configuration 1: u3, u4, u5 with
  // weights 0.2, 0.1, 0.003.
  MatrixXd m0(ns, 3), m1(ns, 3);
  m0 << 4.0 * U.col(0), -U.col(1), 0.1 * U.col(2);
  m1 << -7.0 * U.col(3), U.col(4), 2.0 * U.col(5);
  const VectorXd w0 = vec({1.0, 0.5, 0.005}), w1 = vec({0.2, 0.1, 0.003});
  const VectorXd om0 = w0.cwiseInverse(), om1 = w1.cwiseInverse();

  const double weights[] = {1.0, 0.5, 0.2, 0.1, 0.005, 0.003};  // descending
  double sum = 0;
  for (double w : weights) sum += w;

  const SvdModalResult res = svdModalBasis({m0, m1}, {om0, om1}, 3, 1.0);
  ASSERT_EQ(res.singularValues.size(), 6);
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(res.singularValues[k], weights[k], 1e-12) << k;
    EXPECT_NEAR(res.scaledSingularValues[k], weights[k] / sum, 1e-12) << k;
  }
  EXPECT_NEAR(res.scaledSingularValues.sum(), 1.0, 1e-14);
  // Shares: 0.5531, 0.2765, 0.1106, 0.0553, 0.00277, 0.00166 -> 4 above 0.01.
  EXPECT_EQ(res.kept, 4);
  ASSERT_EQ(res.Vs.cols(), 4);
  // The kept vectors are the u's in order of weight: u0, u1, u3, u4, sign convention applied.
  const int order[] = {0, 1, 3, 4};
  for (int k = 0; k < 4; ++k) {
    VectorXd u = U.col(order[k]);
    normaliseColumn(u);
    EXPECT_LT((res.Vs.col(k) - u).norm(), 1e-10) << k;
  }
  expectSignConvention(res.Vs);

  EXPECT_EQ(svdModalBasis({m0, m1}, {om0, om1}, 3, 1.0, 0.2).kept, 2);  // 0.555, 0.278
  EXPECT_EQ(svdModalBasis({m0, m1}, {om0, om1}, 3, 1.0, 0.06).kept, 3);
  EXPECT_EQ(svdModalBasis({m0, m1}, {om0, om1}, 3, 1.0, 0.0).kept, 6);
  EXPECT_EQ(svdModalBasis({m0, m1}, {om0, om1}, 3, 1.0, 0.2, 5).kept, 5);                 // count wins
  EXPECT_THROW(svdModalBasis({m0, m1}, {om0, om1}, 3, 1.0, 0.6), std::invalid_argument);  // none
}

TEST(ReductionBasisSvdModal, WeightingByFrequency) {
  const int ns = 5;
  const MatrixXd U = randomOrthogonal(ns, 31);
  const MatrixXd modes = U.leftCols(2);
  const VectorXd omegas = vec({1.0, 10.0});
  const SvdModalResult a0 = svdModalBasis({modes}, {omegas}, 2, 0.0, 0.0, 2);
  const SvdModalResult a1 = svdModalBasis({modes}, {omegas}, 2, 1.0, 0.0, 2);
  EXPECT_NEAR(a0.singularValues[0], 1.0, 1e-14);
  EXPECT_NEAR(a0.singularValues[1], 1.0, 1e-14);
  EXPECT_NEAR(a1.singularValues[0], 1.0, 1e-14);
  EXPECT_NEAR(a1.singularValues[1] / a0.singularValues[1], 0.1, 1e-13);
  EXPECT_NEAR(a1.scaledSingularValues[1], 0.1 / 1.1, 1e-13);
  // a = 2: omega^-2.
  const SvdModalResult a2 = svdModalBasis({modes}, {omegas}, 2, 2.0, 0.0, 2);
  EXPECT_NEAR(a2.singularValues[1], 0.01, 1e-14);
  // With a = 1 and the default threshold the 10 rad/s mode (share 0.0909) is still kept; with
  // a = 2 its share is 0.0099 < 0.01 and it is dropped.
  EXPECT_EQ(svdModalBasis({modes}, {omegas}, 2, 1.0).kept, 2);
  EXPECT_EQ(svdModalBasis({modes}, {omegas}, 2, 2.0).kept, 1);
}

TEST(ReductionBasisSvdModal, ZeroFrequencyWithWeightingThrows) {
  const MatrixXd U = randomOrthogonal(4, 41);
  const MatrixXd modes = U.leftCols(3);
  const VectorXd ok = vec({1.0, 2.0, 3.0});
  const VectorXd rigid = vec({0.0, 2.0, 3.0});
  EXPECT_THROW(svdModalBasis({modes, modes}, {ok, rigid}, 2, 1.0), std::invalid_argument);
  const std::string msg = thrownMessage([&] { svdModalBasis({modes, modes}, {ok, rigid}, 2, 1.0); });
  EXPECT_NE(msg.find("configuration 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mode 0"), std::string::npos) << msg;
  EXPECT_THROW(svdModalBasis({modes}, {vec({1.0, -2.0, 3.0})}, 2, -0.5), std::invalid_argument);
  // a = 0: the frequencies are not used.
  EXPECT_NO_THROW(svdModalBasis({modes, modes}, {ok, rigid}, 2, 0.0));
  // Omega beyond r is not used either.
  EXPECT_NO_THROW(svdModalBasis({modes}, {vec({1.0, 2.0, 0.0})}, 2, 1.0));
}

TEST(ReductionBasisSvdModal, InconsistentInputsThrow) {
  const MatrixXd m = randomMatrix(6, 3, 51);
  const VectorXd om = vec({1.0, 2.0, 3.0});
  EXPECT_THROW(svdModalBasis({}, {}, 2, 0.0), std::invalid_argument);
  EXPECT_THROW(svdModalBasis({m, m}, {om}, 2, 0.0), std::invalid_argument);
  EXPECT_THROW(svdModalBasis({m, randomMatrix(5, 3, 52)}, {om, om}, 2, 0.0), std::invalid_argument);
  EXPECT_NE(thrownMessage([&] {
              svdModalBasis({m, randomMatrix(5, 3, 52)}, {om, om}, 2, 0.0);
            }).find("configuration 1"),
            std::string::npos);
  EXPECT_THROW(svdModalBasis({m}, {om}, 4, 0.0), std::invalid_argument);          // r > modes
  EXPECT_THROW(svdModalBasis({m}, {vec({1.0})}, 2, 0.0), std::invalid_argument);  // too few omegas
  EXPECT_THROW(svdModalBasis({m}, {om}, 0, 0.0), std::invalid_argument);          // r < 1
  EXPECT_THROW(svdModalBasis({m}, {om}, 2, 0.0, -0.1), std::invalid_argument);    // threshold
  EXPECT_THROW(svdModalBasis({m}, {om}, 2, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(svdModalBasis({m}, {om}, 2, 0.0, 0.01, -1), std::invalid_argument);  // count
  EXPECT_THROW(svdModalBasis({m}, {om}, 2, 0.0, 0.01, 3), std::invalid_argument);   // > n r
  EXPECT_THROW(svdModalBasis({m}, {om}, 2, std::nan(""), 0.01), std::invalid_argument);
  MatrixXd z = m;
  z.col(1).setZero();
  EXPECT_THROW(svdModalBasis({z}, {om}, 2, 0.0), std::invalid_argument);
}
