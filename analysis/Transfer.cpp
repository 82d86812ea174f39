#include "analysis/Transfer.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>

#include "analysis/DesignDamping.hpp"
#include "analysis/Perturbation.hpp"
#include "core/elements/EulerParameters.hpp"

namespace flexmb::analysis {

namespace {
using Kind = core::TransferChannel::Kind;

std::string channelName(const core::Model& model, const core::TransferChannel& c, const char* suffix = "") {
  const core::Node& n = model.nodes[c.node];
  static const char* axes[] = {"x", "y", "z"};
  std::string what;
  switch (c.kind) {
    case Kind::Force:
      what = c.axis ? "moment" : n.kind == core::NodeKind::Orientation ? "moment" : "force";
      break;
    case Kind::Motion:
      what = "input motion";
      break;
    case Kind::Coordinate:
      what = c.axis || n.kind == core::NodeKind::Orientation ? "rotation" : "displacement";
      break;
    case Kind::Velocity:
      what = c.axis || n.kind == core::NodeKind::Orientation ? "angular velocity" : "velocity";
      break;
    case Kind::NodalForce:
      what = c.axis || n.kind == core::NodeKind::Orientation ? "support moment" : "support force";
      break;
  }
  const std::string comp = n.kind == core::NodeKind::Orientation ? "" : std::string(" ") + axes[c.component - 1];
  return c.keyword + " " + std::to_string(c.number) + ": " + what + comp + suffix + " node " + std::to_string(n.label);
}

// A channel's unit in SI (the .dat has none: SPACAR Light's models are in SI); "" where unknown
// (a warping coordinate). derivative: INX's position (0), velocity (1) or acceleration (2).
std::string channelUnit(const core::Model& model, const core::TransferChannel& c, int derivative = 0) {
  const core::Node& n = model.nodes[c.node];
  if (n.kind == core::NodeKind::Warping) return "";
  const bool turn = c.axis || n.kind == core::NodeKind::Orientation;
  const std::string motion = turn ? "rad" : "m";
  switch (c.kind) {
    case Kind::Force:
    case Kind::NodalForce:
      return turn ? "N m" : "N";
    case Kind::Motion:
      return motion + (derivative == 1 ? "/s" : derivative == 2 ? "/s^2" : "");
    case Kind::Coordinate:
      return motion;
    case Kind::Velocity:
      return motion + "/s";
  }
  return "";
}

// The coordinates a channel acts on, with weights: one coordinate with weight 1, or on a spatial
// orientation node the Euler parameters with 2 E(lambda)^T e_i (a moment about a global axis, its
// dual the rotation 2 E(lambda) dlambda) or 1/2 E(lambda)^T e_i (the moment of the forces on the
// Euler parameters, fxt: M = 1/2 E f_lambda, E E^T = I).
struct Weighted {
  std::vector<int> coords;
  std::vector<double> w;
};
Weighted weights(const core::TransferChannel& c, const Eigen::VectorXd& x, double scale) {
  Weighted r;
  if (!c.axis) {
    r.coords = {c.coord};
    r.w = {1.0};
    return r;
  }
  const Eigen::Vector4d lambda = x.segment<4>(c.coord);
  const core::euler::Mat34 E = core::euler::globalRateMatrix(lambda);
  for (int k = 0; k < 4; ++k) {
    r.coords.push_back(c.coord + k);
    r.w.push_back(scale * E(c.component - 1, k));
  }
  return r;
}
// Known coordinates that become degrees of freedom: INX inputs, OUTF supports.
std::vector<int> transferKnownCoordinates(const core::Model& model) {
  std::vector<int> known;
  auto addKnown = [&](int j) {
    if ((model.xRole[j] == core::Role::Fixed || model.xRole[j] == core::Role::Input) &&
        std::find(known.begin(), known.end(), j) == known.end())
      known.push_back(j);
  };
  for (const auto& c : model.transferInputs)
    if (c.kind == Kind::Motion) addKnown(c.coord);
  for (const auto& c : model.transferOutputs)
    if (c.kind == Kind::NodalForce)
      for (int k = 0; k < (c.axis ? 4 : 1); ++k) addKnown(c.coord + k);
  return known;
}

// What the output rows need of the linearisation: the augmented model's matrices and where the
// model's degrees of freedom (qi) and the inputs' channels are in them.
struct TransferBlocks {
  int m;
  const std::vector<int>& qi;
  const Eigen::MatrixXd &F, &Kt, &Ct;
  const core::LinearizedSystem& s;
  const DofPlaces& at;
  const std::vector<int>& motionChannel;
  const std::vector<std::pair<int, Eigen::VectorXd>>& forceLoads;
  Eigen::RowVectorXd block(const Eigen::MatrixXd& X, int row) const {  // X(row, q) as a row vector
    Eigen::RowVectorXd r(m);
    for (int k = 0; k < m; ++k) r[k] = X(row, qi[k]);
    return r;
  }
};

// The rows of C and D: OUTX / OUTXP from the first-order transfer F (plus an INX input's direct
// motion of the output), OUTF from the balance along the output coordinates.
void outputRows(const core::Model& model, const StaticStep& step, const TransferBlocks& t, StateSpace& ss) {
  const int m = t.m, no = static_cast<int>(model.transferOutputs.size()), ni = static_cast<int>(ss.B.cols());
  const Eigen::MatrixXd &Kt = t.Kt, &Ct = t.Ct, &F = t.F;
  const core::LinearizedSystem& s = t.s;
  const DofPlaces& at = t.at;
  const std::vector<int>& motionChannel = t.motionChannel;
  auto block = [&](const Eigen::MatrixXd& X, int row) { return t.block(X, row); };
  ss.C = Eigen::MatrixXd::Zero(no, 2 * m);
  ss.D = Eigen::MatrixXd::Zero(no, ni);
  for (int r = 0; r < no; ++r) {
    const auto& c = model.transferOutputs[r];
    ss.outputNames.push_back(channelName(model, c));
    ss.outputUnits.push_back(channelUnit(model, c));
    if (c.kind == Kind::Coordinate || c.kind == Kind::Velocity) {
      const Weighted w = weights(c, step.x, 2.0);
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(m);
      for (std::size_t i = 0; i < w.coords.size(); ++i) row += w.w[i] * block(F, w.coords[i]);
      (c.kind == Kind::Coordinate ? ss.C.block(r, 0, 1, m) : ss.C.block(r, m, 1, m)) = row;
      // Direct motion of the output by an INX input: its position (OUTX) or velocity (OUTXP) channel.
      for (std::size_t k = 0; k < model.transferInputs.size(); ++k) {
        if (motionChannel[k] < 0) continue;
        const int u = at.x[model.transferInputs[k].coord];
        double d = 0.0;
        for (std::size_t i = 0; i < w.coords.size(); ++i) d += w.w[i] * F(w.coords[i], u);
        ss.D(r, motionChannel[k] + (c.kind == Kind::Coordinate ? 0 : 1)) += d;
      }
    } else {  // OUTF: fxt_j = f_j - Q_j
      const Weighted w = weights(c, step.x, 0.5);
      Eigen::RowVectorXd rk = Eigen::RowVectorXd::Zero(m), rc = rk, rm = rk;
      std::vector<double> wk(w.coords.size());
      for (std::size_t i = 0; i < w.coords.size(); ++i) {
        const int j = at.x[w.coords[i]];
        if (j < 0) continue;  // a calculable Euler parameter: its force is the applied one (none)
        rk += w.w[i] * block(Kt, j), rc += w.w[i] * block(Ct, j), rm += w.w[i] * block(s.M, j);
      }
      ss.C.block(r, 0, 1, m) = rk + rm * ss.A.bottomLeftCorner(m, m);
      ss.C.block(r, m, 1, m) = rc + rm * ss.A.bottomRightCorner(m, m);
      ss.D.row(r) = rm * ss.B.bottomRows(m);
      // The row of a known coordinate j in the augmented model is the balance of everything that
      // does work along it: the support force plus the applied loads there. A force input acts
      // along j when j moves its point (in the augmented model a support coordinate carries the
      // structure beyond it: a base displacement moves every point), so its share is subtracted.
      for (const auto& [col, bAug] : t.forceLoads)
        for (std::size_t i = 0; i < w.coords.size(); ++i) {
          const int j = at.x[w.coords[i]];
          if (j >= 0) ss.D(r, col) -= w.w[i] * bAug[j];
        }
      for (std::size_t k = 0; k < model.transferInputs.size(); ++k) {
        if (motionChannel[k] < 0) continue;
        const int u = at.x[model.transferInputs[k].coord];
        for (std::size_t i = 0; i < w.coords.size(); ++i) {
          const int j = at.x[w.coords[i]];
          if (j < 0) continue;
          ss.D(r, motionChannel[k]) += w.w[i] * Kt(j, u);
          ss.D(r, motionChannel[k] + 1) += w.w[i] * Ct(j, u);
          ss.D(r, motionChannel[k] + 2) += w.w[i] * s.M(j, u);
        }
      }
    }
  }
}

// The damping a designer states (analysis/DesignDamping.hpp) added to C0 + D0 of the augmented
// linearisation: beta K0 on all its coordinates (as EDAMP = beta * ESTIFF), the modal term and
// alpha M on the degrees of freedom (rows and columns qi) only.
void addDesignDamping(const core::LinearizedSystem& s, const Eigen::MatrixXd& Kt, const std::vector<int>& qi,
                      const DampingOptions& damping, Eigen::MatrixXd& Cs) {
  if (damping.beta != 0.0) Cs += damping.beta * s.K;
  const Eigen::Index m = static_cast<Eigen::Index>(qi.size());
  Eigen::MatrixXd Mq(m, m), Kq(m, m);
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = 0; i < m; ++i) Mq(i, j) = s.M(qi[i], qi[j]), Kq(i, j) = Kt(qi[i], qi[j]);
  DampingOptions onDofs = damping;
  onDofs.beta = 0.0;
  const Eigen::MatrixXd Cq = designDamping(Mq, Kq, Kq, onDofs);
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = 0; i < m; ++i) Cs(qi[i], qi[j]) += Cq(i, j);
}

}  // namespace

