#include "io/pictures/DesignPlots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "io/formats/ResultWriter.hpp"

namespace flexmb::io {

namespace {

constexpr int kPanelHeight = 300;  // pixels of one stacked panel

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool startsWith(const std::string& s, const std::string& head) { return s.compare(0, head.size(), head) == 0; }

std::vector<double> column(const CsvTable& t, std::size_t c) {
  std::vector<double> v;
  v.reserve(t.rows.size());
  for (const auto& row : t.rows) v.push_back(c < row.size() ? row[c] : std::numeric_limits<double>::quiet_NaN());
  return v;
}

std::string bracketed(const std::string& unit) { return unit.empty() ? "" : " [" + unit + "]"; }

// The coordinate's kind: its text after the last '.'.
std::string coordinateKind(const std::string& column) {
  const auto dot = column.rfind('.');
  return dot == std::string::npos ? "" : column.substr(dot + 1);
}

}  // namespace

std::vector<std::string> commaList(const std::string& text) {
  std::vector<std::string> out;
  std::size_t from = 0;
  while (from <= text.size()) {
    std::size_t to = text.find(',', from);
    if (to == std::string::npos) to = text.size();
    std::string item = text.substr(from, to - from);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) out.push_back(item);
    from = to + 1;
  }
  return out;
}

std::string listNames(const std::vector<std::string>& names, std::size_t most) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < most; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > most) s += ", ... and " + std::to_string(names.size() - most) + " more";
  return s;
}

std::size_t tableColumn(const CsvTable& table, const std::string& name, const std::string& what) {
  const auto it = std::find(table.columns.begin(), table.columns.end(), name);
  if (it != table.columns.end()) return static_cast<std::size_t>(it - table.columns.begin());
  throw std::invalid_argument(what + " has no column '" + name + "'; it has: " + listNames(table.columns));
}

int coordinateIndex(const core::Model& model, const std::string& name) {
  const std::vector<std::string> names = coordinateColumnNames(model);
  const auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return static_cast<int>(it - names.begin());
  throw std::invalid_argument("'" + name + "' is not a coordinate of " + model.sourceFile +
                              "; its coordinates (the CSV columns): " + listNames(names));
}

std::string coordinateUnit(const std::string& column) {
  const std::string kind = coordinateKind(column);
  if (kind == "x" || kind == "y" || kind == "z") return "m";
  if (kind == "angle") return "rad";
  if (kind == "w") return "rad/m";
  return "";
}

std::string staticLoadColumn(const CsvTable& table, const std::string& coordinate) {
  for (const char* stem : {"F.", "M."}) {
    const std::string c = stem + coordinate;
    if (std::find(table.columns.begin(), table.columns.end(), c) != table.columns.end()) return c;
  }
  return "load_factor";
}

std::string staticLoadLabel(const std::string& loadColumn) {
  if (startsWith(loadColumn, "F.")) return "applied force " + loadColumn + " [N]";
  if (startsWith(loadColumn, "M.")) return "applied moment " + loadColumn + " [N m]";
  return "load factor (DELXF increments applied) [-]";
}

Plot forceDeflectionPlot(const CsvTable& table, const ForceDeflection& what, const std::string& title) {
  const std::size_t cx = tableColumn(table, what.coordinate, "the table"),
                    cy = tableColumn(table, what.load, "the table");
  Plot p;
  p.title = title;
  p.x.label = !what.deflectionLabel.empty() ? what.deflectionLabel
                                            : "deflection " + what.coordinate + " - " + what.coordinate + "(initial)" +
                                                  bracketed(coordinateUnit(what.coordinate));
  p.y.label = what.loadLabel;
  p.height = kPanelHeight + 60;
  Series s;
  s.label = what.deflectionLabel.empty() ? what.coordinate : "";  // a named quantity: the axis says it
  s.markers = true;
  s.y = column(table, cy);
  for (double v : column(table, cx)) s.x.push_back(v - what.reference);
  p.series.push_back(std::move(s));
  return p;
}

