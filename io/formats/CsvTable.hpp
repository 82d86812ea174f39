#pragma once
// One CSV table as the analyses' results give it (column names, rows of numbers; NaN: an empty
// cell, where a step has fewer frequencies or buckling factors than the table has columns) and its
// one text form, so that every front end writes the same bytes for the same result (issue 36).
#include <string>
#include <vector>

namespace flexmb::io {

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // each as long as columns
};

// "f3_Hz" from ("f", 3, "_Hz").
std::string numberedColumn(const char* stem, long number, const char* suffix);

// Header line, then one line per row: numbers as %.17g (they read back exactly), NaN as nothing.
std::string formatCsv(const CsvTable& table);

}  // namespace flexmb::io
