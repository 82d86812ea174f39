#pragma once
// One model's evaluation workspace, shared by the evaluators of one analysis (the equations of motion
// that integrate, the probe that computes output quantities, the linearisation of an implicit
// integrator's Jacobian, the result quantities): Pinocchio's Model/Data split. It holds what does
// not depend on an evaluator's history: the kinematic structure, KLU's analysis and scratch
// (KinematicsWorkspace), the element mass blocks (Inertia: recomputed at every evaluation before
// use), the constitutive data (Stresses), the Richardson steps (ElementSteps) and the sparse nodal
// matrices of the linearisation (NodalMatrices, made at first use).
// Each evaluator keeps its own warm start (configuration, restart points, predictor, element
// Jacobians, numeric factorisations and their pivot orders, scalings chosen at a first solve), so
// sharing changes no bit of any result (core/tests/test_workspace.cpp).
// Ownership and threading: evaluators hold a reference; the workspace must outlive them. It serves
// one thread at a time and one call at a time: nothing in it carries over from one call to the
// next, so evaluators may alternate call by call (ode45's stages and its output times), but never
// run concurrently or inside one another's call. A result an evaluator leaves in the shared part
// (Inertia's blocks, the nodal matrices of Linearization::atRest read by constrainedPencil) is its
// until another evaluator on the workspace is called.
#include <memory>

#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/NodalMatrices.hpp"
#include "core/dynamics/Stresses.hpp"
#include "core/kinematics/DirectionalDerivative.hpp"
#include "core/kinematics/KinematicsWorkspace.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

class Workspace {
 public:
  explicit Workspace(const Model& model)
      : model_(model), kinematics_(model), inertia_(model), stresses_(model), steps_(model) {}
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

  const Model& model() const { return model_; }
  KinematicsWorkspace& kinematics() { return kinematics_; }
  Inertia& inertia() { return inertia_; }
  const Stresses& stresses() const { return stresses_; }
  const ElementSteps& steps() const { return steps_; }
  // Made at the first call (only linearisations use them).
  NodalMatrices& nodal() {
    if (!nodal_) nodal_ = std::make_unique<NodalMatrices>(model_);
    return *nodal_;
  }

 private:
  const Model& model_;
  KinematicsWorkspace kinematics_;
  Inertia inertia_;
  Stresses stresses_;
  ElementSteps steps_;
  std::unique_ptr<NodalMatrices> nodal_;
};

}  // namespace flexmb::core
