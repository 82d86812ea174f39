#include "analysis/ReducedOperators.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "analysis/Simulation.hpp"
#include "core/EquationsOfMotion.hpp"
#include "core/GeometricTransferFunctions.hpp"
#include "core/ReducedCoordinates.hpp"
#include "core/Workspace.hpp"
#include "solvers/NumberText.hpp"

namespace flexmb::analysis {

namespace {

int packedSize(int m) { return m * (m + 1) / 2; }

// The operators' fit tolerance as a share of the pilot's reduction error estimate.
constexpr double kToleranceShare = 0.02;
// A coordinate whose axis scan needs this degree or more counts as large (solvers::ChebyshevBasis groups).
constexpr int kLargeDegree = 5;

// Row-by-row upper triangle: (0,0) (0,1) .. (0,m-1) (1,1) ..
void packSymmetric(const Eigen::MatrixXd& A, Eigen::Ref<Eigen::VectorXd> v) {
  int k = 0;
  for (int a = 0; a < A.rows(); ++a)
    for (int b = a; b < A.cols(); ++b) v[k++] = 0.5 * (A(a, b) + A(b, a));
}

// Everything the operators fit, at one configuration (zero velocity) of the full model.
struct OperatorSample {
  Eigen::VectorXd eta;
  Eigen::VectorXd force;      // -grad U = (F_q V)^T f_const - (E_q V)^T sigma_const
  Eigen::VectorXd mass;       // packed Mr
  Eigen::VectorXd damping;    // packed Cr (empty without damping)
  Eigen::VectorXd loadValue;  // phi_k
  Eigen::MatrixXd loadGrad;   // m x loads
};

// Solves the full kinematics at q = V eta and projects mass, damping and loads (Eq. 19 at rest).
class OperatorSampler {
 public:
  OperatorSampler(const core::Model& model, const Eigen::MatrixXd& V, const std::vector<OperatorLoad>& loads)
      : model_(model), V_(V), loads_(loads), workspace_(model), gtf_(workspace_.kinematics()) {
    gtf_.setRelativeTolerance(1e-12);
    start_ = gtf_.x();
  }

  // False when the kinematics do not converge at eta (a configuration the mechanism cannot take).
  bool sample(const Eigen::VectorXd& eta, OperatorSample& s) {
    const int m = static_cast<int>(V_.cols());
    const Eigen::VectorXd q = V_ * eta;
    try {
      gtf_.solvePositions(model_.settings.t0, q);
    } catch (const core::KinematicsError&) {
      gtf_.setConfiguration(start_);  // the next sample starts afresh
      return false;
    }
    const Eigen::VectorXd& x = gtf_.x();
    const Eigen::VectorXd& e = gtf_.e();
    gtf_.firstOrder(&V_, FqV_);
    gtf_.deformationFirstOrder(FqV_, EqV_);
    core::Inertia& inertia = workspace_.inertia();
    inertia.update(x);
    inertia.projectedMass(FqV_, Mr_);
    Eigen::VectorXd f = model_.f0.size() == model_.nx ? model_.f0 : Eigen::VectorXd::Zero(model_.nx);
    inertia.addGravity(x, f, 1.0);
    Eigen::VectorXd sigma = Eigen::VectorXd::Zero(model_.ne);
    Eigen::MatrixXd Cr = Eigen::MatrixXd::Zero(m, m);
    for (const auto& E : model_.elements) {
      const int nd = E.impl->numDeformations(), k0 = E.firstDef;
      for (int i = 0; i < nd; ++i) {
        if (!active(k0 + i)) continue;
        if (E.hasStiffness)
          for (int j = 0; j < nd; ++j) sigma[k0 + i] += E.S(i, j) * e[k0 + j];
        if (E.hasDamping)
          for (int j = 0; j < nd; ++j)
            if (E.Sd(i, j) != 0.0) Cr.noalias() += E.Sd(i, j) * EqV_.row(k0 + i).transpose() * EqV_.row(k0 + j);
      }
    }
    if (model_.sigma0.size() == model_.ne)
      for (int k = 0; k < model_.ne; ++k)
        if (active(k)) sigma[k] += model_.sigma0[k];
    s.eta = eta;
    s.force = FqV_.transpose() * f - EqV_.transpose() * sigma;
    s.mass.resize(packedSize(m));
    packSymmetric(Mr_, s.mass);
    if (hasDamping()) {
      s.damping.resize(packedSize(m));
      packSymmetric(Cr, s.damping);
    }
    const int nl = static_cast<int>(loads_.size());
    s.loadValue.resize(nl);
    s.loadGrad.resize(m, nl);
    for (int k = 0; k < nl; ++k) {
      const OperatorLoad& l = loads_[k];
      if (l.kind == OperatorLoad::Kind::NodalForce) {
        s.loadValue[k] = x[l.index];
        s.loadGrad.col(k) = FqV_.row(l.index).transpose();
      } else if (l.kind == OperatorLoad::Kind::Stress) {  // sigma_k = a(t): force -a grad e_k
        s.loadValue[k] = -e[l.index];
        s.loadGrad.col(k) = -EqV_.row(l.index).transpose();
      } else {  // EREF: sigma_i -= S_ik eref_k: force eref grad (sum_i S_ik e_i) over active i
        const auto& [el, local] = elementOf(l.index);
        const auto& E = model_.elements[el];
        double v = 0.0;
        Eigen::VectorXd g = Eigen::VectorXd::Zero(m);
        for (int i = 0; i < E.impl->numDeformations(); ++i)
          if (active(E.firstDef + i) && E.hasStiffness) {
            v += E.S(i, local) * e[E.firstDef + i];
            g += E.S(i, local) * EqV_.row(E.firstDef + i).transpose();
          }
        s.loadValue[k] = v;
        s.loadGrad.col(k) = g;
      }
    }
    return true;
  }

