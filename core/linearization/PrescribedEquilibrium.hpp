#pragma once
// Static equilibrium with one nodal coordinate (or a rotation) prescribed (paper Fig. 5:
// eigenfrequencies over a range of motion): the quantity g(x) is held at `value` by a load P along
// its gradient, the Lagrange multiplier of the bordered Newton system on [eta; P]:
//   Q(eta) + P b(eta) = 0,  g(x(eta)) = value,  b = (F_q V)^T dg/dx  (g = x_k: b = (F_q V)^T e_k).
#include <Eigen/Core>
#include <string>

#include "core/linearization/Linearization.hpp"

namespace flexmb::core {

// What is prescribed: one nodal coordinate, or on a spatial orientation node (Euler parameters) the
// rotation about a global axis from the node's initial orientation, in rad, as the transfer
// block's components of such a node mean: theta_i = 2 atan2(q_i, q_0) of q = lambda (x) conj(lambda0),
// exact for a rotation about axis i. Its gradient on lambda is 2 E(lambda) row i at lambda0.
struct PrescribedQuantity {
  int coord = 0;  // the coordinate, or the node's first Euler parameter
  int axis = 0;   // 0: the coordinate itself; 1..3: the rotation about global x, y, z
  Eigen::Vector4d lambda0 = Eigen::Vector4d::Zero();  // the initial orientation (axis > 0)
  int width() const { return axis ? 4 : 1; }          // coordinates it depends on: coord .. coord + width - 1
  double value(const Eigen::VectorXd& x) const;
  Eigen::Vector4d gradient(const Eigen::VectorXd& x) const;  // d value / d x on those coordinates
};

// Newton from (eta, P), both updated in place, at time t (the loads of the model at t, load factor
// 0). Returns "" on convergence, else the reason (singular bordered system, no equilibrium in 60
// iterations). Throws KinematicsError when the kinematics fail. tangentCondition: the reciprocal
// condition estimate of the last bordered tangent factorised (near 0 at a limit or branch point,
// where the path turns).
std::string prescribedEquilibrium(Linearization& lin, double t, const PrescribedQuantity& prescribed, double value,
                                  Eigen::VectorXd& eta, double& P, double* tangentCondition = nullptr);

}  // namespace flexmb::core
