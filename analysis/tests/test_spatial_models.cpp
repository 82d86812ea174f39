// Spatial models (issue 11) against independent values: the linear 3-D cantilever (Timoshenko
// beam theory), the elastica in two planes and a skew plane, a tip moment rolling the beam up,
// Euler and lateral-torsional buckling (SPACAR's mode 8 factors from K0 and G0), and cantilever
// frequencies in both bending planes and torsion. The models are written as .dat text in the
// style SPACAR Light writes (position node 2i-1, orientation node 2i, BEAM ... y1 y2 y3,
// DYNE e 1 2 3 4 5 6, moments as three global XF components).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "analysis/tests/EnergyDrift.hpp"
#include "analysis/tests/Objectivity.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/Inertia.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/tests/Energy.hpp"
#include "core/tests/ShortRun.hpp"
#include "io/formats/DatReader.hpp"
#include "solvers/Ode45.hpp"

using namespace flexmb;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;
constexpr double kPi = std::numbers::pi;

namespace {

struct Cantilever {
  int n = 1;
  double L = 1.0;
  Vec3 dir = Vec3::UnitX();
  Vec3 y = Vec3::UnitY();
  std::string type = "BEAM";
  double EA = 1e7, GIt = 1, EIy = 1, EIz = 1, cy = 0, cz = 0;
  double rhoA = 0, Jxx = 0, Jyy = 0, Jzz = 0;
  Vec3 F = Vec3::Zero(), M = Vec3::Zero();    // XF at the tip (global)
  Vec3 dF = Vec3::Zero(), dM = Vec3::Zero();  // DELXF at the tip
  int steps = 1;
  Vec4 tipLambda = Vec4(1, 0, 0, 0);

  int tipPos() const { return 2 * (n + 1) - 1; }
  int tipOri() const { return 2 * (n + 1); }
  std::string dat() const {
    std::ostringstream s;
    s.precision(17);
    s << "# spatial cantilever, SPACAR Light style numbering\n#NODES Nn X Y Z\n";
    for (int i = 1; i <= n + 1; ++i) {
      const Vec3 p = dir * (L * (i - 1) / n);
      s << "X\t" << 2 * i - 1 << "\t" << p[0] << "\t" << p[1] << "\t" << p[2] << "\t#node " << i << "\n";
    }
    if (tipLambda != Vec4(1, 0, 0, 0))
      s << "LAMBDA " << tipOri() << " " << tipLambda[0] << " " << tipLambda[1] << " " << tipLambda[2] << " "
        << tipLambda[3] << "\n";
    s << "#ELEMENTS\n";
    for (int e = 1; e <= n; ++e)
      s << type << "\t" << e << "\t" << 2 * e - 1 << "\t" << 2 * e << "\t" << 2 * e + 1 << "\t" << 2 * e + 2 << "\t"
        << y[0] << "\t" << y[1] << "\t" << y[2] << "\t#element " << e << "\n";
    for (int e = 1; e <= n; ++e) s << "DYNE\t" << e << "\t1 2 3 4 5 6\n";
    s << "FIX\t1\nFIX\t2\n\nEND\nHALT\n\n";
    for (int e = 1; e <= n; ++e) {
      s << "ESTIFF\t" << e << "\t" << EA << "\t" << GIt << "\t" << EIy << "\t" << EIz << "\t" << cy << "\t" << cz
        << "\n";
      if (rhoA > 0) s << "EM\t" << e << "\t" << rhoA << "\t" << Jxx << "\t" << Jyy << "\t" << Jzz << "\t0\n";
    }
    auto vec = [&](const char* kw, int node, const Vec3& v) {
      if (v.isZero(0.0)) return;
      s << kw << "\t" << node << "\t" << v[0] << "\t" << v[1] << "\t" << v[2] << "\n";
    };
    vec("XF", tipPos(), F);
    vec("XF", tipOri(), M);
    vec("DELXF", tipPos(), dF);
    vec("DELXF", tipOri(), dM);
    s << "ITERSTEP\t50\t" << steps << "\nEND\nEND\n";
    return s.str();
  }
};

Vec3 tipPosition(const core::Model& m, const Eigen::VectorXd& x, int label) {
  return x.segment<3>(m.nodes[m.nodeByLabel.at(label)].firstCoord);
}
Vec4 tipParameters(const core::Model& m, const Eigen::VectorXd& x, int label) {
  return x.segment<4>(m.nodes[m.nodeByLabel.at(label)].firstCoord);
}

analysis::StaticRun solve(const Cantilever& c, int buckling = 0, int nev = 0) {
  const core::Model m = io::readDatString(c.dat(), "cantilever.dat");
  return analysis::staticAnalysis(m, nev, 0, {}, buckling);
}

}  // namespace