std::vector<Plot> staticForceDeflectionPlots(const core::Model& model, const CsvTable& table,
                                             const std::vector<std::string>& coordinates, const std::string& title) {
  std::vector<Plot> panels;
  for (const auto& c : coordinates) {
    ForceDeflection fd;
    fd.coordinate = c;
    fd.reference = model.x0[coordinateIndex(model, c)];
    fd.load = staticLoadColumn(table, c);
    fd.loadLabel = staticLoadLabel(fd.load);
    panels.push_back(forceDeflectionPlot(table, fd, panels.empty() ? title : ""));
  }
  return panels;
}

std::vector<Plot> sweepForceDeflectionPlots(const core::Model& model, const CsvTable& table,
                                            const std::vector<std::string>& coordinates, const std::string& valueLabel,
                                            const std::string& loadUnit, const std::string& title) {
  std::vector<Plot> panels;
  for (const auto& c : coordinates) {
    ForceDeflection fd;
    fd.coordinate = c;
    if (c == "value")
      fd.deflectionLabel = valueLabel;
    else
      fd.reference = model.x0[coordinateIndex(model, c)];
    fd.load = "load";
    fd.loadLabel = "the holding load" + bracketed(loadUnit);  // the title names what it holds
    panels.push_back(forceDeflectionPlot(table, fd, panels.empty() ? title : ""));
  }
  return panels;
}

std::vector<std::vector<int>> modeGroups(const std::vector<double>& lowest, const std::vector<double>& highest) {
  std::vector<std::vector<int>> groups;
  double limit = 0.0;
  for (std::size_t i = 0; i < lowest.size() && i < highest.size(); ++i) {
    const bool gap = i > 0 && lowest[i] > 3.0 * highest[i - 1];
    if (groups.empty() || gap || !(highest[i] <= limit)) {
      groups.emplace_back();
      limit = 10.0 * std::max(lowest[i], 0.0);
    }
    groups.back().push_back(static_cast<int>(i));
  }
  return groups;
}

std::vector<Plot> frequencyPanels(const CsvTable& table, const std::string& xColumn, const std::string& xLabel,
                                  const std::string& title) {
  const std::vector<double> x = column(table, tableColumn(table, xColumn, "the sweep table"));
  std::vector<std::vector<double>> f;
  std::vector<double> lowest, highest;
  for (int i = 1;; ++i) {
    const auto it = std::find(table.columns.begin(), table.columns.end(), numberedColumn("f", i, "_Hz"));
    if (it == table.columns.end()) break;
    f.push_back(column(table, static_cast<std::size_t>(it - table.columns.begin())));
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (double v : f.back())
      if (std::isfinite(v)) lo = std::min(lo, std::abs(v)), hi = std::max(hi, std::abs(v));
    lowest.push_back(std::isfinite(lo) ? lo : 0.0);
    highest.push_back(hi);
  }
  std::vector<Plot> panels;
  for (const auto& g : modeGroups(lowest, highest)) {
    Plot p;
    p.title = panels.empty() ? title : "";
    const std::string modes = g.size() == 1
                                  ? "mode " + std::to_string(g.front() + 1)
                                  : "modes " + std::to_string(g.front() + 1) + " to " + std::to_string(g.back() + 1);
    p.notes.push_back(modes + (panels.empty() && g.size() < f.size()
                                   ? " (a panel per group of modes: a gap of 3x or a decade starts the next)"
                                   : ""));
    p.x.label = xLabel;
    p.y.label = "frequency [Hz]";
    p.height = kPanelHeight;
    for (int i : g) {
      Series s;
      s.label = numberedColumn("f", i + 1, "");
      s.x = x;
      s.y = f[static_cast<std::size_t>(i)];
      p.series.push_back(std::move(s));
    }
    panels.push_back(std::move(p));
  }
  if (panels.empty()) {  // no frequency columns: one empty panel says so
    Plot p;
    p.title = title;
    p.x.label = xLabel;
    p.y.label = "frequency [Hz]";
    panels.push_back(std::move(p));
  }
  return panels;
}

