#include <filesystem>
#include <iostream>

#include "tools/cli/Commands.hpp"
#include "validation/PaperValidation.hpp"

namespace flexmb::cli {

int runValidate(const std::vector<std::string>& args) {
  validation::ValidationOptions o;
  o.sourceDir = FLEXMB_SOURCE_DIR;
  o.outDir = o.sourceDir + "/validation/report";
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" && i + 1 < args.size()) o.outDir = args[++i];
    else if (args[i] == "--source" && i + 1 < args.size()) o.sourceDir = args[++i];
    else if (args[i] == "--sweep-steps" && i + 1 < args.size()) o.sweepSteps = std::stoi(args[++i]);
    else {
      std::cerr << "usage: flexmb validate [--out DIR] [--source PROJECT_DIR] [--sweep-steps n]\n";
      return 2;
    }
  }
  try {
    return validation::runValidation(o);
  } catch (const std::exception& e) {
    std::cerr << "flexmb validate: " << e.what() << "\n";
    return 3;
  }
}

}  // namespace flexmb::cli
