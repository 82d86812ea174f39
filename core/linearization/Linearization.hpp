#pragma once
// Linearised equations of motion (paper Eq. 15) in q = V eta, A = F_q V:
//   M dqdd + (C + D) dqd + (K + N + G) dq = F_q^T df - E_q^T dsigma_a.
// At rest (Eq. 16): Mbar = A^T M A, Kbar = (E_q V)^T S (E_q V), Dbar = (E_q V)^T S_d (E_q V),
//   Gbar = -F_qq^T f + E_qq^T sigma = A^T H A,  H = sum_i sigma~_i d^2 D_i/dx^2,
// sigma~ = elastic stresses + reaction stresses of the constrained deformations solving
// D_x^T sigma~ = f on the calculable coordinates (the constraint second derivatives vanish along q,
// so this identity is exact), and C = N = 0 (left empty). -dQ/dq = Kbar + Gbar is the static Newton tangent.
// In motion (ref. [13]; derivation in core/README.md) the inertia forces M xdd + h join the loads
// in G, and the variations of the velocities and accelerations give
//   C = A^T (M dxdd/dqd + dh/dxd A),
//   N = A^T (M dxdd/dq + d(M xdd + h)/dx A + dh/dxd dxd/dq) + (E_q V)^T S_d de_d/dq.
// Both G variants include the load stiffness of gravity on distributed masses. Global moments on
// Euler parameters add a load stiffness that is antisymmetric (NodalMatrices: W_x), kept apart in
// Gskew: G is the symmetric part, which the symmetric eigen, buckling and stability problems use
// (Gskew does no work along any motion: v^T Gskew v = 0, so their Rayleigh quotients are those of
// the full matrix); Newton tangents and the Jacobians of the motion use G + Gskew.
#include <Eigen/Core>
#include <memory>
#include <optional>

#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/NodalMatrices.hpp"
#include "core/dynamics/ReducedCoordinates.hpp"
#include "core/dynamics/Stresses.hpp"
#include "core/dynamics/Workspace.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/linearization/ConstrainedTangent.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

struct LinearizedSystem {
  Eigen::MatrixXd M, K, G, D;  // m x m (G symmetric); D at rest without damping 0 x 0 (zero)
  Eigen::MatrixXd Gskew;       // m x m, antisymmetric load stiffness of moments; 0 x 0 without
  Eigen::MatrixXd C, N;        // m x m: velocity sensitivity, dynamic stiffening; at rest 0 x 0 (zero)
  // Generalised forces (F_q V)^T (f - D_x^T sigma) at rest; in motion the residual of Eq. 13,
  // (F_q V)^T (f - M xdd - h - D_x^T sigma), which vanishes on a trajectory.
  Eigen::VectorXd Q;
  Eigen::VectorXd sigma;  // elastic + reaction stresses (ne)
};

// Eq. 21 of the full model on the free nodal coordinates (calculable and DYNX), for the sparse
// eigenanalysis: (K_x + G_x) dx = lambda M_x dx + C^T mu, C dx = 0 has the eigenvalues of
// (Kbar + Gbar, Mbar) because F_q spans null(C); the modes in q are P dx (P: the DYNE rows of D_x,
// unit rows for DYNX), with the same mass normalisation (dx^T M_x dx = q^T Mbar q).
struct ConstrainedPencil {
  std::vector<int> free;             // x index of each free coordinate
  Eigen::SparseMatrix<double> K, M;  // K_x + G_x and M_x on the free coordinates (nf x nf)
  Eigen::SparseMatrix<double> C;     // Jacobian of the fixed and input deformations (r x nf)
  Eigen::SparseMatrix<double> P;     // q = P dx (nq x nf)
};

