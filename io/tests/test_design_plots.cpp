// The designer's plots (io/pictures/DesignPlots): the mode groups' rule, the panels' series and their
// points against the tables they come from, the force-deflection load column, the time history's
// panels per quantity, the errors naming the columns there are.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/pictures/DesignPlots.hpp"

using namespace flexmb::io;

namespace {

size_t count(const std::string& hay, const std::string& needle) {
  size_t n = 0;
  for (size_t at = hay.find(needle); at != std::string::npos; at = hay.find(needle, at + needle.size())) ++n;
  return n;
}

// A sweep table: value, load, f1_Hz..f6_Hz as the straight guidance's (5 Hz, 135 .. 740 Hz).
CsvTable sweepLike() {
  CsvTable t;
  t.columns = {"value", "load", "f1_Hz", "f2_Hz", "f3_Hz", "f4_Hz", "f5_Hz", "f6_Hz"};
  t.rows = {{-0.05, -80, 5.5, 130, 141, 151, 214, 714},
            {0.0, 0, 5.3, 135, 136, 374, 375, 740},
            {0.05, 80, 5.5, 131, 141, 151, 214, 714}};
  return t;
}

}  // namespace

TEST(ModeGroups, AGapOf3xOrADecadeFromTheGroupsLowestStartsTheNextGroup) {
  // 5 Hz alone; 130 .. 740 Hz within ten times 130 Hz.
  const auto g = modeGroups({5.3, 130, 136, 151, 214, 714}, {5.5, 135, 141, 374, 375, 740});
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0], std::vector<int>({0}));
  EXPECT_EQ(g[1], std::vector<int>({1, 2, 3, 4, 5}));
  // 1 Hz and 1 kHz; 10 Hz is still within a decade of 1 Hz, 10.5 Hz is not.
  EXPECT_EQ(modeGroups({1, 1000}, {1, 1000}).size(), 2u);
  EXPECT_EQ(modeGroups({1, 2.5}, {1, 10}).size(), 1u);
  EXPECT_EQ(modeGroups({1, 2.5}, {1, 10.5}).size(), 2u);
  // A gap of more than 3x between neighbours splits within a decade (the cross-spring pivot's sweep:
  // 7.3 Hz apart from 53 .. 85 Hz, not 7.3 .. 57 Hz apart from 85 Hz).
  const auto p = modeGroups({7.2, 53, 56.8, 80}, {7.3, 53.3, 57, 84.5});
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1], std::vector<int>({1, 2, 3}));
  EXPECT_EQ(modeGroups({1, 3}, {1, 9}).size(), 1u);
  EXPECT_EQ(modeGroups({1, 3.1}, {1, 9}).size(), 2u);
  // Rigid-body modes (0 Hz) keep to themselves.
  const auto r = modeGroups({0, 0, 5}, {0, 0, 6});
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0], std::vector<int>({0, 1}));
}

TEST(FrequencyPanels, FiveAnd135HzModesInDifferentPanelsWithTheTablesPoints) {
  const CsvTable t = sweepLike();
  const auto panels = frequencyPanels(t, "value", "prescribed x(node 6, x) [m]", "Eigenfrequencies");
  ASSERT_EQ(panels.size(), 2u);
  ASSERT_EQ(panels[0].series.size(), 1u);
  ASSERT_EQ(panels[1].series.size(), 5u);
  EXPECT_EQ(panels[0].title, "Eigenfrequencies");
  EXPECT_EQ(panels[1].series[0].label, "f2");
  for (size_t r = 0; r < t.rows.size(); ++r) {
    EXPECT_EQ(panels[0].series[0].x[r], t.rows[r][0]);
    EXPECT_EQ(panels[0].series[0].y[r], t.rows[r][2]);
    EXPECT_EQ(panels[1].series[4].y[r], t.rows[r][7]);
  }
  // The document: two panels, six series of three points each.
  const std::string svg = renderSvgStack(panels);
  EXPECT_EQ(count(svg, "<svg"), 3u);
  EXPECT_EQ(count(svg, "<g class=\"series\""), 6u);
  EXPECT_EQ(count(svg, "<polyline"), 6u);
  size_t at = 0;
  for (int k = 0; k < 6; ++k) {
    at = svg.find("points=\"", at) + 8;
    const std::string points = svg.substr(at, svg.find('"', at) - at);
    EXPECT_EQ(count(points, ","), 3u) << points;
  }
}

