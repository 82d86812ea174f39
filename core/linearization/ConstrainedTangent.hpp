#pragma once
// The static Newton tangent Kbar + Gbar = F_q^T H F_q (paper Eq. 16, H = K_x + G_x + W_x, W_x the
// skew load stiffness of moments on Euler parameters, so H need not be symmetric) of a full
// model without F_q: on the free coordinates (calculable and DYNX) and the constrained
// deformations (fixed and input, Jacobian C),
//   [H  C^T] [dx]   [P^T b]
//   [C  0  ] [mu] = [  0  ]    gives    P dx = (Kbar + Gbar)^-1 b,
// because F_q spans null(C) and P F_q = I (P: the DYNE rows of D_x, unit rows for DYNX; the same
// P as ConstrainedPencil): dx = F_q a with F_q^T (H F_q a - P^T b) = 0, so a = P dx solves
// (F_q^T H F_q) a = b. One sparse LU (KLU; the pattern analysed once, values refilled) replaces
// n_q kinematic solves and a dense n_x x n_q x n_q projection per Newton iteration.
#include <Eigen/Core>
#include <vector>

#include "core/dynamics/NodalMatrices.hpp"
#include "core/kinematics/SparseLU.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

class GeometricTransferFunctions;

class ConstrainedTangent {
 public:
  // pattern: the nodal matrices' common pattern (NodalMatrices::K(), G() share it).
  ConstrainedTangent(const Model& model, const NodalMatrices::Sparse& pattern);

  // Factorises with H = K_x + G_x + W_x of `nodal` and the element Jacobians of gtf's configuration
  // (their DYNE rows are copied: solve() stays valid when the kinematics move on). False when
  // the saddle-point matrix is singular.
  bool factorize(const NodalMatrices& nodal, const GeometricTransferFunctions& gtf);
  // The same form with H = M_x: solve() then gives x = Mbar^-1 b (Mbar = F_q^T M_x F_q, the mass
  // matrix of Eq. 16; null(C) is range(F_q) likewise). False when singular: a motion without mass.
  bool factorizeMass(const NodalMatrices& nodal, const GeometricTransferFunctions& gtf);
  // x = (Kbar + Gbar)^-1 b (or Mbar^-1 b) for b, x in q (full model), with the last factorisation.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;

  // An implicit integrator's iteration matrix F_q^T H F_q with H = M_x + gammaP D_x + betaP (K_x +
  // G_x + W_x): keep() copies the nodal matrices and the element Jacobians of gtf's configuration
  // (the workspace's nodal matrices and the kinematics move on), factorizeWeighted forms H for a
  // step size from the copies. solveNodal: x = P dx for [H C^T; C 0] [dx; mu] = [w; 0], a nodal
  // load w (nx), i.e. x = (F_q^T H F_q)^-1 F_q^T w; massProduct: w = M_x z with the kept M_x.
  void keep(const NodalMatrices& nodal, const GeometricTransferFunctions& gtf);
  bool factorizeWeighted(double betaP, double gammaP);
  void solveNodal(const Eigen::VectorXd& w, Eigen::VectorXd& x) const;
  void massProduct(const Eigen::VectorXd& z, Eigen::VectorXd& w) const;
  int size() const { return n_; }

 private:
  struct Entry {            // an element Jacobian entry of a constrained deformation
    int element, row, col;  // element, local deformation row, local coordinate column
    int slotC, slotCt;      // value slots of C (row n_f + r, column f) and of C^T
  };
  struct DofRow {                // P's row of one degree of freedom
    int element = -1, row = -1;  // DYNE: the element and local deformation row (-1 for DYNX)
    int freeIndex = -1;          // DYNX: the free index of its coordinate
    int first = 0;               // DYNE: offset of its copied row in prow_
  };

  // The constraint Jacobian C, C^T and P's rows from gtf's configuration, then the factorisation.
  bool factorizeFilled(const GeometricTransferFunctions& gtf);
  void fillJacobians(const GeometricTransferFunctions& gtf);
  // Solves with rhs_ holding the free part of the right-hand side; x = P dx.
  void solveFilled(Eigen::VectorXd& x) const;

  const Model& model_;
  int nf_ = 0, n_ = 0;                // free coordinates; saddle-point size n_f + constraints
  std::vector<int> freeOf_;           // x index -> free index or -1
  std::vector<int> colPtr_, rowIdx_;  // pattern of the saddle-point matrix (compressed column)
  std::vector<double> values_;
  std::vector<int> hSlot_;  // per nodal pattern entry: its slot, or -1 (not free)
  std::vector<Entry> entries_;
  std::vector<DofRow> dofRows_;
  std::vector<double> prow_;   // copied DYNE rows (element coordinates, 0 where not free)
  std::vector<int> prowFree_;  // free index per copied entry (-1: not free)
  SparseLU lu_;
  mutable Eigen::VectorXd rhs_;
  // keep(): the nodal pattern and the kept values of M_x, K_x + G_x + W_x and D_x.
  std::vector<int> patternOuter_, patternInner_;
  std::vector<double> keptMass_, keptStiffness_, keptDamping_;
};

}  // namespace flexmb::core