  bool hasDamping() const {
    for (const auto& E : model_.elements)
      if (E.hasDamping) return true;
    return false;
  }

 private:
  bool active(int k) const {
    return model_.eRole[k] == core::Role::Dynamic || model_.eRole[k] == core::Role::Calculable;
  }
  std::pair<int, int> elementOf(int eIndex) const {
    for (size_t el = 0; el < model_.elements.size(); ++el) {
      const auto& E = model_.elements[el];
      if (eIndex >= E.firstDef && eIndex < E.firstDef + E.impl->numDeformations())
        return {static_cast<int>(el), eIndex - E.firstDef};
    }
    throw std::logic_error("deformation index without an element");
  }

  const core::Model& model_;
  const Eigen::MatrixXd& V_;
  const std::vector<OperatorLoad>& loads_;
  core::Workspace workspace_;
  core::GeometricTransferFunctions gtf_;
  Eigen::VectorXd start_;
  Eigen::MatrixXd FqV_, EqV_, Mr_;
};

std::vector<OperatorLoad> timeLoads(const core::Model& model) {
  std::vector<OperatorLoad> loads;
  for (const auto& l : model.timeForces) loads.push_back({OperatorLoad::Kind::NodalForce, l.index});
  for (const auto& l : model.timeStresses)
    if (model.eRole[l.index] == core::Role::Dynamic || model.eRole[l.index] == core::Role::Calculable)
      loads.push_back({OperatorLoad::Kind::Stress, l.index});
  for (const auto& l : model.references) loads.push_back({OperatorLoad::Kind::Reference, l.index});
  return loads;
}

// The eta range of a pilot reduced run (Eq. 19), widened by margin of its width on each side, and
// the pilot's reduction error estimate (NaN when it has none).
double pilotRange(const core::Model& model, const Eigen::MatrixXd& V, const OperatorTrainingOptions& o,
                  Eigen::VectorXd& lo, Eigen::VectorXd& hi) {
  SimulationOptions so;
  so.basis = V;
  so.relTol = o.pilotRelTol;
  so.intervals = 0;  // every step's state (Refine output)
  const core::Trajectory run = simulate(model, so);
  if (!run.completed) throw std::runtime_error("the pilot run for the operators' range stopped: " + run.stopReason);
  const core::ReducedCoordinates coords(model.numDofs(), V);
  const int m = static_cast<int>(V.cols());
  Eigen::VectorXd q(model.numDofs());
  for (size_t k = 0; k < run.states.size(); ++k) {
    const core::StateOutputs& s = run.states[k];
    for (int j = 0; j < model.numDofs(); ++j) {
      const auto& d = model.dofs[j];
      q[j] = d.isDeformation ? s.e[d.index] : s.x[d.index];
    }
    const Eigen::VectorXd eta = coords.fromFull(q);
    if (k == 0) lo = hi = eta;
    lo = lo.cwiseMin(eta);
    hi = hi.cwiseMax(eta);
  }
  const Eigen::VectorXd width = hi - lo;
  const double widest = width.maxCoeff();
  for (int i = 0; i < m; ++i) {
    const double w = o.margin * width[i] + 1e-3 * widest + 1e-12;
    lo[i] -= w;
    hi[i] += w;
  }
  return run.reduction.estimated ? run.reduction.estimate : std::numeric_limits<double>::quiet_NaN();
}

// The data groups the operators fit, each measured against its own largest value: the force
// (grad U, so U needs one degree more), the mass, the damping and the load fields' gradients.
enum Group { kForce, kMass, kDamping, kLoads, kGroups };

// Degree of variable i: the Chebyshev coefficients of each group along the axis through the box's
// centre fall below tolerance x that group's largest from this degree on.
std::vector<int> axisDegrees(OperatorSampler& sampler, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                             const OperatorTrainingOptions& o) {
  const int m = static_cast<int>(lo.size()), n = 2 * o.maxDegree + 1;
  const Eigen::VectorXd centre = 0.5 * (lo + hi);
  std::vector<int> degrees(m, 2);
  for (int i = 0; i < m; ++i) {
    Eigen::VectorXd a = Eigen::VectorXd::Constant(1, lo[i]), b = Eigen::VectorXd::Constant(1, hi[i]);
    const solvers::ChebyshevBasis line(a, b, std::vector<int>{o.maxDegree});
    Eigen::MatrixXd points(n, 1), data;
    std::vector<Eigen::VectorXd> rows;
    std::vector<int> group;
    int k = 0;
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd eta = centre;
      eta[i] = 0.5 * (lo[i] + hi[i]) - 0.5 * (hi[i] - lo[i]) * std::cos(M_PI * (j + 0.5) / n);
      OperatorSample s;
      if (!sampler.sample(eta, s)) continue;
      points(k++, 0) = eta[i];
      Eigen::VectorXd r(s.force.size() + s.mass.size() + s.damping.size() + s.loadGrad.size());
      r << s.force, s.mass, s.damping, Eigen::Map<const Eigen::VectorXd>(s.loadGrad.data(), s.loadGrad.size());
      rows.push_back(r);
      if (group.empty()) {
        group.insert(group.end(), s.force.size(), kForce);
        group.insert(group.end(), s.mass.size(), kMass);
        group.insert(group.end(), s.damping.size(), kDamping);
        group.insert(group.end(), s.loadGrad.size(), kLoads);
      }
    }
    if (k < o.maxDegree + 2) throw std::runtime_error("too few configurations solve along the range's axes");
    points.conservativeResize(k, 1);
    data.resize(k, rows.front().size());
    for (int j = 0; j < k; ++j) data.row(j) = rows[j].transpose();
    const Eigen::MatrixXd c = solvers::fitChebyshev(line, points, data, 1.0, Eigen::MatrixXd(), 0.0);
    double scale[kGroups] = {0, 0, 0, 0};
    for (int col = 0; col < c.cols(); ++col) scale[group[col]] = std::max(scale[group[col]], c.col(col).cwiseAbs().maxCoeff());
    int need = 1;
    if (std::getenv("FLEXMB_DEBUG_OPS"))
      for (int d = 0; d <= o.maxDegree; ++d) {
        double mx[kGroups] = {0, 0, 0, 0};
        for (int col = 0; col < c.cols(); ++col) mx[group[col]] = std::max(mx[group[col]], std::abs(c(d, col)));
        std::fprintf(stderr, "axis %d degree %d: force %.2e mass %.2e loads %.2e\n", i, d, mx[kForce] / scale[kForce],
                     mx[kMass] / scale[kMass], mx[kLoads] / std::max(1e-300, scale[kLoads]));
      }
    for (int d = 0; d <= o.maxDegree; ++d)
      for (int col = 0; col < c.cols(); ++col) {
        const int g = group[col];
        // Force and load gradients are gradients of U and phi: those need one degree more.
        if (scale[g] > 0.0 && std::abs(c(d, col)) > o.tolerance * scale[g])
          need = std::max(need, g == kForce || g == kLoads ? d + 1 : d);
      }
    degrees[i] = std::min(o.maxDegree, std::max(need, 2));
  }
  return degrees;
}

// The fits of one set of samples: each field on the fewest leading terms (by weighted degree) that
// meet the tolerance on the held-out samples, else on all of them.
struct FieldFit {
  Eigen::MatrixXd coef;  // terms x columns
  double error = 0.0;
};

}  // namespace

