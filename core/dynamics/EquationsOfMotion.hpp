#pragma once
// Equations of motion in independent coordinates (paper Eq. 13) and, with q = V eta, the reduced
// ones (Eq. 19): the same code with F_q V in place of F_q (V = identity for the full model).
//   Mbar etadd = (F_q V)^T (f - h - M g - D_x^T sigma),  Mbar = (F_q V)^T M (F_q V),
// where g = (F_qq qd) qd + rheonomic terms is xdd at etadd = 0 (one extra kinematic solve) and
// D_x^T sigma = E_q^T sigma through the kinematic Jacobian. Nothing is allocated per call.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <memory>
#include <optional>

#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/ReducedCoordinates.hpp"
#include "core/dynamics/SaddlePointAccelerations.hpp"
#include "core/dynamics/Stresses.hpp"
#include "core/dynamics/Workspace.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

// How the accelerations of Eq. 13 are solved (both give the same qdd to round-off):
// - Projected: Mbar = (F_q V)^T M (F_q V), dense Cholesky; O(n m^2), the form for reduced models
//   and small full ones.
// - SaddlePoint: the sparse nodal system of SaddlePointAccelerations; no F_q, O(n) for chains;
//   full models only.
// - Automatic: SaddlePoint for full models from kSaddlePointDofs degrees of freedom, else Projected
//   (measured: the saddle point is as fast at 4 DOF, 1.8x faster at 17 and 18; 1 DOF projects faster).
enum class DynamicsForm { Automatic, Projected, SaddlePoint };
constexpr int kSaddlePointDofs = 4;

// Everything SPACAR reports at an output time.
struct StateOutputs {
  Eigen::VectorXd x, xd, xdd, e, ed, edd, sig;
  // The USERSIG nodal forces at this state (nx, model order), which `sig` and `xdd` include; empty
  // without USERSIG. Kept so that result files report them without calling the user again.
  Eigen::VectorXd userForces;
};

class EquationsOfMotion {
 public:
  // basis: nq x m (q = V eta); empty optional = the full model (V = I). With a workspace of its own.
  EquationsOfMotion(const Model& model, std::optional<Eigen::MatrixXd> basis = std::nullopt,
                    DynamicsForm form = DynamicsForm::Automatic);
  // On a workspace shared with other evaluators of its model (core/dynamics/Workspace.hpp: it must outlive
  // this object; one call at a time). The results are the same bits as with a workspace of its own.
  EquationsOfMotion(Workspace& workspace, std::optional<Eigen::MatrixXd> basis = std::nullopt,
                    DynamicsForm form = DynamicsForm::Automatic);
  EquationsOfMotion(const EquationsOfMotion&) = delete;
  EquationsOfMotion& operator=(const EquationsOfMotion&) = delete;

  int size() const { return m_; }  // dimension of eta
  const Model& model() const { return model_; }
  const Eigen::MatrixXd* basis() const { return coords_.basis(); }
  GeometricTransferFunctions& kinematics() { return gtf_; }
  const Inertia& inertia() const { return inertia_; }
  const Stresses& stresses() const { return stresses_; }

  // Initial state y0 = [eta0; etad0] from the model's initial values (least squares onto V).
  Eigen::VectorXd initialState();
  // q = V eta (or eta).
  void dofs(const Eigen::VectorXd& eta, Eigen::VectorXd& q) const;

  // dy/dt for y = [eta; etad]. Throws KinematicsError (with t) when the kinematics fail.
  void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt);
  // Residual of Eq. 13/19 at (t, y, etadd): Mbar etadd - (F_q V)^T (f - h - M g - D_x^T sigma),
  // without the mass solve (for linearisation checks and implicit schemes).
  void residual(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& etadd, Eigen::VectorXd& R);
  // Full output quantities at (t, y): one extra evaluation, for output times only.
  void outputs(double t, const Eigen::VectorXd& y, StateOutputs& out);

  long evaluations() const { return evaluations_; }
  // The form in use (Projected or SaddlePoint).
  DynamicsForm form() const { return saddle_ ? DynamicsForm::SaddlePoint : DynamicsForm::Projected; }

 private:
  EquationsOfMotion(std::unique_ptr<Workspace> own, Workspace* shared, std::optional<Eigen::MatrixXd> basis,
                    DynamicsForm form);
  // Positions, velocities, and for the projected form F_q V.
  void kinematicState(double t, const Eigen::VectorXd& y);
  // Tells the kinematics how to use the last state's convective terms for predicting eta.
  void predictorCurvature(const Eigen::Ref<const Eigen::VectorXd>& eta);
  // g = (F_qq qd) qd + rheonomic terms (projected form), from the convective terms of massState.
  void convectiveAccelerations(double t);
  // Nodal forces f - h - D_x^T sigma (fn_), and - M g for the projected form.
  void nodalForces(double t, bool projected);
  // Projected form: Mbar and (F_q V)^T (r - M g).
  void projectedSystem();
  // Mass blocks at x and, when moving, the velocity forces h (hn_) and the convective D2e[xd, xd]
  // of every element (d2_) in the same element pass.
  void massState();
  // Accelerations etadd_ (and xdd_ in the saddle-point form) at the last kinematic state.
  void accelerations(double t);

  std::unique_ptr<Workspace> own_;  // the workspace when not shared, else null
  const Model& model_;
  ReducedCoordinates coords_;
  int m_;
  GeometricTransferFunctions gtf_;  // its own warm start on the workspace's kinematic structure
  Inertia& inertia_;                // the workspace's (blocks recomputed at every evaluation)
  const Stresses& stresses_;
  bool rheonomic_;
  std::optional<SaddlePointAccelerations> saddle_;
  std::vector<int> massless_;  // elements without inertia (their D2e come from a pass of their own)
  bool moving_ = false;
  bool curvatureSet_ = false;  // the kinematics hold the last rhs state's convective terms
  Eigen::VectorXd etaPrev_, etadPrev_;
  long evaluations_ = 0;
  // Workspace (allocated once).
  Eigen::VectorXd q_, qd_, xd_, g_, xdd_, hn_, d2_, ed_, sigma_, fn_, Mg_, rhsEta_, etadd_, userSigma_, userForces_;
  Eigen::MatrixXd FqV_, Mbar_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace flexmb::core
