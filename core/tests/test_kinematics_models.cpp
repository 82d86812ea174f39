// Kinematics on the sample models (SampleModels.hpp: the shipped .dat files built in code): mode-0
// counts, culprits, and the geometric transfer functions of a rigid four-bar against the
// closed-form position analysis and finite differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/elements/EulerParameters.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/kinematics/KinematicCheck.hpp"
#include "core/linearization/PrescribedEquilibrium.hpp"
#include "core/tests/SampleModels.hpp"

using namespace flexmb;
namespace samples = flexmb::core::samples;

namespace {
bool mentions(const std::vector<std::string>& list, const std::string& s) {
  return std::any_of(list.begin(), list.end(), [&](const std::string& x) { return x.find(s) != std::string::npos; });
}
}  // namespace

TEST(KinematicCheck, PaperModelsDegreesOfFreedom) {
  struct Case {
    const char* file;
    int dof;
    core::Model (*build)();
  };
  for (const Case c :
       {Case{"straight_guidance.dat", 17, samples::straightGuidance}, Case{"manipulator.dat", 18, samples::manipulator},
        Case{"slider_crank_s95.dat", 4, samples::sliderCrankS95},
        Case{"tests/fourbar.dat", 1, [] { return samples::fourBar(); }}}) {
    const core::Model m = c.build();
    const core::KinematicReport r = core::checkKinematics(m);
    EXPECT_EQ(r.dof, c.dof) << c.file;
    EXPECT_TRUE(r.wellPosed()) << c.file << "\n" << core::formatReport(r);
    EXPECT_EQ(r.rank, r.xCalculable) << c.file;
  }
}

TEST(KinematicCheck, NamesUnderdeterminedCoordinate) {
  const core::Model m = samples::fourBar(samples::FourBar::Underconstrained);
  const core::KinematicReport r = core::checkKinematics(m);
  ASSERT_FALSE(r.wellPosed());
  ASSERT_FALSE(r.underdetermined.empty());
  // The orientation node 32 at C is free: nothing constrains it (see the header of
  // datfiles/tests/underconstrained.dat).
  EXPECT_NE(r.underdetermined.front().find("node 32"), std::string::npos) << core::formatReport(r);
  EXPECT_EQ(r.underdetermined.size(), 1u) << core::formatReport(r);
}

TEST(KinematicCheck, NamesOverdeterminedLoop) {
  const core::Model m = samples::fourBar(samples::FourBar::Overconstrained);
  const core::KinematicReport r = core::checkKinematics(m);
  ASSERT_FALSE(r.wellPosed());
  EXPECT_TRUE(r.underdetermined.empty()) << core::formatReport(r);
  // One self-stress of the closed loop: the fixed hinge at C (element 6) is among the dependent
  // constraints, and so are the loop's other bending/hinge constraints.
  EXPECT_TRUE(mentions(r.overdetermined, "PLHINGE 6,")) << core::formatReport(r);
  EXPECT_TRUE(mentions(r.overdetermined, "PLHINGE 4,")) << core::formatReport(r);
}

namespace {
struct FourBar {
  double L1 = 0.1, L2 = 0.3, L3 = 0.25, L4 = 0.3;
  // Position of C for crank angle theta, open (upper) assembly.
  Eigen::Vector2d pointC(double theta) const {
    const Eigen::Vector2d B(L1 * std::cos(theta), L1 * std::sin(theta)), D(L4, 0.0);
    const Eigen::Vector2d d = D - B;
    const double dist = d.norm();
    const double a = (L2 * L2 - L3 * L3 + dist * dist) / (2 * dist);
    const double h = std::sqrt(L2 * L2 - a * a);
    const Eigen::Vector2d perp(-d.y() / dist, d.x() / dist);
    return B + a * d / dist + h * perp;
  }
};

int coordOf(const core::Model& m, int node, int comp) { return m.nodes[m.nodeByLabel.at(node)].firstCoord + comp; }
}  // namespace