TEST(SpatialModels, LinearCantileverIsExactWithOneElement) {
  // One BEAM in a skew direction, tip force in both local planes and a torque about the axis,
  // tip with non-trivial initial Euler parameters: the linear response K0^-1 Q is Timoshenko's.
  Cantilever c;
  c.n = 1;
  c.L = 1.7;
  c.dir = Vec3(1, 2, -0.5).normalized();
  c.y = Vec3(0.3, -0.2, 1.0);
  c.EA = 50, c.GIt = 0.7, c.EIy = 1.3, c.EIz = 2.1, c.cy = 0.02, c.cz = 0.05;
  c.tipLambda = Vec4(0.5, -0.4, 0.6, 0.2).normalized();
  const Mat3 F = core::euler::elementFrame(c.dir, c.y);
  const double Fy = 1e-3, Fz = -2e-3, Mx = 1.5e-3;
  c.F = F * Vec3(0, Fy, Fz);
  c.M = F * Vec3(Mx, 0, 0);
  const core::Model m = io::readDatString(c.dat(), "linear.dat");
  core::Linearization lin(m);
  const Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size());
  lin.kinematics().solvePositions(0.0, eta);
  Eigen::VectorXd f;
  lin.appliedForces(0.0, 1.0, f);
  core::LinearizedSystem sys;
  lin.atRest(0.0, eta, f, sys, false);
  const Eigen::VectorXd dq = sys.K.ldlt().solve(sys.Q);
  const Eigen::VectorXd dx = lin.transfer() * dq;
  const int tp = m.nodes[m.nodeByLabel.at(c.tipPos())].firstCoord;
  const int to = m.nodes[m.nodeByLabel.at(c.tipOri())].firstCoord;
  const Vec3 u = F.transpose() * dx.segment<3>(tp);
  const Vec3 th =
      F.transpose() * (2.0 * core::euler::globalRateMatrix(lin.kinematics().x().segment<4>(to)) * dx.segment<4>(to));
  const double L = c.L;
  const Vec3 uRef(0.0, Fy * L * L * L / (3 * c.EIz) + Fy * L * c.cz / c.EIz,
                  Fz * L * L * L / (3 * c.EIy) + Fz * L * c.cy / c.EIy);
  const Vec3 thRef(Mx * L / c.GIt, -Fz * L * L / (2 * c.EIy), Fy * L * L / (2 * c.EIz));
  const double eu = (u - uRef).norm() / uRef.norm(), et = (th - thRef).norm() / thRef.norm();
  std::printf("linear cantilever, 1 BEAM: tip displacement rel. error %.2e, tip rotation rel. error %.2e\n", eu, et);
  EXPECT_LT(eu, 1e-9);
  EXPECT_LT(et, 1e-9);
}

TEST(SpatialModels, ElasticaInTwoPlanesAndASkewPlane) {
  // P L^2/EI = 1, tip dead load perpendicular to the beam: w/L = 0.30172 (Mattiasson).
  const double ref = 0.30172;
  struct Plane {
    const char* name;
    Vec3 load;
  };
  const double a = kPi / 6;
  for (const Plane& pl :
       {Plane{"x-y", Vec3::UnitY()}, Plane{"x-z", Vec3::UnitZ()}, Plane{"skew", Vec3(0, std::cos(a), std::sin(a))}}) {
    double err[3];
    int k = 0;
    for (int n : {4, 8, 16}) {
      Cantilever c;
      c.n = n;
      c.L = 2.0;
      c.EIy = c.EIz = 3.0;
      c.GIt = 2.0;
      c.EA = 1e7 * c.EIz / (c.L * c.L);
      c.dF = -(c.EIz / (c.L * c.L)) * pl.load;
      const auto run = solve(c);
      ASSERT_TRUE(run.completed) << run.stopReason;
      const core::Model m = io::readDatString(c.dat(), "e.dat");
      const Vec3 tip = tipPosition(m, run.steps.back().x, c.tipPos());
      const double w = -tip.dot(pl.load) / c.L;
      err[k++] = w - ref;
      std::printf("elastica %-4s plane, %2d BEAM: w/L = %.5f (u/L = %.5f), error %.2e\n", pl.name, n, w,
                  1 - tip[0] / c.L, w - ref);
    }
    EXPECT_LT(std::abs(err[2]), 1e-3 * ref) << pl.name;
    const double order = std::log2(err[1] / err[2]);
    std::printf("  observed order %.2f\n", order);
    EXPECT_NEAR(order, 2.0, 0.3) << pl.name;
  }
}

