#include "io/pictures/MechanismGeometry.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/elements/CoRotatedCurve.hpp"
#include "core/elements/EulerParameters.hpp"

namespace flexmb::io {

namespace {
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;

// Drawn with its displacement field: the registry says which types are (planar or spatial below).
bool drawnCurved(const core::ElementEntry& el) { return el.type->drawnCurved && el.nodes.size() == 4 && el.impl; }
bool isPlanarBeam(const core::Model& m, const core::ElementEntry& el) {
  return drawnCurved(el) && m.nodes[el.nodes[1]].kind == core::NodeKind::Orientation;
}

bool isEuler(const core::Model& m, int node) { return m.nodes[node].kind == core::NodeKind::EulerParameters; }
bool isOrientation(const core::Model& m, int node) {
  return m.nodes[node].kind == core::NodeKind::Orientation || isEuler(m, node);
}

Point3 positionOf(const core::Model& m, int node, const Eigen::VectorXd& x) {
  const core::Node& n = m.nodes[node];
  Point3 p;
  const int d = n.dim();
  if (d >= 1) p.x = x[n.firstCoord];
  if (d >= 2) p.y = x[n.firstCoord + 1];
  if (d >= 3) p.z = x[n.firstCoord + 2];
  return p;
}
Vec3 vec(const Point3& p) { return {p.x, p.y, p.z}; }
Point3 point(const Vec3& v) { return {v[0], v[1], v[2]}; }

// The rotation of an Euler-parameter node at x (normalised: mode shapes x + s dx leave |lambda| != 1).
Mat3 rotationOf(const core::Model& m, int node, const Eigen::VectorXd& x) {
  Vec4 l = x.segment<4>(m.nodes[node].firstCoord);
  const double n = l.norm();
  if (!(n > 0) || !std::isfinite(n)) return Mat3::Identity();
  return core::euler::rotation(l / n);
}

// Slots (keyword order) of the element's position nodes and its Euler-parameter nodes.
void slots(const core::Model& m, const core::ElementEntry& el, std::vector<int>& pos, std::vector<int>& rot) {
  pos.clear(), rot.clear();
  for (size_t s = 0; s < el.nodes.size(); ++s) {
    if (core::isTranslational(m.nodes[el.nodes[s]].kind)) pos.push_back(el.nodes[s]);
    if (isEuler(m, el.nodes[s])) rot.push_back(el.nodes[s]);
  }
}

// A spatial element drawn with the co-rotated cubic field: two position nodes, triads at two
// Euler-parameter nodes.
bool isSpatialBeam(const core::Model& m, const core::ElementEntry& el) {
  if (!drawnCurved(el)) return false;
  std::vector<int> pos, rot;
  slots(m, el, pos, rot);
  Mat3 A;
  return pos.size() == 2 && rot.size() >= 2 && el.impl->elementFrame(0, A) && el.impl->elementFrame(1, A);
}

// The element's stiffness parameter called `name` in its ESTIFF layout, 0 when it has none.
double stiffnessParameter(const core::ElementEntry& el, const char* name) {
  const auto& spec = el.type->stiffness;
  for (size_t i = 0; i < spec.size() && i < el.stiffnessParams.size(); ++i)
    if (spec[i].name == name) return el.stiffnessParams[i];
  return 0.0;
}

// The centre line (pts) and, when ys and zs are given, the section axes of a framed element at x:
// its own field where it has one (Element::centreLine: the spatial beam), else the co-rotated
// curve through its end triads (core/elements/CoRotatedCurve.hpp; straight with one triad).
// segments + 1 points when both ends carry a triad, else 2; returns the count.
int sampleFramed(const core::Model& m, const core::ElementEntry& el, int segments, const Eigen::VectorXd& x,
                 Eigen::Matrix3Xd& pts, Eigen::Matrix3Xd* ys, Eigen::Matrix3Xd* zs) {
  std::vector<int> pos, rot;
  slots(m, el, pos, rot);
  Mat3 Ap, Aq;
  el.impl->elementFrame(0, Ap);
  const bool curved = rot.size() >= 2 && el.impl->elementFrame(1, Aq);
  const int count = curved ? segments + 1 : 2;
  pts.resize(3, count);
  if (ys && zs) ys->resize(3, count), zs->resize(3, count);
  core::ElemVec xe;
  el.gather(x, xe);
  if (curved && el.impl->centreLine(xe, pts, ys, zs)) return count;
  const Mat3 Rp = rotationOf(m, rot[0], x) * Ap;
  const Mat3 Rq = curved ? Mat3(rotationOf(m, rot[1], x) * Aq) : Rp;
  core::coRotatedCurve(vec(positionOf(m, pos[0], x)), Rp, vec(positionOf(m, pos[1], x)), Rq, el.impl->referenceLength(),
                       curved, pts, ys, zs);
  return count;
}
}  // namespace

bool MechanismGeometry::isPositionNode(int node) const { return core::isTranslational(model_.nodes[node].kind); }

DrawnSection elementSection(const core::Model& model, int element) {
  const core::ElementEntry& el = model.elements[element];
  DrawnSection s;
  const auto look = model.appearance.find(el.label);
  if (look != model.appearance.end() && look->second.section != core::ElementAppearance::Section::Unknown) {
    const bool circle = look->second.section == core::ElementAppearance::Section::Circle;
    s.kind = circle ? DrawnSection::Kind::Circle : DrawnSection::Kind::Rectangle;
    s.width = look->second.width;
    s.thickness = circle ? look->second.width : look->second.thickness;
    s.fromFile = true;
    return s;
  }
  // Radii of gyration: I/A from EM (Jyy/rhoA, Jzz/rhoA) or ESTIFF (EIy/EA, EIz/EA).
  double iy = 0.0, iz = 0.0;
  const core::ElementInertia& in = el.inertia;
  if (in.rhoA > 0 && in.jyy > 0 && in.jzz > 0) {
    iy = in.jyy / in.rhoA, iz = in.jzz / in.rhoA;
  } else {
    const double EA = stiffnessParameter(el, "EA"), EIy = stiffnessParameter(el, "EIy"),
                 EIz = stiffnessParameter(el, "EIz");
    if (EA > 0 && EIy > 0 && EIz > 0) iy = EIy / EA, iz = EIz / EA;
  }
  if (!(iy > 0 && iz > 0) || !std::isfinite(iy + iz)) return s;
  if (std::abs(iy - iz) <= 1e-6 * std::max(iy, iz)) {  // equal: drawn round (I/A = d^2/16)
    s.kind = DrawnSection::Kind::Circle;
    s.width = s.thickness = 4 * std::sqrt(iy);
  } else {  // rectangle w x t: Iz/A = w^2/12, Iy/A = t^2/12
    s.kind = DrawnSection::Kind::Rectangle;
    s.width = std::sqrt(12 * iz);
    s.thickness = std::sqrt(12 * iy);
  }
  return s;
}

MechanismGeometry::MechanismGeometry(const core::Model& model, int beamSegments)
    : model_(model), beamSegments_(std::max(1, beamSegments)), anchor_(model.nodes.size(), -1) {
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    if (core::isTranslational(model.nodes[i].kind)) {
      anchor_[i] = static_cast<int>(i);
      if (model.nodes[i].dim() >= 3) spatial_ = true;
    }
  }
  // Orientation nodes after a position node in an element's list belong to it.
  for (const auto& el : model.elements)
    for (size_t s = 1; s < el.nodes.size(); ++s)
      if (isOrientation(model, el.nodes[s]) && anchor_[el.nodes[s]] < 0 &&
          core::isTranslational(model.nodes[el.nodes[s - 1]].kind))
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
        if (anchor_[n] < 0 && isOrientation(model, n)) anchor_[n] = a, changed = true;
    }
    if (!changed) break;
  }
  std::vector<int> positions, rotations;
  Mat3 A;
  for (size_t e = 0; e < model.elements.size(); ++e) {
    const auto& el = model.elements[e];
    if (el.type->internal) continue;  // L2MIN1: no geometry of its own
    const auto look = model.appearance.find(el.label);
    if (look != model.appearance.end() && look->second.hidden) continue;
    DrawnElement d;
    d.element = static_cast<int>(e);
    d.firstPoint = numPoints_;
    slots(model, el, positions, rotations);
    if (isPlanarBeam(model, el)) {
      d.numPoints = beamSegments_ + 1;
      pointNode_.push_back(el.nodes[0]);
      for (int k = 1; k < beamSegments_; ++k) pointNode_.push_back(-1);
      pointNode_.push_back(el.nodes[2]);
    } else if (isSpatialBeam(model, el)) {
      d.numPoints = beamSegments_ + 1;
      d.framed = true;
      pointNode_.push_back(positions[0]);
      for (int k = 1; k < beamSegments_; ++k) pointNode_.push_back(-1);
      pointNode_.push_back(positions[1]);
    } else if (positions.size() >= 2) {
      d.numPoints = static_cast<int>(positions.size());
      d.framed = positions.size() == 2 && !rotations.empty() && el.impl && el.impl->elementFrame(0, A);
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
    if (d.framed) d.section = elementSection(model, d.element);
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
  Eigen::Matrix3Xd line;
  for (const DrawnElement& d : drawn_) {
    const auto& el = model_.elements[d.element];
    const bool planarCurve = d.shape == DrawnShape::Curve && isPlanarBeam(model_, el);
    const bool spatialCurve = d.framed && d.numPoints == beamSegments_ + 1 && isSpatialBeam(model_, el);
    if (planarCurve || spatialCurve) {  // the element's own field (Element::centreLine)
      line.resize(3, d.numPoints);
      el.gather(x, xe);
      if (el.impl->centreLine(xe, line)) {
        for (int k = 0; k < d.numPoints; ++k) out[d.firstPoint + k] = point(line.col(k));
        continue;
      }
    }
    for (int k = 0; k < d.numPoints; ++k) out[d.firstPoint + k] = positionOf(model_, pointNode_[d.firstPoint + k], x);
  }
}

void MechanismGeometry::sectionAxes(const Eigen::VectorXd& x, std::vector<Point3>& y, std::vector<Point3>& z) const {
  y.assign(numPoints_, Point3{});
  z.assign(numPoints_, Point3{});
  Eigen::Matrix3Xd pts, ys, zs;
  for (const DrawnElement& d : drawn_) {
    if (!d.framed || d.numPoints < 1) continue;
    // The sampler's count can differ from the drawn points (an element drawn straight whose ends
    // both carry a triad, e.g. BEAMW): its axes are spread over the drawn points, never past them.
    const int count = sampleFramed(model_, model_.elements[d.element], beamSegments_, x, pts, &ys, &zs);
    for (int k = 0; k < d.numPoints; ++k) {
      const int from =
          count == d.numPoints || d.numPoints == 1 ? std::min(k, count - 1) : (k * (count - 1)) / (d.numPoints - 1);
      y[d.firstPoint + k] = point(ys.col(from));
      z[d.firstPoint + k] = point(zs.col(from));
    }
  }
}

bool MechanismGeometry::jointAxis(const DrawnElement& d, const Eigen::VectorXd& x, Point3& axis) const {
  const auto& el = model_.elements[d.element];
  if (d.shape != DrawnShape::Joint || !el.impl) return false;
  Mat3 A;
  if (!el.impl->elementFrame(0, A)) return false;
  for (int n : el.nodes)
    if (isEuler(model_, n)) {
      axis = point(rotationOf(model_, n, x) * A.col(0));
      return true;
    }
  return false;
}

Axonometry axonometry(double azimuthDeg, double elevationDeg) {
  const double a = azimuthDeg * M_PI / 180, e = elevationDeg * M_PI / 180;
  Axonometry o;
  o.azimuth = azimuthDeg, o.elevation = elevationDeg;
  const double toViewer[3] = {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
  const double right[3] = {-std::sin(a), std::cos(a), 0.0};
  const double up[3] = {-std::sin(e) * std::cos(a), -std::sin(e) * std::sin(a), std::cos(e)};
  std::copy(toViewer, toViewer + 3, o.toViewer);
  std::copy(right, right + 3, o.right);
  std::copy(up, up + 3, o.up);
  return o;
}

Axonometry axonometry(View view) {
  switch (view) {
    case View::XZ:
      return axonometry(-90, 0);
    case View::YZ:
      return axonometry(0, 0);
    case View::Isometric:
      return axonometry(-127.5, 30);  // MATLAB's view(3): azimuth -37.5, elevation 30 degrees
    default:
      return axonometry(-90, 90);
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
      const Axonometry a = axonometry(view);
      return {a.right[0] * p.x + a.right[1] * p.y + a.right[2] * p.z, a.up[0] * p.x + a.up[1] * p.y + a.up[2] * p.z};
    }
    default:
      return {p.x, p.y};
  }
}

double depth(const Point3& p, View view) {
  switch (view) {
    case View::XZ:
      return -p.y;
    case View::YZ:
      return p.x;
    case View::Isometric: {
      const Axonometry a = axonometry(view);
      return a.toViewer[0] * p.x + a.toViewer[1] * p.y + a.toViewer[2] * p.z;
    }
    default:
      return p.z;
  }
}

const char* viewName(View view) {
  switch (view) {
    case View::XZ:
      return "xz";
    case View::YZ:
      return "yz";
    case View::Isometric:
      return "iso";
    default:
      return "xy";
  }
}

double modelSize(const core::Model& model, const Eigen::VectorXd& x) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  bool any = false;
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    if (!core::isTranslational(model.nodes[i].kind)) continue;
    const Point3 p = positionOf(model, static_cast<int>(i), x);
    const Eigen::Vector3d v(p.x, p.y, p.z);
    if (!v.allFinite()) continue;
    lo = lo.cwiseMin(v), hi = hi.cwiseMax(v), any = true;
  }
  const double r = any ? 0.5 * (hi - lo).norm() : 0.0;
  return r > 1e-12 ? r : 1.0;
}

