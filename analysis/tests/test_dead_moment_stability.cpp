// The stability flag of static equilibria under dead moments (issue 38): a moment of fixed axis is a
// circulatory load, so the kinetic criterion decides (solvers/KineticStability.hpp), not the energy
// criterion on the symmetric part K0 + G0. References, for a cantilever of length L and equal
// bending stiffnesses EI under an end torque T about its axis (linearised Kirchhoff rod):
//  - a semi-tangential torque (Ziegler; Argyris et al. 1979: the moment vector turns with half the tip
//    rotation) buckles statically at T = pi EI / L: the tip condition EI w'' = i T (w'(z) - w'(L)/2)
//    has a solution w' = (1 - e^{ikz}) w'(L)/2 with e^{ikL} = -1, k = T / EI;
//  - a dead (axial) torque has no adjacent equilibrium at any T (w'' = i k w', w'(0) = 0 gives w' = 0),
//    and its two equal bending frequencies split into a complex pair for any T > 0 (flutter: Nikolai's
//    paradox), the split growing linearly with T; with unequal bending stiffnesses the split needs
//    a finite torque.
// flexmb's symmetric part of the dead torque's tangent is, in the straight rod, the semi-tangential
// one: it turns indefinite at pi EI / L. The flag follows the kinetic test.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace deadmoment {

constexpr double kPi = std::numbers::pi;

// A cantilever of n BEAMs along x (L = 1, EIz = 1, EIy given, GIt = 10, rhoA = 1, rotary inertias
// 1e-3), clamped at x = 0, with an end moment (global components) of 2 pi EI / L times `axis`
// reached in `steps` load steps.
analysis::StaticRun cantilever(int n, double EIy, const Eigen::Vector3d& axis, int steps, bool mass = true) {
  std::ostringstream s;
  s.precision(17);
  for (int i = 1; i <= n + 1; ++i) s << "X " << 2 * i - 1 << " " << (i - 1.0) / n << " 0 0\n";
  for (int e = 1; e <= n; ++e)
    s << "BEAM " << e << " " << 2 * e - 1 << " " << 2 * e << " " << 2 * e + 1 << " " << 2 * e + 2 << " 0 1 0\n";
  for (int e = 1; e <= n; ++e) s << "DYNE " << e << " 1 2 3 4 5 6\n";
  s << "FIX 1\nFIX 2\nEND\nHALT\n";
  for (int e = 1; e <= n; ++e) {
    s << "ESTIFF " << e << " 1e7 10 " << EIy << " 1 0 0\n";
    if (mass) s << "EM " << e << " 1 1e-3 1e-3 1e-3 0\n";
  }
  const Eigen::Vector3d M = 2 * kPi * axis;
  s << "DELXF " << 2 * (n + 1) << " " << M[0] << " " << M[1] << " " << M[2] << "\n";
  s << "ITERSTEP 50 " << steps << "\nEND\nEND\n";
  const core::Model model = io::readDatString(s.str(), "dead_moment.dat");
  return analysis::staticAnalysis(model, 0);
}

// Lowest eigenvalue of the symmetric pencil (K0 + G0, M0): the energy criterion the flag used before.
double lowestSymmetric(const analysis::StaticStep& st) {
  const auto& s = st.system;
  return Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(s.K + s.G, s.M, Eigen::EigenvaluesOnly)
      .eigenvalues()[0];
}

const analysis::StaticStep& atLoad(const analysis::StaticRun& run, double s) {
  for (const auto& st : run.steps)
    if (std::abs(st.loadFactor - s) < 1e-9) return st;
  throw std::runtime_error("no load step at " + std::to_string(s));
}

}  // namespace deadmoment

using namespace deadmoment;

TEST(DeadMomentStability, AxialTorqueFluttersAtAnyTorqueWhileItsSymmetricPartBucklesAtPiEIOverL) {
  // 40 steps: T = k pi EI / (20 L).
  const analysis::StaticRun run = cantilever(16, 1.0, Eigen::Vector3d::UnitX(), 40);
  ASSERT_TRUE(run.completed) << run.stopReason;
  // Semi-tangential reference: the symmetric part definite at 0.95 pi EI/L, indefinite at 1.05 pi EI/L.
  const double below = lowestSymmetric(atLoad(run, 0.475)), above = lowestSymmetric(atLoad(run, 0.525));
  std::printf("dead torque, 16 BEAM: lowest eigenvalue of (K0 + G0, M0) %.4g at 0.95 pi EI/L, %.4g at 1.05 pi EI/L\n",
              below, above);
  EXPECT_GT(below, 0.0);
  EXPECT_LT(above, 0.0);
  // Kinetic (dead torque): flutter from the first step, the split linear in T, no divergence.
  double splitPerLoad = 0.0;
  for (const auto& st : run.steps) {
    if (st.loadFactor == 0.0) {
      EXPECT_FALSE(st.kinetic) << "no moment, no kinetic test";
      EXPECT_TRUE(st.newton.stable);
      continue;
    }
    ASSERT_TRUE(st.kinetic);
    const auto& k = *st.kinetic;
    EXPECT_EQ(k.verdict, solvers::KineticVerdict::Flutter) << "s " << st.loadFactor << ": " << k.describe();
    EXPECT_FALSE(st.newton.stable);
    ASSERT_GE(k.critical, 0);
    const double split = std::abs(k.lambda[k.critical].imag()) / st.loadFactor;
    if (st.loadFactor <= 0.25) {  // small torques: Im lambda = c T
      if (splitPerLoad == 0.0) splitPerLoad = split;
      EXPECT_NEAR(split, splitPerLoad, 0.02 * splitPerLoad) << "s " << st.loadFactor;
    }
  }
  std::printf("dead torque: lowest pair %s at T = 0.1 pi EI/L\n", atLoad(run, 0.05).kinetic->describe().c_str());
}

