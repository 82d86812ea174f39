#include "tools/bench/BenchRuns.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/AnchoredDynamics.hpp"
#include "analysis/Interrupt.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "solvers/Bdf.hpp"
#include "tools/bench/BenchSupport.hpp"

namespace flexmb::bench {

using Eigen::VectorXd;

analysis::SimulationOptions recipeOptions(const core::Model& model, analysis::Integrator integrator, double relTol,
                                          double absTol, const std::optional<Eigen::MatrixXd>& basis, int bdfMaxOrder,
                                          double rhoInf) {
  const core::AnalysisSettings& s = model.settings;
  analysis::SimulationOptions o;  // simulate's defaults, then every setting as the command line gives it
  o.integrator = integrator;
  if (bdfMaxOrder > 0) o.bdfMaxOrder = bdfMaxOrder;
  if (!std::isnan(rhoInf)) o.rhoInf = rhoInf;
  o.tEnd = s.tEnd;
  o.relTol = relTol;
  o.absTol = absTol;
  o.maxStep = s.hmax;
  o.intervals = s.outputIntervals;
  o.basis = basis;
  o.operators = nullptr;
  o.trackedOutputs = false;
  o.dynamics = core::DynamicsForm::Automatic;
  o.progress = false;
  o.keepStates = true;
  o.interrupt = nullptr;
  o.interruptSignal = nullptr;
  o.accuracyCheck = false;
  o.deferAccuracy = nullptr;
  o.reductionEstimate = false;
  return o;
}

namespace {

// Sets the flag after `seconds` (never for an infinite cap) unless stopped first.
class Watchdog {
 public:
  Watchdog(std::atomic<bool>& flag, double seconds) {
    if (!std::isfinite(seconds)) return;
    thread_ = std::thread([this, &flag, seconds] {
      std::unique_lock<std::mutex> lock(mutex_);
      if (!wake_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return done_; })) flag = true;
    });
  }
  ~Watchdog() { stop(); }
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

std::string capText(double capSeconds) { return "stopped at the " + fmt("%.0f", capSeconds) + " s cap"; }

// The output times simulate integrates to (the file's span and intervals).
std::vector<double> outputTimes(const analysis::SimulationOptions& o, const core::Model& model) {
  const double t0 = model.settings.t0, tEnd = *o.tEnd;
  const int n = *o.intervals;
  if (n <= 0) return {t0, tEnd};
  std::vector<double> t;
  for (int i = 0; i <= n; ++i) t.push_back(t0 + (tEnd - t0) * i / n);
  return t;
}

}  // namespace

CappedRun runCapped(const core::Model& model, analysis::SimulationOptions options, double capSeconds) {
  CappedRun r;
  std::atomic<bool> stop{false};
  options.interrupt = &stop;
  options.interruptSignal = nullptr;
  Watchdog watchdog(stop, capSeconds);  // started before the clock, joined after it
  const auto start = Clock::now();
  try {
    r.trajectory = analysis::simulate(model, options);
  } catch (const std::exception& e) {  // set-up or the initial kinematics: a failed run, not a crash
    r.trajectory.completed = false;
    r.trajectory.stopReason = e.what();
  }
  r.wall = since(start);
  watchdog.stop();
  const core::Trajectory& t = r.trajectory;
  r.capped = stop && !t.completed;
  if (r.capped) {
    // simulate words it as an interrupt: "<cause> after t = ...; results before it are kept".
    const std::string cause = analysis::interruptCause(nullptr);
    const std::string where = t.stopReason.rfind(cause, 0) == 0 ? t.stopReason.substr(cause.size()) : "";
    // " after t = 0.05600000000000001" -> " after t = 0.056"
    const std::string at = where.substr(0, where.find(';'));
    const size_t eq = at.find("t = ");
    r.reason = capText(capSeconds) +
               (eq == std::string::npos ? at : at.substr(0, eq + 4) + fmt("%.3g", std::atof(at.c_str() + eq + 4)));
  } else if (!t.completed) {
    r.reason = t.stopReason.empty() ? "integrator stopped" : t.stopReason;
  }
  return r;
}

