// Reduced models q = V eta (Eq. 17-23) against the full model and modal truncation theory.
#include <gtest/gtest.h>
#include <atomic>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "analysis/BasisForTarget.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/Simulation.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

Eigen::VectorXd omegasAtInitial(const core::Model& m, std::optional<Eigen::MatrixXd> V) {
  core::Linearization lin(m, V);
  Eigen::VectorXd f, eta = Eigen::VectorXd::Zero(lin.size());
  lin.kinematics().solvePositions(0.0, lin.kinematics().initialDofs());
  lin.appliedForces(0.0, 0.0, f);
  core::LinearizedSystem sys;
  lin.atRest(0.0, eta, f, sys);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(sys.K + sys.G, sys.M);
  return es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

Eigen::MatrixXd projector(const Eigen::MatrixXd& V) {
  const Eigen::MatrixXd Q = V.householderQr().householderQ() * Eigen::MatrixXd::Identity(V.rows(), V.cols());
  return Q * Q.transpose();
}
}  // namespace

TEST(Reduction, IdentityBasisReproducesFullModelExactly) {
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  analysis::SimulationOptions full, ident;
  full.tEnd = ident.tEnd = 0.05;
  full.dynamics = core::DynamicsForm::Projected;  // the form a basis runs in (the saddle point: test_saddle_point)
  ident.basis = Eigen::MatrixXd::Identity(m.numDofs(), m.numDofs());
  const core::Trajectory a = analysis::simulate(m, full), b = analysis::simulate(m, ident);
  ASSERT_TRUE(a.completed && b.completed);
  EXPECT_EQ(a.nfevals, b.nfevals);
  EXPECT_EQ(a.nsteps, b.nsteps);
  EXPECT_EQ(a.nfailed, b.nfailed);
  ASSERT_EQ(a.time.size(), b.time.size());
  double worst = 0.0;
  for (size_t i = 0; i < a.time.size(); ++i)
    worst = std::max(worst, (a.states[i].x - b.states[i].x).lpNorm<Eigen::Infinity>());
  EXPECT_LT(worst, 1e-12);
}

TEST(Reduction, ModalBasisReproducesModalTruncation) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const Eigen::VectorXd full = omegasAtInitial(m, std::nullopt);
  for (int r : {3, 5}) {
    analysis::ReductionOptions o;
    o.method = "modal";
    o.modes = r;
    const analysis::ReductionResult basis = analysis::buildBasis(m, o);
    ASSERT_EQ(basis.V.cols(), r);
    const Eigen::VectorXd red = omegasAtInitial(m, basis.V);
    for (int i = 0; i < r; ++i) EXPECT_NEAR(red[i] / full[i], 1.0, 1e-10) << "mode " << i + 1 << " of MODAL-" << r;
  }
}

TEST(Reduction, ManipulatorModalBasisKeepsHingesAsIdentityColumns) {
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  const std::vector<int> large = analysis::defaultLargeCoordinates(m);
  ASSERT_EQ(large.size(), 2u);
  analysis::ReductionOptions o;
  o.modes = 2;
  const analysis::ReductionResult basis = analysis::buildBasis(m, o);
  ASSERT_EQ(basis.V.rows(), 18);
  ASSERT_EQ(basis.V.cols(), 4);  // MODAL-2: two hinges + two modes
  for (int j = 0; j < 2; ++j) {
    EXPECT_DOUBLE_EQ(basis.V(large[j], j), 1.0);
    EXPECT_DOUBLE_EQ(basis.V.col(j).norm(), 1.0);
    EXPECT_DOUBLE_EQ(basis.V.row(large[j]).norm(), 1.0);
  }
}

TEST(Reduction, SvdModalOfOneConfigurationSpansTheModalBasis) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  analysis::ReductionOptions modal;
  modal.modes = 3;
  analysis::ReductionOptions svd = modal;
  svd.method = "svd-modal";
  svd.configs = 1;
  svd.node = 6;
  svd.component = 1;
  svd.from = svd.to = 0.0;  // the initial configuration
  svd.weight = 0.0;
  svd.threshold = 0.0;
  svd.count = 3;
  const auto a = analysis::buildBasis(m, modal), b = analysis::buildBasis(m, svd);
  ASSERT_EQ(b.V.cols(), 3);
  EXPECT_LT((projector(a.V) - projector(b.V)).norm(), 1e-8);
}

