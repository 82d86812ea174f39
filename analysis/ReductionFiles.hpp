#pragma once
// reduce's products for every front end (the command line, Python): the reduced operators beside a
// basis, and the files that hold both (the basis CSV, <basis>.operators, the manifest's settings).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "analysis/Reduction.hpp"
#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"
#include "io/formats/OutputFile.hpp"

namespace flexmb::analysis {

struct BasisOperators {
  std::shared_ptr<const core::ReducedOperators> operators;  // null: none (note says why)
  std::string note;                                         // describeOperators, or "not built: why"
  bool failed = false;                                      // the training failed: a warning, the basis stands
};

// The operators for V unless not asked (notAsked: the note then, e.g. "(--no-operators)"), or the
// model is one they do not support, or their training fails; with the tracked outputs (reduce --track).
BasisOperators operatorsBesideBasis(const core::Model& model, const Eigen::MatrixXd& V, bool asked,
                                    const std::string& notAsked, const std::vector<core::OperatorOutput>& outputs = {});

// The basis file at path (its header names modelFile), the operators beside it
// (io::operatorPathFor) and the manifest's settings; the caller commits the set.
void writeReduction(io::OutputSet& files, const std::string& path, const std::string& modelFile,
                    const ReductionResult& basis, const BasisOperators& ops);

}  // namespace flexmb::analysis
