#pragma once
// The static job (SPACAR's mode 10, and mode 3 on a file without TIMESTEP): the model read once and
// checked, the number of load steps and eigenfrequencies settled, then analysis::staticAnalysis.
// The command line, Python and spacar() call it.
#include "analysis/ModelJob.hpp"
#include "analysis/StaticDesign.hpp"
#include "analysis/Statics.hpp"

namespace flexmb::analysis {

class StaticJob : public ModelJob {
 public:
  // options.loadSteps 0: ITERSTEP's; options.nev is lowered to the degrees of freedom, and to 0 (with
  // a note) where some have no mass; options.complianceNodes must be nodes of the model (refused
  // otherwise).
  StaticJob(const ModelSource& source, StaticOptions options);
  const core::Model& model() const { return lastModel(); }
  const StaticOptions& options() const { return options_; }  // as settled
  JobStatus run(const RunHooks& hooks = {});  // Completed, Stopped or Interrupted (the load steps reached are kept)
  const StaticRun& result() const { return run_; }
  // The compliances of options.complianceNodes at every step reached (empty without them).
  const StaticCompliances& compliances() const { return compliances_; }

 private:
  StaticOptions options_;
  StaticRun run_;
  StaticCompliances compliances_;
};

}  // namespace flexmb::analysis
