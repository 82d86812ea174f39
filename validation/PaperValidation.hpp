#pragma once
// `flexmb validate`: reproduces the paper's Section 4 (Figs. 3, 4, 5, 7 and the function-evaluation
// counts) and writes validation/report/: report.md with SVG figures and CSV data beside it.
#include <string>

namespace flexmb::validation {

struct ValidationOptions {
  std::string sourceDir;  // project root (datfiles/ live there)
  std::string outDir;     // report folder
  int sweepSteps = 21;    // configurations of the Fig. 5 sweeps
  bool quiet = false;     // no progress lines on stderr
};

// Returns 0 when everything ran and the acceptance checks hold, 1 when a check failed (the report
// says which), 3 when an analysis stopped.
int runValidation(const ValidationOptions& options);

}  // namespace flexmb::validation
