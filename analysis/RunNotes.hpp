#pragma once
// What a finished or stopped simulation says beside its files (stopped early, the ode45-to-bdf switch,
// the integration accuracy check, the reduction error estimate), worded once for every front end:
// the command line prints these lines and keeps their settings in the manifest; the study, Octave and
// Python gateways take the same.
#include <limits>
#include <string>
#include <vector>

#include "analysis/Simulation.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct RunNote {
  enum class Kind { Result, Note, Warning, Stopped };  // screen; note; warning; the run stopped
  Kind kind = Kind::Result;
  std::string text;     // the line, without "flexmb: " or "warning: "
  std::string setting;  // the manifest's key, or empty
  std::string value;    // the manifest's value
  std::string options;  // the options that change it (Diagnostic::options)
};

// `target`: the reduction error the user asked for (NaN: none; the estimate is then compared with
// 10 RelTol).
std::vector<RunNote> runNotes(const core::Model& model, const SimulationOptions& opt, const core::Trajectory& traj,
                              double target = std::numeric_limits<double>::quiet_NaN());

}  // namespace flexmb::analysis
