// Spatial dynamics against independent references (issue 11): a spatial double pendulum of two
// RBEAMs and two HINGEs with non-parallel axes, against a minimal-coordinate rigid-body
// integration written here (Lagrange's equations in the two hinge angles, classical RK4).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "analysis/Simulation.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
constexpr double kPiD = 3.14159265358979323846;

namespace {

Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
  return s;
}
Mat3 rot(const Vec3& a, double th) { return Eigen::AngleAxisd(th, a).toRotationMatrix(); }

// Two point masses m1 at P1 = R1 r1 and m2 at P2 = P1 + R1 R2 r2, R1 = Rot(a1, th1) about the
// fixed origin, R2 = Rot(a2, th2) about an axis fixed in body 1 (a2 in the initial frame).
struct DoublePendulum {
  Vec3 a1, a2, r1, r2, g;
  double m1, m2;

  void positions(const Eigen::Vector2d& th, Vec3& P1, Vec3& P2) const {
    const Mat3 R1 = rot(a1, th[0]);
    P1 = R1 * r1;
    P2 = P1 + R1 * rot(a2, th[1]) * r2;
  }
  // qdd from M(th) qdd = sum m_i J_i^T (g - c_i), c_i = sum_jk d2P_i/dth_j dth_k thd_j thd_k.
  Eigen::Vector2d accelerations(const Eigen::Vector2d& th, const Eigen::Vector2d& thd) const {
    const Mat3 R1 = rot(a1, th[0]), A1 = skew(a1), A2 = skew(a2);
    const Vec3 P1 = R1 * r1, u = rot(a2, th[1]) * r2, s = R1 * u;
    Eigen::Matrix<double, 3, 2> J1, J2;
    J1.col(0) = A1 * P1;
    J1.col(1).setZero();
    J2.col(0) = A1 * (P1 + s);
    J2.col(1) = R1 * A2 * u;
    const Vec3 c1 = A1 * A1 * P1 * thd[0] * thd[0];
    const Vec3 c2 = A1 * A1 * (P1 + s) * thd[0] * thd[0] + 2 * A1 * R1 * A2 * u * thd[0] * thd[1] +
                    R1 * A2 * A2 * u * thd[1] * thd[1];
    const Eigen::Matrix2d M = m1 * J1.transpose() * J1 + m2 * J2.transpose() * J2;
    const Eigen::Vector2d Q = m1 * J1.transpose() * (g - c1) + m2 * J2.transpose() * (g - c2);
    return M.ldlt().solve(Q);
  }
};

// flexmb against the RK4 reference for the pendulum p over 1 s (51 outputs).
struct PendulumComparison {
  core::Trajectory trajectory;
  double worst = 0.0, refErr = 0.0, travel = 0.0;
  int secondHingeAngle = -1;  // index in e of the rotation of HINGE 3
};

