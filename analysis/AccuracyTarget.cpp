#include "analysis/AccuracyTarget.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <thread>

#include "analysis/Interrupt.hpp"
#include "analysis/ReductionError.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {

// The position coordinates of the file's own nodes (indices kept by every refinement).
std::vector<int> originalPositions(const ModelSource& source) {
  ModelSource base = source;
  base.read.refine = 1;
  const auto stages = readStages(base);
  const core::Model& model = stages->back().model;
  std::vector<int> out;
  for (int i = 0; i < model.nx; ++i)
    if (core::isTranslational(model.nodes[model.xOwnerNode[i]].kind)) out.push_back(i);
  return out;
}

// Positions at each of `states` (x vectors), stacked, and their scale: the first level's on every
// level (fixed: 0 until it is set), so that the levels' values compare as they are.
template <class XOf>
MeshLevel positionsLevel(const core::Model& model, const std::vector<int>& positions, size_t count, XOf xOf,
                         const Eigen::VectorXd& initial, std::string& measure, double& fixed) {
  MeshLevel l;
  l.values.resize(static_cast<Eigen::Index>(count * positions.size()));
  double motion = 0.0;
  Eigen::Index k = 0;
  for (size_t s = 0; s < count; ++s) {
    const Eigen::VectorXd& x = xOf(s);
    for (int i : positions) {
      l.values[k++] = x[i];
      motion = std::max(motion, std::abs(x[i] - initial[i]));
    }
  }
  if (!(fixed > 0.0)) {
    const ErrorScale scale = errorScaleOf(model, motion);  // the reduction estimate's scale
    fixed = scale.value;
    measure = scale.text;
  }
  l.scale = fixed;
  l.positionValues = l.values.size();
  l.ok = count > 0;
  if (!l.ok) l.reason = "no result to compare";
  return l;
}

