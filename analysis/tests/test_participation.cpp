// Modal participation factors and effective masses (issue 53 item 3; analysis/Participation.hpp)
// against independent values: a clamped planar chain with lumped masses only (every free coordinate
// is a combination of the degrees of freedom, so the modes carry exactly the masses of the free
// nodes, and the rotation the point masses' m r^2 about the reference plus the nodes' rotary
// inertia), a free spatial pair of beams with distributed mass (nothing holds it: the modes carry
// the whole mass and inertia, R^T M R, in all six directions; the mass, centre and inertia about it
// from the beams' rhoA, length and J), and the straight guidance (the sums over all its modes are
// b^T Mbar^-1 b, its first mode carries the stroke direction x), and a fine cantilever on the sparse
// eigenanalysis (its modes carry the continuum beam's shares of its mass).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "analysis/Modes.hpp"
#include "analysis/Participation.hpp"
#include "core/tests/ModelTexts.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

analysis::InitialModes allModes(const core::Model& m, const Eigen::Vector3d& p) {
  analysis::ReferencePoint ref;
  ref.point = p;
  return analysis::initialModes(m, std::nullopt, m.numDofs(), &ref);
}

}  // namespace

TEST(Participation, ClampedChainWithPointMassesCarriesTheFreeMasses) {
  // Node 1 clamped (its mass 5 moves with the support only); every deformation a degree of freedom.
  const std::string text =
      "PLBEAM 1 1 101 2 102\nPLBEAM 2 2 102 3 103\nX 1 0 0\nX 2 0.3 0.1\nX 3 0.5 0.4\n"
      "FIX 1\nFIX 101\nDYNE 1 1 2 3\nDYNE 2 1 2 3\nEND\nHALT\n"
      "ESTIFF 1 1e4 10\nESTIFF 2 2e4 7\nXM 1 5\nXM 2 2\nXM 3 3\nXM 102 0.01\nXM 103 0.02\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "chain.dat");
  ASSERT_EQ(m.numDofs(), 6);
  const Eigen::Vector3d p(0.1, 0.2, 0.0);
  const analysis::InitialModes im = allModes(m, p);
  const analysis::ModalParticipation& mp = im.participation;
  ASSERT_EQ(mp.directions.size(), 3u);
  ASSERT_EQ(mp.effective.rows(), 6);
  const double rz = 2 * ((0.3 - 0.1) * (0.3 - 0.1) + (0.1 - 0.2) * (0.1 - 0.2)) +
                    3 * ((0.5 - 0.1) * (0.5 - 0.1) + (0.4 - 0.2) * (0.4 - 0.2)) + 0.01 + 0.02;
  const Eigen::Vector3d expected(5.0, 5.0, rz);
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(mp.total[d], expected[d], 1e-10 * expected[d]) << mp.directions[d];
    EXPECT_NEAR(mp.effective.col(d).sum(), expected[d], 1e-9 * expected[d]) << mp.directions[d];
    // Gamma^2 mu = m_eff, with mu = 1 for the mass-normalised modes.
    EXPECT_LT((mp.factors.col(d).array().square() - mp.effective.col(d).array()).abs().maxCoeff(), 1e-9 * expected[d]);
  }
  // The whole model, the clamped node's mass included: 10 at (0.21, 0.17).
  EXPECT_NEAR(mp.mass(), 10.0, 1e-12);
  const Eigen::Vector3d c = mp.centreOfMass();
  EXPECT_NEAR(c[0], (2 * 0.3 + 3 * 0.5) / 10.0, 1e-12);
  EXPECT_NEAR(c[1], (2 * 0.1 + 3 * 0.4) / 10.0, 1e-12);
  // The table: percentages of m_d, the last cumulative one 100.
  const io::CsvTable t = analysis::participationTable(im.frequencies.omega, mp);
  ASSERT_EQ(t.columns.size(), 2u + 4 * 3);
  EXPECT_EQ(t.columns[2], "gamma_x");
  EXPECT_EQ(t.columns[13], "meff_rz_cum_pct");
  EXPECT_NEAR(t.rows.back()[11], 100.0, 1e-8);
  EXPECT_NEAR(t.rows.back()[13], 100.0, 1e-8);
}

