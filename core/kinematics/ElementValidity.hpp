#pragma once
// Element validity over a whole model: is every element's deformation measure still valid at a
// configuration x? The PLBEAM bending of Eq. 3b/3c (l0 sin theta) is exact only while each node
// turns less than 90 degrees against the chord; beyond that a converged equilibrium or a
// simulated state can sit in a spurious, nearly stress-free fold. Statics checks every converged
// load step, dynamics every output time (not the right-hand side: this is a diagnostic, not a
// constraint).
#include <Eigen/Core>
#include <optional>
#include <string>

#include "core/model/Model.hpp"

namespace flexmb::core {

struct InvalidElement {
  int element = -1;  // index into Model::elements
  ElementValidity detail;
  std::string message;  // "element 7 (PLBEAM): node 108 rotated 171.2 degrees against its chord, ..."
};

// The first element (in model order) outside its validity at x (size Model::nx), or nullopt.
// Allocates only when it finds one (the message).
std::optional<InvalidElement> firstInvalidElement(const Model& model, const Eigen::VectorXd& x);

}  // namespace flexmb::core
