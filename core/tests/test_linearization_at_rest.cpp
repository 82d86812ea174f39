// The linearisation at rest (paper Eq. 16) of the loaded sample models against finite differences
// and an independent assembly: Kbar = E_q^T S E_q as the change of E_q0^T sigma(e(q)), Gbar as the
// change of F_q(q)^T (D_x(q)^T sigma~0 - f(x(q))) (sigma~0: elastic and reaction stresses, f the
// loads following the configuration: gravity on distributed masses, moments on spatial nodes),
// Kbar + Gbar as -dQ/dq of the generalised forces, and Mbar = F_q^T M F_q.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/Stresses.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/tests/Differences.hpp"
#include "core/tests/SampleModels.hpp"

using namespace flexmb;
using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace samples = flexmb::core::samples;

namespace {

using core::test::centralDifferences;

double relErr(const MatrixXd& a, const MatrixXd& ref, double floor) { return core::test::relativeError(a, ref, floor); }

}  // namespace

TEST(LinearizationAtRest, MatricesMatchFiniteDifferencesOnLoadedSamples) {
  // geometric: G is not zero. The manipulator is an open chain without loads whose deformations
  // are all degrees of freedom or fixed: E_q is constant there, so Q = -E_q^T sigma(e(q)) has no
  // geometric part and G must vanish (its servo references exercise K at t = 0.2).
  struct Case {
    const char* name;
    core::Model (*build)();
    double t;
    bool geometric;
  };
  for (const Case& c : {Case{"cantilever (tip load)", samples::cantilever, 0.0, true},
                        Case{"portal (side load)", samples::portal, 0.0, true},
                        Case{"gravity cantilever", samples::gravityCantilever, 0.0, true},
                        Case{"manipulator (servo references)", samples::manipulator, 0.2, false},
                        Case{"straight guidance", samples::straightGuidance, 0.05, true},
                        Case{"cross-spring pivot (spatial)", samples::crossSpringPivot, 0.0, true}}) {
    SCOPED_TRACE(c.name);
    const core::Model m = c.build();
    core::Linearization lin(m);
    core::GeometricTransferFunctions& gtf = lin.kinematics();
    gtf.setRelativeTolerance(1e-15);
    core::Stresses stresses(m);
    const int n = lin.size();
    VectorXd eta = gtf.initialDofs();
    for (int j = 0; j < n; ++j) eta[j] += (m.spatial ? 1e-4 : 1e-3) * std::sin(2.1 * j + 0.5);
    // The loads at full load factor where the model is (they follow the configuration).
    auto loadsAt = [&](const VectorXd& v) {
      gtf.solvePositions(c.t, v);
      VectorXd f;
      lin.appliedForces(c.t, 1.0, f);
      return f;
    };
    const VectorXd f0 = loadsAt(eta);
    core::LinearizedSystem sys;
    lin.atRest(c.t, eta, f0, sys);
    ASSERT_EQ(sys.K.rows(), n);

    // Frozen pieces at eta.
    gtf.solvePositions(c.t, eta);
    MatrixXd A0, E0;
    gtf.firstOrder(nullptr, A0);
    gtf.deformationFirstOrder(A0, E0);
    const double h = 1e-7;
    const MatrixXd Kfd = centralDifferences(
        [&](const VectorXd& v) {
          gtf.solvePositions(c.t, v);
          VectorXd s;
          stresses.evaluate(c.t, gtf.e(), nullptr, s);
          return VectorXd(E0.transpose() * s);
        },
        eta, h);
    const MatrixXd Gfd = centralDifferences(
        [&](const VectorXd& v) {
          const VectorXd f = loadsAt(v);
          MatrixXd A;
          gtf.firstOrder(nullptr, A);
          VectorXd r = VectorXd::Zero(m.nx);
          gtf.addTransposedJacobianProduct(sys.sigma, r);
          return VectorXd(A.transpose() * (r - f));
        },
        eta, h);
    const MatrixXd Tfd = -centralDifferences(
        [&](const VectorXd& v) {
          const VectorXd f = loadsAt(v);
          VectorXd Q;
          lin.staticForces(c.t, v, f, Q);
          return Q;
        },
        eta, h);
    gtf.solvePositions(c.t, eta);
    core::Inertia inertia(m);
    inertia.update(gtf.x());
    const MatrixXd Mref = A0.transpose() * inertia.dense() * A0;

    const double scale = sys.K.norm();
    const double eK = relErr(sys.K, Kfd, 1e-9 * scale), eG = relErr(sys.G, Gfd, 1e-9 * scale),
                 eT = relErr(sys.K + sys.G, Tfd, 1e-9 * scale), eM = relErr(sys.M, Mref, 1e-300);
    std::printf("  %-32s %2d DOF |K| %.1e |G| %.1e: K %.1e G %.1e K+G %.1e M %.1e\n", c.name, n, sys.K.norm(),
                sys.G.norm(), eK, eG, eT, eM);
    EXPECT_LT(eK, 1e-6);
    EXPECT_LT(eG, 1e-5);
    EXPECT_LT(eT, 1e-6);
    EXPECT_LT(eM, 1e-12);
    if (c.geometric)
      EXPECT_GT(sys.G.norm(), 1e-9 * scale);  // the loads and stresses are exercised
    else
      EXPECT_LT(sys.G.norm(), 1e-9 * scale);
    EXPECT_EQ(sys.C.norm(), 0.0);  // Eq. 16a
    EXPECT_EQ(sys.N.norm(), 0.0);
  }
}

