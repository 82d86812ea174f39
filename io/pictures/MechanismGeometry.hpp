#pragma once
// MechanismGeometry: the one place that turns nodal coordinates x into drawable geometry. Every
// picture of a mechanism (flexmb show, deformed configurations and mode shapes, the HTML pages,
// the ParaView series) samples its points here and projects them with project().
//
//   * Position nodes are points: (x, y, 0) for planar nodes (2 coordinates), (x, y, z) for spatial
//     ones (3 coordinates).
//   * An element with two or more position nodes is a curve. PLBEAM / PLBEAMNL are sampled with the
//     beam's own displacement field (core/elements/PlanarBeam.hpp): r(xi) = (1-xi) rp + xi rq +
//     n(alpha) (H2 e2 + H3 e3), H2 = xi (1-xi)^2, H3 = xi^2 (1-xi), so bending shows as a curve.
//     A spatial element with two position nodes and an element triad at two orientation nodes
//     (BEAM, BEAMNL; Element::elementFrame) follows the co-rotated cubic field of its mass
//     (core/elements/SpatialBeam.hpp): r(xi) = (1-xi) x_p + xi x_q + l0 [H10 (t_p - e_l) +
//     H11 (t_q - e_l)], H10 = xi (1-xi)^2, H11 = xi^2 (xi-1), t_k = R(lambda_k) A_k e_x. Every other
//     element with position nodes (trusses, RBEAM) is the polyline through its position nodes.
//   * Elements with a triad carry a section frame at each sampled point (sectionAxes: the local y
//     and z axes, y interpolated between the ends and made normal to the curve), so a cross-section
//     can be drawn around the axis: from the VISUALIZATION section (CROSSTYPE, CROSSDIM), else the
//     rectangle with the section's radii of gyration (w = sqrt(12 Iz/A), t = sqrt(12 Iy/A) from the
//     EM values Jzz/rhoA, Jyy/rhoA or the ESTIFF values EIz/EA, EIy/EA).
//   * An element without position nodes (PLHINGE, HINGE) is a joint: one point at the position
//     node its orientation nodes are attached to; a spatial hinge also has an axis (jointAxis).
//   * An orientation node is attached to the position node that precedes it in an element's node
//     list (PLBEAM p, phi_p, q, phi_q; BEAM p, Rp, q, Rq); an orientation node used only by joints
//     takes the attachment of the other orientation nodes of its joints. Unattached nodes and
//     elements (and DONOTDRAW elements) are not drawn.
//
// The point layout (which points belong to which element) is fixed when the geometry is built, so
// a time series has the same points and cells at every output time.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::io {

struct Point3 {
  double x = 0.0, y = 0.0, z = 0.0;
};
struct Point2 {
  double u = 0.0, v = 0.0;
};

enum class DrawnShape { Curve, Joint };

// What is drawn around a curve's axis: nothing (a line), a w x t rectangle (w along the local y
// axis) or a circle of diameter w.
struct DrawnSection {
  enum class Kind { Line, Rectangle, Circle };
  Kind kind = Kind::Line;
  double width = 0.0, thickness = 0.0;
  bool fromFile = false;  // VISUALIZATION (else derived from the section data)
};

struct DrawnElement {
  int element = 0;  // index into Model::elements
  DrawnShape shape = DrawnShape::Curve;
  int firstPoint = 0, numPoints = 0;  // into the sampled points
  bool framed = false;                // sectionAxes are defined at its points
  DrawnSection section;
};

class MechanismGeometry {
 public:
  // beamSegments: straight pieces per beam (at least 1).
  explicit MechanismGeometry(const core::Model& model, int beamSegments = 8);

