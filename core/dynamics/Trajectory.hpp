#pragma once
// What a time simulation produces: output times, SPACAR's quantities at each, and integrator
// statistics. Filled by the simulate analysis, written by io's result writers.
#include <limits>
#include <string>
#include <vector>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/model/ReducedOperatorData.hpp"

namespace flexmb::core {

// The a-posteriori accuracy check of a simulation (the analysis floor's): short windows of
// the run integrated again at a tighter tolerance from the run's own states, compared at their ends.
struct AccuracyEstimate {
  bool checked = false;        // false: not run (not asked for, the run stopped, no window fitted)
  int windows = 0;             // windows compared
  double windowSeconds = 0.0;  // their total length
  double referenceRelTol = 0.0;
  // Largest difference at a window's end between the run and the reference: nodal positions
  // relative to the model size (Model::lengthScale), angles and Euler parameters as they are.
  double windowError = 0.0;
  double estimate = 0.0;  // extrapolated to the whole run: the largest error per second x the span
  double limit = 0.0;     // an estimate above it: the run is not converged
  // The estimate of each kind, judged each on its own scale against the limit: nodal positions
  // relative to the model size, angles (and Euler parameters) in rad; where each comes from ("node 6
  // x", "node 12 rotation"; empty: no difference of that kind).
  double positionEstimate = 0.0, angleEstimate = 0.0;
  std::string positionWhere, angleWhere;
  bool converged() const { return !checked || (positionEstimate <= limit && angleEstimate <= limit); }
  std::string note;  // why it was not run, or what limited it
};

// The reduction error of a reduced run (the analysis floor estimates it): the full model's residual
// at the reduced states, the error it carries along the run, relative to the motion.
struct ReductionEstimate {
  bool estimated = false;
  double estimate = 0.0;     // twice carried
  double quasiStatic = 0.0;  // the largest quasi-static deflection outside the basis / scale (not counted)
  double carried = 0.0;      // the largest error the linearised full model carries along the run / scale
  double scale = 0.0;        // the motion (or model size) it is relative to, in m
  std::string scaleText;     // "of the motion (0.0833 m)" or "of the model size (...)"
  double atTime = 0.0;       // where the largest was found
  int samples = 0;           // output times evaluated
  double seconds = 0.0;      // its cost
  std::string note;          // why not estimated
};

// How a reduced run's right-hand side was evaluated (the analysis floor's choice): by the
// precomputed operators, and by Eq. 19 (the full kinematics) where the state left their range.
struct OperatorUse {
  bool used = false;     // the run had operators
  std::string notUsed;   // why a reduced run had none (or used Eq. 19 throughout)
  long evaluations = 0;  // right-hand sides from the operators
  long fallbacks = 0;    // right-hand sides from Eq. 19 outside the trained range
  double firstFallback = std::numeric_limits<double>::quiet_NaN();  // time of the first
  std::string where;                                                // the coordinate outside the range there
};

// simulate --outputs tracked: the reduced operators' output fields at the output times in place of
// the full StateOutputs (Trajectory::states stays empty), so that an output time costs nothing that
// grows with the mesh. One row per output time, one entry per tracked quantity.
struct TrackedOutputs {
  std::vector<OperatorOutput> quantities;
  std::vector<Eigen::VectorXd> value, rate, acceleration;  // x, xd, xdd or e, ed, edd
  std::vector<Eigen::VectorXd> stress;                     // sig of the deformations (NaN for coordinates)
  std::vector<Eigen::VectorXd> reduced;                    // y = [eta; etad]
  long fromOperators = 0, fromKinematics = 0;              // rows from the fields; from the full kinematics
                                                           // (the state outside the trained range)
  bool empty() const { return quantities.empty(); }
};

struct Trajectory {
  std::vector<double> time;
  std::vector<StateOutputs> states;  // one per output time: x, xd, xdd, e, ed, edd, sig
  TrackedOutputs tracked;            // instead of states (simulate --outputs tracked)
  long nsteps = 0, nfailed = 0, nfevals = 0;
  long nrhsfailed = 0;  // ode45: failed attempts whose right-hand side failed at a trial state
  // The integrator ("ode45", "bdf", or "ode45+bdf" for an auto run that switched) and, for bdf, its
  // Jacobian evaluations and linear-solver set-ups.
  std::string integrator = "ode45";
  long njacevals = 0, nlinsetups = 0;
  // ode45's step bound by stability (the stiffest mode) rather than accuracy: from stiffSince on,
  // stiffBoundSteps steps at the boundary, |lambda| about stiffLambda (1/s); stiffBoundSteps = 0:
  // never. switchedAt: the time an auto run went on with galpha (NaN: it did not).
  double stiffSince = 0.0, stiffLambda = 0.0;
  long stiffBoundSteps = 0;
  double switchedAt = std::numeric_limits<double>::quiet_NaN();
  // An auto run that went on with galpha from its start: the highest eigenfrequency at rest
  // (stiffLambda) bounds ode45 to more steps than it is worth (switchedAt = t0, no ode45 step).
  bool implicitFromStart = false;
  bool completed = true;
  std::string stopReason;  // why the run stopped early (time and reason); empty when completed
  AccuracyEstimate accuracy;
  ReductionEstimate reduction;  // reduced runs (a basis) that keep their states
  OperatorUse operators;        // reduced runs
  // Where the run's time went (s, wall clock): the integration itself (output times included), the
  // accuracy check and the reduction error estimate after it.
  struct Seconds {
    double integration = 0.0, accuracyCheck = 0.0, reductionEstimate = 0.0;
  } seconds;
};

}  // namespace flexmb::core
