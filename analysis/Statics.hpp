#pragma once
// Static equilibrium (mode 10): Newton on the independent coordinates with tangent Kbar + Gbar,
// over the load steps, cutting a load step into halves when Newton fails, and eigenfrequencies in
// each equilibrium.
//
// Load steps with SPACAR's meaning (ITERSTEP maxit nsteps tol c4 c5 ninit):
//   loads = mu (XF, INPUTX values) + s (DELXF, DELINPX), where DELXF and DELINPX are the TOTAL
//   increments reached at the last step (SPACAR Light writes the user's final load as DELXF).
//   1. the initial loads (XF and the INPUTX values, measured from X) are ramped first over ninit
//      steps, mu = k / ninit, s = 0 (ninit = 0 or absent: applied at once, with the first step);
//   2. then the increments in nsteps equal parts: mu = 1, s = i / nsteps.
//   Without any DEL* increment the initial loads ramp over ninit steps, or nsteps when ninit is 0,
//   so XF with n steps gives n distinct equilibria (never one equilibrium n times). Gravity and
//   time-dependent loads are not ramped.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "core/Linearization.hpp"
#include "solvers/StaticEquilibrium.hpp"

namespace flexmb::analysis {

// Equilibrium of lin's model at load factor s from the start eta (updated in place). Spatial full
// models: the loads are evaluated in the configuration itself and the tangent is factorised sparse
// (Linearization::staticTangent), `stable` from the dense Kbar + Gbar at the solution; pass
// options.correctionMonotonicity as staticAnalysis does for them (closed loops). Otherwise the
// dense tangent.
solvers::StaticResult equilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                  const solvers::NewtonOptions& options = {}, double initialFactor = 1.0);

// Natural frequencies (rad/s, ascending) of (K + G) v = w^2 M v; negative eigenvalues give -sqrt(|l|).
struct Frequencies {
  Eigen::VectorXd lambda, omega;
  Eigen::MatrixXd modes;       // M-orthonormal columns in eta
  Eigen::MatrixXd nodalModes;  // the same modes in x (nx x k; F_q V modes); empty from the sys-only overload
  std::string method;          // "dense" or "arpack-shift-invert" on the dense pencil, "sparse-constrained"
};
// lowestShift: ARPACK's shift found by inverse iteration instead of the diagonal ratios
// (solvers::EigenOptions), for pencils whose diagonals are axial (spatial beams: EA over bending,
// ~1e8 in the cross-spring pivot, where the diagonal shift costs ten times the restarts).
Frequencies naturalFrequencies(const core::LinearizedSystem& sys, int nev, bool lowestShift = false);

// Which eigenanalysis: the dense independent-coordinate pencil (Kbar + Gbar, Mbar), or ARPACK
// shift-invert on the sparse nodal pencil with the constraints (core::ConstrainedPencil, one sparse
// LU of [K - sigma M, C^T; C, 0]; full models only). Auto: sparse from kSparseEigenFrom degrees of
// freedom (below it the dense path is as fast and its q-space pencil is better conditioned: the nodal
// pencil carries axial over bending stiffness, ~1e-7 relative on a 999-DOF chain); the environment variable
// FLEXMB_EIGEN=dense|sparse forces either (comparisons, tests).
enum class EigenPath { Auto, Dense, Sparse };
constexpr int kSparseEigenFrom = 400;
EigenPath eigenPathFromEnvironment();
// After lin.atRest(..., withMass = true) gave sys. The sparse path falls back to the dense one when
// ARPACK does not converge on it. Spatial models take the lowest shift on the dense path.
Frequencies naturalFrequencies(const core::Linearization& lin, const core::LinearizedSystem& sys, int nev,
                               EigenPath path = EigenPath::Auto);
// Sparse path only, after lin.nodalAtRest(..., withMass = true): no dense matrix of the model's size
// is formed. Throws std::runtime_error when ARPACK fails.
Frequencies sparseFrequencies(const core::Linearization& lin, int nev);

// One point of the load schedule: mu (initial loads) and s (DEL* increments, 1 = the total).
struct LoadPoint {
  double initial = 1.0;
  double increment = 0.0;
};
// The schedule described above; loadSteps > 0 overrides ITERSTEP's nsteps (--steps).
std::vector<LoadPoint> loadSchedule(const core::Model& model, int loadSteps = 0);
// Buckling load factors (SPACAR mode 8): mu with (K0 + mu G0) v = 0, K0 the structural and G0 the
// geometric stiffness of sys; the smallest positive ones, ascending (at most count). The load that
// produced G0 times mu is the critical load (linear pre-buckling). Empty when K0 is not definite.
Eigen::VectorXd bucklingFactors(const core::LinearizedSystem& sys, int count);

struct StaticStep {
  double loadFactor = 0.0;     // s: fraction of the DEL* increments (1 at the last step)
  double initialFactor = 1.0;  // mu: fraction of the initial loads
  Eigen::VectorXd eta, x, e, sigma;
  Frequencies frequencies;
  Eigen::VectorXd buckling;       // load factors (only when asked for)
  solvers::StaticResult newton;   // of the last (sub-)step
  int iterations = 0;             // Newton iterations of this load step, failed and sub-step attempts included
  core::LinearizedSystem system;  // M0, K0, G0, ... in the equilibrium (SPACAR's .sbm)
};

struct StaticRun {
  std::vector<StaticStep> steps;
  bool completed = true;
  std::string stopReason;
};

// onStep(i, n): progress, called before load step i (0-based) of n.
StaticRun staticAnalysis(const core::Model& model, int nev, int loadSteps = 0 /* 0: from the file */,
                         const std::function<void(int, int)>& onStep = {},
                         int buckling = 0 /* number of buckling load factors per step */);

}  // namespace flexmb::analysis
