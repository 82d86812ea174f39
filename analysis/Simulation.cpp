#include "analysis/Simulation.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/AnchoredDynamics.hpp"
#include "analysis/Interrupt.hpp"
#include "analysis/LapClock.hpp"
#include "analysis/Modes.hpp"
#include "analysis/OperatorDynamics.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/SparseIteration.hpp"
#include "analysis/StateJacobian.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/kinematics/ElementValidity.hpp"
#include "solvers/Bdf.hpp"
#include "solvers/GeneralizedAlpha.hpp"
#include "solvers/Ode45.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
// A default ode45 run "stability-bound for long": this many steps at the stability limit (at
// least 6,000 evaluations spent where an implicit integrator would take a few large steps).
constexpr long kStiffHintSteps = 1000;
}  // namespace

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

const char* integratorName(Integrator i) {
  switch (i) {
    case Integrator::Bdf:
      return "bdf";
    case Integrator::Auto:
      return "auto";
    case Integrator::GeneralizedAlpha:
      return "galpha";
    case Integrator::Ode45:
      break;
  }
  return "ode45";
}

namespace {
std::string alphaDescription(const SimulationOptions& o) {
  return "galpha (generalized-alpha, rho_inf " + text::shortest(o.rhoInf) +
         ", error control on q, modified Newton with a reused iteration matrix)";
}
}  // namespace

std::string integratorDescription(const SimulationOptions& o) {
  const std::string bdf = "bdf (" + solvers::Bdf::library() + ": BDF orders 1-" + std::to_string(o.bdfMaxOrder) +
                          ", Newton, dense LU, analytic Jacobian of Eq. 15)";
  const std::string ode45 = "ode45 (Dormand-Prince 5(4), MATLAB's step control)";
  if (o.integrator == Integrator::Bdf) return bdf;
  if (o.integrator == Integrator::GeneralizedAlpha) return alphaDescription(o);
  if (o.integrator == Integrator::Auto)
    return "auto: " + ode45 + ", switching to " + alphaDescription(o) + " once ode45's step is bound by stability (" +
           std::to_string(StiffnessTest::kStiffSteps) + " steps at h |lambda| > 3.25, or " +
           std::to_string(StiffnessTest::kWindowHits) + " of " + std::to_string(StiffnessTest::kWindow) +
           " at h |lambda| > 0.9: undamped stiff modes)";
  return ode45;
}

bool StiffnessTest::step(double t, double h, double hLambda) {
  const bool beyond = hLambda > kOscillatoryBoundary;
  windowHits_ += static_cast<int>(beyond) - static_cast<int>(window_[static_cast<std::size_t>(windowPos_)]);
  window_[static_cast<std::size_t>(windowPos_)] = beyond;
  windowPos_ = (windowPos_ + 1) % kWindow;
  const bool oscillatory = ++seen_ >= kWindow && windowHits_ >= kWindowHits;
  if (hLambda > kBoundary || oscillatory) {
    calm_ = 0;
    lambda_ = hLambda / h;
    if (stiff_) {
      ++bound_;
    } else if (oscillatory || ++hits_ >= kStiffSteps) {
      stiff_ = true;
      since_ = t;
      bound_ = oscillatory ? windowHits_ : hits_;
    }
  } else if (++calm_ >= kCalmSteps) {
    hits_ = 0;
    stiff_ = false;  // a transient: the next stiff stretch is counted afresh
  }
  return stiff_;
}

