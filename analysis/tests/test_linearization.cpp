// Linearisation (Eq. 15-16), statics and eigenfrequencies against independent values: finite
// differences of the generalised forces, Euler-Bernoulli theory, Euler buckling, the elastica.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

// Clamped-free beam of n PLBEAMs along +x (bending DYNE, elongations fixed), optional tip load.
std::string cantilever(int n, double L, double EI, double rhoA, double fx = 0, double fy = 0, int steps = 1) {
  std::ostringstream s;
  s.precision(17);
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 100 + k << " " << k + 1 << " " << 101 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << L * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 101\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " " << rhoA << "\nESTIFF " << k << " 1e9 " << EI << "\n";
  // DELXF is the total load reached at the last of the load steps (SPACAR's meaning).
  if (fx != 0 || fy != 0) s << "DELXF " << n + 1 << " " << fx << " " << fy << "\n";
  s << "ITERSTEP 50 " << steps << "\nEND\nEND\n";
  return s.str();
}

Eigen::VectorXd lowestOmegas(const core::LinearizedSystem& sys, int k) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(sys.K + sys.G, sys.M);
  Eigen::VectorXd w = es.eigenvalues().head(k);
  for (int i = 0; i < k; ++i) w[i] = w[i] >= 0 ? std::sqrt(w[i]) : -std::sqrt(-w[i]);
  return w;
}

// -dQ/d eta by central differences, column by column.
Eigen::MatrixXd tangentByDifferences(core::Linearization& lin, double t, const Eigen::VectorXd& eta,
                                     const Eigen::VectorXd& f, double h) {
  const int m = lin.size();
  Eigen::MatrixXd T(m, m);
  Eigen::VectorXd Qp, Qm;
  for (int j = 0; j < m; ++j) {
    Eigen::VectorXd ep = eta, em = eta;
    ep[j] += h;
    em[j] -= h;
    lin.staticForces(t, ep, f, Qp);
    lin.staticForces(t, em, f, Qm);
    T.col(j) = -(Qp - Qm) / (2 * h);
  }
  return T;
}
}  // namespace

TEST(Linearization, TangentStiffnessMatchesFiniteDifferences) {
  struct Case {
    std::string file;
    double t;
    double h;
  };
  for (const Case& c : {Case{"straight_guidance.dat", 0.05, 1e-7}, Case{"manipulator.dat", 0.2, 1e-7},
                        Case{"tests/fourbar.dat", 0.0, 1e-5}}) {
    core::Model m = io::readDatFile(dat(c.file));
    m.settings.kinematicTol = 1e-15;
    for (bool reduced : {false, true}) {
      std::optional<Eigen::MatrixXd> V;
      if (reduced) V = Eigen::MatrixXd::Random(m.numDofs(), std::max(1, m.numDofs() / 3));
      core::Linearization lin(m, V);
      Eigen::VectorXd eta = 1e-3 * Eigen::VectorXd::LinSpaced(lin.size(), -1.0, 2.0);
      Eigen::VectorXd f;
      lin.kinematics().solvePositions(c.t, reduced ? Eigen::VectorXd(*V * eta) : eta);
      lin.appliedForces(c.t, 0.0, f);
      f += Eigen::VectorXd::LinSpaced(f.size(), -3.0, 5.0);  // arbitrary extra dead loads on every coordinate
      core::LinearizedSystem sys;
      lin.atRest(c.t, eta, f, sys);
      const Eigen::MatrixXd fd = tangentByDifferences(lin, c.t, eta, f, c.h);
      const double err = (sys.K + sys.G - fd).norm() / fd.norm();
      EXPECT_LT(err, 1e-6) << c.file << (reduced ? " reduced" : " full");
      EXPECT_GT(sys.G.norm(), 1e-6 * sys.K.norm() + 1e-12) << c.file << ": geometric stiffness exercised";
    }
  }
}

