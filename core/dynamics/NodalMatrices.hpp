#pragma once
// The linearisation at rest (paper Eq. 16) before its projection on the independent coordinates:
// sparse nodal matrices (nx x nx) assembled from element blocks,
//   K_x = sum_el D_e^T S D_e            (active deformations; Kbar = A^T K_x A, A = F_q V),
//   D_x = sum_el D_e^T S_d D_e          (damping),
//   G_x = sym(H(sigma~) - dg/dx)        (stress-weighted Hessians and gravity on distributed masses,
//                                        both symmetric: Hessians of a potential; Gbar = A^T G_x A),
//   W_x = -dm/dx                         (global moments on Euler parameters, m = 2 E(lambda)^T M =
//                                        momentMatrix(M) lambda: a constant skew 4 x 4 block per
//                                        loaded node, docs/theory/spatial-elements.md 6.3),
//   M_x                                  (element and lumped masses; Mbar = A^T M_x A).
// The full load stiffness is G_x + W_x. W_x is antisymmetric: a moment of fixed direction is not
// conservative for spatial rotations. It does no work along any motion (v^T W_x v = 0), so the
// symmetric eigen and buckling problems see exactly G_x; Newton tangents and Jacobians add it.
// The pattern (every element block, the diagonal and the moment nodes) is analysed once; each
// assembly only refills values, so a Newton iteration allocates nothing here.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "core/kinematics/DirectionalDerivative.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

class GeometricTransferFunctions;

class NodalMatrices {
 public:
  using Sparse = Eigen::SparseMatrix<double>;  // column-major, full storage of both triangles
  explicit NodalMatrices(const Model& model);

  // K_x (and D_x when the model has damping) from the element Jacobians of gtf's configuration;
  // active[k]: deformation k carries a stress (Stresses::isActive).
  void assembleStiffness(const GeometricTransferFunctions& gtf, const std::vector<char>& active);
  // G_x at x for the stresses sigma (ne; elastic + reaction), with the load stiffness of gravity,
  // and W_x of the global moments at load factors (initialFactor, loadFactor).
  void assembleGeometric(const Eigen::VectorXd& x, const Eigen::VectorXd& sigma, const ElementSteps& steps,
                         double initialFactor, double loadFactor);
  void assembleMass(const Eigen::VectorXd& x);

  const Sparse& K() const { return K_; }
  const Sparse& D() const { return D_; }
  const Sparse& G() const { return G_; }
  // W_x on the same pattern (zero outside the moment nodes' 4 x 4 blocks); hasMomentStiffness():
  // some moment is non-zero at the last assembleGeometric.
  const Sparse& W() const { return W_; }
  bool hasMomentStiffness() const { return hasMoments_; }
  const Sparse& M() const { return M_; }
  bool hasDamping() const { return hasDamping_; }

 private:
  void clear(Sparse& A) const { std::fill(A.valuePtr(), A.valuePtr() + A.nonZeros(), 0.0); }
  void addBlock(Sparse& A, int el, const ElemMat& B) const;

  const Model& model_;
  Sparse pattern_, K_, D_, G_, W_, M_;
  std::vector<std::vector<int>> slot_;           // per element: nc*nc value slots (column-major)
  std::vector<int> diagSlot_;                    // per coordinate
  std::vector<std::array<int, 16>> momentSlot_;  // per moment load: its node's 4x4 block
  std::vector<int> massive_;
  bool hasDamping_ = false;
  bool hasMoments_ = false;
};

}  // namespace flexmb::core
