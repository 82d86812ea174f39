#pragma once
// The transfer job (SPACAR's mode 9): statics over the load steps, then the state-space model between
// the inputs and outputs of the file's transfer block at the last one. The command line, Python and
// spacar() call it.
#include "analysis/ModelJob.hpp"
#include "analysis/Transfer.hpp"

namespace flexmb::analysis {

class TransferJob : public ModelJob {
 public:
  TransferJob(const ModelSource& source, TransferOptions options);
  const core::Model& model() const { return lastModel(); }
  const TransferOptions& options() const { return options_; }
  JobStatus run(
      const RunHooks& hooks = {});  // Completed, Stopped (the load steps reached, no state-space model) or Failed
  const TransferRun& result() const { return run_; }

 private:
  TransferOptions options_;
  TransferRun run_;
};

}  // namespace flexmb::analysis
