#include "analysis/Sweep.hpp"

#include "io/formats/OriginalResults.hpp"
#include "io/formats/ResultWriter.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "analysis/Interrupt.hpp"
#include "analysis/Modes.hpp"
#include "analysis/StaticDesign.hpp"
#include "core/kinematics/ElementValidity.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/linearization/PrescribedEquilibrium.hpp"
#include "solvers/EigenSolver.hpp"

namespace flexmb::analysis {

namespace {

// The coordinate a sweep prescribes (a node's component, or an orientation node's rotation about a
// global axis) and its name; throws std::invalid_argument for one that does not exist or cannot move.
core::PrescribedQuantity sweptQuantity(const core::Model& model, const SweepOptions& o, std::string& coord) {
  auto it = model.nodeByLabel.find(o.node);
  if (it == model.nodeByLabel.end())
    throw std::invalid_argument("sweep: node " + std::to_string(o.node) + " does not exist");
  const core::Node& node = model.nodes[it->second];
  // A spatial orientation node: components 1..3 are its rotation about the global axes (an Euler
  // parameter itself is no quantity to sweep).
  const bool rotation = node.kind == core::NodeKind::EulerParameters;
  const int components = rotation ? 3 : node.dim();
  if (o.component < 1 || o.component > components)
    throw std::invalid_argument(
        "sweep: node " + std::to_string(o.node) + " has no component " + std::to_string(o.component) +
        (rotation ? " (an orientation node: 1, 2, 3 = its rotation about global x, y, z)" : ""));
  core::PrescribedQuantity pq;
  pq.coord = node.firstCoord + (rotation ? 0 : o.component - 1);
  pq.axis = rotation ? o.component : 0;
  if (rotation) pq.lambda0 = model.x0.segment<4>(pq.coord);
  const int k = pq.coord;
  bool movable = false;
  for (int j = 0; j < pq.width(); ++j)
    movable = movable || (model.xRole[k + j] != core::Role::Fixed && model.xRole[k + j] != core::Role::Input);
  if (!movable)
    throw std::invalid_argument("sweep: " + model.coordName(k) + " is " + core::roleName(model.xRole[k]) +
                                ", it cannot be prescribed");
  static const char* const kAxes[] = {"x", "y", "z"};
  coord = rotation
              ? "the rotation of node " + std::to_string(o.node) + " about global " + kAxes[o.component - 1] + " (rad)"
              : model.coordName(k);
  return pq;
}

// Orders the modes of `pt` (unit columns) as the previous point's they continue (MAC tracking).
void followModes(const Eigen::MatrixXd& previousModes, Eigen::MatrixXd& modesQ, SweepPoint& pt) {
  const std::vector<int> perm = solvers::trackModes(previousModes, modesQ);
  Eigen::MatrixXd sorted(modesQ.rows(), modesQ.cols());
  Eigen::VectorXd w(pt.omega.size());
  for (size_t j = 0; j < perm.size(); ++j) {  // current mode j continues previous mode perm[j]
    sorted.col(perm[j]) = modesQ.col(j);
    w[perm[j]] = pt.omega[j];
  }
  modesQ = sorted;
  pt.omega = w;
}

// Why the sweep stops where no sub-step finds an equilibrium. "Turns" only where the path does: the
// bordered tangent singular (a limit point, where the coordinate cannot go further, or a branch
// point). Else Newton itself failed on a regular path.
std::string pathEnds(const std::string& coord, double v, const std::string& err, double rcond, double h) {
  std::ostringstream s;
  s << "with the prescribed coordinate " << coord << " at " << v << ": " << err;
  if (rcond < 1e-13)
    s << "; the equilibrium path turns or branches here (its tangent is singular: condition estimate " << rcond
      << "), so the sweep stops";
  else
    s << "; the path is regular here (tangent condition estimate " << rcond << ") but no equilibrium was found "
      << "even in sub-steps of " << h << ", so the sweep stops (a coordinate the mechanism cannot follow "
      << "by itself? prescribe one it can)";
  return s.str();
}

// The equilibrium at prescribed value v (load P on it, along pq's gradient g) with its modes, in the
// order of the previous point's (`previousModes`, unit columns over q; updated), and its stresses
// (atRest's sigma, the holding load in its nodal forces).
SweepPoint sweepPoint(core::Linearization& lin, double v, double P, const Eigen::VectorXd& eta, const Frequencies& fr,
                      Eigen::MatrixXd& previousModes, const Eigen::VectorXd& sigma, const core::PrescribedQuantity& pq,
                      const Eigen::Vector4d& g) {
  SweepPoint pt;
  pt.value = v;
  pt.load = P;
  pt.eta = eta;
  lin.dofs(eta, pt.q);
  pt.x = lin.kinematics().x();
  pt.e = lin.kinematics().e();
  pt.sigma = sigma;
  pt.holding = Eigen::VectorXd::Zero(lin.model().nx);
  for (int j = 0; j < pq.width(); ++j) pt.holding[pq.coord + j] = P * g[j];
  Eigen::MatrixXd modesQ = lin.basis() ? Eigen::MatrixXd(*lin.basis() * fr.modes) : fr.modes;
  pt.modesAscending = modesQ;
  for (Eigen::Index j = 0; j < modesQ.cols(); ++j) modesQ.col(j).normalize();
  pt.omega = fr.omega;
  pt.omegaSorted = fr.omega;
  if (previousModes.size() && previousModes.cols() == modesQ.cols()) followModes(previousModes, modesQ, pt);
  pt.modes = modesQ;
  previousModes = modesQ;
  return pt;
}

}  // namespace

SweepResult sweep(const core::Model& model, const SweepOptions& o) {
  SweepResult res;
  std::string coord;
  const core::PrescribedQuantity pq = sweptQuantity(model, o, coord);
  const int k = pq.coord;
  if (o.steps < 1) throw std::invalid_argument("sweep: steps must be at least 1");

  std::optional<solvers::Partition> held;
  if (o.heldCoordinates) {
    if (o.basis) throw std::invalid_argument("sweep: held coordinates apply to the full model only");
    held = solvers::Partition::make(model.numDofs(), *o.heldCoordinates);
  }
  core::Linearization lin(model, o.basis);
  // As statics: positions to 1e-12 of the model size. At the default 1e-10 a Newton correction of a
  // stiff model's deformations (1e-11) left the positions where they were, and the bordered Newton
  // stalled on a smooth path (the cross-spring pivot swept through a leaf end).
  lin.kinematics().setRelativeTolerance(std::min(model.settings.kinematicTol, 1e-12));
  Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size());
  double P = 0.0;
  const double start = pq.value(model.x0);
  res.prescribed = coord;
  std::vector<double> values;
  for (int i = 0; i < o.steps; ++i)
    values.push_back(o.steps == 1 ? o.from : o.from + (o.to - o.from) * i / (o.steps - 1));
  // Continuation stays on the branch it starts on whatever the number of sweep points: the
  // prescribed coordinate moves in sub-steps of at most 2.5% of the model size between sweep
  // points, each started from a secant predictor through the two previous equilibria, and a
  // sub-step is accepted only when Newton's correction of the prediction is small against the
  // predicted change (else Newton jumped to another equilibrium: the sub-step is halved). When
  // even a tiny sub-step fails, the sweep stops, saying "turns" only where the tangent is singular.
  const double L = model.lengthScale() > 0.0 ? model.lengthScale() : 1.0;
  const double maxIncrement = 0.025 * L, minIncrement = maxIncrement / 4096;
  double h = maxIncrement / 8;
  double current = start;
  Eigen::VectorXd etaPrev;
  double Pprev = 0.0, valuePrev = start;
  bool havePrev = false;
  double rcond = 1.0;  // of the bordered tangent where Newton stopped (near 0: a limit or branch point)
  auto solveAt = [&](double v) -> std::string {
    try {
      return core::prescribedEquilibrium(lin, o.t, pq, v, eta, P, &rcond);
    } catch (const core::KinematicsError& e) {  // its time is the load time, not the path
      std::ostringstream s;
      s << "the kinematics did not converge (" << e.iterations() << " iterations, residual " << e.residual() << ")";
      return s.str();
    } catch (const std::exception& e) {
      return e.what();
    }
  };
  bool stopped = false;  // the interrupt flag was seen
  auto advance = [&](double target) -> std::string {
    bool first = true;
    while (first || current != target) {
      first = false;
      if (stopRequested(o.interrupt)) {
        stopped = true;
        return interruptCause(o.interruptSignal);
      }
      const double gap = target - current;
      const bool canPredict = havePrev && current != valuePrev && (gap > 0) == (current > valuePrev);
      if (!canPredict) h = std::min(h, maxIncrement / 8);  // no secant (start, a new direction): small
      const double v = std::abs(gap) <= h * (1 + 1e-9) ? target : current + (gap > 0 ? h : -h);
      const Eigen::VectorXd etaHere = eta;
      const double PHere = P;
      const Eigen::VectorXd xHere = lin.kinematics().x();
      const double r = havePrev && current != valuePrev ? (v - current) / (current - valuePrev) : 0.0;
      const bool predict = canPredict && r > 0.0 && r <= 4.0;
      const Eigen::VectorXd etaPred = predict ? Eigen::VectorXd(etaHere + r * (etaHere - etaPrev)) : etaHere;
      eta = etaPred;
      P = predict ? PHere + r * (PHere - Pprev) : PHere;
      std::string err = solveAt(v);
      if (err.empty() && predict) {
        const double change = std::max((etaPred - etaHere).lpNorm<Eigen::Infinity>(), 1e-9 * L);
        const double correction = (eta - etaPred).lpNorm<Eigen::Infinity>();
        if (correction > 0.3 * change) {
          std::ostringstream s;
          s << "Newton left the equilibrium path (correction " << correction << " against a predicted change of "
            << change << ")";
          err = s.str();
        }
      }
      if (!err.empty()) {
        eta = etaHere;
        P = PHere;
        if (xHere.size() == model.nx) lin.kinematics().setConfiguration(xHere);
        if (h <= minIncrement * (1 + 1e-9) || v == current) {
          return pathEnds(coord, v, err, rcond, h);
        }
        h = std::max(0.5 * h, minIncrement);
        continue;
      }
      etaPrev = etaHere;
      Pprev = PHere;
      valuePrev = current;
      havePrev = v != current;
      current = v;
      h = std::min(2 * h, maxIncrement);
    }
    return "";
  };
  {
    const std::string err = advance(values[0]);
    if (!err.empty()) {
      res.completed = false;
      res.interrupted = stopped;
      res.stopReason = stopped ? err + " approaching the sweep start"
                               : "approaching the sweep start " + std::to_string(values[0]) + ": " + err;
      return res;
    }
  }
  Eigen::MatrixXd previousModes;
  core::LinearizedSystem sys;
  Eigen::VectorXd f;
  for (double v : values) {
    const std::string err = advance(v);
    if (!err.empty()) {
      res.completed = false;
      res.interrupted = stopped;
      res.stopReason = stopped ? err + " after " + std::to_string(res.points.size()) + " of " +
                                     std::to_string(o.steps) + " configurations; the points before it are kept"
                               : err;
      return res;
    }
    if (o.onPoint) o.onPoint(static_cast<int>(res.points.size()), o.steps);
    try {
      lin.appliedForces(o.t, 0.0, f);
      const Eigen::Vector4d g = pq.gradient(lin.kinematics().x());
      for (int j = 0; j < pq.width(); ++j) f[k + j] += P * g[j];
      lin.atRest(o.t, eta, f, sys, true);
      // As in staticAnalysis: a converged but folded equilibrium (a beam node past 90 degrees
      // against its chord, outside Eq. 3b/3c) ends the sweep; the points before it are kept.
      if (const auto bad = core::firstInvalidElement(model, lin.kinematics().x())) {
        std::ostringstream s;
        s << "with the prescribed coordinate " << coord << " at " << v << ": " << bad->message << "; refine the mesh";
        res.completed = false;
        res.stopReason = s.str();
        return res;
      }
      const Frequencies fr = held ? subproblemModes(*held, sys, o.nev) : naturalFrequencies(lin, sys, o.nev);
      res.points.push_back(sweepPoint(lin, v, P, eta, fr, previousModes, sys.sigma, pq, g));
    } catch (const std::exception& e) {
      std::ostringstream s;
      s << "with the prescribed coordinate " << coord << " at " << v << ": " << e.what();
      res.completed = false;
      res.stopReason = s.str();
      return res;
    }
  }
  return res;
}

