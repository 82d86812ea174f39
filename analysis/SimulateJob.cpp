#include "analysis/SimulateJob.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/BasisForTarget.hpp"
#include "analysis/InverseDynamics.hpp"
#include "analysis/OperatorPolicy.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/RunNotes.hpp"
#include "analysis/RunSize.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/OperatorFile.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
std::string withoutFinalNewline(std::string s) {
  while (!s.empty() && s.back() == '\n') s.pop_back();
  return s;
}
}  // namespace

SimulateJob::SimulateJob(const ModelSource& source, SimulateRequest request)
    : ModelJob(source), request_(std::move(request)) {
  if (!read()) return;
  runs_ = stagesThatRun(*stages_);
  if (request_.damping.any() && !addDamping()) return;
  prepare();
}

bool SimulateJob::addDamping() {
  const DampingOptions& d = request_.damping;
  std::string why = dampingRefusal(d);
  if (why.empty()) why = timeRunDampingRefusal(d);
  if (why.empty() && (request_.basis || !request_.basisFile.empty()))
    why =
        "added damping applies to full-model runs (a reduction basis and its operators are of the model as the "
        "file gives it): give EDAMP in the file and reduce again";
  if (!why.empty()) return refuse(why);
  auto damped = std::make_shared<std::vector<io::AnalysisStage>>(*stages_);
  for (io::AnalysisStage& stage : *damped) addStiffnessProportionalDamping(stage.model, d.beta);
  stages_ = damped;
  runs_ = stagesThatRun(*stages_);
  settings_.emplace_back("added damping", dampingText(d) + " (beta K as element damping: EDAMP + beta ESTIFF)");
  say(Diagnostic::Kind::Note, "damping added to the model's EDAMP: Rayleigh beta " + text::shortest(d.beta) +
                                  " s as element damping (EDAMP + beta ESTIFF on every element with stiffness)");
  return true;
}

void SimulateJob::prepare() {
  const core::Model& last = model();
  if (!checkModel(last, {true, true, true}, true)) return;
  const SimulationOptions& opt = request_.run;
  // No TIMESTEP: the defaults, said once, with what the options override.
  if (!last.settings.timestepGiven && (!opt.tEnd || !opt.intervals)) {
    std::ostringstream s;
    s << file_ << " has no TIMESTEP: ";
    if (!opt.tEnd)
      s << "the run goes from " << text::shortest(last.settings.t0) << " to " << text::shortest(last.settings.tEnd)
        << " s";
    if (!opt.tEnd && !opt.intervals) s << " in ";
    if (!opt.intervals) s << last.settings.outputIntervals << " output intervals";
    s << " (the defaults; give TIMESTEP, or the end time and the output intervals as options)";
    say(Diagnostic::Kind::Note, s.str());
  }
  if (runs_.size() > 1) say(Diagnostic::Kind::Note, std::to_string(runs_.size()) + " analysis blocks, run in sequence");
  driven_ = isDrivenRigidMechanism(last);
  if (driven_) {
    if (request_.basis || !request_.basisFile.empty())
      refuse(file_ + " is a driven rigid mechanism (no degrees of freedom): there is no reduced model");
    return;
  }
  prepareBasis();
  if (status_ != JobStatus::Ready) return;
  chooseDefaultIntegrator();
  if (request_.fullKinematics && !request_.run.basis)
    say(Diagnostic::Kind::Note, "full kinematics applies to reduced runs (a basis): the full model has no other");
  const RunSizeCheck size = checkRunSize(last, request_.run);
  if (!size.warning.empty()) say(Diagnostic::Kind::Warning, size.warning);
  if (!size.refusal.empty()) {
    refuse(size.refusal);
    diagnostics_.back().options = size.options;
  }
}

