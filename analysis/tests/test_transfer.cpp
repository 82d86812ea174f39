// Mode 9 (issue 21 item 3): the state-space model of a static equilibrium against independent
// values: a one-DOF mass-spring-damper has its exact transfer functions (force to displacement,
// velocity and support force; base motion to displacement), the static gain -C A^-1 B + D of a
// prestressed spatial cantilever under gravity equals the compliance found by static load steps
// (central differences of two more static runs), the poles are +-i omega of the eigenfrequencies at
// that equilibrium, and mode 3's K0B over the kinematic degrees of freedom holds K0 + N0 + G0.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/Perturbation.hpp"
#include "analysis/Statics.hpp"
#include "analysis/Transfer.hpp"
#include "core/elements/EulerParameters.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

// Mass m on a spring k (PLTRUSS, l0 = 1, so k = EA) with damper d (EDAMP), node 1 clamped or moved
// (base), node 2 sliding along x. mass: rhoA of the truss (consistent mass) besides the lumped XM.
std::string massSpring(double m, double k, double d, double rhoA, bool base, const std::string& block) {
  std::ostringstream s;
  s.precision(17);
  s << "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\n";
  s << (base ? "INPUTX 1 1\nFIX 1 2\n" : "FIX 1\n") << "FIX 2 2\nDYNE 1 1\nEND\nHALT\n";
  s << "ESTIFF 1 " << k << "\n";
  if (d > 0) s << "EDAMP 1 " << d << "\n";
  if (rhoA > 0) s << "EM 1 " << rhoA << "\n";
  s << "XM 2 " << m << "\nITERSTEP 10 1\nEND\nHALT\n" << block << "END\nEND\n";
  return s.str();
}

analysis::StateSpace stateSpace(const core::Model& m) {
  const analysis::TransferRun r = analysis::transferAnalysis(m);
  EXPECT_TRUE(r.completed) << r.stopReason;
  return r.model;
}

double relErr(std::complex<double> a, std::complex<double> b) { return std::abs(a - b) / std::abs(b); }

}  // namespace

TEST(Transfer, MassSpringDamperIsExact) {
  const double m = 4.0, k = 400.0, d = 2.0;
  const core::Model model = io::readDatString(
      massSpring(m, k, d, 0.0, false, "INPUTF 1 2 1\nOUTX 1 2 1\nOUTXP 2 2 1\nOUTF 3 1 1\n"), "ms.dat");
  const analysis::StateSpace ss = stateSpace(model);
  ASSERT_EQ(ss.A.rows(), 2);
  Eigen::Matrix2d A;
  A << 0, 1, -k / m, -d / m;
  EXPECT_LT((ss.A - A).norm(), 1e-12 * A.norm()) << ss.A;
  EXPECT_NEAR(ss.B(0, 0), 0.0, 1e-15);
  EXPECT_NEAR(ss.B(1, 0), 1.0 / m, 1e-15);
  // Outputs: x2, its velocity, and the force the clamp takes, fxt_1 = -sigma = -(k x2 + d xd2).
  Eigen::Matrix<double, 3, 2> C;
  C << 1, 0, 0, 1, -k, -d;
  EXPECT_LT((ss.C - C).norm(), 1e-9 * k) << ss.C;
  EXPECT_LT(ss.D.norm(), 1e-12 * k) << ss.D;  // no mass at the clamp: no feedthrough
  EXPECT_FALSE(ss.feedthrough() && ss.D.cwiseAbs().maxCoeff() > 1e-9);
  // H(i w) = 1 / (k - m w^2 + i d w), times (i w) for the velocity and -(k + i d w) for the reaction.
  Eigen::VectorXd w(5);
  w << 0.1, 5.0, 10.0, 10.05, 40.0;
  const Eigen::VectorXcd hx = analysis::frequencyResponse(ss, 0, 0, w);
  const Eigen::VectorXcd hv = analysis::frequencyResponse(ss, 0, 1, w);
  const Eigen::VectorXcd hf = analysis::frequencyResponse(ss, 0, 2, w);
  for (int i = 0; i < w.size(); ++i) {
    const std::complex<double> s(0.0, w[i]), h = 1.0 / (k - m * w[i] * w[i] + d * s);
    EXPECT_LT(relErr(hx[i], h), 1e-12) << "w = " << w[i];
    EXPECT_LT(relErr(hv[i], s * h), 1e-12) << "w = " << w[i];
    EXPECT_LT(relErr(hf[i], -(k + d * s) * h), 1e-12) << "w = " << w[i];
  }
  EXPECT_EQ(ss.inputNames.size(), 1u);
  EXPECT_EQ(ss.outputNames.size(), 3u);
}

