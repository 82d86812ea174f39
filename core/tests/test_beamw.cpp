// BEAMW, the spatial beam with warping (core/elements/BEAMW.md): its first six deformations are
// BEAM's, the warping deformations are l0^2 w - e2, its linear stiffness is the classical 14-dof
// thin-walled beam (Timoshenko bending, Vlasov torsion with the rate of twist as the warping
// coordinate), and with E Cw = 0 condensing the warping coordinates gives BEAM's stiffness back.
// Derivatives, rigid-motion invariance and the inertia's Lagrange consistency are checked with
// every other registered type in test_element_registry.cpp (samples from the slots, Warping included).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/elements/Element.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/elements/SpatialWarpingBeam.hpp"
#include "core/tests/ElementSamples.hpp"

using namespace flexmb::core;
using namespace flexmb::core::test;
using euler::Mat3;
using euler::Vec3;
using euler::Vec4;

namespace {

// A BEAMW's 16 initial coordinates (random ends, orientations, initial warping) and its y vector.
struct BeamWSetup {
  ElemVec x0 = ElemVec(16);
  Vec3 y;
};
BeamWSetup randomSetup(std::mt19937& rng, bool zeroWarping = false) {
  BeamWSetup s;
  for (;;) {
    const Vec3 p(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const Vec3 q(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    s.y = Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    if ((q - p).norm() < 0.4 || std::abs((q - p).normalized().dot(s.y.normalized())) > 0.9) continue;
    s.x0 << p, randomQuaternion(rng), zeroWarping ? 0.0 : uniform(rng, -1, 1), q, randomQuaternion(rng),
        zeroWarping ? 0.0 : uniform(rng, -1, 1);
    return s;
  }
}

// BEAM's 14 coordinates of a BEAMW vector.
ElemVec beamPart(const ElemVec& x) {
  ElemVec b(14);
  b << x.segment<7>(0), x.segment<7>(8);
  return b;
}

// Coordinates -> (u_p, theta_p, W_p, u_q, theta_q, W_q) in global components, at x0:
// delta lambda = 1/2 E(lambda)^T delta theta.
Eigen::Matrix<double, 16, 14> rigidMap(const ElemVec& x0) {
  Eigen::Matrix<double, 16, 14> T = Eigen::Matrix<double, 16, 14>::Zero();
  T.block<3, 3>(0, 0).setIdentity();
  T.block<4, 3>(3, 3) = 0.5 * euler::globalRateMatrix(x0.segment<4>(3)).transpose();
  T(7, 6) = 1.0;
  T.block<3, 3>(8, 7).setIdentity();
  T.block<4, 3>(11, 10) = 0.5 * euler::globalRateMatrix(x0.segment<4>(11)).transpose();
  T(15, 13) = 1.0;
  return T;
}

// The classical thin-walled beam in its local frame, DOFs per end (u, v, w, thx, thy, thz, W),
// W = dthx/dx: axial, Timoshenko bending in both planes, Vlasov torsion with cubic Hermite twist
// (e.g. Barsoum and Gallagher 1970; St Venant part GIt/(30 L) [36 3L -36 3L; ...]).
Eigen::Matrix<double, 14, 14> thinWalledLocal(double L, double EA, double GIt, double EIy, double EIz, double cy,
                                              double cz, double ECw) {
  Eigen::Matrix<double, 14, 14> K = Eigen::Matrix<double, 14, 14>::Zero();
  auto block = [&](const int(&d)[4], const double(&m)[4][4], double k) {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) K(d[i], d[j]) += k * m[i][j];
  };
  K(0, 0) = K(7, 7) = EA / L, K(0, 7) = K(7, 0) = -EA / L;
  {
    const double F = 12 * cz / (L * L);
    const double m[4][4] = {{12, 6 * L, -12, 6 * L},
                            {6 * L, (4 + F) * L * L, -6 * L, (2 - F) * L * L},
                            {-12, -6 * L, 12, -6 * L},
                            {6 * L, (2 - F) * L * L, -6 * L, (4 + F) * L * L}};
    block({1, 5, 8, 12}, m, EIz / (L * L * L * (1 + F)));
  }
  {
    const double F = 12 * cy / (L * L);
    const double m[4][4] = {{12, -6 * L, -12, -6 * L},
                            {-6 * L, (4 + F) * L * L, 6 * L, (2 - F) * L * L},
                            {-12, 6 * L, 12, 6 * L},
                            {-6 * L, (2 - F) * L * L, 6 * L, (4 + F) * L * L}};
    block({2, 4, 9, 11}, m, EIy / (L * L * L * (1 + F)));
  }
  const int t[4] = {3, 6, 10, 13};  // thx_p, W_p, thx_q, W_q
  const double sv[4][4] = {{36, 3 * L, -36, 3 * L},
                           {3 * L, 4 * L * L, -3 * L, -L * L},
                           {-36, -3 * L, 36, -3 * L},
                           {3 * L, -L * L, -3 * L, 4 * L * L}};
  block(t, sv, GIt / (30 * L));
  const double wv[4][4] = {{12, 6 * L, -12, 6 * L},
                           {6 * L, 4 * L * L, -6 * L, 2 * L * L},
                           {-12, -6 * L, 12, -6 * L},
                           {6 * L, 2 * L * L, -6 * L, 4 * L * L}};
  block(t, wv, ECw / (L * L * L));
  return K;
}

// Global stiffness D^T S D at x0 mapped to (u, theta, W) in global components.
Eigen::MatrixXd globalStiffness(const Element& el, const ElemVec& x0, std::span<const double> p) {
  DefMat S;
  el.constitutive(p, S);
  DefJac D;
  el.jacobian(x0, D);
  const Eigen::MatrixXd DT = Eigen::MatrixXd(D) * rigidMap(x0);
  return DT.transpose() * Eigen::MatrixXd(S) * DT;
}

}  // namespace

TEST(BeamW, FirstSixDeformationsAreBeamsAndWarpingIsTwistRateMinusMeanTwist) {
  std::mt19937 rng(7);
  double worst = 0, worstW = 0, worstJ = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const BeamWSetup s = randomSetup(rng);
    const auto bw = findElementType("BEAMW")->createWithVector(s.x0, s.y.data(), {});
    const auto b = findElementType("BEAM")->createWithVector(beamPart(s.x0), s.y.data(), {});
    ElemVec x = s.x0;
    for (int i = 0; i < 16; ++i) x[i] += uniform(rng, -0.3, 0.3);
    DefVec e, eb;
    DefJac D, Db;
    bw->deformationsAndJacobian(x, e, D);
    b->deformationsAndJacobian(beamPart(x), eb, Db);
    ASSERT_EQ(e.size(), 8);
    worst = std::max(worst, (e.head<6>() - eb).cwiseAbs().maxCoeff());
    const double l0 = (s.x0.segment<3>(8) - s.x0.segment<3>(0)).norm();
    worstW = std::max({worstW, std::abs(e[6] - (l0 * l0 * (x[7] - s.x0[7]) - eb[1])),
                       std::abs(e[7] - (l0 * l0 * (x[15] - s.x0[15]) - eb[1]))});
    // The Jacobian's BEAM block is BEAM's; e7, e8 depend on w_p, w_q through l0^2 only.
    Eigen::MatrixXd Dw(6, 14);
    Dw << D.block<6, 7>(0, 0), D.block<6, 7>(0, 8);
    worstJ = std::max({worstJ, (Dw - Eigen::MatrixXd(Db)).cwiseAbs().maxCoeff(), std::abs(D(6, 7) - l0 * l0),
                       std::abs(D(7, 15) - l0 * l0), std::abs(D(6, 15)), std::abs(D(7, 7)),
                       std::abs(D(0, 7)) + std::abs(D(5, 15))});
  }
  std::printf("BEAMW e1..e6 - BEAM: %.1e, e7 e8 definition: %.1e, Jacobian: %.1e\n", worst, worstW, worstJ);
  EXPECT_EQ(worst, 0.0);
  EXPECT_LT(worstW, 1e-14);
  EXPECT_EQ(worstJ, 0.0);
}