void SimulateJob::prepareBasis() {
  const core::Model& last = model();
  SimulationOptions& opt = request_.run;
  if (request_.basisFile == "auto") {
    operatorNote_ = "Eq. 19";
    // The run (reduced or full) answers to the target with its integration error too: without
    // --reltol its tolerance is chosen with the target (issue 49 item 4).
    if (!opt.relTol && std::isfinite(request_.target)) {
      toleranceFromTarget_ = true;
      opt.relTol = relTolForTarget(request_.target, last.settings.relTol);
      // AbsTol at most a tenth of RelTol on the model's size: the file's 1e-6 bounded the
      // 20-element guidance at 1e-4 to 1.0e-4 of its motion at RelTol 5e-6. Scaled with RelTol
      // from the file's, as it was, it cost the larger targets: that guidance at 1e-3 took 0.19 s
      // at AbsTol 5e-8 where 1e-6 takes 0.12 s, both within 1e-3 (3.2e-4). Where the motion is
      // small against the model size (the coarse pivot's 2 mm) the accuracy check measures what
      // AbsTol leaves and a rerun tightens both (a candidate's, or rerunFullAtTighterTolerance).
      if (!opt.absTol && last.lengthScale() > 0.0)
        opt.absTol = std::min(last.settings.absTol, 0.1 * *opt.relTol * last.lengthScale());
      if (*opt.relTol < last.settings.relTol)
        settings_.emplace_back("tolerance for the target",
                               "RelTol " + text::shortest(*opt.relTol) + " = target / 20, AbsTol " +
                                   text::significant(opt.absTol.value_or(last.settings.absTol), 3) +
                                   " (no --reltol; the file's " + text::shortest(last.settings.relTol) + ", " +
                                   text::shortest(last.settings.absTol) +
                                   "): the integration error leaves the target to the "
                                   "reduction");
    }
    useSharedReduction();
    return;
  }
  if (!request_.basisFile.empty()) {
    try {
      opt.basis = io::readBasisFor(request_.basisFile, last.numDofs());
    } catch (const std::exception& e) {
      refuse(e.what());
      return;
    }
    const OperatorChoice choice = chooseOperators(last, file_, *opt.basis, request_.basisFile, request_.fullKinematics);
    if (!choice.refusal.empty()) {
      refuse(choice.refusal);
      return;
    }
    opt.operators = choice.operators;
    operatorNote_ = choice.note;
    // Operators beside the basis that do not serve this model: the run goes on with Eq. 19, said up front.
    if (!choice.operators && choice.note.find("does not fit") != std::string::npos)
      say(Diagnostic::Kind::Note, choice.note, file_);
  } else if (request_.basis) {
    if (request_.basis->rows() != last.numDofs()) {
      refuse("the basis has " + std::to_string(request_.basis->rows()) + " rows; the model has " +
             std::to_string(last.numDofs()) + " degrees of freedom");
      return;
    }
    opt.basis = request_.basis;
    if (!request_.fullKinematics) opt.operators = request_.operators;
    operatorNote_ = "Eq. 19";
  }
  if (request_.trackedOutputs) {
    if (!opt.operators || opt.operators->outputs.empty()) {
      refuse("tracked outputs: " + (opt.operators ? io::operatorPathFor(request_.basisFile) +
                                                        " tracks no output (reduce with tracked nodes or elements "
                                                        "builds them)"
                                                  : "the run uses " + operatorNote_));
      return;
    }
    opt.trackedOutputs = true;
  }
}

// The integrator a user who asked for none gets: auto (galpha where ode45 would be bound by stability,
// SPACAR's ode45 elsewhere, within the tolerance of each other), on the full model and on reduced
// ones alike (galpha's iteration matrix of a reduced run comes from its operators where they hold).
void SimulateJob::chooseDefaultIntegrator() {
  SimulationOptions& opt = request_.run;
  if (!request_.defaultIntegrator) return;
  settings_.emplace_back("integrator choice", std::string(integratorName(opt.integrator)) +
                                                  ", the default (--integrator ode45: MATLAB's ode45 step by step)");
}

