// The files of a design study: parameter tables and grid axes (io/templates/StudyTable.hpp), variant
// summaries, the collected table and the report (io/templates/StudySummary.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "io/templates/StudySummary.hpp"
#include "io/templates/StudyTable.hpp"

using namespace flexmb::io;

namespace {
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(StudyTable, ReadsParametersNamesCommentsAndQuotes) {
  const ParameterTable t = parseParameterTable(
      "# leaf variants\n"
      "name, t, L\n"
      "\n"
      "thin, 1e-4, 0.1\n"
      "\"thick\",+2.5E-4,0.12\n",
      "p.csv");
  ASSERT_EQ(t.parameters, (std::vector<std::string>{"t", "L"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.names, (std::vector<std::string>{"thin", "thick"}));
  EXPECT_EQ(t.rows[1], (std::vector<double>{2.5e-4, 0.12}));
  EXPECT_EQ(t.lines, (std::vector<int>{4, 5}));
}

TEST(StudyTable, ErrorsNameFileLineAndColumn) {
  EXPECT_NE(errorOf([] { parseParameterTable("t,L\n1,2\n3,x\n", "p.csv"); }).find("p.csv:3: column 'L': 'x' is not"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              parseParameterTable("t,L\n1,2\n3,0,5\n", "p.csv");
            }).find("p.csv:3: 3 cells, the header has 2 (a decimal comma?"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("t,t\n1,2\n", "p.csv"); }).find("p.csv:1: column 't' appears twice"),
            std::string::npos);
  EXPECT_NE(
      errorOf([] { parseParameterTable("t,2x\n1,2\n", "p.csv"); }).find("p.csv:1: column 2: '2x' is not a parameter"),
      std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("name,t\na,1\na,2\n", "p.csv"); }).find("p.csv:3: name 'a' appears twice"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("name,t\n../x,1\n", "p.csv"); }).find("p.csv:2: name '../x' cannot name"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("t\n1\ninf\n", "p.csv"); }).find("p.csv:3:"), std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("t\n", "p.csv"); }).find("p.csv: the table has a header but no rows"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("# only\n", "p.csv"); }).find("p.csv: the table is empty"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseParameterTable("t,\"x\n", "p.csv"); }).find("p.csv:1: a quote"), std::string::npos);
}

TEST(StudyTable, GridAxes) {
  const ParameterAxis a = parseParameterAxis("t=0.1e-3:0.5e-3:9");
  EXPECT_EQ(a.name, "t");
  ASSERT_EQ(a.values.size(), 9u);
  EXPECT_EQ(a.values.front(), 0.1e-3);
  EXPECT_EQ(a.values.back(), 0.5e-3);
  EXPECT_EQ(a.values[1], 0.00015);  // rounded to 15 digits: the decimal a user expects
  for (size_t k = 0; k < a.values.size(); ++k) EXPECT_NEAR(a.values[k], 1e-4 + 5e-5 * k, 1e-18);
  EXPECT_EQ(parseParameterAxis("L = 1,2.5, 4").values, (std::vector<double>{1, 2.5, 4}));
  EXPECT_EQ(parseParameterAxis("w=0.05").values, (std::vector<double>{0.05}));
  EXPECT_EQ(parseParameterAxis("w=3:3:1").values, (std::vector<double>{3}));
  EXPECT_EQ(parseParameterAxis("x=-1:1:3").values, (std::vector<double>{-1, 0, 1}));
  for (const char* bad :
       {"t", "t=", "=1", "2t=1", "t=1:2", "t=1:2:0", "t=1:2:2.5", "t=1:2:1", "t=a,b", "t=1:x:3", "status=1"})
    EXPECT_THROW(parseParameterAxis(bad), std::invalid_argument) << bad;
  EXPECT_NE(errorOf([] { parseParameterAxis("t=1:2"); }).find("--param t=1:2: a range is from:to:count"),
            std::string::npos);
}

TEST(StudySummary, RecordRoundTripWithQuotedReasonAndEmptyCells) {
  StudyRecord r;
  r.variant = 7;
  r.name = "v0007";
  r.parameters = {{"t", 1.5e-4}, {"w", 0.05}};
  r.status = "failed";
  r.reason = "static: no equilibrium beyond load factor 0.5, \"step\" 3\nof 9";
  r.quantities = {{"f1_Hz", 12.345678901234567}, {"buckling1", std::numeric_limits<double>::quiet_NaN()}};
  std::ostringstream out;
  writeStudyRecord(out, r);
  EXPECT_EQ(out.str(),
            "variant,name,t,w,status,f1_Hz,buckling1,reason\n"
            "7,v0007,0.00015,0.05,failed,12.345678901234567,,\"static: no equilibrium beyond load factor 0.5, "
            "\"\"step\"\" 3 of 9\"\n");
  const auto back = parseStudyTable(out.str(), "s.csv");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].variant, 7);
  EXPECT_EQ(back[0].parameters, r.parameters);
  EXPECT_EQ(back[0].status, "failed");
  EXPECT_EQ(back[0].reason, "static: no equilibrium beyond load factor 0.5, \"step\" 3 of 9");
  EXPECT_EQ(back[0].quantities[0].second, 12.345678901234567);
  EXPECT_TRUE(std::isnan(back[0].quantities[1].second));
  EXPECT_NE(errorOf([] { parseStudyTable("a,b\n1,2\n", "s.csv"); }).find("s.csv:1:"), std::string::npos);
}

