#include "io/templates/StudyTable.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "io/templates/ModelTemplate.hpp"

namespace flexmb::io {

namespace {

std::string trimmed(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '\r')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r')) --b;
  return std::string(s.substr(a, b - a));
}

// A finite number, the whole text (leading '+' allowed); nothing otherwise.
bool parseNumber(const std::string& s, double& v) {
  std::string_view t = s;
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(v);
}

double roundTo15Digits(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.14e", v);
  double r = v;
  std::from_chars(buf, buf + std::char_traits<char>::length(buf), r, std::chars_format::scientific);
  return r;
}

std::string columnName(const std::vector<std::string>& header, size_t i) {
  return i < header.size() && !header[i].empty() ? "'" + header[i] + "'" : std::to_string(i + 1);
}

}  // namespace

bool isVariantName(const std::string& s) {
  if (s.empty() || s.size() > 100 || s[0] == '.' || s[0] == '-') return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) return false;
  return true;
}

std::string csvCell(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::vector<std::string> splitCsvLine(std::string_view line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false, wasQuoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = wasQuoted = true;
    } else if (c == ',') {
      cells.push_back(wasQuoted ? cell : trimmed(cell));
      cell.clear();
      wasQuoted = false;
    } else {
      cell += c;
    }
  }
  if (quoted) throw std::invalid_argument("a quote (\") is not closed");
  cells.push_back(wasQuoted ? cell : trimmed(cell));
  return cells;
}

ParameterTable parseParameterTable(std::string_view text, const std::string& file) {
  ParameterTable t;
  t.file = file;
  auto fail = [&](int line, const std::string& message) {
    std::string s = file;
    if (line) s.append(":").append(std::to_string(line));
    return std::runtime_error(s.append(": ").append(message));
  };
  std::vector<std::string> header;
  int nameColumn = -1;
  std::set<std::string> names;
  int lineNo = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string line = trimmed(text.substr(pos, end - pos));
    pos = end + 1;
    ++lineNo;
    if (line.empty() || line[0] == '#') {
      if (end == text.size()) break;
      continue;
    }
    std::vector<std::string> cells;
    try {
      cells = splitCsvLine(line);
    } catch (const std::exception& e) {
      throw fail(lineNo, e.what());
    }
    if (header.empty()) {
      header = cells;
      std::set<std::string> seen;
      for (size_t i = 0; i < header.size(); ++i) {
        const std::string& h = header[i];
        if (h == "name") {
          nameColumn = static_cast<int>(i);
        } else if (!isParameterName(h)) {
          throw fail(lineNo, "column " + std::to_string(i + 1) + ": '" + h +
                                 "' is not a parameter name (a letter or '_' followed by letters, digits or '_'; "
                                 "the column 'name' names the variants; variant, status and reason are reserved)");
        } else {
          t.parameters.push_back(h);
        }
        if (!seen.insert(h).second) throw fail(lineNo, "column '" + h + "' appears twice");
      }
      if (t.parameters.empty()) throw fail(lineNo, "the header names no parameter column");
    } else {
      if (cells.size() != header.size())
        throw fail(lineNo, std::to_string(cells.size()) + " cells, the header has " + std::to_string(header.size()) +
                               (cells.size() > header.size() ? " (a decimal comma? write 0.5, not 0,5)" : ""));
      std::vector<double> row;
      for (size_t i = 0; i < cells.size(); ++i) {
        if (static_cast<int>(i) == nameColumn) continue;
        double v = 0.0;
        if (!parseNumber(cells[i], v))
          throw fail(lineNo, "column " + columnName(header, i) + ": '" + cells[i] + "' is not a finite number");
        row.push_back(v);
      }
      std::string name;
      if (nameColumn >= 0 && !cells[nameColumn].empty()) {  // an empty name: the generated one
        name = cells[nameColumn];
        if (!isVariantName(name))
          throw fail(lineNo, "name '" + name +
                                 "' cannot name a result folder (letters, digits, '.', '_', '-'; not starting with '.' "
                                 "or '-'; at most 100 characters)");
        if (!names.insert(name).second) throw fail(lineNo, "name '" + name + "' appears twice");
      }
      t.rows.push_back(std::move(row));
      t.names.push_back(name);
      t.lines.push_back(lineNo);
    }
    if (end == text.size()) break;
  }
  if (header.empty()) throw fail(0, "the table is empty (expected a header row naming the parameters)");
  if (t.rows.empty()) throw fail(0, "the table has a header but no rows");
  return t;
}

ParameterTable readParameterTable(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read the parameter table");
  std::stringstream s;
  s << in.rdbuf();
  return parseParameterTable(s.str(), path);
}

ParameterAxis parseParameterAxis(const std::string& spec) {
  const auto eq = spec.find('=');
  auto bad = [&](const std::string& why) {
    return std::invalid_argument("--param " + spec + ": " + why +
                                 " (write name=from:to:count, name=v1,v2,... or name=value)");
  };
  if (eq == std::string::npos) throw bad("no '='");
  ParameterAxis a;
  a.name = trimmed(spec.substr(0, eq));
  if (!isParameterName(a.name))
    throw bad("'" + a.name + "' is not a parameter name (a letter or '_' followed by letters, digits or '_')");
  const std::string rest = trimmed(spec.substr(eq + 1));
  if (rest.empty()) throw bad("no values");
  if (rest.find(':') != std::string::npos) {
    std::vector<std::string> f;
    std::stringstream s(rest);
    for (std::string x; std::getline(s, x, ':');) f.push_back(trimmed(x));
    double from = 0, to = 0, count = 0;
    if (f.size() != 3 || !parseNumber(f[0], from) || !parseNumber(f[1], to) || !parseNumber(f[2], count))
      throw bad("a range is from:to:count with three numbers");
    if (count < 1 || count != std::floor(count) || count > 1e6)
      throw bad("the count must be a whole number from 1 to 1000000");
    const int n = static_cast<int>(count);
    if (n == 1 && from != to) throw bad("one value from a range with two different ends");
    for (int k = 0; k < n; ++k) a.values.push_back(k == n - 1 ? to : roundTo15Digits(from + (to - from) * k / (n - 1)));
  } else {
    std::stringstream s(rest);
    for (std::string x; std::getline(s, x, ',');) {
      double v = 0.0;
      if (!parseNumber(trimmed(x), v)) throw bad("'" + trimmed(x) + "' is not a finite number");
      a.values.push_back(v);
    }
  }
  return a;
}

}  // namespace flexmb::io