TEST(SpatialModels, TipMomentRollsTheBeamIntoACircle) {
  // Dead moment M about z: a circular arc of radius EI/M turned by M L/EI. Half a turn puts the tip
  // at (0, 2L/pi, 0), a full turn back at the root. The bending measure l0 sin(theta) converges to
  // this with O(h^2). The applied moment is read back from the nodal loads (M = E(lambda) f/2), so
  // the check does not depend on how DELXF is spread over the load steps.
  for (const double turns : {0.5, 1.0}) {
    double prev = 0;
    for (int n : {16, 32, 64}) {
      Cantilever c;
      c.n = n;
      c.EIz = 2.0;
      c.EIy = 2.0;
      c.EA = 1e8;
      c.steps = turns < 1 ? 1 : 8;
      c.dM = Vec3(0, 0, 2 * kPi * turns * c.EIz / c.L);  // DELXF: the total, reached at the last step
      const auto run = solve(c);
      ASSERT_TRUE(run.completed) << run.stopReason;
      const core::Model m = io::readDatString(c.dat(), "m.dat");
      const Eigen::VectorXd& x = run.steps.back().x;
      Eigen::VectorXd f;
      core::appliedLoads(m, core::Inertia(m), 0.0, run.steps.back().loadFactor, x, f);
      const Vec4 l = tipParameters(m, x, c.tipOri());
      const int to = m.nodes[m.nodeByLabel.at(c.tipOri())].firstCoord;
      const Vec3 M = 0.5 * core::euler::globalRateMatrix(l) * f.segment<4>(to) / l.squaredNorm();
      const double theta = M[2] * c.L / c.EIz, R = c.EIz / M[2];
      ASSERT_NEAR(theta, 2 * kPi * turns, 1e-9) << "applied moment";
      const Vec3 ref(R * std::sin(theta), R * (1 - std::cos(theta)), 0);
      const Vec3 tip = tipPosition(m, x, c.tipPos());
      const double err = (tip - ref).norm() / c.L;
      // The Euler parameters give the angle modulo 2 pi: report it next to the exact one.
      const double angle = theta + std::remainder(2 * std::atan2(l[3], l[0]) - theta, 2 * kPi);
      std::printf("tip moment, %.1f turn, %2d BEAM: tip error %.2e L, tip rotation %.5f (exact %.5f)\n", turns, n, err,
                  angle, theta);
      if (prev > 0) {
        EXPECT_NEAR(std::log2(prev / err), 2.0, 0.3);
      }
      prev = err;
      if (n == 64) {
        EXPECT_LT(err, 5e-3);
      }
    }
  }
}

namespace {
// The roll-up of a cantilever by an end moment M = 2 pi EI / L about its local z axis, along a
// beam axis `dir` with cross-section y axis `y`: at each load step the tip error against the exact
// circle (tip at (EI/M)(sin phi, 1 - cos phi) in the bending plane, phi = M L / EI) in units of L,
// and the tip rotation's error (|R(lambda_tip) - Rot(z, phi)|, Frobenius).
struct RollUp {
  std::vector<double> position, rotation;
  std::vector<int> iterations;
  std::string stop;
};
RollUp rollUp(const Vec3& dir, const Vec3& y, int n, int steps) {
  Cantilever c;
  c.n = n;
  c.dir = dir;
  c.y = y;
  c.EIz = c.EIy = 2.0;
  c.GIt = 2.0;
  c.EA = 1e8;
  c.steps = steps;
  const Mat3 F = core::euler::elementFrame(dir, y);
  c.dM = F * Vec3(0, 0, 2 * kPi * c.EIz / c.L);
  const core::Model m = io::readDatString(c.dat(), "rollup.dat");
  const auto run = analysis::staticAnalysis(m, 0);
  RollUp r;
  r.stop = run.completed ? "" : run.stopReason;
  for (const auto& st : run.steps) {  // SPACAR's load steps 0..steps, step 0 unloaded
    const double phi = st.loadFactor * 2 * kPi;
    const Vec3 ref =
        phi == 0.0 ? Vec3(c.L * F.col(0)) : Vec3(F * Vec3(std::sin(phi), 1 - std::cos(phi), 0) * (c.L / phi));
    r.position.push_back((tipPosition(m, st.x, c.tipPos()) - ref).norm() / c.L);
    const Mat3 Rz = Eigen::AngleAxisd(phi, F.col(2)).toRotationMatrix();
    r.rotation.push_back((core::euler::rotation(tipParameters(m, st.x, c.tipOri())) - Rz).norm());
    r.iterations.push_back(st.iterations);
  }
  return r;
}
}  // namespace

