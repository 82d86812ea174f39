#pragma once
// Design studies: one template model (io/templates/ModelTemplate) and a table of parameter values, the same
// analyses run on every variant, and a one-line summary of each (the quantities a designer ranks
// by). The front end (`flexmb study`) runs the variants in worker processes, writes their files
// and collects the summaries (io/templates/StudySummary); this file holds the recipe: which variants there
// are, which of them a task runs, what each variant computes and summarises, and which variants are
// finished (resume).
//
// A further analysis (e.g. transfer functions, SPACAR mode 9) plugs in at three places: a field of
// StudyAnalyses (and its line in describe()), its call in runVariant with its result in
// VariantResults, and its quantities in summarize(); the front end adds its option and its file.
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/Modes.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/Statics.hpp"
#include "analysis/Sweep.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/kinematics/KinematicCheck.hpp"
#include "core/model/Model.hpp"
#include "io/templates/ModelTemplate.hpp"
#include "io/templates/StudySummary.hpp"
#include "io/templates/StudyTable.hpp"

namespace flexmb::analysis {

// ---- variants ----------------------------------------------------------------------------------

struct Variant {
  int number = 0;    // 1-based, the study's order
  std::string name;  // result folder: the table's `name`, else v0001, v0002, ...
  io::ParameterValues values;
};

constexpr int kMaxVariants = 1000000;

// The variants of a table (may be null) and grid axes: every table row combined with every grid
// point (the first axis varies slowest, like nested loops in the order given). Throws
// std::invalid_argument when a parameter is given twice, nothing is given, or there are more than
// kMaxVariants.
std::vector<Variant> expandVariants(const io::ParameterTable* table, const std::vector<io::ParameterAxis>& grid);

// The variants task `task` (0-based) of `of` runs: every of-th variant starting at task (variants
// of similar cost, neighbours in the table, spread over the tasks). Indices into the variant list.
std::vector<int> taskShare(int count, int task, int of);

// ---- analyses ----------------------------------------------------------------------------------

// --accuracy EPS / --error-estimate of a study (analysis/StudyAccuracy.hpp): the mesh every variant
// runs and the discretization error measured at the two ends of the parameter range; each variant
// adds its own integration and reduction errors (quantities discretization_error, integration_error,
// reduction_error, total_error_estimate, accuracy_met).
struct StudyAccuracy {
  double eps = std::numeric_limits<double>::quiet_NaN();  // NaN: --error-estimate (no target)
  int refine = 1;                                         // the mesh of every variant (the read options')
  // D at `refine`, the larger of the two ends' (NaN: not estimated); relative to `measure`.
  double discretization = std::numeric_limits<double>::quiet_NaN();
  bool reachable = true;  // the ladders met their share of EPS (false: the variants miss it, said before)
  std::string analysis;   // the analyses the ladders ran ("simulate", "static and modes")
};

struct StudyAnalyses {
  bool check = false;                 // the kinematic rank check (flexmb check); a variant that is not well posed fails
  int modes = 0;                      // eigenfrequencies in the initial configuration (flexmb modes); 0: not run
  using Statics = StaticOptions;      // nev, load steps (0: the file's ITERSTEP), buckling; as `flexmb static`
  std::optional<Statics> statics;     // flexmb static
  std::optional<SweepOptions> sweep;  // flexmb sweep (onPoint unused)
  std::optional<SimulationOptions> simulation;  // flexmb simulate (single stage; progress and interrupt unused)
  // simulate --target: each variant reduced with the smallest modal basis whose reduction error
  // estimate meets this (analysis/BasisForTarget.hpp); quantities sim_basis_vectors and
  // sim_reduction_estimate.
  std::optional<double> reductionTarget;
  // With reductionTarget: the variants that may share a basis and its reduced operators (those one
  // worker process runs; analysis/TargetOperators.hpp weighs their training against them). Not in
  // describe(): a variant's results meet the same target whichever basis it ran.
  int sharingVariants = 1;
  // Node labels whose tangent stiffness the static step reports (at the last equilibrium); empty:
  // every node that carries a load (XF, DELXF).
  std::vector<int> stiffnessNodes;
  std::optional<StudyAccuracy> accuracy;  // --accuracy / --error-estimate (analysis/StudyAccuracy.hpp)
  // Quantities computed from the parameters and the other quantities (muParser), in order.
  std::vector<std::pair<std::string, std::string>> derived;

  bool any() const { return check || modes > 0 || statics || sweep || simulation; }
  // Every setting as "name: value" lines, in a fixed order (the study's record and the variants'
  // fingerprints: a changed setting reruns every variant).
  std::string describe() const;
};

struct VariantResults {
  std::optional<core::KinematicReport> check;
  std::optional<Frequencies> modes;
  std::optional<StaticRun> statics;
  std::optional<SweepResult> sweep;
  std::optional<core::Trajectory> trajectory;
  std::string failure;  // why the variant failed; empty: it did not
  std::vector<std::string> notes;
  std::vector<std::pair<std::string, double>> quantities;  // the summary's quantity columns (NaN: none)
};

// Runs the analyses on one variant's model, in the order check, modes, static, sweep, simulate.
// Never throws for a model or numerical problem: the first failure is recorded in `failure` (the
// analyses after it do not run) and the quantities of what did run are kept. `parameters`: the
// names derived quantities may use besides the quantities (the variant's parameters and the
// template's definitions).
VariantResults runVariant(const core::Model& model, const StudyAnalyses& analyses,
                          const io::ParameterValues& parameters = {});

// The summary record of a variant (status ok or failed, reason, quantities).
io::StudyRecord summaryRecord(const Variant& variant, const VariantResults& results);
// A failed variant's record with no quantities (the template or the model could not be made).
io::StudyRecord failedRecord(const Variant& variant, const std::string& reason);

// Tangent stiffness at a node in an equilibrium: 1 / C_ii of the compliance C = A (Kbar + Gbar)^-1 A^T
// of the node's coordinates (A = their rows of F_q), per component: N/m along x, y, z; N m/rad for
// rotations (spatial orientation nodes: about the global axes, through 2 E(lambda)^T; planar: the
// angle). Components the model fixes are left out. Empty when the tangent is singular.
std::vector<std::pair<std::string, double>> nodeStiffness(const core::Model& model, const StaticStep& step,
                                                          int nodeLabel);

// ---- resume ------------------------------------------------------------------------------------

// The fingerprint of a variant: the template text, its parameter values, the analyses and the
// program version (64-bit FNV-1a, hex). A finished variant with another fingerprint is run again.
std::string variantFingerprint(const std::string& templateText, const io::ParameterValues& values,
                               const StudyAnalyses& analyses, const std::string& version);

enum class VariantState { NotRun, Finished, FinishedFailed, Stale };
// From the variant's manifest (<prefix>_run.txt, io/formats/OutputFile.hpp) and summary: finished when the
// manifest exists and names the same fingerprint and the summary reads back (the variants' files
// are committed without fsync, io::OutputSet::setSync: after a power failure a manifest may stand
// beside an empty summary, and the variant runs again); FinishedFailed when its status is
// "failed: ..."; Stale when the fingerprint differs (the template or the analyses changed since).
VariantState variantState(const std::string& manifestPath, const std::string& fingerprint,
                          const std::string& summaryPath);

}  // namespace flexmb::analysis