namespace {

// Held-out error of a field: gradients (force, loads) or values (mass, damping), each sample's
// error norm over the largest norm of the data.
double heldOutError(const solvers::ChebyshevBasis& basis, const std::vector<OperatorSample>& pool, int first,
                    const Eigen::MatrixXd& coef, Group g, double scale) {
  const int m = basis.variables(), P = static_cast<int>(coef.rows());
  solvers::ChebyshevBasis::Scratch scratch;
  Eigen::VectorXd phi(basis.size());
  Eigen::MatrixXd grad(m, basis.size());
  double worst = 0.0;
  for (size_t s = first; s < pool.size(); ++s) {
    const OperatorSample& d = pool[s];
    basis.evaluate(d.eta, scratch, phi, &grad, P);
    double e = 0.0;
    if (g == kForce)
      e = (-grad.leftCols(P) * coef.col(0) - d.force).norm();
    else if (g == kLoads)
      for (int k = 0; k < coef.cols(); ++k) e = std::max(e, (grad.leftCols(P) * coef.col(k) - d.loadGrad.col(k)).norm());
    else
      e = (coef.transpose() * phi.head(P) - (g == kMass ? d.mass : d.damping)).norm();
    worst = std::max(worst, e);
  }
  return scale > 0.0 ? worst / scale : worst;
}

FieldFit fitField(const solvers::ChebyshevBasis& basis, const std::vector<OperatorSample>& pool, int n, Group g,
                  double tolerance) {
  const int m = basis.variables();
  double scale = 0.0;
  for (const OperatorSample& d : pool) {
    if (g == kForce) scale = std::max(scale, d.force.norm());
    if (g == kMass) scale = std::max(scale, d.mass.norm());
    if (g == kDamping) scale = std::max(scale, d.damping.norm());
    if (g == kLoads)
      for (int k = 0; k < d.loadGrad.cols(); ++k) scale = std::max(scale, d.loadGrad.col(k).norm());
  }
  const bool gradients = g == kForce || g == kLoads;
  const int cols = g == kForce ? 1 : g == kLoads ? static_cast<int>(pool.front().loadGrad.cols())
                                 : g == kMass    ? static_cast<int>(pool.front().mass.size())
                                                 : static_cast<int>(pool.front().damping.size());
  Eigen::MatrixXd pts(n, m), vals(n, cols), grads(gradients ? n * m : 0, cols);
  for (int s = 0; s < n; ++s) {
    const OperatorSample& d = pool[s];
    pts.row(s) = d.eta.transpose();
    if (g == kForce) grads.block(s * m, 0, m, 1) = -d.force;
    if (g == kLoads) {
      vals.row(s) = d.loadValue.transpose();
      grads.block(s * m, 0, m, cols) = d.loadGrad;
    }
    if (g == kMass) vals.row(s) = d.mass.transpose();
    if (g == kDamping) vals.row(s) = d.damping.transpose();
  }
  FieldFit best;
  best.error = std::numeric_limits<double>::infinity();
  int lastCount = 0;
  for (double level : {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0}) {
    const int count = level < 1.0 ? basis.termsUpTo(level) : basis.size();
    if (count <= lastCount || count < 2) continue;
    lastCount = count;
    const Eigen::MatrixXd coef =
        g == kForce ? solvers::fitChebyshev(basis, pts, Eigen::MatrixXd(), 0.0, grads, 1.0, count)
        : g == kLoads ? solvers::fitChebyshev(basis, pts, vals, 1.0, grads, 1.0, count)
                      : solvers::fitChebyshev(basis, pts, vals, 1.0, Eigen::MatrixXd(), 0.0, count);
    const double e = heldOutError(basis, pool, n, coef, g, scale);
    if (e < best.error) best = {coef, e};
    if (e <= tolerance) break;
  }
  return best;
}

}  // namespace

