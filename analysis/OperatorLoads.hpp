#pragma once
// Internal to the reduced operators: the time-dependent loads they carry for a model, in this order
// (XFT; ESIGT on active deformations; EREF): what training fits (OperatorTraining.cpp) and what a
// model must still have for them to serve it (OperatorPolicy.cpp).
#include <vector>

#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"

namespace flexmb::analysis {

inline std::vector<core::OperatorLoad> timeLoads(const core::Model& model) {
  using core::OperatorLoad;
  std::vector<OperatorLoad> loads;
  for (const auto& l : model.timeForces) loads.push_back({OperatorLoad::Kind::NodalForce, l.index});
  for (const auto& l : model.timeStresses)
    if (model.eRole[l.index] == core::Role::Dynamic || model.eRole[l.index] == core::Role::Calculable)
      loads.push_back({OperatorLoad::Kind::Stress, l.index});
  for (const auto& l : model.references) loads.push_back({OperatorLoad::Kind::Reference, l.index});
  return loads;
}

}  // namespace flexmb::analysis
