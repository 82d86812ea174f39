#include "io/MechanismGeometry.hpp"

#include <algorithm>
#include <cmath>

namespace flexmb::io {

namespace {
// Drawn with its displacement field (the planar beam's, below): the registry says which types are.
bool drawnCurved(const core::ElementEntry& el) { return el.type->drawnCurved && el.nodes.size() == 4 && el.impl; }

Point3 positionOf(const core::Model& m, int node, const Eigen::VectorXd& x) {
  const core::Node& n = m.nodes[node];
  Point3 p;
  const int d = n.dim();
  if (d >= 1) p.x = x[n.firstCoord];
  if (d >= 2) p.y = x[n.firstCoord + 1];
  if (d >= 3) p.z = x[n.firstCoord + 2];
  return p;
}
}  // namespace

MechanismGeometry::MechanismGeometry(const core::Model& model, int beamSegments)
    : model_(model), beamSegments_(std::max(1, beamSegments)), anchor_(model.nodes.size(), -1) {
  using core::NodeKind;
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    if (model.nodes[i].kind == NodeKind::Position) {
      anchor_[i] = static_cast<int>(i);
      if (model.nodes[i].dim() >= 3) spatial_ = true;
    }
  }
  // Orientation nodes after a position node in an element's list belong to it.
  for (const auto& el : model.elements)
    for (size_t s = 1; s < el.nodes.size(); ++s)
      if (model.nodes[el.nodes[s]].kind == NodeKind::Orientation && anchor_[el.nodes[s]] < 0 &&
          model.nodes[el.nodes[s - 1]].kind == NodeKind::Position)
        anchor_[el.nodes[s]] = el.nodes[s - 1];
  // Orientation nodes only joints use (a ground node) take their joint partners' attachment.
  for (size_t pass = 0; pass < model.elements.size(); ++pass) {
    bool changed = false;
    for (const auto& el : model.elements) {
      int a = -1;
      for (int n : el.nodes)
        if (a < 0 && anchor_[n] >= 0) a = anchor_[n];
      if (a < 0) continue;
      for (int n : el.nodes)
        if (anchor_[n] < 0 && model.nodes[n].kind == NodeKind::Orientation) anchor_[n] = a, changed = true;
    }
    if (!changed) break;
  }
  for (size_t e = 0; e < model.elements.size(); ++e) {
    const auto& el = model.elements[e];
    DrawnElement d;
    d.element = static_cast<int>(e);
    d.firstPoint = numPoints_;
    std::vector<int> positions;
    for (int n : el.nodes)
      if (model.nodes[n].kind == NodeKind::Position) positions.push_back(n);
    if (drawnCurved(el)) {
      d.numPoints = beamSegments_ + 1;
      pointNode_.push_back(el.nodes[0]);
      for (int k = 1; k < beamSegments_; ++k) pointNode_.push_back(-1);
      pointNode_.push_back(el.nodes[2]);
    } else if (positions.size() >= 2) {
      d.numPoints = static_cast<int>(positions.size());
      pointNode_.insert(pointNode_.end(), positions.begin(), positions.end());
    } else {
      d.shape = DrawnShape::Joint;
      int a = -1;
      for (int n : el.nodes)
        if (a < 0) a = anchor_[n];
      if (a < 0) continue;  // attached to nothing drawable
      d.numPoints = 1;
      pointNode_.push_back(a);
    }
    numPoints_ += d.numPoints;
    drawn_.push_back(d);
  }
}

Point3 MechanismGeometry::nodePoint(int node, const Eigen::VectorXd& x) const {
  return anchor_[node] < 0 ? Point3{} : positionOf(model_, anchor_[node], x);
}

void MechanismGeometry::points(const Eigen::VectorXd& x, std::vector<Point3>& out) const {
  out.resize(numPoints_);
  core::ElemVec xe;
  core::DefVec e;
  for (const DrawnElement& d : drawn_) {
    const auto& el = model_.elements[d.element];
    if (d.shape == DrawnShape::Curve && drawnCurved(el)) {
      // The beam's own field (PlanarBeam.hpp): chord plus n(alpha) (H2 e2 + H3 e3).
      el.gather(x, xe);
      el.impl->deformations(xe, e);
      const Point3 p = positionOf(model_, el.nodes[0], x), q = positionOf(model_, el.nodes[2], x);
      const double alpha = std::atan2(q.y - p.y, q.x - p.x);
      const double nx = -std::sin(alpha), ny = std::cos(alpha);
      const double e2 = std::isfinite(e[1]) ? e[1] : 0.0, e3 = std::isfinite(e[2]) ? e[2] : 0.0;
      for (int k = 0; k <= beamSegments_; ++k) {
        const double xi = static_cast<double>(k) / beamSegments_;
        const double w = xi * (1 - xi) * (1 - xi) * e2 + xi * xi * (1 - xi) * e3;
        out[d.firstPoint + k] = {(1 - xi) * p.x + xi * q.x + nx * w, (1 - xi) * p.y + xi * q.y + ny * w,
                                 (1 - xi) * p.z + xi * q.z};
      }
    } else {
      for (int k = 0; k < d.numPoints; ++k) out[d.firstPoint + k] = positionOf(model_, pointNode_[d.firstPoint + k], x);
    }
  }
}

View resolveView(View requested, const MechanismGeometry& geometry) {
  if (requested != View::Auto) return requested;
  return geometry.spatial() ? View::Isometric : View::XY;
}

Point2 project(const Point3& p, View view) {
  switch (view) {
    case View::XZ:
      return {p.x, p.z};
    case View::YZ:
      return {p.y, p.z};
    case View::Isometric: {
      // z up, x towards the lower left, y towards the lower right (30 degrees below horizontal).
      const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
      return {c * (p.y - p.x), p.z - s * (p.x + p.y)};
    }
    default:
      return {p.x, p.y};
  }
}

double modelSize(const core::Model& model, const Eigen::VectorXd& x) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  bool any = false;
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    if (model.nodes[i].kind != core::NodeKind::Position) continue;
    const Point3 p = positionOf(model, static_cast<int>(i), x);
    const Eigen::Vector3d v(p.x, p.y, p.z);
    if (!v.allFinite()) continue;
    lo = lo.cwiseMin(v), hi = hi.cwiseMax(v), any = true;
  }
  const double r = any ? 0.5 * (hi - lo).norm() : 0.0;
  return r > 1e-12 ? r : 1.0;
}

Eigen::VectorXd scaledShape(const core::Model& model, const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                            double fraction) {
  double maxDisp = 0.0, maxRot = 0.0;
  for (const core::Node& n : model.nodes) {
    if (n.kind == core::NodeKind::Position)
      maxDisp = std::max(maxDisp, dx.segment(n.firstCoord, n.dim()).norm());
    else if (n.kind == core::NodeKind::Orientation)  // planar angle; Euler parameters, warping: not angles
      maxRot = std::max(maxRot, std::abs(dx[n.firstCoord]));
  }
  double s = 0.0;
  if (maxDisp > 0) s = fraction * modelSize(model, x) / maxDisp;
  if (maxRot > 0 && (s == 0.0 || s * maxRot > 0.3)) s = 0.3 / maxRot;
  if (!std::isfinite(s)) s = 0.0;
  return x + s * dx;
}

}  // namespace flexmb::io
