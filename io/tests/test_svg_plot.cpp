// SVG plot writer (io/pictures/SvgPlot): tick generation, XML validity (checked with python's xml.dom.minidom),
// element counts per series, line breaking at NaN / non-positive log values, clipping, escaping,
// determinism and the error path.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/pictures/SvgPlot.hpp"

namespace fs = std::filesystem;
using namespace flexmb::io;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Parses the file with xml.dom.minidom and prints one line per fact:
//   series <polylines>:<markers> ...     (one pair per <g class="series">, in order)
//   vlines <n>                           (lines in <g class="vertical-lines">)
//   text <class>|<content>               (every <text>, content including <tspan>s)
//   coords <minx> <miny> <maxx> <maxy>   (over all polyline points; "coords none" without any)
const char* kAnalyzer = R"PY(
import sys, xml.dom.minidom as m
d = m.parse(sys.argv[1])
def content(n):
    return ''.join(c.data if c.nodeType == c.TEXT_NODE else content(c) for c in n.childNodes)
series = []
for g in d.getElementsByTagName('g'):
    if g.getAttribute('class') == 'series':
        mk = sum(len([c for c in h.childNodes if c.nodeType == 1])
                 for h in g.getElementsByTagName('g') if h.getAttribute('class') == 'markers')
        series.append('%d:%d' % (len(g.getElementsByTagName('polyline')), mk))
print('series ' + ' '.join(series))
vl = sum(len(g.getElementsByTagName('line')) for g in d.getElementsByTagName('g')
         if g.getAttribute('class') == 'vertical-lines')
print('vlines %d' % vl)
for t in d.getElementsByTagName('text'):
    sys.stdout.buffer.write(('text %s|%s\n' % (t.getAttribute('class'), content(t))).encode('utf-8'))
xs, ys = [], []
for p in d.getElementsByTagName('polyline'):
    for pair in p.getAttribute('points').split():
        x, y = pair.split(',')
        xs.append(float(x)); ys.append(float(y))
print('coords %g %g %g %g' % (min(xs), min(ys), max(xs), max(ys)) if xs else 'coords none')
)PY";

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() / ("flexmb_svg_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

struct Analysis {
  bool parsed = false;
  std::string output;
  std::vector<std::string> series;  // "<polylines>:<markers>"
  int vlines = -1;
  std::vector<std::pair<std::string, std::string>> texts;  // (class, content)
  std::string coords;
  bool hasText(const std::string& cls, const std::string& content) const {
    return std::find(texts.begin(), texts.end(), std::make_pair(cls, content)) != texts.end();
  }
  int countClass(const std::string& cls) const {
    return static_cast<int>(std::count_if(texts.begin(), texts.end(), [&](const auto& t) { return t.first == cls; }));
  }
};

// Writes the plot with writeSvg and runs the analyzer on it.
Analysis analyze(const TempDir& dir, const Plot& plot) {
  const std::string svg = dir.file("plot.svg"), script = dir.file("analyze.py");
  writeSvg(svg, plot);
  std::ofstream(script) << kAnalyzer;
  Analysis a;
  FILE* pipe = ::popen(("/usr/bin/python3 '" + script + "' '" + svg + "' 2>&1").c_str(), "r");
  if (!pipe) return a;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) a.output.append(buf, n);
  a.parsed = ::pclose(pipe) == 0;
  std::istringstream in(a.output);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("series", 0) == 0) {
      std::istringstream ls(line.substr(6));
      std::string s;
      while (ls >> s) a.series.push_back(s);
    } else if (line.rfind("vlines ", 0) == 0) {
      a.vlines = std::stoi(line.substr(7));
    } else if (line.rfind("text ", 0) == 0) {
      const auto bar = line.find('|');
      a.texts.emplace_back(line.substr(5, bar - 5), line.substr(bar + 1));
    } else if (line.rfind("coords ", 0) == 0) {
      a.coords = line.substr(7);
    }
  }
  return a;
}

bool containsNoCase(std::string hay, std::string needle) {
  for (auto* s : {&hay, &needle})
    std::transform(s->begin(), s->end(), s->begin(), [](unsigned char c) { return std::tolower(c); });
  return hay.find(needle) != std::string::npos;
}

