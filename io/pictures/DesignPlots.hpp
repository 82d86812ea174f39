#pragma once
// The plots a flexure designer reads (issue 53 item 2), built from the analyses' tables with the
// column names of their CSV files, so that a plotted point is a cell of the CSV:
//   * force against deflection: a load column (the nodal load on the coordinate F.<c> / M.<c>, the
//     load factor, a sweep's holding load) against a coordinate minus its initial value, one panel
//     per coordinate (flexmb static --plot, flexmb sweep --plot);
//   * frequencies over a stroke, one panel per group of modes (modeGroups) so that 5 Hz and 1 kHz
//     never share a linear axis (flexmb sweep's <prefix>.svg);
//   * a time history: the table's first column is the time, the others are grouped into panels by
//     the quantity they are (historyQuantity: positions, rotations, a deformation's stress, von
//     Mises stresses in MPa) (flexmb simulate --plot).
// Panels are Plots for renderSvgStack / writeSvgStack; the first carries the title.
#include <string>
#include <vector>

#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"
#include "io/pictures/SvgPlot.hpp"

namespace flexmb::io {

// The index of column `name`; std::invalid_argument "<what> has no column 'name'; it has: a, b, ..."
// (the list cut after 40 names, with how many more) otherwise.
std::size_t tableColumn(const CsvTable& table, const std::string& name, const std::string& what);
// The names of a comma-separated list ("node6.x,node6.y"), blanks around them removed, empty ones
// left out (the --plot options' value).
std::vector<std::string> commaList(const std::string& text);
// "a, b, c" of the first `most` names, then "... and N more".
std::string listNames(const std::vector<std::string>& names, std::size_t most = 40);

// A coordinate by its CSV name ("node6.x", io::coordinateColumnNames): its index into x, or
// std::invalid_argument naming the label and listing the model's coordinates.
int coordinateIndex(const core::Model& model, const std::string& name);
// Unit of a coordinate column: "m" (.x .y .z), "rad" (.angle), "rad/m" (.w), "" (Euler parameters).
std::string coordinateUnit(const std::string& column);

struct ForceDeflection {
  std::string coordinate;       // the deflected coordinate's column ("node6.x")
  double reference = 0.0;       // its value in the model's initial configuration: deflection = column - reference
  std::string load;             // the load's column ("F.node6.x", "load_factor", "load")
  std::string loadLabel;        // the y axis's text, unit included
  std::string deflectionLabel;  // the x axis's text, no legend (empty: "deflection <c> - <c>(initial) [unit]")
};
// The load a static table gives along a coordinate: "F.<c>" or "M.<c>" where the table has that
// column (the nodal load applied on the coordinate), else "load_factor".
std::string staticLoadColumn(const CsvTable& table, const std::string& coordinate);
// The y axis's text for staticLoadColumn's column.
std::string staticLoadLabel(const std::string& loadColumn);
// One panel: the load against the deflection over the table's rows (line and a marker per row).
Plot forceDeflectionPlot(const CsvTable& table, const ForceDeflection& what, const std::string& title);

// static --plot: per coordinate (a name of coordinateIndex) a panel of the load along it
// (staticLoadColumn, staticLoadLabel) against its deflection from the model's initial configuration.
std::vector<Plot> staticForceDeflectionPlots(const core::Model& model, const CsvTable& table,
                                             const std::vector<std::string>& coordinates, const std::string& title);
// sweep --plot: per coordinate a panel of the sweep table's holding `load` (in loadUnit) against its
// deflection; "value" is the table's prescribed value itself (a spatial orientation node's rotation
// from its initial orientation), valueLabel on its axis.
std::vector<Plot> sweepForceDeflectionPlots(const core::Model& model, const CsvTable& table,
                                            const std::vector<std::string>& coordinates, const std::string& valueLabel,
                                            const std::string& loadUnit, const std::string& title);

// Groups of consecutive modes (indices into `lowest` / `highest`, each mode's smallest and largest
// |frequency| over the stroke, modes in ascending order): a mode starts the next group where its
// lowest frequency is more than 3 times the previous mode's highest (a gap in the spectrum) or its
// highest more than 10 times the lowest of the group's first mode (no panel spans more than a
// decade); otherwise it joins the current group. A group whose first mode reaches 0 Hz somewhere (a
// rigid-body mode, a buckling point) holds only the modes that stay at 0 Hz.
std::vector<std::vector<int>> modeGroups(const std::vector<double>& lowest, const std::vector<double>& highest);
// The columns f1_Hz, f2_Hz, ... of a sweep table against xColumn, one panel per modeGroups group.
std::vector<Plot> frequencyPanels(const CsvTable& table, const std::string& xColumn, const std::string& xLabel,
                                  const std::string& title);

// The quantity of a time-history column, its panel's y axis text: "x:node6.x" position [m],
// "x:node106.angle" rotation [rad], "xd:"/"xdd:" their rates, "e:"/"ed:"/"edd:"/"sig:" + a deformation
// name the deformation (its rates, its generalised stress) of that kind ("sig of e2_bending_p [N m]":
// elongations in m and N, bending and torsion in rad and N m, others without a unit), "max_stress" /
// "stress_<element>" "von Mises stress [MPa]".
std::string historyQuantity(const std::string& column);
// The panels of a time history: column 0 is the time [s]; the other columns in order, one panel per
// historyQuantity (von Mises stresses drawn in MPa, the table holds Pa). initial: per column after
// the time its value in the model's initial configuration, drawn as the column minus it (a
// coordinate's "displacement from the initial position [m]", "rotation from the initial angle
// [rad]"); NaN or missing: drawn as it is.
std::vector<Plot> timeHistoryPlots(const CsvTable& table, const std::vector<double>& initial, const std::string& title);

}  // namespace flexmb::io