// Base motion u of node 1 (INX): m x'' + d (x' - u') + k (x - u) + (truss mass coupling) = 0.
// With the truss's consistent mass (rhoA l0 / 6 coupling, rhoA l0 / 3 on node 2):
// X / U = (k + i d w + w^2 rhoA/6) / (k + i d w - w^2 (m + rhoA/3)).
TEST(Transfer, BaseMotionInputIsExact) {
  const double m = 2.0, k = 300.0, d = 1.5, rhoA = 0.6;
  const core::Model model =
      io::readDatString(massSpring(m, k, d, rhoA, true, "INX 1 1 1\nOUTX 1 2 1\nOUTF 2 1 1\n"), "base.dat");
  const analysis::StateSpace ss = stateSpace(model);
  ASSERT_EQ(ss.B.cols(), 3);  // position, velocity, acceleration of the base
  const double M22 = m + rhoA / 3.0, M21 = rhoA / 6.0, M11 = rhoA / 3.0;
  Eigen::VectorXd w(4);
  w << 0.5, 8.0, 12.5, 30.0;
  for (int i = 0; i < w.size(); ++i) {
    const std::complex<double> s(0.0, w[i]);
    // Channels combine as u, s u, s^2 u for a base motion u.
    auto response = [&](int out) {
      Eigen::VectorXd one(1);
      one << w[i];
      return analysis::frequencyResponse(ss, 0, out, one)[0] + s * analysis::frequencyResponse(ss, 1, out, one)[0] +
             s * s * analysis::frequencyResponse(ss, 2, out, one)[0];
    };
    const std::complex<double> X = (k + d * s - s * s * M21) / (k + d * s + s * s * M22);
    EXPECT_LT(relErr(response(0), X), 1e-10) << "w = " << w[i];
    // The force the base takes: M11 u'' + M12 x'' + k (u - x) + d (u' - x').
    const std::complex<double> F = s * s * M11 + s * s * M21 * X + (k + d * s) * (1.0 - X);
    EXPECT_LT(relErr(response(1), F), 1e-10) << "w = " << w[i];
  }
  // Static gain: the base moves the mass rigidly (1) and the support takes nothing.
  const std::optional<Eigen::MatrixXd> gain = analysis::staticGain(ss);
  ASSERT_TRUE(gain.has_value());
  const Eigen::MatrixXd& G = *gain;
  EXPECT_NEAR(G(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(G(1, 0), 0.0, 1e-9 * k);
}

namespace {
// A spatial cantilever of n BEAMs along x (clamped at node 1/2), pulled by an axial tip force and
// under gravity -z with distributed and tip mass, transfer block on the tip.
std::string prestressedCantilever(int n, const std::string& extraLoads, const std::string& block, double axial = 40.0) {
  std::ostringstream s;
  s.precision(17);
  for (int i = 1; i <= n + 1; ++i) s << "X " << 2 * i - 1 << " " << 0.5 * (i - 1) / n << " 0 0\n";
  for (int e = 1; e <= n; ++e)
    s << "BEAM " << e << " " << 2 * e - 1 << " " << 2 * e << " " << 2 * e + 1 << " " << 2 * e + 2 << " 0 1 0\n";
  for (int e = 1; e <= n; ++e) s << "DYNE " << e << " 1 2 3 4 5 6\n";
  s << "FIX 1\nFIX 2\nEND\nHALT\n";
  for (int e = 1; e <= n; ++e) s << "ESTIFF " << e << " 2.1e6 6.0 12.0 20.0\nEM " << e << " 0.8 2e-4 1e-4 1e-4 0\n";
  const int tip = 2 * n + 1;
  s << "XM " << tip << " 0.3\nXF " << tip << " " << axial << " 0 0\nGRAVITY 0 0 -9.81\n"
    << extraLoads << "ITERSTEP 30 3 1e-12\nEND\n";
  if (!block.empty()) s << "HALT\n" << block << "END\n";
  s << "END\n";
  return s.str();
}
}  // namespace

// Static gain = compliance of the equilibrium: tip force z and tip moment about z as inputs, the
// tip displacement z and y and the tip rotation about y and z as outputs; the compliance from
// central differences of two static runs with the input load changed by +-delta (O(delta^2)).
TEST(Transfer, StaticGainIsTheStaticCompliance) {
  const int n = 4, tip = 2 * n + 1, rot = tip + 1;
  const std::string block = "INPUTF 1 " + std::to_string(tip) + " 3\nINPUTF 2 " + std::to_string(rot) + " 3\nOUTX 1 " +
                            std::to_string(tip) + " 3\nOUTX 2 " + std::to_string(tip) + " 2\nOUTX 3 " +
                            std::to_string(rot) + " 2\nOUTX 4 " + std::to_string(rot) + " 3\n";
  const core::Model model = io::readDatString(prestressedCantilever(n, "", block), "pc.dat");
  const analysis::TransferRun run = analysis::transferAnalysis(model);
  ASSERT_TRUE(run.completed) << run.stopReason;
  EXPECT_EQ(run.statics.loadSteps, 3);
  const analysis::StateSpace& ss = run.model;
  const std::optional<Eigen::MatrixXd> gain = analysis::staticGain(ss);
  ASSERT_TRUE(gain.has_value());
  const Eigen::MatrixXd& G = *gain;

  auto tipState = [&](const std::string& load) {
    const core::Model mm = io::readDatString(prestressedCantilever(n, load, ""), "fd.dat");
    const analysis::StaticRun r = analysis::staticAnalysis(mm, 0);
    EXPECT_TRUE(r.completed) << r.stopReason;
    const Eigen::VectorXd& x = r.steps.back().x;
    const int p = mm.nodes[mm.nodeByLabel.at(tip)].firstCoord, o = mm.nodes[mm.nodeByLabel.at(rot)].firstCoord;
    return std::make_pair(Eigen::Vector3d(x.segment<3>(p)), core::euler::rotation(x.segment<4>(o).normalized()));
  };
  const double dF = 1e-2, dM = 1e-3;
  const std::string inputs[2][2] = {{"XF " + std::to_string(tip) + " 0 0 " + std::to_string(dF) + "\n",
                                     "XF " + std::to_string(tip) + " 0 0 " + std::to_string(-dF) + "\n"},
                                    {"XF " + std::to_string(rot) + " 0 0 " + std::to_string(dM) + "\n",
                                     "XF " + std::to_string(rot) + " 0 0 " + std::to_string(-dM) + "\n"}};
  for (int in = 0; in < 2; ++in) {
    const auto [pp, Rp] = tipState(inputs[in][0]);
    const auto [pm, Rm] = tipState(inputs[in][1]);
    const double h = 2 * (in == 0 ? dF : dM);
    // Rotation from the minus to the plus state in global axes: log(Rp Rm^T).
    const Eigen::AngleAxisd aa(Rp * Rm.transpose());
    const Eigen::Vector3d theta = aa.angle() * aa.axis();
    Eigen::Vector4d fd;
    fd << (pp[2] - pm[2]) / h, (pp[1] - pm[1]) / h, theta[1] / h, theta[2] / h;
    const double scale = std::max(fd.cwiseAbs().maxCoeff(), G.col(in).cwiseAbs().maxCoeff());
    for (int out = 0; out < 4; ++out)
      EXPECT_LT(std::abs(G(out, in) - fd[out]), 1e-6 * scale)
          << "input " << in + 1 << ", output " << out + 1 << ": gain " << G(out, in) << ", static load steps "
          << fd[out];
  }
  // The prestress matters (axial tension stiffens the bending): the gain is not the unloaded one.
  const analysis::TransferRun free =
      analysis::transferAnalysis(io::readDatString(prestressedCantilever(n, "", block, 0.0), "free.dat"));
  ASSERT_TRUE(free.completed) << free.stopReason;
  const Eigen::MatrixXd Gfree = free.model.D - free.model.C * free.model.A.partialPivLu().solve(free.model.B);
  EXPECT_GT(std::abs(Gfree(0, 0) - G(0, 0)), 1e-3 * std::abs(G(0, 0)));
}

// Undamped: the eigenvalues of A are +-i omega with omega the eigenfrequencies of the same
// equilibrium ((K0 + G0) v = w^2 M0 v, analysis::naturalFrequencies).
TEST(Transfer, PolesAreTheEigenfrequencies) {
  const int n = 3, tip = 2 * n + 1;
  const core::Model model = io::readDatString(
      prestressedCantilever(n, "", "INPUTF 1 " + std::to_string(tip) + " 3\nOUTX 1 " + std::to_string(tip) + " 3\n"),
      "poles.dat");
  analysis::TransferOptions o;
  o.nev = model.numDofs();
  const analysis::TransferRun run = analysis::transferAnalysis(model, o);
  ASSERT_TRUE(run.completed) << run.stopReason;
  const Eigen::VectorXcd ev = run.model.A.eigenvalues();
  std::vector<double> im;
  for (int i = 0; i < ev.size(); ++i) {
    EXPECT_LT(std::abs(ev[i].real()), 1e-6 * std::abs(ev[i])) << ev[i];
    if (ev[i].imag() > 0) im.push_back(ev[i].imag());
  }
  std::sort(im.begin(), im.end());
  const Eigen::VectorXd& omega = run.statics.steps.back().frequencies.omega;
  ASSERT_EQ(static_cast<Eigen::Index>(im.size()), omega.size());
  // A's eigenvalues come from a nonsymmetric solver on a matrix whose lower blocks are of order
  // omega_max^2: the highest poles carry a relative error of order eps omega_max^2 / omega.
  for (std::size_t i = 0; i < im.size(); ++i) EXPECT_NEAR(im[i], omega[i], 1e-7 * omega[i]) << "mode " << i + 1;
}

// Mode 3's K0B over every kinematic degree of freedom (inputs included): its block of the dynamic
// ones is K0 + N0 + G0, its input rows and columns the couplings of the prescribed coordinate.
TEST(Transfer, KinematicDofMatricesHoldTheInputs) {
  const core::Model model = io::readDatString(massSpring(2.0, 300.0, 0.0, 0.6, true, ""), "k0b.dat");
  const analysis::StaticRun run = analysis::staticAnalysis(model, 0);
  ASSERT_TRUE(run.completed) << run.stopReason;
  const analysis::KinematicDofMatrices km = analysis::kinematicDofMatrices(model, run.steps.back());
  ASSERT_EQ(km.K0B.rows(), 2);  // [x^m input (node 1 x), e^m dynamic (truss elongation)]
  // q = (u, e): x2 = u + 1 + e. Stiffness only on e; mass of node 2 (m + rhoA/3) and node 1 (rhoA/3)
  // with the rhoA/6 coupling, in (u, e): M = [[M11 + 2 M21 + M22, M21 + M22], [M21 + M22, M22]].
  const double M11 = 0.2, M21 = 0.1, M22 = 2.2;
  Eigen::Matrix2d M, K;
  M << M11 + 2 * M21 + M22, M21 + M22, M21 + M22, M22;
  K << 0, 0, 0, 300.0;
  EXPECT_LT((km.M0 - M).norm(), 1e-12) << km.M0;
  EXPECT_LT((km.K0B - K).norm(), 1e-9) << km.K0B;
}

// Undamped Bode phase (issue 35): H(i w) is real and flips sign at poles and zeros; the phase is
// H's own (0 or -180), so a collocated pair (force in, its own displacement out: poles and zeros
// alternate) falls at each pole and rises at each zero instead of climbing by 360 at every flip an
// unwrapping guessed the wrong way.
TEST(Transfer, UndampedBodePhaseFallsAtPolesAndRisesAtZeros) {
  const int n = 4, tip = 2 * n + 1;
  const std::string block = "INPUTF 1 " + std::to_string(tip) + " 3\nOUTX 1 " + std::to_string(tip) + " 3\n";
  const analysis::TransferRun run =
      analysis::transferAnalysis(io::readDatString(prestressedCantilever(n, "", block), "pc.dat"));
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_TRUE(analysis::undamped(run.model));
  const Eigen::VectorXd omega = analysis::bodeFrequencies(run.model);
  const Eigen::VectorXcd h = analysis::frequencyResponse(run.model, 0, 0, omega);
  const Eigen::VectorXd phase = analysis::bodePhase(run.model, h);
  int falls = 0, rises = 0;
  for (Eigen::Index k = 0; k < phase.size(); ++k) {
    EXPECT_TRUE(phase[k] <= 1e-3 && phase[k] >= -180.0 - 1e-3) << "at " << omega[k] << " rad/s: " << phase[k];
    // The phase says H's sign (near 0: positive, near -180: negative).
    EXPECT_EQ(h[k].real() >= 0.0, phase[k] > -90.0) << omega[k];
    if (k == 0) continue;
    if (phase[k] < phase[k - 1] - 90.0) ++falls;
    if (phase[k] > phase[k - 1] + 90.0) ++rises;
  }
  EXPECT_NEAR(phase[0], 0.0, 1e-3);  // positive static compliance
  EXPECT_GE(falls, 2);               // the grid spans several eigenfrequencies
  EXPECT_GE(rises, 1);
  EXPECT_LE(falls - rises, 1);
}

// A lightly damped peak (issue 35): the Bode grid reaches its height. Damping of 1e-4 of the
// stiffness gives the first bending mode a peak far narrower than the log grid's steps; its true
// height is found by a golden-section search of |H| about the grid's own maximum.
TEST(Transfer, BodeGridFindsALightlyDampedPeak) {
  const int n = 4, tip = 2 * n + 1;
  std::string damping;
  for (int e = 1; e <= n; ++e) damping += "EDAMP " + std::to_string(e) + " 210 6e-4 1.2e-3 2e-3\n";
  const std::string block = "INPUTF 1 " + std::to_string(tip) + " 3\nOUTX 1 " + std::to_string(tip) + " 3\n";
  const analysis::TransferRun run =
      analysis::transferAnalysis(io::readDatString(prestressedCantilever(n, damping, block), "pcd.dat"));
  ASSERT_TRUE(run.completed) << run.stopReason;
  ASSERT_FALSE(analysis::undamped(run.model));
  const Eigen::VectorXd omega = analysis::bodeFrequencies(run.model);
  const Eigen::VectorXcd h = analysis::frequencyResponse(run.model, 0, 0, omega);
  ASSERT_TRUE(h.allFinite());
  Eigen::Index top = 0;
  h.cwiseAbs().maxCoeff(&top);
  auto magnitude = [&](double w) {
    return std::abs(analysis::frequencyResponse(run.model, 0, 0, Eigen::VectorXd::Constant(1, w))[0]);
  };
  double a = omega[std::max<Eigen::Index>(top - 1, 0)], b = omega[std::min<Eigen::Index>(top + 1, omega.size() - 1)];
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 80; ++it) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if (magnitude(c) > magnitude(d))
      b = d;
    else
      a = c;
  }
  const double peak = magnitude(0.5 * (a + b)), onGrid = std::abs(h[top]);
  std::printf("damped peak at %.6g rad/s: %.6g on the grid, %.6g by search; %ld grid points\n", 0.5 * (a + b), onGrid,
              peak, static_cast<long>(omega.size()));
  EXPECT_GT(onGrid, 0.97 * peak);
  // The static compliance is far below it: the peak is a real resonance, not the grid's edge.
  EXPECT_GT(onGrid, 100.0 * std::abs(h[0]));
}

