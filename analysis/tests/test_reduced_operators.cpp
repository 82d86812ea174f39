// Reduced operators (issue 33): the fitted reduced model against Eq. 19 at states it was not trained
// on, its derivatives against finite differences, energy conservation, and the fallback outside
// the trained range.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <string>

#include "analysis/OperatorDynamics.hpp"
#include "analysis/OperatorPolicy.hpp"
#include "analysis/OperatorTraining.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/Statics.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/OperatorFile.hpp"
#include "solvers/ChebyshevBasis.hpp"
#include "solvers/Ode45.hpp"

using namespace flexmb;

namespace {

std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

Eigen::MatrixXd modalBasis(const core::Model& m, int modes) {
  analysis::ReductionOptions o;
  o.method = "modal";
  o.modes = modes;
  return analysis::buildBasis(m, o).V;
}

// One trained guidance for the tests of this file (training costs a fraction of a second).
struct Guidance {
  core::Model model = io::readDatFile(dat("straight_guidance.dat"));
  Eigen::MatrixXd V = modalBasis(model, 3);
  analysis::ReducedOperators ops = analysis::trainOperators(model, V);
};
Guidance& guidance() {
  static Guidance g;
  return g;
}

// Training on a third of the guidance's stroke (in eta, around the range's centre): a run leaves it.
analysis::OperatorTrainingOptions thirdOfTheRange(const Guidance& g) {
  analysis::OperatorTrainingOptions small;
  const Eigen::VectorXd mid = g.ops.centre + g.ops.rotation * (0.5 * (g.ops.lower + g.ops.upper));
  const Eigen::VectorXd half = (g.ops.rotation * (g.ops.upper - g.ops.lower).asDiagonal()).cwiseAbs().rowwise().sum();
  small.lower = mid - half / 6.0;
  small.upper = mid + half / 6.0;
  return small;
}

}  // namespace

TEST(ChebyshevBasis, FitsAPolynomialOfItsSetExactlyFromValuesOrGradients) {
  const Eigen::Vector2d lo(-1.0, 0.5), hi(2.0, 0.9);
  const solvers::ChebyshevBasis b(lo, hi, std::vector<int>{4, 2});
  auto f = [](const Eigen::Vector2d& x) { return 1.0 + x[0] * x[0] * x[1] - 0.3 * std::pow(x[0], 4) + x[1] * x[1]; };
  auto g = [](const Eigen::Vector2d& x) {
    return Eigen::Vector2d(2 * x[0] * x[1] - 1.2 * std::pow(x[0], 3), x[0] * x[0] + 2 * x[1]);
  };
  const int n = 40;
  Eigen::MatrixXd pts(n, 2), vals(n, 1), grads(2 * n, 1);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d x = b.arcsinePoint(solvers::haltonPoint(i + 1, 2));
    pts.row(i) = x.transpose();
    vals(i, 0) = f(x);
    grads.block(2 * i, 0, 2, 1) = g(x);
  }
  const Eigen::MatrixXd cv = solvers::fitChebyshev(b, pts, vals, 1.0, Eigen::MatrixXd(), 0.0);
  const Eigen::MatrixXd cg = solvers::fitChebyshev(b, pts, Eigen::MatrixXd(), 0.0, grads, 1.0);
  solvers::ChebyshevBasis::Scratch s;
  Eigen::VectorXd phi(b.size());
  Eigen::MatrixXd grad(2, b.size());
  const Eigen::Vector2d x(0.37, 0.61);
  b.evaluate(x, s, phi, &grad);
  EXPECT_NEAR(phi.dot(cv.col(0)), f(x), 1e-12);
  EXPECT_LT((grad * cg.col(0) - g(x)).norm(), 1e-11);
  // The analytic gradient of every term against central differences.
  Eigen::VectorXd pp(b.size()), pm(b.size());
  for (int j = 0; j < 2; ++j) {
    const double h = 1e-6;
    Eigen::Vector2d a = x, c = x;
    a[j] += h;
    c[j] -= h;
    b.evaluate(a, s, pp, nullptr);
    b.evaluate(c, s, pm, nullptr);
    EXPECT_LT(((pp - pm) / (2 * h) - grad.row(j).transpose()).cwiseAbs().maxCoeff(), 1e-7);
  }
  EXPECT_EQ(b.outside(Eigen::Vector2d(2.1, 0.6)), 0);
  EXPECT_EQ(b.outside(Eigen::Vector2d(1.0, 0.6)), -1);
}

