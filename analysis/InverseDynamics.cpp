#include "analysis/InverseDynamics.hpp"

#include <sstream>

#include "analysis/Interrupt.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/dynamics/ResultQuantities.hpp"
#include "core/kinematics/ElementValidity.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

bool isDrivenRigidMechanism(const core::Model& model) {
  if (model.numDofs() != 0) return false;
  auto moves = [](const core::Rheonomic& r) { return r.v != 0.0 || r.a != 0.0 || r.fx || r.fv || r.fa; };
  for (const auto& r : model.inputX)
    if (moves(r)) return true;
  for (const auto& r : model.inputE)
    if (moves(r)) return true;
  return false;
}

InverseDynamicsRun inverseDynamics(const core::Model& model, const InverseDynamicsOptions& options) {
  InverseDynamicsRun run;
  core::Trajectory& traj = run.trajectory;
  traj.integrator = "none (driven rigid mechanism: kinematics and inverse dynamics)";
  const double t0 = model.settings.t0, t1 = options.tEnd.value_or(model.settings.tEnd);
  const int n = std::max(1, options.intervals.value_or(model.settings.outputIntervals));
  // With no degrees of freedom the equations of motion reduce to the kinematics: outputs() solves
  // the positions, velocities (F_t) and accelerations (the rheonomic offset g) at t.
  core::Workspace workspace(model);  // one for both (each keeps its own warm start)
  core::EquationsOfMotion eom(workspace);
  core::ResultQuantities rq(workspace);
  const Eigen::VectorXd y;  // the state: empty
  const Eigen::VectorXd q;
  for (int k = 0; k <= n; ++k) {
    const double t = t0 + (t1 - t0) * k / n;
    if (stopRequested(options.interrupt)) {
      traj.completed = false;
      run.interrupted = true;
      traj.stopReason =
          interruptCause(options.interruptSignal) + " before t = " + text::shortest(t) + "; results before it are kept";
      return run;
    }
    core::StateOutputs out;
    Eigen::VectorXd sigma, fxt;
    try {
      eom.outputs(t, y, out);
      if (const auto bad = core::firstInvalidElement(model, out.x)) {
        std::ostringstream msg;
        msg << "at t = " << text::shortest(t) << ": " << bad->message << "; results before it are kept";
        traj.completed = false;
        traj.stopReason = msg.str();
        return run;
      }
      rq.setState(t, q);
      rq.forces(t, 0.0, out, Eigen::VectorXd(), sigma, fxt);
    } catch (const std::exception& e) {  // KinematicsError: no configuration (a dead point, the loop opens)
      traj.completed = false;
      traj.stopReason = "at t = " + text::shortest(t) + ": the kinematics have no solution (" + e.what() +
                        "); results before it are kept";
      return run;
    }
    if (!out.x.allFinite() || !out.xdd.allFinite() || !sigma.allFinite() || !fxt.allFinite()) {
      traj.completed = false;
      traj.stopReason = "non-finite results at t = " + text::shortest(t) +
                        " (an input expression undefined there?); results before it are kept";
      return run;
    }
    out.sig = sigma;
    traj.time.push_back(t);
    traj.states.push_back(std::move(out));
    run.fxt.push_back(std::move(fxt));
  }
  return run;
}

InverseDynamicsRun inverseDynamicsStages(const std::vector<const core::Model*>& stages,
                                         const InverseDynamicsOptions& options) {
  InverseDynamicsRun all;
  for (size_t k = 0; k < stages.size(); ++k) {
    InverseDynamicsOptions ok = options;
    if (k + 1 < stages.size()) ok.tEnd.reset(), ok.intervals.reset();
    InverseDynamicsRun part = inverseDynamics(*stages[k], ok);
    const auto& pt = part.trajectory;
    const size_t skip =
        !all.trajectory.time.empty() && !pt.time.empty() && pt.time.front() == all.trajectory.time.back();
    for (size_t i = skip; i < pt.time.size(); ++i) {
      all.trajectory.time.push_back(pt.time[i]);
      all.trajectory.states.push_back(pt.states[i]);
      all.fxt.push_back(part.fxt[i]);
    }
    all.trajectory.integrator = pt.integrator;
    all.interrupted = part.interrupted;
    if (!pt.completed) {
      all.trajectory.completed = false;
      all.trajectory.stopReason = pt.stopReason;
      break;
    }
  }
  return all;
}

}  // namespace flexmb::analysis