namespace {
// The largest nodal displacement and rotation (rad) in a change dx of the nodal coordinates.
std::pair<double, double> largestMotion(const core::Model& model, const Eigen::VectorXd& dx) {
  double maxDisp = 0.0, maxRot = 0.0;
  for (const core::Node& n : model.nodes) {
    if (core::isTranslational(n.kind))
      maxDisp = std::max(maxDisp, dx.segment(n.firstCoord, n.dim()).norm());
    else if (n.kind == core::NodeKind::Orientation)  // planar angle (a warping node's rate of twist is none)
      maxRot = std::max(maxRot, std::abs(dx[n.firstCoord]));
    else if (n.kind == core::NodeKind::EulerParameters)  // |d lambda| = half the rotation angle
      maxRot = std::max(maxRot, 2 * dx.segment(n.firstCoord, 4).norm());
  }
  return {maxDisp, maxRot};
}
}  // namespace

double magnification(const core::Model& model, const Eigen::VectorXd& x0, const std::vector<Eigen::VectorXd>& xs) {
  double maxDisp = 0.0, maxRot = 0.0;
  for (const Eigen::VectorXd& x : xs) {
    if (x.size() != x0.size()) continue;
    const auto [d, r] = largestMotion(model, x - x0);
    maxDisp = std::max(maxDisp, d), maxRot = std::max(maxRot, r);
  }
  const double size = modelSize(model, x0);
  if (!(maxDisp > 0.0) || !(size > 0.0) || maxDisp >= 0.05 * size) return 1.0;
  double k = 0.12 * size / maxDisp;
  if (maxRot > 0.0) k = std::min(k, 0.3 / maxRot);
  // Down to 1, 2 or 5 times a power of ten: a factor a reader takes in at a glance.
  const double decade = std::pow(10.0, std::floor(std::log10(k)));
  const double step = k >= 5 * decade ? 5 * decade : k >= 2 * decade ? 2 * decade : decade;
  return step >= 2.0 ? step : 1.0;
}

Eigen::VectorXd scaledShape(const core::Model& model, const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                            double fraction) {
  const auto [maxDisp, maxRot] = largestMotion(model, dx);
  double s = 0.0;
  if (maxDisp > 0) s = fraction * modelSize(model, x) / maxDisp;
  if (maxRot > 0 && (s == 0.0 || s * maxRot > 0.3)) s = 0.3 / maxRot;
  if (!std::isfinite(s)) s = 0.0;
  return x + s * dx;
}

}  // namespace flexmb::io