TEST(StudySummary, CollectedTableTakesTheUnionOfColumns) {
  StudyRecord a{1, "v0001", {{"t", 1}}, "ok", "", {{"dofs", 4}, {"f1_Hz", 10}, {"buckling1", 3}}};
  StudyRecord b{2, "v0002", {{"t", 2}}, "failed", "no mass", {}};
  StudyRecord c{3, "v0003", {{"t", 3}}, "ok", "", {{"f1_Hz", 30}, {"k_node3_x", 5}}};
  std::ostringstream out;
  writeStudyTable(out, {a, b, c});
  EXPECT_EQ(out.str(),
            "variant,name,t,status,dofs,f1_Hz,buckling1,k_node3_x,reason\n"
            "1,v0001,1,ok,4,10,3,,\n"
            "2,v0002,2,failed,,,,,no mass\n"
            "3,v0003,3,ok,,30,,5,\n");
  EXPECT_EQ(plottableQuantities({a, b, c}), (std::vector<std::string>{"f1_Hz", "buckling1", "k_node3_x"}));
  // The same value in every variant that has it: a flat line, not plotted; one variant's value is.
  a.quantities.emplace_back("reduction_error", 0.0);
  c.quantities.emplace_back("reduction_error", 0.0);
  b.quantities.emplace_back("sim_t_end", 0.2);
  EXPECT_EQ(plottableQuantities({a, b, c}), (std::vector<std::string>{"f1_Hz", "buckling1", "sim_t_end", "k_node3_x"}));
}

TEST(StudySummary, PlotsOneLinePerCombinationOfTheOtherParameters) {
  std::vector<StudyRecord> rs;
  int n = 0;
  for (double w : {0.02, 0.05})
    for (double t : {3.0, 1.0, 2.0}) rs.push_back({++n, "v", {{"w", w}, {"t", t}}, "ok", "", {{"f1_Hz", w * t}}});
  rs.push_back({++n, "v", {{"w", 0.05}, {"t", 4.0}}, "failed", "x", {{"f1_Hz", 99}}});  // left out
  const Plot p = studyPlot(rs, "f1_Hz", "t");
  ASSERT_EQ(p.series.size(), 2u);
  EXPECT_EQ(p.series[0].label, "w = 0.02");
  EXPECT_EQ(p.series[0].x, (std::vector<double>{1, 2, 3}));  // sorted along the parameter
  EXPECT_EQ(p.series[1].y, (std::vector<double>{0.05, 0.1, 0.15000000000000002}));
  EXPECT_EQ(p.x.label, "t");
  const Plot q = studyPlot(rs, "f1_Hz", "w");
  EXPECT_EQ(q.series.size(), 3u);  // one per t
}

TEST(StudySummary, ReportHasPlotsFailuresAndTable) {
  std::vector<StudyRecord> rs = {{1, "v0001", {{"t", 1}}, "ok", "", {{"f1_Hz", 10}}},
                                 {2, "v0002", {{"t", 2}}, "ok", "", {{"f1_Hz", 20}}},
                                 {3, "bad<1>", {{"t", 3}}, "failed", "a & b", {}},
                                 {4, "v0004", {{"t", 4}}, "missing", "not run yet", {}}};
  const std::string html = renderStudyReport({"Study of x.dat", {"analysis: modes"}, {}}, rs);
  EXPECT_NE(html.find("4 variants: 2 ok, 1 failed, 1 not run yet"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("f1_Hz against t"), std::string::npos);
  EXPECT_NE(html.find("bad&lt;1&gt;"), std::string::npos);
  EXPECT_NE(html.find("a &amp; b"), std::string::npos);
  EXPECT_EQ(html.find("a & b"), std::string::npos);
}

TEST(StudyTable, VariantNames) {
  EXPECT_TRUE(isVariantName("v0001"));
  EXPECT_TRUE(isVariantName("thin-leaf_2.5"));
  for (const char* bad : {"", ".", "..", "-x", "a/b", "a b", "a,b"}) EXPECT_FALSE(isVariantName(bad)) << bad;
}

// Issue 35: units where the name says them, log axes for positive ranges over two decades, 6
// significant digits in the report's table.
TEST(StudySummary, UnitsLogAxesAndSixDigits) {
  EXPECT_EQ(quantityUnit("f1_Hz"), "Hz");
  EXPECT_EQ(quantityUnit("k_node3_x"), "N/m");
  EXPECT_EQ(quantityUnit("k_node4_rz"), "N m/rad");
  EXPECT_EQ(quantityUnit("max_bending_moment_y"), "N m");
  EXPECT_EQ(quantityUnit("max_axial_force"), "N");
  EXPECT_EQ(quantityUnit("buckling1"), "");
  std::vector<StudyRecord> rs;
  int n = 0;
  for (double t : {1e-4, 1e-3, 1e-2, 1e-1}) rs.push_back({++n, "v", {{"t", t}}, "ok", "", {{"k_node3_x", 1 + t}}});
  const Plot p = studyPlot(rs, "k_node3_x", "t");
  EXPECT_TRUE(p.x.log) << "t spans three decades";
  EXPECT_FALSE(p.y.log) << "k spans less than one";
  EXPECT_EQ(p.y.label, "k_node3_x [N/m]");
  rs.front().parameters = {{"t", 0.123456789}};
  const std::string html = renderStudyReport({"s", {}, {}}, rs);
  EXPECT_NE(html.find(">0.123457<"), std::string::npos) << html;
  EXPECT_NE(html.find("k_node3_x [N/m]"), std::string::npos);
}
