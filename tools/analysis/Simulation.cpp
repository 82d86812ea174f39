#include "tools/analysis/Simulation.hpp"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "core/ElementValidity.hpp"
#include "core/EquationsOfMotion.hpp"
#include "solvers/Ode45.hpp"

namespace flexmb::analysis {

core::Trajectory simulate(const core::Model& model, const SimulationOptions& opt) {
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
  std::string userError;  // a failing USERSIG / USERINP: reported as the stop reason as it is
  const auto start = std::chrono::steady_clock::now();
  auto lastPrint = start;
  bool printed = false;
  auto f = [&eom, &userError](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
    userError.clear();  // only the evaluation that ended the run counts
    try {
      eom.rhs(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());
    } catch (const core::UserFunctionError& e) {  // USERSIG / USERINP (Octave/MATLAB gateway)
      userError = e.what();
      throw solvers::RhsError(e.what());
    }
  };
  auto observer = [&](double t, const Eigen::VectorXd& y) {
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
  const Eigen::VectorXd y0 = eom.initialState();
  const solvers::OdeResult r = ode.integrate(f, tspan, y0, observer);
  if (printed) std::fprintf(stderr, "\n");
  traj.nsteps = r.stats.nsteps;
  traj.nfailed = r.stats.nfailed;
  traj.nfevals = r.stats.nfevals;
  if (r.status != solvers::OdeStatus::Success && traj.completed) {
    traj.completed = false;
    traj.stopReason = r.message;
    // The user's function failed, not the step size: say that, without the integrator's advice.
    if (!userError.empty()) traj.stopReason = userError + "; results before it are kept";
  }
  return traj;
}

}  // namespace flexmb::analysis
