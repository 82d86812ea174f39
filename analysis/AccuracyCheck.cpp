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

// Largest difference of two configurations: positions relative to the model size, angles and
// Euler parameters as they are.
double difference(const core::Model& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double L = model.lengthScale() > 0.0 ? model.lengthScale() : 1.0;
  double worst = 0.0;
  for (int i = 0; i < model.nx; ++i) {
    const core::Node& n = model.nodes[model.xOwnerNode[i]];
    const double d = std::abs(a[i] - b[i]);
    worst = std::max(worst, core::isTranslational(n.kind) ? d / L : d);
  }
  return worst;
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
  core::StateOutputs ref;
  double worstRate = 0.0;
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
    // BDF's orders 1-2 at a 100x tighter tolerance take 30x the run itself on the refined guidance;
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
    const double err = difference(model, w.xb, ref.x);
    a.windowError = std::max(a.windowError, err);
    worstRate = std::max(worstRate, err / (w.tb - w.ta));
    a.windowSeconds += w.tb - w.ta;
    ++a.windows;
  }
  a.estimate = worstRate * (tEnd - t0);
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
  return std::string(a.converged() ? "converged" : "NOT CONVERGED") + ": estimated error " + sig(a.estimate) +
         " (of the model size; angles in rad), limit " + sig(a.limit) + " = 10 RelTol; " + std::to_string(a.windows) +
         " windows of the run (" + sig(a.windowSeconds) + " s) integrated again at RelTol " +
         shortest(a.referenceRelTol) + " differ by up to " + sig(a.windowError);
}

}  // namespace flexmb::analysis
