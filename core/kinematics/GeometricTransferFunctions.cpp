#include "core/kinematics/GeometricTransferFunctions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

namespace flexmb::core {

namespace {
std::string describe(double t, int iterations, double residual, const std::string& reason) {
  std::ostringstream s;
  s << "kinematics failed at t = " << t << ": " << reason;
  if (iterations > 0 || std::isfinite(residual))  // a Newton iteration ran: how far it got
    s << " (iterations " << iterations << ", residual " << residual << ")";
  return s.str();
}
}  // namespace

KinematicsError::KinematicsError(double t, int iterations, double residual, const std::string& reason)
    : std::runtime_error(describe(t, iterations, residual, reason)),
      t_(t),
      iterations_(iterations),
      residual_(residual) {}

GeometricTransferFunctions::GeometricTransferFunctions(const Model& model)
    : GeometricTransferFunctions(std::make_unique<KinematicsWorkspace>(model)) {}

GeometricTransferFunctions::GeometricTransferFunctions(KinematicsWorkspace& workspace)
    : model_(workspace.model()), s_(workspace.structure()), w_(workspace.scratch()) {
  initialise(workspace);
}

GeometricTransferFunctions::GeometricTransferFunctions(std::unique_ptr<KinematicsWorkspace> own)
    : own_(std::move(own)), model_(own_->model()), s_(own_->structure()), w_(own_->scratch()) {
  initialise(*own_);
}

void GeometricTransferFunctions::initialise(const KinematicsWorkspace& workspace) {
  // Rows of J are deformation gradients of order 1 (lengths and unit vectors): no row scaling.
  lu_.disableScaling();
  lu_.shareAnalysis(workspace.analysis());
  setRelativeTolerance(model_.settings.kinematicTol);
  const int ne = model_.ne;
  x_ = model_.x0;
  lastGood_ = anchor_ = model_.x0;
  e_ = lastGoodE_ = anchorE_ = Eigen::VectorXd::Zero(ne);
  curvature_ = Eigen::VectorXd::Zero(numConstraints());
  previousX_ = model_.x0;
  elemJac_.resize(model_.elements.size());
}

bool GeometricTransferFunctions::placeSequentially() {
  ElemVec xe;
  DefVec e;
  for (const KinematicsWorkspace::Placement& p : s_.placements) {
    const auto& E = model_.elements[p.element];
    E.gather(x_, xe);
    e.resize(E.impl->numDeformations());
    for (int i = 0; i < e.size(); ++i) e[i] = w_.target[s_.rowOfDef[E.firstDef + i]];
    if (!E.impl->place(e, p.to, xe)) return false;
    for (size_t j = 0; j < E.coords.size(); ++j)
      if (E.impl->endOfCoordinate(static_cast<int>(j)) == p.to) x_[E.coords[j]] = xe[j];
  }
  return true;
}

void GeometricTransferFunctions::setRelativeTolerance(double tol) {
  // Never ask for less than round-off of the coordinates can deliver.
  tolerance_ = std::max(tol, 16 * std::numeric_limits<double>::epsilon()) * s_.lengthScale;
}

Eigen::VectorXd GeometricTransferFunctions::initialDofs() const {
  Eigen::VectorXd q(nq());
  for (int j = 0; j < nq(); ++j) {
    const auto& d = model_.dofs[j];
    if (d.isDeformation) {
      const double v = model_.e0.size() ? model_.e0[d.index] : 0.0;
      q[j] = std::isnan(v) ? 0.0 : v;
    } else {
      q[j] = model_.x0[d.index];
    }
  }
  return q;
}

void GeometricTransferFunctions::setConfiguration(const Eigen::VectorXd& x) {
  x_ = lastGood_ = x;
  lastGoodE_ = e_;
  consistent_ = false;
  hasCurvature_ = false;
}

void GeometricTransferFunctions::setAnchor() {
  if (!consistent_) return;
  anchor_ = x_;
  anchorE_ = e_;
  hasAnchor_ = true;
}

void GeometricTransferFunctions::restartFromAnchor() {
  if (!hasAnchor_) return;
  x_ = lastGood_ = anchor_;
  e_ = lastGoodE_ = anchorE_;
  consistent_ = false;
  hasCurvature_ = false;
}

void GeometricTransferFunctions::setPredictorCurvature(const Eigen::VectorXd& d2) {
  if (!consistent_) return;
  for (int r = 0; r < numConstraints(); ++r) curvature_[r] = d2[s_.constrainedDefs[r]];
  hasCurvature_ = true;
  curvatureScale_ = 0.0;
}

void GeometricTransferFunctions::inputRates(double t, Eigen::VectorXd& xk, Eigen::VectorXd& ek, int order) const {
  // Prescribed coordinates and deformations: value (order 0), rate (1) or acceleration (2).
  for (const auto& r : model_.inputX) {
    double v[3];
    r.evaluate(t, v[0], v[1], v[2]);
    if (initialLoadFactor_ != 1.0) v[0] = r.base + initialLoadFactor_ * (v[0] - r.base);
    v[0] += inputLoadFactor_ * r.delta;
    xk[r.index] = v[order];
  }
  for (const auto& r : model_.inputE) {
    double v[3];
    r.evaluate(t, v[0], v[1], v[2]);
    if (initialLoadFactor_ != 1.0) v[0] *= initialLoadFactor_;
    ek[r.index] = v[order];
  }
}

void GeometricTransferFunctions::constraintTargets(double t, const Eigen::VectorXd& q) {
  w_.workE.setZero();
  inputRates(t, x_, w_.workE, 0);  // input coordinates straight into x, input deformations into w_.workE
  for (int r = 0; r < numConstraints(); ++r) w_.target[r] = w_.workE[s_.constrainedDefs[r]];
  for (int j = 0; j < nq(); ++j) {
    if (s_.dofRow[j] >= 0)
      w_.target[s_.dofRow[j]] = q[j];
    else
      x_[s_.dofCoord[j]] = q[j];
  }
}

void GeometricTransferFunctions::evaluateElements(bool withJacobian) {
  ElemVec xe;
  DefVec de;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(x_, xe);
    DefJac& De = elemJac_[el];
    if (withJacobian)
      E.impl->deformationsAndJacobian(xe, de, De);
    else
      E.impl->deformations(xe, de);
    for (int i = 0; i < de.size(); ++i) {
      const int k = E.firstDef + i;
      if (s_.hasPeriodic && s_.periodic[k]) {
        // A principal-value angle: take the revolution nearest to the prescribed value (DOF or
        // input) or, for a calculable angle, to the previous one, so e and the residual of Eq. 7
        // stay continuous through pi.
        const double ref = s_.rowOfDef[k] >= 0 ? w_.target[s_.rowOfDef[k]] : e_[k];
        e_[k] = ref + std::remainder(de[i] - ref, 2.0 * M_PI);
      } else {
        e_[k] = de[i];
      }
    }
    if (withJacobian) storeJacobian(el);
  }
}

