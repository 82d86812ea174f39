#pragma once
// Model diagnostics that make an analysis meaningless or surprising, in the user's words:
//   * values too large to compute with (1e308 in ESTIFF, XM, EM, GRAVITY, XF, X ...): products of
//     them overflow double precision long before any solver could say why;
//   * no degrees of freedom (nothing to integrate, no eigenfrequency);
//   * degrees of freedom without mass (simulate and modes need M positive definite);
//   * dynamic (DYNE) deformations without stiffness (no ESTIFF): mechanism degrees of freedom. Legal
//     (a hinge's free rotation is one), but for a beam deformation usually a forgotten ESTIFF, and
//     the reason `modes` shows a zero or negative frequency and `static` a singular tangent; likewise
//     a free warping coordinate whose BEAMWs have no warping stiffness;
//   * an initial assembly that lands on another branch: the kinematic solve from the file's nodal
//     coordinates (X, BETA) with the initial degrees of freedom (E, STARTDE) converged to a folded
//     configuration (a beam node turned past 90 degrees against its chord).
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::core {

struct ModelDiagnosis {
  std::vector<std::string> overflow;               // "ESTIFF of element 3: 1e+308"
  std::vector<std::string> mechanismDeformations;  // "e(element 3, 2) (PLBEAM, no ESTIFF)"
};

// No solving: reads the model's values only.
ModelDiagnosis diagnoseModel(const Model& model);

// Degrees of freedom whose mass vanishes in the initial configuration (names); empty when every one
// has mass. Needs a kinematic solve; throws KinematicsError when the initial assembly fails.
std::vector<std::string> masslessDegreesOfFreedom(const Model& model);

// Empty when the initial assembly is on the branch of the file's coordinates; otherwise what went
// wrong and what to change.
std::string initialAssemblyProblem(const Model& model);

// Values above this magnitude are reported as overflowing (their squares exceed double's range).
constexpr double kOverflowLimit = 1e100;

}  // namespace flexmb::core
