#pragma once
// The global, configuration dependent mass matrix M(x) (lumped + consistent element masses) kept
// as element blocks, with the products the equations of motion need, and the velocity dependent
// inertia forces h(x, xd) and gravity loads. Blocks are recomputed per configuration, never
// assembled into a sparse matrix on the hot path.
#include <Eigen/Core>
#include <vector>

#include "core/kinematics/DirectionalDerivative.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

class Inertia {
 public:
  explicit Inertia(const Model& model);
  bool hasMass() const { return !massive_.empty() || !model_.lumpedMasses.empty(); }
  // Element mass blocks at configuration x.
  void update(const Eigen::VectorXd& x);
  // The same, and y += h(x, xd) in the same element pass (one geometry evaluation per element);
  // with d2, also the convective D2e[xd, xd] of these elements' deformations (the rows of e).
  void updateWithVelocityForces(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, Eigen::VectorXd& y,
                                Eigen::VectorXd* d2 = nullptr);
  // y = M v (nx), y = M F (nx x m).
  void multiply(const Eigen::VectorXd& v, Eigen::VectorXd& y) const;
  void multiply(const Eigen::MatrixXd& F, Eigen::MatrixXd& Y) const;
  // Mbar = F^T M F (m x m) element by element, without the nx x m product M F (Eq. 19's reduced
  // mass; for m up to kMaxProjectedColumns without allocation).
  void projectedMass(const Eigen::MatrixXd& F, Eigen::MatrixXd& Mbar);
  static constexpr int kMaxProjectedColumns = 16;
  // y += h(x, xd) (velocity dependent inertia forces; the inertia force is M xdd + h).
  void addVelocityForces(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, Eigen::VectorXd& y) const;
  // y += scale * gravity loads (lumped and distributed masses); statics ramps gravity with the
  // initial loads (scale = initialFactor).
  void addGravity(const Eigen::VectorXd& x, Eigen::VectorXd& y, double scale = 1.0) const;
  // Derivatives for the linearisation of a moving system (Eq. 15, ref. [13]):
  // Y += (dh/dxd) W; h is quadratic in xd, so polarisation makes each column exact.
  void addVelocityForceJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::MatrixXd& W,
                                Eigen::MatrixXd& Y) const;
  // Y += d(M(x) xdd + h(x, xd))/dx A at fixed xd, xdd (element Richardson; lumped masses are constant).
  void addConfigurationJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& xdd,
                                const Eigen::MatrixXd& A, const ElementSteps& steps, Eigen::MatrixXd& Y) const;
  // The element blocks of the last update (for sparse assembly): element index and its block.
  const std::vector<int>& massiveElements() const { return massive_; }
  const ElemMat& block(size_t k) const { return blocks_[k]; }
  const Eigen::VectorXd& lumped() const { return lumped_; }  // diagonal lumped masses (nx)
  // Dense M (tests, linearisation of small models).
  Eigen::MatrixXd dense() const;
  double kineticEnergy(const Eigen::VectorXd& xd) const;

 private:
  const Model& model_;
  std::vector<int> massive_;       // elements with distributed inertia
  std::vector<ElemMat> blocks_;    // per massive element
  Eigen::VectorXd lumped_;         // diagonal lumped masses (nx)
  std::vector<int> lumpedCoords_;  // coordinates with a lumped mass
  Eigen::MatrixXd wide_;           // M F of projectedMass for wide F
};

// Applied nodal loads at (t, x): initialFactor * (XF + gravity) + loadFactor * DELXF + XFT(t)
// (Eq. 13's f). One definition for the equations of motion, the linearisation and statics; statics
// ramps the initial loads, gravity among them (initialFactor < 1), and the DEL* increments
// (loadFactor = step / steps).
void appliedLoads(const Model& model, const Inertia& inertia, double t, double loadFactor, const Eigen::VectorXd& x,
                  Eigen::VectorXd& f, double initialFactor = 1.0);
// The same without gravity (result files report gravity apart: SPACAR's fx and fxgrav).
void nodalLoads(const Model& model, double t, double loadFactor, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                double initialFactor = 1.0);

// Generalised force on the Euler parameters of a global moment M: 2 E(lambda)^T M = momentMatrix(M) lambda.
Eigen::Matrix4d momentMatrix(const Eigen::Vector3d& M);

}  // namespace flexmb::core
