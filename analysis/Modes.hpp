#pragma once
// Eigenanalyses of a linearised model (paper Eq. 21): natural frequencies and modes in a
// configuration (dense independent-coordinate pencil or ARPACK shift-invert on the sparse nodal
// pencil), buckling load factors (SPACAR mode 8), and the highest eigenfrequency of the model at
// rest (the step an explicit integrator can take).
#include <Eigen/Core>
#include <optional>
#include <string>

#include "analysis/Participation.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"
#include "solvers/ReductionBasis.hpp"

namespace flexmb::analysis {

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
// pencil carries axial over bending stiffness, ~1e-7 relative on a 999-DOF chain). Dense or Sparse
// force either (comparisons, tests, the benchmark).
enum class EigenPath { Auto, Dense, Sparse };
constexpr int kSparseEigenFrom = 400;
// After lin.atRest(..., withMass = true) gave sys. The sparse path falls back to the dense one when
// ARPACK does not converge on it. Spatial models take the lowest shift on the dense path.
Frequencies naturalFrequencies(const core::Linearization& lin, const core::LinearizedSystem& sys, int nev,
                               EigenPath path = EigenPath::Auto);
// Sparse path only, after lin.nodalAtRest(..., withMass = true): no dense matrix of the model's size
// is formed. Throws std::runtime_error when ARPACK fails.
Frequencies sparseFrequencies(const core::Linearization& lin, int nev);

// Buckling load factors (SPACAR mode 8): mu with (K0 + mu G0) v = 0, K0 the structural and G0 the
// geometric stiffness of sys; the smallest positive ones, ascending (at most count). The load that
// produced G0 times mu is the critical load (linear pre-buckling). Empty when K0 is not definite.
Eigen::VectorXd bucklingFactors(const core::LinearizedSystem& sys, int count);

// The natural frequencies of the (reduced) model at rest in its initial configuration (`flexmb
// modes`, SPACAR's modes of the initial state): core::Linearization::initialRest, then
// naturalFrequencies. Throws KinematicsError / std::runtime_error.
struct InitialModes {
  Eigen::VectorXd eta, q;            // the configuration (q = the degrees of freedom)
  core::LinearizedSystem system;     // M0, K0, G0 ... there
  Frequencies frequencies;           // ascending; modes in eta
  Eigen::VectorXd x;                 // the nodal coordinates there
  ModalParticipation participation;  // with a reference point only (analysis/Participation.hpp)
};
// reference: also the modes' participation factors and effective masses, rotations about it.
// Throws std::invalid_argument for a reference node that is no position node.
InitialModes initialModes(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis, int nev,
                          const ReferencePoint* reference = nullptr);
// The frequencies as a table, the one every front end writes (`flexmb modes`, the study): mode,
// f_Hz, omega_rad_s.
io::CsvTable modesTable(const Frequencies& frequencies);

// The lowest nev modes of Eq. 21's q_s subproblem of a full model: the coordinates p.large held at
// zero (the reduction bases' eigenproblem). modes in q with zero rows at p.large; omega as the
// solver reports it (0 for rigid or unstable modes). Throws std::invalid_argument when nev exceeds
// the subproblem, std::runtime_error when the eigensolver fails.
Frequencies subproblemModes(const solvers::Partition& p, const core::LinearizedSystem& sys, int nev);

// The highest eigenfrequency of the (reduced) model at rest in its initial configuration
// (core::Linearization::initialRest) and its mode: an explicit Runge-Kutta method needs
// h < ~3.3 / omegaMax. Dense: models up to maxDofs degrees of freedom only (found = false beyond,
// or when the eigensolver fails).
struct HighestMode {
  bool found = false;
  double omegaMax = 0.0;  // rad/s
  double omegaMin = 0.0;  // the lowest non-zero eigenfrequency (rad/s)
  Eigen::VectorXd modeQ;  // the highest mode in q (V times it for a reduced model)
};
HighestMode highestMode(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis = std::nullopt,
                        int maxDofs = 600);
// Only omega_max at rest (rad/s; eigenvalues without vectors), 0 where it is not computed (more than
// maxDofs coordinates, no stiffness): what bounds ode45's step, for the auto integrator's test.
double highestFrequencyAtRest(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis = std::nullopt,
                              int maxDofs = 600);

}  // namespace flexmb::analysis