// The time a level may take: a watch sets the run's own stop flag when the user's is set (Ctrl-C)
// or when `seconds` have passed, so that a level the prediction underrated stops at the time
// allowed instead of overrunning it.
class Deadline {
 public:
  Deadline(const std::atomic<bool>* user, double seconds)
      : user_(user),
        end_(std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                    std::chrono::duration<double>(std::max(seconds, 0.0)))) {
    watch_ = std::thread([this] {
      while (!done_.load()) {
        const bool byUser = user_ && user_->load();
        if (byUser || std::chrono::steady_clock::now() >= end_) {
          expired_.store(!byUser);
          cause_.store(byUser ? SIGINT : kTimeAllowedCause);
          flag_.store(true);
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    });
  }
  ~Deadline() {
    done_.store(true);
    watch_.join();
  }
  Deadline(const Deadline&) = delete;
  Deadline& operator=(const Deadline&) = delete;
  const std::atomic<bool>* flag() const { return &flag_; }
  const std::atomic<int>* cause() const { return &cause_; }         // what set flag(), for the run's stop reason
  bool expired() const { return flag_.load() && expired_.load(); }  // the time, not the user, stopped it

 private:
  const std::atomic<bool>* user_;
  std::chrono::steady_clock::time_point end_;
  std::atomic<bool> flag_{false}, done_{false}, expired_{false};
  std::atomic<int> cause_{0};
  std::thread watch_;
};

// Builds and runs a job that takes RunHooks (static, sweep) on a mesh, its stop flag the level's
// Deadline.
template <class Job, class Options>
auto stoppableJob(const Options& options) {
  return [&options](const ModelSource& s, const std::atomic<bool>* stop, const std::atomic<int>* cause) {
    auto job = std::make_unique<Job>(s, options);
    if (job->status() == JobStatus::Ready) job->run({nullptr, stop, cause});
    return job;
  };
}

std::string refusalOf(const ModelJob& job) {
  const std::string e = firstError(job.diagnostics());
  return e.empty() ? "it did not complete" : e;
}

// The ladder around one kind of job: make(source) builds and runs the job on a mesh, measure(job)
// gives the level's values; the answer's job is kept.
template <class Job, class Make, class Measure>
AccurateRun<Job> climb(ModelSource source, const AccuracyRequest& a, const std::string& analysis, Make make,
                       Measure measure, double elementOrder = kBeamOrder) {
  AccurateRun<Job> out;
  if (!source.stages && !source.text) {
    try {
      source.text = std::make_shared<const std::string>(io::readDatText(source.file));
    } catch (const std::exception&) {  // the job says what is wrong with the file
      out.job = make(source, a.interrupt, nullptr);
      return out;
    }
  }
  std::vector<int> positions;
  try {
    positions = originalPositions(source);
  } catch (const std::exception&) {
    out.job = make(source, a.interrupt, nullptr);
    return out;
  }
  std::map<int, std::unique_ptr<Job>> jobs;
  double spent = 0.0;  // the levels' seconds so far: what remains of a.maxSeconds bounds the next
  std::string measureText;
  double scale = 0.0;  // the first level's, for every level (measure sets it)
  auto tell = [&](Diagnostic::Kind kind, const std::string& text) {
    Diagnostic d(kind, "", text);
    if (a.progress) a.progress(d);
    out.diagnostics.push_back(std::move(d));
  };
  LadderOptions lo;
  lo.start = source.read.refine;
  lo.target = std::isnan(a.eps) ? a.eps : a.discretizationShare * a.eps;
  lo.maxRefine = a.maxRefine;
  lo.maxSeconds = a.maxSeconds;
  lo.elementOrder = elementOrder;
  lo.onLevel = [&](int refine, const std::string& why) {
    tell(Diagnostic::Kind::Note, analysis + " at refine " + std::to_string(refine) + " (" + why + ")");
  };
  out.ladder = climbMeshLadder(
      [&](int refine) {
        ModelSource s = source;
        s.read.refine = refine;
        const Deadline deadline(a.interrupt, a.maxSeconds - spent);
        std::unique_ptr<Job> job = make(s, deadline.flag(), deadline.cause());
        MeshLevel l;
        if (job->status() == JobStatus::Completed) {
          l = measure(*job, positions, measureText, scale);
        } else {
          l.reason = deadline.expired() ? "stopped at the time allowed (" + text::shortest(a.maxSeconds) + " s in all)"
                                        : refusalOf(*job);
        }
        l.seconds = job->secondsSoFar();
        spent += l.seconds;
        jobs[refine] = std::move(job);
        return l;
      },
      lo);
  DiscretizationEstimate& est = out.ladder.estimate;
  est.measure = measureText;
  const int chosen = est.levels.empty() ? lo.start : est.levels[static_cast<size_t>(out.ladder.chosen)].refine;
  out.job = std::move(jobs[chosen]);
  if (!out.job) out.job = make(source, a.interrupt, nullptr);  // never reached: the first level always runs
  // The value the last pair differs most on: for positions, the coordinate (values are stacked per
  // output time or load step, the original positions in order).
  if (out.job && est.estimated && !positions.empty()) {
    const MeshLevel& pair = est.levels[static_cast<size_t>(std::max(est.of, 1))];
    if (pair.largestAt >= 0 && pair.largestAt < pair.positionValues)
      est.where = out.job->model().coordName(positions[static_cast<size_t>(pair.largestAt) % positions.size()]);
    else if (pair.largestAt >= 0 && pair.positionValues >= 0)
      est.where = "buckling load factor " + std::to_string(pair.largestAt - pair.positionValues + 1);
  }
  for (size_t k = 1; k < est.levels.size(); ++k)
    if (!std::isnan(est.levels[k].differenceToPrevious))
      tell(Diagnostic::Kind::Note, "refine " + std::to_string(est.levels[k].refine) + " differs from refine " +
                                       std::to_string(est.levels[k - 1].refine) + " by " +
                                       text::significant(est.levels[k].differenceToPrevious, 2) + " " + measureText +
                                       " (" + text::significant(est.levels[k].seconds, 2) + " s)");
  return out;
}

// The budget's words and manifest lines, from the ladder and the chosen level's other errors
// (integrationWords empty: the analysis has none to add).
template <class Job>
void fillBudget(AccurateRun<Job>& run, const AccuracyRequest& a, const std::string& integrationWords) {
  const DiscretizationEstimate& est = run.ladder.estimate;
  ErrorBudget& b = run.budget;
  auto setting = [&](const std::string& k, const std::string& v) { b.settings.emplace_back(k, v); };
  if (!std::isnan(a.eps)) setting("accuracy target", text::significant(a.eps, 3) + " " + est.measure);
  setting("discretization error estimate", describeDiscretization(est));
  std::string levels;
  for (const MeshLevel& l : est.levels)
    levels += (levels.empty() ? "" : "; ") + std::string("refine ") + std::to_string(l.refine) + " " +
              (l.ok ? text::significant(l.seconds, 2) + " s" : "failed: " + l.reason);
  setting("meshes run", levels);
  for (const MeshLevel& l : est.levels) b.seconds += l.seconds;
  if (!est.estimated) {
    run.diagnostics.emplace_back(Diagnostic::Kind::Warning, "", "discretization error " + describeDiscretization(est));
    return;
  }
  const MeshLevel& chosen = est.levels[static_cast<size_t>(est.of)];
  b.discretization = est.estimate;
  b.integration = chosen.otherError;
  b.total = b.discretization + b.reduction + b.integration;
  b.estimated = true;
  const bool unknown = !integrationWords.empty() && !chosen.otherUnknown.empty();
  b.met = !std::isnan(a.eps) && b.total <= a.eps && !unknown;
  b.line = "total error estimate: " + text::significant(b.total, 2) + " (discretization " +
           text::significant(b.discretization, 2) + ", reduction 0: the full model ran" +
           (integrationWords.empty() ? std::string()
            : unknown                ? ", " + integrationWords + " not estimated (" + chosen.otherUnknown + ")"
                                     : ", " + integrationWords + " " + text::significant(b.integration, 2)) +
           ") " + est.measure + " at refine " + std::to_string(est.ofRefine);
  setting("total error estimate", b.line.substr(std::string("total error estimate: ").size()));
  setting("refinement chosen", std::to_string(est.ofRefine) + " parts per flexible beam");
  if (!std::isnan(a.eps))
    setting("accuracy target met",
            b.met ? "yes" : "no" + (run.ladder.stopNote.empty() ? std::string() : ": " + run.ladder.stopNote));
  run.diagnostics.emplace_back(Diagnostic::Kind::Result, "",
                               "discretization error estimate: " + describeDiscretization(est));
  run.diagnostics.emplace_back(Diagnostic::Kind::Result, "", b.line);
  if (!std::isnan(a.eps) && !b.met && unknown)  // not a matter of time: the integration error is not known
    run.diagnostics.emplace_back(Diagnostic::Kind::Warning, "",
                                 "the accuracy target " + text::significant(a.eps, 2) +
                                     " is not known to be met: the " + integrationWords + " error is not estimated (" +
                                     chosen.otherUnknown +
                                     "); a tighter --reltol or --dynamics projected may let it be checked",
                                 "", "", "reltol");
  else if (!std::isnan(a.eps) && !b.met)
    run.diagnostics.emplace_back(Diagnostic::Kind::Warning, "",
                                 "the accuracy target " + text::significant(a.eps, 2) +
                                     " is not met: the total error estimate is " + text::significant(b.total, 2) +
                                     (run.ladder.stopNote.empty() ? std::string() : " (" + run.ladder.stopNote + ")"),
                                 "", "", "max_seconds");
  else if (!est.note.empty())
    run.diagnostics.emplace_back(Diagnostic::Kind::Warning, "", "discretization error estimate: " + est.note);
}

}  // namespace

