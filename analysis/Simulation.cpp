#include "analysis/Simulation.hpp"

#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/AnchoredDynamics.hpp"
#include "analysis/Interrupt.hpp"
#include "analysis/StateJacobian.hpp"
#include "core/ElementValidity.hpp"
#include "core/EquationsOfMotion.hpp"
#include "solvers/Bdf.hpp"
#include "solvers/NumberText.hpp"
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

std::string integratorDescription(const SimulationOptions& o) {
  if (o.integrator == Integrator::Bdf)
    return "bdf (" + solvers::Bdf::library() + ": BDF orders 1-" + std::to_string(o.bdfMaxOrder) +
           ", Newton, dense LU, analytic Jacobian of Eq. 15)";
  return "ode45 (Dormand-Prince 5(4), MATLAB's step control)";
}

std::string formatStatistics(const core::Trajectory& run, Integrator integrator) {
  solvers::OdeStats st{run.nsteps, run.nfailed, run.nfevals};
  st.njacevals = run.njacevals;
  st.nrhsfailed = run.nrhsfailed;
  st.nlinsetups = run.nlinsetups;
  return integrator == Integrator::Bdf ? solvers::Bdf::formatStats(st) : solvers::Ode45::formatStats(st);
}

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

// One stage's integration settings: the file's, overridden by the options.
struct StageSettings {
  double t0 = 0.0, tEnd = 0.0, relTol = 0.0, absTol = 0.0, maxStep = 0.0, kinematicTol = 0.0;
  std::vector<double> tspan;  // [t0, tEnd] (Refine output) or the output grid
  bool bdf = false;

  StageSettings(const core::Model& model, const SimulationOptions& opt) {
    const auto& s = model.settings;
    t0 = s.t0;
    tEnd = opt.tEnd.value_or(s.tEnd);
    relTol = opt.relTol.value_or(s.relTol);
    absTol = opt.absTol.value_or(s.absTol);
    maxStep = opt.maxStep.value_or(s.hmax);
    kinematicTol = kinematicTolerance(s, relTol);
    bdf = opt.integrator == Integrator::Bdf;
    const int intervals = opt.intervals.value_or(s.outputIntervals);
    if (intervals <= 0) {
      tspan = {t0, tEnd};
    } else {
      for (int i = 0; i <= intervals; ++i) tspan.push_back(t0 + (tEnd - t0) * i / intervals);
    }
  }
};

// The progress line on stderr: from the first second on, at most every 250 ms, with the time
// reached, steps, evaluations and the time left; a run that will not finish in any reasonable time
// says so once (and how to stop it).
class ProgressLine {
 public:
  ProgressLine(double t0, double tEnd, bool exactSteps)
      : t0_(t0), tEnd_(tEnd), exactSteps_(exactSteps), start_(std::chrono::steady_clock::now()), last_(start_) {}
  ~ProgressLine() {
    if (printed_) std::fprintf(stderr, "\n");
  }
  // steps: accepted steps when exactSteps, else estimated from the evaluations (ode45: 6 per step).
  void update(double t, long evaluations, long steps) {
    const auto now = std::chrono::steady_clock::now();
    if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(250)) return;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double share = (t - t0_) / (tEnd_ - t0_);
    std::fprintf(stderr, "\r  t = %.6g / %.6g s (%3.0f%%), %s%ld steps, %ld evaluations (%.0f/s)", t, tEnd_,
                 100.0 * share, exactSteps_ ? "" : "~", exactSteps_ ? steps : evaluations / 6, evaluations,
                 evaluations / elapsed);
    const double left = share > 1e-6 ? elapsed * (1 - share) / share : 1e300;
    if (share > 1e-6) std::fprintf(stderr, ", about %.0f s left   ", left);
    if (!warnedSlow_ && elapsed > 20 && left > 50 * elapsed) {
      std::fprintf(stderr,
                   "\nflexmb: warning: at this rate the run needs about %.3g hours more: the step size is "
                   "very small (a stiff or reduced-badly model, or a singular configuration). Ctrl-C stops it and "
                   "writes the results so far.\n",
                   left / 3600);
      warnedSlow_ = true;
    }
    std::fflush(stderr);
    last_ = now;
    printed_ = true;
  }

 private:
  const double t0_, tEnd_;
  const bool exactSteps_;
  const std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_;
  bool printed_ = false, warnedSlow_ = false;
};

