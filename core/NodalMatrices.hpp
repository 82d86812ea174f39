#pragma once
// The linearisation at rest (paper Eq. 16) before its projection on the independent coordinates:
// sparse nodal matrices (nx x nx) assembled from element blocks,
//   K_x = sum_el D_e^T S D_e            (active deformations; Kbar = A^T K_x A, A = F_q V),
//   D_x = sum_el D_e^T S_d D_e          (damping),
//   G_x = sym(H(sigma~) - dg/dx - dm/dx) (stress-weighted Hessians, gravity on distributed masses and
//                                        spatial moment loads; Gbar = A^T G_x A),
//   M_x                                  (element and lumped masses; Mbar = A^T M_x A).
// The pattern (every element block, the diagonal and the moment nodes) is analysed once; each
// assembly only refills values, so a Newton iteration allocates nothing here.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "core/DirectionalDerivative.hpp"
#include "core/Model.hpp"

namespace flexmb::core {

class GeometricTransferFunctions;

class NodalMatrices {
 public:
  using Sparse = Eigen::SparseMatrix<double>;  // column-major, full storage of both triangles
  explicit NodalMatrices(const Model& model);

  // K_x (and D_x when the model has damping) from the element Jacobians of gtf's configuration;
  // active[k]: deformation k carries a stress (Stresses::isActive).
  void assembleStiffness(const GeometricTransferFunctions& gtf, const std::vector<char>& active);
  // G_x at x for the stresses sigma (ne; elastic + reaction), with the load stiffness of gravity
  // and of global moments at load factors (initialFactor, loadFactor).
  void assembleGeometric(const Eigen::VectorXd& x, const Eigen::VectorXd& sigma, const ElementSteps& steps,
                         double initialFactor, double loadFactor);
  void assembleMass(const Eigen::VectorXd& x);

  const Sparse& K() const { return K_; }
  const Sparse& D() const { return D_; }
  const Sparse& G() const { return G_; }
  const Sparse& M() const { return M_; }
  bool hasDamping() const { return hasDamping_; }

 private:
  void clear(Sparse& A) const { std::fill(A.valuePtr(), A.valuePtr() + A.nonZeros(), 0.0); }
  void addBlock(Sparse& A, int el, const ElemMat& B) const;

  const Model& model_;
  Sparse pattern_, K_, D_, G_, M_;
  std::vector<std::vector<int>> slot_;           // per element: nc*nc value slots (column-major)
  std::vector<int> diagSlot_;                    // per coordinate
  std::vector<std::array<int, 16>> momentSlot_;  // per moment load: its node's 4x4 block
  std::vector<int> massive_;
  bool hasDamping_ = false;
};

}  // namespace flexmb::core