TEST(GeometricTransferFunctions, FourBarMatchesClosedFormOverFullTurn) {
  core::Model m = samples::fourBar();
  m.settings.kinematicTol = 1e-14;
  core::GeometricTransferFunctions gtf(m);
  FourBar fb;
  const int cx = coordOf(m, 3, 0), cy = coordOf(m, 3, 1), bx = coordOf(m, 2, 0);
  const int coupler = coordOf(m, 21, 0), rocker = coordOf(m, 31, 0);
  double worst = 0.0;
  for (int k = 0; k <= 720; ++k) {
    const double q = 2 * M_PI * k / 720.0, theta = M_PI / 2 + q;
    gtf.solvePositions(0.0, Eigen::VectorXd::Constant(1, q));
    const Eigen::Vector2d C = fb.pointC(theta), B(fb.L1 * std::cos(theta), fb.L1 * std::sin(theta));
    const Eigen::VectorXd& x = gtf.x();
    worst = std::max({worst, std::abs(x[cx] - C.x()), std::abs(x[cy] - C.y()), std::abs(x[bx] - B.x())});
    // Link orientations: the coupler node turns with B->C, the rocker node with D->C.
    const double aCoupler = std::atan2(C.y() - B.y(), C.x() - B.x());
    const double aRocker = std::atan2(C.y(), C.x() - fb.L4);
    worst = std::max(worst, std::abs(std::remainder(x[coupler] - aCoupler, 2 * M_PI)));
    worst = std::max(worst, std::abs(std::remainder(x[rocker] - aRocker, 2 * M_PI)));
  }
  EXPECT_LT(worst, 1e-10);
  std::printf("four-bar over a full crank turn (720 positions): worst deviation from closed form %.3e\n", worst);
}

TEST(GeometricTransferFunctions, FirstOrderAndConvectiveTermsMatchFiniteDifferences) {
  core::Model m = samples::fourBar();
  m.settings.kinematicTol = 1e-15;
  core::GeometricTransferFunctions gtf(m);
  const double h = 1e-5;
  for (double q : {0.0, 0.7, 2.0, 3.5, 5.1}) {
    auto positions = [&](double qq) {
      gtf.solvePositions(0.0, Eigen::VectorXd::Constant(1, qq));
      return Eigen::VectorXd(gtf.x());
    };
    auto transfer = [&](double qq) {
      gtf.solvePositions(0.0, Eigen::VectorXd::Constant(1, qq));
      Eigen::MatrixXd F;
      gtf.firstOrder(nullptr, F);
      return F;
    };
    const Eigen::VectorXd fdFq = (positions(q + h) - positions(q - h)) / (2 * h);
    const Eigen::VectorXd fdFqq = (transfer(q + h) - transfer(q - h)).col(0) / (2 * h);
    const Eigen::MatrixXd Fq = transfer(q);
    EXPECT_LT((Fq.col(0) - fdFq).norm(), 1e-7 * fdFq.norm()) << "q = " << q;
    // xd = F_q qd and g = (F_qq qd) qd for qd = 1.7.
    const double qd = 1.7;
    Eigen::VectorXd xd, g;
    gtf.velocities(0.0, Eigen::VectorXd::Constant(1, qd), xd);
    EXPECT_LT((xd - Fq.col(0) * qd).norm(), 1e-12 * xd.norm());
    gtf.accelerationOffset(0.0, xd, g);
    EXPECT_LT((g - fdFqq * qd * qd).norm(), 1e-6 * g.norm()) << "q = " << q;
  }
}

TEST(GeometricTransferFunctions, StraightGuidanceFirstOrderMatchesFiniteDifferences) {
  core::Model m = samples::straightGuidance();
  m.settings.kinematicTol = 1e-15;
  core::GeometricTransferFunctions gtf(m);
  const int nq = gtf.nq();
  Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(nq, -1e-3, 2e-3);  // bent, a few mm deflection
  gtf.solvePositions(0.0, q);
  Eigen::MatrixXd Fq;
  gtf.firstOrder(nullptr, Fq);
  const double h = 1e-7;
  double worst = 0.0;
  for (int j = 0; j < nq; ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp[j] += h;
    qm[j] -= h;
    gtf.solvePositions(0.0, qp);
    const Eigen::VectorXd xp = gtf.x();
    gtf.solvePositions(0.0, qm);
    const Eigen::VectorXd fd = (xp - gtf.x()) / (2 * h);
    worst = std::max(worst, (Fq.col(j) - fd).norm() / std::max(1e-12, fd.norm()));
  }
  EXPECT_LT(worst, 1e-6);
  // With a basis, F_q V equals F_q times V.
  gtf.solvePositions(0.0, q);
  const Eigen::MatrixXd V = Eigen::MatrixXd::Random(nq, 3);
  Eigen::MatrixXd FqV;
  gtf.firstOrder(&V, FqV);
  EXPECT_LT((FqV - Fq * V).norm(), 1e-12 * (Fq * V).norm());
}

