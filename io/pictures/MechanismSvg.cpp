#include "io/pictures/MechanismSvg.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>

#include <Eigen/Geometry>

#include "io/formats/TextOutput.hpp"

namespace flexmb::io {

namespace {
constexpr std::array<const char*, 7> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000"};
constexpr double kCharWidth = 6.2;

std::string num(double v) { return shortNumber(std::round(v * 100) / 100, 8); }

const char* elementColor(const std::string& role) {
  if (role == "input") return "#CC79A7";
  if (role == "DOF") return "#0072B2";
  if (role == "released") return "#009E73";
  return "#444444";
}

const char* nodeColor(const std::string& role) {
  if (role == "input") return "#CC79A7";
  if (role == "DOF") return "#D55E00";
  if (role == "fixed" || role == "partly fixed") return "#000000";
  return "#444444";
}

// World (projected) to pixels: equal scale, v up, centred in a box.
struct Frame {
  double umin = 0, vmin = 0, scale = 1, left = 0, top = 0, width = 1, height = 1, uc = 0, vc = 0;
  double px(const Point2& p) const { return left + width / 2 + (p.u - uc) * scale; }
  double py(const Point2& p) const { return top + height / 2 - (p.v - vc) * scale; }
};

Frame fit(const std::vector<Point2>& pts, double left, double top, double width, double height, double margin) {
  Frame f;
  f.left = left, f.top = top, f.width = width, f.height = height;
  double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
  for (const Point2& p : pts) {
    if (!std::isfinite(p.u) || !std::isfinite(p.v)) continue;
    u0 = std::min(u0, p.u), u1 = std::max(u1, p.u), v0 = std::min(v0, p.v), v1 = std::max(v1, p.v);
  }
  if (!(u0 <= u1)) u0 = v0 = -1, u1 = v1 = 1;
  const double span = std::max({u1 - u0, v1 - v0, 1e-12});
  const double du = std::max(u1 - u0, 1e-3 * span), dv = std::max(v1 - v0, 1e-3 * span);
  f.scale = std::min((width - 2 * margin) / du, (height - 2 * margin) / dv);
  f.uc = 0.5 * (u0 + u1), f.vc = 0.5 * (v0 + v1);
  return f;
}

std::vector<Point2> projected(const MechanismGeometry& g, const Eigen::VectorXd& x, View view) {
  std::vector<Point3> p3;
  g.points(x, p3);
  std::vector<Point2> p2(p3.size());
  for (size_t i = 0; i < p3.size(); ++i) p2[i] = project(p3[i], view);
  return p2;
}

// One polyline / joint circle per drawn element.
std::string drawElements(const MechanismGeometry& g, const std::vector<Point2>& pts, const Frame& f,
                         const std::string& color, double width, bool dashed, bool perRoleColor) {
  std::string o;
  for (const DrawnElement& d : g.elements()) {
    const std::string c = perRoleColor ? elementColor(elementRole(g.model(), d.element)) : color;
    if (d.shape == DrawnShape::Joint) {
      const Point2& p = pts[d.firstPoint];
      o += "<circle class=\"joint\" cx=\"" + num(f.px(p)) + "\" cy=\"" + num(f.py(p)) + "\" r=\"" + num(2.2 * width) +
           "\" fill=\"none\" stroke=\"" + c + "\" stroke-width=\"" + num(0.6 * width) + "\"" +
           (dashed ? " stroke-dasharray=\"3 2\"" : "") + "/>\n";
      continue;
    }
    o += "<polyline class=\"element\" fill=\"none\" stroke=\"" + c + "\" stroke-width=\"" + num(width) +
         "\" stroke-linecap=\"round\" stroke-linejoin=\"round\"" + (dashed ? " stroke-dasharray=\"6 4\"" : "") +
         " points=\"";
    for (int k = 0; k < d.numPoints; ++k) {
      const Point2& p = pts[d.firstPoint + k];
      if (k) o += ' ';
      o += num(f.px(p)) + "," + num(f.py(p));
    }
    o += "\"/>\n";
  }
  return o;
}

// Spatial models: every element as 3-D primitives (faces of its cross-section along the axis,
// polylines, joints with their axis), drawn far to near (painter's order).
struct Primitive {
  std::vector<Point3> pts;  // polygon (closed) or polyline
  bool closed = false;
  bool joint = false;
  double depth = 0.0;
  std::string color;   // base colour
  double shade = 1.0;  // 0..1, faces only
  int element = 0;     // label
};

std::string shaded(const std::string& hex, double f) {
  // f < 1 darkens, f > 1 lightens towards white.
  auto ch = [&](int k) { return std::stoi(hex.substr(1 + 2 * k, 2), nullptr, 16); };
  char buf[8];
  int c[3];
  for (int k = 0; k < 3; ++k) {
    const double v = f <= 1 ? ch(k) * f : ch(k) + (255 - ch(k)) * (f - 1);
    c[k] = static_cast<int>(std::lround(std::clamp(v, 0.0, 255.0)));
  }
  std::snprintf(buf, sizeof buf, "#%02X%02X%02X", c[0], c[1], c[2]);
  return buf;
}

void spatialPrimitives(const MechanismGeometry& g, const Eigen::VectorXd& x, View view,
                       const std::function<std::string(int)>& colorOf, bool sections, std::vector<Primitive>& out) {
  std::vector<Point3> p, ys, zs;
  g.points(x, p);
  if (sections) g.sectionAxes(x, ys, zs);
  // The light: from the viewer, tilted to the upper left of the picture (as the HTML page).
  const Axonometry ax = axonometry(view);
  const Eigen::Vector3d toViewer(ax.toViewer), up(ax.up), right(ax.right);
  const Eigen::Vector3d light = (toViewer + 0.5 * up - 0.4 * right).normalized();
  auto v3 = [](const Point3& a) { return Eigen::Vector3d(a.x, a.y, a.z); };
  auto pt = [](const Eigen::Vector3d& a) { return Point3{a[0], a[1], a[2]}; };
  for (const DrawnElement& d : g.elements()) {
    const int label = g.model().elements[d.element].label;
    const std::string c = colorOf(d.element);
    if (d.shape == DrawnShape::Joint) {
      Primitive j;
      j.joint = true;
      j.pts.push_back(p[d.firstPoint]);
      Point3 axis;
      if (g.jointAxis(d, x, axis)) {
        const double a = 0.04 * modelSize(g.model(), x);
        const Eigen::Vector3d o = v3(p[d.firstPoint]), u = v3(axis);
        j.pts.push_back(pt(o - a * u));
        j.pts.push_back(pt(o + a * u));
      }
      j.depth = depth(p[d.firstPoint], view) + 1e-9;  // over the elements that meet there
      j.color = c;
      j.element = label;
      out.push_back(j);
      continue;
    }
    const bool solid = sections && d.framed && d.section.kind != DrawnSection::Kind::Line;
    if (!solid) {
      Primitive l;
      l.pts.assign(p.begin() + d.firstPoint, p.begin() + d.firstPoint + d.numPoints);
      double dep = 0.0;
      for (const Point3& q : l.pts) dep += depth(q, view);
      l.depth = dep / static_cast<double>(l.pts.size());
      l.color = c;
      l.element = label;
      out.push_back(l);
      continue;
    }
    // Section outline in (y, z): a rectangle, or a circle as 12 sides.
    std::vector<std::pair<double, double>> outline;
    if (d.section.kind == DrawnSection::Kind::Rectangle) {
      const double a = 0.5 * d.section.width, b = 0.5 * d.section.thickness;
      outline = {{a, b}, {-a, b}, {-a, -b}, {a, -b}};
    } else {
      const double r = 0.5 * d.section.width;
      for (int k = 0; k < 12; ++k) outline.push_back({r * std::cos(k * M_PI / 6), r * std::sin(k * M_PI / 6)});
    }
    const size_t ns = outline.size();
    auto corner = [&](int k, size_t s) -> Eigen::Vector3d {
      const int i = d.firstPoint + k;
      return v3(p[i]) + outline[s].first * v3(ys[i]) + outline[s].second * v3(zs[i]);
    };
    for (int k = 0; k + 1 < d.numPoints; ++k)
      for (size_t s = 0; s < ns; ++s) {
        const size_t t = (s + 1) % ns;
        const Eigen::Vector3d a = corner(k, s), b = corner(k, t), cc = corner(k + 1, t), dd = corner(k + 1, s);
        Primitive f;
        f.closed = true;
        f.pts = {pt(a), pt(b), pt(cc), pt(dd)};
        f.depth = depth(pt(0.25 * (a + b + cc + dd)), view);
        Eigen::Vector3d nrm = (cc - a).cross(dd - b);
        const double nn = nrm.norm();
        f.shade = nn > 0 ? 0.55 + 0.6 * std::abs(nrm.dot(light)) / nn : 1.0;
        f.color = c;
        f.element = label;
        out.push_back(f);
      }
    // End caps.
    for (int k : {0, d.numPoints - 1}) {
      Primitive f;
      f.closed = true;
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (size_t s = 0; s < ns; ++s) {
        f.pts.push_back(pt(corner(k, s)));
        centre += corner(k, s);
      }
      f.depth = depth(pt(centre / static_cast<double>(ns)), view);
      const Eigen::Vector3d t = v3(zs[d.firstPoint + k]).cross(v3(ys[d.firstPoint + k]));
      f.shade = 0.55 + 0.6 * std::abs(t.dot(light));
      f.color = c;
      f.element = label;
      out.push_back(f);
    }
  }
}

// The primitives as SVG, far to near; dashed: a reference configuration (lines only).
std::string drawPrimitives(std::vector<Primitive>& prims, View view, const Frame& f, double width, bool dashed) {
  std::stable_sort(prims.begin(), prims.end(),
                   [](const Primitive& a, const Primitive& b) { return a.depth < b.depth; });
  std::string o;
  for (const Primitive& q : prims) {
    if (q.joint) {
      const Point2 c = project(q.pts[0], view);
      if (q.pts.size() == 3) {
        const Point2 a = project(q.pts[1], view), b = project(q.pts[2], view);
        o += "<line class=\"joint-axis\" x1=\"" + num(f.px(a)) + "\" y1=\"" + num(f.py(a)) + "\" x2=\"" + num(f.px(b)) +
             "\" y2=\"" + num(f.py(b)) + "\" stroke=\"" + q.color + "\" stroke-width=\"" + num(0.8 * width) + "\"" +
             (dashed ? " stroke-dasharray=\"3 2\"" : "") + "/>\n";
      }
      o += "<circle class=\"joint\" data-element=\"" + std::to_string(q.element) + "\" cx=\"" + num(f.px(c)) +
           "\" cy=\"" + num(f.py(c)) + "\" r=\"" + num(2.2 * width) + "\" fill=\"" + (dashed ? "none" : "white") +
           "\" stroke=\"" + q.color + "\" stroke-width=\"" + num(0.6 * width) + "\"" +
           (dashed ? " stroke-dasharray=\"3 2\"" : "") + "/>\n";
      continue;
    }
    std::string pts;
    for (size_t k = 0; k < q.pts.size(); ++k) {
      const Point2 a = project(q.pts[k], view);
      if (k) pts += ' ';
      ((pts += num(f.px(a))) += ',') += num(f.py(a));
    }
    if (q.closed) {
      const std::string fill = shaded(q.color, q.shade);
      o += "<polygon class=\"face\" data-element=\"" + std::to_string(q.element) + "\" points=\"" + pts + "\" fill=\"" +
           fill + "\" stroke=\"" + fill + "\" stroke-width=\"0.5\" stroke-linejoin=\"round\"/>\n";
    } else {
      o += "<polyline class=\"element\" data-element=\"" + std::to_string(q.element) + "\" fill=\"none\" stroke=\"" +
           q.color + "\" stroke-width=\"" + num(width) + "\" stroke-linecap=\"round\" stroke-linejoin=\"round\"" +
           (dashed ? " stroke-dasharray=\"6 4\"" : "") + " points=\"" + pts + "\"/>\n";
    }
  }
  return o;
}

// Every projected point of the primitives (for the fit).
void projectedPoints(const std::vector<Primitive>& prims, View view, std::vector<Point2>& out) {
  for (const Primitive& q : prims)
    for (const Point3& p : q.pts) out.push_back(project(p, view));
}

std::string text(double x, double y, const std::string& s, const std::string& attrs = "") {
  return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\"" + (attrs.empty() ? "" : " " + attrs) + ">" + xmlEscape(s) +
         "</text>\n";
}

std::string header(double w, double h) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(w) +
         "\" height=\"" + num(h) + "\" viewBox=\"0 0 " + num(w) + " " + num(h) +
         "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" "
         "fill=\"white\"/>\n";
}

std::string nodeMarker(double x, double y, const std::string& role) {
  const std::string c = nodeColor(role);
  if (role == "fixed" || role == "partly fixed") {  // a ground triangle under the node
    const std::string fill = role == "fixed" ? "#000000" : "white";
    return "<polygon class=\"node " + role + "\" points=\"" + num(x) + "," + num(y) + " " + num(x - 7) + "," +
           num(y + 11) + " " + num(x + 7) + "," + num(y + 11) + "\" fill=\"" + fill +
           "\" fill-opacity=\"0.35\" stroke=\"" + c + "\" stroke-width=\"1.2\"/>\n<circle cx=\"" + num(x) + "\" cy=\"" +
           num(y) + "\" r=\"3\" fill=\"white\" stroke=\"black\" stroke-width=\"1.2\"/>\n";
  }
  if (role == "input")
    return "<polygon class=\"node input\" points=\"" + num(x) + "," + num(y - 6) + " " + num(x + 6) + "," + num(y) +
           " " + num(x) + "," + num(y + 6) + " " + num(x - 6) + "," + num(y) + "\" fill=\"" + c +
           "\" stroke=\"black\"/>\n";
  if (role == "DOF")
    return "<circle class=\"node DOF\" cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"4.5\" fill=\"" + c +
           "\" stroke=\"black\"/>\n";
  return "<circle class=\"node free\" cx=\"" + num(x) + "\" cy=\"" + num(y) +
         "\" r=\"3.5\" fill=\"white\" stroke=\"#444444\" stroke-width=\"1.2\"/>\n";
}

std::string coordinateList(const core::Model& m, int node) {
  const core::Node& n = m.nodes[node];
  if (n.kind == core::NodeKind::Orientation && n.dim() == 1) return coordinateRoleWord(m.xRole[n.firstCoord]);
  bool same = true;
  for (int i = 1; i < n.dim(); ++i) same = same && m.xRole[n.firstCoord + i] == m.xRole[n.firstCoord];
  if (same) return coordinateRoleWord(m.xRole[n.firstCoord]);
  static const char* names[] = {"x", "y", "z"};
  static const char* lambdas[] = {"\u03bb0", "\u03bb1", "\u03bb2", "\u03bb3"};
  std::string s;
  for (int i = 0; i < n.dim(); ++i) {
    if (i) s += ", ";
    if (core::isTranslational(n.kind) && i < 3)
      s += names[i];
    else if (n.kind == core::NodeKind::EulerParameters && i < 4)
      s += lambdas[i];
    else
      s += std::to_string(i + 1);
    s += std::string(" ") + coordinateRoleWord(m.xRole[n.firstCoord + i]);
  }
  return s;
}

// The symbol of a node's coordinates other than a position: theta (planar angle), lambda (Euler
// parameters) or w (a BEAMW warping node's rate of twist).
const char* orientationSymbol(const core::Node& n) {
  return n.kind == core::NodeKind::EulerParameters ? "\u03bb" : n.kind == core::NodeKind::Warping ? "w" : "\u03b8";
}

// A small triad of the global axes in the corner of a spatial picture (x, y, z as projected).
std::string axisTriad(View view, double x0, double y0) {
  std::string o = "<g class=\"axes\" font-size=\"10\">\n";
  const char* names[] = {"x", "y", "z"};
  const Point3 dirs[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int k = 0; k < 3; ++k) {
    const Point2 d = project(dirs[k], view);
    const double len = std::hypot(d.u, d.v);
    if (len < 1e-9) {  // along the line of sight: a dot
      o += "<circle cx=\"" + num(x0) + "\" cy=\"" + num(y0) + "\" r=\"2\" fill=\"#555555\"/>\n";
      o += text(x0 + 4, y0 - 4, names[k], "fill=\"#555555\"");
      continue;
    }
    const double x1 = x0 + 26 * d.u, y1 = y0 - 26 * d.v;
    o += "<line x1=\"" + num(x0) + "\" y1=\"" + num(y0) + "\" x2=\"" + num(x1) + "\" y2=\"" + num(y1) +
         "\" stroke=\"#555555\" stroke-width=\"1.2\"/>\n";
    o += text(x0 + 33 * d.u, y0 - 33 * d.v + 4, names[k], "text-anchor=\"middle\" fill=\"#555555\"");
  }
  return o + "</g>\n";
}
}  // namespace

