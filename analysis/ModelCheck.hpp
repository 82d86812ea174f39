#pragma once
// Mode 0 (SPACAR's kinematic analysis) and the checks every analysis starts with: the recipes behind
// `flexmb check`, `flexmb show` and the front ends' model loading. The mechanics (rank analysis,
// diagnostics, the kinematic solve) live in core; this composes them once.
#include <string>
#include <vector>

#include "core/kinematics/KinematicCheck.hpp"
#include "core/linearization/ModelDiagnostics.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

// The initial configuration: assembled on the branch of the file's coordinates, and (when asked)
// mass on every degree of freedom.
struct AssemblyCheck {
  std::string problem;                // why the assembly left the file's branch ("" = fine)
  std::string error;                  // the kinematic solve failed (its message; "" = it converged)
  std::vector<std::string> massless;  // degrees of freedom without mass (names), when asked
  bool ok() const { return problem.empty() && error.empty() && massless.empty(); }
};
AssemblyCheck checkAssembly(const core::Model& model, bool mass);

// No solving: overflowing values, DYNE deformations without stiffness (core::diagnoseModel).
core::ModelDiagnosis diagnose(const core::Model& model);

struct ModelCheck {
  core::KinematicReport kinematics;  // rank, degrees of freedom, redundant or missing equations
  std::string kinematicsError;       // the rank analysis itself failed ("" = it ran)
  core::ModelDiagnosis diagnosis;
  AssemblyCheck assembly;  // only when the kinematics are well posed
  bool wellPosed() const { return kinematicsError.empty() && kinematics.wellPosed() && assembly.ok(); }
  // The kinematic report as `flexmb check` prints it (core::formatReport).
  std::string kinematicsText() const;
};
ModelCheck checkModel(const core::Model& model);

}  // namespace flexmb::analysis
