#pragma once
// Modes 3 and 4: linearised matrices and eigenfrequencies along a simulated trajectory (paper
// Eq. 15, Fig. 7b). At each output time the linearisation about the moving state (eta, etad, etadd)
// gives M, C, D, K, N, G (ref. [13]; the inertia forces act as loads in G). Two sets of frequencies:
//   omega       natural frequencies |s| of M s^2 + (C + D) s + (K + N + G) = 0 (the full Eq. 15);
//   omegaFrozen (K + G) v = omega^2 M v, the configuration-frozen spectrum without the velocity
//               sensitivity and dynamic stiffening (what a quasi-static sweep would give).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/dynamics/Trajectory.hpp"
#include "core/linearization/Linearization.hpp"

namespace flexmb::analysis {

struct TrajectoryModes {
  std::vector<double> time;
  std::vector<Eigen::VectorXd> omega;            // rad/s, ordered by magnitude, per output time
  std::vector<Eigen::VectorXd> damping;          // damping ratio per entry of omega
  std::vector<Eigen::VectorXd> omegaFrozen;      // rad/s, ascending
  std::vector<core::LinearizedSystem> matrices;  // when kept (mode 3)
  bool completed = true;
  std::string stopReason;
};

// q at an output state (DYNX coordinates and DYNE deformations); with rates = 1 or 2 the
// velocities or accelerations of those coordinates.
Eigen::VectorXd dofsOf(const core::Model& model, const core::StateOutputs& s, int rate = 0);

TrajectoryModes trajectoryModes(const core::Model& model, const core::Trajectory& traj, int nev,
                                const std::optional<Eigen::MatrixXd>& basis, bool keepMatrices = false);

}  // namespace flexmb::analysis
