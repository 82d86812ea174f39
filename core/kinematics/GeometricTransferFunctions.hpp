#pragma once
// Geometric transfer functions x = F(q, t), e = E(q, t) and their derivatives (paper Eq. 7-8),
// solved by Newton on the kinematic equations D_C(x) = target (fixed, input and dynamic
// deformations) for the calculable nodal coordinates. The sparse pattern is analysed once, in the
// model's KinematicsWorkspace, which several of these objects may share (one thread at a time, see
// core/kinematics/KinematicsWorkspace.hpp); each keeps its own configuration, warm start and factorisation.
#include <Eigen/Core>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/kinematics/DirectionalDerivative.hpp"
#include "core/kinematics/KinematicsWorkspace.hpp"
#include "core/kinematics/SparseLU.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

// A kinematic solve that failed: keeps the time and the reason (design: report, don't ignore).
class KinematicsError : public std::runtime_error {
 public:
  KinematicsError(double t, int iterations, double residual, const std::string& reason);
  double time() const { return t_; }
  int iterations() const { return iterations_; }
  double residual() const { return residual_; }

 private:
  double t_;
  int iterations_;
  double residual_;
};

class GeometricTransferFunctions {
 public:
  // With a workspace of its own.
  explicit GeometricTransferFunctions(const Model& model);
  // On a shared workspace (of the same model), which must outlive this object.
  explicit GeometricTransferFunctions(KinematicsWorkspace& workspace);
  GeometricTransferFunctions(const GeometricTransferFunctions&) = delete;
  GeometricTransferFunctions& operator=(const GeometricTransferFunctions&) = delete;

  const Model& model() const { return model_; }
  int nx() const { return model_.nx; }
  int ne() const { return model_.ne; }
  int nq() const { return model_.numDofs(); }
  int numCalculable() const { return s_.numCalculable(); }
  int numConstraints() const { return s_.numConstraints(); }
  // True when the kinematic equations are square (a prerequisite for solving).
  bool isSquare() const { return s_.isSquare(); }

  // q of the initial configuration: DYNX values of x0, DYNE values e0 (0 where not given).
  Eigen::VectorXd initialDofs() const;

  // Solves the positions for (t, q): x and e. Warm-starts from the last solution.
  // Throws KinematicsError when Newton does not converge or the Jacobian is singular.
  void solvePositions(double t, const Eigen::VectorXd& q);

  // Sets a new warm start (e.g. to restart from the initial configuration).
  void setConfiguration(const Eigen::VectorXd& x);
  // The anchor: the configuration of the integrator's last accepted state. setAnchor() makes the
  // configuration just solved the anchor (ignored when the last solve failed); a solve that fails
  // from its warm start and from the last converged configuration is retried from the anchor, and
  // restartFromAnchor() makes it the next warm start (before an integrator retries a rejected step,
  // whose trial states may have converged far away or on another assembly branch).
  void setAnchor();
  void restartFromAnchor();
  // Second-order predictor (Eq. 8b): d2 = D2[xd, xd] (ne) of the configuration just solved, with
  // xd = F_q qd. When the next change of q is s qd (as between the stages of an integrator),
  // usePredictorCurvature(s) before the next solvePositions adds s^2/2 F_qq[qd, qd] to the linear
  // predictor x + F_q dq, in the same solve. Both are used once, by the next solve only.
  void setPredictorCurvature(const Eigen::VectorXd& d2);
  void usePredictorCurvature(double s) { curvatureScale_ = s; }

  // After solvePositions: F_q V (nx x m) for a basis V (nq x m); V = nullptr means identity.
  void firstOrder(const Eigen::MatrixXd* V, Eigen::MatrixXd& FqV);
  // xd = F_q qd + F_t: one solve (rheonomic rates included).
  void velocities(double t, const Eigen::VectorXd& qd, Eigen::VectorXd& xd);
  // g = xdd at qdd = 0: (F_qq qd) qd plus the rheonomic acceleration terms. One solve.
  void accelerationOffset(double t, const Eigen::VectorXd& xd, Eigen::VectorXd& g);
  // The same from the convective terms d2 = D2[xd, xd] of every deformation (ne), computed by the
  // caller (the equations of motion get them with the element masses).
  void accelerationOffsetFrom(double t, const Eigen::VectorXd& d2, Eigen::VectorXd& g);
  // Prescribed accelerations at t: xk[i] for input coordinates, ek[k] for input deformations;
  // other entries are left as they are.
  void prescribedAccelerations(double t, Eigen::VectorXd& xk, Eigen::VectorXd& ek) const { inputRates(t, xk, ek, 2); }
  // ed = D_x xd (all deformations).
  void deformationRates(const Eigen::VectorXd& xd, Eigen::VectorXd& ed) const;
  // edd = D_x xdd + D2[xd, xd] (all deformations).
  void deformationAccelerations(const Eigen::VectorXd& xd, const Eigen::VectorXd& xdd, Eigen::VectorXd& edd) const;
  // y += scale * D_x^T s (nodal forces dual to stresses s).
  void addTransposedJacobianProduct(const Eigen::VectorXd& s, Eigen::VectorXd& y, double scale = 1.0) const;
  // Reaction stresses of the constrained rows: solves J^T lambda = r_c (r: nodal vector, its
  // calculable part) and adds lambda into sigma (size ne) at the constrained deformations.
  void addConstraintStresses(const Eigen::VectorXd& r, Eigen::VectorXd& sigma);
  // Newton tolerance relative to the model size (floored at round-off). Integrators set it well
  // below their own tolerance: residual noise in x becomes noise in the right-hand side.
  void setRelativeTolerance(double tol);
  // Static load stepping: input coordinates get x + s * DELINPX.
  // Static load steps: input x = base + initial (x0 - base) + s delta (DELINPX, the total at s = 1).
  void setInputLoadFactor(double s, double initial = 1.0) {
    inputLoadFactor_ = s;
    initialLoadFactor_ = initial;
  }
  // E_q V = D_x F_q V (ne x m) from a computed F_q V.
  void deformationFirstOrder(const Eigen::MatrixXd& FqV, Eigen::MatrixXd& EqV) const;

