#include "io/templates/StudySummary.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

#include "io/formats/TextOutput.hpp"
#include "io/templates/ModelTemplate.hpp"
#include "io/templates/StudyTable.hpp"

namespace flexmb::io {

namespace {

std::string cellOf(double v) { return std::isfinite(v) ? roundTripNumber(v) : std::string(); }

double numberOf(const std::string& s) {
  if (s.empty()) return std::numeric_limits<double>::quiet_NaN();
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) throw std::invalid_argument("'" + s + "' is not a number");
  return v;
}

// One line: line breaks in a reason would split the row.
std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

// The quantity columns of all records, in the order they first appear.
std::vector<std::string> quantityColumns(const std::vector<StudyRecord>& records) {
  std::vector<std::string> cols;
  std::set<std::string> seen;
  for (const auto& r : records)
    for (const auto& [name, v] : r.quantities)
      if (seen.insert(name).second) cols.push_back(name);
  return cols;
}

std::vector<std::string> parameterColumns(const std::vector<StudyRecord>& records) {
  std::vector<std::string> cols;
  std::set<std::string> seen;
  for (const auto& r : records)
    for (const auto& [name, v] : r.parameters)
      if (seen.insert(name).second) cols.push_back(name);
  return cols;
}

double valueIn(const std::vector<std::pair<std::string, double>>& v, const std::string& name) {
  for (const auto& [n, x] : v)
    if (n == name) return x;
  return std::numeric_limits<double>::quiet_NaN();
}

void writeHeader(std::ostream& out, const std::vector<std::string>& params,
                 const std::vector<std::string>& quantities) {
  out << "variant,name";
  for (const auto& p : params) out << "," << csvCell(p);
  out << ",status";
  for (const auto& q : quantities) out << "," << csvCell(q);
  out << ",reason\n";
}

void writeRow(std::ostream& out, const StudyRecord& r, const std::vector<std::string>& params,
              const std::vector<std::string>& quantities) {
  out << r.variant << "," << csvCell(r.name);
  for (const auto& p : params) out << "," << cellOf(valueIn(r.parameters, p));
  out << "," << csvCell(r.status);
  for (const auto& q : quantities) out << "," << cellOf(valueIn(r.quantities, q));
  out << "," << csvCell(oneLine(r.reason)) << "\n";
}

}  // namespace

void writeStudyRecord(std::ostream& out, const StudyRecord& record) {
  std::vector<std::string> params, quantities;
  for (const auto& [n, v] : record.parameters) params.push_back(n);
  for (const auto& [n, v] : record.quantities) quantities.push_back(n);
  writeHeader(out, params, quantities);
  writeRow(out, record, params, quantities);
}

void writeStudyTable(std::ostream& out, const std::vector<StudyRecord>& records) {
  const auto params = parameterColumns(records), quantities = quantityColumns(records);
  writeHeader(out, params, quantities);
  for (const auto& r : records) writeRow(out, r, params, quantities);
}

std::vector<StudyRecord> parseStudyTable(const std::string& text, const std::string& file) {
  std::vector<StudyRecord> records;
  std::vector<std::string> header;
  size_t statusAt = 0;
  std::istringstream in(text);
  int lineNo = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    auto fail = [&](const std::string& why) {
      return std::runtime_error(file + ":" + std::to_string(lineNo) + ": " + why + " (not a study summary?)");
    };
    std::vector<std::string> cells;
    try {
      cells = splitCsvLine(line);
    } catch (const std::exception& e) {
      throw fail(e.what());
    }
    if (header.empty()) {
      header = cells;
      const auto st = std::find(header.begin(), header.end(), "status");
      if (header.size() < 4 || header[0] != "variant" || header[1] != "name" || st == header.end() ||
          header.back() != "reason")
        throw fail("expected the columns variant, name, the parameters, status, the quantities, reason");
      statusAt = static_cast<size_t>(st - header.begin());
      continue;
    }
    if (cells.size() != header.size())
      throw fail(std::to_string(cells.size()) + " cells, the header has " + std::to_string(header.size()));
    StudyRecord r;
    try {
      r.variant = static_cast<int>(numberOf(cells[0]));
      r.name = cells[1];
      for (size_t i = 2; i < statusAt; ++i) r.parameters.emplace_back(header[i], numberOf(cells[i]));
      r.status = cells[statusAt];
      for (size_t i = statusAt + 1; i + 1 < header.size(); ++i)
        r.quantities.emplace_back(header[i], numberOf(cells[i]));
      r.reason = cells.back();
    } catch (const std::invalid_argument& e) {
      throw fail(e.what());
    }
    records.push_back(std::move(r));
  }
  return records;
}

