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
#include <functional>
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
};

struct TargetCandidate {
  int vectors = 0;  // reduced columns (besides the identity columns of Eq. 20)
  core::ReductionEstimate estimate;
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
  // keepChosenRun: the chosen candidate's run (no accuracy check and no reduction estimate of its
  // own yet) and its accuracy windows.
  std::optional<core::Trajectory> run;
  DeferredAccuracy runAccuracy;
};

// Throws std::invalid_argument for a target outside (0, 1) or a model without degrees of freedom
// to reduce. An interrupt stops the scan after the candidate it reached (TargetResult::interrupted).
TargetResult basisForTarget(const core::Model& model, const TargetOptions& options);

}  // namespace flexmb::analysis
