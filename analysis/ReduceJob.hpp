#pragma once
// The reduce job: a basis V (Eq. 17-20) of the kind asked, or the smallest of that kind meeting a
// reduction error target, then its reduced operators (analysis/ReducedOperators.md). The command
// line and Python call it; each writes the result with analysis::writeReduction.
#include <limits>
#include <vector>

#include "analysis/BasisForTarget.hpp"
#include "analysis/ModelJob.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionFiles.hpp"

namespace flexmb::analysis {

struct ReduceOptions {
  ReductionOptions basis;                                    // method, modes, path, identity columns ...
  double target = std::numeric_limits<double>::quiet_NaN();  // choose the size for this reduction error
  bool operators = true;                                     // train the reduced operators beside the basis
  std::vector<int> trackNodes, trackElements;                // labels whose outputs the operators also fit
};

class ReduceJob : public ModelJob {
 public:
  // Checks the method, the number of configurations, the identity columns and the tracked labels.
  ReduceJob(const ModelSource& source, ReduceOptions options);
  const core::Model& model() const { return lastModel(); }
  const ReduceOptions& options() const { return options_; }
  // The basis (progress: per configuration of an SVD-modal path). Completed, InputError (options
  // the analysis refuses) or Failed.
  JobStatus run(const RunHooks& hooks = {});
  // The operators for the basis (after run; none for a target no basis meets). A failure to train
  // them is a warning: the basis stands.
  void trainOperators();
  bool hasTarget() const { return !std::isnan(options_.target); }
  const TargetResult& target() const { return target_; }  // with a target: the candidates tried
  bool full() const { return target_.full; }              // with a target: no basis meets it
  const ReductionResult& basis() const { return basis_; }
  const BasisOperators& operators() const { return operators_; }

 private:
  ReduceOptions options_;
  std::vector<core::OperatorOutput> tracked_;
  TargetResult target_;
  ReductionResult basis_;
  BasisOperators operators_;
};

}  // namespace flexmb::analysis