const char* deformationRoleWord(core::Role r) {
  switch (r) {
    case core::Role::Fixed:
      return "rigid";
    case core::Role::Input:
      return "input";
    case core::Role::Dynamic:
      return "DOF";
    case core::Role::Calculable:
      return "released";
  }
  return "?";
}

const char* coordinateRoleWord(core::Role r) {
  switch (r) {
    case core::Role::Fixed:
      return "fixed";
    case core::Role::Input:
      return "input";
    case core::Role::Dynamic:
      return "DOF";
    case core::Role::Calculable:
      return "free";
  }
  return "?";
}

std::string nodeRole(const core::Model& m, int node) {
  const core::Node& n = m.nodes[node];
  int fixed = 0;
  bool input = false, dof = false;
  for (int i = 0; i < n.dim(); ++i) {
    const core::Role r = m.xRole[n.firstCoord + i];
    fixed += r == core::Role::Fixed;
    input = input || r == core::Role::Input;
    dof = dof || r == core::Role::Dynamic;
  }
  if (input) return "input";
  if (dof) return "DOF";
  if (fixed == n.dim()) return "fixed";
  if (fixed > 0) return "partly fixed";
  return "free";
}

std::string elementRole(const core::Model& m, int element) {
  const core::ElementEntry& el = m.elements[element];
  bool input = false, dof = false, released = false;
  // A BEAMW's warping is released wherever the section may warp, also in a body that is otherwise
  // rigid: the element's role is that of its other deformations.
  bool onlyWarping = true;
  for (int i = 0; i < el.type->numDeformations(); ++i)
    onlyWarping = onlyWarping && el.type->deformationKind(i) == core::DeformationKind::Warping;
  for (int i = 0; i < el.type->numDeformations(); ++i) {
    if (!onlyWarping && el.type->deformationKind(i) == core::DeformationKind::Warping) continue;
    const core::Role r = m.eRole[el.firstDef + i];
    input = input || r == core::Role::Input;
    dof = dof || r == core::Role::Dynamic;
    released = released || r == core::Role::Calculable;
  }
  return input ? "input" : dof ? "DOF" : released ? "released" : "rigid";
}