const char* operatorLoadKeyword(OperatorLoad::Kind kind) {
  switch (kind) {
    case OperatorLoad::Kind::Stress:
      return "ESIGT";
    case OperatorLoad::Kind::Reference:
      return "EREF";
    case OperatorLoad::Kind::NodalForce:
      break;
  }
  return "XFT";
}

double basisChecksum(const Eigen::MatrixXd& V) {
  double s = 0.0;
  for (int j = 0; j < V.cols(); ++j)
    for (int i = 0; i < V.rows(); ++i) s += V(i, j) * (1.0 + 0.37 * i + 0.61 * j * j);
  return s;
}

std::string operatorsUnsupported(const core::Model& model) {
  if (!model.inputX.empty() || !model.inputE.empty())
    return "the model has kinematic inputs (INPUTX/INPUTE): its kinematics depend on time";
  if (model.userFunctions) return "the model has user functions (USERSIG/USERINP)";
  if (!model.moments.empty()) return "the model has moments on spatial orientation nodes (not a potential)";
  return "";
}

ReducedOperators trainOperators(const core::Model& model, const Eigen::MatrixXd& V,
                                const OperatorTrainingOptions& o) {
  const std::string why = operatorsUnsupported(model);
  if (!why.empty()) throw std::invalid_argument("no reduced operators: " + why);
  const auto started = std::chrono::steady_clock::now();
  const int m = static_cast<int>(V.cols());
  ReducedOperators ops;
  ops.dofs = static_cast<int>(V.rows());
  ops.basisChecksum = basisChecksum(V);
  ops.loads = timeLoads(model);
  Eigen::VectorXd lo = o.lower, hi = o.upper;
  OperatorTrainingOptions opt = o;
  if (lo.size() == 0) {
    const double estimate = pilotRange(model, V, o, lo, hi);
    std::ostringstream r;
    r << "pilot run of Eq. 19 (ode45, RelTol " << solvers::shortest(o.pilotRelTol) << ") to t = "
      << solvers::shortest(model.settings.tEnd) << " s, widened " << solvers::shortest(100 * o.margin)
      << "% each side";
    // Fit to a small share of the reduction error the basis has anyway (issue 33: the operators may add
    // at most 10% of it; the estimate is 1.4-3x the true error).
    if (std::isnan(opt.tolerance)) {
      opt.tolerance = std::isfinite(estimate) ? std::clamp(kToleranceShare * estimate, 1e-7, 1e-3) : 1e-6;
      r << "; fit tolerance " << solvers::shortest(opt.tolerance)
        << (std::isfinite(estimate) ? " (" + solvers::shortest(kToleranceShare) + " of its reduction error estimate " +
                                          solvers::shortest(estimate) + ")"
                                    : "");
    }
    ops.range = r.str();
  } else {
    if (lo.size() != m || hi.size() != m) throw std::invalid_argument("operator range: one bound per basis column");
    ops.range = "given";
    if (std::isnan(opt.tolerance)) opt.tolerance = 1e-6;
  }
  ops.tolerance = opt.tolerance;
  OperatorSampler sampler(model, V, ops.loads);
  std::vector<int> degrees = axisDegrees(sampler, lo, hi, opt);

  // Samples from the arcsine density (Halton), chained nearest-first so that Newton starts close.
  std::vector<OperatorSample> pool;
  long next = 1;
  auto grow = [&](int count) {
    std::vector<Eigen::VectorXd> pts;
    const solvers::ChebyshevBasis box(lo, hi, std::vector<int>(m, 1));
    for (int i = 0; i < count; ++i) pts.push_back(box.arcsinePoint(solvers::haltonPoint(next++, m)));
    Eigen::VectorXd at = pool.empty() ? Eigen::VectorXd(0.5 * (lo + hi)) : pool.back().eta;
    const Eigen::VectorXd w = (hi - lo).cwiseInverse();
    while (!pts.empty()) {
      size_t best = 0;
      double d = std::numeric_limits<double>::infinity();
      for (size_t j = 0; j < pts.size(); ++j) {
        const double dj = (pts[j] - at).cwiseProduct(w).squaredNorm();
        if (dj < d) d = dj, best = j;
      }
      at = pts[best];
      pts.erase(pts.begin() + static_cast<long>(best));
      OperatorSample s;
      if (sampler.sample(at, s)) pool.push_back(std::move(s));
    }
  };
  const bool damped = sampler.hasDamping();
  const int nl = static_cast<int>(ops.loads.size());
  double bestError = std::numeric_limits<double>::infinity();
  // Large coordinates (those the axis scan finds strongly nonlinear) enter every product with the
  // small ones at their full degree; where that set is larger than maxTerms, one weighted set.
  std::vector<int> groups(m, 1);
  for (int i = 0; i < m; ++i)
    if (degrees[i] >= kLargeDegree) groups[i] = 0;
  if (solvers::ChebyshevBasis(lo, hi, degrees, o.slack, groups).size() > o.maxTerms) groups.clear();
  for (int round = 0; round < 4; ++round) {
    // Rounds widen the products of variables (slack).
    const solvers::ChebyshevBasis basis(lo, hi, degrees, o.slack + round, groups);
    if (basis.size() > o.maxTerms && round > 0) break;
    const int P = basis.size();
    const int want = 3 * P + 40, validation = std::max(60, P / 2);
    if (static_cast<int>(pool.size()) < want + validation) grow(want + validation - static_cast<int>(pool.size()));
    if (static_cast<int>(pool.size()) < (want + validation) / 2)
      throw std::runtime_error("fewer than half of the configurations in the operators' range solve");
    const int n = static_cast<int>(pool.size()) - validation;
    ReducedOperators trial = ops;
    trial.basis = basis;
    const FieldFit force = fitField(basis, pool, n, kForce, opt.tolerance);
    const FieldFit mass = fitField(basis, pool, n, kMass, opt.tolerance);
    trial.potential = force.coef.col(0);
    trial.mass = mass.coef.transpose();
    trial.forceError = force.error;
    trial.massError = mass.error;
    if (damped) {
      const FieldFit d = fitField(basis, pool, n, kDamping, opt.tolerance);
      trial.damping = d.coef.transpose();
      trial.massError = std::max(trial.massError, d.error);
    }
    if (nl) {
      const FieldFit l = fitField(basis, pool, n, kLoads, opt.tolerance);
      trial.loadFields = l.coef;
      trial.forceError = std::max(trial.forceError, l.error);
    } else {
      trial.loadFields.resize(0, 0);
    }
    trial.trainingSamples = n;
    trial.validationSamples = validation;
    const double error = std::max(trial.forceError, trial.massError);
    if (std::getenv("FLEXMB_DEBUG_OPS"))
      std::fprintf(stderr, "round %d: %d terms, force %.2e mass %.2e (target %.2e)\n", round, P, trial.forceError,
                   trial.massError, opt.tolerance);
    if (error < bestError) {
      ops = std::move(trial);
      bestError = error;
    }
    if (error <= opt.tolerance) break;
  }
  ops.trainingSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return ops;
}

