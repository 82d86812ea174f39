// `--refine N` on the command line: the run and its manifest say what it refined, the result files keep the original
// nodes under their labels in their places (the new nodes after them), the deflection of the
// refined guidance is the original's to the beams' discretisation error, and a bad N is a usage error.
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

TEST_F(RefineCli, ResultsKeepTheOriginalNodeLabels) {
  // The guidance with a constant 20 N on the body (a static load) instead of the pulse.
  const std::string model = variant("straight_guidance.dat", "XFT 6 1 [^\n]*", "XF 6 20 0");
  const Result a = flexmb("static " + model + " --nev 1 --out a.csv");
  const Result b = flexmb("static " + model + " --nev 1 --refine 4 --out b.csv");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  // 10 flexure beams in 4 (the rigid body whole): 11 + 30 elements, 24 + 60 nodes.
  EXPECT_TRUE(has(b.err, "refined: every flexible beam split in 4 (41 elements, 84 nodes)")) << b.err;
  EXPECT_TRUE(has(slurp(dir_ / "b_run.txt"), "\nrefined: every flexible beam split in 4 (41 elements, 84 nodes)\n"));
  EXPECT_FALSE(has(slurp(dir_ / "a_run.txt"), "refined"));
  const std::string ta = slurp(dir_ / "a.csv"), tb = slurp(dir_ / "b.csv");
  const std::vector<std::string> ha = headerOf(ta), hb = headerOf(tb);
  // The original coordinates' columns, in the same places: load_step ... node116.angle.
  size_t last = 0;
  while (last < ha.size() && ha[last] != "node116.angle") ++last;
  ASSERT_LT(last, ha.size());
  ASSERT_GT(hb.size(), last);
  for (size_t k = 0; k <= last; ++k) EXPECT_EQ(ha[k], hb[k]) << "column " << k;
  EXPECT_EQ(hb[last + 1].rfind("node117.", 0), 0u) << hb[last + 1];  // the first new node's label
  // node6.x: the body's sideways position, the same within the discretisation error (1e-3).
  size_t x6 = 0;
  while (ha[x6] != "node6.x") ++x6;
  const double ua = lastRowValue(ta, x6), ub = lastRowValue(tb, x6);
  EXPECT_GT(ua, 1e-3);
  EXPECT_NEAR(ub, ua, 1e-3 * ua);
  EXPECT_NE(ub, ua);  // it did refine
}

TEST_F(RefineCli, RefusesABadCount) {
  for (const char* bad : {"0", "-3", "two", "1.5"}) {
    const Result r = flexmb(std::string("modes ") + kData + "straight_guidance.dat --refine " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_TRUE(has(r.err, "--refine")) << r.err;
  }
}