std::string historyQuantity(const std::string& c) {
  if (c == "max_stress" || startsWith(c, "stress_")) return "von Mises stress [MPa]";
  const auto colon = c.find(':');
  const std::string stem = colon == std::string::npos ? "x" : c.substr(0, colon);
  const std::string name = colon == std::string::npos ? c : c.substr(colon + 1);
  if (stem == "x" || stem == "xd" || stem == "xdd") {
    const std::string kind = coordinateKind(name), unit = coordinateUnit(name);
    const std::string rate = stem == "x" ? "" : stem == "xd" ? "/s" : "/s^2";
    if (unit == "m")
      return std::string(stem == "x" ? "position" : stem == "xd" ? "velocity" : "acceleration") + " [m" + rate + "]";
    if (unit == "rad")
      return std::string(stem == "x"    ? "rotation"
                         : stem == "xd" ? "angular velocity"
                                        : "angular acceleration") +
             " [rad" + rate + "]";
    return stem + ": " + (kind.empty() ? name : kind);
  }
  // A deformation "PLBEAM3.e2_bending_p": its kind after the element.
  const auto dot = name.rfind('.');
  const std::string kind = dot == std::string::npos ? name : name.substr(dot + 1);
  // An elongation is a length, its stress a force; a bending or torsion deformation an angle, its
  // stress a moment (stress times deformation is work).
  const bool length = kind.find("elongation") != std::string::npos;
  const bool angle = kind.find("bending") != std::string::npos || kind.find("torsion") != std::string::npos;
  const std::string unit = length ? "m" : angle ? "rad" : "";
  if (stem == "sig") return "sig of " + kind + (length ? " [N]" : angle ? " [N m]" : "");
  if (stem == "e") return "e of " + kind + bracketed(unit);
  if (stem == "ed") return "ed of " + kind + bracketed(unit + (unit.empty() ? "1/s" : "/s"));
  if (stem == "edd") return "edd of " + kind + bracketed(unit + (unit.empty() ? "1/s^2" : "/s^2"));
  return stem + ": " + kind;
}

std::vector<Plot> timeHistoryPlots(const CsvTable& table, const std::vector<double>& initial,
                                   const std::string& title) {
  std::vector<Plot> panels;
  std::map<std::string, std::size_t> panelOf;
  const std::vector<double> time = column(table, 0);
  for (std::size_t c = 1; c < table.columns.size(); ++c) {
    const std::string& name = table.columns[c];
    const double from = c - 1 < initial.size() ? initial[c - 1] : std::numeric_limits<double>::quiet_NaN();
    std::string q = historyQuantity(name);
    if (!std::isnan(from)) {  // a displacement from the initial configuration
      if (startsWith(q, "position")) q = "displacement from the initial position" + q.substr(8);
      if (startsWith(q, "rotation")) q = "rotation from the initial angle" + q.substr(8);
    }
    auto [it, added] = panelOf.emplace(q, panels.size());
    if (added) {
      Plot p;
      p.title = panels.empty() ? title : "";
      p.x.label = "time [s]";
      p.y.label = q;
      p.height = kPanelHeight;
      panels.push_back(std::move(p));
    }
    Series s;
    s.label = startsWith(name, "x:") ? name.substr(2) : name;
    s.x = time;
    s.y = column(table, c);
    if (!std::isnan(from))
      for (double& v : s.y) v -= from;
    if (endsWith(q, "[MPa]"))
      for (double& v : s.y) v *= 1e-6;
    panels[it->second].series.push_back(std::move(s));
  }
  if (panels.empty()) {
    Plot p;
    p.title = title;
    p.x.label = "time [s]";
    panels.push_back(std::move(p));
  }
  return panels;
}

}  // namespace flexmb::io
