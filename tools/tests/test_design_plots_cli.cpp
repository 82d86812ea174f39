// The designer's plots through the command line (issue 53 item 2): static --plot, sweep's frequency
// panels and --plot, simulate --plot. Each plotted point is mapped back from the SVG's pixels through
// the axis ticks and compared with the CSV's cell it should be; unknown names are usage errors that
// list the names there are.
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "tools/tests/CliFixture.hpp"

using namespace flexmb::cli_test;

namespace {

class DesignPlotsCli : public CliTest {};

std::vector<std::string> split(const std::string& s, char by) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string c; std::getline(ss, c, by);) v.push_back(c);
  return v;
}

// A CSV column's values.
std::vector<double> csvColumn(const std::string& csv, const std::string& column) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  const auto names = split(line, ',');
  const auto at = static_cast<size_t>(std::find(names.begin(), names.end(), column) - names.begin());
  std::vector<double> v;
  while (std::getline(in, line)) {
    const auto cells = split(line, ',');
    v.push_back(at < cells.size() && !cells[at].empty() ? std::stod(cells[at]) : NAN);
  }
  EXPECT_LT(at, names.size()) << "no column " << column;
  return v;
}

// One panel of a stacked SVG, its series' points back in data values through its tick labels.
struct Panel {
  std::vector<std::vector<std::pair<double, double>>> series;  // each series' first polyline
  std::string text;
  double dx = 0, dy = 0;  // data per pixel along x and y
};

// An affine map from two (pixel, value) ticks.
struct Axis {
  double p0 = 0, v0 = 0, p1 = 1, v1 = 1;
  double value(double p) const { return v0 + (p - p0) * (v1 - v0) / (p1 - p0); }
  double perPixel() const { return std::abs((v1 - v0) / (p1 - p0)); }
};

std::vector<Panel> panels(const std::string& svg) {
  std::vector<Panel> out;
  const std::regex tick(R"re(<text x="([-0-9.]+)" y="([-0-9.]+)" text-anchor="(middle|end)">([-0-9.e]+)</text>)re");
  for (size_t at = svg.find("<svg", svg.find("<svg") + 1); at != std::string::npos; at = svg.find("<svg", at + 1)) {
    Panel p;
    p.text = svg.substr(at, svg.find("</svg>", at) - at);
    const std::string labels =
        p.text.substr(p.text.find("class=\"tick-labels\""),
                      p.text.find("</g>", p.text.find("class=\"tick-labels\"")) - p.text.find("class=\"tick-labels\""));
    std::vector<std::pair<double, double>> xt, yt;  // (pixel, value)
    for (std::sregex_iterator m(labels.begin(), labels.end(), tick), end; m != end; ++m) {
      if ((*m)[3] == "middle")
        xt.emplace_back(std::stod((*m)[1]), std::stod((*m)[4]));
      else
        yt.emplace_back(std::stod((*m)[2]) - 4, std::stod((*m)[4]));  // the label sits 4 px below its tick
    }
    if (xt.size() < 2 || yt.size() < 2) {
      ADD_FAILURE() << "too few ticks in a panel";
      return out;
    }
    const Axis ax{xt.front().first, xt.front().second, xt.back().first, xt.back().second};
    const Axis ay{yt.front().first, yt.front().second, yt.back().first, yt.back().second};
    for (size_t s = p.text.find("<g class=\"series\""); s != std::string::npos;
         s = p.text.find("<g class=\"series\"", s + 1)) {
      const size_t q = p.text.find("points=\"", s) + 8;
      std::vector<std::pair<double, double>> pts;
      for (const auto& pair : split(p.text.substr(q, p.text.find('"', q) - q), ' ')) {
        const auto xy = split(pair, ',');
        pts.emplace_back(ax.value(std::stod(xy[0])), ay.value(std::stod(xy[1])));
      }
      p.series.push_back(pts);
    }
    p.dx = ax.perPixel(), p.dy = ay.perPixel();
    out.push_back(p);
  }
  return out;
}

