#include "analysis/Simulation.hpp"

#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "analysis/AnchoredDynamics.hpp"
#include "analysis/StateJacobian.hpp"
#include "core/ElementValidity.hpp"
#include "core/EquationsOfMotion.hpp"
#include "solvers/Bdf.hpp"
#include "solvers/Ode45.hpp"

namespace flexmb::analysis {

double kinematicTolerance(const core::AnalysisSettings& s, double relTol) {
  // 1e-10 at most: a stiff full model integrates far more accurately than RelTol says (its step is
  // set by stability), and its energy drifts with the kinematic residual (measured on the released
  // guidance at RelTol 1e-3: 3e-7 over 2 s at 1e-8, below 1e-8 at 1e-10).
  const double derived = std::min(1e-10, 1e-5 * relTol);
  return s.kinematicTolGiven ? std::min(s.kinematicTol, derived) : derived;
}

solvers::OdeResult integrateOde45(core::EquationsOfMotion& eom, const solvers::Ode45Options& options,
                                  const solvers::OdeRhs& f, const std::vector<double>& tspan, const Eigen::VectorXd& y0,
                                  const solvers::OdeObserver& observer) {
  core::GeometricTransferFunctions& kinematics = eom.kinematics();
  return solvers::Ode45(options).integrate(
      f, tspan, y0, observer, [&](double, const Eigen::VectorXd&) { kinematics.setAnchor(); },
      [&](double, const Eigen::VectorXd&) { kinematics.restartFromAnchor(); });
}

const char* integratorName(Integrator i) { return i == Integrator::Bdf ? "bdf" : "ode45"; }

std::optional<Integrator> parseIntegrator(const std::string& name) {
  if (name == "ode45") return Integrator::Ode45;
  if (name == "bdf") return Integrator::Bdf;
  return std::nullopt;
}

namespace {

// The continuation of a stage: the state y = [q; qd] and the configuration x where it ended.
struct Continuation {
  Eigen::VectorXd y, x;
};

core::Trajectory simulateStage(const core::Model& model, const SimulationOptions& opt, const Continuation* from,
                               Continuation* end, bool* interrupted) {
  const auto& s = model.settings;
  const double t0 = s.t0, tEnd = opt.tEnd.value_or(s.tEnd);
  const int intervals = opt.intervals.value_or(s.outputIntervals);

  core::EquationsOfMotion eom(model, opt.basis, opt.dynamics);
  // Output quantities; keeps eom's warm start intact.
  core::EquationsOfMotion probe(model, opt.basis, opt.dynamics);
  const bool bdf = opt.integrator == Integrator::Bdf;
  const double relTol = opt.relTol.value_or(s.relTol), absTol = opt.absTol.value_or(s.absTol);
  const double maxStep = opt.maxStep.value_or(s.hmax);
  std::vector<double> tspan;
  if (intervals <= 0) {
    tspan = {t0, tEnd};
  } else {
    for (int i = 0; i <= intervals; ++i) tspan.push_back(t0 + (tEnd - t0) * i / intervals);
  }

  core::Trajectory traj;
  std::string userError;  // a failing USERSIG / USERINP: reported as the stop reason as it is
  const auto start = std::chrono::steady_clock::now();
  auto lastPrint = start;
  bool printed = false;
  // Progress between output times and Ctrl-C: looked at every 64 right-hand sides only, so the
  // clock costs nothing measurable in the RHS loop.
  long calls = 0, accepted = 0;  // accepted: BDF steps (ode45's are estimated from the evaluations)
  bool stoppedByUser = false, warnedSlow = false;
  double tReached = t0;
  auto printProgress = [&](double t) {
    const auto now = std::chrono::steady_clock::now();
    if (now - start < std::chrono::seconds(1) || now - lastPrint < std::chrono::milliseconds(250)) return;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double share = (t - t0) / (tEnd - t0);
    std::fprintf(stderr, "\r  t = %.6g / %.6g s (%3.0f%%), %s%ld steps, %ld evaluations (%.0f/s)", t, tEnd,
                 100.0 * share, bdf ? "" : "~", bdf ? accepted : eom.evaluations() / 6, eom.evaluations(),
                 eom.evaluations() / elapsed);
    const double left = share > 1e-6 ? elapsed * (1 - share) / share : 1e300;
    if (share > 1e-6) std::fprintf(stderr, ", about %.0f s left   ", left);
    // A run that will not finish in any reasonable time says so once (and how to stop it).
    if (!warnedSlow && elapsed > 20 && left > 50 * elapsed) {
      std::fprintf(stderr,
                   "\nflexmb: warning: at this rate the run needs about %.3g hours more: the step size is "
                   "very small (a stiff or reduced-badly model, or a singular configuration). Ctrl-C stops it and "
                   "writes the results so far.\n",
                   left / 3600);
      warnedSlow = true;
    }
    std::fflush(stderr);
    lastPrint = now;
    printed = true;
  };
  // BDF: every evaluation starts the kinematics from the last accepted state (AnchoredDynamics).
  std::optional<StateJacobian> jacobian;
  std::optional<AnchoredDynamics> anchored;
  if (bdf) {
    jacobian.emplace(model, opt.basis);
    anchored.emplace(eom, &*jacobian);
  }
  auto f = [&](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
    if ((++calls & 63) == 0) {
      if (opt.interrupt && opt.interrupt->load(std::memory_order_relaxed)) {
        stoppedByUser = true;
        throw solvers::RhsAbort("interrupted");
      }
      if (opt.progress) printProgress(t);
    }
    userError.clear();  // only the evaluation that ended the run counts
    try {
      if (anchored)
        anchored->rhs(t, y, dy);
      else
        eom.rhs(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());          // BDF: a trial state; retried with a smaller step
    } catch (const core::UserFunctionError& e) {  // USERSIG / USERINP (Octave/MATLAB gateway)
      userError = e.what();
      throw solvers::RhsAbort(e.what());
    }
  };
  auto jac = [&](double t, const Eigen::VectorXd& y, const Eigen::VectorXd& fy, Eigen::Ref<Eigen::MatrixXd> J) {
    try {
      anchored->jacobian(t, y, fy, J);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());
    }
  };
  auto acceptStep = [&](double t, const Eigen::VectorXd& y) {
    ++accepted;
    try {
      anchored->accept(t, y);
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
      } catch (const core::UserFunctionError& e) {
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
    tReached = t;
    if (opt.progress) printProgress(t);
    return true;
  };
  const double kinTol = kinematicTolerance(s, relTol);
  eom.kinematics().setRelativeTolerance(kinTol);
  probe.kinematics().setRelativeTolerance(kinTol);
  if (jacobian) jacobian->kinematics().setRelativeTolerance(kinTol);
  if (from) {  // Newton starts from where the previous stage ended (a mechanism may have turned far)
    eom.kinematics().setConfiguration(from->x);
    probe.kinematics().setConfiguration(from->x);
    if (jacobian) jacobian->kinematics().setConfiguration(from->x);
  }
  const Eigen::VectorXd y0 = from ? from->y : eom.initialState();
  solvers::OdeResult r;
  if (bdf) {
    solvers::BdfOptions o;
    o.relTol = relTol;
    o.absTol = absTol;
    o.maxStep = maxStep;
    o.maxOrder = opt.bdfMaxOrder;
    r = solvers::Bdf(o).integrate(f, jac, tspan, y0, observer, acceptStep);
  } else {
    solvers::Ode45Options o;
    o.relTol = relTol;
    o.absTol = Eigen::VectorXd::Constant(1, absTol);
    o.maxStep = maxStep;
    r = integrateOde45(eom, o, f, tspan, y0, observer);
  }
  if (printed) std::fprintf(stderr, "\n");
  traj.integrator = integratorName(opt.integrator);
  traj.nsteps = r.stats.nsteps;
  traj.nfailed = r.stats.nfailed;
  traj.nfevals = r.stats.nfevals;
  traj.nrhsfailed = r.stats.nrhsfailed;
  traj.njacevals = r.stats.njacevals;
  traj.nlinsetups = r.stats.nlinsetups;
  if (stoppedByUser) {
    traj.completed = false;
    traj.stopReason = "interrupted (Ctrl-C) after t = " + std::to_string(tReached) + "; results before it are kept";
    if (interrupted) *interrupted = true;
  } else if (r.status != solvers::OdeStatus::Success && traj.completed) {
    traj.completed = false;
    traj.stopReason = r.message;
    // The user's function failed, not the step size: say that, without the integrator's advice.
    if (!userError.empty()) traj.stopReason = userError + "; results before it are kept";
  }
  return traj;
}

}  // namespace

core::Trajectory simulate(const core::Model& model, const SimulationOptions& opt, bool* interrupted) {
  return simulateStage(model, opt, nullptr, nullptr, interrupted);
}

core::Trajectory simulateStages(const std::vector<const core::Model*>& stages, const SimulationOptions& opt,
                                bool* interrupted) {
  if (stages.empty()) throw std::invalid_argument("simulateStages: no stage to run");
  if (stages.size() == 1) return simulate(*stages.front(), opt, interrupted);
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
    core::Trajectory part = simulateStage(m, o, k ? &state : nullptr, &end, interrupted);
    const size_t skip =
        (k > 0 && !part.time.empty() && !all.time.empty() && part.time.front() == all.time.back()) ? 1 : 0;
    for (size_t i = skip; i < part.time.size(); ++i) {
      all.time.push_back(part.time[i]);
      all.states.push_back(std::move(part.states[i]));
    }
    all.integrator = part.integrator;
    all.nsteps += part.nsteps;
    all.nfailed += part.nfailed;
    all.nfevals += part.nfevals;
    all.nrhsfailed += part.nrhsfailed;
    all.njacevals += part.njacevals;
    all.nlinsetups += part.nlinsetups;
    if (!part.completed || end.y.size() == 0) {
      all.completed = false;
      all.stopReason =
          part.stopReason.empty() ? "analysis block " + std::to_string(k + 1) + " produced no state" : part.stopReason;
      return all;
    }
    state = std::move(end);
  }
  return all;
}

}  // namespace flexmb::analysis
