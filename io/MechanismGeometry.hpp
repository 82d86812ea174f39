#pragma once
// MechanismGeometry: the one place that turns nodal coordinates x into drawable geometry. Every
// picture of a mechanism (flexmb show, deformed configurations and mode shapes, the HTML animation,
// the ParaView series) samples its points here and projects them with project().
//
//   * Position nodes are points: (x, y, 0) for planar nodes (2 coordinates), (x, y, z) for spatial
//     ones (3 coordinates).
//   * An element with two or more position nodes is a curve. PLBEAM / PLBEAMNL are sampled with the
//     beam's own displacement field (core/elements/PlanarBeam.hpp): r(xi) = (1-xi) rp + xi rq +
//     n(alpha) (H2 e2 + H3 e3), H2 = xi (1-xi)^2, H3 = xi^2 (1-xi), so bending shows as a curve.
//     Every other element with position nodes (PLTRUSS, future spatial elements until they get a
//     shape of their own) is the polyline through its position nodes.
//   * An element without position nodes (PLHINGE) is a joint: one point at the position node its
//     orientation nodes are attached to.
//   * An orientation node is attached to the position node that precedes it in an element's node
//     list (PLBEAM p, phi_p, q, phi_q); an orientation node used only by joints takes the attachment
//     of the other orientation nodes of its joints. Unattached nodes and elements are not drawn.
//
// The point layout (which points belong to which element) is fixed when the geometry is built, so
// a time series has the same points and cells at every output time.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/Model.hpp"

namespace flexmb::io {

struct Point3 {
  double x = 0.0, y = 0.0, z = 0.0;
};
struct Point2 {
  double u = 0.0, v = 0.0;
};

enum class DrawnShape { Curve, Joint };

struct DrawnElement {
  int element = 0;  // index into Model::elements
  DrawnShape shape = DrawnShape::Curve;
  int firstPoint = 0, numPoints = 0;  // into the sampled points
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

  // Sampled points of all drawn elements at configuration x (size nx), in the fixed layout.
  void points(const Eigen::VectorXd& x, std::vector<Point3>& out) const;
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

// Projection onto the drawing plane. Planar models: (x, y). Spatial models: an isometric view
// with z up, x towards the lower left and y towards the lower right.
enum class View { Auto, XY, XZ, YZ, Isometric };
View resolveView(View requested, const MechanismGeometry& geometry);
Point2 project(const Point3& p, View view);

// The largest distance of the model's position nodes from its centre in x (at least a tiny
// positive length): the scale for mode-shape amplitudes and label offsets.
double modelSize(const core::Model& model, const Eigen::VectorXd& x);

// x + s dx with s chosen so that the largest nodal displacement is `fraction` of modelSize(x)
// and the largest rotation at most 0.3 rad (mode shapes are drawn at this amplitude).
Eigen::VectorXd scaledShape(const core::Model& model, const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                            double fraction = 0.12);

}  // namespace flexmb::io
