// Modes 3 and 4 (linearisation along a trajectory, paper Eq. 15 and Fig. 7b): the dynamic
// stiffening N and velocity sensitivity C against the classical rotating cantilever, and the
// matrices written by `flexmb --mode 3` against a direct evaluation.
#include <gtest/gtest.h>
#include <matio.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "analysis/Simulation.hpp"
#include "analysis/Statics.hpp"
#include "analysis/TrajectoryModes.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/tests/ModelTexts.hpp"
#include "io/formats/DatReader.hpp"
#include "solvers/QuadraticEigen.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

// A cantilever spinning in its own plane about its root: the first in-plane bending frequency in
// the rotating frame follows omega^2 = omega0^2 + (K1 - 1) W^2 with Southwell's coefficient
// K1 = 1.193 for small W: the centrifugal tension stiffens (+K1 W^2, in G through the inertia
// loads) and the spin softens (-W^2, in N). Without C and N (the frozen spectrum) the softening
// is missing. Checked as the slope of omega^2 against W^2 at small W.
TEST(TrajectoryModes, SpinningCantileverFollowsSouthwell) {
  const int n = 12;
  const double L = 1.0, EI = 2.0, rhoA = 3.0;
  const double w0exact = 1.875104068711961 * 1.875104068711961 * std::sqrt(EI / (rhoA * L * L * L * L));
  auto lowest = [&](double W, double& frozen, double& zeta) {
    const core::Model m = io::readDatString(test::spinningBeam(n, L, EI, rhoA, W), "spinning.dat");
    core::Linearization lin(m);
    core::LinearizedSystem sys;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(lin.size());
    lin.inMotion(0.3, zero, zero, zero, sys);  // the straight beam in steady rotation solves Eq. 13
    EXPECT_LT(sys.Q.norm(), 1e-9 * (1 + sys.K.norm())) << "steady rotation is an exact motion";
    const auto q = solvers::quadraticModes(sys.M, sys.C + sys.D, sys.K + sys.N + sys.G, 1);
    EXPECT_TRUE(q.ok) << q.message;
    frozen = analysis::naturalFrequencies(sys, 1).omega[0];
    zeta = q.damping[0];
    return q.omega[0];
  };
  double f0, z0;
  const double w0 = lowest(0.0, f0, z0);
  EXPECT_NEAR(w0, w0exact, 1e-4 * w0exact);
  const double W = 0.1 * w0;
  double frozen, zeta;
  const double w = lowest(W, frozen, zeta);
  const double slope = (w * w - w0 * w0) / (W * W), slopeFrozen = (frozen * frozen - w0 * w0) / (W * W);
  std::printf(
      "  spinning cantilever, W = 0.1 omega0: d(omega^2)/d(W^2) = %.4f with C and N (Southwell K1 - 1 = 0.193), "
      "%.4f frozen (K1 = 1.193); zeta %.1e\n",
      slope, slopeFrozen, zeta);
  EXPECT_NEAR(slope, 0.1932, 0.005);
  EXPECT_NEAR(slopeFrozen, 1.1932, 0.005);
  EXPECT_NEAR(zeta, 0.0, 1e-9) << "no damping: the gyroscopic terms do not dissipate";
}
