// The simulate job (analysis/SimulateJob.hpp) that every front end calls: the same run as the
// recipe it wraps, input errors as diagnostics before anything runs, and --basis auto's chosen
// candidate run reused as the run (integrated once) with the same result as a run of that basis.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/Simulation.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

analysis::ModelSource fileSource(const std::string& name) { return {dat(name), {}, nullptr, nullptr}; }

bool says(const analysis::SimulateJob& job, analysis::Diagnostic::Kind kind, const std::string& text) {
  for (const auto& d : job.diagnostics())
    if (d.kind == kind && d.text.find(text) != std::string::npos) return true;
  return false;
}
}  // namespace

TEST(SimulateJob, RunsTheStagesAsTheRecipeDoes) {
  analysis::SimulateRequest request;
  request.run.tEnd = 0.02;
  analysis::SimulateJob job(fileSource("straight_guidance.dat"), request);
  ASSERT_EQ(job.status(), analysis::JobStatus::Ready) << analysis::firstError(job.diagnostics());
  EXPECT_EQ(job.run(), analysis::JobStatus::Completed);
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const core::Trajectory direct = analysis::simulate(m, request.run);
  EXPECT_EQ(job.trajectory().nfevals, direct.nfevals);
  ASSERT_EQ(job.trajectory().states.size(), direct.states.size());
  EXPECT_EQ((job.trajectory().states.back().x - direct.states.back().x).norm(), 0.0);
  EXPECT_TRUE(says(job, analysis::Diagnostic::Kind::Result, "wall time"));
}

TEST(SimulateJob, RefusesBeforeRunning) {
  {  // a basis file that is not there
    analysis::SimulateRequest request;
    request.basisFile = "no_such_basis.csv";
    analysis::SimulateJob job(fileSource("straight_guidance.dat"), request);
    EXPECT_EQ(job.status(), analysis::JobStatus::InputError);
    EXPECT_FALSE(analysis::firstError(job.diagnostics()).empty());
    EXPECT_EQ(job.run(), analysis::JobStatus::InputError);  // nothing runs
    EXPECT_TRUE(job.trajectory().time.empty());
  }
  {  // a basis of the wrong size
    analysis::SimulateRequest request;
    request.basis = Eigen::MatrixXd::Identity(3, 2);
    analysis::SimulateJob job(fileSource("straight_guidance.dat"), request);
    EXPECT_EQ(job.status(), analysis::JobStatus::InputError);
    EXPECT_TRUE(says(job, analysis::Diagnostic::Kind::Error, "rows"));
  }
  {  // a driven rigid mechanism has no reduced model
    analysis::SimulateRequest request;
    request.basis = Eigen::MatrixXd(0, 1);
    analysis::SimulateJob job(fileSource("slider_crank_rigid.dat"), request);
    EXPECT_TRUE(job.driven());
    EXPECT_TRUE(says(job, analysis::Diagnostic::Kind::Error, "driven rigid mechanism"));
  }
  {  // a file that cannot be read: the reader's message, nothing else
    analysis::SimulateJob job(fileSource("no_such_model.dat"), {});
    EXPECT_EQ(job.status(), analysis::JobStatus::InputError);
    EXPECT_NE(analysis::firstError(job.diagnostics()).find("no_such_model.dat"), std::string::npos);
  }
  {  // an oversized run (a step limit needing more than 1e9 steps)
    analysis::SimulateRequest request;
    request.run.maxStep = 1e-12;
    analysis::SimulateJob job(fileSource("straight_guidance.dat"), request);
    EXPECT_EQ(job.status(), analysis::JobStatus::InputError);
  }
}

TEST(SimulateJob, MatchesTheModeThreeChoice) {
  EXPECT_TRUE(analysis::isStaticFile(io::readDatStages(dat("spatial/cross_spring_pivot_coarse.dat"))));
  EXPECT_FALSE(analysis::isStaticFile(io::readDatStages(dat("straight_guidance.dat"))));
}

// --basis auto: the chosen candidate's run is the run. Its trajectory, accuracy check and reduction
// estimate are those of a run of the chosen basis made afresh.
TEST(SimulateJob, BasisAutoIntegratesTheChosenBasisOnce) {
  analysis::SimulateRequest request;
  request.run.accuracyCheck = true;
  request.basisFile = "auto";
  request.target = 1e-2;
  // The guidance (4 modal vectors): the manipulator, stiff at rest, now runs its full model at once.
  analysis::SimulateJob job(fileSource("straight_guidance.dat"), request);
  ASSERT_EQ(job.status(), analysis::JobStatus::Ready) << analysis::firstError(job.diagnostics());
  ASSERT_EQ(job.run(), analysis::JobStatus::Completed) << analysis::firstError(job.diagnostics());
  ASSERT_TRUE(job.options().basis.has_value());
  EXPECT_TRUE(job.reusedCandidateRun());
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const core::Trajectory fresh = analysis::simulate(m, job.options());
  const core::Trajectory& reused = job.trajectory();
  EXPECT_EQ(reused.nfevals, fresh.nfevals);
  ASSERT_EQ(reused.states.size(), fresh.states.size());
  EXPECT_EQ((reused.states.back().x - fresh.states.back().x).norm(), 0.0);
  ASSERT_TRUE(reused.accuracy.checked);
  EXPECT_DOUBLE_EQ(reused.accuracy.estimate, fresh.accuracy.estimate);
  ASSERT_TRUE(reused.reduction.estimated);
  EXPECT_DOUBLE_EQ(reused.reduction.estimate, fresh.reduction.estimate);
  EXPECT_LE(reused.reduction.estimate, 1e-2);
}

// The coarse cross-spring pivot refined by 4 under the saddle-point form (a force pulse, galpha at
// RelTol 1e-3): the accuracy check solved its references' configurations at the file's kinematic
// tolerance (ITERSTEP 5e-7), Newton took the run's own configuration as converged, and the check said
// "estimated error 0" where the run was 0.028 of its motion off (2026-12-07). Now both forms are
// checked and measure an error; a check that measures nothing would say so rather than "0".
TEST(SimulateJob, TheAccuracyCheckMeasuresUnderBothDynamicsForms) {
  for (const auto form : {core::DynamicsForm::SaddlePoint, core::DynamicsForm::Projected}) {
    analysis::ModelSource source = fileSource("tests/pivot_coarse_pulse.dat");
    source.read.refine = 4;
    analysis::SimulateRequest request;
    request.run.integrator = analysis::Integrator::GeneralizedAlpha;
    request.run.relTol = 1e-3;
    request.run.dynamics = form;
    request.run.accuracyCheck = true;
    analysis::SimulateJob job(source, request);
    ASSERT_EQ(job.run(), analysis::JobStatus::Completed);
    const core::AccuracyEstimate& a = job.trajectory().accuracy;
    ASSERT_TRUE(a.checked) << a.note;
    EXPECT_GT(a.positionEstimate, 1e-5) << analysis::describeAccuracy(a);
  }
}
