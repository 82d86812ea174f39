#pragma once
// The end-of-run state as a complete .dat input that continues the run (SPACAR95 prints its state
// this way; `flexmb simulate --echo` writes it). Reading it back gives the same model in the state
// where the run ended: elements, the current coordinates (XY / BETA), roles, LENGTH0 of every
// element with a length, the deformations E (and rates ED of the dynamic ones), the rates of the
// inputs at the current time, TIME, and every load, mass, stiffness and setting the model had.
//
// Written in the model's dialect: SPACAR95 as one block closed by END and EOF; SPACAR 2013+ as a
// kinematic block, END HALT, the dynamic block, END END (with TIME and LENGTH0, which flexmb
// accepts in both dialects). The next analysis runs one more period of the same length and the
// same number of output intervals (SPACAR95 TIMESTEP n Tp; 2013+ TIMESTEP T n with T = t + Tp).
#include <string>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/model/Model.hpp"

namespace flexmb::io {

// Why flexmb cannot write a restart echo of this model (empty: it can). Asked before a run, so
// that --echo is refused with its reason instead of producing a file the reader refuses: the
// writer covers planar models; a spatial model's echo would need its 3-D coordinates, Euler
// parameters (without the normalisation elements flexmb adds) and the elements' reference
// orientations, which it does not write yet.
std::string restartUnsupportedReason(const core::Model& model);

// The restart text of `model` at time t in `state` (x, xd, e, ed of the final output time).
// Throws std::invalid_argument when the state does not match the model or is not finite, or the
// model is one restartUnsupportedReason names.
std::string restartText(const core::Model& model, double t, const core::StateOutputs& state);

// Writes restartText to path (std::runtime_error naming the path when it cannot be written).
void writeRestart(const std::string& path, const core::Model& model, double t, const core::StateOutputs& state);

}  // namespace flexmb::io
