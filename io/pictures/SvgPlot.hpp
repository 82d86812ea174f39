#pragma once
// SvgPlot: a small, dependency-free SVG line-plot writer for engineering reports (eigenfrequency
// against deflection, time responses, relative errors on a log axis, singular values as markers,
// work-precision diagrams on log-log axes).
//
// Rendering rules:
//   * Axes: linear axes get "nice" ticks on a 1-2-5 grid (linearTicks); log axes get decade ticks
//     labelled 10^k (the exponent as a superscript <tspan>), with a stride of several decades when
//     there are many (logTicks). Without Axis::min/max a linear axis is widened to the outer nice
//     ticks and a log axis to whole decades; given bounds are used as they are (a non-positive
//     bound on a log axis, a non-finite bound or min >= max falls back to the automatic one).
//   * Data: a point whose x or y is NaN/inf, or not positive on a log axis, is dropped and breaks
//     the line. Lines are clipped to the plot area in the writer (so far-away points never make
//     huge coordinates) and also through an SVG clipPath. Every visible run of a series is one
//     <polyline> (a run of one point is a zero-length polyline drawn as a dot by its round caps);
//     markers are one element each (circle, square, triangle, diamond by series index) in the
//     series' <g class="markers">. Each series is one <g class="series"> in input order.
//   * Colours: Series::color, or the Okabe-Ito colour-blind-safe palette by series index.
//   * Vertical lines: dashed grey, over the full plot height; they count for the automatic x range.
//   * Text: title, notes (one <text class="note"> each, under the title), axis labels and a legend
//     (right of the plot area, only for series with a non-empty label). Every text is XML-escaped
//     (& < > " '); line breaks and tabs become blanks, other control characters (forbidden in
//     XML 1.0) '?'. Texts are not wrapped; widths are estimated from the character count.
//   * No drawable point at all (no series, empty or all-NaN series): a valid document with the
//     axes of the default range and a "no data" text in the plot area.
//   * Output is deterministic (numbers through std::to_chars, no locale, no time stamps).
#include <optional>
#include <string>
#include <vector>

namespace flexmb::io {

struct Series {
  std::string label;
  std::vector<double> x, y;  // pairs (x[i], y[i]); extra entries of the longer one are ignored
  std::string color;         // empty: automatic from a fixed colour-blind-safe palette
  bool dashed = false;
  bool markers = false;  // draw a marker at each point
  bool line = true;      // false: markers only
};

struct Axis {
  std::string label;
  bool log = false;
  std::optional<double> min, max;
};

struct Plot {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  std::vector<double> verticalLines;  // dashed grey reference lines (e.g. range of motion)
  std::vector<std::string> notes;     // small text lines under the title (modelling assumptions)
  int width = 720, height = 450;      // pixels; at least 240 x 180 is used
};

// The SVG document text.
std::string renderSvg(const Plot& plot);
// Writes renderSvg(plot) to path; throws std::runtime_error naming the path on failure.
void writeSvg(const std::string& path, const Plot& plot);

// Several plots stacked top to bottom in one document (a Bode diagram: magnitude over phase), each
// rendered as renderSvg renders it, with the widest of their left and right margins (tick labels,
// legend), so that their plot areas line up.
std::string renderSvgStack(const std::vector<Plot>& plots);
void writeSvgStack(const std::string& path, const std::vector<Plot>& plots);

// Tick values inside [lo, hi] (bounds swapped if needed) on a 1-2-5 grid: the smallest step
// m * 10^k, m in {1, 2, 5}, that gives at most maxTicks ticks. Values are k * step rounded so that
// decimal ticks are the nearest doubles (0.03, not 0.030000000000000002). lo == hi gives {lo};
// non-finite bounds give {}.
std::vector<double> linearTicks(double lo, double hi, int maxTicks = 8);
// Ticks for a log axis over [lo, hi] (0 < lo): the decades 10^k inside, every s-th decade
// (k a multiple of s, smallest s with at most maxTicks ticks). With fewer than two decades inside,
// {1, 2, 5} * 10^k inside; with fewer than two of those, linearTicks(lo, hi). Invalid bounds: {}.
std::vector<double> logTicks(double lo, double hi, int maxTicks = 8);

}  // namespace flexmb::io
