// simulate --basis auto --target EPS answers to EPS with its integration error too (issue 49 item 4):
// the runs' tolerance chosen with the target, the accept test on reduction + integration estimate,
// the full model at once where no basis can pay. Checked against full references at RelTol 1e-8.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/BasisForTarget.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/Simulation.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

struct AutoRun {
  double trueError = NAN, estimate = NAN;
  bool reduced = false;
  std::string basis, tolerance;
};

// The job's run against a full run at RelTol 1e-8 (AbsTol 1e-10), the same measure as the estimate.
AutoRun runAgainstReference(const std::string& file, double target, double referenceRelTol = 1e-8) {
  analysis::SimulateRequest request;
  request.run.accuracyCheck = true;
  request.basisFile = "auto";
  request.target = target;
  request.run.integrator = analysis::Integrator::Auto;
  analysis::SimulateJob job({dat(file), {}, nullptr, nullptr}, request);
  EXPECT_EQ(job.run(), analysis::JobStatus::Completed) << analysis::firstError(job.diagnostics());
  AutoRun r;
  for (const auto& [name, value] : job.settings()) {
    if (name == "basis") r.basis = value;
    if (name == "basis auto estimate") r.estimate = std::stod(value);
    if (name == "tolerance for the target") r.tolerance = value;
  }
  r.reduced = job.options().basis.has_value();
  const core::Model m = io::readDatFile(dat(file));
  analysis::SimulationOptions tight;
  tight.integrator = analysis::Integrator::Auto;
  tight.relTol = referenceRelTol;
  tight.absTol = referenceRelTol * 1e-2;
  tight.keepStates = true;
  const core::Trajectory reference = analysis::simulate(m, tight);
  r.trueError = analysis::positionErrorAgainst(m, job.trajectory(), reference);
  return r;
}
}  // namespace

// Before: the 1-mode basis was accepted on its reduction estimate (5.0e-5) at the file's RelTol 1e-3
// and was 7.0e-5 off the tight reference (estimate / true 0.71). Now its run is at RelTol 5e-5 and
// the estimate it prints counts the integration error: measured 5.1e-5 against 3.1e-5.
TEST(BasisAutoTarget, FlexibleFourBarMeetsTheTargetAndItsEstimateCoversIt) {
  const AutoRun r = runAgainstReference("tests/fourbar_flexible.dat", 1e-3);
  EXPECT_TRUE(r.reduced) << r.basis;
  ASSERT_FALSE(std::isnan(r.estimate)) << "no basis auto estimate in the manifest";
  EXPECT_LE(r.trueError, 1e-3);
  EXPECT_GE(r.estimate, r.trueError);
  EXPECT_LE(r.estimate, 10.0 * r.trueError);
}

// Before: the full model (no basis meets 1e-3) ran at the file's RelTol 1e-3, 3.0e-3 off the tight
// reference. Now at RelTol 5e-5: measured 1.4e-4, estimated 9.6e-5 (the accuracy check reads up to a
// third low on this model: issue 48's measurement of RelTol as the global error).
TEST(BasisAutoTarget, GuidanceAtOneThousandthMeetsItWithTheFullModel) {
  const AutoRun r = runAgainstReference("straight_guidance.dat", 1e-3);
  EXPECT_LE(r.trueError, 1e-3) << r.basis;
  ASSERT_FALSE(std::isnan(r.estimate));
  EXPECT_GE(r.estimate, 0.5 * r.trueError);
  EXPECT_LE(r.estimate, 1e-3);
}

// A model whose full run the auto integrator puts on galpha from the start: no candidate is run, the
// full model runs once, and the run says why.
TEST(BasisAutoTarget, NoBasisCanPayAndTheFullModelRunsAtOnce) {
  analysis::SimulateRequest request;
  request.run.accuracyCheck = true;
  request.basisFile = "auto";
  request.target = 1e-2;
  request.run.integrator = analysis::Integrator::Auto;
  analysis::SimulateJob job({dat("tests/straight_guidance_20.dat"), {}, nullptr, nullptr}, request);
  ASSERT_EQ(job.run(), analysis::JobStatus::Completed) << analysis::firstError(job.diagnostics());
  EXPECT_FALSE(job.options().basis.has_value());
  std::string basis;
  for (const auto& [name, value] : job.settings())
    if (name == "basis") basis = value;
  EXPECT_NE(basis.find("no basis can pay for one run"), std::string::npos) << basis;
  EXPECT_NE(basis.find("no candidate run"), std::string::npos) << basis;
  ASSERT_TRUE(job.options().relTol.has_value());
  EXPECT_DOUBLE_EQ(*job.options().relTol, 5e-4);  // the target's tolerance, the full model's run too
}