// The panel's series s against the expected values, to 0.02 px.
void expectPoints(const Panel& p, size_t s, const std::vector<double>& x, const std::vector<double>& y) {
  ASSERT_LT(s, p.series.size());
  const auto& pts = p.series[s];
  ASSERT_EQ(pts.size(), x.size());
  const double tx = 0.02 * p.dx, ty = 0.02 * p.dy;  // the SVG's coordinates are rounded to 0.005 px
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(pts[i].first, x[i], tx) << "point " << i;
    EXPECT_NEAR(pts[i].second, y[i], ty) << "point " << i;
  }
}

}  // namespace

TEST_F(DesignPlotsCli, StaticForceDeflectionIsTheCsvsLoadAgainstDeflection) {
  const Result r = flexmb("static " + kData + "cantilever.dat --steps 4 --plot node5.y,node105.angle --out s.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "wrote s_force_deflection.svg")) << r.out;
  const std::string csv = slurp(dir_ / "s.csv");
  const auto ps = panels(slurp(dir_ / "s_force_deflection.svg"));
  ASSERT_EQ(ps.size(), 2u);
  // node 5 starts at y = 0: its deflection is its y; the load on it is F.node5.y (-0.1 N at step 4).
  const auto y = csvColumn(csv, "node5.y"), f = csvColumn(csv, "F.node5.y");
  ASSERT_EQ(y.size(), 5u);
  EXPECT_NEAR(f.back(), -0.1, 1e-15);
  expectPoints(ps[0], 0, y, f);
  EXPECT_TRUE(has(ps[0].text, ">applied force F.node5.y [N]<"));
  // No load along the tip's angle: the load factor.
  expectPoints(ps[1], 0, csvColumn(csv, "node105.angle"), csvColumn(csv, "load_factor"));
  EXPECT_TRUE(has(ps[1].text, ">deflection node105.angle - node105.angle(initial) [rad]<"));
}

TEST_F(DesignPlotsCli, AnUnknownCoordinateIsAUsageErrorListingTheCoordinates) {
  Result r = flexmb("static " + kData + "cantilever.dat --plot node5.q");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "'node5.q' is not a coordinate")) << r.err;
  EXPECT_TRUE(has(r.err, "node5.x, node5.y, node105.angle")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "cantilever_static.csv"));  // refused before the run
  r = flexmb("simulate " + kData + "straight_guidance.dat --plot PLBEAM3.e2_bending_p");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "write e:PLBEAM3.e2_bending_p (the deformation) or sig:PLBEAM3.e2_bending_p")) << r.err;
  r = flexmb("simulate " + kData + "straight_guidance.dat --plot max_stress");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "no von Mises stress (no element has a VISUALIZATION section)")) << r.err;
  EXPECT_TRUE(has(r.err, "node6.x")) << r.err;
}