StudyRecord readStudyRecord(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read it");
  std::stringstream s;
  s << in.rdbuf();
  const auto records = parseStudyTable(s.str(), path);
  if (records.size() != 1)
    throw std::runtime_error(path + ": " + std::to_string(records.size()) + " rows, a variant summary has one");
  return records.front();
}

std::vector<std::string> plottableQuantities(const std::vector<StudyRecord>& records) {
  // Counts that describe the run rather than the design.
  static const std::set<std::string> bookkeeping = {"dofs", "rank", "static_steps", "sim_steps", "sim_fevals"};
  std::vector<std::string> out;
  for (const auto& q : quantityColumns(records)) {
    if (bookkeeping.count(q)) continue;
    // A quantity the same in every variant that has it (sim_t_end, a reduction error of 0 where the
    // full model ran) draws a flat line that says nothing the table does not: not plotted.
    int finite = 0;
    bool varies = false;
    double first = 0.0;
    for (const auto& r : records) {
      const double v = valueIn(r.quantities, q);
      if (!std::isfinite(v)) continue;
      if (finite++ == 0)
        first = v;
      else
        varies = varies || v != first;
    }
    if (finite == 1 || varies) out.push_back(q);
  }
  return out;
}

std::string quantityUnit(const std::string& q) {
  auto starts = [&](const char* p) { return q.rfind(p, 0) == 0; };
  auto ends = [&](const char* e) {
    const std::string s(e);
    return q.size() >= s.size() && q.compare(q.size() - s.size(), s.size(), s) == 0;
  };
  if (ends("_Hz")) return "Hz";
  if (starts("k_node")) {  // k_node<n>_x|y|z: N/m; _rx|_ry|_rz|_angle: N m/rad
    const auto u = q.rfind('_');
    const std::string c = q.substr(u + 1);
    return c == "x" || c == "y" || c == "z" ? "N/m" : "N m/rad";
  }
  if (q == "max_axial_force" || q == "sweep_max_load") return "N";
  if (starts("max_bending_moment") || q == "max_torsion_moment") return "N m";
  if (starts("max_stress") || starts("max_von_mises")) return "Pa";
  if (q == "max_displacement" || q == "sim_max_displacement") return "m";
  if (q == "sim_t_end") return "s";
  return "";
}

namespace {
// A positive range over more than two decades reads on a logarithmic axis.
bool wideRange(const std::vector<double>& v) {
  double lo = INFINITY, hi = 0.0;
  for (double x : v) {
    if (!(x > 0.0)) return false;
    lo = std::min(lo, x), hi = std::max(hi, x);
  }
  return !v.empty() && hi > 100.0 * lo;
}
}  // namespace