// One stage's integration: the evaluators (eom integrates; probe computes the output quantities
// and keeps eom's warm start intact; BDF adds the Jacobian and the anchored kinematics), the
// callables the integrators call, and the output states.
class StageRun {
 public:
  StageRun(const core::Model& model, const SimulationOptions& opt, const Continuation* from, Continuation* end)
      : model_(model),
        opt_(opt),
        set_(model, opt),
        end_(end),
        eom_(model, opt.basis, opt.dynamics),
        probe_(model, opt.basis, opt.dynamics),
        progress_(set_.t0, set_.tEnd, set_.bdf),
        tReached_(set_.t0) {
    // BDF: every evaluation starts the kinematics from the last accepted state (AnchoredDynamics).
    if (set_.bdf) {
      jacobian_.emplace(model, opt.basis);
      anchored_.emplace(eom_, &*jacobian_);
    }
    eom_.kinematics().setRelativeTolerance(set_.kinematicTol);
    probe_.kinematics().setRelativeTolerance(set_.kinematicTol);
    if (jacobian_) jacobian_->kinematics().setRelativeTolerance(set_.kinematicTol);
    if (from) {  // Newton starts from where the previous stage ended (a mechanism may have turned far)
      eom_.kinematics().setConfiguration(from->x);
      probe_.kinematics().setConfiguration(from->x);
      if (jacobian_) jacobian_->kinematics().setConfiguration(from->x);
    }
    y0_ = from ? from->y : eom_.initialState();
    if (opt.accuracyCheck && opt.keepStates) windows_.emplace(set_.t0, set_.tEnd);
  }

  core::Trajectory run(bool* interrupted) {
    auto f = [this](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) { rhs(t, y, dy); };
    auto observer = [this](double t, const Eigen::VectorXd& y) { return observe(t, y); };
    solvers::OdeResult r;
    if (set_.bdf) {
      solvers::BdfOptions o;
      o.relTol = set_.relTol;
      o.absTol = set_.absTol;
      o.maxStep = set_.maxStep;
      o.maxOrder = opt_.bdfMaxOrder;
      auto jac = [this](double t, const Eigen::VectorXd& y, const Eigen::VectorXd& fy, Eigen::Ref<Eigen::MatrixXd> J) {
        kinematicsAsRhsError([&] { anchored_->jacobian(t, y, fy, J); });
      };
      auto accept = [this](double t, const Eigen::VectorXd& y) {
        ++accepted_;
        kinematicsAsRhsError([&] { anchored_->accept(t, y); });
      };
      r = solvers::Bdf(o).integrate(f, jac, set_.tspan, y0_, observer, accept);
    } else {
      solvers::Ode45Options o;
      o.relTol = set_.relTol;
      o.absTol = Eigen::VectorXd::Constant(1, set_.absTol);
      o.maxStep = set_.maxStep;
      r = integrateOde45(eom_, o, f, set_.tspan, y0_, observer);
    }
    finish(r, interrupted);
    if (windows_ && traj_.completed)
      traj_.accuracy = checkAccuracy(model_, opt_, set_.t0, set_.tEnd, windows_->complete());
    return std::move(traj_);
  }