// Issue 51: the undamped Bode phase reached -540 degrees above 5 kHz (a lightly damped model's
// turns added up where round-off decided their sign), though H evaluated from A, B, C is real or
// imaginary. Now every value is H's own phase, a quarter turn in [-180, 90]: for the pivot's moment
// to its rotation and rotation rate, and for the leaf-spring stage's force to its stage and
// mid-leaf displacements (collocated: 0 below the first resonance, -180 above it).
TEST(Transfer, UndampedBodePhaseIsHsOwnWithinAQuarterTurnBand) {
  for (const char* name : {"cross_spring_pivot_transfer.dat", "parallel_leaf_stage.dat"}) {
    const analysis::TransferRun run =
        analysis::transferAnalysis(io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/" + name));
    ASSERT_TRUE(run.completed) << name << ": " << run.stopReason;
    ASSERT_TRUE(analysis::undamped(run.model)) << name;
    const Eigen::VectorXd omega = analysis::bodeFrequencies(run.model);
    const std::vector<Eigen::VectorXcd> responses = analysis::frequencyResponses(run.model, omega);
    const Eigen::Index no = run.model.C.rows();
    for (Eigen::Index o = 0; o < no; ++o) {
      const Eigen::VectorXcd& h = responses[static_cast<size_t>(o)];
      const Eigen::VectorXd phase = analysis::bodePhase(run.model, h);
      const bool rate = run.model.outputUnits[static_cast<size_t>(o)].find("/s") != std::string::npos;
      for (Eigen::Index k = 0; k < phase.size(); ++k) {
        EXPECT_TRUE(phase[k] == -180.0 || phase[k] == -90.0 || phase[k] == 0.0 || phase[k] == 90.0)
            << name << " output " << o + 1 << " at " << omega[k] << " rad/s: " << phase[k];
        // A displacement's H is real, a rate's imaginary: its sign decides.
        if (rate)
          EXPECT_EQ(phase[k], h[k].imag() >= 0.0 ? 90.0 : -90.0) << name << " " << omega[k];
        else
          EXPECT_EQ(phase[k], h[k].real() >= 0.0 ? 0.0 : -180.0) << name << " " << omega[k];
      }
      std::printf("%s output %ld: phase from %g to %g degrees over %ld frequencies\n", name, static_cast<long>(o + 1),
                  phase.minCoeff(), phase.maxCoeff(), static_cast<long>(phase.size()));
    }
  }
  const analysis::TransferRun stage = analysis::transferAnalysis(
      io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/parallel_leaf_stage.dat"));
  ASSERT_TRUE(stage.completed) << stage.stopReason;
  const double f1 = 2 * M_PI * 14.43;  // its mode 1 (Hz): the stage along x
  const Eigen::VectorXd around = (Eigen::VectorXd(2) << 0.9 * f1, 1.1 * f1).finished();
  const Eigen::VectorXd phase =
      analysis::bodePhase(stage.model, analysis::frequencyResponse(stage.model, 0, 0, around));
  EXPECT_EQ(phase[0], 0.0);
  EXPECT_EQ(phase[1], -180.0);
}

// A damped phase is continuous (unwrapped from the lowest frequency): a mass on a damped spring goes
// from 0 to -180 degrees through -90 at its resonance.
TEST(Transfer, DampedBodePhaseIsContinuous) {
  const analysis::StateSpace ss =
      stateSpace(io::readDatString(massSpring(4.0, 400.0, 2.0, 0.0, false, "INPUTF 1 2 1\nOUTX 1 2 1\n"), "ms.dat"));
  const Eigen::VectorXd omega = analysis::bodeFrequencies(ss);
  const Eigen::VectorXd phase = analysis::bodePhase(ss, analysis::frequencyResponse(ss, 0, 0, omega));
  EXPECT_NEAR(phase[0], 0.0, 1.0);
  EXPECT_NEAR(phase[phase.size() - 1], -180.0, 1.0);
  for (Eigen::Index k = 1; k < phase.size(); ++k) EXPECT_LE(phase[k], phase[k - 1] + 1e-9) << omega[k];
}

// transfer --freq-range (issue 51): the Bode frequencies span the range asked for, the points
// closing in on a resonance included.
TEST(Transfer, BodeFrequenciesSpanTheRangeAskedFor) {
  const analysis::StateSpace ss =
      stateSpace(io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/parallel_leaf_stage.dat"));
  const Eigen::VectorXd automatic = analysis::bodeFrequencies(ss);
  EXPECT_NEAR(automatic[0] / (2 * M_PI), 1.443, 1e-3);  // a decade below mode 1
  const Eigen::VectorXd w = analysis::bodeFrequencies(ss, 10.0, 1000.0);
  EXPECT_NEAR(w[0], 2 * M_PI * 10.0, 1e-9);
  EXPECT_NEAR(w[w.size() - 1], 2 * M_PI * 1000.0, 1e-9);
  EXPECT_GT(w.size(), 400) << "the points closing in on mode 1 (14.4 Hz) and the leaves' modes";
  for (Eigen::Index k = 1; k < w.size(); ++k) EXPECT_GT(w[k], w[k - 1]);
}

// The channels' units (SI), which the Bode diagrams' magnitude axis says: force N, moment N m,
// displacement m, rotation rad, rates per s; INX's position, velocity and acceleration inputs.
TEST(Transfer, ChannelsHaveTheirUnits) {
  const analysis::StateSpace ms = stateSpace(io::readDatString(
      massSpring(4.0, 400.0, 2.0, 0.0, false, "INPUTF 1 2 1\nOUTX 1 2 1\nOUTXP 2 2 1\nOUTF 3 1 1\n"), "ms.dat"));
  EXPECT_EQ(ms.inputUnits, std::vector<std::string>{"N"});
  EXPECT_EQ(ms.outputUnits, (std::vector<std::string>{"m", "m/s", "N"}));
  const analysis::StateSpace base =
      stateSpace(io::readDatString(massSpring(4.0, 400.0, 2.0, 0.0, true, "INX 1 1 1\nOUTX 1 2 1\n"), "base.dat"));
  EXPECT_EQ(base.inputUnits, (std::vector<std::string>{"m", "m/s", "m/s^2"}));
  const analysis::StateSpace pivot =
      stateSpace(io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_transfer.dat"));
  EXPECT_EQ(pivot.inputUnits, std::vector<std::string>{"N m"});
  EXPECT_EQ(pivot.outputUnits, (std::vector<std::string>{"rad", "rad/s"}));
}
