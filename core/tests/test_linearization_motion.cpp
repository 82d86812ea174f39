// Linearised equations of a moving system (paper Eq. 15, ref. [13]) against finite differences of
// the nonlinear equations of motion. The total derivatives come from the integrator's own
// equations (EquationsOfMotion::residual, the rhs before the mass solve); each matrix separately
// from the frozen-factor split of R = A^T (M xdd + h - f + D_x^T sigma), A = F_q V:
//   K: A0^T D_x0^T sigma(e(eta), ed0)       G: A(eta)^T (M0 xdd0 + h0 - f(x(eta)) + D_x(eta)^T sigma0)
//   N: A0^T (M(x) xdd + h)(eta) + E_q0^T sigma(e0, ed(eta))   C, D: the same along etad.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cstdio>
#include <optional>
#include <string>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/Stresses.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/tests/Differences.hpp"
#include "core/tests/SampleModels.hpp"

using namespace flexmb;
using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace samples = flexmb::core::samples;

namespace {

// The pieces of the equations of motion at (eta, etad, etadd), computed the plain way.
struct Pieces {
  VectorXd x, xd, xdd, e, ed, sigma, inertial, f;  // inertial = M xdd + h, f = applied loads
  MatrixXd A, Eq;
};

class Probe {
 public:
  Probe(const core::Model& m, const std::optional<MatrixXd>& V) : m_(m), V_(V), gtf_(m), inertia_(m), stresses_(m) {
    gtf_.setRelativeTolerance(1e-15);
  }
  VectorXd q(const VectorXd& eta) const { return V_ ? VectorXd(*V_ * eta) : eta; }
  // Positions only (A, Eq, e) when full is false.
  Pieces at(double t, const VectorXd& eta, const VectorXd& etad, const VectorXd& etadd) {
    Pieces p;
    gtf_.solvePositions(t, q(eta));
    gtf_.firstOrder(V_ ? &*V_ : nullptr, p.A);
    gtf_.deformationFirstOrder(p.A, p.Eq);
    p.x = gtf_.x();
    p.e = gtf_.e();
    gtf_.velocities(t, q(etad), p.xd);
    gtf_.accelerationOffset(t, p.xd, p.xdd);
    p.xdd += p.A * etadd;
    gtf_.deformationRates(p.xd, p.ed);
    stresses_.evaluate(t, p.e, &p.ed, p.sigma);
    inertia_.update(p.x);
    inertia_.multiply(p.xdd, p.inertial);
    inertia_.addVelocityForces(p.x, p.xd, p.inertial);
    p.f = m_.f0;
    for (const auto& tf : m_.timeForces) p.f[tf.index] += tf.f->value(t);
    inertia_.addGravity(p.x, p.f);
    return p;
  }
  // D_x(x)^T s at the last solved configuration.
  VectorXd jacobianTransposed(const VectorXd& s) const {
    VectorXd y = VectorXd::Zero(m_.nx);
    gtf_.addTransposedJacobianProduct(s, y);
    return y;
  }
  VectorXd stress(double t, const VectorXd& e, const VectorXd& ed) const {
    VectorXd s;
    stresses_.evaluate(t, e, &ed, s);
    return s;
  }

