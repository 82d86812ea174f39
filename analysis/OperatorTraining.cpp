#include "analysis/OperatorTraining.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SVD>
#include "analysis/OperatorDynamics.hpp"
#include "analysis/OperatorLoads.hpp"
#include "analysis/OperatorPolicy.hpp"
#include "analysis/Simulation.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/ReducedCoordinates.hpp"
#include "core/dynamics/Workspace.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "solvers/ChebyshevBasis.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {

int packedSize(int m) { return m * (m + 1) / 2; }

// The shares (OperatorTraining.hpp). The inertia share, measured (flexmb_bench, straight guidance
// SVDm-5): the error a run adds follows the mass fit (held-out 2.4e-5: +17 % of the reduction
// error; 9e-6: none), and a rough fit costs ode45 steps; a loose force fit does not. 0.3 instead
// of 0.4 left every bench error as it is but the 80-element guidance's mass fit stalled 1.3x
// above its target from 33 to 78 terms (0.78 us an evaluation against 0.53 us).
constexpr double kToleranceShare = kOperatorToleranceShare;
constexpr double kInertiaShare = kOperatorInertiaShare;
// The most a fit may miss its tolerance by and still be used (OperatorPolicy: a tenth of the
// reduction error against the tolerance's share of it).
constexpr double kMostOverTolerance = kOperatorMostShare / kOperatorToleranceShare;
// A set that grows by this factor without halving its worst held-out error stops there, once within
// kMostOverTolerance. Measured on the straight guidance, SVD-modal 5: the force fit stalls at
// 4-9e-5 from 160 to 300 terms (tolerance 3e-5).
constexpr double kStallGrowth = 1.3;
// Held-out configurations that judge the fits.
constexpr int kHeldOut = 80;

// Row-by-row upper triangle: (0,0) (0,1) .. (0,m-1) (1,1) ..
void packSymmetric(const Eigen::MatrixXd& A, Eigen::Ref<Eigen::VectorXd> v) {
  int k = 0;
  for (int a = 0; a < A.rows(); ++a)
    for (int b = a; b < A.cols(); ++b) v[k++] = 0.5 * (A(a, b) + A(b, a));
}

// Everything the operators fit, at one configuration (zero velocity) of the full model.
struct OperatorSample {
  Eigen::VectorXd eta;
  Eigen::VectorXd force;        // -grad U = (F_q V)^T f_const - (E_q V)^T sigma_const
  Eigen::VectorXd mass;         // packed Mr
  Eigen::VectorXd damping;      // packed Cr (empty without damping)
  Eigen::VectorXd loadValue;    // phi_k
  Eigen::MatrixXd loadGrad;     // m x loads
  Eigen::VectorXd outputValue;  // the tracked x_i / e_k
  Eigen::MatrixXd outputGrad;   // m x outputs: rows of F_q V / E_q V
};

// Solves the full kinematics at q = q0 + W zeta and projects mass, damping and loads on W (Eq. 19
// at rest): with W = V R, the quantities of the operators' own coordinates zeta.
class OperatorSampler {
 public:
  OperatorSampler(const core::Model& model, const Eigen::MatrixXd& W, const Eigen::VectorXd& q0,
                  const std::vector<OperatorLoad>& loads, const std::vector<core::OperatorOutput>& outputs)
      : model_(model),
        V_(W),
        q0_(q0),
        loads_(loads),
        outputs_(outputs),
        workspace_(model),
        gtf_(workspace_.kinematics()) {
    gtf_.setRelativeTolerance(1e-12);
    start_ = gtf_.x();
  }