TEST_F(DesignPlotsCli, SweepPanelsPerModeGroupAndTheHoldingLoad) {
  const Result r = flexmb("sweep " + kData +
                          "straight_guidance.dat --node 6 --comp 1 --from -0.05 --to 0.05 --steps 4 --nev 6 --plot "
                          "--out sw -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "wrote sw_force_deflection.svg")) << r.out;
  const std::string csv = slurp(dir_ / "sw.csv");
  const auto value = csvColumn(csv, "value");
  ASSERT_EQ(value.size(), 4u);
  // 5 Hz alone, 130 .. 740 Hz together.
  const auto ps = panels(slurp(dir_ / "sw.svg"));
  ASSERT_EQ(ps.size(), 2u);
  ASSERT_EQ(ps[0].series.size(), 1u);
  ASSERT_EQ(ps[1].series.size(), 5u);
  expectPoints(ps[0], 0, value, csvColumn(csv, "f1_Hz"));
  expectPoints(ps[1], 4, value, csvColumn(csv, "f6_Hz"));
  // The load that holds node 6 against its x (it starts at 0).
  const auto fd = panels(slurp(dir_ / "sw_force_deflection.svg"));
  ASSERT_EQ(fd.size(), 1u);
  expectPoints(fd[0], 0, csvColumn(csv, "node6.x"), csvColumn(csv, "load"));
}

TEST_F(DesignPlotsCli, SimulateTimeHistoryOfACoordinateAndAStress) {
  const Result r = flexmb("simulate " + kData +
                          "straight_guidance.dat --t-end 0.05 --plot node6.x,sig:PLBEAM3.e2_bending_p --out h -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "wrote h_history.svg")) << r.out;
  const auto ps = panels(slurp(dir_ / "h_history.svg"));
  ASSERT_EQ(ps.size(), 2u);
  const std::string x = slurp(dir_ / "h_x.csv"), sig = slurp(dir_ / "h_sig.csv");
  // node 6 starts at x = 0: its displacement is its x.
  expectPoints(ps[0], 0, csvColumn(x, "time"), csvColumn(x, "node6.x"));
  expectPoints(ps[1], 0, csvColumn(sig, "time"), csvColumn(sig, "PLBEAM3.e2_bending_p"));
  EXPECT_TRUE(has(ps[1].text, ">sig of e2_bending_p [N m]<"));
}

TEST_F(DesignPlotsCli, SimulateVonMisesStressesTheLargestIsTheLargestElements) {
  // The cantilever with a 20 x 2 mm section, swinging under its tip load.
  std::ofstream(dir_ / "c.dat") << std::regex_replace(slurp(kData + "cantilever.dat"), std::regex("\nITERSTEP"),
                                                      "\nXF 5 0.0 -0.1\nITERSTEP")
                                << "VISUALIZATION\nBEAMPROPS 1 2 3 4\nCROSSTYPE RECT\nCROSSDIM 0.02 0.002\n";
  const Result r = flexmb(
      "simulate c.dat --t-end 0.2 --plot max_stress,stress_PLBEAM1,stress_PLBEAM2,stress_PLBEAM3,stress_PLBEAM4 "
      "--out v -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto ps = panels(slurp(dir_ / "v_history.svg"));
  ASSERT_EQ(ps.size(), 1u);  // one quantity: von Mises stress [MPa]
  EXPECT_TRUE(has(ps[0].text, ">von Mises stress [MPa]<"));
  ASSERT_EQ(ps[0].series.size(), 5u);
  const auto& top = ps[0].series[0];
  double peak = 0.0;
  for (size_t i = 0; i < top.size(); ++i) {
    double largest = 0.0;
    for (size_t s = 1; s < 5; ++s) largest = std::max(largest, ps[0].series[s][i].second);
    EXPECT_NEAR(top[i].second, largest, 0.02 * ps[0].dy) << "at t = " << top[i].first;
    peak = std::max(peak, top[i].second);
  }
  // The clamp's static stress P L (t/2) / I = 0.1 * 1 * 0.001 / 1.3333e-11 = 7.5 MPa; a load applied at
  // once overshoots it, up to twice.
  EXPECT_GT(peak, 7.5);
  EXPECT_LT(peak, 15.1);
}

// Issue 53 item 1: the sweep says its largest stress and reactions on screen, as its CSV has them.
TEST_F(DesignPlotsCli, SweepSaysItsLargestStressAndReactions) {
  const Result r = flexmb("sweep " + kData +
                          "spatial/cross_spring_pivot.dat --node 4 --comp 3 --from -0.1 --to 0.1 --steps 5 --out pv");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir_ / "pv.csv");
  double top = 0.0;
  for (double s : csvColumn(csv, "max_stress")) top = std::max(top, std::abs(s));
  const std::string said = "largest von Mises stress over the sweep: ";
  const auto at = r.out.find(said);
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NEAR(std::stod(r.out.substr(at + said.size())), top, 1e-5 * top) << r.out;
  double reaction = 0.0;
  for (double v : csvColumn(csv, "R.F.node1.z")) reaction = std::abs(v) > std::abs(reaction) ? v : reaction;
  const std::string line = "  R.F.node1.z = ";
  const auto ra = r.out.find(line);
  ASSERT_NE(ra, std::string::npos) << r.out;
  EXPECT_NEAR(std::stod(r.out.substr(ra + line.size())), reaction, 1e-5 * std::abs(reaction)) << r.out;
}
