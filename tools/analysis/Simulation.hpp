#pragma once
// Mode 1: forward dynamics of a model (full or reduced) with the ode45-equivalent integrator.
#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <optional>

#include "core/EquationsOfMotion.hpp"
#include "core/Model.hpp"
#include "core/Trajectory.hpp"

namespace flexmb::analysis {

struct SimulationOptions {
  std::optional<double> tEnd, relTol, absTol, maxStep;
  std::optional<int> intervals;     // output intervals; 0 = ode45's Refine output at every step
  std::optional<Eigen::MatrixXd> basis;  // q = V eta (Eq. 17); empty = full model
  // How Eq. 13 is solved for the accelerations (core::DynamicsForm); reduced models always project.
  core::DynamicsForm dynamics = core::DynamicsForm::Automatic;
  bool progress = false;            // progress line on stderr for runs longer than a second
  bool keepStates = true;           // false: only statistics (benchmarks)
  // Set asynchronously (Ctrl-C): the run stops at its next check (every 64 right-hand sides) with
  // interrupted = true; the output times before it are kept.
  const std::atomic<bool>* interrupt = nullptr;
};

core::Trajectory simulate(const core::Model& model, const SimulationOptions& options, bool* interrupted = nullptr);

// The kinematic Newton tolerance (relative to the model size) of a simulation at relTol: residuals
// must stay far below the integration tolerance (else they are RHS noise) and need be no smaller:
// 1e-5 relTol, or the file's EPSKIN / ITERSTEP tolerance where that is tighter.
double kinematicTolerance(const core::AnalysisSettings& settings, double relTol);

// SPACAR95 block structure: the analysis stages that run (each a model read up to an END, sharing
// the topology), in order. The first starts from its model's initial values; each later one starts
// from the state (q, qd) and configuration where the previous one ended, at its own start time
// (the previous end time). The output is concatenated (the shared time point once) and the
// integrator statistics add up. options.tEnd applies to the last stage; a reduction basis is only
// accepted with a single stage. Stops at the first stage that does not complete.
core::Trajectory simulateStages(const std::vector<const core::Model*>& stages, const SimulationOptions& options,
                                bool* interrupted = nullptr);

}  // namespace flexmb::analysis