TEST(ForceDeflection, TheLoadAlongTheCoordinateAgainstItsDeflection) {
  CsvTable t;
  t.columns = {"load_step", "initial_factor", "load_factor", "node5.x", "node5.y", "F.node5.y"};
  t.rows = {{0, 1, 0, 1.0, 0.0, 0.0}, {1, 1, 0.5, 0.999, -0.006, -0.05}, {2, 1, 1, 0.996, -0.012, -0.1}};
  EXPECT_EQ(staticLoadColumn(t, "node5.y"), "F.node5.y");
  EXPECT_EQ(staticLoadColumn(t, "node5.x"), "load_factor");  // no load along x
  ForceDeflection fd;
  fd.coordinate = "node5.x";
  fd.reference = 1.0;
  fd.load = staticLoadColumn(t, "node5.x");
  fd.loadLabel = staticLoadLabel(fd.load);
  const Plot p = forceDeflectionPlot(t, fd, "title");
  ASSERT_EQ(p.series.size(), 1u);
  ASSERT_EQ(p.series[0].x.size(), 3u);
  for (size_t r = 0; r < 3; ++r) {
    EXPECT_DOUBLE_EQ(p.series[0].x[r], t.rows[r][3] - 1.0);
    EXPECT_EQ(p.series[0].y[r], t.rows[r][2]);
  }
  EXPECT_EQ(p.x.label, "deflection node5.x - node5.x(initial) [m]");
  EXPECT_EQ(p.y.label, "load factor (DELXF increments applied) [-]");
  EXPECT_EQ(staticLoadLabel("F.node5.y"), "applied force F.node5.y [N]");
  // Markers at every load step.
  EXPECT_EQ(count(renderSvg(p), "<circle"), 3u + 1u);  // three points and the legend's marker
}

TEST(TimeHistory, APanelPerQuantityStressesInMPaDisplacementsFromTheStart) {
  CsvTable t;
  t.columns = {"time", "x:node6.x", "x:node106.angle", "x:node16.x", "sig:PLBEAM3.e2_bending_p", "max_stress"};
  t.rows = {{0, 0.2, 0.1, 0.3, 0, 0}, {0.1, 0.25, 0.15, 0.35, 20, 3e6}, {0.2, 0.2, 0.1, 0.3, -30, 5e6}};
  const auto panels = timeHistoryPlots(t, {0.2, 0.1, NAN, NAN, NAN}, "history");
  ASSERT_EQ(panels.size(), 5u);  // displacement, rotation, position (no initial value), sig, von Mises
  EXPECT_EQ(panels[0].y.label, "displacement from the initial position [m]");
  EXPECT_EQ(panels[1].y.label, "rotation from the initial angle [rad]");
  EXPECT_EQ(panels[2].y.label, "position [m]");
  EXPECT_EQ(panels[3].y.label, "sig of e2_bending_p [N m]");
  EXPECT_EQ(panels[4].y.label, "von Mises stress [MPa]");
  EXPECT_EQ(panels[0].series[0].label, "node6.x");
  EXPECT_DOUBLE_EQ(panels[0].series[0].y[1], 0.05);
  EXPECT_DOUBLE_EQ(panels[2].series[0].y[1], 0.35);
  EXPECT_DOUBLE_EQ(panels[4].series[0].y[2], 5.0);
  EXPECT_EQ(panels[3].series[0].x, std::vector<double>({0, 0.1, 0.2}));
  // Two positions share a panel when both are drawn the same way.
  EXPECT_EQ(timeHistoryPlots(t, {}, "history").size(), 4u);
  EXPECT_EQ(historyQuantity("xd:node6.y"), "velocity [m/s]");
  EXPECT_EQ(historyQuantity("xdd:node106.angle"), "angular acceleration [rad/s^2]");
  EXPECT_EQ(historyQuantity("stress_BEAM3"), "von Mises stress [MPa]");
  EXPECT_EQ(historyQuantity("sig:TRUSS2.e1_elongation"), "sig of e1_elongation [N]");
  EXPECT_EQ(historyQuantity("ed:BEAM2.e2_torsion"), "ed of e2_torsion [rad/s]");
}

TEST(DesignPlotColumns, AnUnknownColumnListsTheTablesColumns) {
  const CsvTable t = sweepLike();
  try {
    tableColumn(t, "f9_Hz", "the sweep table");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "the sweep table has no column 'f9_Hz'; it has: value, load, f1_Hz, f2_Hz, f3_Hz, f4_Hz, f5_Hz, f6_Hz");
  }
  EXPECT_EQ(listNames({"a", "b", "c"}, 2), "a, b, ... and 1 more");
  EXPECT_EQ(commaList(" node6.x, ,node6.y,"), std::vector<std::string>({"node6.x", "node6.y"}));
  EXPECT_EQ(coordinateUnit("node106.angle"), "rad");
  EXPECT_EQ(coordinateUnit("node2.lambda1"), "");
}