AccurateRun<SimulateJob> simulateToAccuracy(ModelSource source, SimulateRequest request, const AccuracyRequest& a) {
  const bool eps = !std::isnan(a.eps);
  if (eps && !request.run.relTol) request.run.relTol = a.eps / kToleranceDivisor;
  if (eps && !request.run.absTol) request.run.absTol = *request.run.relTol * 1e-2;
  request.run.accuracyCheck = true;
  AccuracyRequest watched = a;  // the user's stop flag (Ctrl-C) ends the ladder too
  if (!watched.interrupt) watched.interrupt = request.run.interrupt;
  const bool basis = !request.basisFile.empty() || request.basis;
  auto make = [&](const ModelSource& s, const std::atomic<bool>* stop, const std::atomic<int>* cause) {
    SimulateRequest r = request;
    r.run.interrupt = stop;
    if (cause) r.run.interruptSignal = cause;
    auto job = std::make_unique<SimulateJob>(s, std::move(r));
    if (job->status() == JobStatus::Ready) job->run();
    return job;
  };
  if (basis) {
    AccurateRun<SimulateJob> out;
    out.diagnostics.emplace_back(Diagnostic::Kind::Error, "",
                                 "a reduced basis belongs to one mesh: the error against the converged model is "
                                 "estimated on the full model (run without the basis)");
    return out;
  }
  auto measure = [](const SimulateJob& job, const std::vector<int>& positions, std::string& text, double& scale) {
    const core::Trajectory& t = job.trajectory();
    const core::Model& m = job.model();
    MeshLevel l = positionsLevel(
        m, positions, t.completed ? t.states.size() : 0,
        [&](size_t s) -> const Eigen::VectorXd& { return t.states[s].x; }, m.x0, text, scale);
    if (!t.completed) l.reason = "stopped: " + t.stopReason;
    // The accuracy check's position estimate is relative to the model size: on the motion's scale.
    if (t.accuracy.checked)
      l.otherError = t.accuracy.positionEstimate * m.lengthScale() / l.scale;
    else
      l.otherUnknown =
          "the accuracy check did not run: " + (t.accuracy.note.empty() ? "no reason given" : t.accuracy.note);
    return l;
  };
  AccurateRun<SimulateJob> out = climb<SimulateJob>(std::move(source), watched, "simulate", make, measure);
  if (!out.job || out.ladder.estimate.levels.empty()) return out;
  fillBudget(out, a, "integration");
  if (out.job->options().relTol)
    out.budget.settings.emplace_back(
        "integrator tolerance",
        "RelTol " + text::significant(*out.job->options().relTol, 3) + (eps ? " (the accuracy target / 20)" : ""));
  return out;
}