namespace {

using TableRows = std::vector<std::pair<std::string, std::string>>;  // (text, colour)

// The table: one line per node and per element.
TableRows modelTable(const core::Model& m) {
  TableRows rows;
  rows.push_back({"nodes (coordinates: role)", "#000000"});
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const core::Node& n = m.nodes[i];
    std::string s = (core::isTranslational(n.kind) ? std::string("  ") : "  " + std::string(orientationSymbol(n))) +
                    std::to_string(n.label) + " (";
    for (int c = 0; c < n.dim(); ++c) s += (c ? ", " : "") + shortNumber(m.x0[n.firstCoord + c], 5);
    s += "): " + coordinateList(m, static_cast<int>(i));
    rows.push_back({s, nodeColor(nodeRole(m, static_cast<int>(i)))});
  }
  rows.push_back({"", "#000000"});
  rows.push_back({"elements (nodes; deformations: role)", "#000000"});
  int internal = 0;
  for (size_t e = 0; e < m.elements.size(); ++e) {
    const core::ElementEntry& el = m.elements[e];
    if (el.type->internal) {  // flexmb's own (the Euler parameters' normalisation), not the user's
      ++internal;
      continue;
    }
    std::string s = "  " + std::to_string(el.label) + " " + el.type->keyword + " (";
    for (size_t k = 0; k < el.nodes.size(); ++k) {  // piecewise: GCC 12's -Wrestrict (tools/README.md)
      if (k) s += ' ';
      s += std::to_string(m.nodes[el.nodes[k]].label);
    }
    s += "): ";
    for (int d = 0; d < el.type->numDeformations(); ++d)
      s += (d ? ", " : "") + el.type->deformationNames[d] + " " + deformationRoleWord(m.eRole[el.firstDef + d]);
    // Long rows (a BEAMW has eight deformations) continue on indented lines after a comma.
    const std::string colour = elementColor(elementRole(m, static_cast<int>(e)));
    constexpr size_t kRowChars = 100;
    while (s.size() > kRowChars) {
      const size_t cut = s.rfind(", ", kRowChars);
      if (cut == std::string::npos || cut < 8) break;
      rows.push_back({s.substr(0, cut + 1), colour});
      s = "      " + s.substr(cut + 2);
    }
    rows.push_back({s, colour});
  }
  if (internal)
    rows.push_back({"  (and " + std::to_string(internal) +
                        " normalisation constraints of the Euler parameters that flexmb adds, not listed)",
                    "#555555"});
  return rows;
}