std::string formatStatistics(const core::Trajectory& run, Integrator integrator) {
  solvers::OdeStats st{run.nsteps, run.nfailed, run.nfevals};
  st.njacevals = run.njacevals;
  st.nrhsfailed = run.nrhsfailed;
  st.nlinsetups = run.nlinsetups;
  const bool implicit = integrator == Integrator::Bdf || run.integrator != "ode45";
  std::ostringstream s;
  s << (implicit ? solvers::Bdf::formatStats(st) : solvers::Ode45::formatStats(st));
  if (run.implicitFromStart)
    s << "(auto: galpha from the start: the highest eigenfrequency at rest, |lambda| about " << run.stiffLambda
      << " 1/s, would bound ode45's step)\n";
  else if (!std::isnan(run.switchedAt))
    s << "(auto: ode45's step was bound by stability at t = " << run.switchedAt << " s (|lambda| about "
      << run.stiffLambda << " 1/s): galpha from there on)\n";
  else if (integrator == Integrator::Ode45 && run.stiffBoundSteps >= kStiffHintSteps)
    s << "(ode45's step was bound by stability from t = " << run.stiffSince << " s on (" << run.stiffBoundSteps
      << " steps at the stability limit of |lambda| about " << run.stiffLambda
      << " 1/s): the integrator galpha or auto would be faster)\n";
  return s.str();
}