TEST(BeamW, UniformTwistHasNoWarpingDeformation) {
  // An element twisted uniformly by phi (any size) with both twist rates phi/l0: e7 = l0^2 phi/l0
  // - e2 = l0 (phi - sin phi) (e2 = l0 sin phi is BEAM's sine measure, core/elements/BEAMW.md 3), zero to first
  // order; the warping stress of a twisted element with free warping therefore vanishes.
  const Vec3 y(0, 1, 0);
  ElemVec x0(16);
  x0 << 0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 1, 0, 0, 0, 0;
  const auto el = findElementType("BEAMW")->createWithVector(x0, y.data(), {});
  for (double phi : {1e-4, 0.01, 0.3}) {
    ElemVec x = x0;
    x.segment<4>(11) << std::cos(phi / 2), std::sin(phi / 2), 0, 0;  // node q turned by phi about x
    x[7] = x[15] = phi / 2;
    DefVec e;
    el->deformations(x, e);
    EXPECT_NEAR(e[1], 2 * std::sin(phi), 1e-14) << phi;
    EXPECT_NEAR(e[6], 2 * (phi - std::sin(phi)), 1e-14) << phi;
    EXPECT_NEAR(e[7], e[6], 1e-15) << phi;
  }
}

TEST(BeamW, LinearStiffnessIsTheClassicalThinWalledBeam) {
  std::mt19937 rng(3);
  const ElementTypeInfo* t = findElementType("BEAMW");
  ASSERT_NE(t, nullptr);
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const BeamWSetup s = randomSetup(rng);
    const auto el = t->createWithVector(s.x0, s.y.data(), {});
    const double p[7] = {uniform(rng, 1, 100),  uniform(rng, 0.1, 5),  uniform(rng, 0.1, 5), uniform(rng, 0.1, 5),
                         uniform(rng, 0, 0.05), uniform(rng, 0, 0.05), uniform(rng, 0.01, 1)};
    const Eigen::MatrixXd K = globalStiffness(*el, s.x0, p);
    const Vec3 d = s.x0.segment<3>(8) - s.x0.segment<3>(0);
    const double L = d.norm();
    const Mat3 F = euler::elementFrame(d / L, s.y);
    Eigen::Matrix<double, 14, 14> Lam = Eigen::Matrix<double, 14, 14>::Zero();  // local = F^T global
    for (int o : {0, 7}) {
      Lam.block<3, 3>(o, o) = F.transpose();
      Lam.block<3, 3>(o + 3, o + 3) = F.transpose();
      Lam(o + 6, o + 6) = 1.0;
    }
    const Eigen::MatrixXd Kc = Lam.transpose() * thinWalledLocal(L, p[0], p[1], p[2], p[3], p[4], p[5], p[6]) * Lam;
    worst = std::max(worst, (K - Kc).norm() / Kc.norm());
  }
  std::printf("BEAMW D^T S D vs the classical 14-dof thin-walled beam: max relative error %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(BeamW, WithoutWarpingStiffnessCondensedIsBeam) {
  // E Cw = 0: the warping coordinates of one element decouple (they carry the positive St Venant
  // part GIt/(30 l0^3) [4 -1; -1 4] of e7, e8 only), and condensing them out gives BEAM's matrix.
  std::mt19937 rng(17);
  double worst = 0, minEig = 1e300;
  for (int trial = 0; trial < 20; ++trial) {
    const BeamWSetup s = randomSetup(rng, true);
    const auto bw = findElementType("BEAMW")->createWithVector(s.x0, s.y.data(), {});
    const auto b = findElementType("BEAM")->createWithVector(beamPart(s.x0), s.y.data(), {});
    const double p[7] = {uniform(rng, 1, 100),
                         uniform(rng, 0.1, 5),
                         uniform(rng, 0.1, 5),
                         uniform(rng, 0.1, 5),
                         uniform(rng, 0, 0.05),
                         uniform(rng, 0, 0.05),
                         0.0};
    const Eigen::MatrixXd K = globalStiffness(*bw, s.x0, p);
    const int w[2] = {6, 13};
    std::vector<int> o;
    for (int i = 0; i < 14; ++i)
      if (i != 6 && i != 13) o.push_back(i);
    Eigen::Matrix2d Kww;
    Eigen::MatrixXd Kow(12, 2), Koo(12, 12);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) Kww(i, j) = K(w[i], w[j]);
    for (int i = 0; i < 12; ++i) {
      for (int j = 0; j < 2; ++j) Kow(i, j) = K(o[i], w[j]);
      for (int j = 0; j < 12; ++j) Koo(i, j) = K(o[i], o[j]);
    }
    const Eigen::MatrixXd Kc = Koo - Kow * Kww.inverse() * Kow.transpose();
    // BEAM's own matrix at the same state.
    DefMat S;
    b->constitutive(std::span<const double>(p, 6), S);
    DefJac D;
    b->jacobian(beamPart(s.x0), D);
    Eigen::Matrix<double, 14, 12> T = Eigen::Matrix<double, 14, 12>::Zero();
    T.block<3, 3>(0, 0).setIdentity();
    T.block<4, 3>(3, 3) = 0.5 * euler::globalRateMatrix(s.x0.segment<4>(3)).transpose();
    T.block<3, 3>(7, 6).setIdentity();
    T.block<4, 3>(10, 9) = 0.5 * euler::globalRateMatrix(s.x0.segment<4>(11)).transpose();
    const Eigen::MatrixXd DT = Eigen::MatrixXd(D) * T;
    const Eigen::MatrixXd Kb = DT.transpose() * Eigen::MatrixXd(S) * DT;
    worst = std::max(worst, (Kc - Kb).norm() / Kb.norm());
    minEig = std::min(minEig, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(Kww).eigenvalues()[0]);
  }
  std::printf("BEAMW with ECw = 0, warping condensed vs BEAM: %.2e; smallest warping-block eigenvalue %.3g\n", worst,
              minEig);
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(minEig, 0.0);
}