  // For the linearisation of a moving system (Eq. 15, ref. [13]), after solvePositions:
  // Y (ne x m), column j = D2[b, A_j], the symmetric second derivative of all deformations
  // (polarisation of the analytic D2e[v, v]: exact).
  void secondDerivativeProduct(const Eigen::VectorXd& b, const Eigen::MatrixXd& A, Eigen::MatrixXd& Y) const;
  // Y (ne x m), column j = D3[A_j, b, b], the change of D2[b, b] along A_j (element Richardson).
  void thirdDerivativeProduct(const Eigen::VectorXd& b, const Eigen::MatrixXd& A, const ElementSteps& steps,
                              Eigen::MatrixXd& Y) const;
  // Z (nx x m): J Z_c = R_C, R (ne x m) read on the constrained deformations; the other
  // coordinates 0. The calculable response with the known coordinates held.
  void solveConstrained(const Eigen::MatrixXd& R, Eigen::MatrixXd& Z);

  const Eigen::VectorXd& x() const { return x_; }
  const Eigen::VectorXd& e() const { return e_; }
  // Element Jacobian at the current configuration (cached by solvePositions).
  const DefJac& elementJacobian(int element) const { return elemJac_[element]; }
  int lastIterations() const { return lastIterations_; }
  // The kinematic equations form an open chain solved in one pass (no Newton iteration).
  bool isSequential() const { return !s_.placements.empty(); }
  // Factorisations of the kinematic Jacobian with fresh pivoting so far (tests).
  long pivotings() const { return lu_.pivotings(); }

  // Index maps (for diagnostics and the kinematic check).
  const std::vector<int>& calculableCoords() const { return s_.calcCoords; }
  const std::vector<int>& constrainedDeformations() const { return s_.constrainedDefs; }

 private:
  void evaluateElements(bool withJacobian = true);  // e, element Jacobians, J values at x_
  void evaluateJacobians();                         // element Jacobians and J values only
  void storeJacobian(size_t el);                    // element el's Jacobian into J's value slots
  void constraintTargets(double t, const Eigen::VectorXd& q);
  void inputRates(double t, Eigen::VectorXd& xk, Eigen::VectorXd& ek, int order) const;
  // rhs_r = b_r - (D_x v)_r for constrained rows; v holds known-coordinate values.
  void knownCoupling(const Eigen::VectorXd& v, double* rhs) const;

  explicit GeometricTransferFunctions(std::unique_ptr<KinematicsWorkspace> own);
  void initialise(const KinematicsWorkspace& workspace);

  std::unique_ptr<KinematicsWorkspace> own_;  // the workspace when not shared, else null
  const Model& model_;
  const KinematicsWorkspace::Structure& s_;
  KinematicsWorkspace::Scratch& w_;  // per call only
  // What one call leaves for the next (the warm start; never shared, see KinematicsWorkspace.hpp):
  SparseLU lu_;  // the factorisation of J at the last converged configuration (chord steps, predictor)
  double tolerance_ = 1e-10;

  Eigen::VectorXd lastGood_, lastGoodE_;  // last converged configuration: the restart point after a failure
  Eigen::VectorXd anchor_, anchorE_;      // the integrator's last accepted configuration (setAnchor)
  bool hasAnchor_ = false;
  bool retryNewton(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& x, const Eigen::VectorXd& e,
                   KinematicsError& error);
  void newton(double t, const Eigen::VectorXd& q);
  // Open chains (design: no iteration where the topology allows): the workspace's placement order,
  // each element placing one end from the other with its closed form (Element::place).
  bool placeSequentially();  // false when an element had no solution: Newton takes over
  double predict();          // returns the residual it started from
  // A chord (simplified Newton) step is kept while the residual falls at least this much per step;
  // slower contraction refactorises (measured on the paper's models: 0.1 and 0.01 cost more
  // element evaluations than a refactorisation saves).
  static constexpr double kChordContraction = 1e-3;
  // x_, e_ and the factorisation belong to one converged configuration (the predictor may start).
  bool consistent_ = false;
  bool hasCurvature_ = false;      // curvature_ belongs to the consistent configuration
  bool predictionMissed_ = false;  // the last predicted configuration needed a correction
  double curvatureScale_ = 0.0;
  Eigen::VectorXd curvature_;  // D2_C[xd, xd] on the constrained rows
  Eigen::VectorXd previousX_;
  Eigen::VectorXd x_, e_;
  std::vector<DefJac> elemJac_;  // D_e at x_ (the predictor's known-coordinate coupling reads them)
  double inputLoadFactor_ = 0.0;
  double initialLoadFactor_ = 1.0;
  int lastIterations_ = 0;
};

}  // namespace flexmb::core