  // False when the kinematics do not converge at eta (a configuration the mechanism cannot take).
  bool sample(const Eigen::VectorXd& eta, OperatorSample& s) {
    const int m = static_cast<int>(V_.cols());
    const Eigen::VectorXd q = q0_ + V_ * eta;
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
    const int no = static_cast<int>(outputs_.size());
    s.outputValue.resize(no);
    s.outputGrad.resize(m, no);
    for (int k = 0; k < no; ++k) {
      const bool def = outputs_[k].kind == core::OperatorOutput::Kind::Deformation;
      const int i = outputs_[k].index;
      s.outputValue[k] = def ? e[i] : x[i];
      s.outputGrad.col(k) = def ? EqV_.row(i).transpose() : FqV_.row(i).transpose();
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
  const Eigen::MatrixXd V_;
  const Eigen::VectorXd q0_;
  const std::vector<OperatorLoad>& loads_;
  const std::vector<core::OperatorOutput>& outputs_;
  core::Workspace workspace_;
  core::GeometricTransferFunctions gtf_;
  Eigen::VectorXd start_;
  Eigen::MatrixXd FqV_, EqV_, Mr_;
};

// The range of a pilot reduced run (Eq. 19): the frame zeta = R^T (eta - c) of its states'
// principal directions (c their mean), and the box of zeta it covers widened by margin of its width
// on each side. Returns the pilot's reduction error estimate (NaN when it has none).
double pilotRange(const core::Model& model, const Eigen::MatrixXd& V, const OperatorTrainingOptions& o,
                  Eigen::VectorXd& centre, Eigen::MatrixXd& R, Eigen::VectorXd& lo, Eigen::VectorXd& hi) {
  SimulationOptions so;
  so.basis = V;
  if (!std::isnan(o.pilotRelTol)) so.relTol = o.pilotRelTol;
  so.intervals = 0;  // every step's state (Refine output)
  const core::Trajectory run = simulate(model, so);
  if (!run.completed) throw std::runtime_error("the pilot run for the operators' range stopped: " + run.stopReason);
  const core::ReducedCoordinates coords(model.numDofs(), V);
  const int m = static_cast<int>(V.cols());
  Eigen::VectorXd q(model.numDofs());
  Eigen::MatrixXd etas(static_cast<int>(run.states.size()), m);
  for (size_t k = 0; k < run.states.size(); ++k) {
    const core::StateOutputs& s = run.states[k];
    for (int j = 0; j < model.numDofs(); ++j) {
      const auto& d = model.dofs[j];
      q[j] = d.isDeformation ? s.e[d.index] : s.x[d.index];
    }
    etas.row(static_cast<int>(k)) = coords.fromFull(q).transpose();
  }
  centre = etas.colwise().mean().transpose();
  const Eigen::MatrixXd centred = etas.rowwise() - centre.transpose();
  R = Eigen::JacobiSVD<Eigen::MatrixXd>(centred, Eigen::ComputeFullV).matrixV();
  const Eigen::MatrixXd zetas = centred * R;
  lo = zetas.colwise().minCoeff().transpose();
  hi = zetas.colwise().maxCoeff().transpose();
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
// (grad U), the mass, the damping and the load fields' gradients; and the tracked outputs, each
// against its own range (outputScale; fitted as outputs / outputScale).
enum Group { kForce, kMass, kDamping, kLoads, kOutputs, kGroups };

// Samples at which the fields are fitted, and held-out ones at which the fits are judged.
struct Samples {
  std::vector<OperatorSample> train, check;
  double scale[kGroups] = {0, 0, 0, 0, 1};  // each group's largest norm over both
  Eigen::VectorXd outputScale;              // each output's range over both (floored, see rescale)
  void rescale() {
    rescaleOutputs();
    for (const auto* list : {&train, &check})
      for (const OperatorSample& d : *list) {
        scale[kForce] = std::max(scale[kForce], d.force.norm());
        scale[kMass] = std::max(scale[kMass], d.mass.norm());
        scale[kDamping] = std::max(scale[kDamping], d.damping.norm());
        for (int k = 0; k < d.loadGrad.cols(); ++k) scale[kLoads] = std::max(scale[kLoads], d.loadGrad.col(k).norm());
      }
  }
  // An output's range, at least 1e-3 of the widest range of its kind (a coordinate that hardly
  // moves is fitted to the motion of the others, not to its own rounding).
  void rescaleOutputs() {
    const int no = static_cast<int>(check.front().outputValue.size());
    Eigen::VectorXd lo = Eigen::VectorXd::Constant(no, INFINITY), hi = Eigen::VectorXd::Constant(no, -INFINITY);
    for (const auto* list : {&train, &check})
      for (const OperatorSample& d : *list) {
        lo = lo.cwiseMin(d.outputValue);
        hi = hi.cwiseMax(d.outputValue);
      }
    outputScale = no ? Eigen::VectorXd(hi - lo) : Eigen::VectorXd();
    const double widest = no ? outputScale.maxCoeff() : 0.0;
    for (int k = 0; k < no; ++k) outputScale[k] = std::max({outputScale[k], 1e-3 * widest, 1e-300});
  }
};

solvers::ChebyshevBasis toChebyshevBasis(const std::vector<std::vector<int>>& list, const Eigen::VectorXd& lo,
                                         const Eigen::VectorXd& hi) {
  const int m = static_cast<int>(lo.size());
  Eigen::MatrixXi e(static_cast<int>(list.size()), m);
  for (size_t p = 0; p < list.size(); ++p)
    for (int i = 0; i < m; ++i) e(static_cast<int>(p), i) = list[p][i];
  return solvers::ChebyshevBasis(lo, hi, e);
}

// The least-squares systems of every group in normal form over every term seen so far (issue 49:
// training cheaper than a run): the Gram matrices of the value rows (one per sample) and of the
// gradient rows (m per sample) and each group's A^T b, updated as samples and terms are added. A
// step of the adaptive search then costs a Cholesky factorisation of its set and the margin's
// scores come from the same products, instead of a QR of all rows per group and step (the search
// took 2 s of a 2.3 s training on the guidance, SVD-modal 5). Columns are scaled to unit diagonal
// before the factorisation; Chebyshev terms at arcsine samples keep the squared condition small.
class NormalEquations {
 public:
  NormalEquations(const Samples& s, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, std::vector<Group> groups)
      : s_(s), lo_(lo), hi_(hi), m_(static_cast<int>(lo.size())), groups_(std::move(groups)) {
    for (Group g : groups_) {
      bv_[g].resize(0, width(g));
      bg_[g].resize(0, width(g));
      Bv_[g].resize(0, width(g));
      Bg_[g].resize(0, width(g));
    }
  }

  // The columns of `terms`, those not seen yet added with their products over every sample so far;
  // then the samples not in yet added over every column.
  std::vector<int> columns(const std::vector<std::vector<int>>& terms) {
    std::vector<std::vector<int>> fresh;
    std::vector<int> ids;
    for (const auto& k : terms) {
      auto [it, added] = id_.try_emplace(k, static_cast<int>(exps_.size() + fresh.size()));
      if (added) fresh.push_back(k);
      ids.push_back(it->second);
    }
    if (!fresh.empty()) addColumns(fresh);
    addSamples();
    return ids;
  }

  // Group g's coefficients on the columns `ids` (in their order; the constant left out of a
  // gradient-only fit), and the score of each column of `others`: how much of the normalised
  // residual it alone would remove, (a^T r)^2 / (a^T a scale^2), summed over b's columns.
  Eigen::MatrixXd solve(Group g, const std::vector<int>& ids) const {
    Eigen::VectorXd none(0);
    return solve(g, ids, {}, none);
  }
  Eigen::MatrixXd solve(Group g, const std::vector<int>& ids, const std::vector<int>& others,
                        Eigen::Ref<Eigen::VectorXd> score) const {
    const int skip = g == kForce ? 1 : 0, L = static_cast<int>(ids.size()), k = L - skip;
    const std::vector<int> fit(ids.begin() + skip, ids.end());
    const Eigen::MatrixXd G = gram(g, fit, fit), B = rhs(g, fit);
    const Eigen::VectorXd d = G.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::LLT<Eigen::MatrixXd> llt(d.asDiagonal() * G * d.asDiagonal());
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(L, B.cols());
    if (llt.info() == Eigen::Success)
      c.bottomRows(k) = d.asDiagonal() * llt.solve(d.asDiagonal() * B);
    else  // numerically dependent columns: the smallest-norm solution of the normal equations
      c.bottomRows(k) = G.completeOrthogonalDecomposition().solve(B);
    const double scale = s_.scale[g] > 0.0 ? s_.scale[g] : 1.0;
    const Eigen::MatrixXd crossed = gram(g, others, fit), Bo = rhs(g, others);
    for (int j = 0; j < static_cast<int>(others.size()); ++j) {
      const double aa = diagonal(g, others[j]);
      if (aa > 0.0) score[j] += (Bo.row(j) - crossed.row(j) * c.bottomRows(k)).squaredNorm() / (aa * scale * scale);
    }
    return c;
  }

 private:
  bool values(Group g) const { return g != kForce; }
  bool gradients(Group g) const { return g == kForce || g == kLoads || g == kOutputs; }
  int width(Group g) const {
    const OperatorSample& d = s_.check.front();
    return g == kForce     ? 1
           : g == kLoads   ? static_cast<int>(d.loadGrad.cols())
           : g == kOutputs ? static_cast<int>(d.outputGrad.cols())
           : g == kMass    ? static_cast<int>(d.mass.size())
                           : static_cast<int>(d.damping.size());
  }
  bool anyValues() const {
    return std::any_of(groups_.begin(), groups_.end(), [&](Group g) { return values(g); });
  }
  bool anyGradients() const {
    return std::any_of(groups_.begin(), groups_.end(), [&](Group g) { return gradients(g); });
  }
  Eigen::MatrixXd gram(Group g, const std::vector<int>& rows, const std::vector<int>& cols) const {
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(static_cast<int>(rows.size()), static_cast<int>(cols.size()));
    if (values(g)) G += Gv_(rows, cols);
    if (gradients(g)) G += Gg_(rows, cols);
    return G;
  }
  double diagonal(Group g, int j) const { return (values(g) ? Gv_(j, j) : 0.0) + (gradients(g) ? Gg_(j, j) : 0.0); }
  // A^T b on the columns `ids`, the outputs divided by their current scale.
  Eigen::MatrixXd rhs(Group g, const std::vector<int>& ids) const {
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(static_cast<int>(ids.size()), width(g));
    if (values(g)) B += Bv_.at(g)(ids, Eigen::all);
    if (gradients(g)) B += Bg_.at(g)(ids, Eigen::all);
    if (g == kOutputs) B *= s_.outputScale.cwiseInverse().asDiagonal();
    return B;
  }
  // The right-hand sides of one sample: its value row and its m gradient rows (outputs unscaled).
  void sampleRhs(const OperatorSample& d, Group g, Eigen::Ref<Eigen::RowVectorXd> v,
                 Eigen::Ref<Eigen::MatrixXd> gr) const {
    if (g == kMass) v = d.mass.transpose();
    if (g == kDamping) v = d.damping.transpose();
    if (g == kLoads) v = d.loadValue.transpose(), gr = d.loadGrad;
    if (g == kOutputs) v = d.outputValue.transpose(), gr = d.outputGrad;
    if (g == kForce) gr = -d.force;
  }
  // The value and gradient rows of `count` samples from `first` on the columns of `basis`.
  void rowsOf(const solvers::ChebyshevBasis& basis, int first, int count, Eigen::MatrixXd& Av,
              Eigen::MatrixXd& Ag) const {
    const int P = basis.size();
    Av.resize(anyValues() ? count : 0, P);
    Ag.resize(anyGradients() ? count * m_ : 0, P);
    solvers::ChebyshevBasis::Scratch scratch;
    Eigen::VectorXd phi(P);
    Eigen::MatrixXd grad(m_, P);
    for (int i = 0; i < count; ++i) {
      basis.evaluate(s_.train[first + i].eta, scratch, phi, anyGradients() ? &grad : nullptr);
      if (Av.rows()) Av.row(i) = phi.transpose();
      if (Ag.rows()) Ag.middleRows(i * m_, m_) = grad;
    }
  }
  void addColumns(const std::vector<std::vector<int>>& fresh) {
    Eigen::MatrixXd Nv, Ng;  // the new columns at the samples already in
    rowsOf(toChebyshevBasis(fresh, lo_, hi_), 0, samplesIn_, Nv, Ng);
    const int P = static_cast<int>(exps_.size()), F = static_cast<int>(fresh.size());
    exps_.insert(exps_.end(), fresh.begin(), fresh.end());
    auto grow = [&](Eigen::MatrixXd& A, const Eigen::MatrixXd& N, Eigen::MatrixXd& G) {
      G.conservativeResize(P + F, P + F);
      G.topRightCorner(P, F) = A.transpose() * N;
      G.bottomLeftCorner(F, P) = G.topRightCorner(P, F).transpose();
      G.bottomRightCorner(F, F) = N.transpose() * N;
      A.conservativeResize(A.rows(), P + F);
      A.rightCols(F) = N;
    };
    if (anyValues()) grow(Av_, Nv, Gv_);
    if (anyGradients()) grow(Ag_, Ng, Gg_);
    for (Group g : groups_) {
      Bv_[g].conservativeResize(P + F, width(g));
      Bg_[g].conservativeResize(P + F, width(g));
      Bv_[g].bottomRows(F) = values(g) ? Eigen::MatrixXd(Nv.transpose() * bv_[g]) : Eigen::MatrixXd::Zero(F, width(g));
      Bg_[g].bottomRows(F) =
          gradients(g) ? Eigen::MatrixXd(Ng.transpose() * bg_[g]) : Eigen::MatrixXd::Zero(F, width(g));
    }
  }
  void addSamples() {
    const int n = static_cast<int>(s_.train.size()), count = n - samplesIn_, P = static_cast<int>(exps_.size());
    if (count <= 0) return;
    Eigen::MatrixXd Nv, Ng;  // the new samples' rows on every column
    rowsOf(toChebyshevBasis(exps_, lo_, hi_), samplesIn_, count, Nv, Ng);
    auto append = [P](Eigen::MatrixXd& A, const Eigen::MatrixXd& N, Eigen::MatrixXd& G) {
      G.selfadjointView<Eigen::Lower>().rankUpdate(N.transpose());
      G.triangularView<Eigen::StrictlyUpper>() = G.transpose();
      A.conservativeResize(A.rows() + N.rows(), P);
      A.bottomRows(N.rows()) = N;
    };
    if (anyValues()) append(Av_, Nv, Gv_);
    if (anyGradients()) append(Ag_, Ng, Gg_);
    for (Group g : groups_) {
      Eigen::MatrixXd v(values(g) ? count : 0, width(g)), gr(gradients(g) ? count * m_ : 0, width(g));
      Eigen::RowVectorXd vr(width(g));
      Eigen::MatrixXd grr(m_, width(g));
      for (int i = 0; i < count; ++i) {
        sampleRhs(s_.train[samplesIn_ + i], g, vr, grr);
        if (v.rows()) v.row(i) = vr;
        if (gr.rows()) gr.middleRows(i * m_, m_) = grr;
      }
      if (v.rows()) Bv_[g] += Nv.transpose() * v;
      if (gr.rows()) Bg_[g] += Ng.transpose() * gr;
      bv_[g].conservativeResize(bv_[g].rows() + v.rows(), width(g));
      bv_[g].bottomRows(v.rows()) = v;
      bg_[g].conservativeResize(bg_[g].rows() + gr.rows(), width(g));
      bg_[g].bottomRows(gr.rows()) = gr;
    }
    samplesIn_ = n;
  }

  const Samples& s_;
  Eigen::VectorXd lo_, hi_;
  int m_;
  std::vector<Group> groups_;
  std::vector<std::vector<int>> exps_;
  std::map<std::vector<int>, int> id_;
  int samplesIn_ = 0;
  Eigen::MatrixXd Av_, Ag_, Gv_, Gg_;                   // rows (samples) x columns; Gram matrices
  std::map<Group, Eigen::MatrixXd> bv_, bg_, Bv_, Bg_;  // each group's rows' b and A^T b
};

// Held-out error of a group's fit: each sample's error norm over the group's largest norm.
double heldOutError(const solvers::ChebyshevBasis& basis, const Samples& s, const Eigen::MatrixXd& coef, Group g) {
  const int m = basis.variables(), P = static_cast<int>(coef.rows());
  solvers::ChebyshevBasis::Scratch scratch;
  Eigen::VectorXd phi(basis.size());
  Eigen::MatrixXd grad(m, basis.size());
  double worst = 0.0;
  for (const OperatorSample& d : s.check) {
    basis.evaluate(d.eta, scratch, phi, &grad, P);
    double e = 0.0;
    if (g == kForce)
      e = (-grad.leftCols(P) * coef.col(0) - d.force).norm();
    else if (g == kLoads)
      for (int k = 0; k < coef.cols(); ++k)
        e = std::max(e, (grad.leftCols(P) * coef.col(k) - d.loadGrad.col(k)).norm());
    else if (g == kOutputs)
      e = (coef.transpose() * phi.head(P) - d.outputValue.cwiseQuotient(s.outputScale)).cwiseAbs().maxCoeff();
    else
      e = (coef.transpose() * phi.head(P) - (g == kMass ? d.mass : d.damping)).norm();
    worst = std::max(worst, e);
  }
  return s.scale[g] > 0.0 ? worst / s.scale[g] : worst;
}

// A group's fit on the fewest leading terms of the set that meet the tolerance (every leading
// part of an adaptive set is itself a lower set), else on all of them.
struct FieldFit {
  Eigen::MatrixXd coef;  // terms x columns
  double error = 0.0;
};
FieldFit fitGroup(const solvers::ChebyshevBasis& basis, const Samples& s, NormalEquations& normal, Group g,
                  double tolerance, int most) {
  std::vector<std::vector<int>> terms(basis.size(), std::vector<int>(basis.variables()));
  for (int p = 0; p < basis.size(); ++p)
    for (int i = 0; i < basis.variables(); ++i) terms[p][i] = basis.exponents()(p, i);
  const std::vector<int> ids = normal.columns(terms);
  auto solve = [&](int count) { return normal.solve(g, std::vector<int>(ids.begin(), ids.begin() + count)); };
  FieldFit best;
  best.error = std::numeric_limits<double>::infinity();
  int last = 0, below = 0;  // below: the longest leading part tried that does not meet the tolerance
  for (double share : {0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0}) {
    const int count = std::max(2, static_cast<int>(std::ceil(share * most)));
    if (count <= last || count > most) continue;
    last = count;
    const Eigen::MatrixXd c = solve(count);
    const double e = heldOutError(basis, s, c, g);
    if (e < best.error) best = {c, e};
    if (e <= tolerance) break;
    below = count;
  }
  // Between the last part that fails and the first that meets, the shortest that meets (bisection:
  // a term saved here is saved at every evaluation).
  int hi = static_cast<int>(best.coef.rows());
  if (best.error <= tolerance)
    while (hi - below > 1) {
      const int mid = (below + hi) / 2;
      const Eigen::MatrixXd c = solve(mid);
      const double e = heldOutError(basis, s, c, g);
      if (e <= tolerance) {
        best = {c, e};
        hi = mid;
      } else {
        below = mid;
      }
    }
  return best;
}

// The groups a model's operators have: the inertia fields (Mr, Cr), which often vary slowly with
// the configuration, and all of them.
std::vector<Group> inertiaGroupsOf(const Samples& s) {
  std::vector<Group> g{kMass};
  if (s.check.front().damping.size()) g.push_back(kDamping);
  return g;
}
std::vector<Group> allGroupsOf(const Samples& s) {
  std::vector<Group> g = inertiaGroupsOf(s);
  g.push_back(kForce);
  if (s.check.front().loadGrad.cols()) g.push_back(kLoads);
  if (s.check.front().outputGrad.cols()) g.push_back(kOutputs);
  return g;
}

// The polynomial terms, chosen greedily as a lower set (adaptive least squares in the manner of
// Chkifa, Cohen, Migliorati, Nobile & Tempone, ESAIM: M2AN 49, 2015): from {0, e_i}, each step fits
// every group on the set, scores each term of its margin (the terms whose predecessors are all in
// the set) by how much of the normalised residual it alone would remove, and adds the best ones,
// until the held-out errors meet the tolerance or the set reaches maxTerms. The samples grow with
// the set (three training rows per term). Returns the exponents in the order they were added.
std::vector<std::vector<int>> adaptiveTerms(Samples& s, NormalEquations& normal,
                                            const std::function<void(int)>& growTraining, const Eigen::VectorXd& lo,
                                            const Eigen::VectorXd& hi, const OperatorTrainingOptions& o,
                                            const std::vector<Group>& groups) {
  const int m = static_cast<int>(lo.size());
  std::vector<std::vector<int>> terms(1, std::vector<int>(m, 0));
  std::set<std::vector<int>> in(terms.begin(), terms.end());
  for (int i = 0; i < m; ++i) {
    std::vector<int> k(m, 0);
    k[i] = 1;
    terms.push_back(k);
    in.insert(k);
  }
  auto toBasis = [&](const std::vector<std::vector<int>>& list) { return toChebyshevBasis(list, lo, hi); };
  double lastHalved = std::numeric_limits<double>::infinity();
  int halvedAt = 0;
  for (int step = 0; step < 200; ++step) {
    const int L = static_cast<int>(terms.size());
    // The margin.
    std::vector<std::vector<int>> margin;
    std::set<std::vector<int>> seen;
    for (const auto& k : terms)
      for (int i = 0; i < m; ++i) {
        std::vector<int> c = k;
        if (++c[i] > o.maxDegree || in.count(c) || seen.count(c)) continue;
        bool admissible = true;
        for (int j = 0; j < m && admissible; ++j) {
          if (c[j] == 0) continue;
          std::vector<int> below = c;
          --below[j];
          admissible = in.count(below) > 0;
        }
        if (admissible) {
          margin.push_back(c);
          seen.insert(c);
        }
      }
    std::vector<std::vector<int>> all = terms;
    all.insert(all.end(), margin.begin(), margin.end());
    const int want = 3 * L + 40;
    if (static_cast<int>(s.train.size()) < want) growTraining(want - static_cast<int>(s.train.size()));
    if (static_cast<int>(s.train.size()) < L + 10) break;  // configurations do not solve: keep what fits
    s.rescale();
    const solvers::ChebyshevBasis current = toBasis(terms);
    const std::vector<int> ids = normal.columns(all);
    const std::vector<int> setIds(ids.begin(), ids.begin() + L), marginIds(ids.begin() + L, ids.end());
    // Fit the set, judge it, score the margin against the residuals.
    bool met = true;
    double worst = 0.0;  // the groups' largest held-out error over the tolerance
    Eigen::VectorXd score = Eigen::VectorXd::Zero(static_cast<int>(margin.size()));
    for (Group g : groups) {
      const Eigen::MatrixXd c = normal.solve(g, setIds, marginIds, score);
      const double he = heldOutError(current, s, c, g);
      met = met && he <= o.tolerance;
      worst = std::max(worst, he / o.tolerance);
    }
    if (met || L >= o.maxTerms || margin.empty()) break;
    // Terms that no longer pay (issue 49): within the most the operators may add, a set that grew
    // by kStallGrowth without halving its worst error stops (the fit's cost grows as L^3, an
    // evaluation's as L).
    if (worst <= 0.5 * lastHalved) {
      lastHalved = worst;
      halvedAt = L;
    }
    if (worst <= kMostOverTolerance && L > kStallGrowth * halvedAt) break;
    // Add the best-scoring margin terms (at least one, at most a quarter of the set).
    std::vector<int> order(margin.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return score[a] > score[b]; });
    const double top = score[order.front()];
    const int most = std::max(2, L / 4);
    for (int r = 0; r < static_cast<int>(order.size()) && r < most && L + r < o.maxTerms; ++r) {
      if (r > 0 && score[order[r]] < 0.1 * top) break;
      terms.push_back(margin[order[r]]);
      in.insert(margin[order[r]]);
    }
  }
  return terms;
}

// One evaluation of the operators and of Eq. 19 at the range's centre (median of a few dozen):
// what a run saves per evaluation, so that a front end can prefer Eq. 19 where operators cost more.
void timeOneEvaluation(const core::Model& model, const Eigen::MatrixXd& V, ReducedOperators& ops) {
  using Clock = std::chrono::steady_clock;
  OperatorDynamics od(model, ops);
  core::EquationsOfMotion eom(model, V);
  const int m = ops.size();
  Eigen::VectorXd y(2 * m), dy(2 * m);
  y << ops.centre + ops.rotation * (0.5 * (ops.lower + ops.upper)), Eigen::VectorXd::Zero(m);
  const double t = model.settings.t0;
  auto median = [](const std::function<void()>& call) {
    std::vector<double> s;
    for (int k = 0; k < 41; ++k) {
      const auto t0 = Clock::now();
      call();
      s.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    std::nth_element(s.begin(), s.begin() + 20, s.end());
    return s[20];
  };
  try {
    ops.equation19Seconds = median([&] { eom.rhs(t, y, dy); });
  } catch (const core::KinematicsError&) {
    ops.equation19Seconds = 0.0;  // not measured
  }
  ops.operatorSeconds = median([&] { od.rhs(t, y, dy); });
}

}  // namespace

OperatorFit operatorFitAtHeldOut(const core::Model& model, const Eigen::MatrixXd& V, const ReducedOperators& ops) {
  OperatorFit f;
  const int m = ops.size();
  if (ops.heldOut.rows() == 0 || ops.heldOut.cols() != m) return f;
  const std::vector<core::OperatorOutput> none;  // the outputs do not enter the dynamics
  OperatorSampler sampler(model, V * ops.rotation, V * ops.centre, ops.loads, none);
  Samples s;
  s.scale[kForce] = ops.forceScale;
  s.scale[kMass] = ops.massScale;
  s.scale[kDamping] = ops.dampingScale;
  s.scale[kLoads] = ops.loadScale;
  for (int r = 0; r < ops.heldOut.rows(); ++r) {
    OperatorSample d;
    if (sampler.sample(ops.heldOut.row(r).transpose(), d))
      s.check.push_back(std::move(d));
    else
      ++f.unsolved;
  }
  f.configurations = static_cast<int>(ops.heldOut.rows());
  if (s.check.empty()) return f;
  const solvers::ChebyshevBasis basis(ops.lower, ops.upper, ops.exponents);
  f.force = heldOutError(basis, s, Eigen::MatrixXd(ops.potential), kForce);
  f.mass = heldOutError(basis, s, ops.mass.transpose(), kMass);
  if (ops.damping.size()) f.mass = std::max(f.mass, heldOutError(basis, s, ops.damping.transpose(), kDamping));
  if (!ops.loads.empty()) f.force = std::max(f.force, heldOutError(basis, s, ops.loadFields, kLoads));
  return f;
}

// The declared fit: the larger of training's and a run's own measure at the held-out
// configurations (operatorFitAtHeldOut); those that do not solve from the initial configuration
// are dropped.
void declareHeldOutFit(const core::Model& model, const Eigen::MatrixXd& V, ReducedOperators& ops) {
  for (int pass = 0; pass < 3; ++pass) {
    const OperatorFit fit = operatorFitAtHeldOut(model, V, ops);
    if (fit.unsolved == 0) {
      ops.forceError = std::max(ops.forceError, fit.force);
      ops.massError = std::max(ops.massError, fit.mass);
      break;
    }
    const std::vector<core::OperatorOutput> none;
    OperatorSampler again(model, V * ops.rotation, V * ops.centre, ops.loads, none);
    std::vector<int> keep;
    for (int r = 0; r < ops.heldOut.rows(); ++r) {
      OperatorSample d;
      if (again.sample(ops.heldOut.row(r).transpose(), d)) keep.push_back(r);
    }
    ops.heldOut = Eigen::MatrixXd(ops.heldOut(keep, Eigen::all));
    if (pass == 2) throw std::runtime_error("the held-out configurations do not solve reproducibly");
  }
}

ReducedOperators trainOperators(const core::Model& model, const Eigen::MatrixXd& V, const OperatorTrainingOptions& o) {
  const std::string why = operatorsUnsupported(model);
  if (!why.empty()) throw std::invalid_argument("no reduced operators: " + why);
  const auto started = std::chrono::steady_clock::now();
  const int m = static_cast<int>(V.cols());
  ReducedOperators ops;
  ops.dofs = static_cast<int>(V.rows());
  ops.basisChecksum = basisChecksum(V);
  ops.loads = timeLoads(model);
  Eigen::VectorXd lo = o.lower, hi = o.upper;
  ops.centre = Eigen::VectorXd::Zero(m);
  ops.rotation = Eigen::MatrixXd::Identity(m, m);
  OperatorTrainingOptions opt = o;
  if (lo.size() == 0) {
    const double estimate = pilotRange(model, V, o, ops.centre, ops.rotation, lo, hi);
    std::ostringstream r;
    r << "pilot run of Eq. 19 (ode45, RelTol "
      << text::shortest(std::isnan(o.pilotRelTol) ? model.settings.relTol : o.pilotRelTol)
      << ") to t = " << text::shortest(model.settings.tEnd) << " s, its principal directions, widened "
      << text::shortest(100 * o.margin) << "% each side";
    // Fit to a small share of the reduction error the basis has anyway (issue 33: the operators may add
    // at most 10% of it; the estimate is 1.4-3x the true error).
    if (std::isnan(opt.tolerance)) {
      opt.tolerance = std::isfinite(estimate) ? std::clamp(kToleranceShare * estimate, 1e-7, 1e-3) : 1e-6;
      r << "; fit tolerance " << text::shortest(opt.tolerance)
        << (std::isfinite(estimate) ? " (" + text::shortest(kToleranceShare) + " of its reduction error estimate " +
                                          text::shortest(estimate) + ")"
                                    : "");
    }
    ops.range = r.str();
  } else {
    if (lo.size() != m || hi.size() != m) throw std::invalid_argument("operator range: one bound per basis column");
    ops.range = "given";
    if (std::isnan(opt.tolerance)) opt.tolerance = 1e-6;
  }
  ops.tolerance = opt.tolerance;
  for (const core::OperatorOutput& q : o.outputs)
    if (q.index < 0 || q.index >= (q.kind == core::OperatorOutput::Kind::Deformation ? model.ne : model.nx))
      throw std::invalid_argument("operator output index out of range");
  ops.outputs = o.outputs;
  OperatorSampler sampler(model, V * ops.rotation, V * ops.centre, ops.loads, ops.outputs);

  // Samples from the arcsine density (Halton), chained nearest-first so that Newton starts close.
  long next = 1;
  auto draw = [&](int count, std::vector<OperatorSample>& into) {
    std::vector<Eigen::VectorXd> pts;
    const solvers::ChebyshevBasis box(lo, hi, std::vector<int>(m, 1));
    for (int i = 0; i < count; ++i) pts.push_back(box.arcsinePoint(solvers::haltonPoint(next++, m)));
    Eigen::VectorXd at = into.empty() ? Eigen::VectorXd(0.5 * (lo + hi)) : into.back().eta;
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
      if (sampler.sample(at, s)) into.push_back(std::move(s));
    }
  };
  Samples samples;
  draw(kHeldOut, samples.check);
  if (static_cast<int>(samples.check.size()) < kHeldOut / 2)
    throw std::runtime_error("fewer than half of the configurations in the operators' range solve");
  // One set for all fields; then a set of the inertia fields' own, put first where the mass needs
  // fewer terms that way (an evaluation's mass pass, O(terms m^2), is its costly part). Every
  // prefix stays a lower set.
  const auto grow = [&](int count) { draw(count, samples.train); };
  NormalEquations normal(samples, lo, hi, allGroupsOf(samples));
  std::vector<std::vector<int>> terms = adaptiveTerms(samples, normal, grow, lo, hi, opt, allGroupsOf(samples));
  int inertiaTerms = static_cast<int>(terms.size());
  {
    samples.rescale();
    const int shared = static_cast<int>(
        fitGroup(toChebyshevBasis(terms, lo, hi), samples, normal, kMass, kInertiaShare * opt.tolerance, inertiaTerms)
            .coef.rows());
    OperatorTrainingOptions inertiaOpt = opt;
    inertiaOpt.tolerance *= kInertiaShare;
    std::vector<std::vector<int>> own =
        adaptiveTerms(samples, normal, grow, lo, hi, inertiaOpt, inertiaGroupsOf(samples));
    if (static_cast<int>(own.size()) < shared) {
      inertiaTerms = static_cast<int>(own.size());
      for (auto& k : terms)
        if (std::find(own.begin(), own.end(), k) == own.end()) own.push_back(std::move(k));
      terms = std::move(own);
    }
  }
  Eigen::MatrixXi exponents(static_cast<int>(terms.size()), m);
  for (size_t p = 0; p < terms.size(); ++p)
    for (int i = 0; i < m; ++i) exponents(static_cast<int>(p), i) = terms[p][i];
  const solvers::ChebyshevBasis basis(lo, hi, exponents);
  ops.lower = lo;
  ops.upper = hi;
  ops.exponents = exponents;
  samples.rescale();
  const int allTerms = basis.size();
  const FieldFit force = fitGroup(basis, samples, normal, kForce, opt.tolerance, allTerms);
  const FieldFit mass = fitGroup(basis, samples, normal, kMass, kInertiaShare * opt.tolerance, inertiaTerms);
  ops.potential = force.coef.col(0);
  ops.mass = mass.coef.transpose();
  ops.forceError = force.error;
  ops.massError = mass.error;
  if (sampler.hasDamping()) {
    const FieldFit d = fitGroup(basis, samples, normal, kDamping, kInertiaShare * opt.tolerance, inertiaTerms);
    ops.damping = d.coef.transpose();
    ops.massError = std::max(ops.massError, d.error);
  }
  if (!ops.loads.empty()) {
    const FieldFit l = fitGroup(basis, samples, normal, kLoads, opt.tolerance, allTerms);
    ops.loadFields = l.coef;
    ops.forceError = std::max(ops.forceError, l.error);
  }
  if (!ops.outputs.empty()) {
    const FieldFit q = fitGroup(basis, samples, normal, kOutputs, opt.tolerance, allTerms);
    ops.outputFields = q.coef * samples.outputScale.asDiagonal();
    ops.outputError = q.error;
  }
  ops.trainingSamples = static_cast<int>(samples.train.size());
  ops.validationSamples = static_cast<int>(samples.check.size());
  // What a run checks before it uses them (operatorsMismatch): the same errors at the same held-out
  // configurations, solved anew from the initial configuration (their Newton paths differ from the
  // chained sampling's; a configuration that then does not solve is dropped). The declared fit is
  // the larger of the two, so that a run on this model measures at most what they declare.
  ops.modelChecksum = operatorModelChecksum(model);
  ops.forceScale = samples.scale[kForce];
  ops.massScale = samples.scale[kMass];
  ops.dampingScale = samples.scale[kDamping];
  ops.loadScale = samples.scale[kLoads];
  ops.heldOut.resize(static_cast<int>(samples.check.size()), m);
  for (size_t r = 0; r < samples.check.size(); ++r) ops.heldOut.row(static_cast<int>(r)) = samples.check[r].eta;
  declareHeldOutFit(model, V, ops);
  timeOneEvaluation(model, V, ops);
  ops.trainingSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return ops;
}

std::vector<core::OperatorOutput> trackedQuantities(const core::Model& model, const std::vector<int>& nodeLabels,
                                                    const std::vector<int>& elementLabels) {
  std::vector<core::OperatorOutput> out;
  for (int label : nodeLabels) {
    const auto it = model.nodeByLabel.find(label);
    if (it == model.nodeByLabel.end())
      throw std::invalid_argument("node " + std::to_string(label) + " is not in " + model.sourceFile);
    const core::Node& n = model.nodes[it->second];
    for (int i = 0; i < n.dim(); ++i) out.push_back({core::OperatorOutput::Kind::Coordinate, n.firstCoord + i});
  }
  for (int label : elementLabels) {
    const auto it = model.elementByLabel.find(label);
    if (it == model.elementByLabel.end())
      throw std::invalid_argument("element " + std::to_string(label) + " is not in " + model.sourceFile);
    const core::ElementEntry& E = model.elements[it->second];
    for (int i = 0; i < E.impl->numDeformations(); ++i)
      out.push_back({core::OperatorOutput::Kind::Deformation, E.firstDef + i});
  }
  return out;
}

}  // namespace flexmb::analysis
