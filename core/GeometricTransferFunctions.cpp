#include "core/GeometricTransferFunctions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

namespace flexmb::core {

namespace {
std::string describe(double t, int iterations, double residual, const std::string& reason) {
  std::ostringstream s;
  s << "kinematics failed at t = " << t << ": " << reason << " (iterations " << iterations << ", residual " << residual
    << ")";
  return s.str();
}
}  // namespace

KinematicsError::KinematicsError(double t, int iterations, double residual, const std::string& reason)
    : std::runtime_error(describe(t, iterations, residual, reason)),
      t_(t),
      iterations_(iterations),
      residual_(residual) {}

GeometricTransferFunctions::GeometricTransferFunctions(const Model& model) : model_(model) {
  const int nx = model.nx, ne = model.ne;
  colOfCoord_.assign(nx, -1);
  for (int i = 0; i < nx; ++i)
    if (model.xRole[i] == Role::Calculable) {
      colOfCoord_[i] = static_cast<int>(calcCoords_.size());
      calcCoords_.push_back(i);
    }
  rowOfDef_.assign(ne, -1);
  for (int k = 0; k < ne; ++k)
    if (model.eRole[k] != Role::Calculable) {
      rowOfDef_[k] = static_cast<int>(constrainedDefs_.size());
      constrainedDefs_.push_back(k);
    }
  for (const auto& d : model.dofs) {
    dofRow_.push_back(d.isDeformation ? rowOfDef_[d.index] : -1);
    dofCoord_.push_back(d.isDeformation ? -1 : d.index);
    hasDynamicCoords_ |= !d.isDeformation;
  }
  knownMoved_ = hasDynamicCoords_ || !model.inputX.empty();

  periodic_.assign(ne, 0);
  for (const auto& E : model.elements)
    for (int i = 0; i < E.impl->numDeformations(); ++i)
      if (E.impl->isPeriodicAngle(i)) periodic_[E.firstDef + i] = 1, hasPeriodic_ = true;

  // Pattern of J = dD_C/dx_calc, built once; every element entry gets its value slot.
  std::vector<std::tuple<int, int, int, int>> entries;  // col, row, element, local slot
  slot_.resize(model.elements.size());
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nd = E.impl->numDeformations(), nc = E.impl->numCoords();
    slot_[el].assign(nd * nc, -1);
    for (int i = 0; i < nd; ++i) {
      const int row = rowOfDef_[E.firstDef + i];
      if (row < 0) continue;
      for (int j = 0; j < nc; ++j) {
        const int col = colOfCoord_[E.coords[j]];
        if (col >= 0) entries.emplace_back(col, row, static_cast<int>(el), i * nc + j);
      }
    }
  }
  std::sort(entries.begin(), entries.end());
  const int n = numCalculable();
  colPtr_.assign(n + 1, 0);
  rowIdx_.clear();
  for (size_t k = 0; k < entries.size(); ++k) {
    const auto [col, row, el, s] = entries[k];
    if (k > 0 && std::get<0>(entries[k - 1]) == col && std::get<1>(entries[k - 1]) == row) {
      // Two elements cannot share a deformation row, so duplicates do not occur.
      continue;
    }
    slot_[el][s] = static_cast<int>(rowIdx_.size());
    rowIdx_.push_back(row);
    ++colPtr_[col + 1];
  }
  for (int c = 0; c < n; ++c) colPtr_[c + 1] += colPtr_[c];
  values_.assign(rowIdx_.size(), 0.0);
  // Flat (value slot, entry of D_e) lists per element for evaluateElements: no branches there.
  slotRange_.assign(1, 0);
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nd = E.impl->numDeformations(), nc = E.impl->numCoords();
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nc; ++j)
        if (slot_[el][i * nc + j] >= 0) {
          slotFlat_.push_back(slot_[el][i * nc + j]);
          slotLocal_.push_back(i + j * nd);  // DefJac is column-major with leading dimension nd
        }
    slotRange_.push_back(static_cast<int>(slotFlat_.size()));
  }
  slot_.clear();
  // Rows of J are deformation gradients of order 1 (lengths and unit vectors): no row scaling.
  lu_.disableScaling();
  if (isSquare() && n > 0) lu_.analyze(n, colPtr_.data(), rowIdx_.data());

  // Length scale for the Newton tolerance: the model's extent (at least the longest element).
  double scale = 0.0;
  for (int i = 0; i < nx; ++i)
    if (isTranslational(model.nodes[model.xOwnerNode[i]].kind)) scale = std::max(scale, std::abs(model.x0[i]));
  lengthScale_ = scale > 0.0 ? scale : 1.0;
  setRelativeTolerance(model.settings.kinematicTol);

  analysePlacements();

  x_ = model.x0;
  lastGood_ = anchor_ = model.x0;
  e_ = lastGoodE_ = anchorE_ = Eigen::VectorXd::Zero(ne);
  target_ = Eigen::VectorXd::Zero(numConstraints());
  rhs_ = Eigen::VectorXd::Zero(std::max(n, 1));
  work_ = Eigen::VectorXd::Zero(nx);
  convectiveD2_ = Eigen::VectorXd::Zero(ne);
  curvature_ = Eigen::VectorXd::Zero(numConstraints());
  previousX_ = model.x0;
  workE_ = Eigen::VectorXd::Zero(ne);
  elemJac_.resize(model.elements.size());
}