OwnRun runCvodeDifferenceQuotients(const core::Model& model, double relTol, double absTol, int maxOrder,
                                   double capSeconds) {
  const analysis::SimulationOptions o =
      recipeOptions(model, analysis::Integrator::Bdf, relTol, absTol, std::nullopt, maxOrder);
  const std::vector<double> tspan = outputTimes(o, model);
  OwnRun r;
  r.relTol = relTol;
  r.t.reserve(tspan.size());
  r.y.reserve(tspan.size());
  const auto start = Clock::now();
  long calls = 0;
  bool capped = false;
  solvers::OdeResult res;
  try {
    core::Workspace workspace(model);
    core::EquationsOfMotion eom(workspace, std::nullopt, o.dynamics);
    eom.kinematics().setRelativeTolerance(analysis::kinematicTolerance(model.settings, relTol));
    analysis::AnchoredDynamics dynamics(eom, nullptr);  // no Jacobian: CVODE's difference quotients
    auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
      if ((++calls & 255) == 0 && since(start) > capSeconds) {
        capped = true;
        throw solvers::RhsAbort(capText(capSeconds));
      }
      try {
        dynamics.rhs(t, y, dy);
      } catch (const core::KinematicsError& e) {
        throw solvers::RhsError(e.what());  // a trial state: CVODE retries with a smaller step
      }
    };
    auto accept = [&](double t, const VectorXd& y) {
      try {
        dynamics.accept(t, y);
      } catch (const core::KinematicsError& e) {
        throw solvers::RhsError(e.what());
      }
    };
    auto observer = [&r](double t, const VectorXd& y) {
      r.t.push_back(t);
      r.y.push_back(y);
      return true;
    };
    solvers::BdfOptions bo;
    bo.relTol = relTol;
    bo.absTol = absTol;
    bo.maxStep = *o.maxStep;
    bo.maxOrder = o.bdfMaxOrder;
    const VectorXd y0 = eom.initialState();
    res = solvers::Bdf(bo).integrate(f, solvers::OdeJacobian{}, tspan, y0, observer, accept);
  } catch (const std::exception& e) {  // set-up or the initial kinematics: a failed run, not a crash
    r.wall = since(start);
    r.reason = e.what();
    return r;
  }
  r.wall = since(start);
  r.fevals = res.stats.nfevals;
  r.jacFevals = res.stats.njacfevals;
  r.njac = res.stats.njacevals;
  r.nsteps = res.stats.nsteps;
  r.nfailed = res.stats.nfailed;  // error-test plus corrector-convergence failures
  if (res.status != solvers::OdeStatus::Success) {
    r.reason = capped ? capText(capSeconds) + (r.t.empty() ? "" : " after t = " + fmt("%.6g", r.t.back()))
               : res.message.empty() ? "integrator stopped"
                                     : res.message;
  }
  // Our own count (every call) must agree with the integrator's.
  if (calls != r.fevals && r.reason.empty())
    std::fprintf(stderr, "warning: CVODE counted %ld evaluations, the right-hand side saw %ld\n", r.fevals, calls);
  return r;
}

core::Trajectory statesOf(const core::Model& model, const OwnRun& run, analysis::DeferredAccuracy& windows) {
  const double t0 = model.settings.t0, tEnd = model.settings.tEnd;
  core::EquationsOfMotion probe(model);
  probe.kinematics().setRelativeTolerance(analysis::kinematicTolerance(model.settings, run.relTol));
  analysis::AccuracyWindowRecorder recorder(t0, tEnd);
  core::Trajectory traj;
  for (size_t i = 0; i < run.t.size(); ++i) {
    core::StateOutputs out;
    probe.outputs(run.t[i], run.y[i], out);
    recorder.observe(run.t[i], run.y[i], out.x);
    traj.time.push_back(run.t[i]);
    traj.states.push_back(std::move(out));
  }
  windows = {run.reason.empty(), t0, tEnd, INFINITY, recorder.complete()};
  return traj;
}

}  // namespace flexmb::bench
