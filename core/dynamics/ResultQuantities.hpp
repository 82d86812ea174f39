#pragma once
// SPACAR's derived result quantities at a known state (for result files, not the hot path):
//   * sigma with the reaction stresses of the constrained deformations (fixed, input, dynamic rows
//     whose stress is not elastic), from D_c^T sigma~ = (f - M xdd - h - D^T sigma)_c on the
//     calculable coordinates;
//   * fxt = M xdd + h + D^T sigma~: the total nodal force, applied loads plus reactions (on free
//     coordinates it equals the applied force, on fixed and input coordinates it includes the
//     support reaction);
//   * the first-order transfer functions dx/d(input and dynamic coordinates) and D = de/dx.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/Workspace.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

// A coordinate of the kinematic degrees of freedom (SPACAR's x^m and e^m, input ones included).
struct FreeCoordinate {
  bool isDeformation = false;
  int index = 0;  // x or e index
};

class ResultQuantities {
 public:
  // With a workspace of its own.
  explicit ResultQuantities(const Model& model);
  // On a workspace shared with other evaluators of its model (core/dynamics/Workspace.hpp).
  explicit ResultQuantities(Workspace& workspace);
  ResultQuantities(const ResultQuantities&) = delete;
  ResultQuantities& operator=(const ResultQuantities&) = delete;
  // Positions and Jacobians at (t, q), input coordinates at load factor s and initial-load factor
  // mu (the analysis floor's statics). near (size nx): the configuration Newton starts from, the
  // state's own where it is known (a mechanism far from its initial configuration); otherwise the
  // last one solved. Throws KinematicsError.
  void setState(double t, const Eigen::VectorXd& q, double inputLoadFactor = 0.0, double initialFactor = 1.0,
                const Eigen::VectorXd* near = nullptr);
  // The applied part of fxt: nodal loads (XF, XFT, DELXF at the load factor, moments, USERSIG)
  // and, apart, the gravity loads; fxt = applied + gravity on free coordinates.
  struct AppliedForces {
    Eigen::VectorXd loads, gravity;  // nx each
  };
  // After setState: sigma~ and fxt for the state's rates and its elastic stresses sig (size ne;
  // entries of constrained deformations are replaced by reaction stresses, elastic ones kept).
  // userForces (size nx) are nodal loads beyond the model's; empty: the state's USERSIG forces
  // (s.userForces, or the model's user functions called at the state when it holds none).
  // initialFactor: statics' factor of the initial loads (XF, gravity; 1 outside statics).
  void forces(double t, double loadFactor, const StateOutputs& s, const Eigen::VectorXd& userForces,
              Eigen::VectorXd& sigmaTotal, Eigen::VectorXd& fxt, double initialFactor = 1.0,
              AppliedForces* applied = nullptr);
  // After setState: dx (nx x cols.size()), column j = dx / d cols[j] with the other listed
  // coordinates and all fixed ones held.
  void transfer(const std::vector<FreeCoordinate>& cols, Eigen::MatrixXd& dx);
  // After setState: D = de/dx (ne x nx), dense.
  void jacobian(Eigen::MatrixXd& D) const;

 private:
  ResultQuantities(std::unique_ptr<Workspace> own, Workspace* shared);
  std::unique_ptr<Workspace> own_;  // the workspace when not shared, else null
  const Model& model_;
  GeometricTransferFunctions gtf_;
  Inertia& inertia_;
  std::vector<char> calculable_;
};

}  // namespace flexmb::core