void GeometricTransferFunctions::analysePlacements() {
  // Repeatedly place an element whose deformations are all prescribed (fixed, input, dynamic) and
  // of whose two ends one is known and the other unknown; the chain is sequential when this places
  // every calculable coordinate and uses every such element exactly once (a closed loop leaves an
  // element with both ends known: its equations are not a placement).
  if (!isSquare() || numCalculable() == 0) return;
  const auto& els = model_.elements;
  std::vector<char> known(nx()), done(els.size(), 0);
  for (int i = 0; i < nx(); ++i) known[i] = colOfCoord_[i] < 0;
  int pending = 0;
  for (size_t el = 0; el < els.size(); ++el) {
    const auto& E = els[el];
    int constrained = 0;
    for (int i = 0; i < E.impl->numDeformations(); ++i) constrained += rowOfDef_[E.firstDef + i] >= 0;
    if (constrained == 0) {
      done[el] = 1;  // no equations of its own
    } else if (constrained < E.impl->numDeformations() || E.impl->endOfCoordinate(0) < 0) {
      return;  // partly released, or no closed form: Newton
    } else {
      ++pending;
    }
  }
  std::vector<Placement> order;
  for (bool progress = true; progress && pending > 0;) {
    progress = false;
    for (size_t el = 0; el < els.size(); ++el) {
      if (done[el]) continue;
      const auto& E = els[el];
      bool endKnown[2] = {true, true}, endUnknown[2] = {true, true};
      for (size_t j = 0; j < E.coords.size(); ++j) {
        const int end = E.impl->endOfCoordinate(static_cast<int>(j));
        (known[E.coords[j]] ? endUnknown : endKnown)[end] = false;
      }
      if (endKnown[0] && endKnown[1]) return;  // redundant equations: a closed loop
      for (int to = 0; to < 2; ++to)
        if (endKnown[1 - to] && endUnknown[to]) {
          order.push_back({static_cast<int>(el), to});
          for (size_t j = 0; j < E.coords.size(); ++j)
            if (E.impl->endOfCoordinate(static_cast<int>(j)) == to) known[E.coords[j]] = 1;
          done[el] = 1;
          --pending;
          progress = true;
          break;
        }
    }
  }
  if (pending > 0) return;
  for (int i = 0; i < nx(); ++i)
    if (!known[i]) return;
  placements_ = std::move(order);
}

bool GeometricTransferFunctions::placeSequentially() {
  ElemVec xe;
  DefVec e;
  for (const Placement& p : placements_) {
    const auto& E = model_.elements[p.element];
    E.gather(x_, xe);
    e.resize(E.impl->numDeformations());
    for (int i = 0; i < e.size(); ++i) e[i] = target_[rowOfDef_[E.firstDef + i]];
    if (!E.impl->place(e, p.to, xe)) return false;
    for (size_t j = 0; j < E.coords.size(); ++j)
      if (E.impl->endOfCoordinate(static_cast<int>(j)) == p.to) x_[E.coords[j]] = xe[j];
  }
  return true;
}

