#pragma once
// simulate's file set, one writer for every front end (the command line, the Octave gateway,
// Python): the trajectory's tables and .mat first, renamed into place; then each product derived
// from them (the linearisation along the trajectory of modes 3/4, SPACAR's .sbd/.sbm, the restart
// echo, the VTK series, the HTML animation) made and written on its own, so that a failure in one
// keeps the run (io::OutputSet::attempt); the manifest last. The one recipe here that writes:
// the derived products are computed only after the run's own files are safe on disk.
#include <Eigen/Core>
#include <ostream>
#include <string>
#include <vector>

#include "analysis/Simulation.hpp"
#include "analysis/TrajectoryModes.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"
#include "io/formats/OutputFile.hpp"

namespace flexmb::analysis {

// Which files (the command line's --format, --linearize, --matrices, --echo, --vtk, --html).
struct SimulationFiles {
  bool csv = true;        // <prefix>_x.csv ... _sig.csv (and _rot.csv with orientation nodes)
  bool mat = true;        // <prefix>.mat and SPACAR's <prefix>.sbd (.sbm with a linearisation)
  int linearize = 0;      // mode 4: this many eigenfrequencies per output time, <prefix>_frequencies.csv
  bool matrices = false;  // mode 3: the linearised matrices per output time, <prefix>_linear.mat
  std::string echo;       // a restart .dat of the final state (empty: none)
  bool vtk = false, html = false;
  // A driven rigid mechanism's nodal forces per output time (analysis::InverseDynamicsRun::fxt):
  // <prefix>_fxt.csv with the tables.
  const std::vector<Eigen::VectorXd>* fxt = nullptr;
  // simulate --plot: the time history of these columns (historyColumns' names) in
  // <prefix>_history.svg (empty: none).
  std::vector<std::string> plot;
  // The job's wall time before writing (SimulateJob::wallSeconds; negative: not given): the manifest
  // then says the whole command's, writing included.
  double secondsBefore = -1.0;
};

struct WrittenSimulation {
  std::vector<std::string> paths;  // every file written, the manifest last
  bool incomplete = false;         // a derived product failed (said on err and in the manifest)
  double seconds = 0.0;            // writing them (the manifest's own writing aside)
};

// Writes the file set; out gets the progress lines ("linearised at ...", "wrote ..." of the
// pictures), err the failures. The manifest's status is "complete" or why the run stopped. Throws
// std::runtime_error when the trajectory's own files cannot be written.
WrittenSimulation writeSimulation(io::OutputSet& files, const core::Model& model, const SimulationOptions& opt,
                                  const core::Trajectory& traj, bool interrupted, const SimulationFiles& what,
                                  std::ostream& out, std::ostream& err);

// The trajectory's own files (what.csv: the tables, what.fxt's; what.mat: <prefix>.mat) under
// temporary names of the set, not yet renamed: writeSimulation's first step, and a design study's
// variant files.
void writeTrajectoryFiles(io::OutputSet& files, const core::Model& model, const core::Trajectory& traj,
                          const SimulationFiles& what);

// The run's integrator and time span for the manifest: "integrator" and "integration" ("0 to 0.7 s,
// 700 output intervals, reltol 0.001, abstol 1e-06, max step 0.07 s").
void describeIntegration(io::OutputSet& files, const core::Model& model, const SimulationOptions& opt);

// <prefix>_frequencies.csv: time, f1_Hz..fn_Hz (|s| of Eq. 15), zeta1..n, frozen_f1_Hz..n (the
// configuration-frozen spectrum), n = columns; empty cells where fewer were found.
io::CsvTable trajectoryFrequencyTable(const TrajectoryModes& modes, int columns);
// <prefix>_fxt.csv: time and the total nodal force on every coordinate.
// <prefix>_tracked.csv (simulate --outputs tracked): time, then per tracked coordinate x:, xd:, xdd:
// and per tracked deformation e:, ed:, edd:, sig: with the column names of the _x / _e tables.
io::CsvTable trackedOutputTable(const core::Model& model, const core::Trajectory& traj);
io::CsvTable nodalForceTable(const core::Model& model, const core::Trajectory& traj,
                             const std::vector<Eigen::VectorXd>& fxt);

// simulate --plot's columns, normalised: a coordinate "node6.x" or "x:node6.x", its rates "xd:node6.x",
// "xdd:node6.x"; a deformation with its stem "e:PLBEAM3.e2_bending_p", "ed:", "edd:", "sig:" (its
// generalised stress); "max_stress" (the largest von Mises stress over the elements with a
// VISUALIZATION section, analysis/StaticDesign.hpp) and "stress_PLBEAM3" (one such element's). Throws
// std::invalid_argument naming the first label the model does not have and listing those it has.
std::vector<std::string> historyColumns(const core::Model& model, const std::vector<std::string>& labels);
// time and those columns at every output time (a run with tracked outputs: from its tracked table).
io::CsvTable historyTable(const core::Model& model, const core::Trajectory& traj,
                          const std::vector<std::string>& columns);

}  // namespace flexmb::analysis
