#pragma once
// An answer with its error against the converged model (issue 50): `--error-estimate` (the
// discretization error of the model's own mesh, from it and two refinements) and `--accuracy EPS`
// (the refinement and the integrator tolerance chosen so that the total error estimate is at most
// EPS), for the simulate, static, modes and sweep jobs. Each runs the job on a ladder of meshes
// (analysis/DiscretizationError.hpp) from the file's text read once, compares the original nodes'
// positions (or the frequencies) and returns the job whose results are the answer, for the front end
// to write as it writes any run of that job.
//
// The budget of --accuracy: the discretization gets kDiscretizationShare of EPS, the integration
// the rest (RelTol = EPS / kToleranceDivisor: the accuracy check puts a converged run's error at
// 1-4 RelTol); the reduction none: the full model runs (issue 49 measured no single run that a
// reduced basis makes cheaper at these sizes).
#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "analysis/DiscretizationError.hpp"
#include "analysis/ModesJob.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/StaticJob.hpp"
#include "analysis/SweepJob.hpp"

namespace flexmb::analysis {

constexpr double kDiscretizationShare = 0.7;
constexpr double kToleranceDivisor = 20.0;
// The smallest EPS taken: below it RelTol = EPS / 20 is under a thousand round-offs of a double
// (an --accuracy 1e-20 ran its first mesh until the time limit and had nothing to show).
constexpr double kSmallestAccuracy = 1e-10;

struct AccuracyRequest {
  double eps = std::numeric_limits<double>::quiet_NaN();  // --accuracy EPS; NaN: --error-estimate
  double maxSeconds = 300.0;  // no level is started that is predicted to end after this in all
  int maxRefine = 64;
  // The part of EPS the mesh gets (a study that also reduces gives it less: analysis/StudyAccuracy.hpp).
  double discretizationShare = kDiscretizationShare;
  // The user's stop (Ctrl-C): the level running stops and the ladder with it (null: none; simulate
  // takes its request's flag).
  const std::atomic<bool>* interrupt = nullptr;
  // Each level as it starts and ends ("refine 4: 0.21 s, differs from refine 2 by 3.1e-03"), for a
  // front end to show at once.
  std::function<void(const Diagnostic&)> progress;
};

// The total error estimate E = D + R + I on the answer's scale, and its wording.
struct ErrorBudget {
  double total = 0.0, discretization = 0.0, reduction = 0.0, integration = 0.0;
  bool estimated = false;
  bool met = false;      // --accuracy: total <= EPS
  double seconds = 0.0;  // every mesh's run, the answer's included
  // "total error estimate: 8.1e-04 (discretization 6.3e-04, reduction 0 (full model), integration
  // 1.8e-04) of the motion (0.0833 m)"
  std::string line;
  // The manifest's lines: accuracy target, total error estimate, discretization error estimate,
  // refinement chosen, integrator tolerance, the ladder's levels.
  std::vector<std::pair<std::string, std::string>> settings;
};

template <class Job>
struct AccurateRun {
  std::unique_ptr<Job> job;  // the answer's run (null: the model could not be read; see diagnostics)
  LadderResult ladder;
  ErrorBudget budget;
  Diagnostics diagnostics;  // the ladder's own: levels, the estimate, a target missed
};

// source.read.refine is the first level. A SimulateRequest with a basis (file, matrix or auto) is
// refused (a basis belongs to one mesh). With eps, request.run.relTol defaults to eps /
// kToleranceDivisor and the accuracy check stays on (it measures I).
AccurateRun<SimulateJob> simulateToAccuracy(ModelSource source, SimulateRequest request, const AccuracyRequest& a);
AccurateRun<StaticJob> staticToAccuracy(ModelSource source, const StaticOptions& options, const AccuracyRequest& a);
AccurateRun<ModesJob> modesToAccuracy(ModelSource source, const ModesOptions& options, const AccuracyRequest& a);
// The sweep's frequencies at every configuration (relative, as modes'; the element's order 2: the
// configurations are deformed); options.basis must be empty.
AccurateRun<SweepJob> sweepToAccuracy(ModelSource source, const SweepOptions& options, const AccuracyRequest& a);

}  // namespace flexmb::analysis