// Kbar and Dbar are taken through the deformations (E_q^T S E_q, unit rows for DYNE, the calculable
// rows dense) where that is cheaper than the nodal projection F_q^T K_x F_q: both must equal the
// dense product with E_q = D_x F_q from the kinematics, and the Newton tangent and the force scale's
// diagonal must agree with atRest, on every sample, whichever way each is taken.
TEST(LinearizationAtRest, StiffnessThroughDeformationsEqualsDenseProduct) {
  bool mixedRoute = false;  // a sample with calculable rows among few enough for the deformation route
  for (const auto& sample : samples::allSamples()) {
    SCOPED_TRACE(sample.name);
    const core::Model m = sample.build();
    core::Linearization lin(m);
    core::GeometricTransferFunctions& gtf = lin.kinematics();
    core::Stresses stresses(m);
    const int n = lin.size();
    VectorXd eta = gtf.initialDofs();
    for (int j = 0; j < n; ++j) eta[j] += (m.spatial ? 1e-4 : 1e-3) * std::sin(1.7 * j + 0.3);
    const double t = 0.0;
    gtf.solvePositions(t, eta);
    VectorXd f;
    lin.appliedForces(t, 1.0, f);
    core::LinearizedSystem sys;
    lin.atRest(t, eta, f, sys);
    MatrixXd A0, E0;
    gtf.firstOrder(nullptr, A0);
    gtf.deformationFirstOrder(A0, E0);
    MatrixXd S = MatrixXd::Zero(m.ne, m.ne), Sd = S;
    int calculable = 0;
    for (const auto& E : m.elements) {
      const int nd = E.impl->numDeformations();
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) {
          if (!stresses.isActive(E.firstDef + i) || !stresses.isActive(E.firstDef + j)) continue;
          if (E.hasStiffness) S(E.firstDef + i, E.firstDef + j) = E.S(i, j);
          if (E.hasDamping) Sd(E.firstDef + i, E.firstDef + j) = E.Sd(i, j);
        }
    }
    for (int k = 0; k < m.ne; ++k) calculable += stresses.isActive(k) && m.eRole[k] == core::Role::Calculable;
    mixedRoute = mixedRoute || (calculable > 0 && 4 * calculable <= m.nx);
    const MatrixXd Kref = E0.transpose() * S * E0, Dref = E0.transpose() * Sd * E0;
    if (sys.D.size() == 0) sys.D.setZero(n, n);  // no damping: left empty (zero)
    EXPECT_EQ(sys.D.isZero(0.0), Dref.isZero(0.0));
    const double scale = std::max(Kref.norm(), 1e-300);
    VectorXd Q, diagonal;
    MatrixXd T;
    lin.tangent(t, eta, f, Q, T);
    lin.stiffnessDiagonal(t, eta, f, Q, diagonal);
    MatrixXd Tref = sys.K + sys.G;
    if (sys.Gskew.size()) Tref += sys.Gskew;
    std::printf(
        "  %-30s %3d DOF, %3d calculable stressed deformations of %3d, nx %3d: K %.1e D %.1e T %.1e diag %.1e\n",
        sample.name.c_str(), n, calculable, m.ne, m.nx, (sys.K - Kref).norm() / scale,
        (sys.D - Dref).norm() / std::max(Dref.norm(), 1e-300), (T - Tref).norm() / scale,
        (diagonal - Kref.diagonal()).norm() / scale);
    EXPECT_LT((sys.K - Kref).norm(), 1e-11 * scale);
    EXPECT_LT((sys.D - Dref).norm(), 1e-11 * std::max(Dref.norm(), 1e-300));
    EXPECT_LT((T - Tref).norm(), 1e-11 * std::max(Tref.norm(), 1e-300));
    EXPECT_LT((diagonal - Kref.diagonal()).norm(), 1e-11 * scale);
    EXPECT_EQ((sys.K - sys.K.transpose()).norm(), 0.0);
  }
  EXPECT_TRUE(mixedRoute) << "no sample takes the deformation route with calculable rows";
}