StateSpace stateSpaceAt(const core::Model& model, const StaticStep& step, const DampingOptions& damping) {
  if (model.transferInputs.empty() || model.transferOutputs.empty())
    throw std::invalid_argument(
        "the transfer function needs at least one input (INPUTF, INX) and one output (OUTX, OUTXP, OUTF) in the "
        "transfer block after the second END HALT");
  const std::vector<int> known = transferKnownCoordinates(model);
  const core::Model aug = withKnownAsDofs(model, known, {});
  // Without known coordinates the statics' own linearisation of the step is the one needed (its
  // four projections cost O(nx m^2) each): only F is computed here.
  const int nq = model.numDofs();
  const bool ownSystem = known.empty() && step.system.M.rows() == nq && step.system.K.rows() == nq &&
                         step.system.G.rows() == nq && (step.system.D.size() == 0 || step.system.D.rows() == nq) &&
                         (step.system.C.size() == 0 || step.system.C.rows() == nq) &&
                         (step.system.N.size() == 0 || step.system.N.rows() == nq);
  PerturbedSystem p;
  std::unique_ptr<core::Linearization> placed;  // the step's own system: Mbar factorised sparse there
  if (ownSystem) {
    placed = placedAt(aug, step);
    p.F = placed->firstOrderTransfer();
  } else {
    p = linearizeAt(aug, step);
  }
  const DofPlaces at = dofPlaces(aug);
  const core::LinearizedSystem& s = ownSystem ? step.system : p.system;
  // K0 + N0 + G0 and C0 + D0 (at rest N0 and C0 are empty, D0 too without damping: zero). The
  // known coordinates' INX and OUTF channels read Ct's entries: then it is whole.
  const Eigen::MatrixXd Kt = s.N.size() ? Eigen::MatrixXd(s.K + s.G + s.N) : Eigen::MatrixXd(s.K + s.G);
  const Eigen::Index na = s.M.rows();
  const int m = model.numDofs();
  std::vector<int> qi(m);
  bool inOrder = s.M.rows() == m;
  for (int k = 0; k < m; ++k) {
    qi[k] = at.of(model.dofs[k]);
    inOrder = inOrder && qi[k] == k;
  }
  Eigen::MatrixXd Cs;
  if (s.C.size() || (!known.empty() && s.D.size() == 0) || damping.any()) {
    Cs.setZero(na, na);
    if (s.C.size()) Cs += s.C;
    if (s.D.size()) Cs += s.D;
    if (damping.any()) addDesignDamping(s, Kt, qi, damping, Cs);
  }
  const Eigen::MatrixXd& Ct = Cs.size() ? Cs : s.D;
  auto block = [&](const Eigen::MatrixXd& X, int row) {  // X(row, q) as a row vector
    Eigen::RowVectorXd r(m);
    for (int k = 0; k < m; ++k) r[k] = X(row, qi[k]);
    return r;
  };
  // M0, K0 + N0 + G0 and C0 + D0 over the model's degrees of freedom (copies only when the
  // augmented model orders them otherwise).
  Eigen::MatrixXd Mc, Kc, Cc;
  if (!inOrder) {
    Mc.resize(m, m), Kc.resize(m, m), Cc.resize(m, m);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        Mc(i, j) = s.M(qi[i], qi[j]), Kc(i, j) = Kt(qi[i], qi[j]), Cc(i, j) = Ct(qi[i], qi[j]);
  }
  const Eigen::MatrixXd &M = inOrder ? s.M : Mc, &K = inOrder ? Kt : Kc, &Cd = inOrder ? Ct : Cc;
  const Eigen::LLT<Eigen::MatrixXd> mass(M);
  if (mass.info() != Eigen::Success)
    throw std::runtime_error(
        "the mass matrix M0 is not positive definite (a degree of freedom without mass: give EM or XM), so the "
        "state-space model d/dt [dq; dqd] = A [dq; dqd] + B u does not exist");
  // M0^-1 X: by sparse saddle-point solves (O(m nnz) per column, where the Cholesky factor's two
  // triangular solves cost O(m^2)) when the step's own linearisation is placed, accepted by the
  // residual of one combination of the columns; else, or when that fails, by the Cholesky factor.
  bool sparseMass = placed && inOrder && placed->factorizeMass();
  auto solveMass = [&](const Eigen::MatrixXd& X, Eigen::MatrixXd& Y) {
    if (sparseMass) {
      placed->solveMass(X, Y);
      const Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(X.cols(), 1.0, 2.0);
      const Eigen::VectorXd y = Y * w, x = X * w;
      if ((M * y - x).norm() <= 1e-9 * (M.norm() * y.norm() + x.norm())) return;
      sparseMass = false;
    }
    Y = mass.solve(X);
  };

  StateSpace ss;
  ss.A = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  ss.A.topRightCorner(m, m).setIdentity();
  Eigen::MatrixXd Y;
  solveMass(K, Y);
  ss.A.bottomLeftCorner(m, m) = -Y;
  if (Cd.size() && !Cd.isZero(0.0)) {  // undamped: stays 0 (a solve saved)
    solveMass(Cd, Y);
    ss.A.bottomRightCorner(m, m) = -Y;
  }

  // Inputs: the generalised load on q of each channel (columns), before M0^-1.
  std::vector<Eigen::VectorXd> loads;
  std::vector<int> motionChannel(model.transferInputs.size(), -1);  // first of INX's three channels
  // A force input's generalised load on every degree of freedom of the augmented model (its rows
  // of the known coordinates enter OUTF), and its column of B.
  std::vector<std::pair<int, Eigen::VectorXd>> forceLoads;
  for (std::size_t k = 0; k < model.transferInputs.size(); ++k) {
    const auto& c = model.transferInputs[k];
    if (c.kind == Kind::Force) {
      const Weighted w = weights(c, step.x, 2.0);
      Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
      Eigen::VectorXd bAug = Eigen::VectorXd::Zero(p.F.cols());
      for (std::size_t i = 0; i < w.coords.size(); ++i) {
        b += w.w[i] * block(p.F, w.coords[i]).transpose();
        bAug += w.w[i] * p.F.row(w.coords[i]).transpose();
      }
      forceLoads.emplace_back(static_cast<int>(loads.size()), std::move(bAug));
      loads.push_back(b);
      ss.inputNames.push_back(channelName(model, c));
      ss.inputUnits.push_back(channelUnit(model, c));
    } else {  // INX: -(K+G)_qu, -D_qu, -M_qu for u, du/dt, d2u/dt2
      const int u = at.x[c.coord];
      motionChannel[k] = static_cast<int>(loads.size());
      for (const Eigen::MatrixXd* X : {&Kt, &Ct, &s.M}) {
        Eigen::VectorXd b(m);
        for (int i = 0; i < m; ++i) b[i] = -(*X)(qi[i], u);
        loads.push_back(b);
      }
      for (int d = 0; d < 3; ++d) {
        ss.inputNames.push_back(channelName(model, c,
                                            d == 0   ? " (position)"
                                            : d == 1 ? " (velocity)"
                                                     : " (acceleration)"));
        ss.inputUnits.push_back(channelUnit(model, c, d));
      }
    }
  }
  const int ni = static_cast<int>(loads.size());
  Eigen::MatrixXd Q(m, ni);
  for (int k = 0; k < ni; ++k) Q.col(k) = loads[k];
  ss.B = Eigen::MatrixXd::Zero(2 * m, ni);
  solveMass(Q, Y);
  ss.B.bottomRows(m) = Y;

  outputRows(model, step, TransferBlocks{m, qi, p.F, Kt, Ct, s, at, motionChannel, forceLoads}, ss);
  return ss;
}