TEST(SpatialModels, EndMomentRollUpIsTheSameInAnySkewOrientation) {
  // The moment's load stiffness on Euler parameters is antisymmetric (core/dynamics/NodalMatrices.hpp): with
  // it in the Newton tangent the roll-up converges in any orientation, and the skew beam (axis
  // (1, 2, 2)/3) has the aligned beam's errors to round-off.
  const int n = 32, steps = 8;
  const RollUp aligned = rollUp(Vec3::UnitX(), Vec3::UnitY(), n, steps);
  const Vec3 axis = Vec3(1, 2, 2) / 3, y = Vec3(2, -2, 1) / 3;  // y orthogonal to the axis
  const RollUp skew = rollUp(axis, y, n, steps);
  ASSERT_TRUE(aligned.stop.empty()) << aligned.stop;
  ASSERT_TRUE(skew.stop.empty()) << skew.stop;
  ASSERT_EQ(aligned.position.size(), size_t(steps + 1));
  ASSERT_EQ(skew.position.size(), size_t(steps + 1));
  double worst = 0.0;
  for (int k = 0; k <= steps; ++k) {
    std::printf(
        "roll-up, %d BEAM, load %d/%d: tip error %.3e L aligned, %.3e L skew; rotation error %.3e / %.3e; Newton "
        "iterations %d / %d\n",
        n, k, steps, aligned.position[k], skew.position[k], aligned.rotation[k], skew.rotation[k],
        aligned.iterations[k], skew.iterations[k]);
    worst = std::max(
        {worst, std::abs(aligned.position[k] - skew.position[k]), std::abs(aligned.rotation[k] - skew.rotation[k])});
    EXPECT_LT(skew.iterations[k], 10) << "load step " << k;
    EXPECT_LT(aligned.position[k], 1e-2);  // the O(h^2) discretisation error of 32 elements
  }
  std::printf("roll-up: largest difference of the errors, skew against aligned: %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
  // A full turn: the tip is back at the root, turned by 2 pi (to the discretisation error).
  EXPECT_LT(aligned.position.back(), 1e-2);
  EXPECT_LT(aligned.rotation.back(), 0.1);
}

TEST(SpatialModels, EndMomentTangentIsTheDerivativeOfTheResidual) {
  // The full (non-symmetric) tangent T = Kbar + Gbar + Gskew of the skew roll-up at a deformed
  // state (a third of a turn, with a twisting and a lateral component, in one load step) against
  // central differences of the static residual Q, column by
  // column, for the dense projection (Linearization::tangent) and the sparse saddle-point solve
  // (staticTangent). Without Gskew the difference is O(1) of T's skew part.
  Cantilever c;
  c.n = 6;
  c.dir = Vec3(1, 2, 2) / 3;
  c.y = Vec3(2, -2, 1) / 3;
  c.EIz = c.EIy = 2.0, c.GIt = 1.5, c.EA = 1e4;
  c.dM = core::euler::elementFrame(c.dir, c.y) * Vec3(0.3, -0.4, 2 * kPi * c.EIz / c.L) / 3.0;
  c.steps = 1;
  const core::Model m = io::readDatString(c.dat(), "rollup.dat");
  const auto run = analysis::staticAnalysis(m, 0);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_EQ(run.steps.back().loadFactor, 1.0);
  const double s = run.steps.back().loadFactor;
  core::Linearization lin(m);
  lin.kinematics().setRelativeTolerance(1e-15);
  lin.kinematics().setConfiguration(run.steps.back().x);
  Eigen::VectorXd eta = run.steps.back().eta;
  for (int i = 0; i < eta.size(); ++i) eta[i] += 1e-3 * std::sin(0.3 + 1.1 * i);  // off the equilibrium
  Eigen::VectorXd Q, Qp, Qm, f;
  lin.staticResidual(0.0, eta, s, 1.0, Q);
  lin.appliedForces(0.0, s, f, 1.0);
  Eigen::MatrixXd T;
  lin.tangent(0.0, eta, f, Q, T);
  const int nq = lin.size();
  Eigen::MatrixXd Tfd(nq, nq);
  const double h = 1e-6;
  for (int j = 0; j < nq; ++j) {
    Eigen::VectorXd ep = eta, em = eta;
    ep[j] += h, em[j] -= h;
    lin.staticResidual(0.0, ep, s, 1.0, Qp);
    lin.staticResidual(0.0, em, s, 1.0, Qm);
    Tfd.col(j) = -(Qp - Qm) / (2 * h);
  }
  const double skewPart = (0.5 * (Tfd - Tfd.transpose())).norm() / Tfd.norm();
  const double dense = (T - Tfd).norm() / Tfd.norm();
  ASSERT_TRUE(lin.staticTangent(0.0, eta, s, 1.0, Q));
  Eigen::MatrixXd Tinv(nq, nq);
  Eigen::VectorXd col;
  for (int j = 0; j < nq; ++j) {
    lin.solveStaticTangent(Tfd.col(j), col);
    Tinv.col(j) = col;
  }
  const double sparse = (Tinv - Eigen::MatrixXd::Identity(nq, nq)).norm() / std::sqrt(double(nq));
  std::printf(
      "skew roll-up tangent (%d DOF): |T - FD| / |FD| = %.2e dense, |T^-1 FD - I| = %.2e sparse; skew part of the "
      "FD tangent %.2e\n",
      nq, dense, sparse, skewPart);
  EXPECT_GT(skewPart, 1e-3);  // the moment's load stiffness matters here
  EXPECT_LT(dense, 1e-6);
  EXPECT_LT(sparse, 1e-5);
}

TEST(SpatialModels, EulerColumnBucklingWithBeamNL) {
  // Clamped-free column, axial tip load: P_cr = pi^2 EI / (4 L^2); 8 BEAMNL within 0.5%.
  for (const char* type : {"BEAMNL", "BEAM"}) {
    Cantilever c;
    c.n = 8;
    c.type = type;
    c.EIy = 1.0, c.EIz = 1.5, c.GIt = 1.0, c.EA = 1e5;
    const double Pref = 1e-3;
    c.F = Vec3(-Pref, 0, 0);
    const auto run = solve(c, 3);
    ASSERT_TRUE(run.completed) << run.stopReason;
    ASSERT_GE(run.steps.back().buckling.size(), 1);
    const double Pcr = run.steps.back().buckling[0] * Pref;
    const double ref = kPi * kPi * c.EIy / 4;
    std::printf("Euler column, 8 %s: P_cr L^2/EI = %.5f (exact %.5f), error %.3f%%\n", type, Pcr, ref,
                100 * (Pcr / ref - 1));
    if (std::string(type) == "BEAMNL")
      EXPECT_LT(std::abs(Pcr / ref - 1), 5e-3);
    else
      EXPECT_LT(std::abs(Pcr / ref - 1), 1e-2);  // plain BEAM: string geometric stiffness only
  }
}

TEST(SpatialModels, LateralTorsionalBucklingOfANarrowStrip) {
  // Prandtl: P_cr L^2 / sqrt(EI_weak GIt) = 4.0126 for a tip load at the centroid in the stiff plane.
  Cantilever c;
  c.n = 16;
  c.EIy = 1.0;  // weak (bending in x-z)
  c.EIz = 1e4;  // strong (bending in x-y, the load plane)
  c.GIt = 1.0;
  c.EA = 1e5;
  const double Pref = 1e-3;
  c.F = Vec3(0, -Pref, 0);
  const auto run = solve(c, 3);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_GE(run.steps.back().buckling.size(), 1);
  const double k = run.steps.back().buckling[0] * Pref / std::sqrt(c.EIy * c.GIt);
  std::printf("lateral-torsional buckling, 16 BEAM: P_cr L^2/sqrt(EI GIt) = %.4f (Prandtl 4.0126), error %.2f%%\n", k,
              100 * (k / 4.0126 - 1));
  EXPECT_LT(std::abs(k / 4.0126 - 1), 1e-2);
}

TEST(SpatialModels, CantileverFrequenciesInBothPlanesAndTorsion) {
  // omega = 3.51602 sqrt(EI/(rhoA L^4)) per bending plane, (pi/2) sqrt(GIt/(Jxx L^2)) in torsion.
  const double L = 1.0, rhoA = 1.0, EIz = 1.0, EIy = 4.0, GIt = 1.0, Jxx = 0.02;
  const double b1 = 1.8751040687119611;  // first root of cos b cosh b = -1
  const double ref[3] = {b1 * b1 * std::sqrt(EIz / rhoA), b1 * b1 * std::sqrt(EIy / rhoA),
                         kPi / 2 * std::sqrt(GIt / Jxx)};
  double prevErr[3] = {0, 0, 0};
  for (int n : {4, 8, 16}) {
    Cantilever c;
    c.n = n;
    c.L = L;
    c.EA = 1e6, c.GIt = GIt, c.EIy = EIy, c.EIz = EIz;
    c.rhoA = rhoA, c.Jxx = Jxx;
    const auto run = solve(c, 0, 4);
    ASSERT_TRUE(run.completed) << run.stopReason;
    const Eigen::VectorXd w = run.steps.back().frequencies.omega;
    ASSERT_GE(w.size(), 3);
    std::printf("cantilever frequencies, %2d BEAM:", n);
    // modes sorted: bending x-y (EIz), bending x-z (EIy), torsion
    for (int i = 0; i < 3; ++i) {
      const double e = std::abs(w[i] / ref[i] - 1);
      std::printf("  %.5f (exact %.5f, %.3f%%)", w[i], ref[i], 100 * e);
      if (prevErr[i] > 1e-7) {
        EXPECT_LT(e, prevErr[i]) << "mode " << i;
      }
      prevErr[i] = e;
    }
    std::printf("\n");
  }
  EXPECT_LT(prevErr[0], 1e-6);
  EXPECT_LT(prevErr[1], 1e-6);
  EXPECT_LT(prevErr[2], 1e-3);  // torsion with the rotary inertia lumped at the nodes
}

TEST(SpatialModels, TangentStiffnessMatchesFiniteDifferences) {
  // K + G of Eq. 16 against central differences of the generalised forces Q, at a deformed state
  // under loads (moment, force, gravity) of the SPACAR Light style cross-spring pivot.
  const core::Model m =
      io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_coarse.dat");
  core::Linearization lin(m);
  // The file carries SPACAR Light's ITERSTEP tolerance 5e-7; finite differences need the positions
  // far tighter than their step.
  lin.kinematics().setRelativeTolerance(1e-14);
  Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size());
  for (int i = 0; i < eta.size(); ++i) eta[i] = 1e-3 * std::sin(1.0 + i);
  lin.kinematics().solvePositions(0.0, eta);
  Eigen::VectorXd f;
  lin.appliedForces(0.0, 0.5, f);
  core::LinearizedSystem sys;
  lin.atRest(0.0, eta, f, sys, false);
  const Eigen::MatrixXd T = sys.K + sys.G;
  Eigen::MatrixXd Tfd(lin.size(), lin.size());
  const double h = 1e-7;
  Eigen::VectorXd Qp, Qm;
  for (int j = 0; j < lin.size(); ++j) {
    Eigen::VectorXd ep = eta, em = eta;
    ep[j] += h;
    em[j] -= h;
    lin.staticForces(0.0, ep, f, Qp);
    lin.staticForces(0.0, em, f, Qm);
    Tfd.col(j) = -(Qp - Qm) / (2 * h);
  }
  const Eigen::MatrixXd Ts = 0.5 * (Tfd + Tfd.transpose());
  const double err = (T - Ts).norm() / Ts.norm();
  std::printf("cross-spring pivot: |K + G - FD tangent| / |FD| = %.2e (skew part of the FD tangent %.2e)\n", err,
              (Tfd - Ts).norm() / Ts.norm());
  EXPECT_LT(err, 1e-5);  // the difference is the skew part of the FD tangent: difference noise
}