void SimulateJob::chooseBasisForTarget() {
  TargetOptions to;
  to.target = request_.target;
  to.run = request_.run;
  to.keepChosenRun = runs_.size() == 1;  // a candidate runs the last stage alone
  to.sayCandidates = request_.run.progress;
  to.withIntegration = request_.run.accuracyCheck;
  if (request_.autoBasis) to.basis = *request_.autoBasis;
  TargetResult tr;
  try {
    // One run (not shared): where no basis can pay, the full model at once (issue 49 item 4).
    const std::string cannotPay = request_.shared ? std::string() : reductionCannotPay(model(), request_.run);
    if (!cannotPay.empty()) {
      tr.full = true;
      tr.note = cannotPay;
    } else {
      tr = basisForTarget(model(), to);
    }
  } catch (const std::exception& e) {
    say(Diagnostic::Kind::Error, std::string("no basis could be chosen: ") + e.what());
    status_ = JobStatus::Failed;
    return;
  }
  std::ostringstream tried;
  for (const auto& c : tr.tried)
    tried << (tried.tellp() > 0 ? ", " : "") << c.vectors << " vectors: "
          << (!c.completed ? std::string("stopped")
              : c.estimate.estimated
                  ? text::significant(c.estimate.estimate, 2) +
                        (std::isnan(c.integration) ? std::string()
                                                   : " + integration " + text::significant(c.integration, 2))
                  : std::string("not estimated"));
  if (tr.relTol) {  // a candidate's integration error asked for a tighter tolerance: the run's
    const double before = request_.run.relTol.value_or(model().settings.relTol);
    request_.run.relTol = tr.relTol;
    request_.run.absTol = tr.absTol;
    std::erase_if(settings_, [](const auto& s) { return s.first == "tolerance for the target"; });
    settings_.emplace_back("tolerance for the target",
                           "RelTol " + text::significant(*tr.relTol, 3) + ", AbsTol " +
                               text::significant(tr.absTol.value_or(0.0), 3) + " (a candidate's integration error at " +
                               text::significant(before, 3) + " left too little of the target to its reduction error)");
  }
  const std::string how = "target " + text::shortest(request_.target) + ", " + to.basis.method + "; " +
                          (tr.tried.empty() ? std::string("no candidate run") : "tried " + tried.str()) +
                          "; choosing took " + text::shortest(std::round(tr.seconds * 1e4) / 1e4) + " s";
  if (!tr.full && !tr.interrupted) chooseTargetOperators(tr);
  const std::string dynamics = tr.full || tr.interrupted ? "" : "; reduced dynamics: " + operatorNote_;
  settings_.emplace_back("basis",
                         tr.full ? "auto: the full model (" + tr.note + "; " + how + ")"
                                 : "auto: " + std::to_string(tr.basis.V.cols()) + " columns (" + how + ")" + dynamics);
  if (tr.interrupted) {  // Ctrl-C while choosing: what was found is said; there is no run
    std::string best = "no candidate completed";
    if (tr.bestTried >= 0) {
      const TargetCandidate& c = tr.tried[static_cast<size_t>(tr.bestTried)];
      best = "the best so far: " + std::to_string(c.vectors) + " vectors, estimate " +
             text::significant(c.estimate.estimate, 2) + (tr.met ? " (meets the target)" : " (above the target)");
    }
    trajectory_.completed = false;
    trajectory_.stopReason = "interrupted while choosing the basis (" + how + "); " + best;
    say(Diagnostic::Kind::Error, trajectory_.stopReason);
    interrupted_ = true;
    status_ = JobStatus::Interrupted;
    wall_ = secondsSoFar();
    return;
  }
  say(Diagnostic::Kind::Result, "basis auto: " + (tr.full ? tr.note : std::to_string(tr.basis.V.cols()) + " columns") +
                                    " (" + how + ")" + dynamics);
  if (tr.full) {
    targetNote_ = tr.note;
    return;
  }
  request_.run.basis = tr.basis.V;
  if (!request_.fullKinematics && !tr.run) request_.run.operators = operators_;
  if (!tr.run) return;
  // The chosen candidate ran exactly the run asked for: it is the run, with the checks every run gets.
  trajectory_ = std::move(*tr.run);
  reused_ = true;
  settings_.emplace_back("basis auto run", "the chosen candidate's run, integrated once");
  const SimulationOptions& opt = request_.run;
  LapClock clock;
  // The scan's checks of this run are the run's (the estimate it decided on is the one printed).
  const TargetCandidate* chosen = tr.chosenTried >= 0 ? &tr.tried[static_cast<size_t>(tr.chosenTried)] : nullptr;
  if (opt.accuracyCheck && chosen && chosen->accuracy.checked)
    trajectory_.accuracy = chosen->accuracy;
  else if (opt.accuracyCheck && tr.runAccuracy.recorded)
    trajectory_.accuracy = checkAccuracy(model(), opt, tr.runAccuracy.t0, tr.runAccuracy.tEnd, tr.runAccuracy.windows,
                                         tr.runAccuracy.galphaFrom);
  trajectory_.seconds.accuracyCheck = clock.lap();
  if (opt.reductionEstimate && chosen && chosen->estimate.estimated)
    trajectory_.reduction = chosen->estimate;
  else if (opt.reductionEstimate && !trajectory_.states.empty())
    trajectory_.reduction = estimateReductionError(model(), *opt.basis, trajectory_);
  trajectory_.seconds.reductionEstimate = clock.lap();
  // The candidate's run is the run: its integration and checks are said as the run's, not as choosing.
  choosing_ -=
      trajectory_.seconds.integration + trajectory_.seconds.accuracyCheck + trajectory_.seconds.reductionEstimate;
}

