// Damping a designer states (issue 53 item 4; analysis/DesignDamping.hpp) in the transfer function
// against closed forms: a mass on a spring with modal ratio zeta has A = [0 1; -w^2, -2 zeta w] and
// the peak |H(i w_n)| = 1 / (2 zeta k), its poles -zeta w +- i w sqrt(1 - zeta^2); Rayleigh's beta
// gives the same state-space model as EDAMP = beta * ESTIFF (base motion and support force
// included), alpha adds alpha to A's damping entry; modes say each mode's ratio (EDAMP = beta *
// ESTIFF: beta w / 2; Rayleigh: alpha / 2w + beta w / 2); on the spatial parallel leaf-spring stage every
// undamped mode i is damped alone, by 2 zeta_i w_i. In a nonlinear time run (simulate) Rayleigh's beta
// is element damping: the mass on the spring under a step force follows the damped step response
// with zeta = beta w / 2, as EDAMP = beta k does; a modal ratio or alpha is refused there.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/DesignDamping.hpp"
#include "analysis/ModesJob.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/Transfer.hpp"
#include "io/formats/DatReader.hpp"
#include "text/NumberText.hpp"

using namespace flexmb;

namespace {

// Mass m on a spring k (PLTRUSS, l0 = 1, so k = EA) with damper d (EDAMP), node 1 clamped or moved
// (base), node 2 sliding along x (as test_transfer.cpp's).
std::string springMass(double m, double k, double d, bool base, const std::string& block) {
  std::ostringstream s;
  s.precision(17);
  s << "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\n";
  s << (base ? "INPUTX 1 1\nFIX 1 2\n" : "FIX 1\n") << "FIX 2 2\nDYNE 1 1\nEND\nHALT\n";
  s << "ESTIFF 1 " << k << "\n";
  if (d > 0) s << "EDAMP 1 " << d << "\n";
  s << "XM 2 " << m << "\nITERSTEP 10 1\nEND\nHALT\n" << block << "END\nEND\n";
  return s.str();
}

analysis::StateSpace damped(const core::Model& model, const analysis::DampingOptions& damping) {
  analysis::TransferOptions o;
  o.damping = damping;
  const analysis::TransferRun r = analysis::transferAnalysis(model, o);
  EXPECT_TRUE(r.completed) << r.stopReason;
  return r.model;
}

}  // namespace

TEST(DesignDamping, ModalRatioOnASpringMassIsTheClosedForm) {
  const double m = 4.0, k = 400.0, zeta = 0.02, w = std::sqrt(k / m);
  const core::Model model =
      io::readDatString(springMass(m, k, 0.0, false, "INPUTF 1 2 1\nOUTX 1 2 1\n"), "spring_mass.dat");
  analysis::DampingOptions o;
  o.ratios = {zeta};
  const analysis::StateSpace ss = damped(model, o);
  ASSERT_EQ(ss.A.rows(), 2);
  EXPECT_NEAR(ss.A(1, 0), -w * w, 1e-12 * w * w);
  EXPECT_NEAR(ss.A(1, 1), -2 * zeta * w, 1e-12 * w);
  // The peak: H(i w_n) = 1 / (i 2 zeta k), 25 times the static compliance 1/k.
  const Eigen::VectorXcd h = analysis::frequencyResponse(ss, 0, 0, Eigen::VectorXd::Constant(1, w));
  EXPECT_NEAR(std::abs(h[0]), 1.0 / (2 * zeta * k), 1e-12 / (2 * zeta * k));
  EXPECT_NEAR(std::arg(h[0]), -M_PI / 2, 1e-12);
  // The damped poles.
  const Eigen::VectorXcd poles = ss.A.eigenvalues();
  for (Eigen::Index i = 0; i < 2; ++i) {
    EXPECT_NEAR(poles[i].real(), -zeta * w, 1e-12 * w);
    EXPECT_NEAR(std::abs(poles[i].imag()), w * std::sqrt(1 - zeta * zeta), 1e-12 * w);
  }
}