// Where the drawing, its legend and the table go.
struct ModelLayout {
  double drawW = 720, top = 0, legendH = 74, drawH = 0, tableX = 0, tableY = 0, W = 0, H = 0;
};

ModelLayout modelLayout(const TableRows& rows, size_t notes) {
  size_t longest = 0;
  for (const auto& r : rows) longest = std::max(longest, r.first.size());
  ModelLayout l;
  const double tableW = std::clamp(20 + kCharWidth * 0.95 * static_cast<double>(longest), 200.0, 900.0);
  l.top = 40 + 14.0 * static_cast<double>(notes) + 10;
  // Beside the drawing while the table is about as tall; below it for a large model, so that the
  // first screen shows the mechanism and not a column of node rows.
  const double tableH = 14.0 * static_cast<double>(rows.size()) + 20;
  const bool tableBelow = tableH > 480.0 + l.legendH + 140.0;
  l.drawH = tableBelow ? 480.0 : std::max(480.0, tableH - l.legendH);
  l.tableX = tableBelow ? 20.0 : l.drawW, l.tableY = tableBelow ? l.top + l.drawH + l.legendH + 10 : l.top;
  l.W = tableBelow ? std::max(l.drawW, 20 + tableW) : l.drawW + tableW;
  l.H = tableBelow ? l.tableY + tableH : l.top + l.drawH + l.legendH;
  return l;
}

