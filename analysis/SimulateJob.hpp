#pragma once
// The simulate job (mode 1, and the trajectory of modes 3 and 4), once for every front end: the
// command line, Python, spacar() and the study call it. Between the options a front end parsed and
// the files it writes (analysis/SimulationFiles.hpp) it reads the model once, checks it, reads the
// basis and chooses its reduced dynamics (the reduced operators beside the basis file or Eq. 19),
// checks the run's size, chooses a basis for a target, runs the SPACAR95 stages (or a driven
// mechanism's inverse dynamics) and words what the run says. Everything it has to say is a
// Diagnostic; the front end shows them and adds only its own spelling.
#include <Eigen/Core>
#include <atomic>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/BasisForTarget.hpp"
#include "analysis/DesignDamping.hpp"
#include "analysis/ModelJob.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/TargetOperators.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

// What a simulate job is asked, beside the model: the integration (SimulationOptions) and the
// reduced model.
struct SimulateRequest {
  SimulationOptions run;  // integrator, tolerances, span, accuracy check, interrupt flag
  // The reduced basis: a file written by `reduce` (its reduced operators beside it are used where
  // they fit), "auto" (the smallest basis whose reduction error estimate meets `target`), or empty.
  std::string basisFile;
  std::optional<Eigen::MatrixXd> basis;                      // a basis given as a matrix instead
  std::shared_ptr<const core::ReducedOperators> operators;   // and its operators (a reduce result)
  double target = std::numeric_limits<double>::quiet_NaN();  // the reduction error target
  std::optional<ReductionOptions> autoBasis;                 // auto: the kind of basis (default modal)
  // auto: a basis and operators shared with other runs (a study's variants, issue 49 item 3): used
  // where its key is this model's (reductionKey) and kept when a later run's estimate meets the
  // target; otherwise this run chooses (and trains) anew and leaves its own here. Null: not shared.
  std::shared_ptr<SharedReduction> shared;
  bool fullKinematics = false;  // Eq. 19 even where the operators hold
  bool trackedOutputs = false;  // the operators' output fields at the output times
  // The integrator was not asked for: run.integrator is the front end's default (auto). The manifest
  // says which integrator ran and that it was the default.
  bool defaultIntegrator = false;
  // Damping a designer states, added to the model's EDAMP: Rayleigh's beta K0 as element damping
  // (analysis/DesignDamping.hpp); a modal ratio or alpha is refused with why; full-model runs only.
  DampingOptions damping;
};

class SimulateJob : public ModelJob {
 public:
  // Reads the source once, checks the model, the basis and the run's size. status() is Ready or
  // InputError.
  SimulateJob(const ModelSource& source, SimulateRequest request);

  // The stages that run and the last of them (the model the results belong to).
  const std::vector<const core::Model*>& stages() const { return runs_; }
  const core::Model& model() const { return *runs_.back(); }
  bool driven() const { return driven_; }  // a driven rigid mechanism: inverse dynamics, no integrator
  const SimulationOptions& options() const { return request_.run; }
  // The run manifest's lines the job adds (basis, reduced dynamics, tracked outputs, run notes).
  const std::vector<std::pair<std::string, std::string>>& settings() const { return settings_; }

  // Chooses the basis (auto), then runs. Appends diagnostics: the "basis auto" line, the integrator
  // statistics, the reduced dynamics used, the wall time and the run notes (analysis/RunNotes.hpp).
  JobStatus run();

  const core::Trajectory& trajectory() const { return trajectory_; }
  core::Trajectory& trajectory() { return trajectory_; }
  const std::vector<Eigen::VectorXd>& fxt() const { return fxt_; }  // driven: nodal forces per output time
  bool interrupted() const { return interrupted_; }
  // Basis auto: the run is the chosen candidate's own, not integrated again.
  bool reusedCandidateRun() const { return reused_; }
  // With a target: why no basis smaller than the full model was chosen (empty: one was).
  const std::string& targetNote() const { return targetNote_; }
  // From the job's making to the end of run() (reading, choosing, integration, checks).
  double wallSeconds() const { return wall_; }
  // The parts of wallSeconds, "reading and checks 0.004 s, integration 0.055 s, ..." (parts over 0).
  const std::string& timeParts() const { return timeParts_; }

 private:
  void prepare();
  bool addDamping();  // request_.damping into copies of the stages (false: refused)
  void prepareBasis();
  void chooseDefaultIntegrator();
  void chooseBasisForTarget();
  void chooseTargetOperators(const TargetResult& tr);  // auto: Eq. 19 or operators for the chosen basis
  bool useSharedReduction();                           // auto: the shared basis and operators fit this model
  bool sharedReductionMissed();                        // after a run on them: its estimate misses the target (said)
  void sayTargetEstimate();                            // auto: reduction + integration against the target
  void rerunFullAtTighterTolerance();                  // auto, the full model: its integration error missed
  void runDriven();

  SimulateRequest request_;
  std::vector<const core::Model*> runs_;
  bool driven_ = false;
  std::string operatorNote_;  // the reduced dynamics used (operators, or Eq. 19 and why)
  std::string targetNote_;
  bool reused_ = false;                                      // the run is the chosen candidate's (basis auto)
  bool sharedUsed_ = false;                                  // the run is on request_.shared's basis (basis auto)
  bool toleranceFromTarget_ = false;                         // basis auto chose RelTol (no --reltol)
  std::shared_ptr<const core::ReducedOperators> operators_;  // basis auto: trained for the chosen basis
  double trainingSeconds_ = 0.0;
  std::vector<std::pair<std::string, std::string>> settings_;
  core::Trajectory trajectory_;
  std::vector<Eigen::VectorXd> fxt_;
  bool interrupted_ = false;
  double wall_ = 0.0, choosing_ = 0.0;
  std::string timeParts_;
};

}  // namespace flexmb::analysis