TEST(BeamW, ConstitutiveAndWarpingInertia) {
  ElemVec x0(16);
  x0 << 0, 0, 0, 1, 0, 0, 0, 0, 0.5, 0, 0, 1, 0, 0, 0, 0;
  const Vec3 y(0, 0, 1);
  const auto el = findElementType("BEAMW")->createWithVector(x0, y.data(), {});
  const double l = 0.5, GIt = 3.0, ECw = 0.2;
  const double p[7] = {10, GIt, 1, 2, 0, 0, ECw};
  DefMat S;
  el->constitutive(p, S);
  ASSERT_EQ(S.rows(), 8);
  EXPECT_DOUBLE_EQ(S(1, 1), GIt / (l * l * l));
  EXPECT_DOUBLE_EQ(S(6, 6), GIt / (30 * l * l * l) * 4 + ECw / std::pow(l, 5) * 4);
  EXPECT_DOUBLE_EQ(S(6, 7), -GIt / (30 * l * l * l) + ECw / std::pow(l, 5) * 2);
  EXPECT_DOUBLE_EQ(S(7, 6), S(6, 7));
  EXPECT_EQ((S.block<6, 2>(0, 6).cwiseAbs().maxCoeff()), 0.0);
  EXPECT_DOUBLE_EQ(el->referenceLength(), l);
  // Mass: BEAM's on the fourteen, Jw l0/2 on each warping coordinate, no coupling.
  ElementInertia in;
  in.rhoA = 2, in.jxx = 0.1, in.jyy = 0.05, in.jzz = 0.05, in.jw = 1e-3;
  ElemMat M, Mb;
  el->mass(x0, in, M);
  findElementType("BEAM")->createWithVector(beamPart(x0), y.data(), {})->mass(beamPart(x0), in, Mb);
  EXPECT_DOUBLE_EQ(M(7, 7), 0.5 * l * in.jw);
  EXPECT_DOUBLE_EQ(M(15, 15), 0.5 * l * in.jw);
  EXPECT_EQ(M.row(7).cwiseAbs().sum() + M.row(15).cwiseAbs().sum(), M(7, 7) + M(15, 15));
  Eigen::MatrixXd Mw(14, 14);
  for (int i = 0; i < 14; ++i)
    for (int j = 0; j < 14; ++j) Mw(i, j) = M(i < 7 ? i : i + 1, j < 7 ? j : j + 1);
  EXPECT_EQ((Mw - Eigen::MatrixXd(Mb)).cwiseAbs().maxCoeff(), 0.0);
  // Gravity acts on the translational field only (as BEAM).
  const double g[3] = {0, 0, -9.81};
  ElemVec f;
  el->gravityForces3(x0, in, g, f);
  EXPECT_EQ(f[7], 0.0);
  EXPECT_EQ(f[15], 0.0);
  EXPECT_NEAR(f[2] + f[10], -9.81 * in.rhoA * l, 1e-14);
}

