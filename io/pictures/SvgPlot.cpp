#include "io/pictures/SvgPlot.hpp"
#include "io/formats/TextOutput.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <tuple>
#include <utility>

namespace flexmb::io {
namespace {

// Okabe-Ito palette (yellow left out: too light on white).
constexpr std::array<const char*, 7> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000"};
constexpr double kCharWidth = 6.2;  // rough width of one character at font-size 11
constexpr double kClipPad = 2.0;    // the clip rectangle is the plot area grown by this (strokes)

// 10^e, correctly rounded for the exact cases (10^-22 .. 10^22 through an exact power).
double pow10(int e) {
  if (e >= 0) return std::pow(10.0, e);
  if (e >= -22) return 1.0 / std::pow(10.0, -e);
  return std::pow(10.0, e);
}

// k * m * 10^e; for e < 0 as a division by an exact power, so 3 * 10^-2 is the double nearest 0.03.
double gridValue(long long k, int m, int e) {
  const double km = static_cast<double>(k) * m;
  if (e >= 0) return km * pow10(e);
  if (e >= -22) return km / std::pow(10.0, -e);
  return km * pow10(e);
}

long long floorDiv(long long a, long long b) { return a / b - ((a % b != 0) && ((a < 0) != (b < 0))); }
long long ceilDiv(long long a, long long b) { return -floorDiv(-a, b); }

// The 1-2-5 grid for [lo, hi] (lo < hi, both finite): step m * 10^e, tick indices k0 .. k1.
struct Grid {
  int m = 1, e = 0;
  long long k0 = 0, k1 = -1;
  double step() const { return gridValue(1, m, e); }
};

Grid niceGrid(double lo, double hi, int maxTicks) {
  maxTicks = std::max(maxTicks, 2);
  const double halfSpan = hi / 2 - lo / 2;  // no overflow for lo = -DBL_MAX, hi = DBL_MAX
  Grid g;
  g.e = static_cast<int>(std::floor(std::log10(halfSpan) + std::log10(2.0 / maxTicks))) - 1;
  static constexpr int kMant[] = {1, 2, 5};
  for (int iter = 0; iter < 64; ++iter) {
    for (int m : kMant) {
      g.m = m;
      const double step = g.step();
      const double a = std::ceil(lo / step - 1e-9), b = std::floor(hi / step + 1e-9);
      if (b - a + 1 <= maxTicks) {
        g.k0 = static_cast<long long>(a);
        g.k1 = static_cast<long long>(b);
        return g;
      }
    }
    ++g.e;
  }
  return g;  // not reached for finite bounds
}

std::string fixed2(double v) {
  v = std::round(v * 100) / 100;
  if (v == 0 || !std::isfinite(v)) v = 0;  // no "-0"; non-finite never reaches here
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 2);
  std::string s(buf, r.ptr);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

// "1.50e+06" -> "1.5e6", "2e-07" -> "2e-7".
std::string tidyScientific(std::string s) {
  const auto ePos = s.find('e');
  if (ePos == std::string::npos) return s;
  std::string mant = s.substr(0, ePos), ex = s.substr(ePos + 1);
  if (mant.find('.') != std::string::npos) {
    while (mant.back() == '0') mant.pop_back();
    if (mant.back() == '.') mant.pop_back();
  }
  std::string sign;
  if (!ex.empty() && (ex[0] == '+' || ex[0] == '-')) {
    if (ex[0] == '-') sign = "-";
    ex.erase(0, 1);
  }
  while (ex.size() > 1 && ex[0] == '0') ex.erase(0, 1);
  return mant + "e" + sign + ex;
}

// Tick label for a value on a grid of the given step; scientific for very large/small axes.
std::string numberLabel(double v, double step, bool scientific) {
  if (v == 0) return "0";
  char buf[64];
  const int stepExp = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  if (!scientific) {
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, std::max(0, -stepExp));
    return std::string(buf, r.ptr);
  }
  const int p = std::clamp(static_cast<int>(std::floor(std::log10(std::abs(v)))) - stepExp, 0, 16);
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific, p);
  return tidyScientific(std::string(buf, r.ptr));
}

