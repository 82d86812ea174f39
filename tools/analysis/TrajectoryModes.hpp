#pragma once
// Modes 3 and 4: linearised matrices and eigenfrequencies along a simulated trajectory (paper
// Fig. 7b). At each output time the stresses and the reaction stresses follow from the state,
// with the inertia forces as D'Alembert loads (f - M xdd - h). The velocity sensitivity C and the
// dynamic stiffening N of ref. [13] are not included.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/Linearization.hpp"
#include "core/Trajectory.hpp"

namespace flexmb::analysis {

struct TrajectoryModes {
  std::vector<double> time;
  std::vector<Eigen::VectorXd> omega;        // rad/s, ascending, per output time
  std::vector<core::LinearizedSystem> matrices;  // when kept
};

// q at an output state (DYNX coordinates and DYNE deformations), then eta by least squares on V.
Eigen::VectorXd dofsOf(const core::Model& model, const core::StateOutputs& s);

TrajectoryModes trajectoryModes(const core::Model& model, const core::Trajectory& traj, int nev,
                                const std::optional<Eigen::MatrixXd>& basis, bool keepMatrices = false);

}  // namespace flexmb::analysis
