#pragma once
// The end-of-run state as a complete .dat input that continues the run (SPACAR95 prints its state
// this way; `flexmb simulate --echo` writes it). Reading it back gives the same model in the state
// where the run ended: elements, the current coordinates (XY / BETA; spatial below), roles, LENGTH0 of every
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

// A spatial model's echo (flexmb's own: SPACAR publishes none) is always in SPACAR 2013+ form: the
// element lines with their y vectors, X of every node where the run ended (positions, Euler
// parameters; no L2MIN1 lines: the reader adds them), XREF (flexmb extension) with the original
// coordinates of every node that moved, so that the elements are created in the run's reference
// configuration, STARTDE value and rate of every DYNE deformation (released ones follow from X),
// EM in the element's own layout, XM tensors of orientation nodes and moments as XF n Mx My Mz.
//
// Why flexmb cannot write a restart echo of this model (empty: it can). Asked before a run, so
// that --echo is refused with its reason instead of producing a file the reader refuses: a spatial
// model with a coordinate degree of freedom (DYNX, a free BEAMW warping coordinate), whose rate
// SPACAR 2013+ has no keyword for.
std::string restartUnsupportedReason(const core::Model& model);

// The restart text of `model` at time t in `state` (x, xd, e, ed of the final output time).
// Throws std::invalid_argument when the state does not match the model or is not finite, or the
// model is one restartUnsupportedReason names.
std::string restartText(const core::Model& model, double t, const core::StateOutputs& state);

// Writes restartText to path (std::runtime_error naming the path when it cannot be written).
void writeRestart(const std::string& path, const core::Model& model, double t, const core::StateOutputs& state);

}  // namespace flexmb::io