 private:
  template <class F>
  static void kinematicsAsRhsError(F&& f) {
    try {
      f();
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());  // a trial state: retried with a smaller step
    }
  }

  void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
    // Progress and Ctrl-C are looked at every 64 right-hand sides only, so the clock costs nothing
    // measurable in the RHS loop.
    if ((++calls_ & 63) == 0) {
      if (opt_.interrupt && opt_.interrupt->load(std::memory_order_relaxed)) {
        stoppedByUser_ = true;
        throw solvers::RhsAbort("interrupted");
      }
      if (opt_.progress) progress_.update(t, eom_.evaluations(), accepted_);
    }
    userError_.clear();  // only the evaluation that ended the run counts
    try {
      if (anchored_)
        anchored_->rhs(t, y, dy);
      else
        eom_.rhs(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());          // a trial state; retried with a smaller step
    } catch (const core::UserFunctionError& e) {  // USERSIG / USERINP (Octave/MATLAB gateway)
      userError_ = e.what();
      throw solvers::RhsAbort(e.what());
    }
  }

  // An output time: the output quantities from the probe, checked (finite, every element valid).
  bool observe(double t, const Eigen::VectorXd& y) {
    if (end_) end_->y = y;
    if (opt_.keepStates) {
      core::StateOutputs out;
      try {
        probe_.outputs(t, y, out);
      } catch (const core::KinematicsError& e) {
        return stop(e.what());
      } catch (const core::UserFunctionError& e) {
        return stop(e.what());
      }
      for (const Eigen::VectorXd* v : {&out.x, &out.xd, &out.xdd, &out.e, &out.ed, &out.edd, &out.sig})
        if (!v->allFinite())
          return stop("non-finite output quantities at t = " + std::to_string(t) +
                      " (a load or reference expression undefined there?); results before it are kept");
      // A beam node turned past 90 degrees against its chord leaves Eq. 3b/3c (l0 sin theta): the
      // motion after it is not the model's. Checked here, at output times only, not in the RHS.
      if (const auto bad = core::firstInvalidElement(model_, out.x)) {
        std::ostringstream msg;
        msg << "at t = " << t << ": " << bad->message
            << "; refine the mesh or limit the step size; results before it are kept";
        return stop(msg.str());
      }
      if (end_) end_->x = out.x;
      if (windows_) windows_->observe(t, y, out.x);
      traj_.time.push_back(t);
      traj_.states.push_back(std::move(out));
    }
    tReached_ = t;
    if (opt_.progress) progress_.update(t, eom_.evaluations(), accepted_);
    return true;
  }

  bool stop(const std::string& reason) {
    traj_.completed = false;
    traj_.stopReason = reason;
    return false;
  }

  // Statistics and the stop reason of the run.
  void finish(const solvers::OdeResult& r, bool* interrupted) {
    traj_.integrator = integratorName(opt_.integrator);
    traj_.nsteps = r.stats.nsteps;
    traj_.nfailed = r.stats.nfailed;
    traj_.nfevals = r.stats.nfevals;
    traj_.nrhsfailed = r.stats.nrhsfailed;
    traj_.njacevals = r.stats.njacevals;
    traj_.nlinsetups = r.stats.nlinsetups;
    if (stoppedByUser_) {
      traj_.completed = false;
      traj_.stopReason = interruptCause(opt_.interruptSignal) + " after t = " + solvers::shortest(tReached_) +
                         "; results before it are kept";
      if (interrupted) *interrupted = true;
    } else if (r.status != solvers::OdeStatus::Success && traj_.completed) {
      traj_.completed = false;
      traj_.stopReason = r.message;
      // The user's function failed, not the step size: say that, without the integrator's advice.
      if (!userError_.empty()) traj_.stopReason = userError_ + "; results before it are kept";
    }
  }

  const core::Model& model_;
  const SimulationOptions& opt_;
  const StageSettings set_;
  Continuation* end_;
  core::EquationsOfMotion eom_, probe_;
  std::optional<StateJacobian> jacobian_;
  std::optional<AnchoredDynamics> anchored_;
  ProgressLine progress_;
  std::optional<AccuracyWindowRecorder> windows_;  // the accuracy check's windows, when asked for
  Eigen::VectorXd y0_;
  core::Trajectory traj_;
  std::string userError_;          // a failing USERSIG / USERINP: reported as the stop reason as it is
  long calls_ = 0, accepted_ = 0;  // accepted: BDF steps (ode45's are estimated from the evaluations)
  bool stoppedByUser_ = false;
  double tReached_;
};

core::Trajectory simulateStage(const core::Model& model, const SimulationOptions& opt, const Continuation* from,
                               Continuation* end, bool* interrupted) {
  StageRun stage(model, opt, from, end);
  return stage.run(interrupted);
}

}  // namespace

core::Trajectory simulate(const core::Model& model, const SimulationOptions& opt, bool* interrupted) {
  return simulateStage(model, opt, nullptr, nullptr, interrupted);
}

core::Trajectory simulateFrom(const core::Model& model, const SimulationOptions& opt, const Eigen::VectorXd& y0,
                              const Eigen::VectorXd& x0, Eigen::VectorXd& yEnd) {
  const Continuation from{y0, x0};
  Continuation end;
  core::Trajectory t = simulateStage(model, opt, &from, &end, nullptr);
  yEnd = end.y;
  return t;
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
    // The accuracy of the chain: the least converged stage.
    const core::AccuracyEstimate& pa = part.accuracy;
    if (pa.checked && (!all.accuracy.checked || pa.estimate / pa.limit > all.accuracy.estimate / all.accuracy.limit))
      all.accuracy = pa;
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
