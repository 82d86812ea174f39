#pragma once
// Reduction bases q = V eta (paper Eq. 17-23) built from the model's linearisation: the partition
// of Eq. 20 (large-rotation coordinates keep identity columns; by default the hinge DOFs and the
// DYNX orientation coordinates), the modal basis of the q_s subproblem (Eq. 21) and the SVD-modal
// basis over equidistant equilibrium configurations along a path (Eq. 22-23).
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct ReductionOptions {
  std::string method = "modal";  // "modal" or "svd-modal"
  int modes = 3;                 // r: modes per configuration
  // modal: "mass" (default; V_s^T M_s V_s = I, as MATLAB's eig(K, M)) or "unit" (unit columns).
  // ode45's absolute tolerance acts on eta, so the choice changes the reduced run's step sizes.
  std::string normalise = "mass";
  std::optional<std::vector<int>> large;  // q indices with identity columns; default: hinges, DYNX angles
  // SVD-modal path: nodal coordinate prescribed from..to in `configs` equidistant equilibria.
  int configs = 10;
  double weight = 0.0;      // a in omega^-a
  double threshold = 0.01;  // keep singular vectors with a larger share of the sum
  int count = 0;            // > 0: keep exactly this many instead
  int node = 0, component = 1;
  double from = 0.0, to = 0.0;
  std::function<void(int done, int total)> onConfig;  // progress over the SVD-modal configurations
};

struct ReductionResult {
  Eigen::MatrixXd V;  // nq x (n_l + kept)
  // How it was made (the front end writes it with the basis: io::BasisInfo).
  std::string method;
  std::vector<std::pair<std::string, std::string>> parameters;  // e.g. {"r", "4"}, {"a", "1"}
  std::vector<int> large;                // q indices with identity columns (column j <-> large[j])
  Eigen::VectorXd scaledSingularValues;  // SVD-modal only
  Eigen::VectorXd omegaSmall;            // modal: eigenfrequencies (rad/s) of the q_s subproblem kept
};

// The default large-rotation coordinates: DYNE deformations of PLHINGE elements and DYNX
// orientation coordinates, as q indices.
std::vector<int> defaultLargeCoordinates(const core::Model& model);

ReductionResult buildBasis(const core::Model& model, const ReductionOptions& options);

}  // namespace flexmb::analysis