 private:
  const core::Model& m_;
  std::optional<MatrixXd> V_;
  core::GeometricTransferFunctions gtf_;
  core::Inertia inertia_;
  core::Stresses stresses_;
};

using core::test::centralDifferences;

double relErr(const MatrixXd& a, const MatrixXd& ref, double floor) { return core::test::relativeError(a, ref, floor); }

struct Case {
  std::string name;
  core::Model model;
  std::optional<MatrixXd> V;
  VectorXd eta, etad, etadd;
  double t;
};

void checkCase(const Case& c) {
  const core::Model& m = c.model;
  core::Linearization lin(m, c.V);
  lin.kinematics().setRelativeTolerance(1e-15);
  core::LinearizedSystem sys;
  lin.inMotion(c.t, c.eta, c.etad, c.etadd, sys);
  const int n = lin.size();
  const double h = 1e-6;

  // Totals from the integrator's equations of motion: R = Mbar etadd - (F_q V)^T (f - h - M g - D_x^T sigma).
  core::EquationsOfMotion eom(m, c.V);
  eom.kinematics().setRelativeTolerance(1e-15);
  auto R = [&](const VectorXd& eta, const VectorXd& etad, const VectorXd& etadd) {
    VectorXd y(2 * n), r;
    y << eta, etad;
    eom.residual(c.t, y, etadd, r);
    return r;
  };
  const MatrixXd dRdq = centralDifferences([&](const VectorXd& v) { return R(v, c.etad, c.etadd); }, c.eta, h);
  const MatrixXd dRdqd = centralDifferences([&](const VectorXd& v) { return R(c.eta, v, c.etadd); }, c.etad, h);
  const MatrixXd dRdqdd = centralDifferences([&](const VectorXd& v) { return R(c.eta, c.etad, v); }, c.etadd, 1e-3);

  // The separate matrices from the frozen-factor split.
  Probe p0(m, c.V), pv(m, c.V);
  const Pieces s0 = p0.at(c.t, c.eta, c.etad, c.etadd);
  const MatrixXd Kfd = centralDifferences(
      [&](const VectorXd& v) {
        return VectorXd(s0.Eq.transpose() * pv.stress(c.t, pv.at(c.t, v, c.etad, c.etadd).e, s0.ed));
      },
      c.eta, h);
  const MatrixXd Gfd = centralDifferences(
      [&](const VectorXd& v) {
        const Pieces s = pv.at(c.t, v, c.etad, c.etadd);
        return VectorXd(s.A.transpose() * (s0.inertial - s.f + pv.jacobianTransposed(s0.sigma)));
      },
      c.eta, h);
  const MatrixXd Nfd = centralDifferences(
      [&](const VectorXd& v) {
        const Pieces s = pv.at(c.t, v, c.etad, c.etadd);
        return VectorXd(s0.A.transpose() * s.inertial + s0.Eq.transpose() * pv.stress(c.t, s0.e, s.ed));
      },
      c.eta, h);
  // Along etad the configuration stays (p0 solves the same positions each time).
  const MatrixXd Cfd = centralDifferences(
      [&](const VectorXd& v) { return VectorXd(s0.A.transpose() * p0.at(c.t, c.eta, v, c.etadd).inertial); }, c.etad,
      h);
  const MatrixXd Dfd = centralDifferences(
      [&](const VectorXd& v) {
        return VectorXd(s0.Eq.transpose() * p0.stress(c.t, s0.e, p0.at(c.t, c.eta, v, c.etadd).ed));
      },
      c.etad, h);

  const double scaleQ = dRdq.norm(), scaleQd = std::max(dRdqd.norm(), 1e-12 * scaleQ);
  const double eK = relErr(sys.K, Kfd, 1e-9 * scaleQ), eG = relErr(sys.G, Gfd, 1e-9 * scaleQ),
               eN = relErr(sys.N, Nfd, 1e-9 * scaleQ), eC = relErr(sys.C, Cfd, 1e-9 * scaleQd),
               eD = relErr(sys.D, Dfd, 1e-9 * scaleQd), eM = relErr(sys.M, dRdqdd, 1e-12);
  const double eQ = relErr(sys.K + sys.N + sys.G, dRdq, 1e-12), eQd = relErr(sys.C + sys.D, dRdqd, 1e-12 * scaleQ);
  std::printf("  %-34s |K| %.2e |G| %.2e |N| %.2e |C| %.2e |D| %.2e\n", c.name.c_str(), sys.K.norm(), sys.G.norm(),
              sys.N.norm(), sys.C.norm(), sys.D.norm());
  std::printf("  %-34s rel. errors: K %.1e G %.1e N %.1e C %.1e D %.1e M %.1e; K+N+G %.1e C+D %.1e; |Q| %.1e\n", "", eK,
              eG, eN, eC, eD, eM, eQ, eQd, sys.Q.norm());
  EXPECT_LT(eK, 1e-6) << c.name;
  EXPECT_LT(eG, 1e-6) << c.name;
  EXPECT_LT(eN, 1e-6) << c.name;
  EXPECT_LT(eC, 1e-6) << c.name;
  EXPECT_LT(eD, 1e-6) << c.name;
  EXPECT_LT(eM, 1e-8) << c.name;
  EXPECT_LT(eQ, 1e-6) << c.name;
  EXPECT_LT(eQd, 1e-6) << c.name;
  // The moving-state terms are exercised (not trivially zero).
  EXPECT_GT(sys.N.norm(), 1e-4 * scaleQ) << c.name;
  EXPECT_GT(sys.C.norm(), 1e-6 * scaleQd) << c.name;
  // The residual of Eq. 13 is what an arbitrary (off-trajectory) state leaves: R at etadd.
  EXPECT_LT((sys.Q + R(c.eta, c.etad, c.etadd)).norm(), 1e-8 * std::max(1.0, sys.Q.norm())) << c.name;
}

VectorXd pattern(int n, double lo, double hi, int seed) {
  VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = lo + (hi - lo) * (0.5 + 0.5 * std::sin(1.7 * (i + 1) * seed + 0.3 * seed));
  return v;
}

}  // namespace