// The title and the lines under it, centred on a picture W wide.
std::string titleLines(double W, const std::string& title, const std::vector<std::string>& notes) {
  std::string o = text(W / 2, 24, title, "text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\"");
  for (size_t i = 0; i < notes.size(); ++i)
    o += text(W / 2, 42 + 14.0 * static_cast<double>(i), notes[i],
              "class=\"note\" text-anchor=\"middle\" fill=\"#555555\"");
  return o;
}

// The model in its initial configuration: its projected points, the frame that fits them (and the
// nodes and solids) into the drawing's box, and the elements drawn.
struct ModelPicture {
  std::vector<Point2> pts;
  Frame f;
  std::string elements;
};

ModelPicture drawModel(const MechanismGeometry& g, View view, const ModelLayout& l) {
  const core::Model& m = g.model();
  ModelPicture pic;
  pic.pts = projected(g, m.x0, view);
  std::vector<Point2> all = pic.pts;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (g.anchor(static_cast<int>(i)) >= 0) all.push_back(project(g.nodePoint(static_cast<int>(i), m.x0), view));
  std::vector<Primitive> prims;
  if (g.spatial()) {
    spatialPrimitives(
        g, m.x0, view, [&](int e) { return std::string(elementColor(elementRole(m, e))); }, true, prims);
    projectedPoints(prims, view, all);
  }
  pic.f = fit(all, 10, l.top, l.drawW - 20, l.drawH, 50);
  if (g.spatial())
    pic.elements = "<g class=\"elements\">\n" + drawPrimitives(prims, view, pic.f, 3, false) + "</g>\n";
  else
    pic.elements = "<g class=\"elements\">\n" + drawElements(g, pic.pts, pic.f, "", 3, false, true) + "</g>\n";
  return pic;
}

// Element numbers in brackets at the middle of each element, offset to its left side; on large
// models (thin) a number that would overlap one already placed is left out (counted in `thinned`).
std::string elementNumbers(const MechanismGeometry& g, const ModelPicture& pic, const std::string& halo, bool thin,
                           int& thinned) {
  const core::Model& m = g.model();
  const std::vector<Point2>& pts = pic.pts;
  const Frame& f = pic.f;
  std::string o = "<g class=\"element-labels\" font-size=\"10\">\n";
  std::vector<Point2> elementLabels;
  for (const DrawnElement& d : g.elements()) {
    const core::ElementEntry& el = m.elements[d.element];
    const std::string c = elementColor(elementRole(m, d.element));
    double x, y;
    if (d.shape == DrawnShape::Joint) {
      x = f.px(pts[d.firstPoint]) - 16, y = f.py(pts[d.firstPoint]) - 6;
    } else {
      const int a = d.firstPoint + (d.numPoints - 1) / 2, b = d.firstPoint + d.numPoints / 2;
      const double xa = f.px(pts[a]), ya = f.py(pts[a]), xb = f.px(pts[b]), yb = f.py(pts[b]);
      const double xe = f.px(pts[d.firstPoint + d.numPoints - 1]) - f.px(pts[d.firstPoint]);
      const double ye = f.py(pts[d.firstPoint + d.numPoints - 1]) - f.py(pts[d.firstPoint]);
      const double len = std::max(std::hypot(xe, ye), 1e-9);
      x = 0.5 * (xa + xb) + 10 * ye / len, y = 0.5 * (ya + yb) - 10 * xe / len + 4;
    }
    // Like the node numbers: a number that would overlap one already placed is left out.
    if (thin && std::any_of(elementLabels.begin(), elementLabels.end(),
                            [&](const Point2& q) { return std::abs(q.u - x) < 18.0 && std::abs(q.v - y) < 12.0; })) {
      ++thinned;
      continue;
    }
    elementLabels.push_back({x, y});
    o += text(x, y, "[" + std::to_string(el.label) + "]",
              "text-anchor=\"middle\" fill=\"" + std::string(c) + "\"" + halo);
  }
  return o + "</g>\n";
}

