#include "tools/analysis/Simulation.hpp"

#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "core/ElementValidity.hpp"
#include "core/EquationsOfMotion.hpp"
#include "solvers/Ode45.hpp"

namespace flexmb::analysis {

namespace {

// The continuation of a stage: the state y = [q; qd] and the configuration x where it ended.
struct Continuation {
  Eigen::VectorXd y, x;
};

core::Trajectory simulateStage(const core::Model& model, const SimulationOptions& opt, const Continuation* from,
                               Continuation* end) {
  const auto& s = model.settings;
  const double t0 = s.t0, tEnd = opt.tEnd.value_or(s.tEnd);
  const int intervals = opt.intervals.value_or(s.outputIntervals);

  core::EquationsOfMotion eom(model, opt.basis);
  core::EquationsOfMotion probe(model, opt.basis);  // output quantities; keeps eom's warm start intact
  solvers::Ode45Options o;
  o.relTol = opt.relTol.value_or(s.relTol);
  o.absTol = Eigen::VectorXd::Constant(1, opt.absTol.value_or(s.absTol));
  o.maxStep = opt.maxStep.value_or(s.hmax);
  std::vector<double> tspan;
  if (intervals <= 0) {
    tspan = {t0, tEnd};
  } else {
    for (int i = 0; i <= intervals; ++i) tspan.push_back(t0 + (tEnd - t0) * i / intervals);
  }

  core::Trajectory traj;
  const auto start = std::chrono::steady_clock::now();
  auto lastPrint = start;
  bool printed = false;
  auto f = [&eom](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
    try {
      eom.rhs(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());
    }
  };
  auto observer = [&](double t, const Eigen::VectorXd& y) {
    if (end) end->y = y;
    if (opt.keepStates) {
      core::StateOutputs out;
      try {
        probe.outputs(t, y, out);
      } catch (const core::KinematicsError& e) {
        traj.completed = false;
        traj.stopReason = e.what();
        return false;
      }
      for (const Eigen::VectorXd* v : {&out.x, &out.xd, &out.xdd, &out.e, &out.ed, &out.edd, &out.sig})
        if (!v->allFinite()) {
          traj.completed = false;
          traj.stopReason = "non-finite output quantities at t = " + std::to_string(t) +
                            " (a load or reference expression undefined there?); results before it are kept";
          return false;
        }
      // A beam node turned past 90 degrees against its chord leaves Eq. 3b/3c (l0 sin theta): the
      // motion after it is not the model's. Checked here, at output times only, not in the RHS.
      if (const auto bad = core::firstInvalidElement(model, out.x)) {
        std::ostringstream msg;
        msg << "at t = " << t << ": " << bad->message
            << "; refine the mesh or limit the step size; results before it are kept";
        traj.completed = false;
        traj.stopReason = msg.str();
        return false;
      }
      if (end) end->x = out.x;
      traj.time.push_back(t);
      traj.states.push_back(std::move(out));
    }
    if (opt.progress) {
      const auto now = std::chrono::steady_clock::now();
      if (now - start > std::chrono::seconds(1) && now - lastPrint > std::chrono::milliseconds(250)) {
        std::fprintf(stderr, "\r  t = %.6g / %.6g s (%3.0f%%), %ld evaluations", t, tEnd,
                     100.0 * (t - t0) / (tEnd - t0), eom.evaluations());
        lastPrint = now;
        printed = true;
      }
    }
    return true;
  };
  // Kinematic residuals must stay far below the integration tolerance (else they are RHS noise).
  const double kinTol = std::min(s.kinematicTol, 1e-5 * o.relTol);
  eom.kinematics().setRelativeTolerance(kinTol);
  probe.kinematics().setRelativeTolerance(kinTol);
  solvers::Ode45 ode(o);
  if (from) {  // Newton starts from where the previous stage ended (a mechanism may have turned far)
    eom.kinematics().setConfiguration(from->x);
    probe.kinematics().setConfiguration(from->x);
  }
  const Eigen::VectorXd y0 = from ? from->y : eom.initialState();
  const solvers::OdeResult r = ode.integrate(f, tspan, y0, observer);
  if (printed) std::fprintf(stderr, "\n");
  traj.nsteps = r.stats.nsteps;
  traj.nfailed = r.stats.nfailed;
  traj.nfevals = r.stats.nfevals;
  if (r.status != solvers::OdeStatus::Success && traj.completed) {
    traj.completed = false;
    traj.stopReason = r.message;
  }
  return traj;
}

}  // namespace

core::Trajectory simulate(const core::Model& model, const SimulationOptions& opt) {
  return simulateStage(model, opt, nullptr, nullptr);
}

core::Trajectory simulateStages(const std::vector<const core::Model*>& stages, const SimulationOptions& opt) {
  if (stages.empty()) throw std::invalid_argument("simulateStages: no stage to run");
  if (stages.size() == 1) return simulate(*stages.front(), opt);
  if (opt.basis) throw std::invalid_argument("a reduction basis is only supported for a file with one analysis block");
  if (!opt.keepStates) throw std::invalid_argument("several analysis blocks need the states (keepStates)");
  core::Trajectory all;
  Continuation state;
  for (size_t k = 0; k < stages.size(); ++k) {
    const core::Model& m = *stages[k];
    if (m.numDofs() != stages.front()->numDofs() || m.nx != stages.front()->nx)
      throw std::invalid_argument("analysis blocks with different degrees of freedom cannot continue each other");
    SimulationOptions o = opt;
    if (k + 1 < stages.size()) o.tEnd.reset();
    Continuation end;
    core::Trajectory part = simulateStage(m, o, k ? &state : nullptr, &end);
    const size_t skip = (k > 0 && !part.time.empty() && !all.time.empty() && part.time.front() == all.time.back()) ? 1 : 0;
    for (size_t i = skip; i < part.time.size(); ++i) {
      all.time.push_back(part.time[i]);
      all.states.push_back(std::move(part.states[i]));
    }
    all.nsteps += part.nsteps;
    all.nfailed += part.nfailed;
    all.nfevals += part.nfevals;
    if (!part.completed || end.y.size() == 0) {
      all.completed = false;
      all.stopReason = part.stopReason.empty() ? "analysis block " + std::to_string(k + 1) + " produced no state"
                                               : part.stopReason;
      return all;
    }
    state = std::move(end);
  }
  return all;
}

}  // namespace flexmb::analysis
