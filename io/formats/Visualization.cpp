#include "io/formats/Visualization.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

namespace flexmb::io {

namespace {

// Words of a line up to a comment (#, % or ;). Any other byte, a NUL too, belongs to a word:
// strchr would find a NUL in its own terminator and split nothing.
std::vector<std::string> words(std::string_view line) {
  constexpr std::string_view kEnds = " \t\r\v\f#%;";
  std::vector<std::string> w;
  size_t i = 0;
  while (i < line.size()) {
    const char c = line[i];
    if (c == '#' || c == '%' || c == ';') break;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f') {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < line.size() && kEnds.find(line[j]) == std::string_view::npos) ++j;
    w.emplace_back(line.substr(i, j - i));
    i = j;
  }
  return w;
}

bool number(const std::string& s, double& v) {
  std::string t = s;
  for (char& c : t)
    if (c == 'd' || c == 'D') c = 'e';
  const char* end = t.data() + t.size();
  const auto r = std::from_chars(t.data(), end, v);
  return r.ec == std::errc() && r.ptr == end && std::isfinite(v);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

const std::vector<std::pair<std::string, std::string>>& visualizationKeywords() {
  static const std::vector<std::pair<std::string, std::string>> k = {
      {"BEAMPROPS", "`BEAMPROPS e1 e2 ...`: the elements the following CROSSTYPE and CROSSDIM describe"},
      {"CROSSTYPE", "`CROSSTYPE RECT` or `CROSSTYPE CIRC`: cross-section shape"},
      {"CROSSDIM",
       "`CROSSDIM w t` (rectangle: width along the local y axis, thickness along z) or `CROSSDIM d` (circle): "
       "section dimensions, drawn around the beam axis"},
      {"GRAPHICS", "`GRAPHICS e1 e2 ...`: the elements the following FACECOLOR and OPACITY describe"},
      {"FACECOLOR", "`FACECOLOR r g b` (0..1): the elements' colour in the 3-D page"},
      {"OPACITY", "`OPACITY a` (0..1)"},
      {"DONOTDRAW", "`DONOTDRAW e1 e2 ...`: elements left out of the pictures"},
      {"INITIAL", "`INITIAL` then `COLOR r g b`: the initial configuration's colour (accepted, not used)"},
      {"COLOR", "see INITIAL"},
  };
  return k;
}

VisualizationSection parseVisualization(std::string_view text, int firstLine, const std::string& file) {
  VisualizationSection out;
  std::vector<int> propsList, graphicsList;
  // CROSSTYPE and CROSSDIM may come in either order: the type decides how the numbers are read.
  std::vector<double> dims;
  int dimsLine = 0;
  core::ElementAppearance::Section type = core::ElementAppearance::Section::Unknown;
  auto note = [&](int line, const std::string& msg) {
    out.notes.push_back(file + ":" + std::to_string(line) + ": VISUALIZATION: " + msg + " (ignored)");
  };
  auto applySection = [&]() {
    if (type == core::ElementAppearance::Section::Unknown || dims.empty()) return;
    const bool rect = type == core::ElementAppearance::Section::Rectangle;
    if (rect && dims.size() < 2) {
      note(dimsLine, "CROSSDIM of a RECT section needs the width and the thickness");
      return;
    }
    for (int e : propsList) {
      auto& a = out.appearance[e];
      a.section = type;
      a.width = dims[0];
      a.thickness = rect ? dims[1] : dims[0];
    }
  };
  auto labels = [&](const std::vector<std::string>& w, int line, std::vector<int>& list) {
    list.clear();
    for (size_t i = 1; i < w.size(); ++i) {
      double v;
      if (!number(w[i], v) || v < 1 || v != std::floor(v) || v > 1e9) {
        note(line, w[0] + ": '" + w[i] + "' is not an element number");
        continue;
      }
      list.push_back(static_cast<int>(v));
    }
  };
  int lineNo = firstLine - 1;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    const std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    const std::vector<std::string> w = words(line);
    if (w.empty()) continue;
    const std::string k = upper(w[0]);
    std::vector<double> v;
    bool numeric = true;
    for (size_t i = 1; i < w.size(); ++i) {
      double x;
      if (number(w[i], x))
        v.push_back(x);
      else
        numeric = false;
    }
    if (k == "BEAMPROPS") {
      labels(w, lineNo, propsList);
      type = core::ElementAppearance::Section::Unknown;
      dims.clear();
    } else if (k == "CROSSTYPE") {
      const std::string t = w.size() > 1 ? upper(w[1]) : "";
      if (t == "RECT")
        type = core::ElementAppearance::Section::Rectangle;
      else if (t == "CIRC")
        type = core::ElementAppearance::Section::Circle;
      else
        note(lineNo, "CROSSTYPE must be RECT or CIRC");
      applySection();
    } else if (k == "CROSSDIM") {
      if (!numeric || v.empty() || std::any_of(v.begin(), v.end(), [](double x) { return !(x > 0); })) {
        note(lineNo, "CROSSDIM needs positive dimensions");
        continue;
      }
      dims = v;
      dimsLine = lineNo;
      applySection();
    } else if (k == "GRAPHICS") {
      labels(w, lineNo, graphicsList);
    } else if (k == "FACECOLOR") {
      if (!numeric || v.size() < 3 || std::any_of(v.begin(), v.begin() + 3, [](double x) { return x < 0 || x > 1; })) {
        note(lineNo, "FACECOLOR needs three components between 0 and 1");
        continue;
      }
      for (int e : graphicsList) {
        auto& a = out.appearance[e];
        a.hasColor = true;
        std::copy(v.begin(), v.begin() + 3, a.color);
      }
    } else if (k == "OPACITY") {
      if (!numeric || v.size() != 1 || v[0] < 0 || v[0] > 1) {
        note(lineNo, "OPACITY needs one value between 0 and 1");
        continue;
      }
      for (int e : graphicsList) out.appearance[e].opacity = v[0];
    } else if (k == "DONOTDRAW") {
      std::vector<int> list;
      labels(w, lineNo, list);
      for (int e : list) out.appearance[e].hidden = true;
    } else if (k == "INITIAL" || k == "COLOR") {
      // the initial configuration's colour: the pictures draw it in grey
    } else {
      note(lineNo, "unknown statement '" + w[0] + "'");
    }
  }
  return out;
}

}  // namespace flexmb::io
