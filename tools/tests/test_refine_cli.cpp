// `--refine N` on the command line: the run and its manifest say what it refined; the result files
// (static's table, simulate's tables) have exactly the unrefined model's columns, each with the
// refined run's values (those of `--refined-results`, which writes every node and element); the
// deflection of the refined guidance is the original's to the beams' discretisation error; a basis
// that `reduce --refine N` wrote serves `simulate --refine N`; a bad N is a usage error.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "CliFixture.hpp"

using namespace flexmb::cli_test;

namespace {
class RefineCli : public CliTest {};

std::vector<std::string> headerOf(const std::string& csv) {
  std::vector<std::string> names;
  std::istringstream line(csv.substr(0, csv.find('\n')));
  for (std::string name; std::getline(line, name, ',');) names.push_back(name);
  return names;
}

std::vector<std::vector<double>> rowsOf(const std::string& csv) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    rows.emplace_back();
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) rows.back().push_back(cell.empty() ? NAN : std::stod(cell));
  }
  return rows;
}

// Every column of `part` is a column of `whole` with the same values in every row (blank cells
// alike); returns how many columns were compared.
size_t sameColumns(const std::string& part, const std::string& whole) {
  const std::vector<std::string> hp = headerOf(part), hw = headerOf(whole);
  const auto rp = rowsOf(part), rw = rowsOf(whole);
  EXPECT_EQ(rp.size(), rw.size());
  size_t compared = 0;
  for (size_t c = 0; c < hp.size(); ++c) {
    const auto at = std::find(hw.begin(), hw.end(), hp[c]);
    if (at == hw.end()) {
      ADD_FAILURE() << hp[c] << " is not a column of the refined model's file";
      continue;
    }
    const size_t w = static_cast<size_t>(at - hw.begin());
    for (size_t r = 0; r < rp.size() && r < rw.size(); ++r) {
      const double a = rp[r].at(c), b = rw[r].at(w);
      if (std::isnan(a) || std::isnan(b))
        EXPECT_EQ(std::isnan(a), std::isnan(b)) << hp[c] << " row " << r;
      else
        EXPECT_NEAR(a, b, 1e-12 * (1.0 + std::abs(b))) << hp[c] << " row " << r;
    }
    ++compared;
  }
  return compared;
}

double lastRowValue(const std::string& csv, size_t column) {
  std::istringstream in(csv);
  std::string row, last;
  while (std::getline(in, row))
    if (!row.empty()) last = row;
  std::istringstream cells(last);
  std::string cell;
  for (size_t k = 0; k <= column; ++k) std::getline(cells, cell, ',');
  return std::stod(cell);
}
}  // namespace

TEST_F(RefineCli, StaticWritesTheOriginalNodes) {
  // The guidance with a constant 20 N on the body (a static load) instead of the pulse.
  const std::string model = variant("straight_guidance.dat", "XFT 6 1 [^\n]*", "XF 6 20 0");
  const Result a = flexmb("static " + model + " --nev 1 --out a.csv");
  const Result b = flexmb("static " + model + " --nev 1 --refine 4 --out b.csv");
  const Result c = flexmb("static " + model + " --nev 1 --refine 4 --refined-results --out c.csv");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  ASSERT_EQ(c.code, 0) << c.err;
  // 10 flexure beams in 4 (the rigid body whole): 11 + 30 elements, 24 + 60 nodes.
  EXPECT_TRUE(has(b.err, "refined: every flexible beam split in 4 (41 elements, 84 nodes)")) << b.err;
  const std::string ma = slurp(dir_ / "a_run.txt"), mb = slurp(dir_ / "b_run.txt"), mc = slurp(dir_ / "c_run.txt");
  EXPECT_TRUE(has(mb, "\nrefined: every flexible beam split in 4 (41 elements, 84 nodes)\n")) << mb;
  EXPECT_FALSE(has(ma, "refined"));
  EXPECT_TRUE(has(mb, "\nresults: at the original nodes and elements")) << mb;
  EXPECT_TRUE(has(mc, "\nresults: every node and element of the refined model")) << mc;
  const std::string ta = slurp(dir_ / "a.csv"), tb = slurp(dir_ / "b.csv"), tc = slurp(dir_ / "c.csv");
  // Exactly the unrefined table's columns (coordinates, frequency, maxima, loads, reactions) ...
  EXPECT_EQ(headerOf(tb), headerOf(ta));
  // ... with the refined run's values: those of the refined model's own table.
  EXPECT_EQ(sameColumns(tb, tc), headerOf(ta).size());
  const std::vector<std::string> hc = headerOf(tc);
  EXPECT_NE(std::find(hc.begin(), hc.end(), "node117.x"), hc.end());  // the first new node's label
  const std::vector<std::string> ha = headerOf(ta);
  EXPECT_EQ(std::find(ha.begin(), ha.end(), "node117.x"), ha.end());
  // The .ltv (matrices over the refined degrees of freedom) only with the refined model's own files.
  const Result ltv = flexmb("static " + model + " --nev 1 --refine 4 --ltv --format mat --out d.csv");
  EXPECT_EQ(ltv.code, 2);
  EXPECT_TRUE(has(ltv.err, "--refined-results")) << ltv.err;
  EXPECT_EQ(flexmb("static " + model + " --nev 1 --refine 4 --refined-results --ltv --format mat --out e.csv").code, 0);
  // node6.x: the body's sideways position, the same within the discretisation error (1e-3).
  size_t x6 = 0;
  while (ha[x6] != "node6.x") ++x6;
  const double ua = lastRowValue(ta, x6), ub = lastRowValue(tb, x6);
  EXPECT_GT(ua, 1e-3);
  EXPECT_NEAR(ub, ua, 1e-3 * ua);
  EXPECT_NE(ub, ua);  // it did refine
}

