#pragma once
// Linearised equations of motion at rest (paper Eq. 15-16) in q = V eta:
//   Mbar = (F_q V)^T M (F_q V),  Kbar = (E_q V)^T S (E_q V),  Dbar = (E_q V)^T S_d (E_q V),
//   Gbar = -F_qq^T f + E_qq^T sigma = (F_q V)^T H (F_q V),  H = sum_i sigma~_i d^2 D_i/dx^2,
// where sigma~ = elastic stresses + reaction stresses of the constrained deformations solving
// D_x^T sigma~ = f on the calculable coordinates (the constraint second derivatives vanish along q,
// so this identity is exact). -dQ/dq = Kbar + Gbar is also the static Newton tangent.
// Not included: the load stiffness of configuration dependent distributed gravity.
#include <Eigen/Core>
#include <optional>

#include "core/GeometricTransferFunctions.hpp"
#include "core/Inertia.hpp"
#include "core/Model.hpp"
#include "core/Stresses.hpp"

namespace flexmb::core {

struct LinearizedSystem {
  Eigen::MatrixXd M, K, G, D;  // m x m
  Eigen::VectorXd Q;           // static generalised forces (F_q V)^T (f - D_x^T sigma), size m
  Eigen::VectorXd sigma;       // elastic + reaction stresses (ne)
};

class Linearization {
 public:
  explicit Linearization(const Model& model, std::optional<Eigen::MatrixXd> basis = std::nullopt);
  int size() const { return m_; }
  const Model& model() const { return model_; }
  GeometricTransferFunctions& kinematics() { return gtf_; }
  const Eigen::MatrixXd* basis() const { return basis_ ? &*basis_ : nullptr; }
  void dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const;

  // Applied nodal loads: XF + loadFactor * DELXF + XFT(t) + gravity at the current configuration.
  void appliedForces(double t, double loadFactor, Eigen::VectorXd& f) const;
  // Everything at rest in configuration eta under nodal loads f (Eq. 16). Throws KinematicsError.
  void atRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, LinearizedSystem& out,
              bool withMass = true);
  // F_q V at the last evaluation (nx x m).
  const Eigen::MatrixXd& transfer() const { return FqV_; }
  // Only Q (cheap: no second derivatives), for line searches.
  void staticForces(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q);

 private:
  void constitutiveProduct(const Eigen::MatrixXd& EqV, bool damping, Eigen::MatrixXd& out) const;

  const Model& model_;
  std::optional<Eigen::MatrixXd> basis_;
  int m_;
  GeometricTransferFunctions gtf_;
  Inertia inertia_;
  Stresses stresses_;
  Eigen::VectorXd q_, r_, sigma_;
  Eigen::MatrixXd FqV_, EqV_, MF_, HF_;
};

}  // namespace flexmb::core
