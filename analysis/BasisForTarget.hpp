#pragma once
// A reduction basis chosen from an error target (issue 32): the smallest basis of the requested
// kind whose reduced run's reduction error estimate (analysis/ReductionError.hpp) is at most the
// target. The candidates are the leading columns of one basis (modal: the lowest modes of the q_s
// subproblem, Eq. 21; SVD-modal: the leading singular vectors, Eq. 22-23), so one eigenanalysis or
// one sweep serves them all; each candidate is run over the model's span with the run's integrator
// and estimated. The scan starts at a first guess (SVD-modal: the paper's 1% rule; modal: --modes):
// when that meets the target it goes down one vector at a time while the smaller one still meets
// it; else it goes up, each time to the first size whose estimate, predicted from the last run's
// deflections (predictReductionError), is within the target, and runs that. Where none smaller
// than the full model meets it, the full model is the answer (`full`).
#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "analysis/Reduction.hpp"
#include "analysis/Simulation.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct TargetOptions {
  double target = 1e-3;    // the reduction error, relative to the run's motion (ReductionError.hpp)
  ReductionOptions basis;  // kind and parameters; modes / count are what the scan chooses
  SimulationOptions run;   // the integrator and tolerances of the candidate runs (basis set here)
  int maxVectors = 0;      // reduced columns to try at most (0: every small coordinate but one)
  std::function<void(int vectors, double estimate)> onCandidate;  // progress
  // Each candidate on stderr as the scan goes (issue 49): before its run the size and a time
  // estimate from the last candidate's, after it the estimate and the time taken.
  bool sayCandidates = false;
  // Keep the chosen candidate's run (TargetResult::run) with its accuracy check's windows, so that
  // the run asked for is not integrated a second time.
  bool keepChosenRun = false;
  // The accept test counts the candidate's integration error too (issue 49 item 4): a candidate whose
  // reduction estimate meets the target has its accuracy check run, and meets it where the reduction
  // estimate plus that check's position estimate, on the motion's scale, is within the target.
  bool withIntegration = false;
};

// The relative tolerance the runs of a target get where the user gave none (issue 49 item 4): a
// twentieth of the target (at most the file's), so that the integration error leaves most of the
// target to the reduction (measured: analysis/BasisForTarget.cpp).
double relTolForTarget(double target, double fileRelTol);

// The factor on RelTol and AbsTol for a rerun whose integration error (on the target's scale) left
// too little of the target beside its reduction error: a quarter of what is left over the measured
// integration error, the error taken as proportional to the tolerance, within 0.02 ... 0.5.
double tighterToleranceFactor(double target, double reduction, double integration);

// Why no basis can pay for a single run of the full model with the auto integrator (empty: one
// may): where the model's highest eigenfrequency at rest puts auto on galpha from the start (over
// 10,000 ode45 steps over the span), the full run is bound by accuracy, not stability, and a reduced
// run on Eq. 19 takes as many steps, each a full kinematic solve, besides its scan (issue 49 item 4:
// measured in BasisForTarget.cpp). Then the full model runs at once.
std::string reductionCannotPay(const core::Model& model, const SimulationOptions& run);

// The accuracy check's position estimate (relative to the model size) on the reduction estimate's
// scale (the motion, or the model size where the motion is small); NaN where it did not run.
double integrationOnScale(const core::Model& model, const core::AccuracyEstimate& accuracy, double scale);

struct TargetCandidate {
  int vectors = 0;                   // reduced columns (besides the identity columns of Eq. 20)
  core::ReductionEstimate estimate;  // with the run's own estimator (40 output times)
  // withIntegration, where the reduction estimate met the target: the run's accuracy check and its
  // position estimate on the estimate's scale (NaN: not checked).
  core::AccuracyEstimate accuracy;
  double integration = std::numeric_limits<double>::quiet_NaN();
  double total() const { return estimate.estimate + (std::isnan(integration) ? 0.0 : integration); }
  long fevals = 0;
  double seconds = 0.0;             // the candidate's run and estimate
  double integrationSeconds = 0.0;  // its integration alone (what an evaluation costs, issue 49 item 3)
  bool completed = false;
  std::string stopReason;
};

struct TargetResult {
  bool met = false;   // a basis smaller than the full model meets the target
  bool full = false;  // none does: use the full model
  // Stopped by run.interrupt (Ctrl-C): basis is the best so far (met: the smallest that meets the
  // target; else the completed candidate with the lowest estimate, if any; bestTried indexes it).
  bool interrupted = false;
  int bestTried = -1;
  ReductionResult basis;  // the chosen one (met), with its parameters (and "target")
  std::vector<TargetCandidate> tried;
  double buildSeconds = 0.0, seconds = 0.0;  // the basis of all candidates; everything
  std::string note;                          // why the full model (or what limited the scan)
  // keepChosenRun: the chosen candidate's run and its accuracy windows (its estimate and, with
  // withIntegration, its accuracy check: tried[chosenTried]).
  std::optional<core::Trajectory> run;
  DeferredAccuracy runAccuracy;
  int chosenTried = -1;  // met: the chosen candidate in tried (its estimate and accuracy check)
  // withIntegration: a tolerance tighter than run.relTol that a candidate needed (the chosen basis'
  // run uses it).
  std::optional<double> relTol, absTol;
};

// Throws std::invalid_argument for a target outside (0, 1) or a model without degrees of freedom
// to reduce. An interrupt stops the scan after the candidate it reached (TargetResult::interrupted).
TargetResult basisForTarget(const core::Model& model, const TargetOptions& options);

}  // namespace flexmb::analysis
