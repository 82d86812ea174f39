#pragma once
// `flexmb validate`: reproduces the paper's Section 4 (Figs. 3, 4, 5, 7 and the function-evaluation
// counts) and writes validation/report/: report.md with SVG figures and CSV data beside it.
#include <atomic>
#include <string>

namespace flexmb::validation {

struct ValidationOptions {
  std::string sourceDir;  // project root (datfiles/ live there)
  std::string outDir;     // report folder
  int sweepSteps = 21;    // configurations of the Fig. 5 sweeps
  bool quiet = false;     // no progress lines on stderr
  // Set asynchronously (Ctrl-C, SIGTERM): the validation stops at its next check.
  const std::atomic<bool>* interrupt = nullptr;
  const std::atomic<int>* interruptSignal = nullptr;
};

// Returns 0 when everything ran and the acceptance checks hold, 1 when a check failed (the report
// says which), 3 when an analysis stopped, kInterrupted when stopped by options.interrupt.
//
// The report is one unit: every file is written into a temporary folder beside it
// (<outDir>/.validate.part-<pid>) and moved into <outDir> when the run ends, report.md and the
// manifest report_run.txt last; an interrupted run removes its temporary folder, so the previous
// report stays as it was, never mixed with new figures (a temporary folder of a killed run is
// removed by the next run). Other files in <outDir> (bench/, stress.csv) are left alone.
constexpr int kInterrupted = -1;
int runValidation(const ValidationOptions& options);

}  // namespace flexmb::validation
