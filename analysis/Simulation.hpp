#pragma once
// Mode 1: forward dynamics of a model (full or reduced) with the ode45-equivalent integrator or,
// for stiff models, the implicit BDF integrator (SUNDIALS CVODE) with the analytic Jacobian of
// analysis::StateJacobian (Eq. 15).
#include <Eigen/Core>
#include <array>
#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/AccuracyCheck.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"
#include "io/formats/DatReader.hpp"
#include "solvers/Ode45.hpp"

namespace flexmb::analysis {

enum class Integrator {
  Ode45,  // explicit, MATLAB's ode45 step by step (solvers::Ode45)
  Bdf,    // implicit: CVODE BDF + Newton with the analytic Jacobian (solvers::Bdf), anchored kinematics
  // ode45 until its step is bound by stability rather than accuracy (StiffnessTest: the stiffest
  // mode, not the tolerance, sets the step), then GeneralizedAlpha from that accepted state to the
  // end (measured faster than Bdf on every stiff model of the benchmark, the damped probe included).
  Auto,
  // implicit: generalized-alpha (solvers::GeneralizedAlpha) with controlled high-frequency
  // dissipation (rhoInf), modified Newton with a reused iteration matrix, anchored kinematics
  GeneralizedAlpha
};
// Stiffness test on ode45's accepted steps (Hairer's test of DOPRI5, Hairer & Wanner, Solving ODEs
// II, Sec. IV.2): a step whose h |lambda| (solvers::Ode45Options::stepMonitor) exceeds 3.25 sits at
// the explicit method's stability boundary (about 3.3 for Dormand-Prince on the negative real axis).
// The run counts as stability-bound after kStiffSteps such steps with never kCalmSteps ordinary ones
// in a row between them: an accuracy-bound step stays below the boundary, so the boundary is not met
// that often by chance, while a stiff run meets it at nearly every step (its controller keeps hitting it).
// Undamped stiff modes have eigenvalues on the imaginary axis, where Dormand-Prince's stability region
// ends at h |lambda| = 1.0 (|R(iy)| > 1 beyond y = 0.998): there the controller holds h |lambda| near
// 1-1.6 and Hairer's 3.25 is met only now and then (the elbow: 10 % of its steps, a switch only after
// 1.6 s). So a second, oscillatory, criterion: kWindowHits of the last kWindow steps beyond
// kOscillatoryBoundary. Measured on the shipped models at default tolerances: stiff runs (elbow,
// guidance, manipulator, cross-spring pivot) reach 42-50 of 50 within their first 500 steps; non-stiff ones
// (fourbar, slider-crank, wire guidance) at most 16 of 50 (accuracy-bound steps: h |lambda| about 0.25).
class StiffnessTest {
 public:
  static constexpr double kBoundary = 3.25, kOscillatoryBoundary = 0.9;
  static constexpr int kStiffSteps = 15, kCalmSteps = 6, kWindow = 50, kWindowHits = 40;
  // One accepted step ending at t; true while the run is stability-bound.
  bool step(double t, double h, double hLambda);
  bool stiff() const { return stiff_; }
  double since() const { return since_; }     // the time the run became stability-bound
  double lambda() const { return lambda_; }   // |lambda| of the last boundary step (1/s)
  long boundSteps() const { return bound_; }  // steps at the boundary since then