namespace {
// M_s of Eq. 21 in the initial configuration (the small block of the full model's mass matrix).
Eigen::MatrixXd smallMass(const core::Model& m, const std::vector<int>& small) {
  core::Linearization lin(m);
  Eigen::VectorXd f;
  const Eigen::VectorXd q0 = lin.kinematics().initialDofs();
  lin.kinematics().solvePositions(m.settings.t0, q0);
  lin.appliedForces(m.settings.t0, 0.0, f);
  core::LinearizedSystem sys;
  lin.atRest(m.settings.t0, q0, f, sys);
  Eigen::MatrixXd Ms(small.size(), small.size());
  for (size_t i = 0; i < small.size(); ++i)
    for (size_t j = 0; j < small.size(); ++j) Ms(i, j) = sys.M(small[i], small[j]);
  return Ms;
}
}  // namespace

TEST(Reduction, ModalBasisIsMassNormalisedByDefaultAndUnitOnRequest) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  analysis::ReductionOptions o;
  o.modes = 3;
  const analysis::ReductionResult mass = analysis::buildBasis(m, o);
  o.normalise = "unit";
  const analysis::ReductionResult unit = analysis::buildBasis(m, o);
  const std::vector<int> large = analysis::defaultLargeCoordinates(m);
  std::vector<int> small;
  for (int i = 0; i < m.numDofs(); ++i)
    if (std::find(large.begin(), large.end(), i) == large.end()) small.push_back(i);
  const int nl = static_cast<int>(large.size());
  Eigen::MatrixXd Vm(small.size(), 3), Vu(small.size(), 3);
  for (size_t i = 0; i < small.size(); ++i)
    Vm.row(i) = mass.V.row(small[i]).tail(3), Vu.row(i) = unit.V.row(small[i]).tail(3);
  ASSERT_EQ(mass.V.cols(), nl + 3);
  const Eigen::MatrixXd Ms = smallMass(m, small);
  EXPECT_LT((Vm.transpose() * Ms * Vm - Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-10);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(Vu.col(k).norm(), 1.0, 1e-14);
    EXPECT_NEAR(Vu.col(k).dot(Vm.col(k)) / Vm.col(k).norm(), 1.0, 1e-12) << "same direction and sign, mode " << k;
  }
  o.normalise = "length";
  EXPECT_THROW(analysis::buildBasis(m, o), std::invalid_argument);
}

// The paper's counts (Table 2: MODAL-3 697, MODAL-5 1213 evaluations) were made with MATLAB's
// mass-normalised eig(K, M) columns; ode45's absolute tolerance acts on eta, so the scaling matters
// (unit columns: 931 and 1357). Tolerance 15%: the full model's count itself differs from the
// paper's (45,757 against 46,075) and the reduced counts are sensitive to the exact error norm.
TEST(Reduction, MassNormalisedModalCountsNearThePapers) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  for (const auto& [r, paper] : {std::pair<int, double>{3, 697.0}, {5, 1213.0}}) {
    analysis::ReductionOptions o;
    o.modes = r;
    analysis::SimulationOptions so;
    so.basis = analysis::buildBasis(m, o).V;
    const core::Trajectory t = analysis::simulate(m, so);
    ASSERT_TRUE(t.completed) << t.stopReason;
    EXPECT_NEAR(t.nfevals / paper, 1.0, 0.15) << "MODAL-" << r << ": " << t.nfevals << " evaluations, paper " << paper;
  }
}

