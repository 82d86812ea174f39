#pragma once
// Linearised equations of motion (paper Eq. 15) in q = V eta, A = F_q V:
//   M dqdd + (C + D) dqd + (K + N + G) dq = F_q^T df - E_q^T dsigma_a.
// At rest (Eq. 16): Mbar = A^T M A, Kbar = (E_q V)^T S (E_q V), Dbar = (E_q V)^T S_d (E_q V),
//   Gbar = -F_qq^T f + E_qq^T sigma = A^T H A,  H = sum_i sigma~_i d^2 D_i/dx^2,
// sigma~ = elastic stresses + reaction stresses of the constrained deformations solving
// D_x^T sigma~ = f on the calculable coordinates (the constraint second derivatives vanish along q,
// so this identity is exact), and C = N = 0. -dQ/dq = Kbar + Gbar is the static Newton tangent.
// In motion (ref. [13]; derivation in core/README.md) the inertia forces M xdd + h join the loads
// in G, and the variations of the velocities and accelerations give
//   C = A^T (M dxdd/dqd + dh/dxd A),
//   N = A^T (M dxdd/dq + d(M xdd + h)/dx A + dh/dxd dxd/dq) + (E_q V)^T S_d de_d/dq.
// Both G variants include the load stiffness of gravity on distributed masses.
#include <Eigen/Core>
#include <optional>

#include "core/GeometricTransferFunctions.hpp"
#include "core/Inertia.hpp"
#include "core/Model.hpp"
#include "core/ReducedCoordinates.hpp"
#include "core/Stresses.hpp"

namespace flexmb::core {

struct LinearizedSystem {
  Eigen::MatrixXd M, K, G, D;  // m x m
  Eigen::MatrixXd C, N;        // m x m: velocity sensitivity, dynamic stiffening (0 at rest)
  // Generalised forces (F_q V)^T (f - D_x^T sigma) at rest; in motion the residual of Eq. 13,
  // (F_q V)^T (f - M xdd - h - D_x^T sigma), which vanishes on a trajectory.
  Eigen::VectorXd Q;
  Eigen::VectorXd sigma;       // elastic + reaction stresses (ne)
};

class Linearization {
 public:
  explicit Linearization(const Model& model, std::optional<Eigen::MatrixXd> basis = std::nullopt);
  int size() const { return m_; }
  const ReducedCoordinates& coordinates() const { return coords_; }
  const Model& model() const { return model_; }
  GeometricTransferFunctions& kinematics() { return gtf_; }
  const Eigen::MatrixXd* basis() const { return coords_.basis(); }
  void dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const;

  // Applied nodal loads: XF + loadFactor * DELXF + XFT(t) + gravity at the current configuration.
  void appliedForces(double t, double loadFactor, Eigen::VectorXd& f, double initialFactor = 1.0) const;
  // Everything at rest in configuration eta under nodal loads f (Eq. 16). Throws KinematicsError.
  void atRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, LinearizedSystem& out,
              bool withMass = true);
  // Everything about a moving state (eta, etad, etadd) at time t under the model's loads (Eq. 15,
  // ref. [13]). Throws KinematicsError.
  void inMotion(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& etad, const Eigen::VectorXd& etadd,
                LinearizedSystem& out);
  // F_q V at the last evaluation (nx x m).
  const Eigen::MatrixXd& transfer() const { return FqV_; }
  // Only Q (cheap: no second derivatives), for line searches.
  void staticForces(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q);

 private:
  mutable double loadFactor_ = 0.0, initialFactor_ = 1.0;  // of the last appliedForces
  // out = L^T S R (S or S_d), on the active deformations.
  void constitutiveProduct(const Eigen::MatrixXd& L, const Eigen::MatrixXd& R, bool damping,
                           Eigen::MatrixXd& out) const;
  // G = A^T H(sigma~) A - A^T (dg/dx) A; sigma~ = sigma_ + reaction stresses for the nodal residual r_.
  void geometricStiffness(LinearizedSystem& out);

  const Model& model_;
  ReducedCoordinates coords_;
  int m_;
  GeometricTransferFunctions gtf_;
  Inertia inertia_;
  Stresses stresses_;
  ElementSteps steps_;
  Eigen::VectorXd q_, qd_, r_, sigma_, xd_, xdd_, ed_, work_;
  Eigen::MatrixXd FqV_, EqV_, MF_, HF_;
  Eigen::MatrixXd dxd_, dxdd_, Y_, Z_, R_, Ed_;  // motion terms
};

}  // namespace flexmb::core