PendulumComparison compareDoublePendulum(const DoublePendulum& p) {
  const Vec3 P1 = p.r1, P2 = p.r1 + p.r2;
  std::ostringstream s;
  s.precision(17);
  s << "# spatial double pendulum: RBEAM + HINGE twice, non-parallel hinge axes\n"
    << "X 1 0 0 0\nX 3 " << P1[0] << " " << P1[1] << " " << P1[2] << "\nX 5 " << P2[0] << " " << P2[1] << " " << P2[2]
    << "\n"
    << "HINGE 1 2 4 " << p.a1[0] << " " << p.a1[1] << " " << p.a1[2] << "\n"
    << "RBEAM 2 1 4 3 0 0 1\n"
    << "HINGE 3 4 6 " << p.a2[0] << " " << p.a2[1] << " " << p.a2[2] << "\n"
    << "RBEAM 4 3 6 5 0 0 1\n"
    << "FIX 1\nFIX 2\nDYNE 1 1\nDYNE 3 1\nEND\nHALT\n"
    << "XM 3 " << p.m1 << "\nXM 5 " << p.m2 << "\nGRAVITY 0 0 -9.81\nTIMESTEP 1 50\nEND\nEND\n";
  const core::Model m = io::readDatString(s.str(), "double_pendulum.dat");
  EXPECT_EQ(m.numDofs(), 2);
  analysis::SimulationOptions o;
  o.relTol = 1e-10;
  o.absTol = 1e-12;
  PendulumComparison c;
  c.secondHingeAngle = m.elements[m.elementByLabel.at(3)].firstDef;
  c.trajectory = analysis::simulate(m, o);
  const core::Trajectory& tr = c.trajectory;
  EXPECT_TRUE(tr.completed) << tr.stopReason;
  if (tr.time.size() != 51u) {
    ADD_FAILURE() << "expected 51 outputs, got " << tr.time.size();
    return c;
  }

  // Reference: RK4 with h = 1e-4 s (error O(h^4), checked below against h = 2e-4).
  auto integrate = [&](double h, std::vector<Eigen::Vector2d>& out) {
    Eigen::Vector4d y = Eigen::Vector4d::Zero();
    auto f = [&](const Eigen::Vector4d& z) {
      Eigen::Vector4d d;
      d.head<2>() = z.tail<2>();
      d.tail<2>() = p.accelerations(z.head<2>(), z.tail<2>());
      return d;
    };
    const int perOutput = static_cast<int>(std::lround(0.02 / h));
    out = {y.head<2>()};
    for (int k = 0; k < 50; ++k) {
      for (int i = 0; i < perOutput; ++i) {
        const Eigen::Vector4d k1 = f(y), k2 = f(y + 0.5 * h * k1), k3 = f(y + 0.5 * h * k2), k4 = f(y + h * k3);
        y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
      out.push_back(y.head<2>());
    }
  };
  std::vector<Eigen::Vector2d> ref, coarse;
  integrate(1e-4, ref);
  integrate(2e-4, coarse);
  const int n3 = m.nodes[m.nodeByLabel.at(3)].firstCoord, n5 = m.nodes[m.nodeByLabel.at(5)].firstCoord;
  for (size_t i = 0; i < tr.time.size(); ++i) {
    Vec3 q1, q2, c1, c2;
    p.positions(ref[i], q1, q2);
    p.positions(coarse[i], c1, c2);
    const Vec3 x1 = tr.states[i].x.segment<3>(n3), x2 = tr.states[i].x.segment<3>(n5);
    c.worst = std::max({c.worst, (x1 - q1).norm(), (x2 - q2).norm()});
    c.refErr = std::max({c.refErr, (c1 - q1).norm(), (c2 - q2).norm()});
    c.travel = std::max(c.travel, (q2 - P2).norm());
  }
  std::printf(
      "spatial double pendulum over 1 s (tip travels up to %.3f m): max position error %.2e m "
      "(reference RK4 h = 1e-4 vs 2e-4: %.1e m); %ld steps, %ld evaluations\n",
      c.travel, c.worst, c.refErr, tr.nsteps, tr.nfevals);
  return c;
}

}  // namespace

TEST(SpatialDynamics, DoublePendulumOfRBeamsAndHingesMatchesRigidBodyReference) {
  DoublePendulum p;
  p.a1 = Vec3(0.0, 1.0, 0.2).normalized();
  p.a2 = Vec3(1.0, 0.3, -0.4).normalized();
  p.r1 = Vec3(0.2, 0.05, -0.2);
  p.r2 = Vec3(0.1, 0.1, -0.15);
  p.g = Vec3(0, 0, -9.81);
  p.m1 = 1.5, p.m2 = 0.8;
  const PendulumComparison c = compareDoublePendulum(p);
  ASSERT_GT(c.travel, 0.1);   // the motion is large
  ASSERT_LT(c.refErr, 1e-9);  // the reference is far tighter than the bound below
  // ode45 at RelTol 1e-10 / AbsTol 1e-12 (kinematic tolerance 1e-5 of that): local errors of order
  // 1e-10 of the 0.5 m reach, accumulated over ~300 steps, stay below 1e-8 m.
  EXPECT_LT(c.worst, 1e-8);
}