void GeometricTransferFunctions::storeJacobian(size_t el) {
  const double* d = elemJac_[el].data();
  for (int p = s_.slotRange[el]; p < s_.slotRange[el + 1]; ++p) w_.values[s_.slotFlat[p]] = d[s_.slotLocal[p]];
}

void GeometricTransferFunctions::evaluateJacobians() {
  ElemVec xe;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(x_, xe);
    E.impl->jacobian(xe, elemJac_[el]);
    storeJacobian(el);
  }
}

void GeometricTransferFunctions::solvePositions(double t, const Eigen::VectorXd& q) {
  if (!isSquare())
    throw KinematicsError(t, 0, std::numeric_limits<double>::quiet_NaN(),
                          "the kinematic equations are not square (" + std::to_string(numCalculable()) +
                              " calculable coordinates, " + std::to_string(numConstraints()) +
                              " constraints); run `flexmb check`");
  // A failed solve from a warm start far away (a trial state of the integrator) is retried from the
  // last converged configuration, then from the anchor (that converged configuration may itself be
  // a far trial state); a diverged iterate is never kept as the next start.
  const bool warmIsLastGood = x_ == lastGood_;
  try {
    newton(t, q);
  } catch (const KinematicsError& first) {
    KinematicsError error = first;
    const bool solved = (!warmIsLastGood && retryNewton(t, q, lastGood_, lastGoodE_, error)) ||
                        (hasAnchor_ && anchor_ != lastGood_ && retryNewton(t, q, anchor_, anchorE_, error));
    if (!solved) {
      x_ = lastGood_;
      e_ = lastGoodE_;
      throw error;
    }
  }
  lastGood_ = x_;
  lastGoodE_ = e_;
}

