#include "core/linearization/PrescribedEquilibrium.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace flexmb::core {

namespace {
// q = p (x) c as M(c) p (Hamilton product, scalar first).
Eigen::Matrix4d rightProduct(const Eigen::Vector4d& c) {
  Eigen::Matrix4d M;
  M << c[0], -c[1], -c[2], -c[3], c[1], c[0], c[3], -c[2], c[2], -c[3], c[0], c[1], c[3], c[2], -c[1], c[0];
  return M;
}
Eigen::Vector4d conjugate(const Eigen::Vector4d& l) { return Eigen::Vector4d(l[0], -l[1], -l[2], -l[3]); }
}  // namespace

double PrescribedQuantity::value(const Eigen::VectorXd& x) const {
  if (!axis) return x[coord];
  const Eigen::Vector4d q = rightProduct(conjugate(lambda0)) * x.segment<4>(coord);
  return 2.0 * std::atan2(q[axis], q[0]);
}

Eigen::Vector4d PrescribedQuantity::gradient(const Eigen::VectorXd& x) const {
  if (!axis) return Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  const Eigen::Matrix4d M = rightProduct(conjugate(lambda0));
  const Eigen::Vector4d q = M * x.segment<4>(coord);
  const double u = q[axis], w = q[0], n2 = u * u + w * w;
  return 2.0 * (w * M.row(axis) - u * M.row(0)).transpose() / n2;
}

std::string prescribedEquilibrium(Linearization& lin, double t, const PrescribedQuantity& prescribed, double value,
                                  Eigen::VectorXd& eta, double& P, double* tangentCondition) {
  const int m = lin.size();
  const int k = prescribed.coord, width = prescribed.width();
  double previous = std::numeric_limits<double>::infinity();  // the last iteration's force residual
  Eigen::VectorXd f, R(m + 1), dz;
  Eigen::MatrixXd A(m + 1, m + 1);
  LinearizedSystem sys;
  // Scales: the model size for lengths, the holding load (or a stiffness times a small motion) for forces.
  const double L = lin.model().lengthScale() > 0.0 ? lin.model().lengthScale() : 1.0;
  for (int it = 0; it < 60; ++it) {
    lin.kinematics().solvePositions(t, lin.basis() ? Eigen::VectorXd(*lin.basis() * eta) : eta);
    lin.appliedForces(t, 0.0, f);
    const Eigen::Vector4d g = prescribed.gradient(lin.kinematics().x());
    for (int j = 0; j < width; ++j) f[k + j] += P * g[j];
    lin.atRest(t, eta, f, sys, false);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
    for (int j = 0; j < width; ++j) b += g[j] * lin.transfer().row(k + j).transpose();
    R.head(m) = sys.Q;
    R[m] = prescribed.value(lin.kinematics().x()) - value;
    // Floors above the kinematic round-off (positions to ~1e-12 of the model size).
    const double forceScale = std::max({std::abs(P) * b.lpNorm<Eigen::Infinity>(), f.lpNorm<Eigen::Infinity>(),
                                        1e-3 * L * sys.K.diagonal().cwiseAbs().maxCoeff()});
    const double residual = R.head(m).lpNorm<Eigen::Infinity>();
    if (residual <= 1e-8 * forceScale && std::abs(R[m]) <= 1e-10 * L) return "";
    // Stagnation at the round-off of stiff elements (the cross-spring pivot's axial and bending
    // stiffnesses, 1e10 against a soft rotation): Newton's correction no longer lowers the residual,
    // which stands for deformations within 1e-8 of the model size of the exact ones. Accepted there
    // instead of iterating 60 times and calling a smooth path a turning point.
    if (residual >= 0.9 * previous && residual <= 1e-5 * forceScale && std::abs(R[m]) <= 1e-10 * L) return "";
    previous = residual;
    A.topLeftCorner(m, m) = -(sys.K + sys.G);
    if (sys.Gskew.size()) A.topLeftCorner(m, m) -= sys.Gskew;  // moments on Euler parameters
    // The border scaled to the stiffness (s = the largest K entry): [ -K, s b; s b^T, 0 ] [deta; dP/s]
    // = -[Q; s r]. Unscaled, stiff elements (1e10 against the O(1) entries of b) make the
    // factorisation lose the border's digits and the condition estimate meaningless.
    const double s = std::max(sys.K.diagonal().cwiseAbs().maxCoeff(), 1.0);
    A.topRightCorner(m, 1) = s * b;
    A.bottomLeftCorner(1, m) = s * b.transpose();
    A(m, m) = 0.0;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
    if (tangentCondition) *tangentCondition = lu.rcond();
    Eigen::VectorXd rhs = -R;
    rhs[m] *= s;
    dz = lu.solve(rhs);
    dz[m] *= s;
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
