#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/program_options/options_description.hpp>

#include "analysis/AccuracyTarget.hpp"
#include "analysis/DesignDamping.hpp"
#include "analysis/ModelJob.hpp"
#include "analysis/ModelSource.hpp"
#include "core/model/Model.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/pictures/MechanismGeometry.hpp"

namespace flexmb::cli {

// Exit codes (README "Exit codes"): one meaning each, in every command.
enum ExitCode : int {
  kOk = 0,
  kInputError = 1,        // the model, a basis or the output location is wrong (check: not well posed)
  kUsageError = 2,        // the command line: unknown option, invalid or missing value
  kNumericalFailure = 3,  // the analysis stopped (Newton, step size, folded element); results so far written
  kWriteFailed = 4,       // a result file could not be written (disk full, removed folder)
  kInterrupted = 130,     // Ctrl-C (SIGINT): results so far written
  kTerminated = 143,      // SIGTERM (kill, a batch system's time limit): results so far written, as for Ctrl-C
};

int runCheck(const std::vector<std::string>& args);
int runSimulate(const std::vector<std::string>& args);
int runKeywords(const std::vector<std::string>& args);
int runModes(const std::vector<std::string>& args);
int runStatic(const std::vector<std::string>& args);
int runSweep(const std::vector<std::string>& args);
int runReduce(const std::vector<std::string>& args);
int runValidate(const std::vector<std::string>& args);
int runStudy(const std::vector<std::string>& args);     // StudyCommand.cpp: design studies, `study collect`
int runTransfer(const std::vector<std::string>& args);  // mode 9
int runMode3(const std::vector<std::string>& args);     // --mode 3: trajectory or load steps

// Reads a model with the common options (--dialect, --elongation); prints errors, returns false.
struct ModelOptions {
  std::string file;
  std::string dialect;          // "", "95", "2013"
  std::string elongation;       // "", "plain", "corrected"
  int refine = 1;               // --refine N: every flexible beam split in N (io/formats/MeshRefinement.hpp)
  bool refinedResults = false;  // --refined-results: files of every node (io/formats/OriginalResults.hpp)
  bool quiet = false;           // --quiet: no progress, no notes
};
// acceptUserFunctions: a file naming USERSIG / USERINP is read (mode 0 never calls them); else it is
// refused with a message that they run only through spacar().
bool loadModel(const ModelOptions& o, core::Model& model, bool acceptUserFunctions = false);
// loadModel, then the model diagnostics (core/linearization/ModelDiagnostics) that make an analysis meaningless:
// no degrees of freedom, no mass where the analysis needs it, overflowing values, an initial
// assembly on another branch. Prints them; false = input error.
// allowDriven: a driven rigid mechanism (no degrees of freedom, moving inputs) is accepted
// (simulate runs its inverse dynamics).
bool loadModelFor(const ModelOptions& o, core::Model& model, bool needsMass, bool allowDriven = false);
// The file read once with the common options, its stages checked for an analysis with these needs
// (analysis::checkModelFor) and the diagnostics printed; null after an input error (printed).
std::shared_ptr<const std::vector<io::AnalysisStage>> loadChecked(const ModelOptions& o,
                                                                  const analysis::ModelNeeds& needs,
                                                                  bool acceptUserFunctions = false);
// The model file as a job's source (with the text read ahead, when it was).
analysis::ModelSource modelSource(const ModelOptions& o);
// The manifest's model settings: the file, what --refine made of it (the model's note
// "refined: every flexible beam split in N (K elements, M nodes)") and where the results are
// ("results": at the original nodes and elements, or every node of the refined model).
void recordModel(io::OutputSet& files, const ModelOptions& o, const core::Model& model);
// Reads the file's text once for the whole command (throws io::DatError); the analysis then parses
// this text instead of opening the file again.
std::shared_ptr<const std::string> readAhead(const std::string& file);
// An option of Diagnostic::options as the command line spells it (max_step: --max-step).
std::string optionSpelling(const std::string& name);
// A job's diagnostics as the command line shows them: results on stdout; notes (unless quiet),
// warnings and errors on stderr, "file: warning: text".
// from, to: the part of d to print (diagnostics a job added since the last print).
void printDiagnostics(const analysis::Diagnostics& d, bool quiet, std::size_t from = 0,
                      std::size_t to = static_cast<std::size_t>(-1));
// A job's diagnostics from `from` on (printDiagnostics); returns how many it has, the next `from`.
std::size_t showDiagnostics(const analysis::ModelJob& job, bool quiet, std::size_t from = 0);
// A job's exit code: a run that stopped or was interrupted keeps its files (kNumericalFailure /
// the signal's code), an input error is kInputError.
int exitCodeOf(analysis::JobStatus s);
// A file naming USERSIG / USERINP (MATLAB functions) is refused with the reason printed: only
// spacar() in Octave/MATLAB can call them.
bool userFunctionsAllowed(const ModelOptions& o, const core::Model& model);

// The options every model command shares (--dialect, --elongation, --quiet), and the parse of a
// command's options with the model file as positional argument. Returns an exit code when the
// command must stop (--help: 0; a usage error: 2, message printed), nothing to go on.
boost::program_options::options_description commonModelOptions(ModelOptions& m);
std::optional<int> parseCommand(const std::vector<std::string>& args, boost::program_options::options_description& d,
                                ModelOptions& m, const char* usage, bool needsModel = true);

// Value checks for options (run by po::notify; a violation is a usage error naming the option).
std::function<void(const double&)> positive(const char* option);  // finite and > 0
std::function<void(const double&)> finite(const char* option);
std::function<void(const int&)> atLeast(const char* option, int minimum);
// A comma-separated list of finite numbers ("0.01,0.02"); else a usage error naming --option.
std::vector<double> numberList(const std::string& text, const char* option);
// --damping-ratio Z[,Z2...] and --rayleigh ALPHA,BETA (transfer, modes): the damping a designer
// states, added to the model's EDAMP (analysis/DesignDamping.hpp).
void addDampingOptions(boost::program_options::options_description& d, analysis::DampingOptions& damping);

// --error-estimate, --accuracy EPS and --max-seconds S (static, modes, simulate): the error against
// the converged model (analysis/AccuracyTarget.hpp).
struct AccuracyArgs {
  bool estimate = false;
  double eps = 0.0;  // 0: not given
  double maxSeconds = 300.0;
  bool asked() const { return estimate || eps > 0.0; }
};
void addAccuracyOptions(boost::program_options::options_description& d, AccuracyArgs& a);
// The request for the analysis (progress lines on stderr unless quiet); a usage error (printed)
// when both are given or `clash` names an option they cannot go with.
std::optional<analysis::AccuracyRequest> accuracyRequest(const AccuracyArgs& a, bool quiet,
                                                         const std::string& clash = "");
// A command's job: under --accuracy / --error-estimate the ladder's answer, already run (`accurate`
// keeps the ladder's budget and lines), else a new one from (source, options, extra...); null after
// a usage error (printed; clash: an option the ladder cannot go with, empty: none).
template <class Job, class Options, class... Extra>
std::unique_ptr<Job> commandJob(const ModelOptions& m, const Options& options, const AccuracyArgs& accuracy,
                                analysis::AccurateRun<Job> (*ladder)(analysis::ModelSource, const Options&,
                                                                     const analysis::AccuracyRequest&),
                                analysis::AccurateRun<Job>& accurate, const std::string& clash, const Extra&... extra) {
  if (!accuracy.asked()) return std::make_unique<Job>(modelSource(m), options, extra...);
  const std::optional<analysis::AccuracyRequest> ask = accuracyRequest(accuracy, m.quiet, clash);
  if (!ask) return nullptr;
  accurate = ladder(modelSource(m), options, *ask);
  return std::move(accurate.job);
}
// A new job goes on when it is Ready; one from the ladder (ran: true) has run already and goes on to
// its files unless it could not start.
inline bool jobCanGoOn(const analysis::ModelJob& job, bool ran) {
  const analysis::JobStatus s = job.status();
  return ran ? s != analysis::JobStatus::InputError && s != analysis::JobStatus::Failed
             : s == analysis::JobStatus::Ready;
}
// The ladder's lines (the estimate, the total) and the budget's manifest settings.
void reportAccuracy(io::OutputSet& files, const analysis::ErrorBudget& budget, const analysis::Diagnostics& ladder,
                    bool quiet);

// --view of the picture commands (show, modes, static, sweep): auto, xy, xz, yz or iso, anything else
// a usage error; viewNamed reads the checked value (empty: auto).
void addViewOption(boost::program_options::options_description& d, std::string& viewName, const char* autoMeaning);
io::View viewNamed(const std::string& name);

// Ctrl-C and SIGTERM: the first signal sets the flag (an analysis stops at its next check and writes
// what it has; analysis::interruptCause names the signal); a second one ends the program at once.
void installInterruptHandler();
const std::atomic<bool>* interruptFlag();
const std::atomic<int>* interruptSignal();  // the signal that set the flag (0: none yet)
int interruptedExitCode();                  // kInterrupted (SIGINT) or kTerminated (SIGTERM)

// io::OutputSet::attempt with the failures on stderr. Returns false on failure: the command then
// exits with kWriteFailed after writing the manifest. A step that reports its own failure (a
// picture writer returning false) throws ProductFailed, whose reason is already printed.
using io::ProductFailed;
bool tryProduct(io::OutputSet& files, const std::string& what, const std::function<void()>& step);

// Before an analysis: whether the file set and the extra outputs (--svg, --html, --vtk, --echo;
// empty ones skipped) can be written where asked; false, said on stderr, when not (the command then
// exits with kInputError). The VTK writer would make a missing folder for its .vtu files: checked too.
bool outputsWritable(io::OutputSet& files, const std::vector<std::string>& extras = {});

// The stale SPACAR companions (.sbm, .ltv) a file set removed when it renamed its files into place:
// one line each on stdout, after the "wrote" lines.
void sayRemovedStale(const std::vector<std::string>& removed);

}  // namespace flexmb::cli