void GeometricTransferFunctions::setRelativeTolerance(double tol) {
  // Never ask for less than round-off of the coordinates can deliver.
  tolerance_ = std::max(tol, 16 * std::numeric_limits<double>::epsilon()) * lengthScale_;
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
  for (int r = 0; r < numConstraints(); ++r) curvature_[r] = d2[constrainedDefs_[r]];
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
  workE_.setZero();
  inputRates(t, x_, workE_, 0);  // input coordinates straight into x, input deformations into workE_
  for (int r = 0; r < numConstraints(); ++r) target_[r] = workE_[constrainedDefs_[r]];
  for (int j = 0; j < nq(); ++j) {
    if (dofRow_[j] >= 0)
      target_[dofRow_[j]] = q[j];
    else
      x_[dofCoord_[j]] = q[j];
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
      if (hasPeriodic_ && periodic_[k]) {
        // A principal-value angle: take the revolution nearest to the prescribed value (DOF or
        // input) or, for a calculable angle, to the previous one, so e and the residual of Eq. 7
        // stay continuous through pi.
        const double ref = rowOfDef_[k] >= 0 ? target_[rowOfDef_[k]] : e_[k];
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
  for (int p = slotRange_[el]; p < slotRange_[el + 1]; ++p) values_[slotFlat_[p]] = d[slotLocal_[p]];
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
    const int k = constrainedDefs_[r];
    double d = target_[r] - e_[k];
    if (hasPeriodic_ && periodic_[k]) d = std::remainder(d, 2.0 * M_PI);
    rhs_[r] = d;
    res = std::max(res, std::abs(d));
    if (curved) rhs_[r] -= half * curvature_[r];
  }
  bool moved = false;
  if (knownMoved_) {
    for (int i = 0; i < nx(); ++i) {
      work_[i] = colOfCoord_[i] < 0 ? x_[i] - previousX_[i] : 0.0;
      moved |= work_[i] != 0.0;
    }
    if (moved) knownCoupling(work_, rhs_.data());
  }
  // Nothing moved and the last solution still satisfies the equations: keep it as it is (the same
  // state gives the same configuration, bit for bit).
  if (!moved && !curved && res <= tolerance_) return res;
  lu_.solve(rhs_.data(), 1);
  for (int c = 0; c < numCalculable(); ++c) x_[calcCoords_[c]] += rhs_[c];
  return res;
}

void GeometricTransferFunctions::newton(double t, const Eigen::VectorXd& q) {
  // Fixed coordinates keep x0; inputs and DYNX are set by constraintTargets.
  const bool warm = consistent_;
  consistent_ = false;
  if (!warm) hasCurvature_ = false, curvatureScale_ = 0.0;
  if (warm && knownMoved_) previousX_ = x_;
  constraintTargets(t, q);
  const int maxIt = std::max(1, model_.settings.maxIterations);
  int steps = 0;
  double previous = std::numeric_limits<double>::infinity();
  bool chord = warm;
  if (!placements_.empty()) {
    // Open chain: one pass of closed-form placements gives the solution (checked below); where an
    // element has none on its valid branch, Newton continues from the last solution.
    hasCurvature_ = false;
    chord = false;
    if (!placeSequentially())
      for (int c = 0; c < numCalculable(); ++c) x_[calcCoords_[c]] = lastGood_[calcCoords_[c]];
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
      rhs_[r] = target_[r] - e_[constrainedDefs_[r]];
      res = std::max(res, std::abs(rhs_[r]));
    }
    if (!std::isfinite(res)) throw KinematicsError(t, it, res, "non-finite residual");
    const bool converged = res <= tolerance_;
    const bool slow = !chord || res > kChordContraction * previous;
    if (chord && it == 1) predictionMissed_ = !converged;
    if (converged || slow) {
      if (!withJacobian) evaluateJacobians();
      if (!lu_.factorize(values_.data()))
        throw KinematicsError(t, it, res, "singular kinematic Jacobian (dead point or bad constraints)");
    }
    if (converged) {
      lastIterations_ = it;
      consistent_ = true;
      return;
    }
    if (it == maxIt) break;
    if (res > 1e3 * lengthScale_) throw KinematicsError(t, it, res, "Newton iteration diverged");
    previous = res;
    lu_.solve(rhs_.data(), 1);
    for (int c = 0; c < numCalculable(); ++c) x_[calcCoords_[c]] += rhs_[c];
  }
  throw KinematicsError(t, maxIt, res, "Newton iteration did not converge");
}