TEST(BeamW, RegistryEntry) {
  const ElementTypeInfo* t = findElementType("beamw");
  ASSERT_NE(t, nullptr);
  using enum NodeKind;
  EXPECT_EQ(t->slots, (std::vector<NodeKind>{SpatialPosition, EulerParameters, Warping, SpatialPosition,
                                             EulerParameters, Warping}));
  EXPECT_EQ(t->numCoords(), 16);
  EXPECT_EQ(t->numDeformations(), 8);
  EXPECT_EQ(t->stiffness.size(), 7u);
  EXPECT_EQ(t->stiffness.back().name, "ECw");
  EXPECT_EQ(t->inertia.size(), 6u);
  EXPECT_EQ(t->inertia.back().name, "Jw");
  EXPECT_EQ(t->requiredStiffness, 7);
  EXPECT_TRUE(t->isAlwaysReleased(6) && t->isAlwaysReleased(7) && !t->isAlwaysReleased(1));
  EXPECT_EQ(t->vector.size(), 3u);
  EXPECT_EQ(t->spacarTypeId, 18);  // SPACAR's own code of BEAMW (io/results.md)
  EXPECT_TRUE(t->largeRotations.empty());
  EXPECT_FALSE(t->drawnCurved);
  // The readers of other programs' section layouts: BEAM ignores ECw and Jw, TRUSS all but EA/rhoA.
  EXPECT_EQ(findElementType("BEAM")->ignoredStiffness.size(), 1u);
  EXPECT_EQ(findElementType("BEAM")->ignoredInertia.size(), 1u);
  EXPECT_EQ(findElementType("TRUSS")->ignoredStiffness.size(), 6u);
  EXPECT_EQ(findElementType("TRUSS")->ignoredInertia.size(), 5u);
  EXPECT_GE(kMaxElemCoords, t->numCoords());
  EXPECT_GE(kMaxElemDefs, t->numDeformations());
}