// MATLAB's plain call ode45(f, [0 T], y0) (no output grid: Refine output, first trial step hmax):
// the trial stages of that first step are far off the solution, where the kinematics of both paper
// models has no solution; such attempts are rejected and the runs complete. Their counts are the
// paper's within 10% for MODAL-3 / MODAL-5 (issue 13; the grid's effect on the counts is in the
// validation report), within 2% / 5% for the stability-bound full models.
TEST(Reduction, PlainOde45CallRunsThePaperModels) {
  auto count = [](const core::Model& m, std::optional<Eigen::MatrixXd> V) {
    analysis::SimulationOptions so;
    so.basis = std::move(V);
    so.intervals = 0;
    so.keepStates = false;
    const core::Trajectory t = analysis::simulate(m, so);
    EXPECT_TRUE(t.completed) << t.stopReason;
    return t;
  };
  const core::Model g = io::readDatFile(dat("straight_guidance.dat"));
  const core::Trajectory full = count(g, std::nullopt);
  EXPECT_NEAR(full.nfevals / 46075.0, 1.0, 0.02) << full.nfevals;
  for (const auto& [r, paper] : {std::pair<int, double>{3, 697.0}, {5, 1213.0}}) {
    analysis::ReductionOptions o;
    o.modes = r;
    const core::Trajectory t = count(g, analysis::buildBasis(g, o).V);
    EXPECT_NEAR(t.nfevals / paper, 1.0, 0.10) << "MODAL-" << r << ": " << t.nfevals << " evaluations, paper " << paper;
    EXPECT_GT(full.nfevals, 30 * t.nfevals);
  }
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  const core::Trajectory mfull = count(m, std::nullopt);
  EXPECT_NEAR(mfull.nfevals / 345145.0, 1.0, 0.05) << mfull.nfevals;
  EXPECT_GE(mfull.nrhsfailed, 1);  // the first trial step has no configuration
  analysis::ReductionOptions o;
  o.modes = 2;
  const core::Trajectory mred = count(m, analysis::buildBasis(m, o).V);
  EXPECT_GT(mfull.nfevals, 30 * mred.nfevals);
}

// ---- Issue 32: the reduction error estimate of every reduced run, and a basis from a target.

namespace {
analysis::ReductionOptions guidanceSvd(int count) {
  analysis::ReductionOptions o;
  o.method = "svd-modal";
  o.modes = 3;
  o.node = 6, o.component = 1, o.from = -0.0833, o.to = 0.0833, o.configs = 10;
  o.count = count;
  return o;
}
}  // namespace

// The estimate against the full model on the paper's guidance (the same measure: every position,
// every output time, of the full run's motion): effectivity between 1 and 10 for modal and
// SVD-modal bases, and it grows when columns are removed from a basis.
TEST(ReductionErrorEstimate, BoundsTheTrueErrorOnTheGuidanceAndGrowsWithFewerColumns) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const core::Trajectory full = analysis::simulate(m, analysis::SimulationOptions());
  ASSERT_TRUE(full.completed);
  EXPECT_FALSE(full.reduction.estimated) << "a full run has no reduction error to estimate";
  analysis::ReductionOptions modal;
  modal.modes = 3;
  const std::vector<std::pair<std::string, Eigen::MatrixXd>> bases = {
      {"MODAL-3", analysis::buildBasis(m, modal).V},
      {"SVDm-5", analysis::buildBasis(m, guidanceSvd(5)).V},
      {"SVDm-4", analysis::buildBasis(m, guidanceSvd(4)).V},
      {"SVDm-3", analysis::buildBasis(m, guidanceSvd(3)).V}};
  std::vector<double> estimates;
  for (const auto& [name, V] : bases) {
    analysis::SimulationOptions o;
    o.basis = V;
    const core::Trajectory r = analysis::simulate(m, o);
    ASSERT_TRUE(r.completed) << name;
    ASSERT_TRUE(r.reduction.estimated) << name << ": " << r.reduction.note;
    const double truth = analysis::positionErrorAgainst(m, r, full);
    const double effectivity = r.reduction.estimate / truth;
    std::printf("%s: true error %.3g, estimate %.3g, effectivity %.3g, estimate %.3g s\n", name.c_str(), truth,
                r.reduction.estimate, effectivity, r.reduction.seconds);
    EXPECT_GE(effectivity, 1.0) << name;
    EXPECT_LE(effectivity, 10.0) << name;
    estimates.push_back(r.reduction.estimate);
  }
  EXPECT_LT(estimates[1], estimates[2]) << "SVDm: 5 columns against 4";
  EXPECT_LT(estimates[2], estimates[3]) << "SVDm: 4 columns against 3";
}

