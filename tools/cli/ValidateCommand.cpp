#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "tools/cli/Commands.hpp"
#include "validation/PaperValidation.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

int runValidate(const std::vector<std::string>& args) {
  validation::ValidationOptions o;
  o.sourceDir = FLEXMB_SOURCE_DIR;
  o.outDir = o.sourceDir + "/validation/report";
  ModelOptions m;
  po::options_description d("options");
  d.add_options()("out", po::value(&o.outDir), "report folder (default: validation/report in the source tree)")(
      "source", po::value(&o.sourceDir), "project folder whose datfiles/ are used")(
      "sweep-steps", po::value(&o.sweepSteps)->notifier(atLeast("sweep-steps", 2)),
      "configurations of the Fig. 5 sweeps (default 21)")("quiet,q", po::bool_switch(&o.quiet), "no progress lines");
  if (auto rc = parseCommand(args, d, m, "usage: flexmb validate [--out DIR] [--source PROJECT_DIR] [--sweep-steps n]",
                             false))
    return *rc;
  if (o.sweepSteps > 100000) {
    std::cerr << "flexmb: --sweep-steps " << o.sweepSteps << " is too many (limit 100000)\n";
    return kUsageError;
  }
  std::error_code ec;
  if (!std::filesystem::is_directory(o.sourceDir + "/datfiles", ec)) {
    std::cerr << "flexmb: --source " << o.sourceDir << " has no datfiles/ folder\n";
    return kInputError;
  }
  try {
    std::filesystem::create_directories(o.outDir);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: cannot create the report folder '" << o.outDir << "': " << e.what() << "\n";
    return kInputError;
  }
  installInterruptHandler();
  o.interrupt = interruptFlag();
  o.interruptSignal = interruptSignal();
  try {
    const int rc = validation::runValidation(o);
    return rc == validation::kInterrupted ? interruptedExitCode() : rc;
  } catch (const std::exception& e) {
    std::cerr << "flexmb validate: " << e.what() << "\n";
    return kNumericalFailure;
  }
}

}  // namespace flexmb::cli
