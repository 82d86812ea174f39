// Evaluators sharing one Workspace (core/dynamics/Workspace.hpp) compute the same bits as evaluators with a
// workspace each: on every sample model, equations of motion (integrating and probing), a moving
// linearisation, result quantities and bare kinematics are called interleaved, as a simulation
// interleaves them (ode45's stages, output times, an implicit integrator's Jacobian, anchors and
// restarts), once on one shared workspace and once on separate ones; every result must be equal
// bit for bit. Each evaluator keeps its own warm start (configuration, restart points, predictor,
// element Jacobians, factorisations), so the order of calls on the shared workspace changes nothing.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/ResultQuantities.hpp"
#include "core/dynamics/Workspace.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/tests/SampleModels.hpp"

using namespace flexmb;
using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace samples = flexmb::core::samples;

namespace {

// Equal sizes and equal bits (NaN included: a difference in any bit fails).
::testing::AssertionResult sameBits(const MatrixXd& a, const MatrixXd& b, const char* what) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << what << ": sizes " << a.rows() << "x" << a.cols() << " and " << b.rows()
                                         << "x" << b.cols();
  if (a.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) != 0)
    return ::testing::AssertionFailure() << what << ": differ by up to " << (a - b).cwiseAbs().maxCoeff();
  return ::testing::AssertionSuccess();
}

// The evaluators of one analysis: eom integrates, probe gives output quantities, lin linearises in
// motion (an implicit integrator's Jacobian), rq gives the result quantities, gtf solves positions;
// each on the workspace of the same place in ws (all one, or five apart).
struct Evaluators {
  Evaluators(const std::array<core::Workspace*, 5>& ws, const std::optional<MatrixXd>& basis, core::DynamicsForm form)
      : eom(*ws[0], basis, form),
        probe(*ws[1], basis, form),
        lin(*ws[2], basis),
        rq(*ws[3]),
        gtf(ws[4]->kinematics()) {}
  core::EquationsOfMotion eom, probe;
  core::Linearization lin;
  core::ResultQuantities rq;
  core::GeometricTransferFunctions gtf;
};

// Calls every evaluator of `e` in one fixed interleaved sequence of states near the initial one
// (eom moving along its velocity, as between integrator stages, so the kinematic predictor and its
// curvature term are used) and records every result in order.
std::vector<MatrixXd> run(Evaluators& e, const core::Model& m, bool withLinearization) {
  std::vector<MatrixXd> out;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = e.eom.size();
  VectorXd y = e.eom.initialState(), dy(2 * n);
  for (int j = 0; j < n; ++j) y[n + j] = 0.05 * u(rng);
  const double t0 = m.settings.t0;
  for (int i = 0; i < 24; ++i) {
    const double t = t0 + 1e-3 * i;
    y.head(n) += 1e-3 * y.tail(n);  // an ode45-like advance
    e.eom.rhs(t, y, dy);
    out.push_back(dy);
    if (i % 5 == 4) e.eom.kinematics().setAnchor();
    if (i % 7 == 6) e.eom.kinematics().restartFromAnchor();
    if (i % 2 == 1) {  // an output time, at a state of its own
      VectorXd yp = y;
      for (int j = 0; j < n; ++j) yp[j] += 1e-4 * u(rng);
      core::StateOutputs s;
      e.probe.outputs(t, yp, s);
      for (const VectorXd* v : {&s.x, &s.xd, &s.xdd, &s.e, &s.ed, &s.edd, &s.sig}) out.push_back(*v);
      // The result quantities of that output state.
      VectorXd q;
      e.probe.dofs(yp.head(n), q);
      e.rq.setState(t, q);
      VectorXd sigma, fxt;
      e.rq.forces(t, 0.0, s, VectorXd(), sigma, fxt);
      out.push_back(sigma);
      out.push_back(fxt);
      MatrixXd D;
      e.rq.jacobian(D);
      out.push_back(D);
    }
    if (withLinearization && i % 3 == 2) {  // the implicit integrator's Jacobian at the eom state
      core::LinearizedSystem sys;
      e.lin.inMotion(t, y.head(n), y.tail(n), dy.tail(n), sys);
      for (const MatrixXd* a : {&sys.M, &sys.K, &sys.G, &sys.D, &sys.C, &sys.N}) out.push_back(*a);
      out.push_back(sys.Q);
    }
    if (i % 4 == 3) {  // bare kinematics at yet another configuration
      VectorXd q;
      e.eom.dofs(y.head(n), q);
      for (int j = 0; j < q.size(); ++j) q[j] += 1e-4 * u(rng);
      e.gtf.solvePositions(t, q);
      out.push_back(e.gtf.x());
      out.push_back(e.gtf.e());
      out.push_back(VectorXd::Constant(1, static_cast<double>(e.gtf.lastIterations())));
    }
  }
  // The same number of fresh pivotings: each factorisation's history is its evaluator's own.
  out.push_back(VectorXd::Constant(1, static_cast<double>(e.eom.kinematics().pivotings())));
  out.push_back(VectorXd::Constant(1, static_cast<double>(e.gtf.pivotings())));
  return out;
}

