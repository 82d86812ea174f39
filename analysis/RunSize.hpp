#pragma once
// The checks before a time simulation that every front end makes (issue 36: the command line and
// the Octave/MATLAB gateway alike): what cannot finish or fit in this machine is refused with the
// reason and what to change; a run whose explicit steps are bounded by the highest eigenfrequency,
// not by the output or the accuracy, gets a warning that names where that mode lives.
#include <string>

#include "analysis/Simulation.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct RunSizeCheck {
  std::string refusal;  // non-empty: do not run (the reason and what to change)
  std::string options;  // the options that change it (Diagnostic::options)
  std::string warning;  // the stability limit sets ode45's step (the run is slow, not wrong)
};

// Limits: at least 1e9 integrator steps (a maximum step, or ode45's stability limit 3.3 / omega_max
// over the span), or output states needing more than a quarter of this machine's memory.
RunSizeCheck checkRunSize(const core::Model& model, const SimulationOptions& options);

}  // namespace flexmb::analysis
