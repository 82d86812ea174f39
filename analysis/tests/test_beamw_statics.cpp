// BEAMW in whole models (core/elements/BEAMW.md section 5): a cantilevered strip under an end
// torque with warping restrained at the clamp and free at the tip against Vlasov's closed form
// (validation (a)), and BEAMW without warping stiffness and with free warping against BEAM (the
// warping coordinates condense out: the same equilibrium under large tip loads).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "core/elements/EulerParameters.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

struct Section {
  double EA = 1e6, GIt = 1.0, EIy = 50.0, EIz = 80.0, cy = 0.0, cz = 0.0, ECw = 0.0;
};

// A straight cantilever of n elements from (0,0,0) to (L,0,0), y vector (0,1,0). Node i (0..n) has
// position node 3i+1, orientation 3i+2 and warping node 3i+3 (SPACAR Light's numbering). The root's
// position and orientation are fixed, and its warping node when `clampWarping`. Tip loads: a force
// and a global moment.
std::string cantilever(bool warping, int n, double L, const Section& s, bool clampWarping, const Eigen::Vector3d& f,
                       const Eigen::Vector3d& moment) {
  std::ostringstream o;
  o.precision(17);
  for (int i = 0; i <= n; ++i) o << "X " << 3 * i + 1 << " " << L * i / n << " 0 0\n";
  for (int k = 1; k <= n; ++k) {
    const int p = 3 * (k - 1), q = 3 * k;
    if (warping)
      o << "BEAMW " << k << " " << p + 1 << " " << p + 2 << " " << p + 3 << " " << q + 1 << " " << q + 2 << " " << q + 3
        << " 0 1 0\n";
    else
      o << "BEAM " << k << " " << p + 1 << " " << p + 2 << " " << q + 1 << " " << q + 2 << " 0 1 0\n";
    o << "DYNE " << k << " 1 2 3 4 5 6\n";
  }
  o << "FIX 1\nFIX 2\n";
  if (warping && clampWarping) o << "FIX 3\n";
  o << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) {
    o << "ESTIFF " << k << " " << s.EA << " " << s.GIt << " " << s.EIy << " " << s.EIz << " " << s.cy << " " << s.cz;
    if (warping) o << " " << s.ECw;
    o << "\n";
  }
  o << "XF " << 3 * n + 1 << " " << f[0] << " " << f[1] << " " << f[2] << "\n";
  o << "XF " << 3 * n + 2 << " " << moment[0] << " " << moment[1] << " " << moment[2] << "\n";
  o << "ITERSTEP 30 4\nEND\nEND\n";
  return o.str();
}

struct Tip {
  Eigen::Vector3d x;
  Eigen::Matrix3d R;
  Eigen::VectorXd e;
  Eigen::VectorXd sigma;
};

Tip solveTip(const std::string& text, int n) {
  const core::Model m = io::readDatString(text, "cantilever.dat");
  const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
  EXPECT_TRUE(run.completed) << run.stopReason;
  const Eigen::VectorXd& x = run.steps.back().x;
  Tip t;
  t.x = x.segment<3>(m.nodes[m.nodeByLabel.at(3 * n + 1)].firstCoord);
  t.R = core::euler::rotation(x.segment<4>(m.nodes[m.nodeByLabel.at(3 * n + 2)].firstCoord).normalized());
  t.e = run.steps.back().e;
  t.sigma = run.steps.back().sigma;
  return t;
}

}  // namespace