TEST_F(RefineCli, SimulateWritesTheOriginalNodesAndElements) {
  // The 5-element guidance (5 PLBEAMs per leaf) refined by 2, 0.02 s of the pulse.
  const std::string model = std::string(kData) + "straight_guidance.dat";
  const std::string run = "simulate " + model + " --t-end 0.02 --intervals 4 --format both --quiet ";
  const Result a = flexmb(run + "--out a");
  const Result b = flexmb(run + "--refine 2 --out b");
  const Result c = flexmb(run + "--refine 2 --refined-results --out c");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  ASSERT_EQ(c.code, 0) << c.err;
  for (const std::string q : {"_x", "_xd", "_xdd", "_e", "_ed", "_edd", "_sig"}) {
    std::string name = q;
    name.append(".csv");
    const std::string ta = slurp(dir_ / ("a" + name)), tb = slurp(dir_ / ("b" + name)), tc = slurp(dir_ / ("c" + name));
    EXPECT_EQ(headerOf(tb), headerOf(ta)) << q;
    EXPECT_GT(headerOf(tc).size(), headerOf(ta).size()) << q;
    EXPECT_EQ(sameColumns(tb, tc), headerOf(ta).size()) << q;
  }
  // The motion differs from the unrefined run's (it did refine) by the discretisation error.
  const std::string xa = slurp(dir_ / "a_x.csv"), xb = slurp(dir_ / "b_x.csv");
  const std::vector<std::string> h = headerOf(xa);
  const size_t x6 = static_cast<size_t>(std::find(h.begin(), h.end(), "node6.x") - h.begin());
  ASSERT_LT(x6, h.size());
  const double motion = std::abs(lastRowValue(xa, x6) - rowsOf(xa).front().at(x6));
  EXPECT_GT(motion, 0.0);
  EXPECT_NE(lastRowValue(xb, x6), lastRowValue(xa, x6));
  EXPECT_NEAR(lastRowValue(xb, x6), lastRowValue(xa, x6), 5e-3 * motion);
  EXPECT_TRUE(has(slurp(dir_ / "b_run.txt"), "\nresults: at the original nodes and elements"));
  // The .mat and SPACAR's .sbd are written beside them (their layout: io's OriginalResults tests).
  for (const char* f : {"b.mat", "b.sbd", "c.sbd"}) EXPECT_TRUE(fs::exists(dir_ / f)) << f;
  EXPECT_LT(fs::file_size(dir_ / "b.sbd"), fs::file_size(dir_ / "c.sbd"));
}

TEST_F(RefineCli, ABasisOfTheRefinedModelServesTheSameRefinement) {
  // reduce --refine 2 writes the refined model's basis (its degrees of freedom); simulate with the
  // same --refine reads it and writes the original nodes; without it the basis does not fit.
  const std::string model = std::string(kData) + "straight_guidance.dat";
  const Result r = flexmb("reduce " + model + " --refine 2 --modes 3 --out basis.csv --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string run = "simulate " + model + " --t-end 0.02 --intervals 4 --quiet --basis basis.csv ";
  const Result s = flexmb(run + "--refine 2 --out s");
  ASSERT_EQ(s.code, 0) << s.err;
  const Result a = flexmb("simulate " + model + " --t-end 0.02 --intervals 4 --quiet --out a");
  ASSERT_EQ(a.code, 0) << a.err;
  std::string reduced;
  for (const auto& name : files())
    if (name.rfind("s", 0) == 0 && name.size() > 6 && name.compare(name.size() - 6, 6, "_x.csv") == 0) reduced = name;
  ASSERT_FALSE(reduced.empty());
  EXPECT_EQ(headerOf(slurp(dir_ / reduced)), headerOf(slurp(dir_ / "a_x.csv")));
  const Result wrong = flexmb(run + "--out w");
  EXPECT_EQ(wrong.code, 1) << wrong.err;
}

TEST_F(RefineCli, RefusesABadCount) {
  for (const char* bad : {"0", "-3", "two", "1.5"}) {
    const Result r = flexmb(std::string("modes ") + kData + "straight_guidance.dat --refine " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_TRUE(has(r.err, "--refine")) << r.err;
  }
}