TEST(Participation, FreeSpatialBeamPairCarriesItsWholeMassAndInertia) {
  // Nothing fixed: node 1's position and lambda1..3 are DYNX, every deformation DYNE; 2 kg/m over
  // 1 m along x, J = (2e-3, 1e-3, 1e-3) kg m per length about the local axes.
  const std::string text =
      "BEAM 1 1 2 3 4 0 1 0\nBEAM 2 3 4 5 6 0 1 0\n"
      "X 1 0 0 0\nX 3 0.5 0 0\nX 5 1.0 0 0\n"
      "DYNX 1 1 2 3\nDYNX 2 2 3 4\nDYNE 1 1 2 3 4 5 6\nDYNE 2 1 2 3 4 5 6\nEND\nHALT\n"
      "EM 1 2.0 2e-3 1e-3 1e-3 0\nEM 2 2.0 2e-3 1e-3 1e-3 0\n"
      "ESTIFF 1 2e4 30 50 80\nESTIFF 2 2e4 30 50 80\nEND\nEND\n";
  const core::Model m = io::readDatString(text, "free_pair.dat");
  ASSERT_EQ(m.numDofs(), 18);
  const Eigen::Vector3d p(0.2, -0.1, 0.3);
  const analysis::InitialModes im = allModes(m, p);
  const analysis::ModalParticipation& mp = im.participation;
  ASSERT_EQ(mp.directions.size(), 6u);
  // Free: every direction is carried whole, the sum over all the modes is R^T M R's diagonal.
  for (int d = 0; d < 6; ++d) {
    const double whole = mp.rigidBody(d, d);
    EXPECT_NEAR(mp.total[d], whole, 1e-9 * whole) << mp.directions[d];
    EXPECT_NEAR(mp.effective.col(d).sum(), whole, 1e-8 * whole) << mp.directions[d];
  }
  // Mass 2 kg, centre (0.5, 0, 0); about the centre Ixx = 2e-3, Iyy = Izz = m L^2 / 12 + 1e-3.
  EXPECT_NEAR(mp.mass(), 2.0, 1e-12);
  const Eigen::Vector3d c = mp.centreOfMass();
  EXPECT_LT((c - Eigen::Vector3d(0.5, 0.0, 0.0)).norm(), 1e-12);
  const Eigen::Vector3d s = c - p;  // parallel axes
  const double m0 = 2.0, Iyy = m0 / 12.0 + 1e-3;
  EXPECT_NEAR(mp.rigidBody(3, 3), 2e-3 + m0 * (s[1] * s[1] + s[2] * s[2]), 1e-10);
  EXPECT_NEAR(mp.rigidBody(4, 4), Iyy + m0 * (s[0] * s[0] + s[2] * s[2]), 1e-10);
  EXPECT_NEAR(mp.rigidBody(5, 5), Iyy + m0 * (s[0] * s[0] + s[1] * s[1]), 1e-10);
}

TEST(Participation, StraightGuidanceStrokeModeCarriesTheStageAlongX) {
  const core::Model m = io::readDatFile(test::dat("straight_guidance.dat"));
  ASSERT_EQ(m.numDofs(), 17);
  const analysis::InitialModes im = allModes(m, Eigen::Vector3d(0.1, 0.2, 0.0));
  const analysis::ModalParticipation& mp = im.participation;
  for (int d = 0; d < 3; ++d)  // b^T Mbar^-1 b: the sum over all the modes
    EXPECT_NEAR(mp.effective.col(d).sum(), mp.total[d], 1e-9 * mp.rigidBody(d, d)) << mp.directions[d];
  // Stage 6.84 kg/m x 0.2 m; the leaves 2 x 0.228 kg/m x 0.2 m, part of which stays with the clamps.
  const double stage = 6.84 * 0.2, leaves = 2 * 0.228 * 0.2;
  EXPECT_NEAR(mp.mass(), stage + leaves, 1e-12);
  EXPECT_GT(mp.total[0], stage);
  EXPECT_LT(mp.total[0], stage + leaves);
  EXPECT_GT(mp.effective(0, 0), 0.95 * mp.total[0]);  // mode 1 is the stroke
  EXPECT_LT(mp.effective(0, 1), 1e-6 * mp.total[0]);
  std::printf(
      "straight guidance: mass %.6g kg; m_x %.6g, m_y %.6g kg, m_rz %.6g kg m^2 (all modes); mode 1 "
      "%.6g Hz carries %.4f %% of m_x\n",
      mp.mass(), mp.total[0], mp.total[1], mp.total[2], im.frequencies.omega[0] / (2 * M_PI),
      100 * mp.effective(0, 0) / mp.total[0]);
}

TEST(Participation, CantileverModesCarryTheContinuumShares) {
  // A uniform clamped-free beam of 210 PLBEAMs (420 degrees of freedom: the sparse eigenanalysis)
  // along x: across (y) its modes carry the Euler-Bernoulli shares of the beam's mass, 0.6131,
  // 0.1883, 0.0647, 0.0331 (m_eff,n / m = 2 (sigma_n / beta_n L)^2 ... for the clamped-free modes;
  // e.g. Chopra, Dynamics of Structures); rotary inertia left out.
  const int n = 210;
  const double L = 1.0, rhoA = 2.0;
  std::ostringstream s;
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 1000 + k << " " << k + 1 << " " << 1001 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << L * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 1001\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "ESTIFF " << k << " 1e6 1.0\nEM " << k << " " << rhoA << "\n";
  s << "END\nEND\n";
  const core::Model m = io::readDatString(s.str(), "cantilever.dat");
  ASSERT_EQ(m.numDofs(), 2 * n);
  ASSERT_GE(m.numDofs(), analysis::kSparseEigenFrom);
  analysis::ReferencePoint ref;
  const analysis::InitialModes im = analysis::initialModes(m, std::nullopt, 4, &ref);
  EXPECT_EQ(im.frequencies.method, "sparse-constrained");
  const analysis::ModalParticipation& mp = im.participation;
  const double mass = rhoA * L;
  EXPECT_NEAR(mp.mass(), mass, 1e-12);
  EXPECT_GT(mp.total[1], 0.995 * mass);  // the clamp keeps a sliver of the first element
  EXPECT_LE(mp.total[1], mass * (1 + 1e-12));
  const double shares[] = {0.6131, 0.1883, 0.0647, 0.0331};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(mp.effective(i, 1) / mass, shares[i], 2e-4) << "mode " << i + 1;
  EXPECT_LT(mp.effective.col(0).maxCoeff(), 1e-9 * mass);  // nothing along the beam (elongations fixed)
  std::printf("cantilever, 210 PLBEAMs: m_y / m %.6f; modes 1-4 carry %.5f %.5f %.5f %.5f of m\n", mp.total[1] / mass,
              mp.effective(0, 1) / mass, mp.effective(1, 1) / mass, mp.effective(2, 1) / mass,
              mp.effective(3, 1) / mass);
}