io::CsvTable sweepTable(const core::Model& model, const SweepResult& r) {
  Eigen::Index nev = 0;
  for (const auto& p : r.points) nev = std::max({nev, p.omegaSorted.size(), p.omega.size()});
  io::CsvTable t;
  t.columns = {"value", "load"};
  for (Eigen::Index i = 0; i < nev; ++i) t.columns.push_back(io::numberedColumn("f", i + 1, "_Hz"));
  for (Eigen::Index i = 0; i < nev; ++i) t.columns.push_back(io::numberedColumn("tracked", i + 1, "_Hz"));
  for (const auto& name : io::coordinateColumnNames(model)) t.columns.push_back(name);
  const bool stresses = !stressedElements(model).empty();
  if (stresses) t.columns.insert(t.columns.end(), {"max_stress", "max_stress_element"});
  for (const auto& reaction : supportReactions(model, StaticStep())) t.columns.push_back(reaction.first);
  const double empty = std::numeric_limits<double>::quiet_NaN();
  for (const auto& p : r.points) {
    std::vector<double> row{p.value, p.load};
    for (Eigen::Index i = 0; i < nev; ++i)
      row.push_back(i < p.omegaSorted.size() ? p.omegaSorted[i] / (2 * M_PI) : empty);
    for (Eigen::Index i = 0; i < nev; ++i) row.push_back(i < p.omega.size() ? p.omega[i] / (2 * M_PI) : empty);
    for (Eigen::Index i = 0; i < p.x.size(); ++i) row.push_back(p.x[i]);
    for (Eigen::Index i = p.x.size(); i < model.nx; ++i) row.push_back(empty);
    // The point as a static step at load factor 0 (the sweep holds the file's initial loads).
    StaticStep st;
    st.loadFactor = 0.0, st.x = p.x, st.e = p.e, st.sigma = p.sigma;
    if (stresses) {
      const ElementStress top = p.sigma.size() == model.ne ? largestStress(model, st) : ElementStress{-1, empty};
      row.push_back(top.vonMises);
      row.push_back(top.element >= 0 ? model.elements[top.element].label : empty);
    }
    for (const auto& reaction : supportReactions(model, st, p.holding)) row.push_back(reaction.second);
    t.rows.push_back(std::move(row));
  }
  return io::originalColumns(model, std::move(t));  // a refined model's: at the original nodes
}

}  // namespace flexmb::analysis
