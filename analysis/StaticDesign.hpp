#pragma once
// What a designer reads from a static run besides the coordinates (issue 53 item 1), per load step:
//   * the largest von Mises stress of each beam and truss with a cross-section (the VISUALIZATION
//     section's CROSSTYPE / CROSSDIM, core::ElementAppearance), by the formula of flexmb's
//     stressbeam.m (tools/octave): normal stress N/A + My z/Iy - Mz y/Iz (+ the BEAMW bimoment's
//     B y z/Cw) and St Venant torsion shear (rectangle: the exact series; circle: T r/Ip), von Mises
//     sqrt(s^2 + 3 t^2) over both ends and the exterior of the section; the shear of the shear forces
//     is left out (slender beams). Section forces from the step's sigma (reaction stresses included):
//     N = sigma_1, moments and torque l0 times the generalised stresses (core/elements);
//   * the support reactions: at every node with a fixed or input coordinate, the force (and moment)
//     the support exerts on the model, fxt minus the loads applied there (core::ResultQuantities);
//     spatial orientation nodes as a global moment;
//   * the compliance of a named node: C = T^T A (K0 + G0)^-1 A^T T with A the node's rows of the
//     first-order transfer functions F_q at the equilibrium, the displacement per unit load at the
//     node; a position node together with the orientation node it shares a beam end with (planar
//     3 x 3: x, y, angle; spatial 6 x 6: x, y, z and rotations about the global axes, T turning the
//     Euler parameters' rows into those rotations), as SPACAR Light's CMglob.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "analysis/Statics.hpp"
#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"
#include "io/formats/SpacarResults.hpp"

namespace flexmb::analysis {

// The section forces at one beam end and the section they act on.
struct SectionLoads {
  double N = 0.0, T = 0.0, My = 0.0, Mz = 0.0, B = 0.0;  // N, N m, N m, N m, N m^2
};
// The largest von Mises stress (Pa) over the exterior of a rectangle (width along local y, thickness
// along z) or a circle (diameter = width); 0 for an unknown section.
double sectionVonMises(const core::ElementAppearance& section, const SectionLoads& loads);

struct ElementStress {
  int element = -1;  // index into Model::elements
  double vonMises = 0.0;
};
// Each element with a section and a deformation that is not rigid (SPACAR Light's default leaves the
// rigid ones out), in the model's element order, at one step.
std::vector<ElementStress> elementStresses(const core::Model& model, const StaticStep& step);
// The largest of them (element -1 when there is none).
ElementStress largestStress(const core::Model& model, const StaticStep& step);
// The elements elementStresses reports (the same order).
std::vector<int> stressedElements(const core::Model& model);

// Reaction components at the supported nodes, in node order: "R.F.node1.x" (N), "R.M.node2.z" (N m;
// planar orientation nodes "R.M.node2.angle").
// extraLoads (nx, empty: none): nodal loads beyond the model's in the step's equilibrium (a sweep's
// holding load), which the reaction stresses balance too.
std::vector<std::pair<std::string, double>> supportReactions(const core::Model& model, const StaticStep& step,
                                                             const Eigen::VectorXd& extraLoads = Eigen::VectorXd());
// The nodes supportReactions reports (indices into Model::nodes): a fixed or input coordinate each.
std::vector<int> supportedNodes(const core::Model& model);

struct NodeCompliance {
  int label = 0;                        // the node the user named
  int position = -1, orientation = -1;  // indices into Model::nodes (-1: none)
  std::vector<std::string> names;       // x, y[, z], angle | rx, ry, rz
  Eigen::MatrixXd C;                    // empty: K0 + G0 singular at the step
};
// The nodes a compliance is asked for, checked: an error message naming the first label the model
// does not have (empty: all there).
std::string checkComplianceNodes(const core::Model& model, const std::vector<int>& labels);
// The compliance of each named node at one step (one linearisation for all).
std::vector<NodeCompliance> nodeCompliances(const core::Model& model, const StaticStep& step,
                                            const std::vector<int>& labels);

// The compliances of the named nodes at every step of a run (run.steps' order).
using StaticCompliances = std::vector<std::vector<NodeCompliance>>;
StaticCompliances runCompliances(const core::Model& model, const StaticRun& run, const std::vector<int>& labels);

// The tables: per load step the stress of every element elementStresses reports ("stress_BEAM3",
// Pa); the compliance rows (load_step, initial_factor, load_factor, node, row: 1..n in the order of
// the node's `names`, then the row of C in the columns x, y, z, angle, rx, ry, rz, warping that the
// node has, the others empty).
io::CsvTable stressTable(const core::Model& model, const StaticRun& run);
io::CsvTable complianceTable(const StaticRun& run, const StaticCompliances& compliances);

// The .sbd variables under SPACAR Light's names (its results struct), one entry per SPACAR load step
// (the steps spacarFromStatics stores): stressmax (1 x tdef, Pa: the largest over the elements),
// stressel (nel x tdef, Pa, rows by element label: each element's; 0 without a section), Freac and
// Mreac (3 x tdef x nnodes by node label, planar 2 and 1: the supported nodes' reactions, zero
// elsewhere), CMglob (n x n x tdef per named node as CMglob_node<label>; SPACAR Light keeps one per
// node in its struct, a MAT file needs one name each).
std::vector<io::SpacarVariable> spacarDesignVariables(const core::Model& model, const StaticRun& run,
                                                      const StaticCompliances& compliances);

}  // namespace flexmb::analysis