// The anchor (the integrator's last accepted configuration, set by setAnchor) is where a solve that
// fails from its warm start starts again, and where restartFromAnchor puts the warm start (an
// integrator retrying a rejected step whose trial states converged on another assembly branch).
TEST(GeometricTransferFunctions, AnchorIsTheFallbackStartAndTheRestartPoint) {
  core::Model m = samples::fourBar();
  m.settings.kinematicTol = 1e-14;
  FourBar fb;
  const int cx = coordOf(m, 3, 0), cy = coordOf(m, 3, 1), bx = coordOf(m, 2, 0), by = coordOf(m, 2, 1);
  const int coupler[2] = {coordOf(m, 21, 0), coordOf(m, 22, 0)}, rocker[2] = {coordOf(m, 31, 0), coordOf(m, 32, 0)};
  const double q = 0.05, theta = M_PI / 2 + q;
  const Eigen::VectorXd Q = Eigen::VectorXd::Constant(1, q);
  const Eigen::Vector2d B(fb.L1 * std::cos(theta), fb.L1 * std::sin(theta)), D(fb.L4, 0.0);
  const Eigen::Vector2d open = fb.pointC(theta);
  // The crossed assembly: C mirrored about the line B-D.
  const Eigen::Vector2d u = (D - B).normalized();
  const Eigen::Vector2d crossed = B + 2 * (open - B).dot(u) * u - (open - B);
  auto distanceTo = [&](const Eigen::VectorXd& x, const Eigen::Vector2d& C) {
    return std::hypot(x[cx] - C.x(), x[cy] - C.y());
  };

  core::GeometricTransferFunctions gtf(m);
  gtf.solvePositions(0.0, Eigen::VectorXd::Zero(1));
  gtf.setAnchor();
  const Eigen::VectorXd start = gtf.x();

  // 1. A warm start Newton cannot use (the coupler of zero length: non-finite deformations) fails
  //    without an anchor and is retried from the anchor with one.
  Eigen::VectorXd degenerate = start;
  degenerate[cx] = degenerate[bx], degenerate[cy] = degenerate[by];
  core::GeometricTransferFunctions plain(m);
  plain.setConfiguration(degenerate);
  EXPECT_THROW(plain.solvePositions(0.0, Q), core::KinematicsError);
  gtf.setConfiguration(degenerate);
  ASSERT_NO_THROW(gtf.solvePositions(0.0, Q));
  EXPECT_LT(distanceTo(gtf.x(), open), 1e-10);

  // 2. From the crossed assembly Newton stays on it; restartFromAnchor returns to the open one.
  Eigen::VectorXd x = start;
  x[cx] = crossed.x(), x[cy] = crossed.y();
  for (int i : coupler) x[i] = std::atan2(crossed.y() - B.y(), crossed.x() - B.x());
  for (int i : rocker) x[i] = std::atan2(crossed.y(), crossed.x() - fb.L4);
  gtf.setConfiguration(x);
  gtf.solvePositions(0.0, Q);
  EXPECT_LT(distanceTo(gtf.x(), crossed), 1e-10);  // the premise: another branch, same q
  gtf.restartFromAnchor();
  gtf.solvePositions(0.0, Q);
  EXPECT_LT(distanceTo(gtf.x(), open), 1e-10);

  // 3. setAnchor after a failed solve keeps the previous anchor (here: none).
  plain.setConfiguration(degenerate);
  EXPECT_THROW(plain.solvePositions(0.0, Q), core::KinematicsError);
  plain.setAnchor();  // ignored: the last solve failed
  plain.setConfiguration(degenerate);
  EXPECT_THROW(plain.solvePositions(0.0, Q), core::KinematicsError);
}

TEST(GeometricTransferFunctions, SingularOrUnsquareKinematicsAreReportedNotIgnored) {
  const core::Model m = samples::fourBar(samples::FourBar::Underconstrained);
  core::GeometricTransferFunctions gtf(m);
  try {
    gtf.solvePositions(0.25, gtf.initialDofs());
    FAIL() << "expected a KinematicsError";
  } catch (const core::KinematicsError& e) {
    EXPECT_DOUBLE_EQ(e.time(), 0.25);
    EXPECT_NE(std::string(e.what()).find("t = 0.25"), std::string::npos) << e.what();
  }
}

TEST(GeometricTransferFunctions, OpenChainsArePlacedInOnePassWithoutIteration) {
  // The manipulator is an open chain of PLHINGEs and PLBEAMs: every calculable coordinate follows
  // from the element before it in closed form (Element::place), so a solve needs no Newton
  // correction, even far from the last configuration. Closed loops keep Newton.
  const core::Model m = samples::manipulator();
  core::GeometricTransferFunctions gtf(m);
  ASSERT_TRUE(gtf.isSequential());
  for (const auto& [f, build] :
       {std::pair<const char*, core::Model (*)()>{"straight_guidance.dat", samples::straightGuidance},
        {"slider_crank_s95.dat", samples::sliderCrankS95},
        {"tests/fourbar.dat", [] { return samples::fourBar(); }},
        {"portal.dat", samples::portal}}) {
    const core::Model closed = build();
    EXPECT_FALSE(core::GeometricTransferFunctions(closed).isSequential()) << f;
  }
  const core::Model cantilever = samples::cantilever();
  EXPECT_TRUE(core::GeometricTransferFunctions(cantilever).isSequential());
  Eigen::VectorXd q = gtf.initialDofs();
  for (int trial = 0; trial < 5; ++trial) {
    for (int j = 0; j < q.size(); ++j) {
      const auto& d = m.dofs[j];
      const bool hinge = m.elements[m.eOwnerElement[d.index]].impl->numDeformations() == 1;
      q[j] = hinge ? 1.3 * std::sin(3.0 * trial + j) : 2e-3 * std::cos(5.0 * trial + j);  // large turns
    }
    gtf.solvePositions(0.0, q);
    EXPECT_EQ(gtf.lastIterations(), 0) << "trial " << trial;
    double residual = 0.0;
    for (int j = 0; j < q.size(); ++j) residual = std::max(residual, std::abs(gtf.e()[m.dofs[j].index] - q[j]));
    for (size_t k = 0; k < gtf.constrainedDeformations().size(); ++k) {
      const int e = gtf.constrainedDeformations()[k];
      if (m.eRole[e] == core::Role::Fixed) residual = std::max(residual, std::abs(gtf.e()[e]));
    }
    EXPECT_LT(residual, 1e-14) << "trial " << trial;
  }
}