double textWidth(std::string_view s) {  // UTF-8 code points times an average glyph width
  double n = 0;
  for (char c : s) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n * kCharWidth;
}

struct Tick {
  double value;
  std::string svg;  // text content (may hold a superscript <tspan>)
  double width;
};

struct AxisMap {
  bool log = false;
  double lo = 0, hi = 1;  // data-space bounds
  double p0 = 0, p1 = 1;  // pixel positions of lo and hi
  bool valid(double v) const { return std::isfinite(v) && (!log || v > 0); }
  // Pixel coordinate, or NaN when invalid or absurdly far away.
  double px(double v) const {
    if (!valid(v)) return std::numeric_limits<double>::quiet_NaN();
    const double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                         : (v / 2 - lo / 2) / (hi / 2 - lo / 2);
    const double p = p0 + t * (p1 - p0);
    return std::abs(p) < 1e300 ? p : std::numeric_limits<double>::quiet_NaN();
  }
};

// Resolve the axis range from the valid data values (and given bounds).
std::pair<double, double> resolveRange(const Axis& ax, const std::vector<double>& data, bool any) {
  const auto ok = [&](const std::optional<double>& b) { return b && std::isfinite(*b) && (!ax.log || *b > 0); };
  double lo = ax.log ? 1 : 0, hi = ax.log ? 10 : 1;
  if (any) {
    lo = *std::min_element(data.begin(), data.end());
    hi = *std::max_element(data.begin(), data.end());
    if (ax.log) {
      int a = static_cast<int>(std::floor(std::log10(lo) + 1e-12));
      int b = static_cast<int>(std::ceil(std::log10(hi) - 1e-12));
      if (a >= b) --a, ++b;
      a = std::max(a, -307), b = std::min(b, 308);
      lo = pow10(a), hi = pow10(b);
    } else {
      if (lo == hi) {
        const double d = lo == 0 ? 1 : std::abs(lo) * 0.1;
        lo -= d, hi += d;
      }
      for (int iter = 0; iter < 3; ++iter) {  // widen to the outer ticks until the grid is stable
        const Grid g = niceGrid(lo, hi, 8);
        const double step = g.step();
        const double nlo = gridValue(static_cast<long long>(std::floor(lo / step + 1e-9)), g.m, g.e);
        const double nhi = gridValue(static_cast<long long>(std::ceil(hi / step - 1e-9)), g.m, g.e);
        if (!std::isfinite(nlo) || !std::isfinite(nhi) || (nlo == lo && nhi == hi)) break;
        lo = nlo, hi = nhi;
      }
    }
  }
  const double glo = ok(ax.min) ? *ax.min : lo, ghi = ok(ax.max) ? *ax.max : hi;
  if (glo < ghi) return {glo, ghi};
  return {lo, hi};
}

std::vector<Tick> makeTicks(const AxisMap& m) {
  std::vector<Tick> out;
  const std::vector<double> values = m.log ? logTicks(m.lo, m.hi) : linearTicks(m.lo, m.hi);
  const double maxAbs = std::max(std::abs(m.lo), std::abs(m.hi));
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    const int k = static_cast<int>(std::lround(std::log10(std::abs(v) > 0 ? std::abs(v) : 1)));
    if (m.log && v == pow10(k)) {
      const std::string ex = std::to_string(k);
      out.push_back(
          {v, "10<tspan dy=\"-5\" font-size=\"8\">" + ex + "</tspan>", 2 * kCharWidth + 0.75 * textWidth(ex)});
      continue;
    }
    double step;
    if (m.log)
      step = pow10(static_cast<int>(std::floor(std::log10(v) + 1e-9)));
    else
      step = values.size() >= 2 ? values[1] - values[0] : (maxAbs > 0 ? maxAbs : 1);
    const double mag = m.log ? v : maxAbs;
    const bool sci = mag >= 1e5 || mag < 1e-3;
    const std::string s = numberLabel(v, step, sci);
    out.push_back({v, s, textWidth(s)});
  }
  return out;
}

