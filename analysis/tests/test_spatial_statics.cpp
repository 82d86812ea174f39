// The static Newton iteration of spatial models (issue 11 item 6): the cross-spring pivot
// (datfiles/spatial/cross_spring_pivot.dat, 2 x 20 BEAM, 234 DOF, a moment and a force on the
// platform, gravity on the distributed masses) through its load steps.
//  - few iterations per load step (3-6, where the residual test alone needed 9 and 127 at the first);
//  - the saddle-point tangent (core::ConstrainedTangent, no F_q) solves the projected Kbar + Gbar;
//  - it is the derivative of the static residual: central differences along random directions,
//    and one Newton step from near the equilibrium squares the error (quadratic convergence);
//  - the stability flag of the sparse path (a spatial column below and above its buckling load).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "analysis/Sweep.hpp"
#include "analysis/tests/Objectivity.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
core::Model pivot() {
  return io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot.dat");
}

Eigen::VectorXd direction(int n, double phase) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = std::sin(phase + 1.7 * i) + 0.3 * std::cos(0.37 * i);
  return v / v.norm();
}

// A loaded state of the pivot: the equilibrium of the middle step, for load factor s.
struct LoadedPivot {
  core::Model model = pivot();
  analysis::StaticRun run = analysis::staticAnalysis(model, 0, 10);
  const analysis::StaticStep& mid() const { return run.steps[run.steps.size() / 2]; }
  // lin placed at the middle load step's configuration, its kinematics solved to `tolerance`.
  void placeAtMid(core::Linearization& lin, double tolerance) const {
    lin.kinematics().setRelativeTolerance(tolerance);
    lin.kinematics().setConfiguration(mid().x);
  }
};
}  // namespace

TEST(SpatialStatics, PivotNeedsFewNewtonIterationsPerLoadStep) {
  const core::Model m = pivot();
  ASSERT_EQ(m.numDofs(), 234);
  const analysis::StaticRun run = analysis::staticAnalysis(m, 0, 10);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_EQ(run.steps.size(), 11u);  // load steps 0..10 (load step 0: no initial loads)
  int total = 0;
  std::string per;
  for (const auto& st : run.steps) {
    (per += ' ') += std::to_string(st.iterations);  // piecewise: GCC 12 -Wrestrict (tools/README.md)
    total += st.iterations;
    EXPECT_LE(st.iterations, 6) << "load factor " << st.loadFactor;
    EXPECT_TRUE(st.newton.stable) << "load factor " << st.loadFactor;
  }
  std::printf("cross-spring pivot, load steps 0..10: Newton iterations per step%s (total %d)\n", per.c_str(), total);
  EXPECT_LE(total, 50);  // the residual test alone: 212 for the file's 9 steps
}

TEST(SpatialStatics, SaddlePointTangentSolvesTheProjectedTangent) {
  // Off the equilibrium (the middle step's state moved along a direction) under the loads of the
  // last step: T x = b with the dense projected T = Kbar + Gbar and x from the saddle-point solve.
  const LoadedPivot p;
  ASSERT_TRUE(p.run.completed) << p.run.stopReason;
  core::Linearization lin(p.model);
  p.placeAtMid(lin, 1e-14);
  const Eigen::VectorXd eta = p.mid().eta + 1e-6 * direction(lin.size(), 0.4);
  Eigen::VectorXd Qsparse, Qdense, f, x;
  ASSERT_TRUE(lin.staticTangent(0.0, eta, 1.0, 1.0, Qsparse));
  const Eigen::VectorXd b = direction(lin.size(), 2.0);
  lin.solveStaticTangent(b, x);
  lin.staticResidual(0.0, eta, 1.0, 1.0, Qdense);
  lin.appliedForces(0.0, 1.0, f, 1.0);
  Eigen::MatrixXd T;
  lin.tangent(0.0, eta, f, Qdense, T);
  const double backward = (T * x - b).norm() / (T.norm() * x.norm());
  const double qdiff = (Qsparse - Qdense).norm() / Qdense.norm();
  std::printf("pivot: saddle-point solve, backward error in the projected tangent %.2e; |Q| %.3e (paths differ %.1e)\n",
              backward, Qdense.norm(), qdiff);
  EXPECT_LT(backward, 1e-13);
  EXPECT_LT(qdiff, 1e-12);
  // And the solution itself against the dense LU, relative to the condition of T.
  const Eigen::VectorXd xd = T.partialPivLu().solve(b);
  EXPECT_LT((x - xd).norm() / xd.norm(), 1e-6);
}