TEST(SpatialModels, FreeTumblingFlexibleBeamConservesEnergy) {
  // Two flexible BEAMs, nothing fixed: node 1's position and lambda1..3 of its orientation are DYNX
  // (lambda0 follows from L2MIN1), every deformation DYNE. Initial spin about an oblique axis,
  // translation and bending in both planes: gyroscopic and convective terms all act.
  const std::string text =
      "BEAM 1 1 2 3 4 0 1 0\nBEAM 2 3 4 5 6 0 1 0\n"
      "X 1 0 0 0\nX 3 0.5 0 0\nX 5 1.0 0 0\n"
      "DYNX 1 1 2 3\nDYNX 2 2 3 4\nDYNE 1 1 2 3 4 5 6\nDYNE 2 1 2 3 4 5 6\nEND\nHALT\n"
      "EM 1 2.0 2e-3 1e-3 1e-3 0\nEM 2 2.0 2e-3 1e-3 1e-3 0\n"
      "ESTIFF 1 2e4 30 50 80\nESTIFF 2 2e4 30 50 80\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "tumbling.dat");
  ASSERT_EQ(m.numDofs(), 18);
  core::EquationsOfMotion eom(m), probe(m);
  const double relTol = 1e-10;
  eom.kinematics().setRelativeTolerance(1e-5 * relTol);
  probe.kinematics().setRelativeTolerance(1e-5 * relTol);
  Eigen::VectorXd y0 = eom.initialState();
  const int nq = 18;
  y0[nq + 0] = 0.3, y0[nq + 1] = -0.2, y0[nq + 2] = 0.1;  // translation of node 1
  // lambdad = E^T w / 2 with |w| = 2.3 rad/s: node 2 turns less than pi in 1 s, so lambda0 (the
  // calculable parameter) stays away from 0, where lambda1..3 stop being coordinates.
  y0[nq + 3] = 0.5 * 0.5, y0[nq + 4] = 0.5 * 1.0, y0[nq + 5] = 0.5 * 2.0;
  y0[6 + 2] = 4e-3, y0[6 + 4] = -3e-3, y0[12 + 3] = 2e-3, y0[12 + 5] = 5e-3;  // bending
  core::Inertia inertia(m);
  auto energy = [&](const core::StateOutputs& st) { return core::test::totalEnergy(m, inertia, st, true); };
  // Slow by design (5 min under the sanitizers): the short run integrates the first 0.1 s.
  const double tEnd = flexmb::test::shortRun() ? 0.1 : 1.0;
  solvers::OdeResult r;
  const double worst = flexmb::test::largestEnergyDeviation(eom, probe, y0, tEnd, relTol, energy, r);
  ASSERT_EQ(r.status, solvers::OdeStatus::Success) << r.message;
  std::printf("free tumbling BEAM pair: relative energy drift over %g s at RelTol 1e-10: %.3e (%s)\n", tEnd, worst,
              solvers::Ode45::formatStats(r.stats).c_str());
  EXPECT_LT(worst, 1e-7);
}

