#pragma once
// ParaView time series of a simulation (or of load steps, or mode shapes): one VTK XML UnstructuredGrid (.vtu, ASCII)
// per output time and a .pvd collection naming them with their times. Geometry from MechanismGeometry (the points of
// the drawn elements in model coordinates, z = 0 for planar models):
//   * cells: one VTK_POLY_LINE (type 4) per beam / truss (its sampled points), one VTK_VERTEX
//     (type 1) per joint (hinge);
//   * point data: "displacement" (3 components, from the initial configuration), "rotation" (the
//     rotation from the initial configuration as a rotation vector, axis times angle in rad: of the
//     section frame along a spatial beam, else of the orientation node at the point's position node;
//     planar models about z), "node_label" (the position node's label, 0 for points inside a beam);
//   * cell data: "element_label", "deformation", "deformation_rate", "stress" (the element's e, ed
//     and sigma in keyword order, as many components as the model's largest element has
//     deformations, unused components 0);
//   * field data: TimeValue.
// Every value is checked to be finite first (std::invalid_argument naming quantity and time).
#include <string>
#include <vector>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "io/pictures/MechanismGeometry.hpp"

namespace flexmb::io {

// The .vtu document of one state at time t.
std::string renderVtu(const MechanismGeometry& geometry, const core::StateOutputs& state, double t);

// Writes <prefix>.pvd and <prefix>_vtu/<stem>_NNNNN.vtu (stem = the prefix's file name), creating
// the folder. Returns the paths written, the .pvd first. Throws std::runtime_error on write
// failures (naming the path), std::invalid_argument on wrong sizes or non-finite values.
std::vector<std::string> writeVtkSeries(const std::string& prefix, const core::Model& model,
                                        const core::Trajectory& traj);

}  // namespace flexmb::io