TEST(SpatialStatics, NewtonTangentIsTheDerivativeOfTheStaticResidual) {
  // Central differences of Q (moment on the Euler parameters and gravity on the distributed
  // masses evaluated where the model is) along three directions v: the tangent maps T^-1 (-dQ/dv)
  // back onto v.
  const LoadedPivot p;
  ASSERT_TRUE(p.run.completed) << p.run.stopReason;
  core::Linearization lin(p.model);
  p.placeAtMid(lin, 1e-15);
  const Eigen::VectorXd eta = p.mid().eta;
  const double s = p.mid().loadFactor;
  Eigen::VectorXd Q, Qp, Qm, x;
  double worst = 0.0;
  for (double phase : {0.1, 1.3, 2.9}) {
    const Eigen::VectorXd v = 1e-4 * direction(lin.size(), phase);  // |v| ~ 0.1 of eta
    const double h = 1e-3;                                          // steps of 1e-7 along v
    lin.staticResidual(0.0, eta + h * v, s, 1.0, Qp);
    lin.staticResidual(0.0, eta - h * v, s, 1.0, Qm);
    ASSERT_TRUE(lin.staticTangent(0.0, eta, s, 1.0, Q));
    lin.solveStaticTangent(-(Qp - Qm) / (2 * h), x);
    worst = std::max(worst, (x - v).norm() / v.norm());
  }
  std::printf("pivot: |T^-1 (-dQ/dv) - v| / |v| over three directions: %.2e\n", worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(SpatialStatics, NewtonConvergesQuadraticallyNearThePivotEquilibrium) {
  // One Newton step from eta* + d v: the error falls as d^2 (a consistent tangent). Quartering d
  // divides it by ~16 (by 4 for a tangent that is off by O(1)).
  const LoadedPivot p;
  ASSERT_TRUE(p.run.completed) << p.run.stopReason;
  core::Linearization lin(p.model);
  p.placeAtMid(lin, 1e-15);
  const Eigen::VectorXd& star = p.mid().eta;
  const double s = p.mid().loadFactor;
  const Eigen::VectorXd v = direction(lin.size(), 0.7);
  auto errorAfterOneStep = [&](double d) {
    const Eigen::VectorXd eta = star + d * v;
    Eigen::VectorXd Q, step;
    EXPECT_TRUE(lin.staticTangent(0.0, eta, s, 1.0, Q));
    lin.solveStaticTangent(Q, step);
    return (eta + step - star).norm();
  };
  // |eta*| ~ 1e-3; the error constant is large (~3e6 / m: a step error in the leaves opens the
  // loop at the released beam, whose axial stiffness sees it to second order), so the quadratic
  // range starts below ~1e-7 (from 2e-7 one step leaves 3e-7).
  const double d = 2e-8;
  const double e1 = errorAfterOneStep(d), e4 = errorAfterOneStep(d / 4);
  std::printf("pivot: one Newton step from |error| %.1e -> %.2e, from %.1e -> %.2e (ratio %.1f, quadratic 16)\n", d, e1,
              d / 4, e4, e1 / e4);
  EXPECT_LT(e1, 0.2 * d);
  EXPECT_GT(e1 / e4, 10.0);
}

// A clamped-free BEAMNL column along x (8 elements, L = 1, EI = 1 and 1.5) under an axial tip
// load P (compressive), in two load steps.
static std::string axiallyLoadedColumn(double P) {
  std::string dat;
  for (int e = 1; e <= 8; ++e)
    dat += "BEAMNL " + std::to_string(e) + " " + std::to_string(2 * e - 1) + " " + std::to_string(2 * e) + " " +
           std::to_string(2 * e + 1) + " " + std::to_string(2 * e + 2) + " 0 1 0\n";
  for (int i = 1; i <= 9; ++i) dat += "X " + std::to_string(2 * i - 1) + " " + std::to_string((i - 1) / 8.0) + " 0 0\n";
  for (int e = 1; e <= 8; ++e) dat += "DYNE " + std::to_string(e) + " 1 2 3 4 5 6\n";
  dat += "FIX 1\nFIX 2\nEND\nHALT\n";
  for (int e = 1; e <= 8; ++e) dat += "ESTIFF " + std::to_string(e) + " 1e5 1 1 1.5\n";
  return dat + "XF 17 " + std::to_string(-P) + " 0 0\nITERSTEP 10 2\nEND\nEND\n";
}

TEST(SpatialStatics, StabilityOfAColumnBelowAndAboveItsBucklingLoad) {
  // Clamped-free BEAMNL column (8 elements, L = 1, EI = 1 and 1.5), axial tip load 0.5 and 1.5 of
  // P_cr = pi^2 EI / (4 L^2): the straight equilibrium is stable below, unstable above (the
  // sparse Newton reports it from Kbar + Gbar at the equilibrium).
  const double Pcr = M_PI * M_PI / 4.0;
  for (double fraction : {0.5, 1.5}) {
    const std::string dat = axiallyLoadedColumn(fraction * Pcr);
    const core::Model m = io::readDatString(dat, "column.dat");
    const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
    ASSERT_TRUE(run.completed) << run.stopReason;
    const auto& st = run.steps.back();
    std::printf("spatial column at %.1f P_cr: %s after %d iterations\n", fraction,
                st.newton.stable ? "stable" : "unstable", st.iterations);
    EXPECT_EQ(st.newton.stable, fraction < 1.0);
  }
}

TEST(SpatialStatics, PivotLoadStepsTurnWithTheModel) {
  // Objectivity (issue 22): the pivot (2 x 20 BEAM, moment and force on the platform, gravity)
  // turned by a random rotation: every load step's equilibrium is the turned one, reached with the
  // same Newton iterations, and the stability flags agree.
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot.dat");
  std::ostringstream text;
  text << in.rdbuf();
  const Eigen::Matrix3d R = objectivity::randomRotation(5);
  const core::Model a = pivot();
  const core::Model b = io::readDatString(objectivity::rotatedDat(text.str(), R), "turned.dat");
  const analysis::StaticRun ra = analysis::staticAnalysis(a, 0, 10), rb = analysis::staticAnalysis(b, 0, 10);
  ASSERT_TRUE(ra.completed) << ra.stopReason;
  ASSERT_TRUE(rb.completed) << rb.stopReason;
  ASSERT_EQ(ra.steps.size(), rb.steps.size());
  double worst = 0.0;
  std::string iterations;
  for (size_t k = 0; k < ra.steps.size(); ++k) {
    worst = std::max(worst, objectivity::configurationDifference(a, ra.steps[k].x, b, rb.steps[k].x, R, 0.1));
    (((iterations += ' ') += std::to_string(ra.steps[k].iterations)) += '/') += std::to_string(rb.steps[k].iterations);
    EXPECT_EQ(ra.steps[k].newton.stable, rb.steps[k].newton.stable) << "step " << k + 1;
    EXPECT_LE(std::abs(ra.steps[k].iterations - rb.steps[k].iterations), 1) << "step " << k + 1;
  }
  std::printf("pivot turned by a random rotation: largest difference %.1e; Newton iterations (aligned/turned)%s\n",
              worst, iterations.c_str());
  EXPECT_LT(worst, 1e-8);
}

TEST(SpatialStatics, ColumnStabilityDoesNotDependOnTheOrientation) {
  // The column of StabilityOfAColumnBelowAndAboveItsBucklingLoad along a random direction.
  const double Pcr = M_PI * M_PI / 4.0;
  const Eigen::Matrix3d R = objectivity::randomRotation(9);
  for (double fraction : {0.5, 1.5}) {
    const std::string dat = axiallyLoadedColumn(fraction * Pcr);
    const core::Model m = io::readDatString(objectivity::rotatedDat(dat, R), "column.dat");
    const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
    ASSERT_TRUE(run.completed) << run.stopReason;
    EXPECT_EQ(run.steps.back().newton.stable, fraction < 1.0) << fraction;
  }
}

// Issue 34 item 4: a sweep prescribes the rotation of a spatial orientation node about a global
// axis (not an Euler parameter), and sweeps the cross-spring pivot through a leaf end without
// calling the smooth path a turning point. The load that holds a rotation is the moment about that
// axis: the static analysis under that moment (gravity as in the sweep) turns the platform by the
// prescribed angle, measured from the rotation matrices, not from the sweep's own formula.
TEST(SweepSpatial, ThePivotsRotationIsPrescribedAboutAGlobalAxis) {
  const std::string path = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_coarse.dat";
  const core::Model m = io::readDatFile(path);
  analysis::SweepOptions o;
  o.node = 4;
  o.component = 3;  // about global z
  o.from = -0.05, o.to = 0.05, o.steps = 3, o.nev = 2;
  const analysis::SweepResult r = analysis::sweep(m, o);
  ASSERT_TRUE(r.completed) << r.stopReason;
  ASSERT_EQ(r.points.size(), 3u);
  EXPECT_NE(r.prescribed.find("rotation of node 4 about global z"), std::string::npos) << r.prescribed;
  const core::Node& n4 = m.nodes[m.nodeByLabel.at(4)];
  const Eigen::Matrix3d R0 = core::euler::rotation(m.x0.segment<4>(n4.firstCoord));
  for (const auto& p : r.points) {
    const Eigen::Matrix3d R = core::euler::rotation(p.x.segment<4>(n4.firstCoord)) * R0.transpose();
    EXPECT_NEAR(std::atan2(R(1, 0), R(0, 0)), p.value, 1e-9) << p.value;
  }
  const double moment = r.points.back().load;
  EXPECT_GT(moment, 0.0);
  // The same moment as a static load.
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string dat = text.str();
  for (const char* line :
       {"DELXF\t\t  3\t\t0.000000\t-0.020000\t0.000000", "DELXF\t\t  4\t\t0.000000\t0.000000\t0.005000"}) {
    const auto at = dat.find(line);
    ASSERT_NE(at, std::string::npos) << line;
    dat.erase(at, std::string(line).size());
  }
  const auto end = dat.find("\nITERSTEP");  // the statement, not the header's mention of it
  ASSERT_NE(end, std::string::npos);
  char line[64];
  std::snprintf(line, sizeof line, "\nDELXF 4 0 0 %.17g", moment);
  dat.insert(end, line);
  const core::Model loaded = io::readDatString(dat);
  const analysis::StaticRun st = analysis::staticAnalysis(loaded, 0);
  ASSERT_TRUE(st.completed) << st.stopReason;
  const Eigen::Matrix3d R = core::euler::rotation(st.steps.back().x.segment<4>(n4.firstCoord)) * R0.transpose();
  EXPECT_NEAR(std::atan2(R(1, 0), R(0, 0)), 0.05, 2e-6);
  // The leaf end sweeps through the same range of motion (before: stopped after one configuration).
  analysis::SweepOptions x = o;
  x.node = 3, x.component = 1, x.from = 0.095, x.to = 0.105, x.steps = 3;
  const analysis::SweepResult rx = analysis::sweep(m, x);
  EXPECT_TRUE(rx.completed) << rx.stopReason;
  // An Euler parameter is no quantity to sweep.
  x.node = 4, x.component = 4;
  EXPECT_THROW(analysis::sweep(m, x), std::invalid_argument);
}