// Reduced operators for the chosen basis (analysis/TargetOperators.hpp): trained where they pay for
// what is still to be integrated on it, by this run (nothing where the chosen candidate's run is the
// run) and the runs that share it; the shared reduction then holds basis and operators for them.
void SimulateJob::chooseTargetOperators(const TargetResult& tr) {
  const int k = static_cast<int>(tr.basis.V.cols() - static_cast<Eigen::Index>(tr.basis.large.size()));
  const TargetCandidate* chosen = nullptr;
  for (const TargetCandidate& c : tr.tried)
    if (c.vectors == k && c.completed) chosen = &c;
  // The runs still to integrate on the basis: this one unless the candidate's run is it, and those
  // that share it.
  const bool shared = static_cast<bool>(request_.shared);
  const int runs = shared ? std::max(1, request_.shared->runs) : 1;
  const long evaluations = chosen ? chosen->fevals * (runs - (tr.run ? 1 : 0)) : 0;
  const double perEvaluation =
      chosen && chosen->fevals > 0 ? chosen->integrationSeconds / static_cast<double>(chosen->fevals) : 0.0;
  const TargetOperators t = operatorsForTarget(model(), tr.basis.V, evaluations, perEvaluation, runs);
  operators_ = t.operators;
  operatorNote_ = t.note;
  trainingSeconds_ = t.seconds;
  if (tr.run && t.operators)  // trained for the runs that share the basis; this one is the candidate's (Eq. 19)
    operatorNote_ = "Eq. 19 (the chosen candidate's run is this run); " + t.note;
  if (shared) *request_.shared = {reductionKey(model(), request_.target), tr.basis.V, t.operators, t.note, runs};
}