TEST(DesignDamping, RayleighBetaIsEdampBetaTimesEstiffAndAlphaAddsAlpha) {
  const double m = 4.0, k = 400.0, beta = 3e-3, alpha = 0.7;
  const std::string block = "INX 1 1 1\nOUTX 1 2 1\nOUTXP 2 2 1\nOUTF 3 1 1\n";
  const analysis::StateSpace byEdamp = damped(io::readDatString(springMass(m, k, beta * k, true, block), "e.dat"), {});
  analysis::DampingOptions o;
  o.beta = beta;
  const core::Model bare = io::readDatString(springMass(m, k, 0.0, true, block), "b.dat");
  const analysis::StateSpace byBeta = damped(bare, o);
  ASSERT_EQ(byBeta.A.rows(), 2);
  ASSERT_EQ(byBeta.B.cols(), 3);  // base position, velocity, acceleration
  EXPECT_NEAR(byBeta.A(1, 1), -beta * k / m, 1e-12);
  EXPECT_LT((byBeta.A - byEdamp.A).norm(), 1e-12 * byEdamp.A.norm());
  EXPECT_LT((byBeta.B - byEdamp.B).norm(), 1e-12 * byEdamp.B.norm());  // the base velocity's beta k / m
  EXPECT_LT((byBeta.C - byEdamp.C).norm(), 1e-12 * byEdamp.C.norm());  // the support force's damper term
  EXPECT_LT((byBeta.D - byEdamp.D).norm(), 1e-12 * (1 + byEdamp.D.norm()));
  // The support force has the damper's share, beta k times the spring's rate (as EDAMP's).
  EXPECT_NEAR(std::abs(byBeta.C(2, 1)), beta * k, 1e-9 * beta * k);
  o.alpha = alpha;
  const analysis::StateSpace both = damped(bare, o);
  EXPECT_NEAR(both.A(1, 1), -alpha - beta * k / m, 1e-12);
}

TEST(DesignDamping, ModalRatiosDampEveryModeOfTheLeafSpringStageAlone) {
  // Each undamped mode phi_i of (K0 + G0, M0) at the equilibrium is an eigenvector of A's damping
  // block with -2 zeta_i w_i (no coupling between the modes): A [phi; s phi] = s [phi; s phi] for
  // s^2 + 2 zeta_i w_i s + w_i^2 = 0, the damped pole. (Checked on the damping block: A's own
  // eigenvalues and its stiffness block carry round-off of ~1e-16 |A| ~ 1e-16 w_max^2, far beyond the
  // lowest pole's digits.)
  const core::Model model =
      io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/parallel_leaf_stage.dat");
  analysis::TransferOptions o;
  o.damping.ratios = {0.01, 0.03};  // mode 1 0.01, the others 0.03
  const analysis::TransferRun run = analysis::transferAnalysis(model, o);
  ASSERT_TRUE(run.completed) << run.stopReason;
  const core::LinearizedSystem& sys = run.statics.steps.back().system;
  const Eigen::Index m = run.model.A.rows() / 2;
  ASSERT_EQ(sys.M.rows(), m);
  EXPECT_FALSE(analysis::undamped(run.model));  // the file has no EDAMP: all of it is the modal term
  const Eigen::MatrixXd A22 = run.model.A.bottomRightCorner(m, m);
  const Eigen::MatrixXd Kt = 0.5 * ((sys.K + sys.G) + (sys.K + sys.G).transpose());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Kt, sys.M);
  ASSERT_EQ(es.info(), Eigen::Success);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double w = std::sqrt(es.eigenvalues()[i]), zeta = i == 0 ? 0.01 : 0.03;
    const Eigen::VectorXd phi = es.eigenvectors().col(i);
    worst = std::max(worst, (A22 * phi + 2 * zeta * w * phi).norm() / (2 * zeta * w * phi.norm()));
  }
  // 2e-5 measured, on mode 1: A's blocks are M0^-1 X from the sparse saddle-point solve, accepted at
  // 1e-9 of the whole column, which the highest modes dominate. A wrong ratio, frequency or mass
  // normalisation is off by O(1).
  EXPECT_LT(worst, 1e-4) << "modes " << m;
  std::printf("leaf-spring stage: %d modes, f1 %.6g Hz, largest relative error of a mode's damping %.2e\n",
              static_cast<int>(m), std::sqrt(es.eigenvalues()[0]) / (2 * M_PI), worst);
}