bool GeometricTransferFunctions::retryNewton(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& x,
                                             const Eigen::VectorXd& e, KinematicsError& error) {
  x_ = x;
  e_ = e;  // the reference of calculable periodic angles
  try {
    newton(t, q);
    return true;
  } catch (const KinematicsError& again) {
    error = again;
    return false;
  }
}

double GeometricTransferFunctions::predict() {
  // The first Newton step from the last solution reuses its factorisation and deformations: with
  // the known coordinates already moved by constraintTargets, J dx_c = target - e - D_k dx_k, which
  // is the linear predictor x + F_q dq (+ F_t dt) of the transfer functions. With the convective
  // terms of the last evaluation, - s^2/2 D2_C[xd, xd] on the right adds the second-order term
  // of the motion (dq ~ s qd between the stages of an integrator), at no extra solve.
  double res = 0.0;
  const bool curved = hasCurvature_ && curvatureScale_ != 0.0;
  const double half = 0.5 * curvatureScale_ * curvatureScale_;
  hasCurvature_ = false;
  curvatureScale_ = 0.0;
  for (int r = 0; r < numConstraints(); ++r) {
    const int k = s_.constrainedDefs[r];
    double d = w_.target[r] - e_[k];
    if (s_.hasPeriodic && s_.periodic[k]) d = std::remainder(d, 2.0 * M_PI);
    w_.rhs[r] = d;
    res = std::max(res, std::abs(d));
    if (curved) w_.rhs[r] -= half * curvature_[r];
  }
  bool moved = false;
  if (s_.knownMoved) {
    for (int i = 0; i < nx(); ++i) {
      w_.work[i] = s_.colOfCoord[i] < 0 ? x_[i] - previousX_[i] : 0.0;
      moved |= w_.work[i] != 0.0;
    }
    if (moved) knownCoupling(w_.work, w_.rhs.data());
  }
  // Nothing moved and the last solution still satisfies the equations: keep it as it is (the same
  // state gives the same configuration, bit for bit).
  if (!moved && !curved && res <= tolerance_) return res;
  lu_.solve(w_.rhs.data(), 1);
  for (int c = 0; c < numCalculable(); ++c) x_[s_.calcCoords[c]] += w_.rhs[c];
  return res;
}