bool SimulateJob::useSharedReduction() {
  const std::shared_ptr<SharedReduction>& s = request_.shared;
  if (!s || s->key.empty() || s->V.rows() != model().numDofs() || s->key != reductionKey(model(), request_.target))
    return false;
  request_.run.basis = s->V;
  if (!request_.fullKinematics) request_.run.operators = s->operators;
  operatorNote_ = s->operators ? s->note : s->note.substr(0, s->note.find(" ("));
  sharedUsed_ = true;
  const std::string text = std::to_string(s->V.cols()) +
                           " columns, shared: chosen for the target on a model with the same operator checksum and "
                           "target (" +
                           s->key + "), kept where this run's estimate meets the target";
  settings_.emplace_back("basis", "auto: " + text);
  say(Diagnostic::Kind::Result, "basis auto: " + text);
  return true;
}

bool SimulateJob::sharedReductionMissed() {
  const core::ReductionEstimate& e = trajectory_.reduction;
  if (trajectory_.completed && e.estimated && e.estimate <= request_.target) return false;
  say(Diagnostic::Kind::Note, "basis auto: the shared basis " +
                                  (!trajectory_.completed ? "run stopped (" + trajectory_.stopReason + ")"
                                   : e.estimated          ? "estimates " + text::significant(e.estimate, 2)
                                                          : std::string("has no estimate")) +
                                  ", target " + text::shortest(request_.target) + ": a basis is chosen for this model");
  request_.run.basis.reset();
  request_.run.operators.reset();
  std::erase_if(settings_, [](const auto& s) { return s.first == "basis"; });  // the scan's replaces it
  operatorNote_ = "Eq. 19";
  sharedUsed_ = false;
  trajectory_ = core::Trajectory();
  interrupted_ = false;
  return true;
}

// What the target is measured against (issue 49 item 4): the reduction estimate plus the accuracy
// check's position estimate, both relative to the motion (the model size where the motion is small).
void SimulateJob::sayTargetEstimate() {
  const core::Trajectory& t = trajectory_;
  const bool reduced = request_.run.basis.has_value();
  double scale = t.reduction.scale;
  std::string scaleText = t.reduction.scaleText;
  if (!reduced || !t.reduction.estimated) {
    const ErrorScale s = errorScaleOf(model(), motionScale(model(), t));
    scale = s.value;
    scaleText = s.text;
  }
  if (reduced && !t.reduction.estimated) return;  // the run says why it has no estimate
  const double integration = integrationOnScale(model(), t.accuracy, scale);
  const double reduction = reduced ? t.reduction.estimate : 0.0;
  const double total = reduction + (std::isnan(integration) ? 0.0 : integration);
  std::string text = text::significant(total, 2) + " " + scaleText + " (";
  if (reduced) text += "reduction " + text::significant(reduction, 2) + " + ";
  text += std::isnan(integration) ? std::string("integration not checked")
                                  : "integration " + text::significant(integration, 2) +
                                        ", the accuracy check's positions on the same scale";
  text += "); target " + text::shortest(request_.target) + ": " +
          (std::isnan(integration)    ? "not known"
           : total <= request_.target ? "met"
                                      : "NOT met");
  settings_.emplace_back("basis auto estimate", text);
  say(Diagnostic::Kind::Result, "basis auto estimate: " + text);
}