TransferRun transferAnalysis(const core::Model& model, const TransferOptions& options) {
  if (model.transferInputs.empty() || model.transferOutputs.empty())
    throw std::invalid_argument(
        "the transfer function needs at least one input (INPUTF, INX) and one output (OUTX, OUTXP, OUTF) in the "
        "transfer block after the second END HALT");
  TransferRun r;
  StaticOptions so;
  so.nev = std::min(options.nev, model.numDofs());  // the .sbm's frequencies: at most one per degree of freedom
  so.loadSteps = options.loadSteps;
  so.onStep = options.onStep;
  r.statics = staticAnalysis(model, so);
  r.completed = r.statics.completed;
  r.stopReason = r.statics.stopReason;
  if (!r.completed || r.statics.steps.empty()) {
    if (r.completed) r.completed = false, r.stopReason = "no load step reached";
    return r;
  }
  try {  // the statics stand when the state-space model cannot be made
    r.model = stateSpaceAt(model, r.statics.steps.back(), options.damping);
  } catch (const std::exception& e) {
    r.completed = false;
    r.stopReason =
        std::string("the state-space model at the last load step: ") + e.what() + "; the load steps are kept";
  }
  return r;
}

std::vector<Eigen::VectorXcd> frequencyResponses(const StateSpace& ss, const Eigen::VectorXd& omega) {
  // A = Q H Q^T (Hessenberg, once for every pair): each frequency is then one O(n^2) Hessenberg
  // elimination shared by all inputs.
  const Eigen::Index n = ss.A.rows(), ni = ss.B.cols(), no = ss.C.rows();
  std::vector<Eigen::VectorXcd> h(static_cast<std::size_t>(ni * no), Eigen::VectorXcd(omega.size()));
  if (n == 0) {
    for (Eigen::Index i = 0; i < ni; ++i)
      for (Eigen::Index o = 0; o < no; ++o) h[i * no + o].setConstant(ss.D(o, i));
    return h;
  }
  const Eigen::HessenbergDecomposition<Eigen::MatrixXd> hd(ss.A);
  const Eigen::MatrixXd H = hd.matrixH();
  const Eigen::MatrixXd Qm = hd.matrixQ();
  const Eigen::MatrixXcd b = (Qm.transpose() * ss.B).cast<std::complex<double>>();
  const Eigen::MatrixXcd c = (ss.C * Qm).cast<std::complex<double>>();
  Eigen::MatrixXcd T(n, n), z(n, ni);
  for (Eigen::Index k = 0; k < omega.size(); ++k) {
    const std::complex<double> s(0.0, omega[k]);
    T = -H.cast<std::complex<double>>();
    T.diagonal().array() += s;
    z = b;
    // Gaussian elimination of the one subdiagonal, rows swapped when the subdiagonal is larger.
    for (Eigen::Index i = 0; i + 1 < n; ++i) {
      if (std::abs(T(i + 1, i)) > std::abs(T(i, i))) {
        T.row(i).segment(i, n - i).swap(T.row(i + 1).segment(i, n - i));
        z.row(i).swap(z.row(i + 1));
      }
      if (T(i + 1, i) == 0.0) continue;
      const std::complex<double> l = T(i + 1, i) / T(i, i);
      T.row(i + 1).segment(i, n - i) -= l * T.row(i).segment(i, n - i);
      z.row(i + 1) -= l * z.row(i);
    }
    for (Eigen::Index i = n - 1; i >= 0; --i) {
      for (Eigen::Index j = i + 1; j < n; ++j) z.row(i) -= T(i, j) * z.row(j);
      z.row(i) /= T(i, i);
    }
    const Eigen::MatrixXcd y = c * z;  // no x ni
    for (Eigen::Index i = 0; i < ni; ++i)
      for (Eigen::Index o = 0; o < no; ++o) h[i * no + o][k] = y(o, i) + ss.D(o, i);
  }
  return h;
}