void GeometricTransferFunctions::newton(double t, const Eigen::VectorXd& q) {
  // Fixed coordinates keep x0; inputs and DYNX are set by constraintTargets.
  const bool warm = consistent_;
  consistent_ = false;
  if (!warm) hasCurvature_ = false, curvatureScale_ = 0.0;
  if (warm && s_.knownMoved) previousX_ = x_;
  constraintTargets(t, q);
  const int maxIt = std::max(1, model_.settings.maxIterations);
  int steps = 0;
  double previous = std::numeric_limits<double>::infinity();
  bool chord = warm;
  if (!s_.placements.empty()) {
    // Open chain: one pass of closed-form placements gives the solution (checked below); where an
    // element has none on its valid branch, Newton continues from the last solution.
    hasCurvature_ = false;
    chord = false;
    if (!placeSequentially())
      for (int c = 0; c < numCalculable(); ++c) x_[s_.calcCoords[c]] = lastGood_[s_.calcCoords[c]];
  } else if (warm) {
    previous = predict();
    ++steps;
  }
  // Simplified Newton: the factorisation is reused while the residual contracts quickly, and
  // refreshed where it does not; the converged configuration always gets its own factorisation
  // (velocities, F_q and the saddle-point rows need the exact Jacobian).
  // The check of a prediction that missed last time evaluates the deformations only: a chord step
  // needs no Jacobian, and it would be thrown away (the reduced models' larger steps miss most
  // predictions); the Jacobian follows where this x is kept or refactorised.
  double res = 0.0;
  for (int it = steps; it <= maxIt; ++it) {
    const bool withJacobian = !(chord && it == 1 && predictionMissed_);
    evaluateElements(withJacobian);
    res = 0.0;
    for (int r = 0; r < numConstraints(); ++r) {
      w_.rhs[r] = w_.target[r] - e_[s_.constrainedDefs[r]];
      res = std::max(res, std::abs(w_.rhs[r]));
    }
    if (!std::isfinite(res)) throw KinematicsError(t, it, res, "non-finite residual");
    const bool converged = res <= tolerance_;
    const bool slow = !chord || res > kChordContraction * previous;
    if (chord && it == 1) predictionMissed_ = !converged;
    if (converged || slow) {
      if (!withJacobian) evaluateJacobians();
      if (!lu_.factorize(w_.values.data()))
        throw KinematicsError(t, it, res, "singular kinematic Jacobian (dead point or bad constraints)");
    }
    if (converged) {
      lastIterations_ = it;
      consistent_ = true;
      return;
    }
    if (it == maxIt) break;
    if (res > 1e3 * s_.lengthScale) throw KinematicsError(t, it, res, "Newton iteration diverged");
    previous = res;
    lu_.solve(w_.rhs.data(), 1);
    for (int c = 0; c < numCalculable(); ++c) x_[s_.calcCoords[c]] += w_.rhs[c];
  }
  throw KinematicsError(t, maxIt, res, "Newton iteration did not converge");
}

void GeometricTransferFunctions::knownCoupling(const Eigen::VectorXd& v, double* rhs) const {
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& De = elemJac_[el];
    const int nc = static_cast<int>(E.coords.size());
    for (int i = 0; i < De.rows(); ++i) {
      const int row = s_.rowOfDef[E.firstDef + i];
      if (row < 0) continue;
      double s = 0.0;
      for (int j = 0; j < nc; ++j) s += De(i, j) * v[E.coords[j]];
      rhs[row] -= s;
    }
  }
}

void GeometricTransferFunctions::firstOrder(const Eigen::MatrixXd* V, Eigen::MatrixXd& FqV) {
  // Columns of F_q V: J x_c = b - J_k x_k per basis vector, all solved in one multi-RHS call.
  const int m = V ? static_cast<int>(V->cols()) : nq();
  const int n = numCalculable();
  FqV.setZero(nx(), m);
  w_.rhsMat.setZero(n, m);
  const int* row = s_.dofRow.data();
  for (int c = 0; c < m; ++c) {
    if (V) {  // every dof's entry (no test for zeros: the loop is branch-predictable)
      const double* v = V->col(c).data();
      double* r = w_.rhsMat.col(c).data();
      for (int j = 0; j < nq(); ++j) {
        if (row[j] >= 0)
          r[row[j]] += v[j];
        else
          FqV(s_.dofCoord[j], c) = v[j];
      }
    } else if (row[c] >= 0) {
      w_.rhsMat(row[c], c) = 1.0;
    } else {
      FqV(s_.dofCoord[c], c) = 1.0;
    }
    if (s_.hasDynamicCoords) {
      w_.work = FqV.col(c);
      knownCoupling(w_.work, w_.rhsMat.col(c).data());
    }
  }
  lu_.solve(w_.rhsMat.data(), m);
  for (int c = 0; c < m; ++c)
    for (int k = 0; k < n; ++k) FqV(s_.calcCoords[k], c) = w_.rhsMat(k, c);
}