// A candidate whose reduction error meets the target and whose integration error does not runs
// again at a tighter tolerance rather than growing the basis: the four-bar at 5e-5 with RelTol 1e-2
// (3 vectors: reduction 1.5e-6 + integration 5.7e-5, then 1.0e-5 at RelTol 2.1e-3; 2 vectors chosen).
TEST(BasisAutoTarget, AnIntegrationErrorThatMissesTightensTheToleranceNotTheBasis) {
  const core::Model m = io::readDatFile(dat("tests/fourbar_flexible.dat"));
  analysis::TargetOptions t;
  t.target = 5e-5;
  t.withIntegration = true;
  t.keepChosenRun = true;
  t.run.integrator = analysis::Integrator::Auto;
  t.run.relTol = 1e-2;
  const analysis::TargetResult r = analysis::basisForTarget(m, t);
  ASSERT_TRUE(r.met) << r.note;
  ASSERT_TRUE(r.relTol.has_value());
  EXPECT_LT(*r.relTol, 1e-2);
  ASSERT_GE(r.chosenTried, 0);
  const analysis::TargetCandidate& c = r.tried[static_cast<size_t>(r.chosenTried)];
  EXPECT_LE(c.total(), t.target);
  EXPECT_FALSE(std::isnan(c.integration));
  EXPECT_EQ(r.tried.front().vectors, 3);
  EXPECT_GT(r.tried.front().total(), t.target);  // the first run of 3 vectors missed on its integration
  EXPECT_LE(r.tried.front().estimate.estimate, t.target);
  // The run kept is the chosen candidate's at the tighter tolerance: its error against a tight
  // reference is within the target.
  ASSERT_TRUE(r.run.has_value());
  analysis::SimulationOptions tight;
  tight.integrator = analysis::Integrator::Auto;
  tight.relTol = 1e-8;
  tight.absTol = 1e-10;
  tight.keepStates = true;
  EXPECT_LE(analysis::positionErrorAgainst(m, *r.run, analysis::simulate(m, tight)), t.target);
}

TEST(BasisAutoTarget, ToleranceIsATwentiethOfTheTargetAtMostTheFiles) {
  EXPECT_DOUBLE_EQ(analysis::relTolForTarget(1e-3, 1e-3), 5e-5);
  EXPECT_DOUBLE_EQ(analysis::relTolForTarget(1e-1, 1e-3), 1e-3);
}

// A rerun's tolerance: a quarter of what the reduction leaves of the target over the integration
// error measured (the pivot: 0.25 x 0.01 / 0.027 = 0.093), never looser than half, never tighter
// than a fiftieth.
TEST(BasisAutoTarget, ARerunTightensByAQuarterOfWhatIsLeftOverTheMeasuredError) {
  EXPECT_NEAR(analysis::tighterToleranceFactor(0.01, 0.0, 0.027), 0.0926, 1e-4);
  EXPECT_DOUBLE_EQ(analysis::tighterToleranceFactor(1e-3, 5e-4, 2.5e-4), 0.5);  // 0.5 exactly
  EXPECT_DOUBLE_EQ(analysis::tighterToleranceFactor(1e-3, 0.0, 1e-3), 0.25);
  EXPECT_DOUBLE_EQ(analysis::tighterToleranceFactor(1e-3, 0.0, 1.0), 0.02);  // clamped
  EXPECT_DOUBLE_EQ(analysis::tighterToleranceFactor(1e-3, 0.0, 1e-5), 0.5);  // clamped
}

// The full model's integration error that misses at the tolerance chosen in advance (RelTol target /
// 20) is rerun once at the tolerance its accuracy check asks for: the coarse pivot's 2.1 mm motion in
// a 0.14 m model was 0.018 of the motion off at 1e-2 (the check read 0.027, "NOT met"); at RelTol
// 4.6e-5 it is 1.8e-4 off a reference at 1e-8, and the check reads 0.0039. The reference here is at
// RelTol 1e-5 (seconds, not minutes).
TEST(BasisAutoTarget, TheFullModelThatMissesOnIntegrationRunsAgainTighter) {
  const AutoRun r = runAgainstReference("tests/pivot_coarse_pulse.dat", 1e-2, 1e-5);
  EXPECT_FALSE(r.reduced) << r.basis;
  EXPECT_NE(r.tolerance.find("off by its accuracy check"), std::string::npos) << r.tolerance;
  ASSERT_FALSE(std::isnan(r.estimate)) << "no basis auto estimate in the manifest";
  EXPECT_LE(r.estimate, 1e-2);
  EXPECT_LE(r.trueError, 1e-2);
  EXPECT_GE(r.estimate, r.trueError);
}