TEST(ChebyshevBasis, PathDerivativesAreTheTimeDerivativesOfTheTermsAlongAPath) {
  const Eigen::Vector3d lo(-1.0, 0.5, -0.2), hi(2.0, 0.9, 0.3);
  const solvers::ChebyshevBasis b(lo, hi, std::vector<int>{5, 3, 4});
  const Eigen::Vector3d x(0.37, 0.61, 0.05), v(0.8, -0.3, 0.4), a(-0.5, 0.2, 1.1);
  auto at = [&](double t) { return Eigen::Vector3d(x + t * v + 0.5 * t * t * a); };
  solvers::ChebyshevBasis::Scratch s;
  Eigen::VectorXd phi(b.size()), rate(b.size()), acc(b.size()), p(b.size()), m(b.size()), c(b.size());
  b.pathDerivatives(x, v, a, s, phi, rate, acc);
  const double h = 1e-4;
  b.evaluate(at(h), s, p, nullptr);
  b.evaluate(at(-h), s, m, nullptr);
  b.evaluate(at(0.0), s, c, nullptr);
  EXPECT_LT((phi - c).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT(((p - m) / (2 * h) - rate).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT(((p - 2 * c + m) / (h * h) - acc).cwiseAbs().maxCoeff(), 2e-4 * acc.cwiseAbs().maxCoeff());
}

TEST(ReducedOperators, MatchEquation19AtStatesOutsideTheTrainingSet) {
  Guidance& g = guidance();
  const analysis::ReducedOperators& ops = g.ops;
  std::printf(
      "guidance MODAL-3 operators: %d terms, held-out force error %.2e, mass error %.2e (target %.2e), %d + %d "
      "samples, %.3f s; range: %s\n",
      ops.terms(), ops.forceError, ops.massError, ops.tolerance, ops.trainingSamples, ops.validationSamples,
      ops.trainingSeconds, ops.range.c_str());
  EXPECT_LE(ops.forceError, ops.tolerance);
  EXPECT_LE(ops.massError, ops.tolerance);
  core::EquationsOfMotion eom(g.model, g.V);
  eom.kinematics().setRelativeTolerance(1e-13);
  analysis::OperatorDynamics od(g.model, ops);
  const int m = ops.size();
  double worst = 0.0;
  for (int k = 0; k < 20; ++k) {
    // Points of another sequence (shifted Halton) with velocities of the size the run has.
    const Eigen::VectorXd u = solvers::haltonPoint(1000 + 7 * k, 2 * m);
    Eigen::VectorXd y(2 * m);
    Eigen::VectorXd zeta(m), zetad(m);  // in the operators' frame and box
    for (int i = 0; i < m; ++i) {
      const double lo = ops.lower[i], hi = ops.upper[i];
      zeta[i] = lo + (0.1 + 0.8 * u[i]) * (hi - lo);
      zetad[i] = (u[m + i] - 0.5) * 40.0 * (hi - lo);  // about the guidance's 10 Hz motion
    }
    y << ops.centre + ops.rotation * zeta, ops.rotation * zetad;
    const double t = 0.013 * k;  // the load varies with t
    Eigen::VectorXd full(2 * m), fitted(2 * m);
    eom.rhs(t, y, full);
    ASSERT_TRUE(od.rhs(t, y, fitted));
    worst = std::max(worst, (fitted.tail(m) - full.tail(m)).norm() / full.tail(m).norm());
  }
  std::printf("largest relative acceleration difference to Eq. 19 at 20 untrained states: %.2e\n", worst);
  EXPECT_LT(worst, 10 * ops.tolerance);
}

namespace {

// The right-hand side against the fitted energies it derives from (massMatrix and potential, which
// evaluate the fields term by term and not through the right-hand side's fused pass): at rest with
// the time loads off (t_off), M etadd = -grad U by central differences of U; in motion, Lagrange's
// equations of T = 1/2 etad^T M etad by differences of M.
void expectLagrangeConsistent(const core::Model& model, const analysis::ReducedOperators& ops, double tOff) {
  analysis::OperatorDynamics od(model, ops);
  const int m = ops.size();
  // Directions and sizes in eta of the operators' box (its frame is the pilot's principal axes).
  const Eigen::VectorXd mid = ops.centre + ops.rotation * (0.5 * (ops.lower + ops.upper));
  const Eigen::VectorXd w = (ops.rotation * (ops.upper - ops.lower).asDiagonal()).cwiseAbs().rowwise().maxCoeff();
  Eigen::VectorXd y(2 * m), dy(2 * m);
  y.head(m) = mid + 0.21 * w;
  y.tail(m).setZero();
  ASSERT_TRUE(od.rhs(tOff, y, dy));
  Eigen::MatrixXd M;
  od.massMatrix(y.head(m), M);
  const Eigen::VectorXd force = M * dy.tail(m);
  for (int j = 0; j < m; ++j) {
    const double h = 1e-5 * w[j];
    Eigen::VectorXd a = y.head(m), b = y.head(m);
    a[j] += h;
    b[j] -= h;
    const double fd = -(od.potential(a) - od.potential(b)) / (2 * h);
    EXPECT_NEAR(force[j], fd, 1e-6 * force.norm()) << "m = " << m << ", coordinate " << j;
  }
  // M etadd + dM/dt etad - 1/2 d/deta (etad^T M etad) = -grad U.
  y.tail(m) = 30.0 * w.cwiseProduct(Eigen::VectorXd::LinSpaced(m, 1.0, -0.5));
  ASSERT_TRUE(od.rhs(tOff, y, dy));
  const Eigen::VectorXd etad = y.tail(m);
  const double h = 1e-6;
  Eigen::MatrixXd Mp, Mm;
  od.massMatrix(y.head(m) + h * etad, Mp);
  od.massMatrix(y.head(m) - h * etad, Mm);
  const Eigen::VectorXd Mdot_etad = (Mp - Mm) * etad / (2 * h);
  Eigen::VectorXd dT(m);
  for (int j = 0; j < m; ++j) {
    const double hj = 1e-5 * w[j];
    Eigen::VectorXd a = y.head(m), b = y.head(m);
    a[j] += hj;
    b[j] -= hj;
    od.massMatrix(a, Mp);
    od.massMatrix(b, Mm);
    dT[j] = 0.5 * etad.dot((Mp - Mm) * etad) / (2 * hj);
  }
  od.massMatrix(y.head(m), M);
  const Eigen::VectorXd lhs = M * dy.tail(m) + Mdot_etad - dT;
  EXPECT_LT((lhs - force).norm(), 1e-5 * (force.norm() + Mdot_etad.norm()))
      << "m = " << m << ": " << lhs.transpose() << " | " << force.transpose();
}

// Operators with made-up fields (total degree 2 in m coordinates, a rotated frame, a mass matrix
// kept positive definite by its constant term): the right-hand side's code for any m, whatever
// training would give.
analysis::ReducedOperators madeUpOperators(int m) {
  const solvers::ChebyshevBasis basis(Eigen::VectorXd::Constant(m, -1.0), Eigen::VectorXd::Constant(m, 2.0),
                                      std::vector<int>(static_cast<size_t>(m), 2));
  analysis::ReducedOperators ops;
  ops.lower = basis.lower();
  ops.upper = basis.upper();
  ops.exponents = basis.exponents();
  ops.centre = Eigen::VectorXd::LinSpaced(m, 0.1, 0.3);
  ops.rotation = Eigen::MatrixXd::Random(m, m).householderQr().householderQ();
  const int P = basis.size(), packed = m * (m + 1) / 2;
  ops.potential = Eigen::VectorXd::Random(P);
  ops.mass = 0.05 * Eigen::MatrixXd::Random(packed, P - 1);  // one term fewer: a shorter field
  for (int a = 0, k = 0; a < m; ++a)
    for (int b = a; b < m; ++b, ++k) ops.mass(k, 0) = a == b ? 2.0 : 0.0;
  ops.dofs = m;
  return ops;
}

}  // namespace

TEST(ReducedOperators, ForcesAndVelocityTermsAreDerivativesOfTheFittedEnergies) {
  Guidance& g = guidance();
  expectLagrangeConsistent(g.model, g.ops, 0.15);  // t = 0.15 s: after the load pulse
  // Made-up fields through the fixed-size passes (m = 1, 2, 6) and the general one (m = 7).
  for (int m : {1, 2, 6, 7}) expectLagrangeConsistent(g.model, madeUpOperators(m), 0.15);
}

TEST(ReducedOperators, ConserveEnergyOfAnUnforcedUndampedRun) {
  core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  m.timeForces.clear();
  {  // released from the static deflection under 40 N (as Dynamics.StraightGuidanceConserves...)
    core::Model loaded = m;
    loaded.f0[m.nodes[m.nodeByLabel.at(6)].firstCoord] = 40.0;
    core::Linearization lin(loaded);
    Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size());
    ASSERT_EQ(analysis::equilibrium(lin, 0.0, 0.0, eta).status, solvers::StaticStatus::Converged);
    for (size_t j = 0; j < m.dofs.size(); ++j) m.e0[m.dofs[j].index] = eta[j];
  }
  const Eigen::MatrixXd V = modalBasis(m, 3);
  const analysis::ReducedOperators ops = analysis::trainOperators(m, V);
  analysis::OperatorDynamics od(m, ops);
  core::EquationsOfMotion eom(m, V);
  const Eigen::VectorXd y0 = eom.initialState();
  const double relTol = 1e-6;
  solvers::Ode45Options o;
  o.relTol = relTol;
  o.absTol = Eigen::VectorXd::Constant(1, 1e-9);
  const double e0 = od.energy(y0);
  double drift = 0.0, scale = 0.0;
  int refused = 0;
  auto f = [&](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
    if (!od.rhs(t, y, dy)) ++refused;
  };
  auto observe = [&](double, const Eigen::VectorXd& y) {
    const Eigen::VectorXd eta = y.head(ops.size());
    scale = std::max(scale, std::abs(od.potential(eta) - od.potential(y0.head(ops.size()))));
    drift = std::max(drift, std::abs(od.energy(y) - e0));
    return true;
  };
  const auto r = solvers::Ode45(o).integrate(f, {0.0, 0.5}, y0, observe);
  ASSERT_EQ(r.status, solvers::OdeStatus::Success);
  ASSERT_EQ(refused, 0);
  std::printf("energy drift of the operator model over 0.5 s at RelTol %g: %.2e of the energy exchanged\n", relTol,
              drift / scale);
  EXPECT_LT(drift / scale, 10 * relTol);
}

TEST(ReducedOperators, RunFallsBackToEquation19OutsideTheTrainedRangeAndSaysWhen) {
  Guidance& g = guidance();
  // Operators trained on a third of the stroke: the run must leave the range and use Eq. 19.
  const analysis::OperatorTrainingOptions small = thirdOfTheRange(g);
  auto ops = std::make_shared<analysis::ReducedOperators>(analysis::trainOperators(g.model, g.V, small));
  analysis::SimulationOptions with, without;
  with.basis = without.basis = g.V;
  with.operators = ops;
  with.reductionEstimate = without.reductionEstimate = false;
  const core::Trajectory a = analysis::simulate(g.model, with), b = analysis::simulate(g.model, without);
  ASSERT_TRUE(a.completed) << a.stopReason;
  EXPECT_GT(a.operators.evaluations, 0);
  EXPECT_GT(a.operators.fallbacks, 0);
  EXPECT_GT(a.operators.firstFallback, 0.0);
  EXPECT_NE(a.operators.where.find("outside the trained"), std::string::npos) << a.operators.where;
  const double diff = analysis::positionErrorAgainst(g.model, a, b);
  std::printf("fallback run: %ld operator evaluations, %ld by Eq. 19 from t = %g (%s); difference to Eq. 19 %.2e\n",
              a.operators.evaluations, a.operators.fallbacks, a.operators.firstFallback, a.operators.where.c_str(),
              diff);
  EXPECT_LT(diff, 1e-3);
}

// The guidance's operators that also fit the tip node's coordinates and element 1's deformations.
analysis::ReducedOperators trackingOperators(const analysis::OperatorTrainingOptions& base = {}) {
  Guidance& g = guidance();
  analysis::OperatorTrainingOptions o = base;
  o.outputs = analysis::trackedQuantities(g.model, {6}, {1});
  return analysis::trainOperators(g.model, g.V, o);
}

// Largest |tracked - full| over the run, relative to the full quantity's range over the run.
double trackedDifference(const core::Trajectory& tracked, const core::Trajectory& full, int column, char what) {
  const core::OperatorOutput& q = tracked.tracked.quantities[column];
  const bool def = q.kind == core::OperatorOutput::Kind::Deformation;
  double worst = 0.0, lo = INFINITY, hi = -INFINITY;
  for (size_t k = 0; k < full.time.size(); ++k) {
    const core::StateOutputs& s = full.states[k];
    const double ref = what == 'v'   ? (def ? s.e : s.x)[q.index]
                       : what == 'r' ? (def ? s.ed : s.xd)[q.index]
                       : what == 'a' ? (def ? s.edd : s.xdd)[q.index]
                                     : s.sig[q.index];
    const double got = what == 'v'   ? tracked.tracked.value[k][column]
                       : what == 'r' ? tracked.tracked.rate[k][column]
                       : what == 'a' ? tracked.tracked.acceleration[k][column]
                                     : tracked.tracked.stress[k][column];
    worst = std::max(worst, std::abs(got - ref));
    lo = std::min(lo, ref);
    hi = std::max(hi, ref);
  }
  return worst / std::max(hi - lo, 1e-300);
}

TEST(ReducedOperators, TrackedOutputsMatchTheFullKinematicsAtTheRunsStates) {
  Guidance& g = guidance();
  const auto ops = std::make_shared<analysis::ReducedOperators>(trackingOperators());
  ASSERT_EQ(ops->outputs.size(), 5u);  // node 6: x, y; element 1: three deformations
  EXPECT_LE(ops->outputError, ops->tolerance);
  analysis::SimulationOptions tracked, all;
  tracked.basis = all.basis = g.V;
  tracked.operators = all.operators = ops;
  tracked.trackedOutputs = true;
  const core::Trajectory a = analysis::simulate(g.model, tracked), b = analysis::simulate(g.model, all);
  ASSERT_TRUE(a.completed && b.completed) << a.stopReason << b.stopReason;
  EXPECT_TRUE(a.states.empty());
  ASSERT_EQ(a.time, b.time);  // the same run: the output fields change nothing in the integration
  EXPECT_EQ(a.tracked.fromOperators, static_cast<long>(a.time.size()));
  EXPECT_EQ(a.tracked.fromKinematics, 0);
  const double x = trackedDifference(a, b, 0, 'v'), xd = trackedDifference(a, b, 0, 'r'),
               xdd = trackedDifference(a, b, 0, 'a'), bend = trackedDifference(a, b, 3, 'v'),
               bendRate = trackedDifference(a, b, 3, 'r'), stress = trackedDifference(a, b, 3, 's');
  std::printf(
      "tracked tip x: value %.2e, rate %.2e, acceleration %.2e of its range; element 1 bending %.2e, rate %.2e, "
      "stress %.2e (output fit %.2e)\n",
      x, xd, xdd, bend, bendRate, stress, ops->outputError);
  EXPECT_LT(x, 20 * ops->tolerance);
  EXPECT_LT(xd, 20 * ops->tolerance);
  // The accelerations are the operators' (what the run integrates), not Eq. 19's at the same state.
  EXPECT_LT(xdd, 0.01);
  EXPECT_LT(bend, 20 * ops->tolerance);
  EXPECT_LT(bendRate, 20 * ops->tolerance);
  EXPECT_LT(stress, 20 * ops->tolerance);
  // The reduction estimate from its samples' full kinematics: the same samples as from the states.
  ASSERT_TRUE(a.reduction.estimated) << a.reduction.note;
  ASSERT_TRUE(b.reduction.estimated) << b.reduction.note;
  EXPECT_NEAR(a.reduction.estimate, b.reduction.estimate, 0.2 * b.reduction.estimate);
}

TEST(ReducedOperators, TrackedOutputsComeFromTheFullKinematicsOutsideTheTrainedRange) {
  Guidance& g = guidance();
  const analysis::OperatorTrainingOptions small = thirdOfTheRange(g);
  analysis::SimulationOptions tracked, all;
  tracked.basis = all.basis = g.V;
  tracked.operators = all.operators = std::make_shared<analysis::ReducedOperators>(trackingOperators(small));
  tracked.trackedOutputs = true;
  tracked.reductionEstimate = all.reductionEstimate = false;
  const core::Trajectory a = analysis::simulate(g.model, tracked), b = analysis::simulate(g.model, all);
  ASSERT_TRUE(a.completed && b.completed);
  EXPECT_GT(a.tracked.fromOperators, 0);
  EXPECT_GT(a.tracked.fromKinematics, 0);
  EXPECT_EQ(a.tracked.fromOperators + a.tracked.fromKinematics, static_cast<long>(a.time.size()));
  EXPECT_LT(trackedDifference(a, b, 0, 'v'), 1e-3);
  // The file keeps them; a damaged output line is refused.
  const std::string text = io::formatOperators(*tracked.operators);
  const core::ReducedOperators back = io::parseOperators(text, "t.operators");
  EXPECT_EQ(io::formatOperators(back), text);
  ASSERT_EQ(back.outputs.size(), 5u);
  EXPECT_EQ(back.outputFields, tracked.operators->outputFields);
  std::string bad = text;
  bad.replace(bad.find("output x"), 8, "output q");
  try {
    io::parseOperators(bad, "t.operators");
    ADD_FAILURE() << "an unknown output was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("t.operators:"), std::string::npos) << e.what();
  }
  core::ReducedOperators beyond = back;
  beyond.outputs.front().index = g.model.nx;
  EXPECT_NE(analysis::operatorsMismatch(g.model, g.V, beyond).find("track x index"), std::string::npos);
  EXPECT_THROW(analysis::trackedQuantities(g.model, {999}, {}), std::invalid_argument);
}

TEST(ReducedOperators, AddAtMostATenthOfTheReductionError) {
  Guidance& g = guidance();
  analysis::SimulationOptions with, without, full;
  with.basis = without.basis = g.V;
  with.operators = std::make_shared<analysis::ReducedOperators>(g.ops);
  with.reductionEstimate = without.reductionEstimate = full.reductionEstimate = false;
  with.relTol = without.relTol = 1e-6;
  full.relTol = 1e-7;
  const core::Trajectory a = analysis::simulate(g.model, with), b = analysis::simulate(g.model, without);
  const core::Trajectory ref = analysis::simulate(g.model, full);
  ASSERT_TRUE(a.completed && b.completed && ref.completed);
  EXPECT_EQ(a.operators.fallbacks, 0);
  const double added = analysis::positionErrorAgainst(g.model, a, b);
  const double reduction = analysis::positionErrorAgainst(g.model, b, ref);
  std::printf("MODAL-3 at RelTol 1e-6: reduction error %.2e, operators add %.2e (of the motion)\n", reduction, added);
  EXPECT_LT(added, 0.1 * reduction);
}

// Issue 48, item 4: generalized-alpha on the operators (its iteration matrix their difference
// quotients) ends where ode45 on the same operators does, within its RelTol, without the full model.
TEST(ReducedOperators, GeneralizedAlphaRunsOnTheOperatorsAlone) {
  Guidance& g = guidance();
  analysis::SimulationOptions alpha, ref, eq19;
  alpha.basis = ref.basis = eq19.basis = g.V;
  alpha.operators = ref.operators = std::make_shared<analysis::ReducedOperators>(g.ops);
  alpha.reductionEstimate = ref.reductionEstimate = eq19.reductionEstimate = false;
  alpha.integrator = eq19.integrator = analysis::Integrator::GeneralizedAlpha;
  alpha.relTol = eq19.relTol = 1e-4;
  ref.relTol = 1e-8;
  ref.absTol = 1e-11;
  const core::Trajectory a = analysis::simulate(g.model, alpha), r = analysis::simulate(g.model, ref);
  const core::Trajectory b = analysis::simulate(g.model, eq19);
  ASSERT_TRUE(a.completed && r.completed && b.completed) << a.stopReason << r.stopReason << b.stopReason;
  EXPECT_EQ(a.integrator, "galpha");
  EXPECT_GT(a.operators.evaluations, a.nfevals / 2);  // the Jacobian's quotients are operator evaluations too
  EXPECT_EQ(a.operators.fallbacks, 0);                // neither a right-hand side nor a Jacobian of Eq. 19
  EXPECT_TRUE(a.operators.notUsed.empty()) << a.operators.notUsed;
  const double onOperators = analysis::positionErrorAgainst(g.model, a, r);
  const double onEq19 = analysis::positionErrorAgainst(g.model, b, r);
  std::printf(
      "galpha on MODAL-3 operators at RelTol 1e-4: %ld steps, %ld operator evaluations, error %.2e to ode45 "
      "at 1e-8 on them; galpha on Eq. 19: %ld steps, %.2e\n",
      a.nsteps, a.operators.evaluations, onOperators, b.nsteps, onEq19);
  EXPECT_LT(onOperators, 10 * *alpha.relTol);
  // The same steps as on Eq. 19 within a factor (the operators fit Eq. 19 to 1e-3 of its forces).
  EXPECT_LT(std::abs(static_cast<double>(a.nsteps - b.nsteps)), 0.5 * static_cast<double>(b.nsteps));
}

// Outside the trained range galpha's right-hand sides and Jacobians come from Eq. 19, with the
// kinematics caught up from where they were left; the run ends as the run on Eq. 19 does.
TEST(ReducedOperators, GeneralizedAlphaFallsBackToEquation19OutsideTheRange) {
  Guidance& g = guidance();
  auto ops = std::make_shared<analysis::ReducedOperators>(analysis::trainOperators(g.model, g.V, thirdOfTheRange(g)));
  analysis::SimulationOptions with, without;
  with.basis = without.basis = g.V;
  with.operators = ops;
  with.reductionEstimate = without.reductionEstimate = false;
  with.integrator = without.integrator = analysis::Integrator::GeneralizedAlpha;
  with.relTol = without.relTol = 1e-5;
  const core::Trajectory a = analysis::simulate(g.model, with), b = analysis::simulate(g.model, without);
  ASSERT_TRUE(a.completed && b.completed) << a.stopReason << b.stopReason;
  EXPECT_GT(a.operators.evaluations, 0);
  EXPECT_GT(a.operators.fallbacks, 0);
  const double diff = analysis::positionErrorAgainst(g.model, a, b);
  std::printf("galpha fallback run: %ld operator evaluations, %ld by Eq. 19 from t = %g; difference to Eq. 19 %.2e\n",
              a.operators.evaluations, a.operators.fallbacks, a.operators.firstFallback, diff);
  EXPECT_LT(diff, 1e-3);
}

TEST(ReducedOperators, RefuseModelsWhoseKinematicsDependOnTime) {
  const core::Model m = io::readDatFile(dat("slider_crank_rigid.dat"));  // INPUTE: the crank angle is driven
  ASSERT_FALSE(m.inputE.empty());
  EXPECT_NE(analysis::operatorsUnsupported(m), "");
  EXPECT_THROW(analysis::trainOperators(m, Eigen::MatrixXd::Identity(m.numDofs(), m.numDofs())), std::invalid_argument);
}

TEST(ReducedOperators, FileReadsBackBitwiseAndRefusesDamage) {
  const analysis::ReducedOperators& ops = guidance().ops;
  const std::string text = io::formatOperators(ops);
  const core::ReducedOperators back = io::parseOperators(text, "m3.operators");
  EXPECT_EQ(io::formatOperators(back), text);
  EXPECT_EQ(back.mass, ops.mass);
  EXPECT_EQ(back.exponents, ops.exponents);
  EXPECT_EQ(back.loads.size(), ops.loads.size());
  // Damage: a ragged row, a non-number, a missing block, a block too short.
  auto damaged = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const size_t at = t.find(from);
    if (at == std::string::npos) return std::string("pattern not found: ") + from;
    t.replace(at, from.size(), to);
    try {
      io::parseOperators(t, "m3.operators");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(damaged("matrix lower 3 1\n", "matrix lower 3 1\n1,").find("m3.operators:"), std::string::npos);
  EXPECT_NE(damaged("matrix lower 3 1\n", "matrix lower 3 1\nx").find("not a finite number"), std::string::npos);
  EXPECT_NE(damaged("matrix mass", "matrix mess").find("unknown block"), std::string::npos);
  EXPECT_NE(damaged("matrix upper 3 1", "matrix upper 4 1").find("m3.operators:"), std::string::npos);
  EXPECT_NE(damaged("# flexmb reduced operators", "# flexmb basis").find("not a flexmb operator file"),
            std::string::npos);
  // Against the model and basis: another basis, another model.
  EXPECT_EQ(analysis::operatorsMismatch(guidance().model, guidance().V, ops), "");
  EXPECT_NE(analysis::operatorsMismatch(guidance().model, 2.0 * guidance().V, ops).find("another basis"),
            std::string::npos);
  core::Model other = guidance().model;
  other.timeForces.clear();
  EXPECT_NE(analysis::operatorsMismatch(other, guidance().V, ops).find("XFT"), std::string::npos);
}

// Issue 49: a run checks what training checked, the fields' errors at the held-out configurations
// relative to the largest values in the range, so that operators serve the model they were made
// for; a misfit never stops a run (Eq. 19 through the same basis, said in the note), and only a
// changed checksum says that the model changed.
namespace {

// The basis and operator files of `ops` for V in a fresh folder; returns the basis path.
std::string besideABasis(const std::string& name, const Eigen::MatrixXd& V, const analysis::ReducedOperators& ops) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("flexmb_ops_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::create_directories(dir);
  const std::string basis = (dir / (name + ".csv")).string();
  io::writeBasis(basis, V, {"modal", "straight_guidance.dat", {}, {}, {}});
  io::writeOperators(io::operatorPathFor(basis), ops);
  return basis;
}

}  // namespace

TEST(ReducedOperators, ARunMeasuresTheFitTrainingDeclaredAtTheSameConfigurations) {
  Guidance& g = guidance();
  // Written and read back as simulate --basis reads them.
  const core::ReducedOperators back = io::parseOperators(io::formatOperators(g.ops), "m3.operators");
  ASSERT_EQ(back.heldOut.rows(), g.ops.validationSamples);
  EXPECT_EQ(back.modelChecksum, analysis::operatorModelChecksum(g.model));
  const analysis::OperatorFit fit = analysis::operatorFitAtHeldOut(g.model, g.V, back);
  std::printf("guidance MODAL-3 at its %d held-out configurations: force %.3e (declared %.3e), mass %.3e (%.3e)\n",
              fit.configurations, fit.force, back.forceError, fit.mass, back.massError);
  EXPECT_EQ(fit.unsolved, 0);
  EXPECT_LE(fit.force, back.forceError);
  EXPECT_LE(fit.mass, back.massError);
  EXPECT_GT(fit.force, 0.5 * back.forceError);  // the same measure, not a looser one
  EXPECT_EQ(analysis::operatorsMismatch(g.model, g.V, back), "");
  const std::string basis = besideABasis("same", g.V, back);
  const analysis::OperatorChoice c = analysis::chooseOperators(g.model, "straight_guidance.dat", g.V, basis, false);
  EXPECT_TRUE(c.operators) << c.note;
  EXPECT_EQ(c.refusal, "");
  std::filesystem::remove_all(std::filesystem::path(basis).parent_path());
}

TEST(ReducedOperators, AMisfitAtRunTimeFallsBackToEquation19AndSaysSo) {
  Guidance& g = guidance();
  // Fields that no longer fit what they declare (a potential 2 % off): same model, same basis.
  analysis::ReducedOperators off = g.ops;
  off.potential *= 1.02;
  EXPECT_NE(analysis::operatorsMismatch(g.model, g.V, off).find("training measured"), std::string::npos);
  std::string basis = besideABasis("off", g.V, off);
  analysis::OperatorChoice c = analysis::chooseOperators(g.model, "straight_guidance.dat", g.V, basis, false);
  EXPECT_FALSE(c.operators);
  EXPECT_EQ(c.refusal, "");
  EXPECT_EQ(c.note.rfind("Eq. 19 (", 0), 0u) << c.note;
  EXPECT_NE(c.note.find("training measured"), std::string::npos) << c.note;
  EXPECT_EQ(c.note.find("the model changed"), std::string::npos) << c.note;
  // The same model data read with the plain PLBEAM elongation (--elongation plain): the checksum
  // covers data, not element options, and the fit at the held-out configurations sees the rest.
  io::ReadOptions plain;
  plain.elongation = core::ElongationDefinition::Plain;
  const core::Model p = io::readDatFile(dat("straight_guidance.dat"), plain);
  EXPECT_EQ(analysis::operatorModelChecksum(p), g.ops.modelChecksum);
  const std::string why = analysis::operatorsMismatch(p, g.V, g.ops);
  std::printf("guidance read with plain elongation: %s\n", why.c_str());
  EXPECT_NE(why.find("training measured"), std::string::npos) << why;
  // The run goes on with Eq. 19: no evaluation of the operators.
  std::filesystem::remove_all(std::filesystem::path(basis).parent_path());
  basis = besideABasis("plain", g.V, g.ops);
  c = analysis::chooseOperators(p, "straight_guidance.dat", g.V, basis, false);
  ASSERT_FALSE(c.operators);
  std::filesystem::remove_all(std::filesystem::path(basis).parent_path());
  analysis::SimulationOptions o;
  o.basis = g.V;
  o.operators = c.operators;
  o.reductionEstimate = false;
  const core::Trajectory run = analysis::simulate(p, o);
  EXPECT_TRUE(run.completed);
  EXPECT_EQ(run.operators.evaluations, 0);
}

TEST(ReducedOperators, OnlyAChangedChecksumSaysTheModelChanged) {
  Guidance& g = guidance();
  EXPECT_EQ(analysis::operatorModelChecksum(io::readDatFile(dat("straight_guidance.dat"))), g.ops.modelChecksum);
  // A stiffer flexure element: the model changed, and the run uses Eq. 19.
  core::Model stiffer = g.model;
  stiffer.elements[0].S(1, 1) *= 1.1;
  EXPECT_NE(analysis::operatorModelChecksum(stiffer), g.ops.modelChecksum);
  EXPECT_NE(analysis::operatorsMismatch(stiffer, g.V, g.ops).find("the model changed"), std::string::npos);
  const std::string basis = besideABasis("stiffer", g.V, g.ops);
  const analysis::OperatorChoice c = analysis::chooseOperators(stiffer, "stiffer.dat", g.V, basis, false);
  EXPECT_FALSE(c.operators);
  EXPECT_EQ(c.refusal, "");
  EXPECT_NE(c.note.find("the model changed"), std::string::npos) << c.note;
  std::filesystem::remove_all(std::filesystem::path(basis).parent_path());
  // A constant force too; the amplitude of a time-dependent load is not in the fields (a run
  // evaluates a(t) itself): the same checksum, and the operators serve.
  core::Model pushed = g.model;
  pushed.f0[0] += 1.0;
  EXPECT_NE(analysis::operatorModelChecksum(pushed), g.ops.modelChecksum);
  const std::string text = io::readDatText(dat("straight_guidance.dat"));
  const std::string strongerText = std::regex_replace(text, std::regex("50\\*\\(1-cos"), "80*(1-cos");
  ASSERT_NE(strongerText, text);
  const core::Model stronger = io::readDatString(strongerText, "stronger.dat");
  EXPECT_EQ(analysis::operatorModelChecksum(stronger), g.ops.modelChecksum);
  EXPECT_EQ(analysis::operatorsMismatch(stronger, g.V, g.ops), "");
  // Operators without a checksum (an older flexmb): not used, and not "the model changed".
  analysis::ReducedOperators old = g.ops;
  old.modelChecksum.clear();
  EXPECT_NE(analysis::operatorsMismatch(g.model, g.V, old).find("older flexmb"), std::string::npos);
}

// Operators that would add more than a tenth of the basis' reduction error are not written
// (reduce says why); those within it but above their target say that they missed it.
TEST(ReducedOperators, TrainingWritesNoneThatMissTheirTargetBeyondWhatARunMayCarry) {
  Guidance& g = guidance();
  EXPECT_EQ(analysis::operatorsMissTheirTarget(g.ops), "");
  analysis::ReducedOperators missed = g.ops;
  missed.forceError = 2.0 * missed.tolerance;
  EXPECT_EQ(analysis::operatorsMissTheirTarget(missed), "");
  EXPECT_NE(analysis::describeOperators(missed).find("missed"), std::string::npos);
  missed.forceError = 4.0 * missed.tolerance;
  EXPECT_NE(analysis::operatorsMissTheirTarget(missed).find("Eq. 19"), std::string::npos);
  analysis::ReducedOperators rough = g.ops;
  rough.massError = 2.0 * rough.tolerance;
  EXPECT_NE(analysis::operatorsMissTheirTarget(rough), "");
  // Through reduce's product: a tolerance the fit cannot reach in 12 terms.
  analysis::OperatorTrainingOptions few;
  few.maxTerms = 12;
  const analysis::ReducedOperators cut = analysis::trainOperators(g.model, g.V, few);
  std::printf("MODAL-3 on 12 terms: %s\n", analysis::operatorsMissTheirTarget(cut).c_str());
  EXPECT_NE(analysis::operatorsMissTheirTarget(cut), "");
}