TEST(DeadMomentStability, UnequalBendingStiffnessesNeedAFiniteTorqueToFlutter) {
  const analysis::StaticRun run = cantilever(16, 2.0, Eigen::Vector3d::UnitX(), 10);
  ASSERT_TRUE(run.completed) << run.stopReason;
  const auto& low = atLoad(run, 0.1);
  const auto& high = atLoad(run, 0.3);
  ASSERT_TRUE(low.kinetic && high.kinetic);
  EXPECT_EQ(low.kinetic->verdict, solvers::KineticVerdict::Stable) << low.kinetic->describe();
  EXPECT_TRUE(low.newton.stable);
  EXPECT_EQ(high.kinetic->verdict, solvers::KineticVerdict::Flutter) << high.kinetic->describe();
  EXPECT_FALSE(high.newton.stable);
}

TEST(DeadMomentStability, RollUpIsStablePastPiEIOverLUntilItFlutters) {
  // The roll-up by a dead bending moment about z: the symmetric part turns indefinite near pi EI/L
  // (where the flag used to say UNSTABLE); the kinetic test finds the equilibria stable there and
  // flutter (two out-of-plane modes coalescing) further on, at a load that depends on the inertia.
  const analysis::StaticRun run = cantilever(16, 1.0, Eigen::Vector3d::UnitZ(), 10);
  ASSERT_TRUE(run.completed) << run.stopReason;
  int firstFlutter = -1;
  for (const auto& st : run.steps) {
    if (st.loadFactor == 0.0) continue;
    ASSERT_TRUE(st.kinetic);
    EXPECT_NE(st.kinetic->verdict, solvers::KineticVerdict::Divergence) << st.kinetic->describe();
    if (!st.kinetic->stable() && firstFlutter < 0) firstFlutter = static_cast<int>(std::lround(st.loadFactor * 10));
    std::printf("roll-up s = %.1f: symmetric part %.4g, kinetic %s\n", st.loadFactor, lowestSymmetric(st),
                st.kinetic->describe().c_str());
  }
  const auto& past = atLoad(run, 0.6);
  EXPECT_LT(lowestSymmetric(past), 0.0) << "the energy criterion would flag 1.2 pi EI/L";
  EXPECT_TRUE(past.newton.stable) << past.kinetic->describe();
  EXPECT_FALSE(atLoad(run, 0.9).newton.stable);
  EXPECT_EQ(atLoad(run, 0.9).kinetic->verdict, solvers::KineticVerdict::Flutter);
  std::printf("roll-up, 16 BEAM: first flutter at s = 0.%d (M = %.1f pi EI/L)\n", firstFlutter, 0.2 * firstFlutter);
}

TEST(DeadMomentStability, WithoutMassTheEnergyCriterionStandsAndSaysWhy) {
  // No EM: M0 = 0, the kinetic test cannot be made; the flag is the energy criterion's, and the
  // verdict in words says so (never a silent switch of criterion).
  const analysis::StaticRun run = cantilever(8, 1.0, Eigen::Vector3d::UnitX(), 5, false);
  ASSERT_TRUE(run.completed) << run.stopReason;
  for (const auto& st : run.steps) {
    if (st.loadFactor == 0.0) continue;
    ASSERT_TRUE(st.kinetic);
    EXPECT_EQ(st.kinetic->verdict, solvers::KineticVerdict::Undecided);
    const std::string verdict = analysis::stabilityVerdict(st);
    EXPECT_NE(verdict.find("could not be made"), std::string::npos) << verdict;
    EXPECT_NE(verdict.find("mass matrix is not positive definite"), std::string::npos) << verdict;
    // The energy criterion: T = 2 pi EI/L s turns K0 + G0 indefinite past s = 0.5 (pi EI/L).
    EXPECT_EQ(st.newton.stable, st.loadFactor < 0.5) << "s " << st.loadFactor << ": " << verdict;
  }
}