void GeometricTransferFunctions::velocities(double t, const Eigen::VectorXd& qd, Eigen::VectorXd& xd) {
  xd.setZero(nx());
  w_.workE.setZero();
  inputRates(t, xd, w_.workE, 1);
  for (int r = 0; r < numConstraints(); ++r) w_.rhs[r] = w_.workE[s_.constrainedDefs[r]];
  for (int j = 0; j < nq(); ++j) {
    if (s_.dofRow[j] >= 0)
      w_.rhs[s_.dofRow[j]] = qd[j];
    else
      xd[s_.dofCoord[j]] = qd[j];
  }
  for (int c = 0; c < numCalculable(); ++c) xd[s_.calcCoords[c]] = 0.0;
  if (s_.knownMoved) knownCoupling(xd, w_.rhs.data());  // else every known coordinate is at rest
  lu_.solve(w_.rhs.data(), 1);
  for (int c = 0; c < numCalculable(); ++c) xd[s_.calcCoords[c]] = w_.rhs[c];
}

void GeometricTransferFunctions::accelerationOffset(double t, const Eigen::VectorXd& xd, Eigen::VectorXd& g) {
  // Convective part D2[xd, xd] of every deformation, then the solve.
  w_.workE.setZero();
  ElemVec xe, ve;
  DefVec d2;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(xd, ve);
    if (ve.isZero(0.0)) continue;
    E.gather(x_, xe);
    E.impl->secondDerivative(xe, ve, d2);
    for (int i = 0; i < d2.size(); ++i) w_.workE[E.firstDef + i] = d2[i];
  }
  w_.convectiveD2 = w_.workE;
  accelerationOffsetFrom(t, w_.convectiveD2, g);
}

void GeometricTransferFunctions::accelerationOffsetFrom(double t, const Eigen::VectorXd& d2, Eigen::VectorXd& g) {
  g.setZero(nx());
  w_.workE.setZero();
  inputRates(t, g, w_.workE, 2);
  for (int c = 0; c < numCalculable(); ++c) g[s_.calcCoords[c]] = 0.0;
  for (int j = 0; j < nq(); ++j)
    if (s_.dofCoord[j] >= 0) g[s_.dofCoord[j]] = 0.0;
  // J g_c = edd_input - D_k g_k - D2_C[xd, xd] (Eq. 8b with qdd = 0; F_qq is never formed).
  for (int r = 0; r < numConstraints(); ++r) w_.rhs[r] = w_.workE[s_.constrainedDefs[r]];
  for (int j = 0; j < nq(); ++j)
    if (s_.dofRow[j] >= 0) w_.rhs[s_.dofRow[j]] = 0.0;  // qdd = 0
  if (s_.knownMoved) knownCoupling(g, w_.rhs.data());
  for (int r = 0; r < numConstraints(); ++r) w_.rhs[r] -= d2[s_.constrainedDefs[r]];
  lu_.solve(w_.rhs.data(), 1);
  for (int c = 0; c < numCalculable(); ++c) g[s_.calcCoords[c]] = w_.rhs[c];
}

void GeometricTransferFunctions::deformationRates(const Eigen::VectorXd& xd, Eigen::VectorXd& ed) const {
  ed.setZero(ne());
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& De = elemJac_[el];
    for (int i = 0; i < De.rows(); ++i) {
      double s = 0.0;
      for (int j = 0; j < De.cols(); ++j) s += De(i, j) * xd[E.coords[j]];
      ed[E.firstDef + i] = s;
    }
  }
}

void GeometricTransferFunctions::deformationAccelerations(const Eigen::VectorXd& xd, const Eigen::VectorXd& xdd,
                                                          Eigen::VectorXd& edd) const {
  deformationRates(xdd, edd);
  ElemVec xe, ve;
  DefVec d2;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(x_, xe);
    E.gather(xd, ve);
    E.impl->secondDerivative(xe, ve, d2);
    for (int i = 0; i < d2.size(); ++i) edd[E.firstDef + i] += d2[i];
  }
}

void GeometricTransferFunctions::addTransposedJacobianProduct(const Eigen::VectorXd& s, Eigen::VectorXd& y,
                                                              double scale) const {
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& De = elemJac_[el];
    for (int i = 0; i < De.rows(); ++i) {
      const double si = scale * s[E.firstDef + i];
      if (si == 0.0) continue;
      for (int j = 0; j < De.cols(); ++j) y[E.coords[j]] += De(i, j) * si;
    }
  }
}

