#pragma once
// Results of a refined model at the original nodes and elements (`--refine N`, core::Model::unrefined):
// the writers (io/formats/ResultWriter, SpacarResults, the analyses' tables) pass what a refined run
// computed through these, so that its files have the columns, variables and layout of the model as
// read, under its labels, with the refined run's values there. A refined model keeps the original's
// coordinates [0, nx) and deformations [0, ne) first (core/model/Refinement.hpp), so the values are the
// leading entries; a split element's deformations and stresses are those of its part at node p.
// `--refined-results` (io::ReadOptions::refinedResults) leaves Model::unrefined null: then every
// function here returns its input unchanged.
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"
#include "io/formats/SpacarResults.hpp"

namespace flexmb::io {

// The model the result files describe: the model as read for a refined one, else the model itself.
const core::Model& resultModel(const core::Model& model);

// x, xd, xdd (and the USERSIG forces) at the original coordinates, e, ed, edd, sig at the original
// deformations; the rest (times, statistics, tracked outputs) as it is.
core::Trajectory originalTrajectory(const core::Model& model, const core::Trajectory& traj);

// The SPACAR-shaped results in the original model's layout (its lnp, le, role-sorted x and e): the
// per-step state, fxt, fx, fxgrav, e, ed, edd, sig and the mode shapes in x (modex) at the original
// nodes and elements; the frequencies, the state-space model (mode 9, between named channels) and
// the extra .sbd variables as they are. What is over the refined model's degrees of freedom has no
// place in the original's layout and is left out: dx, de, bigd, M0 .. N0, the mode shapes in q
// (modeq) and the .ltv's M0 and K0B.
SpacarResults originalSpacarResults(const core::Model& model, const SpacarResults& results);

// The table without the columns that name a node, coordinate, element or deformation the refinement
// added ("node117.x", "F.node117.y", "x:node117.x", "PLBEAM121.e2_bending_p", "stress_PLBEAM121");
// the other columns (times, frequencies, maxima over the whole mesh and the element they are at) stay.
CsvTable originalColumns(const core::Model& model, CsvTable table);

}  // namespace flexmb::io