  const core::Model& model() const { return model_; }
  const std::vector<DrawnElement>& elements() const { return drawn_; }
  int numPoints() const { return numPoints_; }
  // Node index (into Model::nodes) of each sampled point that is a position node, else -1.
  const std::vector<int>& pointNodes() const { return pointNode_; }
  // The position node an orientation node is drawn at (itself for position nodes), -1 if none.
  int anchor(int node) const { return anchor_[node]; }
  // True when some position node has a third (out-of-plane) coordinate.
  bool spatial() const { return spatial_; }
  // Position nodes (planar or spatial) are drawn as points; orientation nodes are not.
  bool isPositionNode(int node) const;

  // Sampled points of all drawn elements at configuration x (size nx), in the fixed layout.
  void points(const Eigen::VectorXd& x, std::vector<Point3>& out) const;
  // Per sampled point the section's local y and z axes (unit vectors) at x; zero vectors for points
  // of elements without a frame.
  void sectionAxes(const Eigen::VectorXd& x, std::vector<Point3>& y, std::vector<Point3>& z) const;
  // A spatial joint's axis (unit, global) at x: the hinge triad's e_x; false for a planar joint.
  bool jointAxis(const DrawnElement& d, const Eigen::VectorXd& x, Point3& axis) const;
  // Where a node is drawn (its anchor's position); (0,0,0) for an unattached node.
  Point3 nodePoint(int node, const Eigen::VectorXd& x) const;

 private:
  const core::Model& model_;
  int beamSegments_;
  std::vector<DrawnElement> drawn_;
  std::vector<int> pointNode_, anchor_;
  int numPoints_ = 0;
  bool spatial_ = false;
};

// Projection onto the drawing plane. Planar models: (x, y). Spatial models: the axonometric view
// SPACAR's MATLAB viewer opens with (MATLAB's view(3): azimuth -37.5 degrees from -y, elevation 30
// degrees; z up, x to the right and towards the viewer, y to the right and away from the viewer: no
// coordinate plane or diagonal of a model is seen edge-on); xy seen from +z, xz from -y (z up), yz
// from +x (z up). `iso` names that axonometric view.
enum class View { Auto, XY, XZ, YZ, Isometric };
// A view direction in the page's terms: azimuth a and elevation e (degrees) of the viewer, seen from
// toViewer = (cos e cos a, cos e sin a, sin e), with the screen's right and up vectors.
struct Axonometry {
  double azimuth = 0.0, elevation = 0.0;
  double toViewer[3], right[3], up[3];
};
Axonometry axonometry(double azimuthDeg, double elevationDeg);
Axonometry axonometry(View view);
View resolveView(View requested, const MechanismGeometry& geometry);
Point2 project(const Point3& p, View view);
// Distance towards the viewer (larger is nearer): the painter's order of the 3-D pictures.
double depth(const Point3& p, View view);
// "xy", "xz", "yz", "iso".
const char* viewName(View view);

// The largest distance of the model's position nodes from its centre in x (at least a tiny
// positive length): the scale for mode-shape amplitudes and label offsets.
double modelSize(const core::Model& model, const Eigen::VectorXd& x);

// The drawn section of element e (index): VISUALIZATION, else the rectangle with the section's radii
// of gyration (EM, then ESTIFF), else a line.
DrawnSection elementSection(const core::Model& model, int element);

// The factor small deflections are drawn magnified by (load steps, sweep points, against x0): 1 when
// the largest displacement is 5 % of modelSize or more; else 1, 2 or 5 times a power of ten, at most
// what brings it to 12 % and the largest rotation to 0.3 rad (as the mode shapes are drawn).
double magnification(const core::Model& model, const Eigen::VectorXd& x0, const std::vector<Eigen::VectorXd>& xs);

// x + s dx with s chosen so that the largest nodal displacement is `fraction` of modelSize(x)
// and the largest rotation at most 0.3 rad (mode shapes are drawn at this amplitude; the rotation
// of an Euler-parameter node is 2 |d lambda|).
Eigen::VectorXd scaledShape(const core::Model& model, const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                            double fraction = 0.12);

}  // namespace flexmb::io