OperatorDynamics::OperatorDynamics(const core::Model& model, const ReducedOperators& ops)
    : ops_(ops),
      m_(ops.size()),
      nPacked_(packedSize(ops.size())),
      nU_(static_cast<int>(ops.potential.size())),
      nM_(static_cast<int>(ops.mass.cols())),
      nC_(static_cast<int>(ops.damping.cols())),
      nL_(static_cast<int>(ops.loadFields.rows())),
      llt_(ops.size()) {
  for (const OperatorLoad& l : ops.loads) {
    const std::vector<core::TimeLoad>* list = l.kind == OperatorLoad::Kind::NodalForce ? &model.timeForces
                                              : l.kind == OperatorLoad::Kind::Stress   ? &model.timeStresses
                                                                                       : &model.references;
    const auto it = std::find_if(list->begin(), list->end(), [&](const core::TimeLoad& t) { return t.index == l.index; });
    if (it == list->end())
      throw std::invalid_argument(std::string("the operators have a ") + operatorLoadKeyword(l.kind) +
                                  " load the model does not have");
    loadFunctions_.push_back(it->f);
  }
  const int P = ops.terms();
  phi_.setZero(P);
  coef_.setZero(P);
  grad_.setZero(m_, P);
  weights_.resize(nPacked_);
  Mpacked_.resize(nPacked_);
  packed_.resize(nPacked_);
  force_.resize(m_);
  etadd_.resize(m_);
  a_.resize(static_cast<int>(ops.loads.size()));
  M_.resize(m_, m_);
  Md_.resize(m_, m_);
  PD_.resize(nM_, 2);
  MD_.resize(nPacked_, 2);
  C_.resize(m_, m_);
  lastEta_.resize(m_);
}