void GeometricTransferFunctions::deformationFirstOrder(const Eigen::MatrixXd& FqV, Eigen::MatrixXd& EqV) const {
  EqV.setZero(ne(), FqV.cols());
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& De = elemJac_[el];
    for (int i = 0; i < De.rows(); ++i)
      for (int j = 0; j < De.cols(); ++j) EqV.row(E.firstDef + i) += De(i, j) * FqV.row(E.coords[j]);
  }
}

}  // namespace flexmb::core

namespace flexmb::core {

void GeometricTransferFunctions::addConstraintStresses(const Eigen::VectorXd& r, Eigen::VectorXd& sigma) {
  for (int c = 0; c < numCalculable(); ++c) w_.rhs[c] = r[s_.calcCoords[c]];
  lu_.solveTransposed(w_.rhs.data(), 1);
  for (int k = 0; k < numConstraints(); ++k) sigma[s_.constrainedDefs[k]] += w_.rhs[k];
}

}  // namespace flexmb::core

namespace flexmb::core {

void GeometricTransferFunctions::secondDerivativeProduct(const Eigen::VectorXd& b, const Eigen::MatrixXd& A,
                                                         Eigen::MatrixXd& Y) const {
  const int m = static_cast<int>(A.cols());
  Y.setZero(ne(), m);
  ElemVec xe, be, ae, v;
  DefVec dp, dm;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(b, be);
    if (be.isZero(0.0)) continue;
    E.gather(x_, xe);
    for (int j = 0; j < m; ++j) {
      ae.resize(static_cast<int>(E.coords.size()));
      for (size_t k = 0; k < E.coords.size(); ++k) ae[k] = A(E.coords[k], j);
      const double an = ae.norm();
      if (an == 0.0) continue;
      // D2[b + s a] - D2[b - s a] = 4 s D2[b, a]; s balances the two magnitudes.
      const double s = be.norm() / an;
      v = be + s * ae;
      E.impl->secondDerivative(xe, v, dp);
      v = be - s * ae;
      E.impl->secondDerivative(xe, v, dm);
      for (int i = 0; i < dp.size(); ++i) Y(E.firstDef + i, j) = (dp[i] - dm[i]) / (4.0 * s);
    }
  }
}

void GeometricTransferFunctions::thirdDerivativeProduct(const Eigen::VectorXd& b, const Eigen::MatrixXd& A,
                                                        const ElementSteps& steps, Eigen::MatrixXd& Y) const {
  const int m = static_cast<int>(A.cols());
  Y.setZero(ne(), m);
  ElemVec xe, be, ae;
  DefVec d;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(b, be);
    if (be.isZero(0.0)) continue;
    E.gather(x_, xe);
    const Element& impl = *E.impl;
    auto d2 = [&](const ElemVec& xx, DefVec& out) { impl.secondDerivative(xx, be, out); };
    for (int j = 0; j < m; ++j) {
      ae.resize(static_cast<int>(E.coords.size()));
      for (size_t k = 0; k < E.coords.size(); ++k) ae[k] = A(E.coords[k], j);
      const double h = steps.step(static_cast<int>(el), ae);
      if (h == 0.0) continue;
      directionalDerivative(d2, xe, ae, h, d);
      for (int i = 0; i < d.size(); ++i) Y(E.firstDef + i, j) = d[i];
    }
  }
}

void GeometricTransferFunctions::solveConstrained(const Eigen::MatrixXd& R, Eigen::MatrixXd& Z) {
  const int m = static_cast<int>(R.cols()), n = numCalculable();
  Z.setZero(nx(), m);
  if (n == 0 || m == 0) return;
  w_.rhsMat.resize(n, m);
  for (int j = 0; j < m; ++j)
    for (int r = 0; r < n; ++r) w_.rhsMat(r, j) = R(s_.constrainedDefs[r], j);
  lu_.solve(w_.rhsMat.data(), m);
  for (int j = 0; j < m; ++j)
    for (int c = 0; c < n; ++c) Z(s_.calcCoords[c], j) = w_.rhsMat(c, j);
}

}  // namespace flexmb::core
