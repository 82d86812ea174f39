#pragma once
// Static equilibrium with one nodal coordinate prescribed (paper Fig. 5: eigenfrequencies over a
// range of motion): the coordinate x_k is held at `value` by a dead load P along it, the Lagrange
// multiplier of the bordered Newton system on [eta; P]:
//   Q(eta) + P b(eta) = 0,  x_k(eta) = value,  b = (F_q V)^T e_k.
#include <Eigen/Core>
#include <string>

#include "core/Linearization.hpp"

namespace flexmb::core {

// Newton from (eta, P), both updated in place, at time t (the loads of the model at t, load factor
// 0). Returns "" on convergence, else the reason (singular bordered system, no equilibrium in 60
// iterations). Throws KinematicsError when the kinematics fail. tangentCondition: the reciprocal
// condition estimate of the last bordered tangent factorised (near 0 at a limit or branch point,
// where the path turns).
std::string prescribedEquilibrium(Linearization& lin, double t, int k, double value, Eigen::VectorXd& eta, double& P,
                                  double* tangentCondition = nullptr);

}  // namespace flexmb::core
