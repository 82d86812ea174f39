// flexmb study --accuracy EPS / --error-estimate: the mesh ladders on the range's two ends before
// the variants run (the recipe: analysis/StudyAccuracy.hpp).
#include <iostream>

#include "analysis/StudyAccuracy.hpp"
#include "tools/cli/StudyCommand.hpp"

namespace flexmb::cli::study {

const std::vector<std::string>& accuracyKeys() {
  static const std::vector<std::string> keys = {"accuracy target",   "refinement chosen",       "integrator tolerance",
                                                "reduction target",  "discretization measured", "discretization ladder",
                                                "accuracy reachable"};
  return keys;
}

std::optional<int> planStudyMesh(const StudyArgs& sa, Study& s) {
  if (!sa.accuracy.asked()) return std::nullopt;
  std::optional<analysis::AccuracyRequest> ask = accuracyRequest(sa.accuracy, sa.m.quiet);
  if (!ask) return kUsageError;
  installInterruptHandler();  // Ctrl-C during the ladders stops them (and the study)
  ask->interrupt = interruptFlag();
  // The nominal design (the first variant) and the other end of the range (the last).
  std::vector<analysis::StudyEnd> ends;
  std::vector<size_t> at = {0};
  if (s.variants.size() > 1) at.push_back(s.variants.size() - 1);
  for (size_t k : at) {
    analysis::StudyEnd end;
    end.name = s.variants[k].name;
    end.source.file = s.templatePath;  // names the model in messages (the template's lines)
    end.source.read = s.readOptions;
    try {
      end.source.text = std::make_shared<const std::string>(s.model->instantiate(s.variants[k].values));
    } catch (const std::exception& e) {
      std::cerr << e.what() << "\n";
      return kInputError;
    }
    ends.push_back(std::move(end));
  }
  if (!sa.m.quiet)
    std::cout << "study " << (sa.accuracy.estimate ? "--error-estimate" : "--accuracy")
              << ": the discretization error measured at " << ends.front().name
              << (ends.size() > 1 ? " and " + ends.back().name : std::string()) << " before the variants\n";
  analysis::StudyAccuracyPlan plan;
  try {
    plan = analysis::planStudyAccuracy(ends, s.analyses, *ask, sa.reduce);
  } catch (const std::invalid_argument& e) {
    std::cerr << "flexmb: --accuracy and --error-estimate: " << e.what() << "\n";
    return kUsageError;
  }
  printDiagnostics(plan.diagnostics, sa.m.quiet);
  if (interruptFlag()->load()) {
    std::cerr << "flexmb: interrupted while measuring the discretization error; no variant ran\n";
    return interruptedExitCode();
  }
  if (!plan.ok) return kInputError;
  s.readOptions.refine = s.analyses.accuracy->refine;
  s.accuracySettings = plan.settings;
  return std::nullopt;
}

}  // namespace flexmb::cli::study
