// Geometric transfer functions (paper Eq. 7-8) of every sample model against finite differences of
// the kinematic solve itself: F_q = dx/dq, the velocities xd = F_q qd + x_t (rheonomic inputs
// included), the convective accelerations g = (F_qq qd) qd + ... (xdd at qdd = 0), and the
// deformation rates of the degrees of freedom.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/tests/SampleModels.hpp"

using namespace flexmb;
using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace samples = flexmb::core::samples;

namespace {

// A configuration away from the initial one: hinge angles (large rotations) turned by up to 0.5 rad,
// deformations and coordinates moved by up to 1e-3, and a rate of the same pattern.
void sampleState(const core::Model& m, const VectorXd& q0, VectorXd& q, VectorXd& qd) {
  q = q0;
  qd.resize(q0.size());
  for (int j = 0; j < q.size(); ++j) {
    const auto& d = m.dofs[j];
    const core::ElementEntry* el = d.isDeformation ? &m.elements[m.eOwnerElement[d.index]] : nullptr;
    const bool large = el && el->type->isLargeRotation(d.index - el->firstDef);
    const double s = std::sin(1.3 * j + 0.4);
    q[j] += (large ? 0.5 : 1e-3) * s;
    qd[j] = (large ? 2.0 : 0.05) * std::cos(0.7 * j + 0.2);
  }
}

}  // namespace

TEST(TransferFunctions, MatchFiniteDifferencesOfTheKinematicSolveOnEverySample) {
  for (const auto& sample : samples::allSamples()) {
    SCOPED_TRACE(sample.name);
    const core::Model m = sample.build();
    core::GeometricTransferFunctions gtf(m);
    gtf.setRelativeTolerance(1e-15);
    const int nq = gtf.nq();
    VectorXd q, qd;
    sampleState(m, gtf.initialDofs(), q, qd);
    const double t = m.settings.t0 + 0.3 * (m.settings.tEnd - m.settings.t0);
    auto positions = [&](double tt, const VectorXd& qq) {
      gtf.solvePositions(tt, qq);
      return VectorXd(gtf.x());
    };

    // F_q against central differences of x(q), column by column.
    gtf.solvePositions(t, q);
    MatrixXd Fq;
    gtf.firstOrder(nullptr, Fq);
    ASSERT_EQ(Fq.rows(), m.nx);
    ASSERT_EQ(Fq.cols(), nq);
    const double h = 1e-6;
    double errFq = 0.0;
    for (int j = 0; j < nq; ++j) {
      VectorXd qp = q, qm = q;
      qp[j] += h;
      qm[j] -= h;
      const VectorXd fd = (positions(t, qp) - positions(t, qm)) / (2 * h);
      errFq = std::max(errFq, (Fq.col(j) - fd).norm() / std::max(fd.norm(), 1e-12));
    }
    EXPECT_LT(errFq, 1e-6);

    // xd = F_q qd + x_t, x_t by differences in time at fixed q (rheonomic inputs).
    const VectorXd xt = (positions(t + h, q) - positions(t - h, q)) / (2 * h);
    gtf.solvePositions(t, q);
    VectorXd xd;
    gtf.velocities(t, qd, xd);
    const double errXd = (xd - (Fq * qd + xt)).norm() / std::max(xd.norm(), 1e-12);
    EXPECT_LT(errXd, 1e-7);

    // The degrees of freedom's deformation rates are qd; fixed deformations do not change.
    VectorXd ed;
    gtf.deformationRates(xd, ed);
    for (int j = 0; j < nq; ++j) {
      if (m.dofs[j].isDeformation) {
        EXPECT_NEAR(ed[m.dofs[j].index], qd[j], 1e-9 * std::max(1.0, std::abs(qd[j])));
      }
    }
    for (int k = 0; k < m.ne; ++k) {
      if (m.eRole[k] == core::Role::Fixed) {
        EXPECT_NEAR(ed[k], 0.0, 1e-9 * std::max(1.0, xd.norm()));
      }
    }

    // g = xdd at qdd = 0: the change of xd along the motion (q + s qd, t + s).
    VectorXd g;
    gtf.accelerationOffset(t, xd, g);
    auto velocityAlong = [&](double s) {
      gtf.solvePositions(t + s, q + s * qd);
      VectorXd v;
      gtf.velocities(t + s, qd, v);
      return v;
    };
    const double hs = 1e-5;
    const VectorXd gfd = (velocityAlong(hs) - velocityAlong(-hs)) / (2 * hs);
    const double errG = (g - gfd).norm() / std::max(g.norm(), 1e-6 * xd.norm());
    EXPECT_LT(errG, 1e-5);
    std::printf("  %-30s %2d DOF: F_q %.1e, xd %.1e, g %.1e (|g| %.2e)\n", sample.name.c_str(), nq, errFq, errXd, errG,
                g.norm());
  }
}