// The manipulator with a single mode is off by its own motion (a phase error of the kept mode), which
// a quasi-static deflection does not see (0.39 of the true error): the error the linearised full
// model carries along the run does, and keeps the estimate above the true error.
TEST(ReductionErrorEstimate, TheCarriedErrorSeesAPoorBasisOwnMotion) {
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  const core::Trajectory full = analysis::simulate(m, analysis::SimulationOptions());
  ASSERT_TRUE(full.completed);
  analysis::ReductionOptions one;
  one.modes = 1;
  analysis::SimulationOptions o;
  o.basis = analysis::buildBasis(m, one).V;
  const core::Trajectory r = analysis::simulate(m, o);
  ASSERT_TRUE(r.completed && r.reduction.estimated) << r.reduction.note;
  const double truth = analysis::positionErrorAgainst(m, r, full);
  std::printf("manipulator, one mode: true error %.3g, quasi-static %.3g, carried %.3g, estimate %.3g (%.3g s)\n",
              truth, r.reduction.quasiStatic, r.reduction.carried, r.reduction.estimate, r.reduction.seconds);
  EXPECT_LT(r.reduction.quasiStatic, 0.5 * truth);
  EXPECT_GT(r.reduction.carried, 0.7 * truth);
  EXPECT_LT(r.reduction.carried, 1.5 * truth);
  EXPECT_GE(r.reduction.estimate / truth, 1.0);
  EXPECT_LE(r.reduction.estimate / truth, 10.0);
}

// A target the paper's 1% rule does not meet (it keeps 5 SVD-modal vectors, 6.5e-4 off): the scan
// goes up to the first basis whose estimate meets it, and its true error does.
TEST(ReductionErrorEstimate, ATargetBeyondTheOnePercentRuleIsMet) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  analysis::TargetOptions t;
  t.target = 3e-4;
  t.basis = guidanceSvd(0);
  const analysis::TargetResult r = analysis::basisForTarget(m, t);
  ASSERT_TRUE(r.met) << r.note;
  const int chosen = static_cast<int>(r.basis.V.cols());
  EXPECT_GT(chosen, 5) << "the 1% rule's 5 vectors do not meet 3e-4";
  EXPECT_EQ(r.tried.front().vectors, 5) << "the scan starts at the 1% rule";
  const core::Trajectory full = analysis::simulate(m, analysis::SimulationOptions());
  analysis::SimulationOptions o;
  o.basis = r.basis.V;
  const core::Trajectory red = analysis::simulate(m, o);
  EXPECT_LE(analysis::positionErrorAgainst(m, red, full), t.target);
  // Bad targets are input errors.
  for (double bad : {0.0, -1e-3, 1.0, 2.0, std::nan("")}) {
    t.target = bad;
    EXPECT_THROW(analysis::basisForTarget(m, t), std::invalid_argument) << bad;
  }
}

// Issue 49, item 5: Ctrl-C during the target scan stops it after the candidate it reached and keeps
// what it found: here the first candidate (the 1% rule's 5 vectors, which miss 3e-4) is the best so
// far, the second is stopped by the interrupt.
TEST(ReductionTarget, AnInterruptKeepsTheBestBasisSoFar) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  std::atomic<bool> stop{false};
  analysis::TargetOptions t;
  t.target = 3e-4;
  t.basis = guidanceSvd(0);
  t.run.interrupt = &stop;
  t.onCandidate = [&](int, double) { stop = true; };  // Ctrl-C once the first candidate is in
  const analysis::TargetResult r = analysis::basisForTarget(m, t);
  ASSERT_TRUE(r.interrupted);
  EXPECT_FALSE(r.met);
  EXPECT_FALSE(r.full);  // not decided: the scan did not finish
  ASSERT_EQ(r.bestTried, 0) << r.note;
  ASSERT_GE(r.tried.size(), 1u);
  EXPECT_LE(r.tried.size(), 2u);
  if (r.tried.size() == 2) {
    EXPECT_FALSE(r.tried[1].completed);
  }
  EXPECT_EQ(r.basis.V.cols() - static_cast<Eigen::Index>(r.basis.large.size()), r.tried[0].vectors);
  EXPECT_NE(r.note.find("interrupted"), std::string::npos) << r.note;
}

