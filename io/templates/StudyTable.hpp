#pragma once
// The parameter values of a design study (`flexmb study`), as a table file or as grid axes.
//
// Table (CSV): a header row naming one parameter per column, plus optionally a column `name` (the
// variant's name, used for its result folder; an empty cell: v0001, v0002, ... by row), then one
// row per variant. Blank lines and lines
// starting with '#' are skipped; cells may be quoted ("..."); numbers use a decimal point (a decimal
// comma would split the cell). Every error names the file, the line and the column.
//
// Grid axis: `t=0.1e-3:0.5e-3:9` (9 equidistant values from 0.1e-3 to 0.5e-3, both included),
// `t=1e-4,2e-4,5e-4` (a list) or `t=2e-4` (one value). Grid values are rounded to 15 significant
// digits, so 0.1e-3:0.5e-3:9 gives 0.00015 and not 0.00015000000000000001.
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace flexmb::io {

struct ParameterTable {
  std::string file;
  std::vector<std::string> parameters;    // column names, table order (without `name`)
  std::vector<std::string> names;         // per row: the `name` cell, or empty without a name column
  std::vector<std::vector<double>> rows;  // per row: one value per parameter
  std::vector<int> lines;                 // per row: its line in the file
};

// Throws std::runtime_error "file:line: message" (duplicate or invalid column names, a row with
// too few or too many cells, a cell that is not a finite number, duplicate or unusable names, no
// rows).
ParameterTable parseParameterTable(std::string_view text, const std::string& file);
ParameterTable readParameterTable(const std::string& path);

struct ParameterAxis {
  std::string name;
  std::vector<double> values;
};
// Throws std::invalid_argument naming the specification and what is wrong.
ParameterAxis parseParameterAxis(const std::string& spec);

// Whether s is a usable variant name (a folder name): letters, digits, '.', '_', '-', not starting
// with '.' or '-', at most 100 characters.
bool isVariantName(const std::string& s);

// RFC 4180 cell: quoted when it holds a comma, a quote or a line break.
std::string csvCell(const std::string& s);
// Splits one CSV line into cells (quotes honoured); throws std::invalid_argument on an unclosed quote.
std::vector<std::string> splitCsvLine(std::string_view line);

}  // namespace flexmb::io