// Validation (a): phi(L) = T L/(G It) (1 - tanh(kL)/(kL)), k^2 = G It/(E Cw), for warping fixed at
// the clamp (phi' = 0) and free at the tip (bimoment 0). Two and four elements are within 1% for kL
// up to 6; the error falls at least fivefold per halving of the elements (the cubic Hermite twist
// converges as h^4: 16 asymptotically; core/elements/BEAMW.md 5.1 has the table).
TEST(BeamWStatics, VlasovCantileverTipTwist) {
  const double L = 1.0, T = 1e-4;  // small: the linear theory
  const int meshes[] = {1, 2, 4, 8};
  std::printf("   kL   Vlasov phi(L)/(TL/GIt)   BEAMW/Vlasov N=1        N=2        N=4        N=8   BEAM/Vlasov\n");
  for (double kL : {0.5, 1.0, 2.0, 3.0, 4.0, 6.0}) {
    Section s;
    s.GIt = 2.0;
    s.ECw = s.GIt * L * L / (kL * kL);
    const double exact = T * L / s.GIt * (1 - std::tanh(kL) / kL);
    double ratio[4];
    for (int i = 0; i < 4; ++i) {
      const int n = meshes[i];
      const Tip w = solveTip(cantilever(true, n, L, s, true, Eigen::Vector3d::Zero(), {T, 0, 0}), n);
      ratio[i] = std::atan2(w.R(2, 1), w.R(1, 1)) / exact;
      EXPECT_LT((w.x - Eigen::Vector3d(L, 0, 0)).norm(), 1e-12);  // the twist is pure: no bending, no stretch
    }
    const Tip b = solveTip(cantilever(false, 4, L, s, true, Eigen::Vector3d::Zero(), {T, 0, 0}), 4);
    const double phiB = std::atan2(b.R(2, 1), b.R(1, 1));
    std::printf("%5.1f   %22.6f   %16.5f %10.5f %10.5f %10.5f   %11.4f\n", kL, exact / (T * L / s.GIt), ratio[0],
                ratio[1], ratio[2], ratio[3], phiB / exact);
    EXPECT_NEAR(ratio[1], 1.0, 0.01) << "N = 2, kL = " << kL;
    EXPECT_NEAR(ratio[2], 1.0, 0.01) << "N = 4, kL = " << kL;
    for (int i = 0; i + 1 < 4; ++i) {
      const double e = std::abs(ratio[i] - 1), eFiner = std::abs(ratio[i + 1] - 1);
      if (e > 1e-5) {
        EXPECT_LT(eFiner, e / 5) << "N = " << meshes[i] << " -> " << meshes[i + 1] << ", kL = " << kL;
      }
    }
    EXPECT_NEAR(phiB * s.GIt / (T * L), 1.0, 1e-6);  // BEAM: St Venant only
  }
}

// Without warping stiffness and with free warping, one BEAMW condenses exactly to BEAM (its
// warping coordinates make e7 = e8 = 0 whatever the load): the same equilibrium under large tip
// loads in every direction. In a chain the shared twist rate couples neighbours only where the
// torque varies along the beam; under an end torque it is uniform and the chain equals BEAM too.
TEST(BeamWStatics, WithoutWarpingStiffnessFreeWarpingEqualsBeam) {
  Section s;
  s.cy = 1e-3, s.cz = 2e-3;
  struct Case {
    int n;
    Eigen::Vector3d f, m;
    const char* what;
  };
  const Case cases[] = {
      {1, {1.05, -7.0, 10.5}, {0.21, -1.4, 1.75}, "one element, force and moment in every direction"},
      {4, {50.0, 0.0, 0.0}, {0.8, 0.0, 0.0}, "four elements, end torque and tension"},
  };
  for (const Case& c : cases) {
    const Tip w = solveTip(cantilever(true, c.n, 1.0, s, false, c.f, c.m), c.n);
    const Tip b = solveTip(cantilever(false, c.n, 1.0, s, false, c.f, c.m), c.n);
    const double dx = (w.x - b.x).norm(), dR = (w.R - b.R).norm();
    const double twist = std::atan2(b.R(2, 1), b.R(1, 1));
    double e78 = 0;
    for (int k = 0; k < c.n; ++k) e78 = std::max({e78, std::abs(w.e[8 * k + 6]), std::abs(w.e[8 * k + 7])});
    std::printf(
        "%s: tip displacement %.4f m, twist %.3f rad; BEAMW - BEAM: position %.1e, rotation %.1e; "
        "max |e7|, |e8| %.1e\n",
        c.what, (b.x - Eigen::Vector3d(1, 0, 0)).norm(), twist, dx, dR, e78);
    EXPECT_GT((b.x - Eigen::Vector3d(1, 0, 0)).norm() + std::abs(twist), 0.1);  // large, not a linear check
    EXPECT_LT(dx, 1e-9) << c.what;
    EXPECT_LT(dR, 1e-9) << c.what;
    EXPECT_LT(e78, 1e-9) << c.what;
  }
}
