#include "io/formats/BasisFile.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include "text/NumberText.hpp"

namespace flexmb::io {
namespace {

constexpr std::string_view kMagic = "flexmb basis";

bool isBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
  return s;
}

using text::appendG17;
using text::g17;

// Shortened quote of user text for messages.
std::string quote(std::string_view s) {
  std::string q = "'";
  if (s.size() > 40) {
    q.append(s.substr(0, 37));
    q += "...";
  } else {
    q.append(s);
  }
  for (char& c : q)
    if (static_cast<unsigned char>(c) < 0x20) c = '?';
  return q + "'";
}

// The whole field must be a finite double (a leading '+' is accepted).
std::optional<double> parseDouble(std::string_view s) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) return std::nullopt;
  }
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long> parseLong(std::string_view s) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) return std::nullopt;
  }
  if (s.empty()) return std::nullopt;
  long v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

std::vector<std::string_view> splitBlanks(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && isBlank(s[i])) ++i;
    std::size_t j = i;
    while (j < s.size() && !isBlank(s[j])) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

bool isReserved(std::string_view key) {
  return key == "method" || key == "model" || key == "size" || key == "large" || key == "singular values";
}

// ---------------------------------------------------------------------------------------------
// Writing: validation.

[[noreturn]] void badArg(const std::string& msg) { throw std::invalid_argument("writeBasis: " + msg); }

void checkText(std::string_view s, const std::string& what, bool allowEmpty) {
  if (s.empty()) {
    if (!allowEmpty) badArg(what + " is empty");
    return;
  }
  for (char c : s)
    if (c == '\n' || c == '\r') badArg(what + " " + quote(s) + " contains a line break");
  if (isBlank(s.front()) || isBlank(s.back()))
    badArg(what + " " + quote(s) + " has leading or trailing blanks (would not read back)");
}

// Columns j < large.size() of V must be e_{large[j]}.
template <class Fail>
void checkLarge(const std::vector<int>& large, const Eigen::MatrixXd& V, Fail&& fail) {
  if (static_cast<Eigen::Index>(large.size()) > V.cols())
    fail(std::to_string(large.size()) + " large coordinates but V has only " + std::to_string(V.cols()) + " columns");
  std::vector<char> seen(static_cast<std::size_t>(V.rows()), 0);
  for (std::size_t j = 0; j < large.size(); ++j) {
    const int i = large[j];
    if (i < 0 || i >= V.rows())
      fail("large index " + std::to_string(i) + " out of range [0, " + std::to_string(V.rows()) + ")");
    if (seen[static_cast<std::size_t>(i)]) fail("duplicate large index " + std::to_string(i));
    seen[static_cast<std::size_t>(i)] = 1;
    const Eigen::Index col = static_cast<Eigen::Index>(j);
    for (Eigen::Index r = 0; r < V.rows(); ++r)
      if (V(r, col) != (r == i ? 1.0 : 0.0))
        fail("column " + std::to_string(j) + " of V is not the unit vector of large index " + std::to_string(i) +
             " (V(" + std::to_string(r) + ", " + std::to_string(j) + ") = " + g17(V(r, col)) + ")");
  }
}

// ---------------------------------------------------------------------------------------------
// Reading.

class Parser {
 public:
  Parser(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}

