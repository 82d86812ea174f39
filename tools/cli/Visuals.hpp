#pragma once
// The pictures and animations of the command line: `flexmb show`, the --svg figures of modes,
// static and sweep, and simulate's --vtk / --html outputs. The drawing itself lives in io/
// (MechanismGeometry, MechanismSvg, VtkWriter, HtmlAnimation); this file only gathers what the
// analyses computed (configurations in q, modes in q) into nodal coordinates.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "analysis/Statics.hpp"
#include "analysis/Sweep.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "io/pictures/MechanismGeometry.hpp"

namespace flexmb::cli {

// The end of every --html option's help: the page's URL options (io/pictures/HtmlAnimation.hpp).
inline constexpr const char* kHtmlUrlOptions =
    "; its address opens in a state: #seq=K&frame=K&view=iso|xy|xz|yz&magnify=1|10|100|1000&pause&numbers&"
    "noreference (docs/analyses/show.md)";

int runShow(const std::vector<std::string>& args);

// A configuration in degrees of freedom q with mode shapes (q coordinates, one per column).
struct ModeSet {
  std::string title;  // "load factor 1", "x(node 3, y) = 0.05"
  Eigen::VectorXd q;
  Eigen::MatrixXd modes;         // nq x k (may be empty)
  Eigen::VectorXd omega;         // rad/s, one per mode column
  double t = 0.0;                // time of the configuration (rheonomic inputs)
  double inputLoadFactor = 0.0;  // DELINPX factor of static load steps
};
// A named configuration in nodal coordinates x.
struct NamedConfiguration {
  std::string label;
  Eigen::VectorXd x;
};

// The figure of `modes`, `static` and `sweep --svg`: a first panel with the initial configuration
// (dashed grey) and the given configurations over it (light to dark blue), then one panel per mode
// of each mode set: the configuration (dashed grey) and x + s F_q v (s: scaledShape). Positions and
// F_q are recomputed from q by the model's kinematics. Throws std::runtime_error on failures.
// view: the projection of every panel; Auto: each panel in the view that sees most of its model and
// motion (io::panelView; spatial models, named in a note), xy (planar ones).
void writeShapeFigure(const std::string& path, const core::Model& model, const std::string& title,
                      const std::vector<NamedConfiguration>& configurations, const std::vector<ModeSet>& modeSets,
                      io::View view = io::View::Auto);

// Nodal coordinates of each q at time t by the model's kinematics, solved in order (each solve
// starts from the previous one, as a continuation does).
std::vector<Eigen::VectorXd> positionsOf(const core::Model& model, const std::vector<Eigen::VectorXd>& qs, double t);

// static --svg: the equilibria of every load step and the mode shapes of the last one.
// sweep --svg: the configurations of every point and the mode shapes at the first and the last.
// Both print "wrote <path>", or the error (false).
bool writeStaticFigure(const std::string& path, const core::Model& model, const std::string& modelFile,
                       const analysis::StaticRun& run, io::View view = io::View::Auto);
bool writeSweepFigure(const std::string& path, const core::Model& model, const std::string& modelFile,
                      const analysis::SweepResult& sweep, double t, io::View view = io::View::Auto);

// The 3-D page (io/pictures/HtmlAnimation.hpp) and the ParaView series (io/pictures/VtkWriter.hpp) of the other
// analyses:
//   show --html: the model in its initial configuration, numbers shown;
//   static --html: the load steps (from the initial configuration) and each mode shape of the last
//   step; static --vtk: one .vtu per load step (time = the load factor: 0 at load step 0, a ramp
//   step of the initial loads before it at its fraction minus 1), with e and sigma;
//   modes --html: each mode shape; modes --vtk: one .vtu per mode (time = the mode's number), the
//   configuration moved by the drawn mode shape (displacement and rotation fields are the shape).
// Each prints "wrote <path>", or the error (false).
bool writeModelPage(const std::string& path, const core::Model& model, const std::string& title);
bool writeStaticPage(const std::string& path, const core::Model& model, const std::string& modelFile,
                     const analysis::StaticRun& run);
bool writeStaticVtk(const std::string& prefix, const core::Model& model, const analysis::StaticRun& run);
bool writeModesPage(const std::string& path, const core::Model& model, const std::string& modelFile,
                    const ModeSet& set);
bool writeModesVtk(const std::string& prefix, const core::Model& model, const ModeSet& set);

}  // namespace flexmb::cli