void OperatorDynamics::evaluate(const Eigen::Ref<const Eigen::VectorXd>& eta, bool gradient) {
  ops_.basis.evaluate(eta, scratch_, phi_, gradient ? &grad_ : nullptr, static_cast<int>(phi_.size()));
}

void OperatorDynamics::unpack(const Eigen::Ref<const Eigen::VectorXd>& packed, Eigen::MatrixXd& S) const {
  int k = 0;
  for (int a = 0; a < m_; ++a)
    for (int b = a; b < m_; ++b) S(a, b) = S(b, a) = packed[k++];
}

bool OperatorDynamics::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  const auto eta = y.head(m_);
  const auto etad = y.tail(m_);
  lastOutside_ = ops_.basis.outside(eta);
  if (lastOutside_ >= 0) {
    lastEta_ = eta;
    return false;
  }
  evaluate(eta, true);
  // Mr and dMr/dt from one product: [phi, d phi/dt] of the mass terms.
  PD_.col(0) = phi_.head(nM_);
  PD_.col(1).noalias() = grad_.leftCols(nM_).transpose() * etad;
  MD_.noalias() = ops_.mass * PD_;
  unpack(MD_.col(0), M_);
  unpack(MD_.col(1), Md_);
  // Generalised force: -grad U + sum_k a_k(t) grad phi_k + 1/2 grad(etad^T Mr etad) in one product
  // with the gradient table; then the rest of the velocity terms, - dMr/dt etad.
  int k = 0;
  for (int a = 0; a < m_; ++a)
    for (int b = a; b < m_; ++b) weights_[k++] = (a == b ? 0.5 : 1.0) * etad[a] * etad[b];
  coef_.head(nM_).noalias() = ops_.mass.transpose() * weights_;
  coef_.tail(coef_.size() - nM_).setZero();
  coef_.head(nU_) -= ops_.potential;
  for (int l = 0; l < a_.size(); ++l) coef_.head(nL_).noalias() += loadFunctions_[l]->value(t) * ops_.loadFields.col(l);
  force_.noalias() = grad_ * coef_;
  force_.noalias() -= Md_ * etad;
  if (nC_) {
    packed_.noalias() = ops_.damping * phi_.head(nC_);
    unpack(packed_, C_);
    force_.noalias() -= C_ * etad;
  }
  llt_.compute(M_);
  if (llt_.info() != Eigen::Success) {
    lastEta_ = eta;
    lastOutside_ = m_;  // not positive definite: treated as outside the range
    return false;
  }
  etadd_ = force_;
  llt_.solveInPlace(etadd_);
  dydt.resize(2 * m_);
  dydt.head(m_) = etad;
  dydt.tail(m_) = etadd_;
  return true;
}