Plot studyPlot(const std::vector<StudyRecord>& records, const std::string& quantity, const std::string& parameter) {
  Plot plot;
  plot.title = quantity + " against " + parameter;
  plot.x.label = parameter;
  const std::string unit = quantityUnit(quantity);
  plot.y.label = unit.empty() ? quantity : quantity + " [" + unit + "]";
  const auto params = parameterColumns(records);
  // One series per combination of the other parameters (ordered by their values).
  std::map<std::vector<double>, std::vector<std::pair<double, double>>> groups;
  for (const auto& r : records) {
    if (r.status != "ok") continue;
    const double x = valueIn(r.parameters, parameter), y = valueIn(r.quantities, quantity);
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    std::vector<double> key;
    for (const auto& p : params)
      if (p != parameter) key.push_back(valueIn(r.parameters, p));
    groups[key].emplace_back(x, y);
  }
  const bool labelled = groups.size() > 1 && groups.size() <= 12;
  for (auto& [key, points] : groups) {
    std::sort(points.begin(), points.end());
    Series s;
    s.markers = true;
    if (labelled) {
      size_t k = 0;
      for (const auto& p : params)
        if (p != parameter) s.label += (s.label.empty() ? "" : ", ") + p + " = " + shortNumber(key[k++]);
    }
    for (const auto& [x, y] : points) {
      s.x.push_back(x);
      s.y.push_back(y);
    }
    plot.series.push_back(std::move(s));
  }
  if (groups.size() > 12)
    plot.notes.push_back(std::to_string(groups.size()) + " lines: one per combination of the other parameters");
  std::vector<double> xs, ys;
  for (const auto& s : plot.series)
    xs.insert(xs.end(), s.x.begin(), s.x.end()), ys.insert(ys.end(), s.y.begin(), s.y.end());
  plot.x.log = wideRange(xs);
  plot.y.log = wideRange(ys);
  return plot;
}

std::string renderStudyReport(const StudyReport& report, const std::vector<StudyRecord>& records) {
  std::ostringstream h;
  int ok = 0, failed = 0, missing = 0;
  for (const auto& r : records) (r.status == "ok" ? ok : r.status == "failed" ? failed : missing)++;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << xmlEscape(report.title) << "</title>\n"
    << "<style>body{font-family:sans-serif;margin:2em;max-width:80em}table{border-collapse:collapse;font-size:85%}"
       "td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}th{background:#eee}td.t{text-align:left}"
       ".failed{background:#fdd}.missing{background:#eee}figure{display:inline-block;margin:0.5em}</style>\n"
    << "</head><body>\n<h1>" << xmlEscape(report.title) << "</h1>\n";
  for (const auto& l : report.lines) h << "<div>" << xmlEscape(l) << "</div>\n";
  h << "<p>" << records.size() << " variants: " << ok << " ok, " << failed << " failed, " << missing
    << " not run yet.</p>\n";
  const auto params = parameterColumns(records);
  const auto quantities = report.quantities.empty() ? plottableQuantities(records) : report.quantities;
  if (ok > 0 && !params.empty()) {
    h << "<h2>Plots</h2>\n";
    for (const auto& q : quantities)
      for (const auto& p : params) {
        Plot plot = studyPlot(records, q, p);
        plot.width = 480;
        plot.height = 320;
        h << "<figure>" << renderSvg(plot) << "</figure>\n";
      }
  }
  if (failed > 0) {
    h << "<h2>Failed variants</h2>\n<table><tr><th>variant</th><th>name</th><th>reason</th></tr>\n";
    for (const auto& r : records)
      if (r.status == "failed")
        h << "<tr><td>" << r.variant << "</td><td class=\"t\">" << xmlEscape(r.name) << "</td><td class=\"t\">"
          << xmlEscape(r.reason) << "</td></tr>\n";
    h << "</table>\n";
  }
  h << "<h2>Table</h2>\n<table><tr><th>variant</th><th>name</th>";
  const auto cols = quantityColumns(records);
  for (const auto& p : params) h << "<th>" << xmlEscape(p) << "</th>";
  h << "<th>status</th>";
  for (const auto& q : cols) {
    const std::string unit = quantityUnit(q);
    h << "<th>" << xmlEscape(unit.empty() ? q : q + " [" + unit + "]") << "</th>";
  }
  h << "</tr>\n";
  for (const auto& r : records) {
    h << "<tr class=\"" << xmlEscape(r.status) << "\"><td>" << r.variant << "</td><td class=\"t\">" << xmlEscape(r.name)
      << "</td>";
    for (const auto& p : params) {
      const double v = valueIn(r.parameters, p);
      h << "<td>" << (std::isfinite(v) ? shortNumber(v, 6) : "") << "</td>";
    }
    h << "<td class=\"t\">" << xmlEscape(r.status) << "</td>";
    for (const auto& q : cols) {
      const double v = valueIn(r.quantities, q);
      h << "<td>" << (std::isfinite(v) ? shortNumber(v, 6) : "") << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n</body></html>\n";
  return h.str();
}

}  // namespace flexmb::io