std::vector<double> minorLogTicks(const AxisMap& m) {
  std::vector<double> out;
  const int a = static_cast<int>(std::floor(std::log10(m.lo))), b = static_cast<int>(std::ceil(std::log10(m.hi)));
  if (b - a > 10) return out;
  for (int k = a; k <= b; ++k)
    for (int d = 2; d <= 9; ++d) {
      const double v = gridValue(d, 1, k);
      if (v > m.lo && v < m.hi) out.push_back(v);
    }
  return out;
}

struct Pt {
  double x, y;
};
struct Rect {
  double x0, y0, x1, y1;
  bool inside(Pt p, double pad = 0) const {
    return p.x >= x0 - pad && p.x <= x1 + pad && p.y >= y0 - pad && p.y <= y1 + pad;
  }
};

// Liang-Barsky: the part [t0, t1] of a->b inside r; false when none.
bool clipSegment(Pt a, Pt b, const Rect& r, double& t0, double& t1) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - r.x0, r.x1 - a.x, a.y - r.y0, r.y1 - a.y};
  t0 = 0, t1 = 1;
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

// Visible runs of one unbroken run of points.
void clipRun(const std::vector<Pt>& run, const Rect& r, std::vector<std::vector<Pt>>& out) {
  if (run.size() == 1) {
    if (r.inside(run[0])) out.push_back({run[0], run[0]});
    return;
  }
  std::vector<Pt> cur;
  const auto flush = [&] {
    if (!cur.empty()) out.push_back(std::move(cur));
    cur.clear();
  };
  for (std::size_t i = 0; i + 1 < run.size(); ++i) {
    const Pt a = run[i], b = run[i + 1];
    double t0, t1;
    if (!clipSegment(a, b, r, t0, t1)) {
      flush();
      continue;
    }
    const Pt ca{a.x + t0 * (b.x - a.x), a.y + t0 * (b.y - a.y)};
    const Pt cb{a.x + t1 * (b.x - a.x), a.y + t1 * (b.y - a.y)};
    if (cur.empty() || t0 > 0) {
      flush();
      cur.push_back(ca);
    }
    cur.push_back(cb);
    if (t1 < 1) flush();
  }
  flush();
}

std::string marker(int shape, Pt p) {
  const std::string x = fixed2(p.x), y = fixed2(p.y);
  const auto pt = [](double a, double b) { return fixed2(a) + "," + fixed2(b); };
  switch (shape % 4) {
    case 0:
      return "<circle cx=\"" + x + "\" cy=\"" + y + "\" r=\"3.2\"/>";
    case 1:
      return "<rect x=\"" + fixed2(p.x - 3) + "\" y=\"" + fixed2(p.y - 3) + "\" width=\"6\" height=\"6\"/>";
    case 2:
      return "<polygon points=\"" + pt(p.x, p.y - 3.8) + " " + pt(p.x + 3.5, p.y + 2.6) + " " +
             pt(p.x - 3.5, p.y + 2.6) + "\"/>";
    default:
      return "<polygon points=\"" + pt(p.x, p.y - 4) + " " + pt(p.x + 4, p.y) + " " + pt(p.x, p.y + 4) + " " +
             pt(p.x - 4, p.y) + "\"/>";
  }
}

std::string seriesColor(const Series& s, std::size_t index) {
  return s.color.empty() ? kPalette[index % kPalette.size()] : xmlEscape(s.color);
}

std::string strokeStyle(const std::string& color, bool dashed) {
  return "fill=\"none\" stroke=\"" + color + "\" stroke-width=\"1.5\" stroke-linejoin=\"round\"" +
         " stroke-linecap=\"round\"" + (dashed ? " stroke-dasharray=\"6 4\"" : "");
}

}  // namespace

