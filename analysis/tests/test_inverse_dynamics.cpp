// Mode 1 on a driven rigid mechanism (issue 24): the kinematics over time and the forces the
// inputs need, against a hand derivation for a rigid slider-crank (datfiles/slider_crank_rigid.dat).
//
// Crank r (uniform bar m1 = rho1 r about its end), rod l (uniform bar m2 = rho2 l), slider m3, crank
// angle theta(t) prescribed, no gravity, no loads. With s = sqrt(l^2 - r^2 sin^2 theta) the slider
// is at x_C = r cos theta + s; x' = dx_C/dtheta = -r sin theta - r^2 sin theta cos theta / s and
// x'' = -r cos theta - r^2 cos 2theta / s - r^4 sin^2 theta cos^2 theta / s^3. The crank pin moves
// with v_B = r thetad (-sin theta, cos theta), the slider with v_C = (x' thetad, 0); a uniform bar
// with end velocities v_B, v_C has kinetic energy m/6 (v_B^2 + v_B.v_C + v_C^2). So
//   T = J(theta) thetad^2 / 2,  J = m1 r^2 / 3 + m2/3 (r^2 - r sin theta x' + x'^2) + m3 x'^2,
// and Lagrange's equation gives the torque the drive applies to the crank:
//   tau = J(theta) thetadd + J'(theta) thetad^2 / 2,
//   J' = m2/3 (-r cos theta x' - r sin theta x'' + 2 x' x'') + 2 m3 x' x''.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "analysis/InverseDynamics.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

const std::string kFile = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/slider_crank_rigid.dat";

std::string text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct SliderCrank {
  double r = 0.15, l = 0.30, m1 = 1.0 * 0.15, m2 = 0.5 * 0.30, m3 = 0.2;
  double xC(double th) const { return r * std::cos(th) + std::sqrt(l * l - r * r * std::sin(th) * std::sin(th)); }
  double torque(double th, double w, double a) const {
    const double sn = std::sin(th), cs = std::cos(th), s = std::sqrt(l * l - r * r * sn * sn);
    const double x1 = -r * sn - r * r * sn * cs / s;
    const double x2 = -r * cs - r * r * std::cos(2 * th) / s - std::pow(r, 4) * sn * sn * cs * cs / std::pow(s, 3);
    const double J = m1 * r * r / 3 + m2 / 3 * (r * r - r * sn * x1 + x1 * x1) + m3 * x1 * x1;
    const double dJ = m2 / 3 * (-r * cs * x1 - r * sn * x2 + 2 * x1 * x2) + 2 * m3 * x1 * x2;
    return J * a + 0.5 * dJ * w * w;
  }
};

constexpr double kW0 = 2 * M_PI, kAlpha = 3.0;  // the file's drive: theta = kW0 t + kAlpha t^2 / 2

double coordinate(const core::Model& m, int node, int comp) {
  return m.nodes[m.nodeByLabel.at(node)].firstCoord + comp - 1;
}

}  // namespace

