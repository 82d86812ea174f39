#include "analysis/AccuracyCheck.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/Simulation.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
constexpr double kWindowShare = 1.0 / 30.0;  // of the span, per window
constexpr double kCentres[] = {1.0 / 6.0, 0.5, 5.0 / 6.0};

// The largest difference of two configurations of each kind: positions relative to the model size,
// angles and Euler parameters as they are (rad), with the coordinate each comes from.
struct Difference {
  double position = 0.0, angle = 0.0;
  int positionAt = -1, angleAt = -1;  // coordinate index into x
};
Difference difference(const core::Model& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double L = model.lengthScale() > 0.0 ? model.lengthScale() : 1.0;
  Difference d;
  for (int i = 0; i < model.nx; ++i) {
    const double v = std::abs(a[i] - b[i]);
    if (core::isTranslational(model.nodes[model.xOwnerNode[i]].kind)) {
      if (v / L > d.position || d.positionAt < 0) d.position = v / L, d.positionAt = i;
    } else if (v > d.angle || d.angleAt < 0) {
      d.angle = v, d.angleAt = i;
    }
  }
  return d;
}

// "node 6 x", "node 12 rotation", "node 7 Euler parameter 2" for coordinate i of x.
std::string coordinateName(const core::Model& model, int i) {
  if (i < 0) return "";
  const core::Node& n = model.nodes[model.xOwnerNode[i]];
  const int c = i - n.firstCoord;
  static const char* axes[] = {"x", "y", "z"};
  const std::string what = core::isTranslational(n.kind)               ? std::string(axes[std::min(c, 2)])
                           : n.kind == core::NodeKind::EulerParameters ? "Euler parameter " + std::to_string(c)
                                                                       : std::string("rotation");
  return "node " + std::to_string(n.label) + " " + what;
}
}  // namespace

AccuracyWindowRecorder::AccuracyWindowRecorder(double t0, double tEnd) : length_(kWindowShare * (tEnd - t0)) {
  for (double c : kCentres) slots_.push_back({t0 + c * (tEnd - t0) - 0.5 * length_, {}, false, false});
}

void AccuracyWindowRecorder::observe(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& x) {
  for (Slot& s : slots_) {
    if (!s.started) {
      if (t >= s.start) {
        s.window.ta = t;
        s.window.ya = y;
        s.window.xa = x;
        s.started = true;
      }
    } else if (!s.ended && t >= s.window.ta + length_ * (1 - 1e-9)) {
      s.window.tb = t;
      s.window.yb = y;
      s.window.xb = x;
      s.ended = true;
    }
  }
}

bool AccuracyWindowRecorder::wantsAt(double t) const {
  for (const Slot& s : slots_)
    if ((!s.started && t >= s.start) || (s.started && !s.ended && t >= s.window.ta + length_ * (1 - 1e-9))) return true;
  return false;
}

std::vector<AccuracyWindow> AccuracyWindowRecorder::complete() const {
  std::vector<AccuracyWindow> w;
  for (const Slot& s : slots_)
    if (s.ended && s.window.tb > s.window.ta) w.push_back(s.window);
  // Overlapping windows (a grid coarser than a window): keep the first of each overlap.
  std::vector<AccuracyWindow> kept;
  for (const auto& x : w)
    if (kept.empty() || x.ta >= kept.back().tb) kept.push_back(x);
  return kept;
}

