#pragma once
// Mode 9: the linearised state-space model of a static equilibrium between the inputs and the
// outputs of the .dat's transfer block (core::TransferChannel; io/dat-language.md):
//   d/dt [dq; dqd] = A [dq; dqd] + B u,   y = C [dq; dqd] + D u,
//   A = [0 I; -M0^-1 (K0 + N0 + G0), -M0^-1 (C0 + D0)],
// the states in the order of the degrees of freedom q (the rows of M0 in the .sbm), so that SPACAR
// Light can replace A's lower-right block by modal damping built from M0 and its modes.
//   INPUTF (force f on coordinate j):  B = [0; M0^-1 F_j^T]  (F = dx/dq; spatial orientation node:
//                                      the moment about a global axis, generalised force 2 E^T e_i);
//   INX (prescribed motion u of an input coordinate): three channels u, du/dt, d2u/dt2 with
//                                      B = [0; -M0^-1 (K+G)_qu], [0; -M0^-1 D_qu], [0; -M0^-1 M_qu],
//                                      and D = F_ju (or its rate) on the outputs it moves directly;
//   OUTX / OUTXP: C = [F_j 0] / [0 F_j] (spatial orientation node: the rotation 2 E(lambda) dlambda);
//   OUTF (force fxt_j a fixed or input coordinate takes): fxt_j = f_j - Q_j, so its change is
//                                      (K+G)_jq dq + D_jq dqd + M_jq dqdd with dqdd from A and B:
//                                      C = [(K+G)_jq + M_jq A21, D_jq + M_jq A22], D = M_jq B2 minus
//                                      the force inputs' generalised loads along j (+ the direct INX
//                                      couplings); on an orientation node the moment
//                                      1/2 E(lambda) f_lambda.
// The mixed blocks come from the model with u and j as degrees of freedom (analysis/Perturbation).
// The equilibrium is the last load step of the static analysis (analysis/Statics: load steps
// 0..nsteps; SPACAR Light writes no loads besides gravity in mode 9).
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/DesignDamping.hpp"
#include "analysis/Statics.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct StateSpace {
  Eigen::MatrixXd A, B, C, D;                                      // 2m x 2m, 2m x ni, no x 2m, no x ni
  std::vector<std::string> inputNames, outputNames;                // one per column of B / row of C
  std::vector<std::string> inputUnits, outputUnits;                // SI ("N", "m/s", "rad"); "" if unknown
  bool feedthrough() const { return D.size() && !D.isZero(0.0); }  // SPACAR's DFT
};

// The state-space model of the equilibrium `step` of model (its transfer block). Throws
// std::invalid_argument when the block has no input or no output, std::runtime_error when M0 is not
// positive definite (a degree of freedom without mass).
// damping: modal and Rayleigh damping added to C0 + D0 (analysis/DesignDamping.hpp).
StateSpace stateSpaceAt(const core::Model& model, const StaticStep& step, const DampingOptions& damping = {});

struct TransferOptions {
  int nev = 0;             // eigenfrequencies per load step of the statics (0: none)
  int loadSteps = 0;       // > 0 overrides ITERSTEP's number of load steps
  DampingOptions damping;  // added to the model's EDAMP (analysis/DesignDamping.hpp)
  std::function<void(int, int)> onStep;
};
struct TransferRun {
  StaticRun statics;  // the load steps; the state-space model belongs to the last
  StateSpace model;
  bool completed = true;
  std::string stopReason;
};
// Statics over the load steps, then stateSpaceAt the last one. A run that stops keeps its load
// steps and has no state-space model.
TransferRun transferAnalysis(const core::Model& model, const TransferOptions& options = {});

// The frequency response of one input-output pair, H(i w) = C (i w I - A)^-1 B + D, at the given
// angular frequencies (rad/s): one complex solve per frequency.
Eigen::VectorXcd frequencyResponse(const StateSpace& ss, int input, int output, const Eigen::VectorXd& omega);
// Every input-output pair at once (one Hessenberg reduction; per frequency one elimination for all
// inputs): element i * outputs + o is H_oi.
std::vector<Eigen::VectorXcd> frequencyResponses(const StateSpace& ss, const Eigen::VectorXd& omega);

// The phase in degrees of H(i w) (h: frequencyResponse's). Damped: continuous along the
// frequencies (unwrapped: no jump over 180 degrees between neighbours). Undamped (A's damping block
// zero): H is real or imaginary and flips sign at poles and zeros, where only damping would say
// whether it turns by +180 or -180; its phase is H's own, rounded to a quarter turn: 0, +-90 or -180.
Eigen::VectorXd bodePhase(const StateSpace& ss, const Eigen::VectorXcd& h);
// True when the model has no damping (A's damping block is zero).
bool undamped(const StateSpace& ss);

// The static gain -C A^-1 B + D: the compliance of the equilibrium (outputs per unit input); none
// when A is singular (a free motion without stiffness).
std::optional<Eigen::MatrixXd> staticGain(const StateSpace& ss);

// Angular frequencies for a Bode plot: 400 log-spaced points a decade beyond the undamped
// eigenfrequencies' range (1..1e3 rad/s without any; from fminHz to fmaxHz when 0 < fminHz < fmaxHz),
// and, for a model of up to 300 degrees of freedom, 12 more closing in on each of its lowest 30
// eigenfrequencies in range (to 1e-4 of it), so a lightly damped peak is drawn at its height.
Eigen::VectorXd bodeFrequencies(const StateSpace& ss, double fminHz = 0.0, double fmaxHz = 0.0);

}  // namespace flexmb::analysis