TEST(SpatialModels, CrossSpringPivotRotationalStiffness) {
  // The SPACAR Light style pivot (2 x 20 BEAMs, leaves of length L = 0.1 sqrt 2 crossing at
  // mid-length): a platform rotating about the crossing point bends each leaf at constant curvature
  // without shear force, so K = 2 EI/L (docs/theory/spatial-elements.md 9.7), up to the leaves' axial compliance.
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot.dat");
  std::ostringstream text;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("GRAVITY", 0) == 0 || line.rfind("DELXF", 0) == 0 || line.rfind("XF", 0) == 0) continue;
    if (line.rfind("ITERSTEP", 0) == 0) line = "ITERSTEP 10 1\nDELXF 4 0 0 1e-5";
    text << line << "\n";
  }
  const core::Model m = io::readDatString(text.str(), "pivot.dat");
  const auto run = analysis::staticAnalysis(m, 0, 1);
  ASSERT_TRUE(run.completed) << run.stopReason;
  const Vec4 l = tipParameters(m, run.steps.back().x, 4);
  const double theta = 2 * std::atan2(l[3], l[0]);
  const double K = 1e-5 / theta, ref = 2 * 7.0e-3 / (0.1 * std::sqrt(2.0));
  std::printf("cross-spring pivot (2 x 20 BEAM): K = %.6f N m/rad, 2 EI/L = %.6f, difference %.3f%%\n", K, ref,
              100 * (K / ref - 1));
  EXPECT_LT(std::abs(K / ref - 1), 1e-3);
}