Series makeSeries(std::string label, std::vector<double> x, std::vector<double> y) {
  Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  return s;
}

// A frequency-against-deflection style plot: three kinds of series, reference lines, notes.
Plot samplePlot() {
  Plot p;
  p.title = "First eigenfrequency";
  p.x.label = "deflection [mm]";
  p.y.label = "frequency [Hz]";
  p.notes = {"beams: 4 elements each", "no damping"};
  p.verticalLines = {-2.5, 2.5};
  p.series.push_back(makeSeries("full", {-3, -2, -1, 0, 1, 2, 3}, {50, 55, 58, 60, 58, 55, 50}));
  Series reduced = makeSeries("reduced", {-3, -1.5, 0, 1.5, 3}, {51, 56, 60.5, 56, 51});
  reduced.line = false;
  reduced.markers = true;
  p.series.push_back(reduced);
  Series dashed = makeSeries("linearised", {-3, 0, 3}, {60, 60, 60});
  dashed.dashed = true;
  dashed.markers = true;
  p.series.push_back(dashed);
  return p;
}

}  // namespace

TEST(SvgPlotTicks, LinearTicksOn125GridInsideRange) {
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {0.013, 0.087}, {-7.3, 12.1}, {0, 1}, {1e5, 3.7e6}, {-1e-9, 4e-9}, {0.99, 1.01}}) {
    SCOPED_TRACE(std::to_string(lo) + " .. " + std::to_string(hi));
    const std::vector<double> t = linearTicks(lo, hi);
    ASSERT_GE(t.size(), 3u);
    ASSERT_LE(t.size(), 8u);
    const double step = t[1] - t[0];
    const double mant = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mant - 1) < 1e-6 || std::abs(mant - 2) < 1e-6 || std::abs(mant - 5) < 1e-6) << "step " << step;
    for (std::size_t i = 0; i < t.size(); ++i) {
      EXPECT_GE(t[i], lo);
      EXPECT_LE(t[i], hi);
      EXPECT_NEAR(t[i] / step, std::round(t[i] / step), 1e-6);
      if (i > 0) {
        EXPECT_NEAR(t[i] - t[i - 1], step, 1e-9 * step);
      }
    }
  }
  // The values are the doubles nearest the decimals, and all the grid points in the range.
  EXPECT_EQ(linearTicks(0.013, 0.087), (std::vector<double>{0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08}));
  EXPECT_EQ(linearTicks(1.0, 1.0), std::vector<double>{1.0});
  EXPECT_EQ(linearTicks(1.0, 0.0).front(), 0.0);  // swapped bounds
  EXPECT_TRUE(linearTicks(kNaN, 1.0).empty());
}

TEST(SvgPlotTicks, LogTicksAreDecades) {
  EXPECT_EQ(logTicks(3e-7, 2e-2), (std::vector<double>{1e-6, 1e-5, 1e-4, 1e-3, 1e-2}));
  const std::vector<double> wide = logTicks(1e-16, 1.0);  // singular values: stride of decades
  ASSERT_GE(wide.size(), 3u);
  EXPECT_LE(wide.size(), 8u);
  for (double v : wide) EXPECT_DOUBLE_EQ(v, std::pow(10.0, std::round(std::log10(v))));
  EXPECT_EQ(logTicks(2.0, 5.0), (std::vector<double>{2.0, 5.0}));  // no decade inside: 1-2-5
  EXPECT_FALSE(logTicks(1.1, 1.9).empty());                        // within 1-2-5: linear
  EXPECT_TRUE(logTicks(-1.0, 10.0).empty());
}