// A hinge DOF turning through pi: its principal-value angle must not make the kinematic Newton
// jump a revolution (it diverged at t = 0.52 s before the kinematics unwrapped periodic angles).
TEST(SpatialDynamics, HingeAngleRunsOnThroughAHalfTurn) {
  DoublePendulum p;
  p.a1 = Vec3(0.0, 1.0, 0.2).normalized();
  p.a2 = Vec3(1.0, 0.3, -0.4).normalized();
  p.r1 = Vec3(0.3, 0.0, 0.0);
  p.r2 = Vec3(0.05, 0.25, 0.1);
  p.g = Vec3(0, 0, -9.81);
  p.m1 = 1.5, p.m2 = 0.8;
  const PendulumComparison c = compareDoublePendulum(p);
  ASSERT_EQ(c.trajectory.time.size(), 51u);
  ASSERT_LT(c.refErr, 1e-9);
  EXPECT_LT(c.worst, 1e-8);
  // The second hinge's angle passes pi continuously.
  const int k = c.secondHingeAngle;
  double maxAngle = 0.0, maxJump = 0.0;
  for (size_t i = 0; i < c.trajectory.states.size(); ++i) {
    const double a = c.trajectory.states[i].e[k];
    maxAngle = std::max(maxAngle, std::abs(a));
    if (i > 0) maxJump = std::max(maxJump, std::abs(a - c.trajectory.states[i - 1].e[k]));
  }
  std::printf("second hinge angle reaches %.3f rad; largest change between outputs %.3f rad\n", maxAngle, maxJump);
  EXPECT_GT(maxAngle, 3.3);
  EXPECT_LT(maxJump, 1.0);
}

// Reduction on a spatial model (issue 11): the four-wire parallel guidance of
// datfiles/spatial/wire_guidance.dat, driven by a corner force, simulated full and with modal and
// SVD-modal bases; then modes 3/4 (linearisation along the trajectory) full and reduced.
#include <chrono>

#include "analysis/Reduction.hpp"
#include "analysis/TrajectoryModes.hpp"

