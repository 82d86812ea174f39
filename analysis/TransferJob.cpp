#include "analysis/TransferJob.hpp"

#include <algorithm>

namespace flexmb::analysis {

TransferJob::TransferJob(const ModelSource& source, TransferOptions options)
    : ModelJob(source), options_(std::move(options)) {
  if (!read() || !checkModel(model(), {true, true, false}, false)) return;
  if (model().transferInputs.empty() || model().transferOutputs.empty()) {
    refuse(
        "no transfer block: transfer functions need at least one input (INPUTF, INX) and one output (OUTX, "
        "OUTXP, OUTF) in a block after the dynamic block's END HALT (io/dat-language.md)",
        file_);
    return;
  }
  if (const std::string why = dampingRefusal(options_.damping); !why.empty()) {
    refuse(why);
    return;
  }
  options_.nev = std::min(std::max(options_.nev, 0), model().numDofs());
}

JobStatus TransferJob::run(const RunHooks& hooks) {
  if (status_ != JobStatus::Ready) return status_;
  options_.onStep = hooks.progress;
  try {
    run_ = transferAnalysis(model(), options_);
  } catch (const std::exception& e) {
    fail(e.what());
    return status_;
  }
  return finish(run_.completed, false, "transfer", run_.stopReason,
                "the load steps reached are kept; no state-space model");
}

}  // namespace flexmb::analysis