std::vector<double> linearTicks(double lo, double hi, int maxTicks) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (lo > hi) std::swap(lo, hi);
  if (lo == hi) return {lo};
  const Grid g = niceGrid(lo, hi, maxTicks);
  const double tol = 1e-9 * g.step();
  std::vector<double> out;
  for (long long k = g.k0; k <= g.k1; ++k) {
    const double v = gridValue(k, g.m, g.e);
    if (v >= lo - tol && v <= hi + tol) out.push_back(v == 0 ? 0.0 : v);
  }
  return out;
}

std::vector<double> logTicks(double lo, double hi, int maxTicks) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (lo > hi) std::swap(lo, hi);
  if (!(lo > 0)) return {};
  maxTicks = std::max(maxTicks, 2);
  const long long a = static_cast<long long>(std::ceil(std::log10(lo) - 1e-12));
  const long long b = static_cast<long long>(std::floor(std::log10(hi) + 1e-12));
  std::vector<double> out;
  if (b - a + 1 >= 2) {
    for (long long s = 1;; ++s) {
      const long long j0 = ceilDiv(a, s), j1 = floorDiv(b, s);
      if (j1 - j0 + 1 > maxTicks) continue;
      for (long long j = j0; j <= j1; ++j) out.push_back(pow10(static_cast<int>(j * s)));
      return out;
    }
  }
  for (long long k = a - 1; k <= b; ++k)
    for (int m : {1, 2, 5}) {
      const double v = gridValue(m, 1, static_cast<int>(k));
      if (v >= lo * (1 - 1e-12) && v <= hi * (1 + 1e-12)) out.push_back(v);
    }
  if (out.size() >= 2) return out;
  return linearTicks(lo, hi, maxTicks);
}