TEST(Linearization, CantileverFrequenciesConvergeToEulerBernoulliAtFourthOrder) {
  const double L = 1.0, EI = 2.0, rhoA = 3.0;
  const double betaL[3] = {1.875104068711961, 4.694091132974175, 7.854757438237613};
  double prev[3] = {0, 0, 0};
  std::printf("  elements  err(w1)      err(w2)      err(w3)\n");
  for (int n : {5, 10, 20, 40}) {
    const core::Model m = io::readDatString(cantilever(n, L, EI, rhoA), "cantilever.dat");
    core::Linearization lin(m);
    core::LinearizedSystem sys;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(m.nx);
    lin.atRest(0.0, Eigen::VectorXd::Zero(lin.size()), f, sys);
    const Eigen::VectorXd w = lowestOmegas(sys, 3);
    double err[3];
    for (int i = 0; i < 3; ++i) {
      const double exact = betaL[i] * betaL[i] * std::sqrt(EI / (rhoA * std::pow(L, 4)));
      err[i] = (w[i] - exact) / exact;
      EXPECT_GT(err[i], -1e-12) << "converges from above (consistent mass), mode " << i + 1;
      if (prev[i] > 1e-9) {
        const double order = std::log2(prev[i] / err[i]);
        EXPECT_GT(order, 3.6) << "mode " << i + 1 << " at " << n << " elements";
        EXPECT_LT(order, 4.4) << "mode " << i + 1 << " at " << n << " elements";
      }
      prev[i] = err[i];
    }
    std::printf("  %8d  %.4e   %.4e   %.4e\n", n, err[0], err[1], err[2]);
  }
}

TEST(Linearization, EulerBucklingLoadOfClampedFreeColumn) {
  const double L = 1.0, EI = 2.0, rhoA = 3.0, Pcr = M_PI * M_PI * EI / (4 * L * L);
  auto lowest = [&](double P) {  // P > 0 compressive, along -x at the tip
    const core::Model m = io::readDatString(cantilever(20, L, EI, rhoA, -P, 0.0), "column.dat");
    core::Linearization lin(m);
    Eigen::VectorXd f;
    lin.kinematics().solvePositions(0.0, Eigen::VectorXd::Zero(lin.size()));
    lin.appliedForces(0.0, 1.0, f);
    core::LinearizedSystem sys;
    lin.atRest(0.0, Eigen::VectorXd::Zero(lin.size()), f, sys);
    return lowestOmegas(sys, 1)[0];
  };
  const double w0 = lowest(0.0);
  EXPECT_GT(lowest(0.995 * Pcr), 0.0);
  EXPECT_LT(lowest(1.005 * Pcr), 0.0);
  EXPECT_LT(lowest(0.5 * Pcr), w0);
  EXPECT_GT(lowest(-0.5 * Pcr), w0) << "a tensile load raises the frequency";
  // Rayleigh: w1(P)^2 / w1(0)^2 is close to 1 - P/Pcr for a clamped-free column.
  EXPECT_NEAR(std::pow(lowest(0.5 * Pcr) / w0, 2), 0.5, 0.02);
}

TEST(Statics, CantileverUnderTipDeadLoadMatchesElastica) {
  // P L^2 / EI = 1, load perpendicular to the undeformed beam (Bisshopp & Drucker): tip deflection
  // 0.30172 L, tip rotation 0.46135 rad; 10 elements, 4 load steps (XF alone: load steps 0..4, the
  // first unloaded).
  const double L = 2.0, EI = 3.0, P = EI / (L * L);
  const core::Model m = io::readDatString(cantilever(10, L, EI, 1.0, 0.0, -P, 4), "elastica.dat");
  const analysis::StaticRun run = analysis::staticAnalysis(m, 0);
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_EQ(run.steps.size(), 5u);
  const auto& last = run.steps.back();
  const int tipY = m.nodes[m.nodeByLabel.at(11)].firstCoord + 1;
  const int tipRot = m.nodes[m.nodeByLabel.at(111)].firstCoord;
  EXPECT_NEAR(-last.x[tipY] / L / 0.30172, 1.0, 1e-3);
  EXPECT_NEAR(-last.x[tipRot] / 0.46135, 1.0, 1e-3);
  EXPECT_TRUE(last.newton.stable);
}