void GeometricTransferFunctions::knownCoupling(const Eigen::VectorXd& v, double* rhs) const {
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& De = elemJac_[el];
    const int nc = static_cast<int>(E.coords.size());
    for (int i = 0; i < De.rows(); ++i) {
      const int row = rowOfDef_[E.firstDef + i];
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
  rhsMat_.setZero(n, m);
  const int* row = dofRow_.data();
  for (int c = 0; c < m; ++c) {
    if (V) {  // every dof's entry (no test for zeros: the loop is branch-predictable)
      const double* v = V->col(c).data();
      double* r = rhsMat_.col(c).data();
      for (int j = 0; j < nq(); ++j) {
        if (row[j] >= 0)
          r[row[j]] += v[j];
        else
          FqV(dofCoord_[j], c) = v[j];
      }
    } else if (row[c] >= 0) {
      rhsMat_(row[c], c) = 1.0;
    } else {
      FqV(dofCoord_[c], c) = 1.0;
    }
    if (hasDynamicCoords_) {
      work_ = FqV.col(c);
      knownCoupling(work_, rhsMat_.col(c).data());
    }
  }
  lu_.solve(rhsMat_.data(), m);
  for (int c = 0; c < m; ++c)
    for (int k = 0; k < n; ++k) FqV(calcCoords_[k], c) = rhsMat_(k, c);
}

void GeometricTransferFunctions::velocities(double t, const Eigen::VectorXd& qd, Eigen::VectorXd& xd) {
  xd.setZero(nx());
  workE_.setZero();
  inputRates(t, xd, workE_, 1);
  for (int r = 0; r < numConstraints(); ++r) rhs_[r] = workE_[constrainedDefs_[r]];
  for (int j = 0; j < nq(); ++j) {
    if (dofRow_[j] >= 0)
      rhs_[dofRow_[j]] = qd[j];
    else
      xd[dofCoord_[j]] = qd[j];
  }
  for (int c = 0; c < numCalculable(); ++c) xd[calcCoords_[c]] = 0.0;
  if (knownMoved_) knownCoupling(xd, rhs_.data());  // else every known coordinate is at rest
  lu_.solve(rhs_.data(), 1);
  for (int c = 0; c < numCalculable(); ++c) xd[calcCoords_[c]] = rhs_[c];
}

void GeometricTransferFunctions::accelerationOffset(double t, const Eigen::VectorXd& xd, Eigen::VectorXd& g) {
  // Convective part D2[xd, xd] of every deformation, then the solve.
  workE_.setZero();
  ElemVec xe, ve;
  DefVec d2;
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    E.gather(xd, ve);
    if (ve.isZero(0.0)) continue;
    E.gather(x_, xe);
    E.impl->secondDerivative(xe, ve, d2);
    for (int i = 0; i < d2.size(); ++i) workE_[E.firstDef + i] = d2[i];
  }
  convectiveD2_ = workE_;
  accelerationOffsetFrom(t, convectiveD2_, g);
}

void GeometricTransferFunctions::accelerationOffsetFrom(double t, const Eigen::VectorXd& d2, Eigen::VectorXd& g) {
  g.setZero(nx());
  workE_.setZero();
  inputRates(t, g, workE_, 2);
  for (int c = 0; c < numCalculable(); ++c) g[calcCoords_[c]] = 0.0;
  for (int j = 0; j < nq(); ++j)
    if (dofCoord_[j] >= 0) g[dofCoord_[j]] = 0.0;
  // J g_c = edd_input - D_k g_k - D2_C[xd, xd] (Eq. 8b with qdd = 0; F_qq is never formed).
  for (int r = 0; r < numConstraints(); ++r) rhs_[r] = workE_[constrainedDefs_[r]];
  for (int j = 0; j < nq(); ++j)
    if (dofRow_[j] >= 0) rhs_[dofRow_[j]] = 0.0;  // qdd = 0
  if (knownMoved_) knownCoupling(g, rhs_.data());
  for (int r = 0; r < numConstraints(); ++r) rhs_[r] -= d2[constrainedDefs_[r]];
  lu_.solve(rhs_.data(), 1);
  for (int c = 0; c < numCalculable(); ++c) g[calcCoords_[c]] = rhs_[c];
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
  for (int c = 0; c < numCalculable(); ++c) rhs_[c] = r[calcCoords_[c]];
  lu_.solveTransposed(rhs_.data(), 1);
  for (int k = 0; k < numConstraints(); ++k) sigma[constrainedDefs_[k]] += rhs_[k];
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
  rhsMat_.resize(n, m);
  for (int j = 0; j < m; ++j)
    for (int r = 0; r < n; ++r) rhsMat_(r, j) = R(constrainedDefs_[r], j);
  lu_.solve(rhsMat_.data(), m);
  for (int j = 0; j < m; ++j)
    for (int c = 0; c < n; ++c) Z(calcCoords_[c], j) = rhsMat_(c, j);
}

}  // namespace flexmb::core
