// The equations of motion (paper Eq. 13) on the sample models: the projected form
// Mbar qdd = F_q^T (f - h - M g - D_x^T sigma) and the sparse nodal saddle-point form give the same
// accelerations at moving states; without loads, damping and inputs the accelerations conserve the
// energy T + V (its rate along the motion, by central differences in time, vanishes); the residual
// is linear in the accelerations with Mbar = F_q^T M F_q.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/tests/Energy.hpp"
#include "core/tests/SampleModels.hpp"

using namespace flexmb;
using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace samples = flexmb::core::samples;

namespace {

// A moving state near the initial one: hinge angles (large rotations) moved by up to 0.3 rad,
// the other coordinates by up to qScale, rates up to 1 (hinges) and qdScale.
VectorXd movingState(core::EquationsOfMotion& eom, double qScale, double qdScale, std::mt19937& rng) {
  const core::Model& m = eom.model();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VectorXd y = eom.initialState();
  const int n = eom.size();
  for (int j = 0; j < n; ++j) {
    const auto& d = m.dofs[j];
    const core::ElementEntry* el = d.isDeformation ? &m.elements[m.eOwnerElement[d.index]] : nullptr;
    const bool large = el && el->type->isLargeRotation(d.index - el->firstDef);
    y[j] += (large ? 0.3 : qScale) * u(rng);
    y[n + j] = (large ? 1.0 : qdScale) * u(rng);
  }
  return y;
}

// T + V: kinetic energy and the elastic energy of the deformations that carry stress.
double energy(const core::Model& m, core::EquationsOfMotion& eom, core::Inertia& inertia, double t, const VectorXd& y) {
  core::StateOutputs s;
  eom.outputs(t, y, s);
  return core::test::totalEnergy(m, inertia, s);
}

}  // namespace

TEST(EquationsOfMotion, ProjectedAndSaddlePointFormsGiveTheSameAccelerations) {
  std::mt19937 rng(17);
  for (const auto& sample : samples::allSamples()) {
    SCOPED_TRACE(sample.name);
    const core::Model m = sample.build();
    core::EquationsOfMotion projected(m, std::nullopt, core::DynamicsForm::Projected);
    core::EquationsOfMotion saddle(m, std::nullopt, core::DynamicsForm::SaddlePoint);
    ASSERT_EQ(projected.form(), core::DynamicsForm::Projected);
    ASSERT_EQ(saddle.form(), core::DynamicsForm::SaddlePoint);
    projected.kinematics().setRelativeTolerance(1e-15);
    saddle.kinematics().setRelativeTolerance(1e-15);
    const int n = projected.size();
    double worst = 0.0;
    for (int trial = 0; trial < 3; ++trial) {
      const VectorXd y = movingState(projected, m.spatial ? 1e-5 : 1e-3, m.spatial ? 0.2 : 0.5, rng);
      const double t = m.settings.t0 + 0.1 * trial;
      VectorXd a(2 * n), b(2 * n);
      projected.rhs(t, y, a);
      saddle.rhs(t, y, b);
      EXPECT_EQ(a.head(n), y.tail(n));  // d(eta)/dt = etad
      worst = std::max(worst, (a.tail(n) - b.tail(n)).lpNorm<Eigen::Infinity>() /
                                  std::max(a.tail(n).lpNorm<Eigen::Infinity>(), 1e-300));
    }
    std::printf("  %-30s %2d DOF: largest relative difference %.1e\n", sample.name.c_str(), n, worst);
    EXPECT_LT(worst, 1e-8);
  }
}