// The hinge's input deformation: its stress sig is the generalised stress conjugate to the crank
// angle e, positive as a spring's (one wound up by e > 0 holds sig > 0 and turns the crank back), so
// the torque the drive applies to the crank in the direction of e is -sig.
TEST(InverseDynamics, SliderCrankTorqueAtTheInputHinge) {
  const core::Model m = io::readDatFile(kFile);
  ASSERT_EQ(m.numDofs(), 0);
  ASSERT_TRUE(analysis::isDrivenRigidMechanism(m));
  const analysis::InverseDynamicsRun run = analysis::inverseDynamics(m, {});
  const core::Trajectory& t = run.trajectory;
  ASSERT_TRUE(t.completed) << t.stopReason;
  ASSERT_EQ(t.time.size(), 101u);
  EXPECT_EQ(t.nfevals, 0);
  const SliderCrank sc;
  const int hinge = m.elements[m.elementByLabel.at(3)].firstDef;
  const int xc = static_cast<int>(coordinate(m, 3, 1));
  double worst = 0.0, scale = 0.0, worstX = 0.0;
  for (size_t k = 0; k < t.time.size(); ++k) {
    const double tt = t.time[k], th = kW0 * tt + 0.5 * kAlpha * tt * tt, w = kW0 + kAlpha * tt;
    const double tau = sc.torque(th, w, kAlpha);
    scale = std::max(scale, std::abs(tau));
    worst = std::max(worst, std::abs(-t.states[k].sig[hinge] - tau));
    worstX = std::max(worstX, std::abs(t.states[k].x[xc] - sc.xC(th)));
    EXPECT_NEAR(t.states[k].e[hinge], th, 1e-9) << "t = " << tt;
    EXPECT_NEAR(t.states[k].ed[hinge], w, 1e-9) << "t = " << tt;
    EXPECT_NEAR(t.states[k].edd[hinge], kAlpha, 1e-8) << "t = " << tt;
  }
  EXPECT_GT(scale, 0.3);  // the torque is not trivially small (up to 0.46 N m here)
  EXPECT_LT(worst, 1e-8 * scale) << "largest torque error " << worst << " of " << scale;
  EXPECT_LT(worstX, 1e-10);
  // The total nodal force at the fixed ground node 11 (fxt = M xdd + h + D^T sig, D = -1 there): the
  // drive's torque, taken by the support.
  const int g = static_cast<int>(coordinate(m, 11, 1));
  for (size_t k = 0; k < t.time.size(); k += 10) {
    const double tt = t.time[k];
    EXPECT_NEAR(run.fxt[k][g], sc.torque(kW0 * tt + 0.5 * kAlpha * tt * tt, kW0 + kAlpha * tt, kAlpha), 1e-8 * scale);
  }
}

// The same crank driven as a coordinate (INPUTX on the crank's orientation node, no hinge): the
// total nodal force fxt at the input coordinate is the drive torque.
TEST(InverseDynamics, SliderCrankTorqueAtAnInputCoordinate) {
  std::string s = text(kFile);
  s = std::regex_replace(s, std::regex("PLHINGE  3  11  12[^\n]*\n"), "");
  s = std::regex_replace(s, std::regex("FIX  11\n"), "");
  s = std::regex_replace(s, std::regex("INPUTE 3 1  0.0  6.283185307179586  3.0"),
                         "INPUTX 12 1  0.0  6.283185307179586  3.0");
  s = std::regex_replace(s, std::regex("INPUTE 3 1 +%[^\n]*\n"), "INPUTX 12 1\n");
  const core::Model m = io::readDatString(s, "slider_crank_inputx.dat");
  ASSERT_EQ(m.numDofs(), 0);
  ASSERT_EQ(m.inputX.size(), 1u);
  const analysis::InverseDynamicsRun run = analysis::inverseDynamics(m, {});
  ASSERT_TRUE(run.trajectory.completed) << run.trajectory.stopReason;
  const SliderCrank sc;
  const int in = static_cast<int>(coordinate(m, 12, 1));
  double worst = 0.0, scale = 0.0;
  for (size_t k = 0; k < run.trajectory.time.size(); ++k) {
    const double tt = run.trajectory.time[k], th = kW0 * tt + 0.5 * kAlpha * tt * tt, w = kW0 + kAlpha * tt;
    const double tau = sc.torque(th, w, kAlpha);
    scale = std::max(scale, std::abs(tau));
    worst = std::max(worst, std::abs(run.fxt[k][in] - tau));
  }
  EXPECT_LT(worst, 1e-8 * scale) << "largest torque error " << worst << " of " << scale;
}

// A mechanism whose inputs do not move is not driven; one with degrees of freedom is simulated.
TEST(InverseDynamics, OnlyMovingInputsWithoutDegreesOfFreedom) {
  std::string s =
      std::regex_replace(text(kFile), std::regex("INPUTE 3 1  0.0  6.283185307179586  3.0"), "INPUTE 3 1  0.5");
  EXPECT_FALSE(analysis::isDrivenRigidMechanism(io::readDatString(s, "still.dat")));
  EXPECT_FALSE(analysis::isDrivenRigidMechanism(
      io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/tests/fourbar.dat")));
}
