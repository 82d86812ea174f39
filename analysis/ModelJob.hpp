#pragma once
// What every analysis job shares (SimulateJob, StaticJob, ModesJob, SweepJob, TransferJob): the
// model read once from its source, the checks an analysis makes before it starts, its messages as
// data (Diagnostic) and its status. A front end builds the job from the options it parsed, shows the
// diagnostics in its own way, writes what the job computed and adds nothing else.
#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/LapClock.hpp"
#include "analysis/ModelSource.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

enum class JobStatus {
  Ready,        // prepared, not run
  InputError,   // refused before it ran (diagnostics say why)
  Failed,       // could not start or could not finish a step that has no partial result (diagnostics say why)
  Completed,    // ran to the end
  Stopped,      // stopped early (the results so far are kept; the reason is a diagnostic)
  Interrupted,  // Ctrl-C / SIGTERM (the results so far are kept)
};

// A reduced basis q = V eta (Eq. 17) given to a linear analysis: a file written by `reduce`, or a
// matrix (neither: the full model).
struct BasisInput {
  std::string file;
  std::optional<Eigen::MatrixXd> matrix;
};

// What a front end hands a run beside its options: progress (called before step `done` of `total`)
// and the flag Ctrl-C / SIGTERM sets (analysis/Interrupt.hpp); the run stops at its next step and
// keeps what it reached.
struct RunHooks {
  std::function<void(int done, int total)> progress;
  const std::atomic<bool>* interrupt = nullptr;
  const std::atomic<int>* interruptSignal = nullptr;
};

// Why an analysis other than dynamics refuses a model naming MATLAB user functions (USERSIG, USERINP:
// only spacar() in Octave or MATLAB calls them, in mode 1); empty: it names none.
std::string userFunctionRefusal(const core::Model& model, const std::string& file);

// A single model (a study's variant, a model built in code) as a job's source.
ModelSource sourceOfModel(const core::Model& model);

class ModelJob {
 public:
  JobStatus status() const { return status_; }
  const Diagnostics& diagnostics() const { return diagnostics_; }
  const std::string& file() const { return file_; }
  std::shared_ptr<const std::vector<io::AnalysisStage>> allStages() const { return stages_; }
  // Wall-clock seconds since the job was made (reading the model included).
  double secondsSoFar() const { return clock_.total(); }

 protected:
  // Reads the source once; a reading error is the job's first diagnostic (InputError).
  explicit ModelJob(const ModelSource& source);
  // The last stage's model (the one a linear analysis is about); only when the source was read.
  const core::Model& lastModel() const { return stages_->back().model; }
  bool read() const { return stages_ != nullptr; }
  // The checks of analysis::checkModelFor, and, for an analysis other than dynamics, that the model
  // names no MATLAB user function. False (InputError) when one fails.
  bool checkModel(const core::Model& model, const ModelNeeds& needs, bool userFunctionsAllowed);
  // The basis of `input` for `model` (rows = its degrees of freedom); a file that cannot be read or a
  // matrix of another height is refused (false).
  bool readBasis(const core::Model& model, const BasisInput& input, std::optional<Eigen::MatrixXd>& basis);
  void say(Diagnostic::Kind kind, std::string text, std::string where = "");
  bool refuse(std::string text, std::string where = "");  // an input error: InputError, false
  void fail(std::string text);                            // a numerical failure: Failed
  // The status after a run that keeps its partial results; a stop is said as an Error diagnostic
  // without a file ("<analysis> stopped: <reason> (<kept>)").
  JobStatus finish(bool completed, bool interrupted, const std::string& analysis, const std::string& stopReason,
                   const std::string& kept);

  LapClock clock_;  // first: it starts before the model is read
  std::string file_;
  std::shared_ptr<const std::vector<io::AnalysisStage>> stages_;
  JobStatus status_ = JobStatus::Ready;
  Diagnostics diagnostics_;
};

}  // namespace flexmb::analysis