Eigen::VectorXcd frequencyResponse(const StateSpace& ss, int input, int output, const Eigen::VectorXd& omega) {
  StateSpace one;
  one.A = ss.A;
  one.B = ss.B.col(input);
  one.C = ss.C.row(output);
  one.D = ss.D.block(output, input, 1, 1);
  return frequencyResponses(one, omega)[0];
}

bool undamped(const StateSpace& ss) {
  const Eigen::Index m = ss.A.rows() / 2;
  return m > 0 && ss.A.bottomRightCorner(m, m).isZero(0.0);
}

Eigen::VectorXd bodePhase(const StateSpace& ss, const Eigen::VectorXcd& h) {
  Eigen::VectorXd phase(h.size());
  if (undamped(ss)) {
    // Undamped, H(i w) is real (a position or force output) or imaginary (a velocity output): its
    // phase is 0, +-90 or 180 degrees (near a resonance round-off tilts it by a few). Which way a
    // sign change turns (+180 or -180) only damping the model lacks decides: added up over the
    // resonances it reached -540 degrees and more, a phase no evaluation of H shows. So each value
    // is H's own, rounded to a quarter turn, a negative real H at -180 (as a lightly damped model's
    // just past its first resonance): within [-180, 90].
    for (Eigen::Index k = 0; k < h.size(); ++k) {
      const double quarter = std::round(std::arg(h[k]) * 2.0 / M_PI);
      phase[k] = 90.0 * (quarter > 1.5 ? -2.0 : quarter);
    }
    return phase;
  }
  // Damped: continuous (no jump over 180 degrees between neighbours), from H's phase at the lowest
  // frequency: each resonance and zero turns it by up to 180 degrees, the way the damping says.
  double unwrap = 0.0, last = 0.0;
  for (Eigen::Index k = 0; k < h.size(); ++k) {
    const double a = std::arg(h[k]) * 180.0 / M_PI;
    if (k > 0) {
      while (a + unwrap - last > 180.0) unwrap -= 360.0;
      while (a + unwrap - last < -180.0) unwrap += 360.0;
    }
    last = phase[k] = a + unwrap;
  }
  return phase;
}

