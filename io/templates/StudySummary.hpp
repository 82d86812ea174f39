#pragma once
// The summary files of a design study (`flexmb study`, tools/README.md):
//   * one variant's summary: a CSV with a header and one row,
//       variant,name,<parameters...>,status,<quantities...>,reason
//     status is ok or failed; a quantity that is not available is an empty cell; reason says why a
//     variant failed (or what it noted);
//   * the collected table: the same columns, one row per variant in variant order (the union of
//     the quantity columns, in the order they first appear);
//   * the report: a self-contained HTML page with the table and one SVG plot per quantity against
//     each parameter (variants that differ in other parameters are separate lines).
// Numbers are the shortest text that reads back as the same double, so a table is the same byte for
// byte whatever the order in which its variants ran.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "io/pictures/SvgPlot.hpp"

namespace flexmb::io {

struct StudyRecord {
  int variant = 0;   // 1-based number in the study
  std::string name;  // result folder name
  std::vector<std::pair<std::string, double>> parameters;
  std::string status;  // "ok", "failed", or in a collected table "missing" (not run yet)
  std::string reason;
  std::vector<std::pair<std::string, double>> quantities;  // NaN: not available
};

// One record as a two-line CSV (header and row).
void writeStudyRecord(std::ostream& out, const StudyRecord& record);
// Reads it back; throws std::runtime_error "file: message" when it is not one.
StudyRecord readStudyRecord(const std::string& path);
// Parses a table of records (header + rows); parameters are the columns between name and status.
std::vector<StudyRecord> parseStudyTable(const std::string& text, const std::string& file);

// The collected table (records in the order given).
void writeStudyTable(std::ostream& out, const std::vector<StudyRecord>& records);

// The plots of the report: `quantity` against `parameter`, one series per combination of the
// other parameters' values (failed and missing variants left out).
// The unit of a study quantity where its name says it ("Hz" for f1_Hz, "N/m" for k_node3_x, "N m/rad" for
// k_node4_rz, "N", "N m", "Pa", "m", "s"); empty where it is a count or a ratio.
std::string quantityUnit(const std::string& quantity);
// Logarithmic axes where the values are positive and span more than two decades; the unit in the
// quantity's axis label.
Plot studyPlot(const std::vector<StudyRecord>& records, const std::string& quantity, const std::string& parameter);

struct StudyReport {
  std::string title;                    // e.g. the template's name
  std::vector<std::string> lines;       // what the study ran (shown under the title)
  std::vector<std::string> quantities;  // what to plot (empty: every quantity)
};
// The HTML page: title, summary counts, plots (inline SVG), the failed variants with reasons, and
// the table.
std::string renderStudyReport(const StudyReport& report, const std::vector<StudyRecord>& records);
// The quantities plotted by default: every quantity column with a finite value in some record,
// except the counts (dofs, rank, static_steps, sim_steps, sim_fevals) and those equal in every
// record that has them (two or more).
std::vector<std::string> plottableQuantities(const std::vector<StudyRecord>& records);

}  // namespace flexmb::io