TEST(LinearizationInMotion, MatricesMatchFiniteDifferencesOfTheEquationsOfMotion) {
  std::vector<Case> cases;
  {
    // Rheonomic, damped, gravity, flexible: all terms present.
    core::Model m = samples::swungArm();
    const int n = m.numDofs();
    VectorXd eta = 1e-3 * pattern(n, -1, 1, 1), etad = 0.2 * pattern(n, -1, 1, 2), etadd = 30.0 * pattern(n, -1, 1, 3);
    cases.push_back({"swung arm (input hinge, damping)", m, std::nullopt, eta, etad, etadd, 0.37});
  }
  {
    core::Model m = samples::manipulator();
    const int n = m.numDofs();
    core::GeometricTransferFunctions g(m);
    VectorXd q0 = g.initialDofs();
    VectorXd eta = q0 + 1e-3 * pattern(n, -1, 1, 4), etad = pattern(n, -2, 2, 5), etadd = 50.0 * pattern(n, -1, 1, 6);
    cases.push_back({"manipulator (full)", m, std::nullopt, eta, etad, etadd, 0.21});
    // A reduced model: q = V eta with q0 in the span of V.
    MatrixXd B(n, 5);
    B.col(0) = q0;
    for (int j = 1; j < 5; ++j) B.col(j) = pattern(n, -1, 1, 10 + j);
    const MatrixXd V = Eigen::HouseholderQR<MatrixXd>(B).householderQ() * MatrixXd::Identity(n, 5);
    const VectorXd e0 = V.transpose() * q0;
    cases.push_back({"manipulator (reduced, 5 columns)", m, V, e0 + 1e-3 * pattern(5, -1, 1, 7), pattern(5, -2, 2, 8),
                     40.0 * pattern(5, -1, 1, 9), 0.33});
  }
  {
    core::Model m = samples::fourBar();
    const int n = m.numDofs();
    core::GeometricTransferFunctions g(m);
    cases.push_back({"four-bar (rigid, closed loop)", m, std::nullopt, g.initialDofs() + 0.1 * pattern(n, -1, 1, 11),
                     pattern(n, 2, 3, 12), pattern(n, -5, 5, 13), 0.0});
  }
  for (const Case& c : cases) checkCase(c);
}

TEST(LinearizationInMotion, AtRestEqualsTheStaticLinearization) {
  // With etad = etadd = 0 and a time-independent model, C = N = 0 (Eq. 16a) and the other matrices
  // are those of atRest.
  const core::Model m = samples::straightGuidance();
  core::Linearization lin(m);
  const VectorXd eta = 1e-3 * pattern(lin.size(), -1, 1, 3), zero = VectorXd::Zero(lin.size());
  core::LinearizedSystem moving, rest;
  lin.inMotion(0.0, eta, zero, zero, moving);
  VectorXd f;
  lin.appliedForces(0.0, 0.0, f);
  lin.atRest(0.0, eta, f, rest);
  EXPECT_EQ(moving.C.norm(), 0.0);
  EXPECT_EQ(moving.N.norm(), 0.0);
  EXPECT_LT((moving.K - rest.K).norm(), 1e-12 * rest.K.norm());
  EXPECT_LT((moving.G - rest.G).norm(), 1e-12 * rest.K.norm());
  EXPECT_LT((moving.M - rest.M).norm(), 1e-12 * rest.M.norm());
}

TEST(LinearizationInMotion, StaticTangentIncludesGravityLoadStiffness) {
  // Distributed masses under gravity: their consistent nodal loads turn with the elements, so
  // -dQ/dq = K + G needs the load stiffness -A^T (dg/dx) A (the static Newton tangent).
  const core::Model m = samples::gravityCantilever();
  core::Linearization lin(m);
  lin.kinematics().setRelativeTolerance(1e-15);
  const VectorXd eta = 1e-2 * pattern(lin.size(), -1, 1, 5);
  auto Q = [&](const VectorXd& v) {
    VectorXd f, q;
    lin.kinematics().solvePositions(0.0, v);
    lin.appliedForces(0.0, 0.0, f);  // gravity at this configuration
    lin.staticForces(0.0, v, f, q);
    return q;
  };
  const MatrixXd fd = -centralDifferences(Q, eta, 1e-6);
  VectorXd f;
  lin.kinematics().solvePositions(0.0, eta);
  lin.appliedForces(0.0, 0.0, f);
  core::LinearizedSystem sys;
  lin.atRest(0.0, eta, f, sys);
  const double err = relErr(sys.K + sys.G, fd, 1e-12);
  std::printf("  gravity-loaded cantilever: |K + G - FD| / |FD| = %.1e\n", err);
  EXPECT_LT(err, 1e-7);
}
