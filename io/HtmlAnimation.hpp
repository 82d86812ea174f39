#pragma once
// A self-contained HTML page that plays a simulation in a browser: inline data and JavaScript,
// a <canvas>, no network access. Geometry from MechanismGeometry, projected once in C++ (planar:
// x, y; spatial: isometric), so the page only draws 2-D polylines.
//
// The page: play/pause, a time slider, playback speed (real time x 0.1 ... x 10), the time and
// frame number, elements coloured by role (as in `flexmb show`), fixed nodes marked, the path of
// the last position node traced. On load it sets document.title to "ok" when the first frame was
// drawn, or "error: <message>" on any JavaScript error (what the headless-browser test reads).
#include <string>

#include "core/Model.hpp"
#include "core/Trajectory.hpp"
#include "io/MechanismGeometry.hpp"

namespace flexmb::io {

struct AnimationOptions {
  std::string title;  // shown above the canvas
  View view = View::Auto;
  int maxFrames = 2000;  // more output times are thinned evenly (first and last kept)
};

std::string renderHtmlAnimation(const core::Model& model, const core::Trajectory& traj,
                                const AnimationOptions& options = {});
// Checked, atomic write (writeTextFile). Throws std::invalid_argument for an empty trajectory or
// non-finite positions.
void writeHtmlAnimation(const std::string& path, const core::Model& model, const core::Trajectory& traj,
                        const AnimationOptions& options = {});

}  // namespace flexmb::io