TEST(SpatialModels, SpaLightPivotFilesRunUnchangedWithTheirIterstep) {
  // The SPACAR Light style pivot files carry SPACAR Light's own ITERSTEP line for incremental loads
  // (ITERSTEP 10 9 5e-7 1 3 0). They must go through `check` and `static` unchanged, and the
  // equilibria must not depend on that tolerance: the same file with 1e-12 gives the same states
  // (the command line on the same files: tools/tests/test_cli_models.cpp).
  for (const char* name : {"cross_spring_pivot_coarse.dat", "cross_spring_pivot.dat"}) {
    const std::string path = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/" + name;
    std::ifstream in(path);
    std::ostringstream original, tight;
    std::string line;
    bool spalightIterstep = false;
    while (std::getline(in, line)) {
      original << line << "\n";
      if (line.rfind("ITERSTEP", 0) == 0) {
        std::istringstream ls(line);
        std::string kw;
        double f[6];
        ls >> kw;
        for (double& v : f) ls >> v;
        spalightIterstep = ls && f[0] == 10 && f[1] == 9 && f[2] == 5e-7 && f[3] == 1 && f[4] == 3 && f[5] == 0;
        line = "ITERSTEP 10 9 1e-12 1 3 0";
      }
      tight << line << "\n";
    }
    ASSERT_TRUE(spalightIterstep) << name << ": expected SPACAR Light's `ITERSTEP 10 9 5e-7 1 3 0`";
    // In process: load steps 0..9, the same equilibria as with a 1e-12 tolerance.
    const core::Model a = io::readDatString(original.str(), name), b = io::readDatString(tight.str(), name);
    const auto ra = analysis::staticAnalysis(a, 0), rb = analysis::staticAnalysis(b, 0);
    ASSERT_TRUE(ra.completed) << ra.stopReason;
    ASSERT_TRUE(rb.completed) << rb.stopReason;
    ASSERT_EQ(ra.steps.size(), 10u);
    ASSERT_EQ(rb.steps.size(), 10u);
    double diff = 0;
    for (size_t i = 0; i < ra.steps.size(); ++i)
      diff = std::max(diff, (ra.steps[i].x - rb.steps[i].x).lpNorm<Eigen::Infinity>());
    const Vec4 l = tipParameters(a, ra.steps.back().x, 4);
    std::printf(
        "%s with ITERSTEP 10 9 5e-7 1 3 0: check and static pass, load steps 0..9, platform turned %.5f rad; "
        "largest coordinate difference to the 1e-12 run %.1e\n",
        name, 2 * std::atan2(l[3], l[0]), diff);
    EXPECT_LT(diff, 1e-12);
  }
}

// Objectivity (issue 22): every benchmark above that runs along a global axis, turned as a whole by
// a random rotation R (objectivity::rotatedDat: positions, y axes, loads, gravity, initial Euler
// parameters), gives the turned answer: configurations x' = R x at every load step, the same
// buckling factors and frequencies, and the turned mode shapes.
namespace {
struct Pair {
  core::Model a, b;
  analysis::StaticRun ra, rb;
};
Pair solvedTurned(const std::string& dat, const Mat3& R, int buckling = 0, int nev = 0) {
  Pair p{io::readDatString(dat, "a.dat"), io::readDatString(objectivity::rotatedDat(dat, R), "b.dat"), {}, {}};
  p.ra = analysis::staticAnalysis(p.a, nev, 0, {}, buckling);
  p.rb = analysis::staticAnalysis(p.b, nev, 0, {}, buckling);
  return p;
}
double stepsDifference(const Pair& p, const Mat3& R, double L) {
  double worst = 0.0;
  for (size_t k = 0; k < p.ra.steps.size(); ++k)
    worst = std::max(worst, objectivity::configurationDifference(p.a, p.ra.steps[k].x, p.b, p.rb.steps[k].x, R, L));
  return worst;
}
}  // namespace

TEST(SpatialObjectivity, StaticBenchmarksTurnWithTheModel) {
  const Mat3 R = objectivity::randomRotation();
  struct Case {
    const char* name;
    Cantilever c;
  };
  std::vector<Case> cases;
  {  // elastica, load in the x-y plane (ElasticaInTwoPlanesAndASkewPlane)
    Cantilever c;
    c.n = 8, c.L = 2.0, c.EIy = c.EIz = 3.0, c.GIt = 2.0, c.EA = 1e7 * 3.0 / 4.0;
    c.dF = -(c.EIz / (c.L * c.L)) * Vec3::UnitY();
    cases.push_back({"elastica", c});
  }
  {  // half a turn by a tip moment (TipMomentRollsTheBeamIntoACircle)
    Cantilever c;
    c.n = 16, c.EIz = c.EIy = 2.0, c.EA = 1e8;
    c.dM = Vec3(0, 0, kPi * c.EIz / c.L);
    cases.push_back({"tip moment", c});
  }
  {  // a full turn in 8 steps (EndMomentRollUpIsTheSameInAnySkewOrientation)
    Cantilever c;
    c.n = 16, c.EIz = c.EIy = 2.0, c.GIt = 2.0, c.EA = 1e8, c.steps = 8;
    c.dM = Vec3(0, 0, 2 * kPi * c.EIz / c.L);
    cases.push_back({"roll-up", c});
  }
  for (const Case& cs : cases) {
    const Pair p = solvedTurned(cs.c.dat(), R);
    ASSERT_TRUE(p.ra.completed) << cs.name << ": " << p.ra.stopReason;
    ASSERT_TRUE(p.rb.completed) << cs.name << " turned: " << p.rb.stopReason;
    ASSERT_EQ(p.ra.steps.size(), p.rb.steps.size()) << cs.name;
    const double d = stepsDifference(p, R, cs.c.L);
    std::printf("objectivity, %-10s: %zu load steps, largest |R x - x'| %.2e L (positions) / rotations\n", cs.name,
                p.ra.steps.size(), d);
    EXPECT_LT(d, 1e-8) << cs.name;
  }
}