std::optional<Eigen::MatrixXd> staticGain(const StateSpace& ss) {
  const Eigen::Index n = ss.A.rows(), ni = ss.B.cols();
  // Static gain -C A^-1 B + D: the compliance of the equilibrium (outputs per unit input). A is
  // [0 I; A21 A22] over (dq, dqd): with x = A^-1 B, x2 = B1 and A21 x1 = B2 - A22 B1, so only
  // A21 = -M^-1 K is factorised. The whole A is far worse conditioned (its I block beside
  // M^-1 K's largest entries, e.g. BEAMW's tiny warping masses) and its rcond would say singular.
  const Eigen::Index nq = n / 2;
  Eigen::MatrixXd x;
  bool solved = false;
  if (n % 2 == 0 && ss.A.topLeftCorner(nq, nq).isZero(0.0) && ss.A.topRightCorner(nq, nq).isIdentity(0.0)) {
    // Rows equilibrated first: M^-1 scales them by the inverse masses (BEAMW's warping masses are
    // ~1e-15), which alone would make the condition estimate say singular.
    const Eigen::VectorXd rowScale =
        ss.A.bottomLeftCorner(nq, nq).rowwise().lpNorm<Eigen::Infinity>().cwiseMax(1e-300).cwiseInverse();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(rowScale.asDiagonal() * ss.A.bottomLeftCorner(nq, nq));
    if (lu.rcond() > 1e-14) {
      x.resize(n, ni);
      x.bottomRows(nq) = ss.B.topRows(nq);
      x.topRows(nq) =
          lu.solve(rowScale.asDiagonal() * (ss.B.bottomRows(nq) - ss.A.bottomRightCorner(nq, nq) * ss.B.topRows(nq)));
      solved = true;
    }
  } else {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(ss.A);
    if (lu.rcond() > 1e-14) x = lu.solve(ss.B), solved = true;
  }
  if (!solved) return std::nullopt;
  return Eigen::MatrixXd(ss.D - ss.C * x);
}