namespace {
core::AccuracyEstimate runWindows(const core::Model& model, const SimulationOptions& options, double t0, double tEnd,
                                  const std::vector<AccuracyWindow>& windows, double galphaFrom,
                                  core::AccuracyEstimate a) {
  const double absTol = options.absTol.value_or(model.settings.absTol);
  core::EquationsOfMotion probe(model, options.basis, options.dynamics);
  // The reference's configuration solved as tightly as the runs solve theirs: at the file's own
  // kinematic tolerance (the coarse pivot's ITERSTEP 5e-7) Newton took the run's configuration as
  // converged, and every window read "no difference" where the run was 0.028 of its motion off.
  probe.kinematics().setRelativeTolerance(kinematicTolerance(model.settings, a.referenceRelTol));
  core::StateOutputs ref;
  double positionRate = 0.0, angleRate = 0.0;
  bool moved = false, differed = false;
  for (const AccuracyWindow& w : windows) {
    // The window as a model of its own span (inputs and time functions keep their absolute time).
    core::Model span = model;
    span.settings.t0 = w.ta;
    span.settings.tEnd = w.tb;
    SimulationOptions o = options;
    o.relTol = a.referenceRelTol;
    o.absTol = absTol / kAccuracyReferenceFactor;
    o.tEnd.reset();
    o.intervals = 1;
    o.progress = false;
    o.keepStates = false;
    o.accuracyCheck = false;
    if (o.integrator == Integrator::Auto && w.ta >= galphaFrom) o.integrator = Integrator::GeneralizedAlpha;
    // BDF's orders 1-2 at a 100x tighter tolerance took 30x the run itself on the refined guidance;
    // galpha solves the same equations to that tolerance in a fraction of it.
    if (o.integrator == Integrator::Bdf) o.integrator = Integrator::GeneralizedAlpha;
    Eigen::VectorXd yEnd;
    const core::Trajectory r = simulateFrom(span, o, w.ya, w.xa, yEnd);
    if (!r.completed || yEnd.size() != w.yb.size()) {
      a.note = "the reference run of the window " + text::shortest(w.ta) + " to " + text::shortest(w.tb) +
               " s stopped: " + r.stopReason;
      return a;
    }
    // The reference's configuration, solved from the run's own one at tb (the model's initial
    // configuration may lie on the far side of a turn: Newton would not reach it from there).
    probe.kinematics().setConfiguration(w.xb);
    probe.outputs(w.tb, yEnd, ref);
    const Difference d = difference(model, w.xb, ref.x);
    const Difference travel = difference(model, w.xa, w.xb);
    moved = moved || travel.position > 0.0 || travel.angle > 0.0;
    differed = differed || d.position > 0.0 || d.angle > 0.0;
    a.windowError = std::max({a.windowError, d.position, d.angle});
    const double h = w.tb - w.ta;
    if (d.position / h > positionRate)
      positionRate = d.position / h, a.positionWhere = coordinateName(model, d.positionAt);
    if (d.angle / h > angleRate) angleRate = d.angle / h, a.angleWhere = coordinateName(model, d.angleAt);
    a.windowSeconds += h;
    ++a.windows;
  }
  // A reference at a tighter tolerance that lands on the run's own state to the last bit, where the
  // run moved, measured nothing (the coarse pivot refined under the saddle-point form: "0" where the
  // run was 0.028 of its motion off): no estimate rather than a zero.
  if (moved && !differed) {
    a.note = "the windows' reference runs at RelTol " + text::significant(a.referenceRelTol, 2) +
             " ended exactly on the run's own states (no difference at all, where the run moved): the "
             "check measured nothing";
    return a;
  }
  a.positionEstimate = positionRate * (tEnd - t0);
  a.angleEstimate = angleRate * (tEnd - t0);
  a.estimate = std::max(a.positionEstimate, a.angleEstimate);
  a.checked = true;
  return a;
}
}  // namespace

core::AccuracyEstimate checkAccuracy(const core::Model& model, const SimulationOptions& options, double t0, double tEnd,
                                     const std::vector<AccuracyWindow>& windows, double galphaFrom) {
  core::AccuracyEstimate a;
  const double relTol = options.relTol.value_or(model.settings.relTol);
  a.referenceRelTol = relTol / kAccuracyReferenceFactor;
  a.limit = std::max(10.0 * relTol, 1e-6);
  if (windows.empty()) {
    a.note = "no window fitted between the output times";
    return a;
  }
  // The check is a step after a completed run: whatever goes wrong in it (a kinematic Newton
  // iteration, a user function) is its own failure, said as such, never the run's.
  try {
    return runWindows(model, options, t0, tEnd, windows, galphaFrom, a);
  } catch (const std::exception& e) {
    a.checked = false;
    a.note = std::string("the check failed: ") + e.what();
    return a;
  }
}

std::string describeAccuracy(const core::AccuracyEstimate& a) {
  using text::shortest;
  auto sig = [](double v) { return text::significant(v, 2); };
  if (!a.checked) return "not checked: " + (a.note.empty() ? std::string("no reason recorded") : a.note);
  // Each kind on its own scale, and where the larger comes from.
  std::string kinds;
  if (!a.positionWhere.empty())
    kinds += "positions " + sig(a.positionEstimate) + " of the model size (" + a.positionWhere + ")";
  if (!a.angleWhere.empty())
    kinds +=
        (kinds.empty() ? "" : ", ") + std::string("angles ") + sig(a.angleEstimate) + " rad (" + a.angleWhere + ")";
  return std::string(a.converged() ? "converged" : "NOT CONVERGED") + ": estimated error " + sig(a.estimate) + " (" +
         (kinds.empty() ? std::string("no difference") : kinds) + "), limit " + sig(a.limit) +
         " = 10 RelTol for each; " + std::to_string(a.windows) + " windows of the run (" + sig(a.windowSeconds) +
         " s) integrated again at RelTol " + sig(a.referenceRelTol) + " differ by up to " + sig(a.windowError);
}

}  // namespace flexmb::analysis