TEST(SvgPlot, DocumentParsesAndHasTheExpectedElements) {
  TempDir dir;
  const Analysis a = analyze(dir, samplePlot());
  ASSERT_TRUE(a.parsed) << a.output;
  // full: one line; reduced: markers only; linearised: dashed line with markers.
  EXPECT_EQ(a.series, (std::vector<std::string>{"1:0", "0:5", "1:3"}));
  EXPECT_EQ(a.vlines, 2);
  EXPECT_TRUE(a.hasText("title", "First eigenfrequency"));
  EXPECT_EQ(a.countClass("note"), 2);
  EXPECT_TRUE(a.hasText("note", "no damping"));
  EXPECT_TRUE(a.hasText("axis-label", "deflection [mm]"));
  EXPECT_TRUE(a.hasText("axis-label", "frequency [Hz]"));
  EXPECT_TRUE(a.hasText("", "reduced"));  // legend entry
  EXPECT_EQ(a.countClass("no-data"), 0);
  const std::string svg = renderSvg(samplePlot());
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
  EXPECT_NE(svg.find("clip-path=\"url(#flexmb-plot-area)\""), std::string::npos);
  EXPECT_NE(svg.find("#0072B2"), std::string::npos);  // automatic palette colour
}

TEST(SvgPlot, ALongTitleContinuesOnLinesThatFitThePage) {
  // Issue 35: a Bode diagram's title with the model's path ran off both sides of the 720 px page.
  Plot p = samplePlot();
  p.title =
      "rotation z node 4 / INPUTF 1: moment z node 4 (/a/long/path/to/the/models/of/a/user/spatial/"
      "cross_spring_pivot_transfer.dat)";
  const std::string svg = renderSvg(p);
  std::vector<std::string> lines;
  for (size_t at = 0; (at = svg.find("class=\"title\"", at)) != std::string::npos; ++at) {
    const size_t open = svg.find('>', at), close = svg.find("</text>", at);
    lines.push_back(svg.substr(open + 1, close - open - 1));
  }
  ASSERT_GE(lines.size(), 2u) << svg.substr(0, 800);
  std::string joined, title;
  for (const std::string& l : lines) {
    joined += l;
    EXPECT_LE(l.size() * 15 * 0.6, static_cast<size_t>(p.width) - 20) << l;  // bold 15 px glyphs ~9 px
  }
  for (char c : p.title)
    if (c != ' ') title += c;
  joined.erase(std::remove(joined.begin(), joined.end(), ' '), joined.end());
  EXPECT_EQ(joined, title);  // every character, in order (broken after spaces and slashes)
  TempDir dir;
  EXPECT_TRUE(analyze(dir, p).parsed);
}

TEST(SvgPlot, NaNBreaksLineAndLogDropsNonPositive) {
  TempDir dir;
  Plot p;
  p.series.push_back(makeSeries("gap", {0, 1, 2, 3, 4, 5}, {1, 2, kNaN, 3, 4, 5}));
  p.series.push_back(makeSeries("spike", {0, 1, 2, 3}, {1, kInf, 2, 3}));
  p.series.push_back(makeSeries("clean", {0, 1, 2}, {1, 2, 3}));
  Analysis a = analyze(dir, p);
  ASSERT_TRUE(a.parsed) << a.output;
  EXPECT_EQ(a.series, (std::vector<std::string>{"2:0", "2:0", "1:0"}));
  std::string svg = renderSvg(p);
  EXPECT_FALSE(containsNoCase(svg, "nan"));
  EXPECT_FALSE(containsNoCase(svg, "inf"));

  // Relative error over time on a log y axis: -1 and 0 are dropped and break the line.
  Plot q;
  q.y.log = true;
  Series e = makeSeries("error", {0, 1, 2, 3, 4, 5, 6}, {1e-3, 2e-3, -1, 1e-2, 2e-2, 0, 3e-2});
  e.markers = true;
  q.series.push_back(e);
  a = analyze(dir, q);
  ASSERT_TRUE(a.parsed) << a.output;
  EXPECT_EQ(a.series, std::vector<std::string>{"3:5"});  // runs {0,1}, {3,4}, {6}; 5 markers
  svg = renderSvg(q);
  EXPECT_FALSE(containsNoCase(svg, "nan"));
  EXPECT_FALSE(containsNoCase(svg, "inf"));
}

