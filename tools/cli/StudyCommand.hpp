#pragma once
// The `study` command's parts, shared by its files: StudyCommand.cpp (the command: the study folder,
// what is left to run), StudyArguments.cpp (its options and their checks), StudyWorkers.cpp (the
// variants run in a pool of worker processes, each under its lock) and StudyCollect.cpp (the table,
// report and plots of `flexmb study collect`).
#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "analysis/Study.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/templates/ModelTemplate.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/StudySlurm.hpp"

namespace flexmb::cli::study {

std::string variantFolder(const std::string& dir, const std::string& name);

// Everything a worker needs, made once before the workers are forked.
struct Study {
  std::string templatePath, stem, dir;
  io::ReadOptions readOptions;
  std::optional<io::ModelTemplate> model;
  analysis::StudyAnalyses analyses;
  std::vector<analysis::Variant> variants;
  std::vector<std::string> fingerprints;  // per variant
  std::vector<std::string> plot;          // quantities to plot (empty: all)
  // --accuracy / --error-estimate: the study's record of the ladders (study.txt's lines)
  std::vector<std::pair<std::string, std::string>> accuracySettings;
  bool quiet = false;
  std::string prefix(int k) const;  // <dir>/variants/<name>/<stem>
};

// "name = value, ..." (round-trip numbers).
std::string parametersText(const io::ParameterValues& values);
// Flushes f; throws (naming `what`) when a write failed.
void writeChecked(std::ofstream& f, const std::string& what);
// One file of the set, <prefix><suffix>, holding text.
void writeText(io::OutputSet& files, const std::string& suffix, const std::string& text);
// The non-empty items of s between separators.
std::vector<std::string> splitList(const std::string& s, char sep);

// ---- StudyArguments.cpp ----------------------------------------------------------------------

// The study's command line.
struct StudyArgs {
  ModelOptions m;
  std::vector<std::string> params, derive, plot;
  std::string table, out;
  bool check = false, modes = false, statics = false, simulate = false, rerunFailed = false;
  int nev = 6, steps = 0, buckling = 0, jobs = 0, task = -1, of = 0;
  std::vector<int> stiffness;
  analysis::SweepOptions sw;
  double tEnd = 0, relTol = 0, absTol = 0;
  int intervals = -1;
  std::string integrator = "auto";  // simulate's default (flexmb simulate's)
  double target = NAN;              // --target (NaN: not given)
  AccuracyArgs accuracy;            // --accuracy, --error-estimate, --max-seconds (StudyLadder.cpp)
  bool reduce = false;              // --reduce: with --accuracy, each variant reduced (basis auto)
  SlurmOptions slurm;
  StudyArgs() { sw.node = 0; }
};

// Parses the command line into sa (a usage error or --help: its exit code).
std::optional<int> parseStudyArgs(const std::vector<std::string>& args, StudyArgs& sa);
// The analyses every variant runs, from the command line (a usage error: its exit code).
std::optional<int> chooseStudyAnalyses(const std::vector<std::string>& args, StudyArgs& sa, analysis::StudyAnalyses& a);

// ---- StudyLadder.cpp --------------------------------------------------------------------------

// --accuracy / --error-estimate: the mesh ladders on the first and the last variant
// (analysis/StudyAccuracy.hpp), before the fingerprints; sets s.readOptions.refine, s.analyses and
// s.accuracySettings (an error: its exit code). Nothing to do when neither is asked.
std::optional<int> planStudyMesh(const StudyArgs& sa, Study& s);
// The keys of study.txt that planStudyMesh adds (collect repeats them in the study's manifest).
const std::vector<std::string>& accuracyKeys();

// ---- StudyWorkers.cpp ------------------------------------------------------------------------

struct PoolReport {
  int finished = 0, failed = 0, busy = 0, writeFailed = 0, killed = 0;
  bool interrupted = false;
  double analysisSeconds = 0.0;
};

// Runs the pending variants (indices into s.variants) in `jobs` worker processes, with a progress
// line; Ctrl-C or SIGTERM stops the workers too (rep.interrupted).
PoolReport runPool(const Study& s, const std::vector<int>& pending, int jobs);

// ---- StudyCollect.cpp ------------------------------------------------------------------------

// Joins the variants' summaries of the study in dir into its table, report and plots; an exit code.
int collect(const std::string& dir, std::vector<std::string> plot, bool quiet);
// `flexmb study collect folder [--plot ...]`.
int runCollect(const std::vector<std::string>& args);

}  // namespace flexmb::cli::study