Eigen::VectorXd bodeFrequencies(const StateSpace& ss, double fminHz, double fmaxHz) {
  const Eigen::Index m = ss.A.rows() / 2;
  double lo = 1.0, hi = 1e3;
  std::vector<double> resonances;  // undamped eigenfrequencies [rad/s] (all of a small model)
  if (m > 0) {
    // Undamped frequencies: w^2 the eigenvalues of -A21 = M0^-1 K (exact for small models; for
    // large ones the extremes by power iteration on -A21 and its inverse).
    const Eigen::MatrixXd K = -ss.A.bottomLeftCorner(m, m);
    std::vector<double> w2;
    if (m <= 300) {
      const Eigen::VectorXcd ev = K.eigenvalues();
      for (Eigen::Index i = 0; i < ev.size(); ++i)
        if (ev[i].real() > 0) w2.push_back(ev[i].real());
      for (const double v : w2) resonances.push_back(std::sqrt(v));
    } else {
      Eigen::VectorXd v = Eigen::VectorXd::Ones(m);
      double top = 0.0;
      for (int it = 0; it < 50; ++it) {
        Eigen::VectorXd y = K * v;
        top = y.norm() / v.norm();
        v = y / y.norm();
      }
      w2.push_back(top);
      const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K);
      v = Eigen::VectorXd::Ones(m);
      double inv = 0.0;
      for (int it = 0; it < 50; ++it) {
        Eigen::VectorXd y = lu.solve(v);
        inv = y.norm() / v.norm();
        v = y / y.norm();
      }
      if (std::isfinite(inv) && inv > 0) w2.push_back(1.0 / inv);
    }
    if (!w2.empty()) {
      const auto [a, b] = std::minmax_element(w2.begin(), w2.end());
      lo = std::sqrt(*a) / 10.0;
      hi = std::min(std::sqrt(*b) * 10.0, lo * 1e5);
      if (!(lo > 0.0) || !std::isfinite(hi) || hi <= lo) lo = 1.0, hi = 1e3;
    }
  }
  if (fminHz > 0.0 && fmaxHz > fminHz) lo = 2 * M_PI * fminHz, hi = 2 * M_PI * fmaxHz;
  const int n = 400;
  std::vector<double> w(n);
  for (int k = 0; k < n; ++k) w[k] = lo * std::pow(hi / lo, static_cast<double>(k) / (n - 1));
  // A lightly damped peak is narrower than the log grid's 2-3 % steps: points closing in on each
  // undamped eigenfrequency (the lowest 30 in range) draw it, and with damping the frequency itself
  // (undamped, H is infinite there: the closest points are 1e-4 off).
  std::sort(resonances.begin(), resonances.end());
  int refined = 0;
  for (const double wn : resonances) {
    if (!(wn > lo && wn < hi) || ++refined > 30) continue;
    for (const double s : {3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4})
      for (const double v : {wn * (1.0 - s), wn * (1.0 + s)})
        if (v > lo && v < hi) w.push_back(v);  // within the range asked for
    if (!undamped(ss)) w.push_back(wn);
  }
  std::sort(w.begin(), w.end());
  w.erase(std::unique(w.begin(), w.end()), w.end());
  return Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
}

}  // namespace flexmb::analysis