// Nodes: markers and numbers; orientation nodes listed beside the position node they belong to. On
// large models (thin) numbers that would overlap one already placed are left out (every node is in
// the table), said under the drawing (at noteY) with the element numbers left out.
std::string nodeNumbers(const MechanismGeometry& g, View view, const Frame& f, const std::string& halo, bool thin,
                        int thinnedElements, double noteY) {
  const core::Model& m = g.model();
  std::map<int, std::vector<int>> orientationAt;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!g.isPositionNode(static_cast<int>(i)) && g.anchor(static_cast<int>(i)) >= 0)
      orientationAt[g.anchor(static_cast<int>(i))].push_back(static_cast<int>(i));
  // Those of nodes with a role first, then the free ones in order, so an edge-on leaf keeps some.
  std::vector<size_t> order;
  for (int pass = 0; pass < 2; ++pass)
    for (size_t i = 0; i < m.nodes.size(); ++i)
      if (g.isPositionNode(static_cast<int>(i)) && (nodeRole(m, static_cast<int>(i)) == "free") == (pass == 1))
        order.push_back(i);
  std::vector<Point2> placed;
  int thinned = 0;
  std::string o = "<g class=\"nodes\">\n";
  for (const size_t i : order) {
    const Point2 p = project(g.nodePoint(static_cast<int>(i), m.x0), view);
    const double x = f.px(p), y = f.py(p);
    const std::string role = nodeRole(m, static_cast<int>(i));
    o += nodeMarker(x, y, role);
    const bool crowded = std::any_of(placed.begin(), placed.end(), [&](const Point2& q) {
      return std::abs(q.u - x) < 16.0 && std::abs(q.v - y) < 12.0;
    });
    if (thin && crowded) {
      ++thinned;
      continue;
    }
    placed.push_back({x, y});
    o += text(x + 6, y - 6, std::to_string(m.nodes[i].label),
              "font-weight=\"bold\" fill=\"" + std::string(nodeColor(role)) + "\"" + halo);
    auto it = orientationAt.find(static_cast<int>(i));
    if (it == orientationAt.end()) continue;
    // Below left of the node: element numbers sit on the other side of their elements.
    o += "<text x=\"" + num(x - 6) + "\" y=\"" + num(y + 18) + "\" font-size=\"9.5\" text-anchor=\"end\"" + halo + ">" +
         orientationSymbol(m.nodes[it->second.front()]);
    for (size_t k = 0; k < it->second.size(); ++k) {
      const int n = it->second[k];
      o += std::string(k ? "," : "") + "<tspan fill=\"" + nodeColor(nodeRole(m, n)) + "\">" +
           std::to_string(m.nodes[n].label) + "</tspan>";
    }
    o += "</text>\n";
  }
  if (thinned || thinnedElements)
    o += text(90, noteY,
              std::to_string(thinned) + " node and " + std::to_string(thinnedElements) +
                  " element numbers left out where they would overlap (every one is in the table)",
              "fill=\"#555555\" font-size=\"10\"");
  return o + "</g>\n";
}

// The legend under the drawing (its first line at ly): element and node roles, the orientation
// nodes' symbol and a spatial model's view.
std::string modelLegend(const core::Model& m, View view, bool spatial, double ly) {
  double lx = 20;
  std::string warpingNote;
  for (const core::Node& n : m.nodes)
    if (n.kind == core::NodeKind::Warping) warpingNote = "w: warping nodes (BEAMW's rate of twist); ";
  std::string o = "<g class=\"legend\" font-size=\"10\">\n";
  for (const char* r : {"rigid", "DOF", "released", "input"}) {
    o += "<line x1=\"" + num(lx) + "\" y1=\"" + num(ly) + "\" x2=\"" + num(lx + 22) + "\" y2=\"" + num(ly) +
         "\" stroke=\"" + elementColor(r) + "\" stroke-width=\"3\"/>\n";
    o += text(lx + 26, ly + 4, std::string("element: ") + r);
    lx += 135;
  }
  lx = 20;
  for (const char* r : {"fixed", "partly fixed", "input", "DOF", "free"}) {
    o += nodeMarker(lx + 8, ly + 20, r);
    o += text(lx + 20, ly + 24, std::string("node: ") + r);
    lx += 135;
  }
  o += text(20, ly + 44,
            spatial ? "\u03bb: orientation nodes (Euler parameters) attached there; " + warpingNote + "view " +
                          std::string(viewName(view)) +
                          (view == View::Isometric ? " (azimuth -37.5, elevation 30 degrees, as MATLAB's view(3))" : "")
                    : std::string("\u03b8: orientation nodes attached there"),
            "fill=\"#555555\"");
  return o + "</g>\n";
}