// The full model under basis auto answers to the target alone (no reduction error). Where its accuracy
// check puts the integration error above the target at the tolerance chosen for it (RelTol target /
// 20: the coarse pivot's 2.1 mm motion in a 0.14 m model was 0.018 of the motion off at 1e-2), it runs
// once more at the tolerance the measured error asks for (tighterToleranceFactor, as a candidate's in
// BasisForTarget), said, and that run is the answer. A
// rerun that does not complete (Ctrl-C, a failed step) leaves the first run's results, said.
void SimulateJob::rerunFullAtTighterTolerance() {
  SimulationOptions& opt = request_.run;
  if (request_.basisFile != "auto" || opt.basis || !toleranceFromTarget_ || interrupted_ || !trajectory_.completed ||
      !std::isfinite(request_.target) || !opt.relTol)
    return;
  const ErrorScale scale = errorScaleOf(model(), motionScale(model(), trajectory_));
  const double integration = integrationOnScale(model(), trajectory_.accuracy, scale.value);
  if (!(integration > request_.target) || !std::isfinite(integration)) return;
  const double factor = tighterToleranceFactor(request_.target, 0.0, integration);
  const std::optional<double> relTol = opt.relTol, absTol = opt.absTol;
  const double first = trajectory_.seconds.integration + trajectory_.seconds.accuracyCheck;
  opt.relTol = *relTol * factor;
  opt.absTol = absTol.value_or(model().settings.absTol) * factor;
  const std::string text = "RelTol " + text::significant(*opt.relTol, 3) + ", AbsTol " +
                           text::significant(*opt.absTol, 3) + " (the full model at RelTol " +
                           text::significant(*relTol, 3) + " was " + text::significant(integration, 2) + " " +
                           scale.text + " off by its accuracy check, target " + text::shortest(request_.target) +
                           "; that run took " + text::significant(first, 2) + " s and is replaced)";
  say(Diagnostic::Kind::Note, "basis auto: " + text);
  core::Trajectory firstRun = std::move(trajectory_);
  trajectory_ = simulateStages(runs_, opt, &interrupted_);
  if (!trajectory_.completed) {
    const std::string stopped = "the rerun at RelTol " + text::significant(*opt.relTol, 3) + " stopped (" +
                                trajectory_.stopReason + "): the results are the first run's, at RelTol " +
                                text::significant(*relTol, 3);
    say(Diagnostic::Kind::Note, "basis auto: " + stopped);
    settings_.emplace_back("rerun for the target", stopped);
    trajectory_ = std::move(firstRun);
    opt.relTol = relTol;
    opt.absTol = absTol;
    return;
  }
  choosing_ += first;  // said apart from this run's integration and check
  std::erase_if(settings_, [](const auto& s) { return s.first == "tolerance for the target"; });
  settings_.emplace_back("tolerance for the target", text);
}

namespace {
// "reading and checks 0.004 s, integration 0.055 s, ..." (the parts that took time).
std::string describeParts(const std::vector<std::pair<const char*, double>>& parts) {
  std::ostringstream s;
  for (const auto& [name, seconds] : parts)
    if (seconds >= 1e-4) s << (s.tellp() > 0 ? ", " : "") << name << " " << text::significant(seconds, 2) << " s";
  return s.str();
}
}  // namespace

void SimulateJob::runDriven() {
  InverseDynamicsOptions o;
  o.tEnd = request_.run.tEnd;
  o.intervals = request_.run.intervals;
  o.interrupt = request_.run.interrupt;
  o.interruptSignal = request_.run.interruptSignal;
  InverseDynamicsRun all = inverseDynamicsStages(runs_, o);
  trajectory_ = std::move(all.trajectory);
  fxt_ = std::move(all.fxt);
  interrupted_ = all.interrupted;
  say(Diagnostic::Kind::Result, "driven rigid mechanism (no degrees of freedom): kinematics and inverse dynamics at " +
                                    std::to_string(trajectory_.time.size()) + " output times, no integration");
  if (!trajectory_.completed) say(Diagnostic::Kind::Error, "stopped early: " + trajectory_.stopReason);
}