TEST(SpatialObjectivity, BucklingFactorsDoNotDependOnTheOrientation) {
  const Mat3 R = objectivity::randomRotation(7);
  // Euler column (BEAMNL) and lateral-torsional buckling (BEAM), as above.
  Cantilever column;
  column.n = 8, column.type = "BEAMNL", column.EIy = 1.0, column.EIz = 1.5, column.GIt = 1.0, column.EA = 1e5;
  column.F = Vec3(-1e-3, 0, 0);
  Cantilever strip;
  strip.n = 16, strip.EIy = 1.0, strip.EIz = 1e4, strip.GIt = 1.0, strip.EA = 1e5;
  strip.F = Vec3(0, -1e-3, 0);
  for (const auto& [name, c] : {std::pair{"Euler column", column}, std::pair{"lateral-torsional", strip}}) {
    const Pair p = solvedTurned(c.dat(), R, 3);
    ASSERT_TRUE(p.ra.completed && p.rb.completed) << name;
    const Eigen::VectorXd& a = p.ra.steps.back().buckling;
    const Eigen::VectorXd& b = p.rb.steps.back().buckling;
    ASSERT_EQ(a.size(), 3) << name;
    ASSERT_EQ(b.size(), 3) << name;
    const double d = ((a - b).cwiseQuotient(a)).cwiseAbs().maxCoeff();
    std::printf("objectivity, %s buckling factors %.6g %.6g %.6g: turned model differs by %.1e (relative)\n", name,
                a[0], a[1], a[2], d);
    EXPECT_LT(d, 1e-8) << name;
  }
}

TEST(SpatialObjectivity, FrequenciesAndModeShapesTurnWithTheModel) {
  const Mat3 R = objectivity::randomRotation(11);
  Cantilever c;  // CantileverFrequenciesInBothPlanesAndTorsion, 8 elements
  c.n = 8, c.EA = 1e6, c.GIt = 1.0, c.EIy = 4.0, c.EIz = 1.0, c.rhoA = 1.0, c.Jxx = 0.02;
  const Pair p = solvedTurned(c.dat(), R, 0, 6);
  ASSERT_TRUE(p.ra.completed && p.rb.completed);
  const auto& fa = p.ra.steps.back().frequencies;
  const auto& fb = p.rb.steps.back().frequencies;
  ASSERT_EQ(fa.omega.size(), 6);
  ASSERT_EQ(fb.omega.size(), 6);
  const double df = ((fa.omega - fb.omega).cwiseQuotient(fa.omega)).cwiseAbs().maxCoeff();
  const double dm = objectivity::modeDifference(p.a, p.ra.steps.back().x, fa.nodalModes, fa.omega, p.b,
                                                p.rb.steps.back().x, fb.nodalModes, fb.omega, R);
  std::printf("objectivity, cantilever: 6 frequencies differ by %.1e (relative), mode shapes by %.1e\n", df, dm);
  EXPECT_LT(df, 1e-9);
  EXPECT_LT(dm, 1e-8);
}

TEST(SpatialObjectivity, CrossSpringPivotTurnsWithTheModel) {
  // The SPACAR Light style pivot with its loads and gravity (9 load steps) and its frequencies.
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_coarse.dat");
  std::ostringstream text;
  text << in.rdbuf();
  const Mat3 R = objectivity::randomRotation(3);
  const Pair p = solvedTurned(text.str(), R, 0, 4);
  ASSERT_TRUE(p.ra.completed) << p.ra.stopReason;
  ASSERT_TRUE(p.rb.completed) << p.rb.stopReason;
  ASSERT_EQ(p.ra.steps.size(), 10u);  // ITERSTEP's 9 steps: load steps 0..9
  ASSERT_EQ(p.rb.steps.size(), 10u);
  const double d = stepsDifference(p, R, 0.1);
  const auto& fa = p.ra.steps.back().frequencies;
  const auto& fb = p.rb.steps.back().frequencies;
  const double df = ((fa.omega - fb.omega).cwiseQuotient(fa.omega)).cwiseAbs().maxCoeff();
  const double dm = objectivity::modeDifference(p.a, p.ra.steps.back().x, fa.nodalModes, fa.omega, p.b,
                                                p.rb.steps.back().x, fb.nodalModes, fb.omega, R);
  std::printf(
      "objectivity, cross-spring pivot (coarse): 10 load steps differ by %.1e (positions / 0.1 m, rotations), "
      "4 frequencies by %.1e, modes by %.1e\n",
      d, df, dm);
  EXPECT_LT(d, 1e-8);
  EXPECT_LT(df, 1e-7);
  EXPECT_LT(dm, 1e-6);
}