// Issue 49, item 6: a basis that keeps most of the model cannot pay for a run. On the 20-element
// guidance (77 coordinates) the modal scan at 1e-3 used to run 73 vectors (1.8 s of choosing against
// 0.15 s for the full model); now it stops after the first candidate, whose prediction at the cap
// (70% of the coordinates) misses the target, and answers with the full model, saying why.
TEST(ReductionTarget, ABasisThatKeepsMostOfTheModelIsNotTried) {
  const core::Model m = io::readDatFile(dat("tests/straight_guidance_20.dat"));
  analysis::TargetOptions t;
  t.target = 1e-3;
  const analysis::TargetResult r = analysis::basisForTarget(m, t);
  EXPECT_FALSE(r.met);
  EXPECT_TRUE(r.full);
  ASSERT_EQ(r.tried.size(), 1u);
  EXPECT_EQ(r.tried[0].vectors, 3);
  EXPECT_NE(r.note.find("up to 53 vectors"), std::string::npos) << r.note;
  EXPECT_NE(r.note.find("cannot pay for a run"), std::string::npos) << r.note;
  // A limit of the caller's lifts the cap: the scan may then try the larger bases. On the auto
  // integrator, as the command line runs them: ode45 took 64 s and 82 s for 56 and 60 vectors, which
  // galpha runs in 0.6 s.
  t.maxVectors = 60;
  t.run.integrator = analysis::Integrator::Auto;
  t.target = 1e-2;
  const analysis::TargetResult lifted = analysis::basisForTarget(m, t);
  EXPECT_GT(lifted.tried.size(), 1u) << lifted.note;
  EXPECT_EQ(lifted.note.find("cannot pay"), std::string::npos) << lifted.note;
}

// Issue 49 item 4: on the elbow (6 s of its free vibration after the load) the stiffness in motion
// nearly vanishes near t = 4.6 s, where the quasi-static deflection reads 20-380 times the true error
// of a modal basis; the carried error (inertia kept) follows it, so the estimate is twice that: for
// 19 modes 0.0020 against a true 0.00105 (before: 0.12, effectivity 115, which drove the scan to 73
// vectors where 12 meet 1e-2).
TEST(ReductionErrorEstimate, TheCarriedErrorHoldsWhereTheQuasiStaticDeflectionDoesNot) {
  const core::Model m = io::readDatFile(dat("spatial/elbow.dat"));
  analysis::SimulationOptions o;
  o.tEnd = 6.0;
  o.intervals = 60;
  o.relTol = 1e-6;
  o.absTol = 1e-8;
  o.integrator = analysis::Integrator::Auto;
  o.accuracyCheck = false;
  const core::Trajectory full = analysis::simulate(m, o);
  ASSERT_TRUE(full.completed) << full.stopReason;
  analysis::ReductionOptions modal;
  modal.modes = 19;
  o.basis = analysis::buildBasis(m, modal).V;
  const core::Trajectory r = analysis::simulate(m, o);
  ASSERT_TRUE(r.completed && r.reduction.estimated) << r.stopReason << r.reduction.note;
  const double truth = analysis::positionErrorAgainst(m, r, full);
  std::printf("elbow, 19 modes: true error %.3g, quasi-static %.3g, carried %.3g, estimate %.3g\n", truth,
              r.reduction.quasiStatic, r.reduction.carried, r.reduction.estimate);
  EXPECT_GT(r.reduction.quasiStatic, 10.0 * truth);
  EXPECT_GE(r.reduction.estimate / truth, 1.0);
  EXPECT_LE(r.reduction.estimate / truth, 10.0);
}