TEST(EquationsOfMotion, ResidualIsMbarTimesTheAccelerationsMinusTheForces) {
  // R(etadd) = Mbar etadd - Q is linear in etadd with Mbar = F_q^T M F_q, and vanishes at rhs's
  // accelerations.
  std::mt19937 rng(5);
  for (const auto& sample : samples::allSamples()) {
    SCOPED_TRACE(sample.name);
    const core::Model m = sample.build();
    core::EquationsOfMotion eom(m, std::nullopt, core::DynamicsForm::Projected);
    eom.kinematics().setRelativeTolerance(1e-15);
    const int n = eom.size();
    const VectorXd y = movingState(eom, m.spatial ? 1e-5 : 1e-3, 0.3, rng);
    const double t = m.settings.t0 + 0.05;
    VectorXd dydt(2 * n), R0, Rj, Ra;
    eom.rhs(t, y, dydt);
    eom.residual(t, y, dydt.tail(n), Ra);
    eom.residual(t, y, VectorXd::Zero(n), R0);
    EXPECT_LT(Ra.norm(), 1e-9 * std::max(1.0, R0.norm()));
    // Columns of Mbar from the residual, against F_q^T M F_q assembled densely.
    MatrixXd Mres(n, n);
    for (int j = 0; j < n; ++j) {
      eom.residual(t, y, VectorXd::Unit(n, j), Rj);
      Mres.col(j) = Rj - R0;
    }
    core::GeometricTransferFunctions& gtf = eom.kinematics();
    gtf.solvePositions(t, y.head(n));
    MatrixXd Fq;
    gtf.firstOrder(nullptr, Fq);
    core::Inertia inertia(m);
    inertia.update(gtf.x());
    const MatrixXd Mbar = Fq.transpose() * inertia.dense() * Fq;
    EXPECT_LT((Mres - Mbar).norm(), 1e-9 * Mbar.norm());
  }
}

TEST(EquationsOfMotion, AccelerationsConserveTheEnergyOfConservativeSamples) {
  // Without damping, inputs and loads dE/dt = 0 for E = T + V: dE/dt by central differences of E
  // over the states a time step h before and after (q +- h qd + h^2/2 qdd, qd +- h qdd), against
  // the power flowing between T and V (which the check also measures).
  std::mt19937 rng(23);
  struct Case {
    const char* name;
    core::Model (*build)();
  };
  for (const Case& c :
       {Case{"slider-crank (flexible rod)", samples::sliderCrankS95},
        Case{"four-bar (rigid)", [] { return samples::fourBar(); }}, Case{"cantilever", samples::cantilever}}) {
    SCOPED_TRACE(c.name);
    const core::Model m = c.build();
    core::EquationsOfMotion eom(m), probe(m);
    eom.kinematics().setRelativeTolerance(1e-15);
    probe.kinematics().setRelativeTolerance(1e-15);
    core::Inertia inertia(m);
    const int n = eom.size();
    for (int trial = 0; trial < 3; ++trial) {
      const VectorXd y = movingState(eom, 1e-3, 0.3, rng);
      VectorXd dydt(2 * n);
      eom.rhs(0.0, y, dydt);
      const VectorXd qd = y.tail(n), qdd = dydt.tail(n);
      const double h = 2e-7;
      auto at = [&](double s) {
        VectorXd ys(2 * n);
        ys << y.head(n) + s * qd + 0.5 * s * s * qdd, qd + s * qdd;
        return energy(m, probe, inertia, s, ys);
      };
      const double E0 = energy(m, probe, inertia, 0.0, y);
      // The quadratic path leaves the motion at O(s^3), so the central difference errs by O((omega h)^2)
      // of the power; Richardson's combination of h and h/2 removes that term (the cantilever's axial
      // modes reach omega ~ 7e4 rad/s).
      auto rate = [&](double hh) { return (at(hh) - at(-hh)) / (2 * hh); };
      const double dEdt = (4 * rate(h / 2) - rate(h)) / 3;
      // The scale of the power: the rate of the kinetic energy alone at qdd = 0 minus at qdd.
      VectorXd yT(2 * n);
      auto kinetic = [&](double s, const VectorXd& acc) {
        yT << y.head(n) + s * qd + 0.5 * s * s * acc, qd + s * acc;
        core::StateOutputs o;
        probe.outputs(s, yT, o);
        inertia.update(o.x);
        return inertia.kineticEnergy(o.xd);
      };
      const double power = std::abs((kinetic(h, qdd) - kinetic(-h, qdd)) / (2 * h)) + E0 * qd.lpNorm<Eigen::Infinity>();
      std::printf("  %-28s E %.3e, dE/dt %.2e, power scale %.2e\n", c.name, E0, dEdt, power);
      EXPECT_LT(std::abs(dEdt), 1e-6 * power);
    }
  }
}
