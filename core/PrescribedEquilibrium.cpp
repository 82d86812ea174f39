#include "core/PrescribedEquilibrium.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace flexmb::core {

std::string prescribedEquilibrium(Linearization& lin, double t, int k, double value, Eigen::VectorXd& eta, double& P) {
  const int m = lin.size();
  Eigen::VectorXd f, R(m + 1), dz;
  Eigen::MatrixXd A(m + 1, m + 1);
  LinearizedSystem sys;
  // Scales: the model size for lengths, the holding load (or a stiffness times a small motion) for forces.
  const double L = lin.model().lengthScale() > 0.0 ? lin.model().lengthScale() : 1.0;
  for (int it = 0; it < 60; ++it) {
    lin.kinematics().solvePositions(t, lin.basis() ? Eigen::VectorXd(*lin.basis() * eta) : eta);
    lin.appliedForces(t, 0.0, f);
    f[k] += P;
    lin.atRest(t, eta, f, sys, false);
    const Eigen::VectorXd b = lin.transfer().row(k).transpose();
    R.head(m) = sys.Q;
    R[m] = lin.kinematics().x()[k] - value;
    // Floors above the kinematic round-off (positions to ~1e-12 of the model size).
    const double forceScale = std::max({std::abs(P) * b.lpNorm<Eigen::Infinity>(), f.lpNorm<Eigen::Infinity>(),
                                        1e-3 * L * sys.K.diagonal().cwiseAbs().maxCoeff()});
    if (R.head(m).lpNorm<Eigen::Infinity>() <= 1e-8 * forceScale && std::abs(R[m]) <= 1e-10 * L) return "";
    A.topLeftCorner(m, m) = -(sys.K + sys.G);
    if (sys.Gskew.size()) A.topLeftCorner(m, m) -= sys.Gskew;  // moments on Euler parameters
    A.topRightCorner(m, 1) = b;
    A.bottomLeftCorner(1, m) = b.transpose();
    A(m, m) = 0.0;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
    dz = lu.solve(-R);
    if (!dz.allFinite()) return "singular bordered system (the prescribed coordinate cannot move the mechanism)";
    // Damp steps larger than a tenth of the model size (Newton far from the solution).
    const double stepNorm = dz.head(m).lpNorm<Eigen::Infinity>();
    const double alpha = stepNorm > 0.1 * L ? 0.1 * L / stepNorm : 1.0;
    eta += alpha * dz.head(m);
    P += alpha * dz[m];
    if (it > 0 && alpha == 1.0 && stepNorm <= 1e-12 * L && std::abs(R[m]) <= 1e-10 * L) return "";
  }
  std::ostringstream s;
  s << "no equilibrium found with the coordinate at " << value << " (60 iterations)";
  return s.str();
}

}  // namespace flexmb::core