namespace {

// One series' lines (cut where a point is not finite, clipped to the area) and markers.
void appendSeries(std::string& o, const Series& s, std::size_t si, const AxisMap& xm, const AxisMap& ym,
                  const Rect& clip) {
  const std::string color = seriesColor(s, si);
  std::vector<std::vector<Pt>> runs(1);
  std::vector<Pt> points;
  for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
    const Pt p{xm.px(s.x[i]), ym.px(s.y[i])};
    if (std::isfinite(p.x) && std::isfinite(p.y)) {
      runs.back().push_back(p);
      points.push_back(p);
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  o += "<g class=\"series\" clip-path=\"url(#flexmb-plot-area)\">\n";
  if (s.line) {
    std::vector<std::vector<Pt>> visible;
    for (const auto& run : runs)
      if (!run.empty()) clipRun(run, clip, visible);
    for (const auto& run : visible) {
      o += "<polyline " + strokeStyle(color, s.dashed) + " points=\"";
      for (std::size_t i = 0; i < run.size(); ++i) {
        if (i > 0) o += ' ';
        o += fixed2(run[i].x) + "," + fixed2(run[i].y);
      }
      o += "\"/>\n";
    }
  }
  if (s.markers) {
    o += "<g class=\"markers\" fill=\"" + color + "\" stroke=\"none\">\n";
    for (const Pt& p : points)
      if (clip.inside(p, 5)) o += marker(static_cast<int>(si), p) + "\n";
    o += "</g>\n";
  }
  o += "</g>\n";
}

// The legend right of the plot area: one row per labelled series.
void appendLegend(std::string& o, const Plot& plot, const std::vector<std::size_t>& legendItems, double legendW,
                  const Rect& area) {
  const double x0 = area.x1 + 12, y0 = area.y0;
  o += "<g class=\"legend\">\n<rect x=\"" + fixed2(x0) + "\" y=\"" + fixed2(y0) + "\" width=\"" + fixed2(legendW) +
       "\" height=\"" + fixed2(10 + 16.0 * static_cast<double>(legendItems.size())) +
       "\" fill=\"white\" stroke=\"#bbbbbb\" stroke-width=\"1\"/>\n";
  for (std::size_t r = 0; r < legendItems.size(); ++r) {
    const std::size_t si = legendItems[r];
    const Series& s = plot.series[si];
    const std::string color = seriesColor(s, si);
    const double y = y0 + 13 + 16.0 * static_cast<double>(r);
    if (s.line)
      o += "<line x1=\"" + fixed2(x0 + 8) + "\" y1=\"" + fixed2(y) + "\" x2=\"" + fixed2(x0 + 34) + "\" y2=\"" +
           fixed2(y) + "\" " + strokeStyle(color, s.dashed) + "/>\n";
    if (s.markers) o += "<g fill=\"" + color + "\">" + marker(static_cast<int>(si), {x0 + 21, y}) + "</g>\n";
    o += "<text x=\"" + fixed2(x0 + 40) + "\" y=\"" + fixed2(y + 4) + "\">" + xmlEscape(s.label) + "</text>\n";
  }
  o += "</g>\n";
}

}  // namespace

namespace {

// One plot; its plot area's left and right margins at least minLeft and minRight (stacked panels
// share their plot area's edges), the margins used in *used.
std::string renderPanel(const Plot& plot, double minLeft, double minRight, std::pair<double, double>* used) {
  const double W = std::max(plot.width, 240), H = std::max(plot.height, 180);

  // Data ranges from the valid points.
  AxisMap xm, ym;
  xm.log = plot.x.log, ym.log = plot.y.log;
  std::vector<double> xs, ys;
  for (const Series& s : plot.series)
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (xm.valid(s.x[i]) && ym.valid(s.y[i])) xs.push_back(s.x[i]), ys.push_back(s.y[i]);
  const bool noData = xs.empty();
  std::vector<double> xr = xs;
  for (double v : plot.verticalLines)
    if (xm.valid(v) && !noData) xr.push_back(v);
  std::tie(xm.lo, xm.hi) = resolveRange(plot.x, xr, !xr.empty());
  std::tie(ym.lo, ym.hi) = resolveRange(plot.y, ys, !ys.empty());
  const std::vector<Tick> xt = makeTicks(xm), yt = makeTicks(ym);

  // Layout.
  std::string head;
  double cursor = 8;
  if (!plot.title.empty()) {
    // A title wider than the page (a long model path) continues on further lines, broken after a
    // space or a slash.
    const double titleScale = 15.0 * 1.1 / 11.0;  // bold 15 px against textWidth's 11 px glyphs
    std::vector<std::string> lines{""};
    std::string_view rest = plot.title;
    while (!rest.empty()) {
      const std::size_t space = rest.find_first_of(" /");
      const std::string_view word = rest.substr(0, space == std::string_view::npos ? rest.size() : space + 1);
      rest.remove_prefix(word.size());
      if (!lines.back().empty() && textWidth(lines.back() + std::string(word)) * titleScale > W - 20)
        lines.emplace_back();
      lines.back() += word;
    }
    for (std::string& line : lines) {
      while (!line.empty() && line.back() == ' ') line.pop_back();
      cursor += 16;
      head += "<text class=\"title\" x=\"" + fixed2(W / 2) + "\" y=\"" + fixed2(cursor) +
              "\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" + xmlEscape(line) + "</text>\n";
    }
    cursor += 4;
  }
  for (const std::string& note : plot.notes) {
    cursor += 13;
    head += "<text class=\"note\" x=\"" + fixed2(W / 2) + "\" y=\"" + fixed2(cursor) +
            "\" text-anchor=\"middle\" font-size=\"10\" fill=\"#555555\">" + xmlEscape(note) + "</text>\n";
  }
  std::vector<std::size_t> legendItems;
  double legendW = 0;
  for (std::size_t i = 0; i < plot.series.size(); ++i)
    if (!plot.series[i].label.empty()) {
      legendItems.push_back(i);
      legendW = std::max(legendW, textWidth(plot.series[i].label));
    }
  legendW = legendItems.empty() ? 0 : std::min(legendW + 48, W * 0.4);
  double yLabelW = 0;
  for (const Tick& t : yt) yLabelW = std::max(yLabelW, t.width);
  const double left = std::max(minLeft, 10 + (plot.y.label.empty() ? 0 : 18) + yLabelW + 9);
  double right = legendItems.empty() ? 16 : legendW + 24;
  if (!xt.empty()) right = std::max(right, xt.back().width / 2 + 4);
  right = std::max(right, minRight);
  if (used) *used = {left, right};
  const double top = cursor + 12;
  const double bottom = 8 + 5 + 14 + (plot.x.label.empty() ? 0 : 18) + 4;
  const Rect area{left, top, std::max(left + 40, W - right), std::max(top + 20, H - bottom)};
  const Rect clip{area.x0 - kClipPad, area.y0 - kClipPad, area.x1 + kClipPad, area.y1 + kClipPad};
  xm.p0 = area.x0, xm.p1 = area.x1, ym.p0 = area.y1, ym.p1 = area.y0;

  std::string o;
  o += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fixed2(W) + "\" height=\"" + fixed2(H) +
       "\" viewBox=\"0 0 " + fixed2(W) + " " + fixed2(H) + "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o += "<defs><clipPath id=\"flexmb-plot-area\"><rect x=\"" + fixed2(clip.x0) + "\" y=\"" + fixed2(clip.y0) +
       "\" width=\"" + fixed2(clip.x1 - clip.x0) + "\" height=\"" + fixed2(clip.y1 - clip.y0) +
       "\"/></clipPath></defs>\n";
  o += head;

  // Grid, ticks and tick labels.
  const auto vline = [&](double x, const char* attrs) {
    return "<line x1=\"" + fixed2(x) + "\" y1=\"" + fixed2(area.y0) + "\" x2=\"" + fixed2(x) + "\" y2=\"" +
           fixed2(area.y1) + "\"" + attrs + "/>\n";
  };
  const auto hline = [&](double y, const char* attrs) {
    return "<line x1=\"" + fixed2(area.x0) + "\" y1=\"" + fixed2(y) + "\" x2=\"" + fixed2(area.x1) + "\" y2=\"" +
           fixed2(y) + "\"" + attrs + "/>\n";
  };
  o += "<g class=\"grid\" stroke-width=\"1\">\n";
  if (xm.log)
    for (double v : minorLogTicks(xm)) o += vline(xm.px(v), " stroke=\"#f2f2f2\"");
  if (ym.log)
    for (double v : minorLogTicks(ym)) o += hline(ym.px(v), " stroke=\"#f2f2f2\"");
  for (const Tick& t : xt) o += vline(xm.px(t.value), " stroke=\"#dddddd\"");
  for (const Tick& t : yt) o += hline(ym.px(t.value), " stroke=\"#dddddd\"");
  o += "</g>\n<g class=\"ticks\" stroke=\"#333333\" stroke-width=\"1\">\n";
  for (const Tick& t : xt) {
    const std::string x = fixed2(xm.px(t.value));
    o +=
        "<line x1=\"" + x + "\" y1=\"" + fixed2(area.y1) + "\" x2=\"" + x + "\" y2=\"" + fixed2(area.y1 + 5) + "\"/>\n";
  }
  for (const Tick& t : yt) {
    const std::string y = fixed2(ym.px(t.value));
    o +=
        "<line x1=\"" + fixed2(area.x0 - 5) + "\" y1=\"" + y + "\" x2=\"" + fixed2(area.x0) + "\" y2=\"" + y + "\"/>\n";
  }
  o += "</g>\n<g class=\"tick-labels\" fill=\"#333333\">\n";
  for (const Tick& t : xt)
    o += "<text x=\"" + fixed2(xm.px(t.value)) + "\" y=\"" + fixed2(area.y1 + 18) + "\" text-anchor=\"middle\">" +
         t.svg + "</text>\n";
  for (const Tick& t : yt)
    o += "<text x=\"" + fixed2(area.x0 - 8) + "\" y=\"" + fixed2(ym.px(t.value) + 4) + "\" text-anchor=\"end\">" +
         t.svg + "</text>\n";
  o += "</g>\n";
  if (!plot.x.label.empty())
    o += "<text class=\"axis-label\" x=\"" + fixed2((area.x0 + area.x1) / 2) + "\" y=\"" + fixed2(area.y1 + 36) +
         "\" text-anchor=\"middle\" font-size=\"12\">" + xmlEscape(plot.x.label) + "</text>\n";
  if (!plot.y.label.empty())
    o += "<text class=\"axis-label\" transform=\"translate(" + fixed2(14) + "," + fixed2((area.y0 + area.y1) / 2) +
         ") rotate(-90)\" text-anchor=\"middle\" dy=\"0.35em\" font-size=\"12\">" + xmlEscape(plot.y.label) +
         "</text>\n";

  // Reference lines and data, clipped to the plot area.
  o += "<g class=\"vertical-lines\" clip-path=\"url(#flexmb-plot-area)\">\n";
  for (double v : plot.verticalLines) {
    const double x = xm.px(v);
    if (std::isfinite(x) && x >= area.x0 - kClipPad && x <= area.x1 + kClipPad)
      o += vline(x, " stroke=\"#808080\" stroke-width=\"1\" stroke-dasharray=\"5 4\"");
  }
  o += "</g>\n";
  for (std::size_t si = 0; si < plot.series.size(); ++si) appendSeries(o, plot.series[si], si, xm, ym, clip);
  if (noData)
    o += "<text class=\"no-data\" x=\"" + fixed2((area.x0 + area.x1) / 2) + "\" y=\"" +
         fixed2((area.y0 + area.y1) / 2) +
         "\" text-anchor=\"middle\" font-size=\"14\" fill=\"#888888\">no data</text>\n";
  o += "<rect class=\"frame\" x=\"" + fixed2(area.x0) + "\" y=\"" + fixed2(area.y0) + "\" width=\"" +
       fixed2(area.x1 - area.x0) + "\" height=\"" + fixed2(area.y1 - area.y0) +
       "\" fill=\"none\" stroke=\"#333333\" stroke-width=\"1\"/>\n";

  if (!legendItems.empty()) appendLegend(o, plot, legendItems, legendW, area);  // right of the plot area
  o += "</svg>\n";
  return o;
}

}  // namespace

std::string renderSvg(const Plot& plot) { return renderPanel(plot, 0, 0, nullptr); }

std::string renderSvgStack(const std::vector<Plot>& plots) {
  double W = 240, H = 0;
  std::string body;
  // The widest margins of all panels for each, so that their plot areas line up.
  double minLeft = 0, minRight = 0;
  for (const Plot& p : plots) {
    std::pair<double, double> used;
    renderPanel(p, 0, 0, &used);
    minLeft = std::max(minLeft, used.first), minRight = std::max(minRight, used.second);
  }
  for (std::size_t k = 0; k < plots.size(); ++k) {
    std::string one = renderPanel(plots[k], minLeft, minRight, nullptr);
    one.erase(0, one.find("<svg"));  // no XML declaration inside
    // Each plot's clip path gets its own id.
    const std::string id = "flexmb-plot-area", own = id + "-" + std::to_string(k + 1);
    for (std::size_t at = one.find(id); at != std::string::npos; at = one.find(id, at + own.size()))
      one.replace(at, id.size(), own);
    one.insert(4, " y=\"" + fixed2(H) + "\"");
    body += one;
    W = std::max(W, static_cast<double>(std::max(plots[k].width, 240)));
    H += std::max(plots[k].height, 180);
  }
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fixed2(W) +
         "\" height=\"" + fixed2(std::max(H, 180.0)) + "\" font-family=\"sans-serif\">\n" + body + "</svg>\n";
}

namespace {
// The whole text in one checked write (the open's and the write's failures named).
void writeWhole(const std::string& path, const std::string& text) {
  errno = 0;
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) {
    const std::string why = errno ? std::generic_category().message(errno) : "open failed";
    throw std::runtime_error("cannot open '" + path + "' for writing: " + why);
  }
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  f.close();
  if (!f) throw std::runtime_error("error writing '" + path + "'");
}
}  // namespace

void writeSvgStack(const std::string& path, const std::vector<Plot>& plots) { writeWhole(path, renderSvgStack(plots)); }

void writeSvg(const std::string& path, const Plot& plot) { writeWhole(path, renderSvg(plot)); }

}  // namespace flexmb::io
