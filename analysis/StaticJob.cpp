#include "analysis/StaticJob.hpp"

#include "analysis/ModelCheck.hpp"

namespace flexmb::analysis {

namespace {
// Each load step is at least one Newton solve, one eigenproblem and a table row.
constexpr long kMaxLoadSteps = 100000;
}  // namespace

StaticJob::StaticJob(const ModelSource& source, StaticOptions options)
    : ModelJob(source), options_(std::move(options)) {
  if (!read() || !checkModel(model(), {false, true, false}, false)) return;
  const core::Model& m = model();
  const long steps = options_.loadSteps > 0 ? options_.loadSteps : std::max(1, m.settings.loadSteps);
  if (steps > kMaxLoadSteps) {
    refuse(std::to_string(steps) + " load steps are too many (each is a Newton solve, an eigenproblem and a table " +
               "row; the limit is " + std::to_string(kMaxLoadSteps) +
               "): lower ITERSTEP's second field or ask for fewer load steps",
           file_);
    diagnostics_.back().options = "load_steps";
    return;
  }
  options_.loadSteps = static_cast<int>(steps);
  if (const std::string missing = checkComplianceNodes(m, options_.complianceNodes); !missing.empty()) {
    refuse(missing, file_);
    diagnostics_.back().options = "compliance";
    return;
  }
  if (const auto massless = checkAssembly(m, true).massless; !massless.empty() && options_.nev > 0) {
    say(Diagnostic::Kind::Note,
        "no eigenfrequencies: " + std::to_string(massless.size()) +
            " degree(s) of freedom have no mass (give EM or XM), e.g. " + massless.front(),
        file_);
    options_.nev = 0;
  }
  options_.nev = std::min(options_.nev, m.numDofs());
}

JobStatus StaticJob::run(const RunHooks& hooks) {
  if (status_ != JobStatus::Ready) return status_;
  options_.onStep = hooks.progress;
  options_.interrupt = hooks.interrupt;
  options_.interruptSignal = hooks.interruptSignal;
  run_ = staticAnalysis(model(), options_);
  try {
    compliances_ = runCompliances(model(), run_, options_.complianceNodes);
  } catch (const std::exception& e) {
    say(Diagnostic::Kind::Warning, std::string("no compliances: ") + e.what(), file_);
    compliances_.clear();
  }
  return finish(run_.completed, run_.interrupted, "static analysis", run_.stopReason,
                "the load steps before it are kept");
}

}  // namespace flexmb::analysis
