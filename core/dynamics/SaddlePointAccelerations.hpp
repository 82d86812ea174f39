#pragma once
// Accelerations of the full model from the nodal saddle-point form of Eq. 13 (docs/develop/design.md, Dynamics):
//   [ M_ff  C^T ] [ xdd_f ]   [ r_f - (M xdd_k)_f                        ]
//   [ C     0   ] [ mu    ] = [ edd_R(t) - D2_R[xd, xd] - (D_R xdd_k)    ]
// f: the free nodal coordinates (calculable and DYNX); R: the fixed and input deformations, C = D_R on
// the free coordinates; xdd_k: the prescribed accelerations of the known coordinates;
// r = f - h - D_x^T sigma. F_q spans null(C) on the free coordinates, so this is Mbar qdd =
// F_q^T (r - M g) without F_q and without a dense product: one sparse factorisation of a pattern
// analysed once. The dynamic rows then give qdd_j = D_j xdd + D2_j[xd, xd] (DYNE) or xdd (DYNX).
#include <Eigen/Core>
#include <vector>

#include "core/dynamics/Inertia.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/kinematics/SparseLU.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

class SaddlePointAccelerations {
 public:
  SaddlePointAccelerations(const Model& model, const Inertia& inertia);

  // After gtf.solvePositions (element Jacobians at x) and inertia.update(x), with d2 = D2[xd, xd] of
  // every deformation (ne) and the nodal forces r: qdd (nq) and the nodal accelerations xdd (nx).
  // Returns false when the saddle-point matrix is singular (no mass on a degree of freedom).
  bool solve(double t, const GeometricTransferFunctions& gtf, const Eigen::VectorXd& d2, const Eigen::VectorXd& r,
             Eigen::VectorXd& qdd, Eigen::VectorXd& xdd);

  int size() const { return n_; }

 private:
  void assemble(const GeometricTransferFunctions& gtf);
  void chooseScaling();

  const Model& model_;
  const Inertia& inertia_;
  int nf_ = 0, nr_ = 0, n_ = 0;
  std::vector<int> freeOf_;  // x index -> free index or -1
  std::vector<int> rowOf_;   // e index -> constraint index or -1
  std::vector<int> freeCoord_;
  // Compressed-column pattern of the whole (symmetric, both triangles) matrix and value slots.
  std::vector<int> colPtr_, rowIdx_;
  std::vector<double> values_;
  std::vector<int> diagSlot_;                                  // per free coordinate
  std::vector<int> massRange_, massSlot_, massLocal_;          // per massive element (Inertia order)
  std::vector<int> jacRange_, jacSlot_, jacSlotT_, jacLocal_;  // per element: C and C^T entries
  std::vector<double> scale_;                                  // symmetric diagonal scaling, chosen at the first solve
  std::vector<double> slotScale_;                              // per value slot: scale of its row times its column
  bool scaled_ = false;
  bool inputCoords_ = false, inputDefs_ = false;
  SparseLU lu_;
  Eigen::VectorXd b_, xddKnown_, eddInput_, Mk_;
};

}  // namespace flexmb::core
