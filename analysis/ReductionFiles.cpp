#include "analysis/ReductionFiles.hpp"

#include "analysis/OperatorPolicy.hpp"
#include "analysis/OperatorTraining.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/OperatorFile.hpp"

namespace flexmb::analysis {

BasisOperators operatorsBesideBasis(const core::Model& model, const Eigen::MatrixXd& V, bool asked,
                                    const std::string& notAsked, const std::vector<core::OperatorOutput>& outputs) {
  BasisOperators b;
  if (!asked) {
    b.note = "not built " + notAsked;
  } else if (const std::string why = operatorsUnsupported(model); !why.empty()) {
    b.note = "not built: " + why;
  } else {
    try {
      OperatorTrainingOptions o;
      o.outputs = outputs;
      auto ops = std::make_shared<const core::ReducedOperators>(trainOperators(model, V, o));
      // Operators a run would carry beyond a tenth of the reduction error are not written: Eq. 19
      // (the full kinematics through V) serves the basis instead, and the note says why.
      if (const std::string miss = operatorsMissTheirTarget(*ops); !miss.empty()) {
        b.note = "not built: " + miss;
      } else {
        b.operators = std::move(ops);
        b.note = describeOperators(*b.operators);
      }
    } catch (const std::exception& e) {
      b.note = std::string("not built: ") + e.what();
      b.failed = true;
    }
  }
  return b;
}

void writeReduction(io::OutputSet& files, const std::string& path, const std::string& modelFile,
                    const ReductionResult& basis, const BasisOperators& ops) {
  const std::string opsPath = io::operatorPathFor(path);
  files.setting("reduced operators", ops.operators ? opsPath + ": " + ops.note : ops.note);
  io::writeBasis(files.temporaryPath(path), basis.V,
                 {basis.method, modelFile, basis.parameters, basis.large, basis.scaledSingularValues});
  if (ops.operators) io::writeOperators(files.temporaryPath(opsPath), *ops.operators);
  std::string kept;
  for (int i : basis.large) {  // piecewise: GCC 12's -Wrestrict false positive on s += a + b
    if (!kept.empty()) kept += ',';
    kept += std::to_string(i + 1);
  }
  files.setting("identity columns (--large, 1-based)", kept.empty() ? std::string("none") : kept);
}

}  // namespace flexmb::analysis
