#pragma once
// Pictures of a mechanism as SVG (SPAVISUAL's still pictures), from MechanismGeometry.
//   * renderModelSvg: the model in its initial configuration, to check it before running: every
//     element (colour by the roles of its deformations: rigid, DOF, released, input) with its
//     number, every position node with its number and a marker by the roles of its coordinates
//     (fixed, partly fixed, input, DOF, free), orientation node numbers beside the position node
//     they are attached to, and a table listing every node and element with the role of each
//     coordinate and deformation.
//   * renderShapesSvg: panels of configurations over each other (a reference in dashed grey, then
//     deformed configurations or mode shapes in colour), all panels at one scale, each in its own
//     projection (panelView) with its axes drawn.
// Equal scales on both axes; y (or z) up. Output is deterministic and self-contained.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/pictures/MechanismGeometry.hpp"

namespace flexmb::io {

struct ShapeLayer {
  Eigen::VectorXd x;       // nodal coordinates (size nx)
  std::string label;       // legend entry; "" for none
  std::string color;       // "" = from the palette by layer index
  bool reference = false;  // dashed grey, drawn first
};

struct ShapePanel {
  std::string title;
  std::vector<ShapeLayer> layers;
};

struct ShapeFigure {
  std::string title;
  std::vector<std::string> notes;  // lines under the title
  std::vector<ShapePanel> panels;
  int columns = 0;  // 0: min(3, number of panels)
  int panelWidth = 380, panelHeight = 300;
  View view = View::Auto;
};

struct ModelDrawing {
  std::string title;
  std::vector<std::string> notes;  // lines under the title (degrees of freedom, check results)
  View view = View::Auto;
};

// Role summaries used in the pictures and their tables.
// Node: "fixed", "partly fixed", "input", "DOF" or "free" (the strongest role of its coordinates:
// input, then DOF, then fixed).
std::string nodeRole(const core::Model& model, int node);
// Element: "input", "DOF", "released" or "rigid" (input, DOF, released deformations, in that order).
std::string elementRole(const core::Model& model, int element);
// A deformation's role in the words of the pictures: rigid (fixed), input, DOF (DYNE),
// released (RLSE, calculable).
const char* deformationRoleWord(core::Role r);
// A nodal coordinate's role: fixed, input, DOF (DYNX), free (calculable).
const char* coordinateRoleWord(core::Role r);

// The projection of one panel of a shape figure: the figure's view when one is set; with Auto, for a
// spatial model, the view among xy, xz, yz and iso that sees most of the panel's model and motion:
// the largest product of the share of the model's drawn length (its reference layer) and of the
// displacements of its drawn points (axis points and section corners, the other layers against the
// reference) that survive the projection, planes
// before iso on a tie; xy for planar models. So the cross-spring pivot's rotation mode is drawn
// face-on, and a parallel leaf-spring stage flat in xz moving along x is drawn in xz, not from the top.
View panelView(const MechanismGeometry& geometry, const ShapePanel& panel, View requested);

std::string renderModelSvg(const MechanismGeometry& geometry, const ModelDrawing& drawing);
std::string renderShapesSvg(const MechanismGeometry& geometry, const ShapeFigure& figure);
// Both write through writeTextFile (checked, atomic).
void writeModelSvg(const std::string& path, const MechanismGeometry& geometry, const ModelDrawing& drawing);
void writeShapesSvg(const std::string& path, const MechanismGeometry& geometry, const ShapeFigure& figure);

}  // namespace flexmb::io
