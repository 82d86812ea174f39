// `flexmb static`'s stresses, reactions and --compliance (issue 53 item 1; analysis/StaticDesign.hpp) on
// datfiles/cantilever.dat with a 20 x 2 mm section: the files, the screen, and the errors.
#include <cmath>
#include <string>

#include "tools/tests/CliFixture.hpp"

using namespace flexmb::cli_test;

namespace {

class StaticDesignCli : public CliTest {
 protected:
  // The cantilever with its section (VISUALIZATION after the file's last END).
  std::string sectioned() {
    std::ofstream(dir_ / "cantilever.dat")
        << slurp(kData + "cantilever.dat") << "VISUALIZATION\nBEAMPROPS 1 2 3 4\nCROSSTYPE RECT\nCROSSDIM 0.02 0.002\n";
    return "cantilever.dat";
  }
};

// The cell of `column` in the row of a CSV text whose first cells are `prefix`.
double cell(const std::string& csv, const std::string& prefix, const std::string& column) {
  std::istringstream in(csv);
  std::string header, line;
  std::getline(in, header);
  auto split = [](const std::string& s) {
    std::vector<std::string> v;
    std::stringstream ss(s);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(c);
    return v;
  };
  const auto names = split(header);
  const auto at = std::find(names.begin(), names.end(), column) - names.begin();
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0) {
      const auto cells = split(line);
      if (static_cast<size_t>(at) < cells.size() && !cells[static_cast<size_t>(at)].empty())
        return std::stod(cells[static_cast<size_t>(at)]);
    }
  ADD_FAILURE() << "no " << column << " in the row " << prefix;
  return NAN;
}

}  // namespace

TEST_F(StaticDesignCli, WritesStressReactionsAndCompliance) {
  const Result r = flexmb("static " + sectioned() + " --compliance 5 --out s.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  // Screen: the clamp's stress P L (t/2)/I (the arm shortened by the deflection), the reaction, the tip's matrix.
  EXPECT_TRUE(has(r.out, "largest von Mises stress at the last load step: 7499430 Pa (PLBEAM 1")) << r.out;
  EXPECT_TRUE(has(r.out, "R.F.node1.y = 0.1\n")) << r.out;
  EXPECT_TRUE(has(r.out, "compliance at the last load step")) << r.out;
  // The unloaded step's compliance: L^3/(3 EI), L/(EI) with EI = 2.8 N m^2, L/(EA) with EA = 8.4e6 N.
  const std::string c = slurp(dir_ / "s_compliance.csv");
  EXPECT_NEAR(cell(c, "0,1,0,5,2,", "y"), 1.0 / 8.4, 1e-9);
  EXPECT_NEAR(cell(c, "0,1,0,5,3,", "angle"), 1.0 / 2.8, 1e-9);
  EXPECT_NEAR(cell(c, "0,1,0,5,1,", "x"), 1.0 / 8.4e6, 1e-15);
  const std::string s = slurp(dir_ / "s_stress.csv");
  EXPECT_NEAR(cell(s, "1,", "stress_PLBEAM1"), 7.5e6, 1e-3 * 7.5e6);
  const std::string main = slurp(dir_ / "s.csv");
  EXPECT_NEAR(cell(main, "1,", "R.F.node1.y"), 0.1, 1e-12);
  EXPECT_NEAR(cell(main, "1,", "max_stress_element"), 1.0, 0.0);
  EXPECT_TRUE(fs::exists(dir_ / "cantilever.sbd")) << listing();
  EXPECT_TRUE(has(slurp(dir_ / "s_run.txt"), "compliance nodes: 5")) << slurp(dir_ / "s_run.txt");
}

TEST_F(StaticDesignCli, UnknownOrMalformedNodesAreRefused) {
  Result r = flexmb("static " + sectioned() + " --compliance 5,77");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_TRUE(has(r.err, "77") && has(r.err, "--compliance")) << r.err;
  r = flexmb("static " + sectioned() + " --compliance tip");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "--compliance")) << r.err;
}