std::string tableText(const TableRows& rows, double x, double y) {
  std::string o = "<g class=\"table\" font-family=\"DejaVu Sans Mono, monospace\" font-size=\"10\">\n";
  for (size_t i = 0; i < rows.size(); ++i)
    o += text(x, y + 10 + 14.0 * static_cast<double>(i), rows[i].first,
              "fill=\"" + rows[i].second + "\"" +
                  (i == 0 || rows[i].first.rfind("elements", 0) == 0 ? " font-weight=\"bold\"" : ""));
  return o + "</g>\n";
}

}  // namespace

std::string renderModelSvg(const MechanismGeometry& g, const ModelDrawing& drawing) {
  const View view = resolveView(drawing.view, g);
  const TableRows rows = modelTable(g.model());
  const ModelLayout l = modelLayout(rows, drawing.notes.size());
  std::string o = header(l.W, l.H) + titleLines(l.W, drawing.title, drawing.notes);
  const ModelPicture pic = drawModel(g, view, l);
  o += pic.elements;
  // Labels over the drawn solids of a spatial model get a white halo.
  const std::string halo = g.spatial() ? " stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"" : "";
  // Numbers are thinned on large models only: a small one keeps every number, overlapping or not.
  const bool thin = g.elements().size() > 20;
  int thinnedElements = 0;
  o += elementNumbers(g, pic, halo, thin, thinnedElements);
  o += nodeNumbers(g, view, pic.f, halo, thin, thinnedElements, l.top + l.drawH - 8);
  o += modelLegend(g.model(), view, g.spatial(), l.top + l.drawH + 18);
  if (g.spatial()) o += axisTriad(view, 40, l.top + l.drawH - 30);
  return o + tableText(rows, l.tableX, l.tableY) + "</svg>\n";
}

namespace {
// The share of the vectors' total length that survives the projection (1 for none).
double seenShare(const std::vector<Point3>& v, View view) {
  double all = 0.0, seen = 0.0;
  for (const Point3& d : v) {
    all += std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    const Point2 p = project(d, view);
    seen += std::hypot(p.u, p.v);
  }
  return all > 0.0 ? seen / all : 1.0;
}

// The drawn points of configuration x: the sampled axis points and, of elements drawn as solids,
// their sections' corners (a leaf's twist moves its edges, not its axis).
void drawnPoints(const MechanismGeometry& g, const Eigen::VectorXd& x, std::vector<Point3>& out) {
  std::vector<Point3> p, ys, zs;
  g.points(x, p);
  g.sectionAxes(x, ys, zs);
  out = p;
  for (const DrawnElement& d : g.elements()) {
    if (d.shape != DrawnShape::Curve || !d.framed || d.section.kind == DrawnSection::Kind::Line) continue;
    const bool circle = d.section.kind == DrawnSection::Kind::Circle;
    const double a = 0.5 * d.section.width, b = circle ? a : 0.5 * d.section.thickness;
    for (int i = d.firstPoint; i < d.firstPoint + d.numPoints; ++i)
      for (const double sa : {-a, a})
        for (const double sb : {-b, b})
          out.push_back({p[i].x + sa * ys[i].x + sb * zs[i].x, p[i].y + sa * ys[i].y + sb * zs[i].y,
                         p[i].z + sa * ys[i].z + sb * zs[i].z});
  }
}
}  // namespace

View panelView(const MechanismGeometry& g, const ShapePanel& panel, View requested) {
  if (requested != View::Auto || !g.spatial()) return resolveView(requested, g);
  const ShapeLayer* reference = nullptr;
  for (const ShapeLayer& l : panel.layers)
    if (l.reference && l.x.size() == g.model().nx) {
      reference = &l;
      break;
    }
  if (!reference) return View::Isometric;
  // The model: its drawn curves' pieces in the reference configuration.
  std::vector<Point3> pts, pieces, moves;
  g.points(reference->x, pts);
  for (const DrawnElement& d : g.elements())
    for (int k = 1; d.shape == DrawnShape::Curve && k < d.numPoints; ++k) {
      const Point3 &a = pts[d.firstPoint + k - 1], &b = pts[d.firstPoint + k];
      pieces.push_back({b.x - a.x, b.y - a.y, b.z - a.z});
    }
  // Its motion: the drawn points' displacements in the other layers.
  std::vector<Point3> rest, moved;
  drawnPoints(g, reference->x, rest);
  for (const ShapeLayer& l : panel.layers) {
    if (l.reference || l.x.size() != g.model().nx) continue;
    drawnPoints(g, l.x, moved);
    for (size_t i = 0; i < rest.size() && i < moved.size(); ++i)
      moves.push_back({moved[i].x - rest[i].x, moved[i].y - rest[i].y, moved[i].z - rest[i].z});
  }
  // A product: a view that hides the model (leaves seen end-on) or its motion scores near zero.
  // Planes first, iso only where it sees more (a model and motion in no one plane).
  View best = View::XY;
  double bestScore = -1.0;
  for (const View v : {View::XY, View::XZ, View::YZ, View::Isometric}) {
    const double score = seenShare(pieces, v) * seenShare(moves, v);
    if (score > bestScore + 1e-9) best = v, bestScore = score;
  }
  return best;
}

