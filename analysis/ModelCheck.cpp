#include "analysis/ModelCheck.hpp"

#include <exception>

#include "core/kinematics/GeometricTransferFunctions.hpp"

namespace flexmb::analysis {

AssemblyCheck checkAssembly(const core::Model& model, bool mass) {
  AssemblyCheck a;
  // Not square: no configuration to solve for (said as such, without a Newton iteration's time,
  // count and residual that never ran).
  int calculable = 0, constraints = 0;
  for (int i = 0; i < model.nx; ++i) calculable += model.xRole[i] == core::Role::Calculable;
  for (int i = 0; i < model.ne; ++i) constraints += model.eRole[i] != core::Role::Calculable;
  if (calculable != constraints) {
    a.error = "the kinematic equations are not square: " + std::to_string(constraints) + " (fixed, input and " +
              "dynamic deformations) for " + std::to_string(calculable) + " calculable coordinates";
    return a;
  }
  try {
    a.problem = core::initialAssemblyProblem(model);
    if (a.problem.empty() && mass) a.massless = core::masslessDegreesOfFreedom(model);
  } catch (const core::KinematicsError& e) {
    a.error = e.what();
  }
  return a;
}

core::ModelDiagnosis diagnose(const core::Model& model) { return core::diagnoseModel(model); }

std::string ModelCheck::kinematicsText() const { return core::formatReport(kinematics); }

ModelCheck checkModel(const core::Model& model) {
  ModelCheck c;
  try {
    c.kinematics = core::checkKinematics(model);
  } catch (const std::exception& e) {
    c.kinematicsError = e.what();
  }
  c.diagnosis = core::diagnoseModel(model);
  if (c.kinematicsError.empty() && c.kinematics.wellPosed()) c.assembly = checkAssembly(model, false);
  return c;
}

}  // namespace flexmb::analysis
