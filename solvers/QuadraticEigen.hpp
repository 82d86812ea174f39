#pragma once
// Eigenvalues s of the linearised equations M x'' + C x' + K x = 0 about a moving state (paper
// Eq. 15: C = Cbar + Dbar and K = Kbar + Nbar + Gbar, both in general nonsymmetric), from the
// first-order companion form [0 I; -M^-1 K  -M^-1 C] with a dense general eigensolver. Each
// oscillating pair gives one natural frequency |s| and damping ratio -Re(s)/|s|; a real root
// s > 0 is a divergent mode (reported as omega = -s, the sign convention of the symmetric solver),
// |s| ~ 0 a rigid mode (omega = 0), s < 0 an overdamped root (omega = |s|, zeta = 1).
#include <Eigen/Core>
#include <string>

namespace flexmb::solvers {

struct QuadraticModes {
  bool ok = false;
  std::string message;      // why not ok (M singular, eigensolver failed)
  Eigen::VectorXd omega;    // rad/s, ordered by |omega|, at most nev
  Eigen::VectorXd damping;  // zeta per entry
};

QuadraticModes quadraticModes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C, const Eigen::MatrixXd& K, int nev);

}  // namespace flexmb::solvers
