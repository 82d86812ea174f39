#pragma once
// Static equilibrium (mode 10): Newton on the independent coordinates with tangent Kbar + Gbar,
// over the load steps, cutting a load step into halves when Newton fails, and eigenfrequencies in
// each equilibrium.
//
// Load steps with SPACAR's meaning (ITERSTEP maxit nsteps tol c4 c5 ninit):
//   loads = mu (XF, INPUTX values, gravity) + s (DELXF, DELINPX), where DELXF and DELINPX are the
//   TOTAL increments reached at the last step (SPACAR Light writes the user's final load as DELXF).
//   Load step 0 is the equilibrium under the initial loads (mu = 1, s = 0); load step i = 1..nsteps
//   adds i / nsteps of the increments. So a run has nsteps + 1 load steps, which SPACAR stores as
//   records 1..nsteps + 1 (io/results.md). Before load step 0 the initial loads are ramped over
//   ninit steps, mu = k / ninit (ninit = 0 or absent: at once, sub-stepped when Newton needs it);
//   these ramp steps are computed and reported (CSV) but are not load steps of the .sbd.
//   Without any DEL* increment and with ninit = 0 the initial loads are the increments: load step i
//   has mu = i / nsteps (load step 0 is the unloaded model), so XF with n steps gives n distinct
//   equilibria; with ninit > 0 they ramp over ninit and load steps 1..nsteps repeat load step 0
//   (zero increments), as SPACAR Light's "initial loads only" files (ITERSTEP 10 1 tol 1 1 n) expect.
// Gravity is an initial load: it is a dead load present from the start, like XF, so it is ramped
// with mu. Every path then starts from the unloaded reference configuration (an exact equilibrium,
// where the first Newton step begins), and the first steps of a heavy model are as small as the
// ramp makes them. Time-dependent loads (XFT at t0) are not ramped.
#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/Modes.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/CsvTable.hpp"
#include "solvers/KineticStability.hpp"
#include "solvers/StaticEquilibrium.hpp"

namespace flexmb::analysis {

// Equilibrium of lin's model at load factor s from the start eta (updated in place). Spatial full
// models: the loads are evaluated in the configuration itself and the tangent is factorised sparse
// (Linearization::staticTangent), `stable` from the dense Kbar + Gbar at the solution; pass
// options.correctionMonotonicity as staticAnalysis does for them (closed loops). Otherwise the
// dense tangent.
solvers::StaticResult equilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                  const solvers::NewtonOptions& options = {}, double initialFactor = 1.0);

// One point of the load schedule: mu (initial loads) and s (DEL* increments, 1 = the total), and
// its SPACAR load step (0..nsteps; -1 for a ramp step of the initial loads before load step 0).
struct LoadPoint {
  double initial = 1.0;
  double increment = 0.0;
  int loadStep = -1;
};
// The schedule described above; loadSteps > 0 overrides ITERSTEP's nsteps (--steps).
std::vector<LoadPoint> loadSchedule(const core::Model& model, int loadSteps = 0);
struct StaticStep {
  double loadFactor = 0.0;     // s: fraction of the DEL* increments (1 at the last step)
  double initialFactor = 1.0;  // mu: fraction of the initial loads
  int loadStep = -1;           // SPACAR's load step 0..nsteps (-1: a ramp step before load step 0)
  Eigen::VectorXd eta, x, e, sigma;
  Frequencies frequencies;
  Eigen::VectorXd buckling;      // load factors (only when asked for)
  solvers::StaticResult newton;  // of the last (sub-)step; newton.stable: see `kinetic`
  // Under dead moments (a non-zero Gskew) the kinetic criterion on K + G + Gskew, M, which then sets
  // newton.stable (unless Undecided); otherwise empty and newton.stable is K + G positive definite.
  std::optional<solvers::KineticStability> kinetic;
  int iterations = 0;             // Newton iterations of this load step, failed and sub-step attempts included
  core::LinearizedSystem system;  // M0, K0, G0, ... in the equilibrium (SPACAR's .sbm)
};

// The step's stability in words, for every front end: "stable", "K0 + G0 not positive definite",
// "flutter (lambda = a +- bi (rad/s)^2) under the dead moments", "divergence (...) under the dead moments";
// where the kinetic test could not be made (a mass matrix not positive definite) the energy criterion's
// verdict and why.
std::string stabilityVerdict(const StaticStep& step);

struct StaticRun {
  std::vector<StaticStep> steps;  // every computed step, initial-load ramp steps included
  int loadSteps = 0;              // nsteps: the run has load steps 0..nsteps
  bool completed = true;
  bool interrupted = false;  // stopped by StaticOptions::interrupt (then completed = false)
  std::string stopReason;
};

struct StaticOptions {
  int nev = 6;        // eigenfrequencies per equilibrium (0: none)
  int loadSteps = 0;  // > 0 overrides ITERSTEP's number of load steps
  int buckling = 0;   // buckling load factors per equilibrium
  // Node labels whose compliance StaticJob computes at every step after the run (StaticDesign.hpp).
  std::vector<int> complianceNodes;
  EigenPath eigenPath = EigenPath::Auto;
  std::function<void(int, int)> onStep;  // progress: called before load step i (0-based) of n
  // Set asynchronously (Ctrl-C): the run stops before its next load step or Newton sub-step and
  // keeps the equilibria reached (analysis/Interrupt.hpp); interruptSignal names the signal.
  const std::atomic<bool>* interrupt = nullptr;
  const std::atomic<int>* interruptSignal = nullptr;
};
StaticRun staticAnalysis(const core::Model& model, const StaticOptions& options);
// The largest section force of each kind over the user's elements that deform (any dynamic or
// released deformation; the reaction stresses of their fixed deformations included), from a step's
// sigma: max_axial_force (N), max_bending_moment (planar), max_bending_moment_y / _z (about the
// section's local axes), max_torsion_moment (N m; a beam's generalised stress times its length), in
// this order, each kind the model has (whatever sigma holds), with the element where it is largest.
// An element's reference length l0: its own where it keeps one (PLBEAM), else the distance between
// its first and last position node in the initial configuration.
double elementLength(const core::Model& model, const core::ElementEntry& element);
struct SectionForceMaximum {
  std::string name;
  double value = 0.0;
  int element = -1;  // index into Model::elements; -1 while every value is zero
};
std::vector<SectionForceMaximum> sectionForceMaxima(const core::Model& model, const Eigen::VectorXd& sigma);

// The nodal loads a step applies (initial loads x initial_factor + DEL* increments x load_factor, XFT
// at t0), one per loaded coordinate: "F.node3.y" (a force; "M.node3.angle" on a planar orientation
// node) and "M.node4.x" (a global moment about x on a spatial orientation node). Gravity is apart.
std::vector<std::pair<std::string, double>> appliedNodalLoads(const core::Model& model, const StaticStep& step);

// The load steps as a table, the one every front end writes (`flexmb static`, the study): load_step,
// initial_factor, load_factor, every nodal coordinate, f1_Hz... (as many as any step has),
// buckling1..buckling<buckling> (a step with fewer has empty cells), then per step its
// sectionForceMaxima and its appliedNodalLoads (columns added at the end: scripts read the others
// by place).
io::CsvTable staticTable(const core::Model& model, const StaticRun& run, int buckling);
// The same with the options as arguments; onStep(i, n): progress, called before load step i of n.
StaticRun staticAnalysis(const core::Model& model, int nev, int loadSteps = 0 /* 0: from the file */,
                         const std::function<void(int, int)>& onStep = {},
                         int buckling = 0 /* number of buckling load factors per step */);

}  // namespace flexmb::analysis