 private:
  int hits_ = 0, calm_ = 0;
  bool stiff_ = false;
  double since_ = 0.0, lambda_ = 0.0;
  long bound_ = 0;
  std::array<bool, kWindow> window_{};  // the last kWindow steps: h |lambda| > kOscillatoryBoundary
  int windowPos_ = 0, windowHits_ = 0;
  long seen_ = 0;
};
// "ode45", "bdf", "auto" or "galpha" (the command line's names); parseIntegrator returns nothing for other text.
const char* integratorName(Integrator i);
std::optional<Integrator> parseIntegrator(const std::string& name);
struct SimulationOptions;
// The integrator and its settings in words (the run manifest), e.g. "ode45 (Dormand-Prince 5(4), ...)".
std::string integratorDescription(const SimulationOptions& options);

// The accuracy check's windows of a run, kept for a check made later (BasisForTarget's candidates:
// the chosen candidate's run is the job's run, checked once it is chosen instead of run again).
struct DeferredAccuracy {
  bool recorded = false;  // the run completed and its windows are here
  double t0 = 0.0, tEnd = 0.0;
  double galphaFrom = std::numeric_limits<double>::infinity();  // an auto run's switch
  std::vector<AccuracyWindow> windows;
};

struct SimulationOptions {
  // Ode45: the library's default, on which validate, the benchmark and the tests of the paper's
  // function-evaluation counts rely. The front ends (simulate, study --simulate, Python, spacar())
  // default to Auto (SimulateRequest::defaultIntegrator, issue 48).
  Integrator integrator = Integrator::Ode45;
  // Bdf: the highest BDF order. 2 (A-stable) by default: with orders 3-5 the undamped high-frequency
  // modes of a full model bound CVODE's step (manipulator, RelTol 1e-3: 57,356 steps at order <= 5,
  // 463 at order <= 2; tools/bench/README.md).
  int bdfMaxOrder = 2;
  // GeneralizedAlpha: the spectral radius at infinite step, 0 ... 1 (1: no numerical dissipation).
  double rhoInf = 0.8;
  std::optional<double> tEnd, relTol, absTol, maxStep;
  std::optional<int> intervals;          // output intervals; 0 = ode45's Refine output at every step
  std::optional<Eigen::MatrixXd> basis;  // q = V eta (Eq. 17); empty = full model
  // Reduced operators for the basis (analysis/OperatorDynamics.hpp): ode45 evaluates them instead of
  // Eq. 19 where the state lies in their trained range, and Eq. 19 elsewhere (Trajectory::operators
  // says how often and from when). Null: Eq. 19 throughout. BDF and auto runs use Eq. 19.
  std::shared_ptr<const core::ReducedOperators> operators;
  // With operators that track outputs (flexmb reduce --track): the output times give
  // Trajectory::tracked from their output fields instead of the full states (the full kinematics
  // only where the state leaves the trained range, at the accuracy check's window ends and at the
  // reduction estimate's samples). Ignored without such operators or when they are not used.
  bool trackedOutputs = false;
  // How Eq. 13 is solved for the accelerations (core::DynamicsForm); reduced models always project.
  core::DynamicsForm dynamics = core::DynamicsForm::Automatic;
  bool progress = false;   // progress line on stderr for runs longer than a second
  bool keepStates = true;  // false: only statistics (benchmarks)
  // Set asynchronously (Ctrl-C): the run stops at its next check (every 64 right-hand sides) with
  // interrupted = true; the output times before it are kept.
  const std::atomic<bool>* interrupt = nullptr;
  const std::atomic<int>* interruptSignal = nullptr;  // the signal that set it (analysis::interruptCause)
  // The a-posteriori accuracy check (analysis/AccuracyCheck.hpp) into Trajectory::accuracy, for a
  // run that completes and keeps its states.
  bool accuracyCheck = false;
  // Set: the run records the check's windows here instead of checking (single-stage runs).
  DeferredAccuracy* deferAccuracy = nullptr;
  // The reduction error estimate (analysis/ReductionError.hpp) into Trajectory::reduction, for a
  // reduced run (basis) that keeps its states: on by default, as every reduced run must say it.
  bool reductionEstimate = true;
};

core::Trajectory simulate(const core::Model& model, const SimulationOptions& options, bool* interrupted = nullptr);
// A run's integrator statistics (steps, failed attempts, evaluations, Jacobians) as its integrator
// prints them; an Auto run that switched says when, and a default ode45 run whose step was bound
// by stability for long says that galpha or auto would be faster.
std::string formatStatistics(const core::Trajectory& run, Integrator integrator);

// The kinematic Newton tolerance (relative to the model size) of a simulation at relTol: residuals
// must stay far below the integration tolerance (else they are RHS noise) and need be no smaller:
// 1e-5 relTol but at most 1e-10, or the file's EPSKIN / ITERSTEP tolerance where that is tighter.
double kinematicTolerance(const core::AnalysisSettings& settings, double relTol);

// ode45 on the equations of motion as simulate runs it (the benchmark too): the configuration of every
// accepted state becomes the kinematics' anchor, and an attempt far off the solution restarts from
// it, never from its own trial states (which may have converged on another assembly branch).
solvers::OdeResult integrateOde45(core::EquationsOfMotion& eom, const solvers::Ode45Options& options,
                                  const solvers::OdeRhs& f, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                                  const solvers::OdeObserver& observer);

// One run of the model from a given state at its t0: y0 = [eta; etad] and the configuration x0
// the kinematics start from (an accuracy-check window). yEnd: the state at the last output time.
core::Trajectory simulateFrom(const core::Model& model, const SimulationOptions& options, const Eigen::VectorXd& y0,
                              const Eigen::VectorXd& x0, Eigen::VectorXd& yEnd);

// The stages of a file that run an analysis (SPACAR95 blocks with TIMESTEP); none: the last, with
// the defaults.
std::vector<const core::Model*> stagesThatRun(const std::vector<io::AnalysisStage>& stages);

// SPACAR95 block structure: the analysis stages that run (each a model read up to an END, sharing
// the topology), in order. The first starts from its model's initial values; each later one starts
// from the state (q, qd) and configuration where the previous one ended, at its own start time
// (the previous end time). The output is concatenated (the shared time point once) and the
// integrator statistics add up. options.tEnd applies to the last stage; a reduction basis is only
// accepted with a single stage. Stops at the first stage that does not complete.
core::Trajectory simulateStages(const std::vector<const core::Model*>& stages, const SimulationOptions& options,
                                bool* interrupted = nullptr);

}  // namespace flexmb::analysis