TEST(SvgStack, StackedPanelsShareTheirPlotAreasEdges) {
  // Tick labels and legends of different widths: the frames still line up.
  Plot a, b;
  a.series.push_back({"x", {0, 1}, {0, 0.10000000004}, "", false, false, true});
  b.series.push_back({"a much longer legend label", {0, 1}, {-40, 30}, "", false, false, true});
  const std::string svg = renderSvgStack({a, b});
  std::vector<std::string> frames;
  for (size_t at = svg.find("class=\"frame\""); at != std::string::npos; at = svg.find("class=\"frame\"", at + 1))
    frames.push_back(svg.substr(at, svg.find("height", at) - at));  // its x, y and width
  ASSERT_EQ(frames.size(), 2u);
  const auto xw = [](const std::string& f) {
    return f.substr(f.find("x=")).erase(f.substr(f.find("x=")).find(" y=")) + f.substr(f.find("width="));
  };
  EXPECT_EQ(xw(frames[0]), xw(frames[1]));
  // Alone, the two would differ.
  const std::string one = renderSvg(a), two = renderSvg(b);
  EXPECT_NE(one.substr(one.find("class=\"frame\""), 40), two.substr(two.find("class=\"frame\""), 40));
}

namespace {
// A tip: position node 5 at (1, 0) and its orientation node 105.
flexmb::core::Model tipModel() {
  using flexmb::core::NodeKind;
  flexmb::core::Model m;
  m.sourceFile = "tip.dat";
  flexmb::core::Node p, o;
  p.label = 5, p.kind = NodeKind::Position, p.firstCoord = 0;
  o.label = 105, o.kind = NodeKind::Orientation, o.firstCoord = 2;
  m.nodes = {p, o};
  m.nodeByLabel = {{5, 0}, {105, 1}};
  m.nx = 3;
  m.x0 = Eigen::Vector3d(1.0, 0.0, 0.0);
  return m;
}
}  // namespace

TEST(ForceDeflection, StaticAndSweepPanelsFromTheModelsInitialConfiguration) {
  const flexmb::core::Model m = tipModel();
  CsvTable s;
  s.columns = {"load_step", "initial_factor", "load_factor", "node5.x", "node5.y", "node105.angle", "F.node5.y"};
  s.rows = {{0, 1, 0, 1.0, 0.0, 0.0, 0.0}, {1, 1, 1, 0.99, -0.1, -0.15, -2.0}};
  const auto st = staticForceDeflectionPlots(m, s, {"node5.y", "node5.x"}, "static");
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].title, "static");
  EXPECT_EQ(st[1].title, "");
  EXPECT_EQ(st[0].series[0].y, std::vector<double>({0.0, -2.0}));  // F.node5.y
  EXPECT_EQ(st[1].series[0].y, std::vector<double>({0.0, 1.0}));   // the load factor: no load along x
  EXPECT_DOUBLE_EQ(st[1].series[0].x[1], 0.99 - 1.0);              // from X = 1
  // A sweep of the tip's rotation: its value is the deflection itself, the holding load in N m.
  CsvTable w;
  w.columns = {"value", "load", "f1_Hz", "node5.x", "node5.y", "node105.angle"};
  w.rows = {{-0.1, -0.5, 3, 0.99, -0.1, -0.1}, {0.1, 0.5, 3, 0.99, 0.1, 0.1}};
  const auto sw = sweepForceDeflectionPlots(m, w, {"value", "node5.x"}, "prescribed rotation [rad]", "N m", "sweep");
  ASSERT_EQ(sw.size(), 2u);
  EXPECT_EQ(sw[0].x.label, "prescribed rotation [rad]");
  EXPECT_EQ(sw[0].y.label, "the holding load [N m]");
  EXPECT_EQ(sw[0].series[0].label, "");  // the axis names it
  EXPECT_EQ(sw[0].series[0].x, std::vector<double>({-0.1, 0.1}));
  EXPECT_EQ(sw[1].series[0].y, std::vector<double>({-0.5, 0.5}));
  EXPECT_NEAR(sw[1].series[0].x[0], -0.01, 1e-15);
  try {
    staticForceDeflectionPlots(m, s, {"node5.z"}, "static");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "'node5.z' is not a coordinate of tip.dat; its coordinates (the CSV columns): node5.x, node5.y, "
              "node105.angle");
  }
}