TEST(DesignDamping, RefusesNegativeOrNonFiniteValues) {
  analysis::DampingOptions o;
  EXPECT_EQ(analysis::dampingRefusal(o), "");
  EXPECT_EQ(analysis::dampingText(o), "none added");
  o.ratios = {0.01, -0.1};
  EXPECT_NE(analysis::dampingRefusal(o), "");
  o.ratios = {0.01};
  o.beta = std::nan("");
  EXPECT_NE(analysis::dampingRefusal(o), "");
  o.beta = 1e-4;
  EXPECT_EQ(analysis::dampingRefusal(o), "");
  EXPECT_NE(analysis::dampingText(o).find("beta " + text::shortest(1e-4) + " s"), std::string::npos)
      << analysis::dampingText(o);
}

TEST(DesignDamping, ModesSayEachModesRatioFromEdampAndTheOptions) {
  // The straight guidance unloaded (G0 = 0): EDAMP = beta * ESTIFF gives mode i beta w_i / 2,
  // Rayleigh alpha + beta on the bare file alpha / (2 w_i) + beta w_i / 2, a modal ratio itself.
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/straight_guidance.dat");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string bare = buffer.str();
  const double beta = 1e-4, alpha = 0.5;
  std::ostringstream edamp;
  for (int e : {1, 2, 3, 4, 5, 11, 12, 13, 14, 15})
    edamp << "EDAMP " << e << " " << beta * 6.3e6 << " " << beta * 0.525 << "\n";
  std::string damped = bare;
  const std::size_t at = damped.find("% Eq. 24");
  ASSERT_NE(at, std::string::npos);
  damped.insert(at, edamp.str());
  auto ratios = [](const std::string& text, const analysis::DampingOptions& d) {
    analysis::ModesOptions o;
    o.nev = 5;
    o.damping = d;
    analysis::ModesJob job(analysis::sourceOfModel(io::readDatString(text, "g.dat")), o);
    EXPECT_EQ(job.run(), analysis::JobStatus::Completed);
    return std::make_pair(job.dampingRatios(), Eigen::VectorXd(job.result().frequencies.omega));
  };
  const auto [none, w0] = ratios(bare, {});
  EXPECT_EQ(none.size(), 0);  // undamped: no ratios
  const auto [byEdamp, w] = ratios(damped, {});
  ASSERT_EQ(byEdamp.size(), 5);
  analysis::DampingOptions o;
  o.alpha = alpha, o.beta = beta;
  const auto [byRayleigh, w1] = ratios(bare, o);
  o = {};
  o.ratios = {0.02, 0.05};
  const auto [byRatio, w2] = ratios(bare, o);
  for (Eigen::Index i = 0; i < 5; ++i) {
    EXPECT_NEAR(byEdamp[i], beta * w[i] / 2, 1e-9 * beta * w[i]) << "mode " << i + 1;
    EXPECT_NEAR(byRayleigh[i], alpha / (2 * w[i]) + beta * w[i] / 2, 1e-9 * byRayleigh[i]) << "mode " << i + 1;
    EXPECT_NEAR(byRatio[i], i == 0 ? 0.02 : 0.05, 1e-9) << "mode " << i + 1;
  }
}

namespace {

// The mass m on the spring k (l0 = 1) sliding along x from rest under a step force F at t = 0.
std::string springMassStep(double m, double k, double d, double F, double tEnd, int intervals) {
  std::ostringstream s;
  s.precision(17);
  s << "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\nESTIFF 1 " << k << "\n";
  if (d > 0) s << "EDAMP 1 " << d << "\n";
  s << "XM 2 " << m << "\nXF 2 " << F << " 0\nTIMESTEP " << tEnd << " " << intervals << "\nEND\nEND\n";
  return s.str();
}

analysis::SimulateJob stepRun(const std::string& text, const analysis::DampingOptions& damping) {
  analysis::SimulateRequest r;
  r.run.integrator = analysis::Integrator::Ode45;
  r.run.relTol = 1e-10;
  r.run.absTol = 1e-15;
  r.damping = damping;
  return analysis::SimulateJob(analysis::sourceOfModel(io::readDatString(text, "step.dat")), r);
}

}  // namespace