  Eigen::MatrixXd run(BasisInfo* out) {
    splitLines();
    BasisInfo info;
    bool haveMagic = false;
    bool haveRows = false;
    bool haveMethod = false, haveModel = false, haveLarge = false, haveSv = false;
    int sizeLine = 0, largeLine = 0, firstRowLine = 0;
    long sizeRows = -1, sizeCols = -1;
    Eigen::Index ncols = -1;
    std::vector<double> values;
    Eigen::Index nrows = 0;
    std::vector<std::string> paramKeys;

    for (std::size_t k = 0; k < lines_.size(); ++k) {
      const int ln = static_cast<int>(k) + 1;
      std::string_view line = trim(lines_[k]);
      if (line.empty()) continue;

      if (!haveMagic) {
        if (line.front() != '#' || trim(line.substr(1)) != kMagic)
          fail(ln, "missing header: the first line must be '# flexmb basis', found " + quote(line));
        haveMagic = true;
        continue;
      }

      if (line.front() == '#') {
        if (haveRows)
          fail(ln, "header line after the data rows (first row at line " + std::to_string(firstRowLine) + ")");
        const std::string_view body = line.substr(1);
        const std::size_t colon = body.find(':');
        if (colon == std::string_view::npos) fail(ln, "expected a header line '# key: value', found " + quote(line));
        const std::string_view key = trim(body.substr(0, colon));
        const std::string_view value = trim(body.substr(colon + 1));
        if (key.empty()) fail(ln, "empty key in header line " + quote(line));

        if (key == "method") {
          if (haveMethod) fail(ln, "duplicate 'method' line");
          haveMethod = true;
          info.method = std::string(value);
        } else if (key == "model") {
          if (haveModel) fail(ln, "duplicate 'model' line");
          haveModel = true;
          info.model = std::string(value);
        } else if (key == "size") {
          if (sizeLine) fail(ln, "duplicate 'size' line");
          sizeLine = ln;
          parseSize(ln, value, sizeRows, sizeCols);
        } else if (key == "large") {
          if (haveLarge) fail(ln, "duplicate 'large' line");
          haveLarge = true;
          largeLine = ln;
          for (std::string_view tok : splitBlanks(value)) {
            const auto v = parseLong(tok);
            if (!v || *v < 0 || *v > 2147483647L)
              fail(ln, "large index " + quote(tok) + " is not a non-negative integer");
            info.large.push_back(static_cast<int>(*v));
          }
        } else if (key == "singular values") {
          if (haveSv) fail(ln, "duplicate 'singular values' line");
          haveSv = true;
          const auto toks = splitBlanks(value);
          info.scaledSingularValues.resize(static_cast<Eigen::Index>(toks.size()));
          for (std::size_t i = 0; i < toks.size(); ++i) {
            const auto v = parseDouble(toks[i]);
            if (!v) fail(ln, "singular value " + quote(toks[i]) + " is not a finite number");
            info.scaledSingularValues[static_cast<Eigen::Index>(i)] = *v;
          }
        } else {
          for (const std::string& pk : paramKeys)
            if (pk == key) fail(ln, "duplicate parameter " + quote(key));
          paramKeys.emplace_back(key);
          info.parameters.emplace_back(std::string(key), std::string(value));
        }
        continue;
      }

      // Data row.
      if (!haveRows) {
        haveRows = true;
        firstRowLine = ln;
      }
      Eigen::Index count = 0;
      std::size_t start = 0;
      while (true) {
        const std::size_t comma = line.find(',', start);
        const std::string_view field =
            trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        ++count;
        if (field.empty()) fail(ln, "empty field " + std::to_string(count));
        const auto v = parseDouble(field);
        if (!v) fail(ln, "field " + std::to_string(count) + " " + quote(field) + " is not a finite number");
        values.push_back(*v);
        if (comma == std::string_view::npos) break;
        start = comma + 1;
      }
      if (ncols < 0) {
        ncols = count;
        if (sizeLine && ncols != sizeCols)
          fail(ln, "row has " + std::to_string(count) + " values but the size line (line " + std::to_string(sizeLine) +
                       ") says " + std::to_string(sizeCols) + " columns");
      } else if (count != ncols) {
        fail(ln, "ragged row: " + std::to_string(count) + " values, expected " + std::to_string(ncols) +
                     " (as in line " + std::to_string(firstRowLine) + ")");
      }
      ++nrows;
    }

    const int lastLine = lines_.empty() ? 1 : static_cast<int>(lines_.size());
    if (!haveMagic) fail(1, "empty file");
    if (!haveRows) fail(lastLine, "no data rows");
    if (sizeLine && nrows != sizeRows)
      fail(lastLine, std::to_string(nrows) + " data rows but the size line (line " + std::to_string(sizeLine) +
                         ") says " + std::to_string(sizeRows));

    Eigen::MatrixXd V(nrows, ncols);
    for (Eigen::Index i = 0; i < nrows; ++i)
      for (Eigen::Index j = 0; j < ncols; ++j) V(i, j) = values[static_cast<std::size_t>(i * ncols + j)];

    checkLarge(info.large, V, [&](const std::string& msg) { fail(largeLine, msg); });

    if (out) *out = std::move(info);
    return V;
  }

 private:
  void splitLines() {
    std::string_view t = text_;
    if (t.substr(0, 3) == "\xEF\xBB\xBF") t.remove_prefix(3);  // UTF-8 byte order mark
    std::size_t start = 0;
    while (start < t.size()) {
      std::size_t nl = t.find('\n', start);
      if (nl == std::string_view::npos) nl = t.size();
      std::string_view line = t.substr(start, nl - start);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      lines_.push_back(line);
      start = nl + 1;
    }
  }

  void parseSize(int ln, std::string_view value, long& rows, long& cols) {
    const std::size_t x = value.find('x');
    const auto r = x == std::string_view::npos ? std::nullopt : parseLong(trim(value.substr(0, x)));
    const auto c = x == std::string_view::npos ? std::nullopt : parseLong(trim(value.substr(x + 1)));
    if (!r || !c || *r < 1 || *c < 1)
      fail(ln, "size must be 'rows x columns' with positive integers, found " + quote(value));
    rows = *r;
    cols = *c;
  }

  [[noreturn]] void fail(int line, const std::string& msg) const {
    throw std::runtime_error(name_ + ":" + std::to_string(line) + ": " + msg);
  }