JobStatus SimulateJob::run() {
  if (status_ != JobStatus::Ready) return status_;
  const double before = secondsSoFar();  // reading the model, the checks, a basis file
  if (driven_) {
    runDriven();
    wall_ = secondsSoFar();
  } else {
    if (request_.basisFile == "auto" && !sharedUsed_) {
      LapClock choosing;
      chooseBasisForTarget();
      choosing_ += choosing.total();
      if (status_ != JobStatus::Ready) return status_;
    }
    const SimulationOptions& opt = request_.run;
    try {
      if (!reused_) trajectory_ = simulateStages(runs_, opt, &interrupted_);
      if (sharedUsed_ && !interrupted_ && sharedReductionMissed()) {  // the shared basis misses here: choose anew
        LapClock choosing;
        chooseBasisForTarget();
        choosing_ += choosing.total();
        if (status_ != JobStatus::Ready) return status_;
        if (!reused_) trajectory_ = simulateStages(runs_, opt, &interrupted_);
      }
      rerunFullAtTighterTolerance();
    } catch (const std::exception& e) {
      say(Diagnostic::Kind::Error, std::string("simulation could not start: ") + e.what());
      status_ = JobStatus::Failed;
      return status_;
    }
    // From the making of the job: reading and choosing a basis for a target included.
    wall_ = secondsSoFar();
    const core::Trajectory::Seconds& sec = trajectory_.seconds;
    timeParts_ = describeParts({{"reading and checks", before},
                                {"choosing the basis", choosing_ - trainingSeconds_},
                                {"training reduced operators", trainingSeconds_},
                                {"integration", sec.integration},
                                {"accuracy check", sec.accuracyCheck},
                                {"reduction estimate", sec.reductionEstimate}});
    settings_.emplace_back("wall time", text::significant(wall_, 3) + " s before writing (" + timeParts_ + ")");
    say(Diagnostic::Kind::Result, withoutFinalNewline(formatStatistics(trajectory_, opt.integrator)));
    diagnostics_.back().topic = "statistics";
    if (opt.integrator == Integrator::Auto && !trajectory_.integrator.empty()) {  // which integrator ran
      std::ostringstream ran;
      if (trajectory_.implicitFromStart)
        ran << "galpha from the start";
      else if (!std::isnan(trajectory_.switchedAt))
        ran << "ode45 until t = " << trajectory_.switchedAt << " s, then galpha";
      else if (!model().userStressFunction.empty())
        ran << "ode45 throughout (galpha's iteration matrix would lack the derivatives of the user's forces, "
            << model().userStressFunction << ")";
      else
        ran << "ode45 throughout (its step was never bound by stability)";
      settings_.emplace_back("integrator ran", ran.str());
    }
    if (opt.basis) {  // which reduced dynamics ran
      const std::string text =
          opt.operators ? describeOperatorUse(trajectory_.operators, *opt.operators) : operatorNote_;
      say(Diagnostic::Kind::Result, "reduced dynamics: " + text);
      settings_.emplace_back("reduced dynamics", text);
    }
    if (!trajectory_.tracked.empty()) {
      const std::string text = describeTrackedOutputs(trajectory_.tracked, *opt.operators);
      say(Diagnostic::Kind::Result, "tracked outputs: " + text);
      settings_.emplace_back("tracked outputs", text);
    }
    std::ostringstream w;
    w << "wall time " << wall_ << " s, " << trajectory_.time.size() << " output times (" << timeParts_ << ")";
    say(Diagnostic::Kind::Result, w.str());
    diagnostics_.back().topic = "wall time";
    if (request_.basisFile == "auto" && trajectory_.completed) sayTargetEstimate();
    for (const RunNote& n : runNotes(model(), opt, trajectory_, request_.target)) {
      if (!n.setting.empty()) settings_.emplace_back(n.setting, n.value);
      switch (n.kind) {
        case RunNote::Kind::Result:
          say(Diagnostic::Kind::Result, n.text);
          break;
        case RunNote::Kind::Note:
          say(Diagnostic::Kind::Note, n.text);
          break;
        case RunNote::Kind::Warning:
          say(Diagnostic::Kind::Warning, n.text);
          diagnostics_.back().options = n.options;
          break;
        case RunNote::Kind::Stopped:
          say(Diagnostic::Kind::Error, n.text);
          break;
      }
    }
  }
  status_ = interrupted_ ? JobStatus::Interrupted : trajectory_.completed ? JobStatus::Completed : JobStatus::Stopped;
  return status_;
}

}  // namespace flexmb::analysis