AccurateRun<StaticJob> staticToAccuracy(ModelSource source, const StaticOptions& options, const AccuracyRequest& a) {
  const auto make = stoppableJob<StaticJob>(options);
  // Positions; with buckling factors asked, also their logarithms (relative differences) at the last
  // load step, the positions then divided by their scale.
  auto measure = [](const StaticJob& job, const std::vector<int>& positions, std::string& text, double& scale) {
    std::vector<const Eigen::VectorXd*> xs;
    for (const StaticStep& s : job.result().steps)
      if (s.loadStep >= 0) xs.push_back(&s.x);
    const core::Model& m = job.model();
    MeshLevel l = positionsLevel(
        m, positions, xs.size(), [&](size_t s) -> const Eigen::VectorXd& { return *xs[s]; }, m.x0, text, scale);
    const Eigen::VectorXd lambda = job.result().steps.empty() ? Eigen::VectorXd() : job.result().steps.back().buckling;
    if (l.ok && job.options().buckling > 0) {
      if (lambda.size() == 0 || !(lambda.array() > 0.0).all()) return l;  // none found: positions alone
      Eigen::VectorXd v(l.values.size() + lambda.size());
      v << l.values / l.scale, lambda.array().log().matrix();
      l.values = std::move(v);
      l.scale = 1.0;
      if (text.find("buckling") == std::string::npos) text += " and relative (the buckling load factors)";
    }
    return l;
  };
  AccurateRun<StaticJob> out = climb<StaticJob>(std::move(source), a, "static", make, measure);
  if (out.job && !out.ladder.estimate.levels.empty()) fillBudget(out, a, "");
  return out;
}

AccurateRun<ModesJob> modesToAccuracy(ModelSource source, const ModesOptions& options, const AccuracyRequest& a) {
  auto make = [&](const ModelSource& s, const std::atomic<bool>*, const std::atomic<int>*) {  // not stopped
    auto job = std::make_unique<ModesJob>(s, options);
    if (job->status() == JobStatus::Ready) job->run();
    return job;
  };
  // ln f of the lowest modes: their differences are relative.
  auto measure = [](const ModesJob& job, const std::vector<int>&, std::string& text, double&) {
    MeshLevel l;
    const Eigen::VectorXd& w = job.result().frequencies.omega;
    l.values = w.array().max(1e-300).log().matrix();
    l.ok = w.size() > 0 && (w.array() > 0.0).all();
    if (!l.ok) l.reason = "a mode without a positive frequency";
    text = "relative (the largest over the " + std::to_string(w.size()) + " lowest frequencies)";
    return l;
  };
  AccurateRun<ModesJob> out = climb<ModesJob>(std::move(source), a, "modes", make, measure, kFrequencyOrder);
  if (out.job && !out.ladder.estimate.levels.empty()) fillBudget(out, a, "");
  return out;
}

AccurateRun<SweepJob> sweepToAccuracy(ModelSource source, const SweepOptions& options, const AccuracyRequest& a) {
  const auto make = stoppableJob<SweepJob>(options);
  // ln f of every configuration's frequencies (ascending): their differences are relative.
  auto measure = [](const SweepJob& job, const std::vector<int>&, std::string& text, double&) {
    MeshLevel l;
    const std::vector<SweepPoint>& points = job.result().points;
    Eigen::Index n = 0;
    for (const SweepPoint& p : points) n += p.omegaSorted.size();
    l.values.resize(n);
    n = 0;
    l.ok = !points.empty() && job.result().completed;
    for (const SweepPoint& p : points)
      for (Eigen::Index i = 0; i < p.omegaSorted.size(); ++i) {
        l.ok = l.ok && p.omegaSorted[i] > 0.0;
        l.values[n++] = std::log(std::max(p.omegaSorted[i], 1e-300));
      }
    if (!l.ok) l.reason = "a configuration without positive frequencies, or the sweep stopped";
    text = "relative (the largest over the frequencies of the " + std::to_string(points.size()) + " configurations)";
    return l;
  };
  AccurateRun<SweepJob> out = climb<SweepJob>(std::move(source), a, "sweep", make, measure);
  if (out.job && !out.ladder.estimate.levels.empty()) fillBudget(out, a, "");
  return out;
}

}  // namespace flexmb::analysis
