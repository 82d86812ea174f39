#pragma once
// A self-contained HTML page that shows a model in 3-D and plays sequences of its configurations:
// inline data and JavaScript, a <canvas>, no network access. Geometry from MechanismGeometry: the
// sampled element axes and, where a cross-section is known (VISUALIZATION, section data), the local
// section axes, so the page draws beams as shaded solids (painter's order), trusses and planar
// elements as lines, hinges as joints with their axis.
//
// The page: drag rotates the view (azimuth, elevation), the wheel zooms, shift-drag pans; buttons
// for the iso, xy, xz and yz views and for fitting; a sequence list (the motion, the load steps,
// each mode shape), play/pause, a frame slider, playback speed for timed sequences, node and element
// numbers on request, displacements from the initial configuration magnified 10 ... 1000 times (small
// elastic motions); elements coloured by role (as in `flexmb show`), or by the file's FACECOLOR.
// Planar models start in the xy view, spatial ones in iso.
// On load it sets document.title to "ok" when the first frame was drawn, or "error: <message>" on any
// JavaScript error (what the headless-browser test reads). The URL fragment selects a state for
// scripted views: #seq=K (0-based), #frame=K, #pause, #view=xy|xz|yz|iso, #magnify=K, #numbers,
// #noreference (the initial configuration's dashed centre lines off),
// #drag=DX,DY (a mouse drag by
// DX, DY pixels through the page's own handlers; the title then reads "ok az=A el=E" in degrees).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "io/pictures/MechanismGeometry.hpp"

namespace flexmb::io {

// One playable sequence of configurations.
struct AnimationSequence {
  std::string name;                 // "motion", "load steps", "mode 1, 12.3 Hz"
  std::vector<Eigen::VectorXd> x;   // nodal coordinates per frame (size nx)
  std::vector<std::string> labels;  // per frame (may be empty: "frame k")
  std::vector<double> times;        // per frame for real-time playback; empty: evenly spaced frames
  bool periodic = false;            // a mode shape: loops back to its first frame
};

struct AnimationOptions {
  std::string title;  // shown above the canvas
  View view = View::Auto;
  int maxFrames = 2000;  // more frames in a sequence are thinned evenly (first and last kept)
  bool numbers = false;  // node and element numbers shown at first
};

// The page of any sequences (at least one frame in total).
std::string renderHtmlPage(const core::Model& model, const std::vector<AnimationSequence>& sequences,
                           const AnimationOptions& options = {});
// A simulation: one timed sequence.
std::string renderHtmlAnimation(const core::Model& model, const core::Trajectory& traj,
                                const AnimationOptions& options = {});
// A mode shape as a periodic sequence: x + sin(2 pi k / frames) * (shaped - x), k = 0 .. frames - 1,
// where shaped = scaledShape(x, dx).
AnimationSequence modeSequence(const core::Model& model, const std::string& name, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& dx, int frames = 24);

// Checked, atomic writes (writeTextFile). Throw std::invalid_argument for empty input, wrong sizes
// or non-finite positions.
void writeHtmlPage(const std::string& path, const core::Model& model, const std::vector<AnimationSequence>& sequences,
                   const AnimationOptions& options = {});
void writeHtmlAnimation(const std::string& path, const core::Model& model, const core::Trajectory& traj,
                        const AnimationOptions& options = {});

}  // namespace flexmb::io