TEST(SpatialDynamics, ParallelGuidanceReducedWithModalAndSvdModalBases) {
  const std::string path = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/wire_guidance.dat";
  const core::Model m = io::readDatFile(path);
  const int corner = m.nodes[m.nodeByLabel.at(3)].firstCoord;
  auto run = [&](const std::optional<Eigen::MatrixXd>& V, double& seconds) {
    analysis::SimulationOptions o;
    o.basis = V;
    const auto t0 = std::chrono::steady_clock::now();
    core::Trajectory tr = analysis::simulate(m, o);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return tr;
  };
  double tFull = 0;
  const core::Trajectory full = run(std::nullopt, tFull);
  ASSERT_TRUE(full.completed) << full.stopReason;
  double amplitude = 0;
  for (const auto& s : full.states)
    amplitude = std::max(amplitude, (s.x.segment<3>(corner) - m.x0.segment<3>(corner)).norm());
  std::printf("wire guidance (%d DOF), full: %ld evaluations, %ld steps, %.2f s; corner amplitude %.3e m\n",
              m.numDofs(), full.nfevals, full.nsteps, tFull, amplitude);
  ASSERT_GT(amplitude, 1e-4);

  struct Case {
    const char* name;
    analysis::ReductionOptions o;
    double bound;
  };
  analysis::ReductionOptions modal3, modal6, svd;
  modal3.method = modal6.method = "modal";
  modal3.modes = 3;
  modal6.modes = 6;
  svd.method = "svd-modal";
  svd.modes = 3;
  svd.configs = 5;
  svd.node = 3, svd.component = 1;
  svd.from = 0.08, svd.to = 0.0805;  // the loaded corner pushed 0.5 mm along x
  std::optional<Eigen::MatrixXd> V3;
  core::Trajectory red3;
  for (const Case& c : {Case{"MODAL-3", modal3, 0.06}, Case{"MODAL-6", modal6, 0.01}, Case{"SVD-MODAL", svd, 0.02}}) {
    const analysis::ReductionResult b = analysis::buildBasis(m, c.o);
    if (std::string(c.name) == "MODAL-3") V3 = b.V;
    double t = 0;
    const core::Trajectory red = run(b.V, t);
    ASSERT_TRUE(red.completed) << c.name << ": " << red.stopReason;
    ASSERT_EQ(red.time.size(), full.time.size());
    if (std::string(c.name) == "MODAL-3") red3 = red;
    double err = 0;
    for (size_t i = 0; i < full.time.size(); ++i)
      err = std::max(err, (red.states[i].x.segment<3>(corner) - full.states[i].x.segment<3>(corner)).norm());
    std::printf(
        "  %-9s (%ld columns): %ld evaluations, %ld steps, %.3f s; corner response error %.3e m = %.3f%% "
        "of the amplitude\n",
        c.name, static_cast<long>(b.V.cols()), red.nfevals, red.nsteps, t, err, 100 * err / amplitude);
    EXPECT_LT(err / amplitude, c.bound) << c.name;
    EXPECT_LT(red.nfevals, full.nfevals / 10) << c.name;  // the >800 Hz modes are gone
  }

  // Modes 3/4 along the trajectory: the guidance frequencies (17, 26, 29 Hz) barely move at these
  // small deflections; MODAL-3 (along its own trajectory) gives them at t = 0.
  const analysis::TrajectoryModes tmFull = analysis::trajectoryModes(m, full, 6, std::nullopt);
  const analysis::TrajectoryModes tmRed = analysis::trajectoryModes(m, red3, 3, V3);
  ASSERT_TRUE(tmFull.completed) << tmFull.stopReason;
  ASSERT_TRUE(tmRed.completed) << tmRed.stopReason;
  double drift = 0, redErr = 0, redErr0 = 0;
  for (int k = 0; k < 3; ++k) {
    std::printf("  t = 0: full %.5f, MODAL-3 %.5f Hz\n", tmFull.omegaFrozen[0][k] / (2 * kPiD),
                tmRed.omegaFrozen[0][k] / (2 * kPiD));
    redErr0 = std::max(redErr0, std::abs(tmRed.omegaFrozen[0][k] / tmFull.omegaFrozen[0][k] - 1));
  }
  for (size_t i = 0; i < tmFull.time.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      drift = std::max(drift, std::abs(tmFull.omegaFrozen[i][k] / tmFull.omegaFrozen[0][k] - 1));
      redErr = std::max(redErr, std::abs(tmRed.omegaFrozen[i][k] / tmFull.omegaFrozen[i][k] - 1));
    }
  std::printf(
      "  modes 3/4: f1..f3 at t = 0: %.4f %.4f %.4f Hz, largest change along the run %.2e; "
      "MODAL-3 vs full %.2e\n",
      tmFull.omegaFrozen[0][0] / (2 * kPiD), tmFull.omegaFrozen[0][1] / (2 * kPiD),
      tmFull.omegaFrozen[0][2] / (2 * kPiD), drift, redErr);
  EXPECT_NEAR(tmFull.omegaFrozen[0][0] / (2 * kPiD), 17.05, 0.05);  // the static eigenanalysis' value
  EXPECT_LT(drift, 1e-2);
  // At t = 0 MODAL-3 spans the three guidance modes: the same frequencies (the load applied at
  // t = 0 enters G, hence the small difference of the third). Along the run the third (platform
  // twist) of the reduced model rises to ~32 Hz while the full one stays at 28.8 Hz; the first two
  // agree to 1e-4. Likely cause (not verified): the reduced model's stresses (S e of three modes)
  // are not in equilibrium with the corner load, so its G differs. Printed, not asserted.
  EXPECT_LT(redErr0, 1e-2);
}
