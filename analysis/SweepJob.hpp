#pragma once
// The sweep job (Fig. 5 of the paper): one coordinate prescribed over a range, the equilibrium and
// eigenfrequencies at each configuration. The command line and Python call it.
#include "analysis/ModelJob.hpp"
#include "analysis/Sweep.hpp"

namespace flexmb::analysis {

class SweepJob : public ModelJob {
 public:
  // Checks the prescribed node and component, the number of configurations and the basis (read into
  // options.basis); options.nev is lowered to the degrees of freedom or the basis's columns.
  SweepJob(const ModelSource& source, SweepOptions options, const BasisInput& basis = {});
  const core::Model& model() const { return lastModel(); }
  const SweepOptions& options() const { return options_; }
  JobStatus run(const RunHooks& hooks = {});  // Completed, Stopped or Interrupted (the configurations reached are kept)
  const SweepResult& result() const { return result_; }

 private:
  bool checkPrescribed();
  SweepOptions options_;
  SweepResult result_;
};

}  // namespace flexmb::analysis