std::string OperatorDynamics::whereOutside() const {
  std::ostringstream s;
  if (lastOutside_ < 0) return "";
  if (lastOutside_ >= m_) {
    s << "the fitted mass matrix is not positive definite there";
    return s.str();
  }
  const int i = lastOutside_;
  s << "eta_" << i + 1 << " = " << solvers::shortest(lastEta_[i]) << " outside the trained ["
    << solvers::shortest(ops_.basis.lower()[i]) << ", " << solvers::shortest(ops_.basis.upper()[i]) << "]";
  return s.str();
}

void OperatorDynamics::massMatrix(const Eigen::VectorXd& eta, Eigen::MatrixXd& M) {
  evaluate(eta, false);
  Mpacked_.noalias() = ops_.mass * phi_.head(nM_);
  M.resize(m_, m_);
  unpack(Mpacked_, M);
}

double OperatorDynamics::potential(const Eigen::VectorXd& eta) {
  evaluate(eta, false);
  return ops_.potential.dot(phi_.head(nU_));
}

double OperatorDynamics::energy(const Eigen::VectorXd& y) {
  massMatrix(y.head(m_), M_);
  return 0.5 * y.tail(m_).dot(M_ * y.tail(m_)) + ops_.potential.dot(phi_.head(nU_));
}

}  // namespace flexmb::analysis
