#pragma once
// SPACAR-shaped results (io/formats/SpacarResults.hpp, io/results.md) from flexmb's analyses: every analysis
// fills one io::SpacarResults, written as <name>.sbd / <name>.sbm. The derived quantities SPACAR
// reports (reaction stresses in sig, total nodal forces fxt, transfer functions dx, D = de/dx)
// come from core::ResultQuantities at each stored step.
#include <optional>

#include "analysis/Statics.hpp"
#include "analysis/TrajectoryModes.hpp"
#include "analysis/Transfer.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/model/Model.hpp"
#include "io/formats/SpacarResults.hpp"

namespace flexmb::analysis {

// What is stored beside the state: dx (OUTLEVEL .. 1, or asked for) and bigd (D = de/dx).
struct SpacarOutputOptions {
  bool transferFunctions = false;
  bool jacobian = false;
  bool matrices = true;  // the system matrices M0 .. N0 of each step (static runs: flexmb static --matrices)
};

// Mode 1 (and 3, 4 with `modes`: its matrices and frequencies per step). `mode` is written as is.
io::SpacarResults spacarFromTrajectory(const core::Model& model, const core::Trajectory& traj,
                                       const TrajectoryModes* modes, int mode, const SpacarOutputOptions& options);
// Mode 10: one record per SPACAR load step 0..nsteps (time = step / nsteps; the ramp steps of the
// initial loads before load step 0 are left out), with reactions, matrices and frequencies.
io::SpacarResults spacarFromStatics(const core::Model& model, const StaticRun& run, const SpacarOutputOptions& options);
// Mode 3 on a static file (no TIMESTEP): the load steps of mode 10 (mode = 3), each with M0 and
// K0B over every kinematic degree of freedom for the .ltv (analysis/Perturbation).
io::SpacarResults spacarFromStaticPerturbation(const core::Model& model, const StaticRun& run,
                                               const SpacarOutputOptions& options);
// Mode 9: the load steps of mode 10 (mode = 9) and the state-space model of the last one.
io::SpacarResults spacarFromTransfer(const core::Model& model, const TransferRun& run,
                                     const SpacarOutputOptions& options);
// The modes of the initial configuration: one step with M0 .. N0, frequencies and mode shapes
// (in q and in x). modes: M-orthonormal columns in eta; basis: q = V eta (empty: the full model).
io::SpacarResults spacarFromModes(const core::Model& model, double t, const Eigen::VectorXd& eta,
                                  const core::LinearizedSystem& sys, const Eigen::VectorXd& omega,
                                  const Eigen::MatrixXd& modes, const std::optional<Eigen::MatrixXd>& basis);
// Mode 0: the initial configuration with dx and bigd (SPACAR's kinematic analysis).
io::SpacarResults spacarKinematic(const core::Model& model);

}  // namespace flexmb::analysis