std::optional<Integrator> parseIntegrator(const std::string& name) {
  if (name == "ode45") return Integrator::Ode45;
  if (name == "bdf") return Integrator::Bdf;
  if (name == "auto") return Integrator::Auto;
  if (name == "galpha") return Integrator::GeneralizedAlpha;
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
  bool bdf = false;           // BDF from the start
  bool alpha = false;         // generalized-alpha from the start

  StageSettings(const core::Model& model, const SimulationOptions& opt) {
    const auto& s = model.settings;
    t0 = s.t0;
    tEnd = opt.tEnd.value_or(s.tEnd);
    relTol = opt.relTol.value_or(s.relTol);
    absTol = opt.absTol.value_or(s.absTol);
    maxStep = opt.maxStep.value_or(s.hmax);
    kinematicTol = kinematicTolerance(s, relTol);
    bdf = opt.integrator == Integrator::Bdf;
    alpha = opt.integrator == Integrator::GeneralizedAlpha;
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
  // Once, on a default ode45 run whose step has been bound by stability for long: that an implicit
  // integrator would be faster.
  void stiffNote(const StiffnessTest& test) {
    if (notedStiff_ || !printed_ || test.boundSteps() < kStiffHintSteps) return;
    std::fprintf(stderr,
                 "\nflexmb: note: since t = %.6g s ode45's step is bound by stability, not accuracy (%ld steps at "
                 "the stability limit of the stiffest mode, |lambda| about %.3g 1/s): the integrator galpha or "
                 "auto would be faster.\n",
                 test.since(), test.boundSteps(), test.lambda());
    notedStiff_ = true;
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
  bool printed_ = false, warnedSlow_ = false, notedStiff_ = false;
};

// One stage's integration: the evaluators (eom integrates; probe computes the output quantities
// and keeps eom's warm start intact; BDF adds the Jacobian and the anchored kinematics) on one
// workspace (each with its own warm start: the same bits as separate workspaces), the callables
// the integrators call, and the output states.
class StageRun {
 public:
  StageRun(const core::Model& model, const SimulationOptions& opt, const Continuation* from, Continuation* end)
      : model_(model),
        opt_(opt),
        set_(model, opt),
        end_(end),
        workspace_(model),
        eom_(workspace_, opt.basis, opt.dynamics),
        probe_(workspace_, opt.basis, opt.dynamics),
        progress_(set_.t0, set_.tEnd, true),
        tReached_(set_.t0) {
    eom_.kinematics().setRelativeTolerance(set_.kinematicTol);
    probe_.kinematics().setRelativeTolerance(set_.kinematicTol);
    if (set_.bdf || set_.alpha) startImplicit();
    if (from) {  // Newton starts from where the previous stage ended (a mechanism may have turned far)
      eom_.kinematics().setConfiguration(from->x);
      probe_.kinematics().setConfiguration(from->x);
      if (jacobian_) jacobian_->kinematics().setConfiguration(from->x);
    }
    y0_ = from ? from->y : eom_.initialState();
    startX_ = probe_.kinematics().x();
    if ((opt.accuracyCheck || opt.deferAccuracy) && opt.keepStates) windows_.emplace(set_.t0, set_.tEnd);
    if (opt.operators && opt.basis) {
      traj_.operators.used = true;
      if (!set_.bdf) {  // ode45, galpha and auto (galpha's iteration matrix from the operators)
        operators_.emplace(model, *opt.operators);
        if (opt.trackedOutputs && opt.keepStates && !end && !opt.operators->outputs.empty()) {
          outputMap_.emplace(model, *opt.operators);
          traj_.tracked.quantities = opt.operators->outputs;
        }
      } else
        traj_.operators.notUsed = "the reduced operators serve ode45 and galpha, not bdf: Eq. 19 throughout";
    }
    eomEta_ = y0_.head(eom_.size());
    // auto: omega_max at rest, for the choice of the integrator and ode45's stiffness test. The step's
    // own estimate of h |lambda| alone can miss the limit for long (issue 48).
    // auto with the user's forces (USERSIG): ode45 throughout. galpha's iteration matrix has no
    // derivative of them; on FlexibleInstrumentSimulation's contact forces its Newton iteration
    // stalled at t = 1e-5 s where ode45 runs the public script through (issue 48).
    if (opt.integrator == Integrator::Auto && !model.userStressFunction.empty()) {
      ode45Only_ = true;
    } else if (opt.integrator == Integrator::Auto)
      try {
        omegaAtRest_ = highestFrequencyAtRest(model, opt.basis);
      } catch (const std::exception&) {  // no linearisation at rest: the step's estimate alone
      }
  }

  core::Trajectory run(bool* interrupted) {
    // A failure no integrator maps to a stop (an unexpected exception from a solver, out of memory)
    // still keeps the output times reached: the run stops there with the reason.
    LapClock clock;
    try {
      integrate(interrupted);
    } catch (const std::exception& e) {
      traj_.completed = false;
      traj_.stopReason =
          std::string(e.what()) + " after t = " + text::shortest(tReached_) + "; results before it are kept";
    }
    traj_.seconds.integration = clock.lap();
    const double galphaFrom = switchAt_ ? *switchAt_ : std::numeric_limits<double>::infinity();
    if (windows_ && traj_.completed && opt_.deferAccuracy)
      *opt_.deferAccuracy = {true, set_.t0, set_.tEnd, galphaFrom, windows_->complete()};
    else if (windows_ && traj_.completed)
      traj_.accuracy = checkAccuracy(model_, opt_, set_.t0, set_.tEnd, windows_->complete(), galphaFrom);
    traj_.seconds.accuracyCheck = clock.lap();
    // Also for a run that stopped: the states it reached say how good the basis was so far.
    if (opt_.basis && opt_.reductionEstimate && opt_.keepStates && !traj_.states.empty())
      traj_.reduction = estimateReductionError(model_, *opt_.basis, traj_);
    else if (opt_.basis && opt_.reductionEstimate && outputMap_ && !traj_.time.empty())
      traj_.reduction = estimateFromSamples();
    traj_.seconds.reductionEstimate = clock.lap();
    return std::move(traj_);
  }

 private:
  void integrate(bool* interrupted) {
    solvers::OdeResult r;
    if (set_.bdf) {
      r = integrateImplicit(set_.tspan, y0_);
    } else if (set_.alpha) {
      r = integrateAlpha(set_.tspan, y0_);
    } else if (implicitFromStart()) {  // auto: ode45 would be stability-bound from its first step
      traj_.switchedAt = set_.t0;
      traj_.implicitFromStart = true;
      traj_.stiffLambda = omegaAtRest_;
      switchAt_ = set_.t0;
      startImplicit();
      jacobian_->kinematics().setConfiguration(eom_.kinematics().x());
      r = integrateAlpha(set_.tspan, y0_);
    } else {
      r = integrateExplicit();
      if (switchAt_) {  // auto: on with galpha from the accepted state where ode45 became stability-bound
        traj_.switchedAt = *switchAt_;
        std::vector<double> rest{*switchAt_};
        if (set_.tspan.size() == 2) {
          if (set_.tEnd > *switchAt_) rest.push_back(set_.tEnd);
        } else
          for (double t : set_.tspan)
            if (t > *switchAt_) rest.push_back(t);
        solvers::OdeResult r2;
        if (rest.size() > 1) {
          startImplicit();
          jacobian_->kinematics().setConfiguration(eom_.kinematics().x());
          skipObservation_ = true;  // the switch state: output already given by ode45, or not an output time
          r2 = integrateAlpha(rest, ySwitch_);
        }
        r2.stats.nsteps += r.stats.nsteps, r2.stats.nfailed += r.stats.nfailed, r2.stats.nfevals += r.stats.nfevals;
        r2.stats.nrhsfailed += r.stats.nrhsfailed;
        r = std::move(r2);
      }
    }
    finish(r, interrupted);
  }

  // auto: galpha from the start where the highest eigenfrequency at rest alone bounds ode45 to more
  // than kImplicitStartSteps steps over the span (span omega_max / 3.3, the real-axis limit; undamped
  // modes allow a third of that step). Measured (issue 48): stiff models 2,400 (guidance) to 160,000
  // (guidance with 40 elements per leaf, where ode45 took 35,000 steps before its test fired);
  // accuracy-bound ones 810 (slider-crank) and 970 (wire guidance). Below the threshold ode45 starts
  // and its stiffness test decides.
  static constexpr double kImplicitStartSteps = 1e4;
  bool implicitFromStart() const {
    return opt_.integrator == Integrator::Auto && omegaAtRest_ > 0.0 &&
           (set_.tEnd - set_.t0) * omegaAtRest_ / 3.3 > kImplicitStartSteps;
  }

  // BDF: every evaluation starts the kinematics from the last accepted state (AnchoredDynamics).
  void startImplicit() {
    jacobian_.emplace(workspace_, opt_.basis);
    anchored_.emplace(eom_, &*jacobian_);
    jacobian_->kinematics().setRelativeTolerance(set_.kinematicTol);
  }

  solvers::OdeResult integrateImplicit(const std::vector<double>& tspan, const Eigen::VectorXd& y0) {
    solvers::BdfOptions o;
    // One absolute tolerance: per-coordinate ones as galpha's cost CVODE 10-100x the steps on the
    // refined guidance (its velocity components of the stiff modes); orders 3-5 are not calibrated.
    const double factor = opt_.bdfMaxOrder <= 2 ? solvers::Bdf::localTolerance(set_.relTol) / set_.relTol : 1.0;
    o.relTol = factor * set_.relTol;
    o.absTol = factor * set_.absTol;
    o.maxStep = set_.maxStep;
    o.maxOrder = opt_.bdfMaxOrder;
    const ImplicitCallables c = implicitCallables();
    return solvers::Bdf(o).integrate(c.f, c.jacobian, tspan, y0, c.observer, c.accept);
  }

  // Generalized-alpha's local tolerances, so that RelTol and AbsTol mean the run's global error
  // in the accuracy check's measure (nodal coordinates, positions relative to the model size, angles
  // in rad): RelTol through the method's calibration (localTolerance), AbsTol per coordinate of eta
  // divided by the largest nodal coordinate its unit change moves (F_q V of Eq. 7 at the start):
  // a bending deformation of a short element turns its nodes by far more than its own size, so one
  // absolute tolerance on eta would loosen with every refinement of the mesh (issue 48).
  struct AlphaTolerances {
    double relTol = 0.0;
    Eigen::VectorXd absTols;
  };
  AlphaTolerances alphaTolerances(double t, const Eigen::VectorXd& y0) {
    AlphaTolerances r;
    const double factor = solvers::GeneralizedAlpha::localTolerance(set_.relTol) / set_.relTol;
    r.relTol = factor * set_.relTol;
    const int m = eom_.size();
    r.absTols = Eigen::VectorXd::Constant(m, factor * set_.absTol);
    etaUnits_ = Eigen::VectorXd::Ones(m);
    try {
      Eigen::VectorXd q;
      eom_.dofs(y0.head(m), q);
      core::GeometricTransferFunctions& k = probe_.kinematics();
      k.solvePositions(t, q);
      Eigen::MatrixXd FqV;
      k.firstOrder(opt_.basis ? &*opt_.basis : nullptr, FqV);
      const double L = model_.lengthScale() > 0.0 ? model_.lengthScale() : 1.0;
      for (int i = 0; i < model_.nx; ++i)
        if (core::isTranslational(model_.nodes[model_.xOwnerNode[i]].kind)) FqV.row(i) /= L;
      for (int j = 0; j < m; ++j) {
        const double moves = FqV.col(j).cwiseAbs().maxCoeff();
        if (moves > 0.0 && std::isfinite(moves)) r.absTols[j] /= moves, etaUnits_[j] = 1.0 / moves;
      }
    } catch (const core::KinematicsError&) {  // the scalar tolerance: the run will say why it cannot start
    }
    return r;
  }

  // What both implicit integrators call: the right-hand side, the output times, the Jacobian of
  // Eq. 15 and the accepted states (the anchor of the kinematics), kinematic failures as RhsError.
  struct ImplicitCallables {
    solvers::OdeRhs f;
    solvers::OdeObserver observer;
    solvers::OdeJacobian jacobian;
    solvers::OdeStepHook accept;
  };
  ImplicitCallables implicitCallables() {
    ImplicitCallables c;
    c.f = [this](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) { rhs(t, y, dy); };
    c.observer = [this](double t, const Eigen::VectorXd& y) { return observe(t, y); };
    c.jacobian = [this](double t, const Eigen::VectorXd& y, const Eigen::VectorXd& fy, Eigen::Ref<Eigen::MatrixXd> J) {
      if (operators_) {
        if (operators_->stateJacobian(t, y, etaUnits_, J)) return;
        noteFallback(t);
      }
      kinematicsAsRhsError([&] {
        catchUpAnchor();
        anchored_->jacobian(t, y, fy, J);
      });
    };
    c.accept = [this](double t, const Eigen::VectorXd& y) {
      ++accepted_;
      if (operators_) {  // on the operators the kinematics wait until Eq. 19 needs them
        lagT_ = t, lagY_ = y, anchorLags_ = true;
        return;
      }
      kinematicsAsRhsError([&] { anchored_->accept(t, y); });
    };
    return c;
  }

  // galpha on the reduced operators: the anchor of the kinematics follows the last accepted state
  // only when Eq. 19 is needed (outside the trained range), from where it last was in up to eight
  // steps (a stretch on the operators may have moved far). Throws core::KinematicsError.
  void catchUpAnchor() {
    if (!anchorLags_) return;
    const int m = eom_.size();
    try {
      anchored_->accept(lagT_, lagY_);
    } catch (const core::KinematicsError&) {
      Eigen::VectorXd y = lagY_;
      for (int k = 1; k <= 8; ++k) {
        y.head(m) = anchorEta_ + (k / 8.0) * (lagY_.head(m) - anchorEta_);
        anchored_->accept(lagT_, y);
      }
    }
    anchorEta_ = lagY_.head(m);
    anchorLags_ = false;
  }

  // Generalized-alpha on the anchored equations of motion (as BDF: every evaluation starts the
  // kinematics from the last accepted state).
  solvers::OdeResult integrateAlpha(const std::vector<double>& tspan, const Eigen::VectorXd& y0) {
    solvers::GeneralizedAlphaOptions o;
    o.rhoInf = opt_.rhoInf;
    const AlphaTolerances tol = alphaTolerances(tspan.front(), y0);
    o.relTol = tol.relTol;
    o.absTols = tol.absTols;
    o.maxStep = set_.maxStep;
    // On the operators the kinematics were last solved at eomEta_ (an ode45 stretch before an auto
    // switch may have stayed on the operators): the anchor catches up from there.
    anchorEta_ = operators_ ? eomEta_ : Eigen::VectorXd(y0.head(eom_.size()));
    const ImplicitCallables c = implicitCallables();
    if (!opt_.basis) {  // full models: the sparse iteration matrix (a few RHS instead of Eq. 15's hundreds)
      SparseIteration system(
          workspace_, c.f, c.accept, [this]() -> const Eigen::VectorXd& { return anchored_->anchor(); },
          set_.kinematicTol);
      return solvers::GeneralizedAlpha(o).integrate(system, tspan, y0, c.observer);
    }
    solvers::FirstOrderAsSecondOrder system(c.f, c.jacobian, eom_.size(), c.accept);
    return solvers::GeneralizedAlpha(o).integrate(system, tspan, y0, c.observer);
  }

  // ode45 with the stiffness test on its accepted steps: auto stops it (and keeps the state) once
  // the step is bound by stability; a default run notes it on the progress line.
  solvers::OdeResult integrateExplicit() {
    solvers::Ode45Options o;
    o.relTol = set_.relTol;
    o.absTol = Eigen::VectorXd::Constant(1, set_.absTol);
    o.maxStep = set_.maxStep;
    const bool autoSwitch = opt_.integrator == Integrator::Auto && !ode45Only_;
    // auto: h omega_max of the model at rest beside the step's own estimate of h |lambda|. The
    // estimate alone can miss the limit for long: the 40-element guidance sat at it for 117,000 steps
    // and 15,000 failed attempts (issue 48). The exact omega_max puts an accuracy-bound step at
    // h omega_max about 0.25-0.3 (slider-crank, wire guidance) and a stability-bound one at 1-1.6.
    const double omegaMax = omegaAtRest_;
    o.stepMonitor = [this, autoSwitch, omegaMax](double t, const Eigen::VectorXd& y, double h, double hLambda) {
      ++accepted_;
      if (!stiffness_.step(t, h, std::max(hLambda, h * omegaMax))) return true;
      if (autoSwitch) {
        switchAt_ = t;
        ySwitch_ = y;
        return false;
      }
      if (opt_.progress) progress_.stiffNote(stiffness_);
      return true;
    };
    auto f = [this](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) { rhs(t, y, dy); };
    auto observer = [this](double t, const Eigen::VectorXd& y) { return observe(t, y); };
    return integrateOde45(eom_, o, f, set_.tspan, y0_, observer);
  }

  template <class F>
  void kinematicsAsRhsError(F&& f) {
    try {
      f();
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());          // a trial state: retried with a smaller step
    } catch (const core::UserFunctionError& e) {  // USERINP in the Jacobian or an accepted step: as in rhs
      userError_ = e.what();
      throw solvers::RhsAbort(e.what());
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
    if (operators_) {
      if (operators_->rhs(t, y, dy)) {
        ++traj_.operators.evaluations;
        return;
      }
      noteFallback(t);
    }
    try {
      if (anchored_) {
        catchUpAnchor();
        anchored_->rhs(t, y, dy);
      } else
        equationsOfMotion(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());          // a trial state; retried with a smaller step
    } catch (const core::UserFunctionError& e) {  // USERSIG / USERINP (Octave/MATLAB gateway)
      userError_ = e.what();
      throw solvers::RhsAbort(e.what());
    }
  }

  // An evaluation (right-hand side or galpha's Jacobian) by the full model outside the operators' range.
  void noteFallback(double t) {
    core::OperatorUse& use = traj_.operators;
    if (use.fallbacks++ == 0) {
      use.firstFallback = t;
      use.where = operators_->whereOutside();
    }
  }

  // Eq. 19. After a stretch on the operators its Newton start may lie far back: on a failure it walks
  // there from the last state it solved in eight steps before giving up.
  void equationsOfMotion(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
    const int m = eom_.size();
    try {
      eom_.rhs(t, y, dy);
    } catch (const core::KinematicsError&) {
      if (!operators_) throw;
      Eigen::VectorXd q;
      for (int k = 1; k <= 8; ++k) {
        eom_.dofs(eomEta_ + (k / 8.0) * (y.head(m) - eomEta_), q);
        eom_.kinematics().solvePositions(t, q);
      }
      eom_.rhs(t, y, dy);
    }
    if (operators_) eomEta_ = y.head(m);  // only a run with operators walks back
  }

  // An output time: the output quantities from the probe, checked (finite, every element valid).
  bool observe(double t, const Eigen::VectorXd& y) {
    if (skipObservation_) {
      skipObservation_ = false;
      return true;
    }
    if (outputMap_) return observeTracked(t, y);
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

  // An output time of a run with tracked outputs: the operators' output fields at the state (their
  // accelerations from the operators' right-hand side); the full kinematics only where the state
  // is outside the trained range or the accuracy check keeps the configuration.
  bool observeTracked(double t, const Eigen::VectorXd& y) {
    core::TrackedOutputs& tr = traj_.tracked;
    const int m = eom_.size();
    if (trackedRate_.size() != y.size()) trackedRate_.resize(y.size());
    const bool fitted = operators_->rhs(t, y, trackedRate_) && outputMap_->evaluate(t, y, trackedRate_.tail(m), tr);
    if (!fitted || (windows_ && windows_->wantsAt(t))) {
      core::StateOutputs out;
      try {
        probe_.outputs(t, y, out);
      } catch (const std::exception& e) {
        return stop(std::string(e.what()) + " (at t = " + text::shortest(t) + "; results before it are kept)");
      }
      if (!fitted) outputMap_->fromStates(out, tr);
      if (windows_) windows_->observe(t, y, out.x);
    }
    if (!tr.value.back().allFinite() || !tr.rate.back().allFinite() || !tr.acceleration.back().allFinite()) {
      for (auto* v : {&tr.value, &tr.rate, &tr.acceleration, &tr.stress}) v->pop_back();
      return stop("non-finite tracked outputs at t = " + text::shortest(t) + "; results before it are kept");
    }
    tr.reduced.push_back(y);
    traj_.time.push_back(t);
    tReached_ = t;
    if (opt_.progress) progress_.update(t, eom_.evaluations(), accepted_);
    return true;
  }

  // The reduction error estimate of a run with tracked outputs: the full outputs at the estimate's
  // samples only (analysis::reductionSamples), solved in time order from one to the next.
  core::ReductionEstimate estimateFromSamples() {
    core::Trajectory sampled;
    probe_.kinematics().setConfiguration(startX_);  // the samples go forward in time from the start
    try {
      for (int k : reductionSamples(static_cast<int>(traj_.time.size()))) {
        core::StateOutputs out;
        probe_.outputs(traj_.time[k], traj_.tracked.reduced[k], out);
        sampled.time.push_back(traj_.time[k]);
        sampled.states.push_back(std::move(out));
      }
    } catch (const std::exception& e) {
      core::ReductionEstimate r;
      r.note = std::string("the full kinematics at a sample failed: ") + e.what();
      return r;
    }
    return estimateReductionError(model_, *opt_.basis, sampled);
  }

  bool stop(const std::string& reason) {
    traj_.completed = false;
    traj_.stopReason = reason;
    return false;
  }

  // Statistics and the stop reason of the run.
  void finish(const solvers::OdeResult& r, bool* interrupted) {
    traj_.integrator = set_.bdf                                ? "bdf"
                       : set_.alpha || traj_.implicitFromStart ? "galpha"
                       : switchAt_                             ? "ode45+galpha"
                                                               : "ode45";
    traj_.stiffSince = stiffness_.since();
    traj_.stiffLambda = traj_.implicitFromStart ? omegaAtRest_ : stiffness_.lambda();
    traj_.stiffBoundSteps = stiffness_.stiff() || switchAt_ ? stiffness_.boundSteps() : 0;
    traj_.nsteps = r.stats.nsteps;
    traj_.nfailed = r.stats.nfailed;
    traj_.nfevals = r.stats.nfevals;
    traj_.nrhsfailed = r.stats.nrhsfailed;
    traj_.njacevals = r.stats.njacevals;
    traj_.nlinsetups = r.stats.nlinsetups;
    if (stoppedByUser_) {
      traj_.completed = false;
      traj_.stopReason = interruptCause(opt_.interruptSignal) + " after t = " + text::shortest(tReached_) +
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
  core::Workspace workspace_;  // shared by eom_, probe_ and jacobian_ (one call at a time)
  core::EquationsOfMotion eom_, probe_;
  std::optional<StateJacobian> jacobian_;
  std::optional<AnchoredDynamics> anchored_;
  std::optional<OperatorDynamics> operators_;   // reduced operators, when given (ode45, galpha)
  std::optional<OperatorOutputMap> outputMap_;  // their tracked outputs (SimulationOptions::trackedOutputs)
  Eigen::VectorXd trackedRate_;                 // dy/dt at an output time (the tracked accelerations)
  Eigen::VectorXd startX_;                      // the configuration the run starts from
  Eigen::VectorXd eomEta_;                      // where eom_ last solved (the fallback's start)
  Eigen::VectorXd etaUnits_;                    // galpha: per eta, the change that moves a node by the model size
  Eigen::VectorXd anchorEta_, lagY_;            // galpha on the operators: the anchor's eta, the last accepted state
  double lagT_ = 0.0;
  bool anchorLags_ = false;  // the anchor is behind the last accepted state
  ProgressLine progress_;
  bool ode45Only_ = false;                         // auto on a model with USERSIG: no switch to galpha
  double omegaAtRest_ = 0.0;                       // auto: the highest eigenfrequency at rest (rad/s; 0: not known)
  std::optional<AccuracyWindowRecorder> windows_;  // the accuracy check's windows, when asked for
  Eigen::VectorXd y0_;
  core::Trajectory traj_;
  std::string userError_;          // a failing USERSIG / USERINP: reported as the stop reason as it is
  long calls_ = 0, accepted_ = 0;  // accepted steps (ode45's and BDF's)
  bool stoppedByUser_ = false;
  StiffnessTest stiffness_;
  std::optional<double> switchAt_;  // auto: the time ode45 stopped to hand over to galpha
  Eigen::VectorXd ySwitch_;         // and its state there
  bool skipObservation_ = false;    // the next observation is the BDF start at the switch
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
  // Checked before any block runs: a later block must not throw away the blocks integrated before it.
  for (const core::Model* m : stages)
    if (m->numDofs() != stages.front()->numDofs() || m->nx != stages.front()->nx)
      throw std::invalid_argument("analysis blocks with different degrees of freedom cannot continue each other");
  core::Trajectory all;
  Continuation state;
  for (size_t k = 0; k < stages.size(); ++k) {
    const core::Model& m = *stages[k];
    SimulationOptions o = opt;
    if (k + 1 < stages.size()) o.tEnd.reset();
    Continuation end;
    core::Trajectory part;
    try {
      part = simulateStage(m, o, k ? &state : nullptr, &end, interrupted);
    } catch (const std::exception& e) {  // the block could not start: the blocks before it stand
      if (k == 0) throw;
      all.completed = false;
      all.stopReason = "analysis block " + std::to_string(k + 1) + " could not start: " + e.what() +
                       "; the results of the blocks before it are kept";
      return all;
    }
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
    all.seconds.integration += part.seconds.integration;
    all.seconds.accuracyCheck += part.seconds.accuracyCheck;
    if (std::isnan(all.switchedAt)) all.switchedAt = part.switchedAt;
    if (part.stiffBoundSteps > all.stiffBoundSteps)
      all.stiffSince = part.stiffSince, all.stiffLambda = part.stiffLambda, all.stiffBoundSteps = part.stiffBoundSteps;
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

std::vector<const core::Model*> stagesThatRun(const std::vector<io::AnalysisStage>& stages) {
  std::vector<const core::Model*> runs;
  for (const auto& st : stages)
    if (st.runs) runs.push_back(&st.model);
  if (runs.empty() && !stages.empty()) runs.push_back(&stages.back().model);
  return runs;
}

}  // namespace flexmb::analysis