// The rotation a sweep prescribes on a spatial orientation node (core/linearization/PrescribedEquilibrium.hpp):
// exact for a rotation about the axis from any initial orientation, and its gradient on the Euler
// parameters against central differences (also away from lambda0, where it is not 2 E(lambda)).
TEST(PrescribedRotation, ValueIsTheAngleAboutTheAxisAndGradientMatchesDifferences) {
  Eigen::Vector4d l0(0.8, -0.3, 0.4, 0.33);
  l0.normalize();
  for (int axis = 1; axis <= 3; ++axis) {
    flexmb::core::PrescribedQuantity p;
    p.coord = 2;
    p.axis = axis;
    p.lambda0 = l0;
    for (double theta : {-1.2, 0.0, 0.3, 2.5}) {
      // q about the global axis, then lambda = q (x) lambda0.
      const double c = std::cos(theta / 2), s = std::sin(theta / 2);
      Eigen::Vector4d q(c, 0, 0, 0);
      q[axis] = s;
      const Eigen::Vector4d l(q[0] * l0[0] - q.tail<3>().dot(l0.tail<3>()), 0, 0, 0);
      Eigen::Vector4d lam;
      lam[0] = l[0];
      lam.tail<3>() = q[0] * l0.tail<3>() + l0[0] * q.tail<3>() + q.tail<3>().cross(l0.tail<3>());
      Eigen::VectorXd x = Eigen::VectorXd::Zero(7);
      x.segment<4>(2) = lam;
      EXPECT_NEAR(p.value(x), theta, 1e-12) << "axis " << axis << " theta " << theta;
      // The rotation matrix agrees (the convention of core::euler::rotation).
      const Eigen::Matrix3d R = flexmb::core::euler::rotation(lam) * flexmb::core::euler::rotation(l0).transpose();
      const int i = axis % 3, j = (axis + 1) % 3;  // the plane normal to the axis
      EXPECT_NEAR(std::atan2(R(j, i), R(i, i)), theta, 1e-12) << "axis " << axis;
      // Gradient at a perturbed, non-normalised lambda.
      x.segment<4>(2) += Eigen::Vector4d(0.01, -0.02, 0.015, 0.005);
      const Eigen::Vector4d g = p.gradient(x);
      for (int k = 0; k < 4; ++k) {
        Eigen::VectorXd xp = x, xm = x;
        xp[2 + k] += 1e-6, xm[2 + k] -= 1e-6;
        EXPECT_NEAR(g[k], (p.value(xp) - p.value(xm)) / 2e-6, 1e-7) << "axis " << axis << " k " << k;
      }
    }
  }
}

// Issue 34 item 10: the advice counts what to change (a closed spatial loop of beams has six
// redundant equations: "release one" was wrong).
TEST(KinematicReportAdvice, CountsTheDeformationsToRelease) {
  flexmb::core::KinematicReport r;
  r.eFixed = 12, r.rank = 6, r.xCalculable = 6;
  r.overdetermined = {"a", "b", "c", "d", "e", "f", "g"};
  const std::string six = flexmb::core::formatReport(r);
  EXPECT_NE(six.find("release (RLSE) 6 of these deformations"), std::string::npos) << six;
  r.eFixed = 7;
  const std::string one = flexmb::core::formatReport(r);
  EXPECT_NE(one.find("release (RLSE) one of these deformations"), std::string::npos) << one;
  r.overdetermined.clear();
  r.eFixed = 3, r.rank = 3, r.underdetermined = {"x", "y"};
  const std::string free = flexmb::core::formatReport(r);
  EXPECT_NE(free.find("FIX or DYNX 3 of these coordinates"), std::string::npos) << free;
}
