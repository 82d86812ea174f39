#include "io/formats/CsvTable.hpp"

#include <cmath>
#include <stdexcept>

#include "text/NumberText.hpp"

namespace flexmb::io {

std::string numberedColumn(const char* stem, long number, const char* suffix) {
  std::string s(stem);
  s.append(std::to_string(number)).append(suffix);
  return s;
}

std::string formatCsv(const CsvTable& table) {
  std::string out;
  for (size_t j = 0; j < table.columns.size(); ++j) {
    if (j) out += ',';
    out += table.columns[j];
  }
  out += '\n';
  for (const auto& row : table.rows) {
    if (row.size() != table.columns.size()) throw std::logic_error("CSV row and header differ in length");
    for (size_t j = 0; j < row.size(); ++j) {
      if (j) out += ',';
      if (!std::isnan(row[j])) text::appendG17(out, row[j]);
    }
    out += '\n';
  }
  return out;
}

}  // namespace flexmb::io