std::string renderShapesSvg(const MechanismGeometry& g, const ShapeFigure& fig) {
  const int n = static_cast<int>(fig.panels.size());
  std::vector<View> views(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    views[static_cast<size_t>(i)] = panelView(g, fig.panels[static_cast<size_t>(i)], fig.view);
  const int cols = std::max(1, fig.columns > 0 ? fig.columns : std::min(3, n));
  const int rowsN = std::max(1, (n + cols - 1) / cols);
  const double pw = std::max(160, fig.panelWidth), ph = std::max(120, fig.panelHeight);
  const double top = 40 + 14.0 * static_cast<double>(fig.notes.size());
  const double W = cols * pw, H = top + rowsN * ph + 10;

  // One scale for all panels. Spatial models: faces of the cross-sections (reference layers as
  // centre lines), far to near within each layer.
  const bool spatial = g.spatial();
  std::vector<std::vector<std::vector<Point2>>> pts(n);
  std::vector<std::vector<std::vector<Primitive>>> prims(n);
  std::vector<Point2> all;
  for (int i = 0; i < n; ++i) {
    size_t colourIndex = 0;
    const View view = views[static_cast<size_t>(i)];
    for (const ShapeLayer& l : fig.panels[i].layers) {
      if (l.x.size() != g.model().nx) continue;
      pts[i].push_back(projected(g, l.x, view));
      all.insert(all.end(), pts[i].back().begin(), pts[i].back().end());
      prims[i].emplace_back();
      if (!spatial) continue;
      const std::string c = l.reference       ? "#999999"
                            : l.color.empty() ? kPalette[colourIndex++ % kPalette.size()]
                                              : l.color;
      spatialPrimitives(
          g, l.x, view, [&](int) { return c; }, !l.reference, prims[i].back());
      projectedPoints(prims[i].back(), view, all);
    }
  }
  const Frame unit = fit(all, 0, 0, pw, ph - 96, 14);  // room for the title and three legend lines

  std::string o = header(W, H) + titleLines(W, fig.title, fig.notes);
  for (int i = 0; i < n; ++i) {
    const ShapePanel& panel = fig.panels[i];
    const View view = views[static_cast<size_t>(i)];
    Frame f = unit;
    const double panelTop = top + (i / cols) * ph;
    f.left = (i % cols) * pw, f.top = panelTop + 24;
    o += "<g class=\"panel\">\n<rect x=\"" + num(f.left + 4) + "\" y=\"" + num(panelTop + 4) + "\" width=\"" +
         num(pw - 8) + "\" height=\"" + num(ph - 8) + "\" fill=\"none\" stroke=\"#dddddd\"/>\n";
    o += text(f.left + pw / 2, panelTop + 20, panel.title, "text-anchor=\"middle\" font-weight=\"bold\"");
    if (spatial) o += axisTriad(view, f.left + pw - 48, panelTop + ph - 44);
    size_t k = 0, colourIndex = 0;
    double legendY = panelTop + ph - 44;
    for (const ShapeLayer& l : panel.layers) {
      if (l.x.size() != g.model().nx) continue;
      const std::string c = l.reference       ? "#999999"
                            : l.color.empty() ? kPalette[colourIndex++ % kPalette.size()]
                                              : l.color;
      o += "<g class=\"" + std::string(l.reference ? "reference" : "shape") + "\">\n" +
           (spatial ? drawPrimitives(prims[i][k], view, f, l.reference ? 1.5 : 2.2, l.reference)
                    : drawElements(g, pts[i][k], f, c, l.reference ? 1.5 : 2.2, l.reference, false)) +
           "</g>\n";
      ++k;
      if (!l.label.empty() && legendY < panelTop + ph - 12) {
        o += "<line x1=\"" + num(f.left + 14) + "\" y1=\"" + num(legendY) + "\" x2=\"" + num(f.left + 32) + "\" y2=\"" +
             num(legendY) + "\" stroke=\"" + c + "\" stroke-width=\"2\"" +
             (l.reference ? " stroke-dasharray=\"4 3\"" : "") + "/>\n";
        o += text(f.left + 36, legendY + 4, l.label, "font-size=\"10\"");
        legendY += 12;
      }
    }
    // The reference's centre lines once more over the solid shapes, so that a shape never hides the
    // configuration it is measured from (a leaf bent out of plane covers its own rest position).
    if (spatial) {
      k = 0;
      for (const ShapeLayer& l : panel.layers) {
        if (l.x.size() != g.model().nx) continue;
        if (l.reference && panel.layers.size() > 1)
          o += "<g class=\"reference-over\">\n" + drawPrimitives(prims[i][k], view, f, 1.2, true) + "</g>\n";
        ++k;
      }
    }
    o += "</g>\n";
  }
  o += "</svg>\n";
  return o;
}

void writeModelSvg(const std::string& path, const MechanismGeometry& geometry, const ModelDrawing& drawing) {
  writeTextFile(path, renderModelSvg(geometry, drawing));
}

void writeShapesSvg(const std::string& path, const MechanismGeometry& geometry, const ShapeFigure& figure) {
  writeTextFile(path, renderShapesSvg(geometry, figure));
}

}  // namespace flexmb::io
