#pragma once
// Mode 1 on a driven rigid mechanism: no degrees of freedom, inputs (INPUTX, INPUTE, their time
// functions) that move in time. The configuration is a function of time alone, so there is nothing
// to integrate: at every output time the kinematics give x, xd, xdd (Eq. 7-8 with q empty: the
// rheonomic terms only) and the inverse dynamics the forces the inputs need (SPACAR's mode 1 on
// such a model): the reaction stresses sig~ of the input and fixed deformations (an INPUTE hinge:
// its stress, positive as a spring's, i.e. the drive applies -sig~ in the direction of e) and the
// total nodal forces fxt (an INPUTX coordinate: the force or torque
// the drive applies there), from D_c^T sig~ = (f - M xdd - h - D^T sig)_c (core::ResultQuantities).
#include <Eigen/Core>
#include <atomic>
#include <optional>
#include <vector>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

// The model has no degrees of freedom and at least one input that moves: simulate runs the
// inverse dynamics instead of an integrator.
bool isDrivenRigidMechanism(const core::Model& model);

struct InverseDynamicsOptions {
  std::optional<double> tEnd;    // overrides TIMESTEP's end time
  std::optional<int> intervals;  // output intervals (> 0), overrides TIMESTEP's
  // Set asynchronously (Ctrl-C): stops before the next output time, keeping those before it.
  const std::atomic<bool>* interrupt = nullptr;
  const std::atomic<int>* interruptSignal = nullptr;
};

struct InverseDynamicsRun {
  // states[k].sig: the total stresses, reaction stresses of fixed and input deformations included
  // (for a rigid mechanism every stress is one); nsteps = nfevals = 0 (no integrator).
  core::Trajectory trajectory;
  std::vector<Eigen::VectorXd> fxt;  // total nodal forces per output time (size nx)
  bool interrupted = false;
};

// Over the model's time span (t0 to tEnd in intervals equal steps, both ends included). Stops at
// the first output time whose kinematics fail (a dead point, no assembly), keeping the times before.
InverseDynamicsRun inverseDynamics(const core::Model& model, const InverseDynamicsOptions& options);

// SPACAR95 blocks: each stage over its own span (nothing carries over but the time; options.tEnd and
// intervals apply to the last), the outputs concatenated (a shared time point once); stops at the
// first stage that does not complete.
InverseDynamicsRun inverseDynamicsStages(const std::vector<const core::Model*>& stages,
                                         const InverseDynamicsOptions& options);

}  // namespace flexmb::analysis