class Linearization {
 public:
  // With a workspace of its own.
  explicit Linearization(const Model& model, std::optional<Eigen::MatrixXd> basis = std::nullopt);
  // On a workspace shared with other evaluators of its model (core/dynamics/Workspace.hpp: it must outlive
  // this object; one call at a time; the nodal matrices are the workspace's, so constrainedPencil
  // reads those of this object's last call only while no other evaluator assembled them since).
  explicit Linearization(Workspace& workspace, std::optional<Eigen::MatrixXd> basis = std::nullopt);
  Linearization(const Linearization&) = delete;
  Linearization& operator=(const Linearization&) = delete;
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
  // The recipe "linearise at rest in the initial configuration": the positions solved at t0 from the
  // initial degrees of freedom, the loads of t0 without increments (XF, XFT(t0), gravity; load factor
  // 0), and atRest there with eta = q0 (full model) or 0 (a basis measures from the initial
  // configuration). What modes, reduction, model diagnostics and the stiffness estimate share.
  void initialRest(LinearizedSystem& out, Eigen::VectorXd& eta, bool withMass = true);
  // Everything about a moving state (eta, etad, etadd) at time t under the model's loads (Eq. 15,
  // ref. [13]). Throws KinematicsError.
  void inMotion(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& etad, const Eigen::VectorXd& etadd,
                LinearizedSystem& out);
  // The nodal matrices at rest without F_q (the sparse eigenanalysis): K_x, G_x with the reaction
  // stresses of the residual f - D_x^T sigma, and M_x. Throws KinematicsError.
  void nodalAtRest(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, bool withMass = true);
  // The pencil above from the nodal matrices of the last atRest / nodalAtRest (withMass) and the
  // element Jacobians of that configuration. Full models only (throws with a basis).
  void constrainedPencil(ConstrainedPencil& out) const;
  // F_q V at the last atRest / tangent / inMotion (nx x m; staticForces does not form it).
  const Eigen::MatrixXd& transfer() const { return FqV_; }
  // Q and the static Newton tangent T = Kbar + Gbar + Gskew only (one projection instead of atRest's
  // four; T is not symmetric under moments on Euler parameters).
  void tangent(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q, Eigen::MatrixXd& T);
  // Q and the diagonal of Kbar = F^T K_x F only (statics' force scale): O(nnz(K_x) m), where
  // atRest's projections cost O(nx m^2) each.
  void stiffnessDiagonal(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q,
                         Eigen::VectorXd& diagonal);
  // F_q V in the current configuration (the positions last solved), without any projection.
  const Eigen::MatrixXd& firstOrderTransfer() {
    updateTransfer();
    return FqV_;
  }
  // Only Q (cheap: no second derivatives, no F_q: one transposed kinematic solve), for line searches.
  void staticForces(double t, const Eigen::VectorXd& eta, const Eigen::VectorXd& f, Eigen::VectorXd& Q);