TEST(SvgPlot, EmptyAndAllNaNGiveNoDataDocument) {
  TempDir dir;
  Analysis a = analyze(dir, Plot{});
  ASSERT_TRUE(a.parsed) << a.output;
  EXPECT_TRUE(a.hasText("no-data", "no data"));
  EXPECT_TRUE(a.series.empty());

  Plot p;
  p.x.log = p.y.log = true;
  p.series.push_back(makeSeries("nothing", {kNaN, 1, -2}, {1, kNaN, 3}));
  p.series.push_back(makeSeries("empty", {}, {}));
  p.verticalLines = {kNaN, 5};
  a = analyze(dir, p);
  ASSERT_TRUE(a.parsed) << a.output;
  EXPECT_TRUE(a.hasText("no-data", "no data"));
  EXPECT_EQ(a.series, (std::vector<std::string>{"0:0", "0:0"}));
  const std::string svg = renderSvg(p);
  EXPECT_FALSE(containsNoCase(svg, "nan"));
  EXPECT_FALSE(containsNoCase(svg, "inf"));
}

TEST(SvgPlot, WorkPrecisionLogLogWithDecadeLabelsAndClipping) {
  TempDir dir;
  Plot p;
  p.title = "Work-precision";
  p.x.log = p.y.log = true;
  p.x.label = "wall time [s]";
  p.y.label = "error";
  p.y.min = 1e-6;  // given bounds: the last point of "rk4" lies far outside and is clipped
  p.y.max = 1e-1;
  for (const char* method : {"ode45", "rk4", "newmark"}) {
    Series s = makeSeries(method, {1e-3, 1e-2, 1e-1, 1.0}, {1e-2, 1e-3, 1e-4, 1e-5});
    s.markers = true;
    p.series.push_back(s);
  }
  p.series[1].y.back() = 1e-250;
  const Analysis a = analyze(dir, p);
  ASSERT_TRUE(a.parsed) << a.output;
  EXPECT_EQ(a.series, (std::vector<std::string>{"1:4", "1:3", "1:4"}));
  // Decade labels as 10 with a superscript exponent.
  EXPECT_TRUE(a.hasText("", "10-6"));
  EXPECT_TRUE(a.hasText("", "10-1"));
  EXPECT_TRUE(a.hasText("", "10-3"));
  // All polyline coordinates inside the document.
  std::istringstream c(a.coords);
  double x0, y0, x1, y1;
  ASSERT_TRUE(c >> x0 >> y0 >> x1 >> y1) << a.coords;
  EXPECT_GE(x0, 0);
  EXPECT_GE(y0, 0);
  EXPECT_LE(x1, p.width);
  EXPECT_LE(y1, p.height);
}

TEST(SvgPlot, EscapesSpecialCharactersInEveryText) {
  TempDir dir;
  Plot p;
  p.title = "a<b & \"c\"";
  p.notes = {"x > 0 & y < 1"};
  p.x.label = "<x>";
  p.y.label = "'y' & \"z\"";
  p.series.push_back(makeSeries("A&B <full>", {0, 1}, {0, 1}));
  p.series.back().color = "#123\"456";
  const Analysis a = analyze(dir, p);
  ASSERT_TRUE(a.parsed) << a.output;
  EXPECT_TRUE(a.hasText("title", "a<b & \"c\""));
  EXPECT_TRUE(a.hasText("note", "x > 0 & y < 1"));
  EXPECT_TRUE(a.hasText("axis-label", "<x>"));
  EXPECT_TRUE(a.hasText("axis-label", "'y' & \"z\""));
  EXPECT_TRUE(a.hasText("", "A&B <full>"));
  const std::string svg = renderSvg(p);
  EXPECT_NE(svg.find("a&lt;b &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_EQ(svg.find("<full>"), std::string::npos);
}

TEST(SvgPlot, SameInputGivesIdenticalBytes) {
  TempDir dir;
  const Plot p = samplePlot();
  const std::string first = renderSvg(p);
  EXPECT_EQ(first, renderSvg(p));
  writeSvg(dir.file("a.svg"), p);
  std::ifstream in(dir.file("a.svg"), std::ios::binary);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(first, written);
}

TEST(SvgPlot, UnwritablePathThrowsNamingThePath) {
  const std::string path = "/nonexistent-flexmb-directory/sub/plot.svg";
  try {
    writeSvg(path, samplePlot());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}
