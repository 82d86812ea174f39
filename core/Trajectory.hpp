#pragma once
// What a time simulation produces: output times, SPACAR's quantities at each, and integrator
// statistics. Filled by the simulate analysis, written by io's result writers.
#include <string>
#include <vector>

#include "core/EquationsOfMotion.hpp"

namespace flexmb::core {

struct Trajectory {
  std::vector<double> time;
  std::vector<StateOutputs> states;  // one per output time: x, xd, xdd, e, ed, edd, sig
  long nsteps = 0, nfailed = 0, nfevals = 0;
  long nrhsfailed = 0;  // ode45: failed attempts whose right-hand side failed at a trial state
  // The integrator ("ode45" or "bdf") and, for bdf, its Jacobian evaluations and linear-solver set-ups.
  std::string integrator = "ode45";
  long njacevals = 0, nlinsetups = 0;
  bool completed = true;
  std::string stopReason;  // why the run stopped early (time and reason); empty when completed
};

}  // namespace flexmb::core