  // The static Newton iteration of a full model with configuration-dependent loads and a sparse
  // tangent. staticResidual places the model at eta (one kinematic solve), evaluates the loads
  // of (loadFactor, initialFactor) there (gravity on distributed masses and moments follow the
  // configuration) and Q. staticTangent adds Kbar + Gbar, factorised without F_q in the nodal
  // saddle-point form (ConstrainedTangent); false when singular. Full models only (throws with
  // a basis). Both throw KinematicsError.
  void staticResidual(double t, const Eigen::VectorXd& eta, double loadFactor, double initialFactor,
                      Eigen::VectorXd& Q);
  bool staticTangent(double t, const Eigen::VectorXd& eta, double loadFactor, double initialFactor, Eigen::VectorXd& Q);
  // x = (Kbar + Gbar)^-1 b with the last staticTangent.
  void solveStaticTangent(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  // Mbar factorised sparse in the same saddle-point form (H = M_x) at the configuration the positions
  // were last solved in; false when singular. Full models only (throws with a basis). Then
  // solveMass: X = Mbar^-1 B column by column, O(m nnz) where a dense Cholesky costs O(m^3).
  bool factorizeMass();
  void solveMass(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const;

  // An implicit integrator's iteration matrix S = Mbar + gammaP Dbar + betaP (Kbar + Gbar + Gskew)
  // of a full model in the same saddle-point form (no F_q, no C and N: a modified Newton iteration
  // converges without them). iterationMatrix places the model at eta and keeps the nodal matrices
  // there (G with the reaction stresses of f - D_x^T sigma, which the inertia forces balance in
  // motion); factorizeIteration forms S for a step (false when singular); solveIteration gives
  // x = S^-1 Mbar r. Full models only (throws with a basis); iterationMatrix throws KinematicsError.
  void iterationMatrix(double t, const Eigen::VectorXd& eta);
  bool factorizeIteration(double betaP, double gammaP);
  void solveIteration(const Eigen::VectorXd& r, Eigen::VectorXd& x);

 private:
  Linearization(std::unique_ptr<Workspace> own, Workspace* shared, std::optional<Eigen::MatrixXd> basis);
  mutable double loadFactor_ = 0.0, initialFactor_ = 1.0;  // of the last appliedForces
  // out = L^T S R (S or S_d), on the active deformations.
  void constitutiveProduct(const Eigen::MatrixXd& L, const Eigen::MatrixXd& R, bool damping,
                           Eigen::MatrixXd& out) const;
  // G = A^T G_x A (H(sigma~) - dg/dx - dm/dx); sigma~ = sigma_ + reaction stresses for the nodal
  // residual r_. Also assembles the nodal K_x (and D_x).
  void geometricStiffness(LinearizedSystem& out, bool projectG = true);
  // F_q V at the current configuration (formed once per configuration).
  void updateTransfer();
  // Its row-major copy (made at the first use after updateTransfer).
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& transferRows() {
    if (!transferRows_) FqVrows_ = FqV_, transferRows_ = true;
    return FqVrows_;
  }
  // out = A^T X A for a sparse symmetric nodal X, A = F_q V (after updateTransfer).
  void project(const NodalMatrices::Sparse& X, Eigen::MatrixXd& out);
  // Kbar (damping: Dbar) = E_q^T S E_q through the deformations (Eq. 16) when that is cheaper than
  // the nodal projection: a full model whose few calculable deformations carry the only dense rows
  // of E_q (a DYNE deformation's row is its unit row, a fixed or input one's is zero, by Eq. 7).
  // False (out untouched) otherwise; after updateTransfer, with the element Jacobians of the
  // configuration. diagonalOnly: only out's diagonal, as an m x 1 matrix.
  bool deformationProjection(bool damping, Eigen::MatrixXd& out, bool diagonalOnly = false);
  // out += A^T W_x A: the moments' 4 x 4 blocks only (W_x is zero elsewhere).
  void addMomentStiffness(Eigen::MatrixXd& out);
  // Q = (F_q V)^T r_ by one transposed kinematic solve.
  void generalizedForces(Eigen::VectorXd& Q);
  // sigma_, r_ = f - D_x^T sigma and Q at the current kinematic configuration.
  void forcesInPlace(double t, const Eigen::VectorXd& f, Eigen::VectorXd& Q);

  std::unique_ptr<Workspace> own_;  // the workspace when not shared, else null
  const Model& model_;
  ReducedCoordinates coords_;
  int m_;
  GeometricTransferFunctions gtf_;  // its own warm start on the workspace's kinematic structure
  Inertia& inertia_;                // the workspace's
  const Stresses& stresses_;
  const ElementSteps& steps_;
  NodalMatrices& nodal_;
  std::vector<char> active_;  // per deformation: carries a stress
  std::vector<int> defDof_;   // per deformation: its degree of freedom (DYNE), else -1
  std::vector<int> defCalc_;  // per deformation: its row in Ec_ (active and calculable), else -1
  int nCalc_ = 0;
  Eigen::VectorXd q_, qd_, r_, sigma_, xd_, xdd_, ed_, work_, lambda_, qf_;
  Eigen::MatrixXd FqV_, EqV_, MF_, HF_, WA_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> FqVrows_, XArows_, Ec_, SEc_;
  Eigen::VectorXd transferX_;  // the configuration FqV_ was formed in (empty: none yet)
  bool transferRows_ = false;  // FqVrows_ is FqV_'s copy
  Eigen::MatrixXd Gq_;         // the projected G_x of a Newton tangent taken through the deformations
  NodalMatrices::Sparse KG_;
  std::unique_ptr<ConstrainedTangent> constrainedTangent_;     // made at the first staticTangent
  std::unique_ptr<ConstrainedTangent> constrainedMass_;        // made at the first factorizeMass
  std::unique_ptr<ConstrainedTangent> iteration_;              // made at the first iterationMatrix
  double iterationTime_ = 0.0;                                 // its time (input rates of the velocities)
  Eigen::VectorXd iterationRest_, nodalVelocity_, nodalLoad_;  // F_q r from velocities(r) - velocities(0)
  Eigen::VectorXd f_;
  LinearizedSystem scratch_;
  Eigen::MatrixXd dxd_, dxdd_, Y_, Z_, R_, Ed_;  // motion terms
};

// A static equilibrium as the analyses hand it over (a load step, a study's variant, a transfer
// function's operating point): time, load factors (DEL* s, initial loads mu), the linearisation's
// coordinates eta and, when known, the configuration x it was found in (its assembly branch).
struct EquilibriumPoint {
  double t = 0.0, loadFactor = 1.0, initialFactor = 1.0;
  Eigen::VectorXd eta;
  const Eigen::VectorXd* x = nullptr;  // nx, or null: from the model's initial configuration
};

// The recipe the analyses shared by hand: the kinematic tolerance at most 1e-12 of the model size,
// the inputs at the load factors, the positions solved at q(eta) from x's branch (Newton from the
// initial configuration may not reach a large deflection, or reach another branch).
void placeAt(Linearization& lin, const EquilibriumPoint& at);
// placeAt, the applied forces there and M, K, G, C, D, N (Eq. 15-16; withMass = false skips M).
void linearizeAt(Linearization& lin, const EquilibriumPoint& at, LinearizedSystem& out, bool withMass = true);

}  // namespace flexmb::core
