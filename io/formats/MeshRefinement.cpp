#include "io/formats/MeshRefinement.hpp"

#include <stdexcept>

#include "core/model/Refinement.hpp"

namespace flexmb::io {

void refineStages(std::vector<AnalysisStage>& stages, const ReadOptions& options) {
  if (options.refine == 1) return;
  for (AnalysisStage& stage : stages) {
    core::Model& m = stage.model;
    core::ElementOptions eo;
    eo.elongation = options.elongation ? *options.elongation : defaultElongation(m.dialect);
    core::RefinedModel r;
    try {
      r = core::refineModel(m, options.refine, eo);
    } catch (const std::invalid_argument& e) {
      throw DatError(m.sourceFile, 0, "", std::string("refinement: ") + e.what());
    }
    r.model.notes.push_back(r.summary.text());
    for (const std::string& w : r.summary.whole) r.model.notes.push_back("refinement left " + w + " whole");
    if (options.refinedResults) r.model.unrefined.reset();  // the refined model's own results
    m = std::move(r.model);
  }
}

}  // namespace flexmb::io