TEST(DesignDamping, RayleighBetaInATimeRunIsTheDampedStepResponse) {
  const double m = 4.0, k = 400.0, beta = 4e-3, F = 1e-3, w = std::sqrt(k / m), zeta = beta * w / 2;  // zeta 0.02
  ASSERT_NEAR(zeta, 0.02, 1e-15);
  analysis::DampingOptions o;
  o.beta = beta;
  analysis::SimulateJob byBeta = stepRun(springMassStep(m, k, 0.0, F, 2.0, 200), o);
  ASSERT_EQ(byBeta.status(), analysis::JobStatus::Ready);
  ASSERT_EQ(byBeta.run(), analysis::JobStatus::Completed);
  analysis::SimulateJob byEdamp = stepRun(springMassStep(m, k, beta * k, F, 2.0, 200), {});
  ASSERT_EQ(byEdamp.run(), analysis::JobStatus::Completed);
  analysis::SimulateJob bare = stepRun(springMassStep(m, k, 0.0, F, 2.0, 200), {});
  ASSERT_EQ(bare.run(), analysis::JobStatus::Completed);
  const core::Trajectory &t = byBeta.trajectory(), &te = byEdamp.trajectory(), &t0 = bare.trajectory();
  ASSERT_EQ(t.time.size(), 201u);
  ASSERT_EQ(te.time.size(), 201u);
  // x of node 2 (model order: node 1's x, y, then node 2's x, y).
  const double wd = w * std::sqrt(1 - zeta * zeta), xs = F / k;
  double worst = 0.0, worstEdamp = 0.0;
  for (std::size_t i = 0; i < t.time.size(); ++i) {
    const double tt = t.time[i];
    const double exact =
        1.0 + xs * (1 - std::exp(-zeta * w * tt) *
                            (std::cos(wd * tt) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * tt)));
    worst = std::max(worst, std::abs(t.states[i].x[2] - exact));
    worstEdamp = std::max(worstEdamp, std::abs(t.states[i].x[2] - te.states[i].x[2]));
  }
  std::cout << "step response, zeta " << zeta << ": largest departure from the closed form " << worst / xs
            << " of F/k, from EDAMP = beta k " << worstEdamp / xs << "\n";
  EXPECT_LT(worst, 1e-6 * xs) << "largest departure from the closed form, m";
  EXPECT_LT(worstEdamp, 1e-12 * xs) << "beta against EDAMP = beta k";
  // Without the damping the oscillation about F/k keeps its amplitude (|x - F/k| up to F/k).
  double undampedMax = 0.0;
  for (std::size_t i = 150; i < t0.time.size(); ++i)
    undampedMax = std::max(undampedMax, std::abs(t0.states[i].x[2] - 1.0 - xs));
  EXPECT_GT(undampedMax, 0.9 * xs);
  // The manifest says what was added.
  bool said = false;
  for (const auto& [key, value] : byBeta.settings()) said |= key == "added damping";
  EXPECT_TRUE(said);
}

TEST(DesignDamping, ATimeRunRefusesAModalRatioAndAlphaWithWhy) {
  const std::string text = springMassStep(4.0, 400.0, 0.0, 1e-3, 0.1, 10);
  auto refusal = [&](const analysis::DampingOptions& d) {
    analysis::SimulateJob job = stepRun(text, d);
    EXPECT_EQ(job.status(), analysis::JobStatus::InputError);
    return analysis::firstError(job.diagnostics());
  };
  analysis::DampingOptions o;
  o.ratios = {0.01};
  EXPECT_NE(refusal(o).find("modal damping ratio has no form in a nonlinear time run"), std::string::npos)
      << refusal(o);
  o = {};
  o.alpha = 0.5, o.beta = 1e-3;
  EXPECT_NE(refusal(o).find("alpha M"), std::string::npos) << refusal(o);
  o = {};
  o.beta = -1.0;
  EXPECT_NE(refusal(o).find("at least 0"), std::string::npos) << refusal(o);
}
