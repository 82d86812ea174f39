#include "analysis/ReduceJob.hpp"

#include <cmath>
#include <stdexcept>

#include "analysis/OperatorTraining.hpp"

namespace flexmb::analysis {

namespace {
constexpr int kMaxConfigurations = 100000;
}

ReduceJob::ReduceJob(const ModelSource& source, ReduceOptions options)
    : ModelJob(source), options_(std::move(options)) {
  if (!read() || !checkModel(model(), {true, true, false}, false)) return;
  const ReductionOptions& b = options_.basis;
  if (b.method != "modal" && b.method != "svd-modal") {
    refuse("the method must be modal or svd-modal, not '" + b.method + "'");
    diagnostics_.back().options = "method";
    return;
  }
  if (b.configs > kMaxConfigurations) {
    refuse(std::to_string(b.configs) + " configurations are too many (limit " + std::to_string(kMaxConfigurations) +
           ")");
    diagnostics_.back().options = "configs";
    return;
  }
  if (b.large)
    for (int i : *b.large)
      if (i < 0 || i >= model().numDofs()) {
        refuse("identity column " + std::to_string(i + 1) + " is out of range (the model has " +
               std::to_string(model().numDofs()) + " degrees of freedom, 1 to " + std::to_string(model().numDofs()) +
               ")");
        diagnostics_.back().options = "large";
        return;
      }
  if (!options_.operators && (!options_.trackNodes.empty() || !options_.trackElements.empty())) {
    refuse("tracked nodes and elements are fitted into the reduced operators: they need the operators");
    diagnostics_.back().options = "track,operators";
    return;
  }
  try {
    tracked_ = trackedQuantities(model(), options_.trackNodes, options_.trackElements);
  } catch (const std::invalid_argument& e) {
    refuse(std::string("tracked outputs: ") + e.what());
    diagnostics_.back().options = "track";
  }
}

JobStatus ReduceJob::run(const RunHooks& hooks) {
  if (status_ != JobStatus::Ready) return status_;
  ReductionOptions b = options_.basis;
  b.onConfig = hooks.progress;
  try {
    if (hasTarget()) {
      TargetOptions to;
      to.target = options_.target;
      to.basis = b;
      to.run.interrupt = hooks.interrupt;
      to.run.interruptSignal = hooks.interruptSignal;
      to.sayCandidates = static_cast<bool>(hooks.progress);
      target_ = basisForTarget(model(), to);
      if (!target_.full) basis_ = target_.basis;
      if (target_.interrupted) {  // the best so far is the basis (written by the front end), said
        say(Diagnostic::Kind::Error,
            "reduce: " + target_.note +
                (target_.bestTried >= 0 ? "; the basis is the best so far" : "; no candidate completed: no basis"));
        return status_ = JobStatus::Interrupted;
      }
    } else {
      basis_ = buildBasis(model(), b);
    }
  } catch (const std::invalid_argument& e) {
    refuse(e.what());
    return status_;
  } catch (const std::exception& e) {
    fail(e.what());
    return status_;
  }
  return status_ = JobStatus::Completed;
}

void ReduceJob::trainOperators() {
  if (status_ != JobStatus::Completed) return;
  if (full()) {
    operators_.note = "not built: no basis";
    return;
  }
  operators_ = operatorsBesideBasis(model(), basis_.V, options_.operators, "(not asked)", tracked_);
  if (operators_.failed) say(Diagnostic::Kind::Warning, "reduced operators " + operators_.note + "; the basis stands");
  if (!tracked_.empty() && !operators_.operators)
    say(Diagnostic::Kind::Warning,
        "no reduced operators, so no tracked outputs: a run asking for tracked outputs will refuse this basis");
}

}  // namespace flexmb::analysis