void expectSameAsSeparate(const core::Model& m, const std::optional<MatrixXd>& basis, core::DynamicsForm form,
                          bool withLinearization) {
  core::Workspace shared(m);
  Evaluators together({&shared, &shared, &shared, &shared, &shared}, basis, form);
  core::Workspace a(m), b(m), c(m), d(m), e(m);  // separate: as before the workspace was shared
  Evaluators apart({&a, &b, &c, &d, &e}, basis, form);
  const std::vector<MatrixXd> r1 = run(together, m, withLinearization);
  const std::vector<MatrixXd> r2 = run(apart, m, withLinearization);
  ASSERT_EQ(r1.size(), r2.size());
  for (size_t k = 0; k < r1.size(); ++k) ASSERT_TRUE(sameBits(r1[k], r2[k], "result")) << "result " << k;
}

}  // namespace

TEST(Workspace, SharedEvaluatorsGiveTheSameBitsAsSeparateOnes) {
  for (const auto& sample : samples::allSamples()) {
    SCOPED_TRACE(sample.name);
    const core::Model m = sample.build();
    if (m.numDofs() == 0) continue;
    expectSameAsSeparate(m, std::nullopt, core::DynamicsForm::Automatic, true);
    expectSameAsSeparate(m, std::nullopt, core::DynamicsForm::Projected, false);
  }
}

TEST(Workspace, SharedReducedEvaluatorsGiveTheSameBitsAsSeparateOnes) {
  const core::Model m = samples::straightGuidance();
  const int nq = m.numDofs();
  MatrixXd V = MatrixXd::Identity(nq, 3);
  V.col(0).setConstant(1.0 / std::sqrt(double(nq)));  // a dense column: every q moves
  expectSameAsSeparate(m, V, core::DynamicsForm::Automatic, true);
}

TEST(Workspace, KinematicsOnOneWorkspaceShareItsStructureNotTheirState) {
  const core::Model m = samples::fourBar();
  core::KinematicsWorkspace ws(m);
  core::GeometricTransferFunctions a(ws), b(ws);
  EXPECT_EQ(&a.calculableCoords(), &b.calculableCoords());  // one structure
  EXPECT_EQ(&a.calculableCoords(), &ws.structure().calcCoords);
  core::GeometricTransferFunctions alone(m);
  EXPECT_NE(&alone.calculableCoords(), &ws.structure().calcCoords);
  // Different configurations, kept apart: solving b does not move a.
  VectorXd qa = a.initialDofs(), qb = qa;
  qb.array() += 0.2;
  a.solvePositions(0.0, qa);
  const VectorXd xa = a.x();
  b.solvePositions(0.0, qb);
  EXPECT_TRUE(sameBits(a.x(), xa, "a after b"));
  EXPECT_GT((b.x() - xa).cwiseAbs().maxCoeff(), 1e-3);
}