  std::string_view text_;
  std::string name_;
  std::vector<std::string_view> lines_;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

std::string formatBasis(const Eigen::MatrixXd& V, const BasisInfo& info) {
  if (V.rows() == 0 || V.cols() == 0)
    badArg("V is " + std::to_string(V.rows()) + " x " + std::to_string(V.cols()) +
           " (must have at least one row and one column)");
  for (Eigen::Index j = 0; j < V.cols(); ++j)
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      if (!std::isfinite(V(i, j)))
        badArg("V(" + std::to_string(i) + ", " + std::to_string(j) + ") = " + g17(V(i, j)) + " is not finite");
  checkText(info.method, "method", false);
  checkText(info.model, "model", true);
  for (const auto& [key, value] : info.parameters) {
    checkText(key, "parameter key", false);
    if (key.find(':') != std::string::npos) badArg("parameter key " + quote(key) + " contains ':'");
    if (isReserved(key)) badArg("parameter key " + quote(key) + " is reserved");
    checkText(value, "value of parameter " + quote(key), true);
  }
  for (std::size_t i = 0; i < info.parameters.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (info.parameters[i].first == info.parameters[k].first)
        badArg("duplicate parameter key " + quote(info.parameters[i].first));
  checkLarge(info.large, V, [](const std::string& msg) { badArg(msg); });
  for (Eigen::Index k = 0; k < info.scaledSingularValues.size(); ++k)
    if (!std::isfinite(info.scaledSingularValues[k])) badArg("singular value " + std::to_string(k) + " is not finite");

  auto header = [](std::string& out, std::string_view key, std::string_view value) {
    out += "# ";
    out += key;
    out += ':';
    if (!value.empty()) {
      out += ' ';
      out += value;
    }
    out += '\n';
  };
  std::string out;
  out.reserve(static_cast<std::size_t>(V.size()) * 24 + 256);
  out += "# ";
  out += kMagic;
  out += '\n';
  header(out, "method", info.method);
  header(out, "model", info.model);
  header(out, "size", std::to_string(V.rows()) + " x " + std::to_string(V.cols()));
  for (const auto& [key, value] : info.parameters) header(out, key, value);
  std::string large;
  for (std::size_t j = 0; j < info.large.size(); ++j) {
    if (j) large += ' ';
    large += std::to_string(info.large[j]);
  }
  header(out, "large", large);
  if (info.scaledSingularValues.size() > 0) {
    std::string sv;
    for (Eigen::Index k = 0; k < info.scaledSingularValues.size(); ++k) {
      if (k) sv += ' ';
      appendG17(sv, info.scaledSingularValues[k]);
    }
    header(out, "singular values", sv);
  }
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (Eigen::Index j = 0; j < V.cols(); ++j) {
      if (j) out += ',';
      appendG17(out, V(i, j));
    }
    out += '\n';
  }
  return out;
}

void writeBasis(const std::string& path, const Eigen::MatrixXd& V, const BasisInfo& info) {
  const std::string text = formatBasis(V, info);  // validates before the file is touched
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f)
    throw std::runtime_error("cannot open '" + path +
                             "' for writing: " + (errno ? std::strerror(errno) : "unknown error"));
  errno = 0;
  const bool shortWrite = std::fwrite(text.data(), 1, text.size(), f) != text.size();
  const int writeErr = errno;
  const bool bad = std::ferror(f) != 0;
  errno = 0;
  const int rc = std::fclose(f);
  const int closeErr = errno;
  if (shortWrite || bad || rc != 0) {
    const int e = writeErr ? writeErr : closeErr;
    throw std::runtime_error("error writing '" + path + "': " + (e ? std::strerror(e) : "write failed"));
  }
}

Eigen::MatrixXd parseBasis(const std::string& text, const std::string& name, BasisInfo* info) {
  return Parser(text, name).run(info);
}

Eigen::MatrixXd readBasis(const std::string& path, BasisInfo* info) {
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f)
    throw std::runtime_error("cannot open '" + path +
                             "' for reading: " + (errno ? std::strerror(errno) : "unknown error"));
  std::string text;
  char buf[65536];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
  const bool bad = std::ferror(f) != 0;
  std::fclose(f);
  if (bad) throw std::runtime_error("error reading '" + path + "'");
  return parseBasis(text, path, info);
}

Eigen::MatrixXd readBasisFor(const std::string& path, int degreesOfFreedom) {
  Eigen::MatrixXd V = readBasis(path);
  if (V.rows() != degreesOfFreedom)
    throw std::runtime_error(path + ": basis has " + std::to_string(V.rows()) + " rows, the model has " +
                             std::to_string(degreesOfFreedom) + " degrees of freedom");
  return V;
}

}  // namespace flexmb::io
