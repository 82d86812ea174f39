#include "analysis/RunNotes.hpp"

#include <cmath>
#include <sstream>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/ReductionError.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
// "node 6 x by about 0.0013 of the model size" or "node 12 rotation by about 0.00026 rad": the
// larger of the two kinds' estimates.
std::string worstChange(const core::AccuracyEstimate& a) {
  if (a.angleEstimate > a.positionEstimate)
    return a.angleWhere + " by about " + text::significant(a.angleEstimate, 2) + " rad";
  return a.positionWhere + " by about " + text::significant(a.positionEstimate, 2) + " of the model size";
}
}  // namespace

std::vector<RunNote> runNotes(const core::Model& model, const SimulationOptions& opt, const core::Trajectory& traj,
                              double target) {
  using Kind = RunNote::Kind;
  std::vector<RunNote> notes;
  if (!traj.completed) notes.push_back({Kind::Stopped, "simulation stopped early: " + traj.stopReason, "", "", ""});
  if (traj.implicitFromStart) {
    const double span = opt.tEnd.value_or(model.settings.tEnd) - model.settings.t0;
    std::ostringstream sw;
    sw << "galpha from the start: the highest eigenfrequency at rest (|lambda| about " << traj.stiffLambda
       << " 1/s) would bound ode45 to at least " << std::round(span * traj.stiffLambda / 3.3) << " steps";
    notes.push_back({Kind::Note, sw.str(), "auto switch", sw.str(), ""});
  } else if (!std::isnan(traj.switchedAt)) {
    std::ostringstream sw;
    sw << "ode45 until t = " << traj.switchedAt << " s, where its step was bound by stability (|lambda| about "
       << traj.stiffLambda << " 1/s); galpha from there on";
    notes.push_back({Kind::Note, sw.str(), "auto switch", sw.str(), ""});
  }
  // A reduced run's accuracy check measures the integration error only (its windows run with the
  // same basis); the reduction error is estimated apart, and both are named for what they measure.
  const std::string integration = opt.basis ? "integration " : "";
  if (traj.completed && opt.accuracyCheck) {
    const std::string text = describeAccuracy(traj.accuracy);
    // A check that could not run says why; the run stands.
    notes.push_back({Kind::Result, integration + (traj.accuracy.checked ? "accuracy check: " : "accuracy ") + text,
                     integration + "accuracy", text, ""});
    if (!traj.accuracy.converged())
      notes.push_back(
          {Kind::Warning,
           "the result is not converged: a tighter tolerance changes " + worstChange(traj.accuracy) +
               " over the run (more than 10 RelTol): tighten the relative and absolute tolerances (RelTol, AbsTol) "
               "and compare",
           "", "", "reltol,abstol"});
  }
  if (opt.basis && (!traj.states.empty() || !traj.tracked.empty())) {
    const core::ReductionEstimate& re = traj.reduction;
    const std::string text = describeReductionError(re);
    notes.push_back({Kind::Result, "reduction error estimate: " + text, "reduction error estimate", text, ""});
    const double limit = !std::isnan(target) ? target : 10.0 * opt.relTol.value_or(model.settings.relTol);
    if (re.estimated && re.estimate > limit)
      notes.push_back({Kind::Warning,
                       "the reduction error estimate " + text::significant(re.estimate, 2) + " is larger than " +
                           (!std::isnan(target) ? "the target" : "10 RelTol") + " (" + text::significant(limit, 2) +
                           "): the basis leaves out deflections the full model has; a larger basis (one chosen "
                           "for a reduction error target) or the full model is more accurate",
                       "", "", "target"});
  }
  return notes;
}

}  // namespace flexmb::analysis
