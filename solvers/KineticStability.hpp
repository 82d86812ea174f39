#pragma once
// Stability of an equilibrium under circulatory loads: the kinetic criterion.
//
// The undamped motion about the equilibrium, M v'' + A v = 0 with A = K + G + Gskew (paper Eq. 16 at
// rest; Gskew the antisymmetric load stiffness of dead moments), is stable when every eigenvalue of
// A v = lambda M v is real and positive (lambda = omega^2). A real lambda < 0 is divergence (static
// buckling); a complex pair is flutter (two modes coalesced; sqrt(lambda) has an imaginary part, so
// one of the pair grows). With a symmetric A this is the energy criterion (A positive definite); with
// an antisymmetric part the two differ (Ziegler, Principles of Structural Stability; Nikolai's
// paradox: a cantilever of equal bending stiffnesses under a dead axial torque flutters at any torque,
// while A's symmetric part, the tangent of a semi-tangential torque, stays definite up to pi EI/L).
//
// Only the eigenvalues nearest zero are examined: nev of them (complex pairs complete), found by ARPACK
// (dnaupd/dneupd, regular mode on OP = (A - sigma M)^-1 M, one dense LU) or, for small n, by a dense
// eigensolver. A coalescence among higher modes is not seen. Damping (D) is not included: the verdict
// is that of the undamped motion, as the natural frequencies are.
//
// Thresholds, relative to scale = max(the diagonal scale of EigenSolver (median A_ii / M_ii), largest
// |lambda| returned):
//   divergence : a lambda with |Im| <= 1e-8 scale and Re < -1e-8 scale;
//   flutter    : a lambda with |Im| > 1e-8 scale.
// M must be positive definite (else Undecided, with the reason); sizes must agree (std::invalid_argument).
#include <Eigen/Core>
#include <string>

namespace flexmb::solvers {

enum class KineticVerdict { Stable, Divergence, Flutter, Undecided };

struct KineticStability {
  KineticVerdict verdict = KineticVerdict::Undecided;
  Eigen::VectorXcd lambda;  // the eigenvalues examined, by increasing modulus
  double scale = 0.0;       // spectrum scale of the thresholds above
  int critical = -1;        // index in lambda of the eigenvalue that decided Divergence / Flutter
  std::string method;       // "arpack" or "dense"
  std::string message;      // why Undecided, or a note (ARPACK fell back to dense)
  bool stable() const { return verdict == KineticVerdict::Stable; }
  // "stable", "divergence (lambda = -3.2 (rad/s)^2)", "flutter (lambda = 7.6 +- 15.1i (rad/s)^2)", ...
  std::string describe() const;
};

KineticStability kineticStability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& M, int nev = 8,
                                  Eigen::Index denseBelow = 60);

}  // namespace flexmb::solvers
