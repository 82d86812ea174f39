#pragma once
// Mesh refinement without editing the model (`--refine N`): every flexible beam (PLBEAM, PLBEAMNL,
// BEAM, BEAMNL, BEAMW) split into N equal elements along its reference centre line. The refined
// model keeps the original's nodes, elements, coordinate and deformation indices and labels (the
// original element keeps its label as the sub-element at its node p), so every load, mass, input,
// fix, transfer channel and output that names an original node still names it; the new nodes and
// elements come after them with labels above the largest used; Model::unrefined keeps the model as
// read, so that results can be written at its nodes and elements. docs/models.md "Refining the mesh"
// gives the rules for users.
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::core {

struct RefinementSummary {
  int parts = 1;
  int split = 0;             // elements split
  int elements = 0;          // the refined model's user elements (L2MIN1 left out)
  int nodes = 0;             // the refined model's nodes
  int originalNodes = 0;     // the original model's nodes: indices [0, originalNodes) of the refined one
  int originalElements = 0;  // the original model's elements (L2MIN1 included): indices [0, originalElements)
  // Flexible beams left whole, with the reason ("PLBEAM 7: an input deformation (INPUTE)").
  std::vector<std::string> whole;
  // "refined: every flexible beam split in 8 (85 elements, 86 nodes)" (+ the elements left whole).
  std::string text() const;
};

struct RefinedModel {
  Model model;
  RefinementSummary summary;
};

// The model with every flexible beam split in `parts` (>= 1; 1 returns the model unchanged).
// A beam is flexible when one of its deformations that is not fixed has stiffness; rigid beams, hinges,
// trusses (a split truss would be a chain of pins that no deformation holds sideways) and the
// automatic L2MIN1 elements stay as they are. New nodes are interpolated between the element's end
// nodes in the reference configuration (positions, angles and warping linearly, Euler parameters by
// normalised linear interpolation); each sub-element takes the element's stiffness, damping, mass
// per length, direction vector and deformation roles, except that a released (RLSE) deformation is
// released only where it was: a bending deformation at p in the first sub-element, at q in the last,
// an elongation or a torsion in the last; the sub-elements' other copies of it are DYNE when it has
// stiffness, fixed when it has none. A beam with an input deformation (INPUTE, INPUTET), a
// time-dependent stress (ESIGT, EREF), a bending prestress or non-zero initial values of its
// deformations (E, ED, STARTDE) stays whole (said in RefinementSummary::whole). Throws std::invalid_argument for
// parts < 1 and for a restart state (LENGTH0, XREF): its X is not the reference configuration.
// `options` are the ones the model's elements were created with (the PLBEAM elongation).
RefinedModel refineModel(const Model& model, int parts, const ElementOptions& options);

}  // namespace flexmb::core
