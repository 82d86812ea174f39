// `flexmb simulate --rayleigh 0,BETA` (issue 53 item 4): Rayleigh's beta K in a nonlinear time run is
// element damping, EDAMP = beta * ESTIFF on every element. A mass m on a spring k under a step force
// F follows x = F/k (1 - exp(-zeta w t) (cos wd t + zeta / sqrt(1 - zeta^2) sin wd t)) with
// zeta = beta w / 2, and the run equals the one of the file with EDAMP = beta k; a modal ratio and
// alpha have no form in a time run and are refused with why (input error, exit 1).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tools/tests/CliFixture.hpp"

namespace fs = std::filesystem;

namespace {

using namespace flexmb::cli_test;

std::string dampedStepModel(const char* edamp) {
  return std::string("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\nESTIFF 1 400\n") + edamp +
         "XM 2 4\nXF 2 0.001 0\nTIMESTEP 2 200\nEND\nEND\n";
}

// Column `name` of a CSV table written by simulate.
std::vector<double> csvColumn(const fs::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::stringstream head(line);
  int col = -1, k = 0;
  for (std::string c; std::getline(head, c, ','); ++k)
    if (c == name) col = k;
  std::vector<double> v;
  if (col < 0) return v;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string c;
    for (int j = 0; j <= col; ++j) std::getline(s, c, ',');
    v.push_back(std::stod(c));
  }
  return v;
}

class DampingCli : public CliTest {
 protected:
  DampingCli() : CliTest("flexmb_damping_") {}
};

}  // namespace

TEST_F(DampingCli, SimulateRayleighBetaIsTheDampedStepResponseAndEdamp) {
  std::ofstream(dir_ / "step.dat") << dampedStepModel("");
  std::ofstream(dir_ / "step_edamp.dat") << dampedStepModel("EDAMP 1 1.6\n");  // beta k = 0.004 * 400
  const std::string tight = " --integrator ode45 --reltol 1e-10 --abstol 1e-15";
  Result r = flexmb("simulate step.dat --rayleigh 0,0.004 --out b" + tight);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("damping added to the model's EDAMP"), std::string::npos) << r.err;
  EXPECT_NE(slurp(dir_ / "b_run.txt").find("added damping: Rayleigh alpha 0 1/s, beta 0.004 s"), std::string::npos)
      << slurp(dir_ / "b_run.txt");
  r = flexmb("simulate step_edamp.dat --out e" + tight);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<double> t = csvColumn(dir_ / "b_x.csv", "time"), x = csvColumn(dir_ / "b_x.csv", "node2.x"),
                            xe = csvColumn(dir_ / "e_x.csv", "node2.x");
  ASSERT_EQ(x.size(), 201u);
  ASSERT_EQ(xe.size(), x.size());
  const double k = 400, m = 4, F = 1e-3, w = std::sqrt(k / m), zeta = 0.004 * w / 2,
               wd = w * std::sqrt(1 - zeta * zeta);
  double worst = 0, worstEdamp = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double exact =
        1 + F / k *
                (1 - std::exp(-zeta * w * t[i]) *
                         (std::cos(wd * t[i]) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * t[i])));
    worst = std::max(worst, std::abs(x[i] - exact));
    worstEdamp = std::max(worstEdamp, std::abs(x[i] - xe[i]));
  }
  EXPECT_LT(worst, 1e-6 * F / k);  // the CSV's 17 digits on x near 1 leave ~1e-16
  EXPECT_LT(worstEdamp, 1e-12 * F / k);
  // Damped: the swing about F/k from 1.5 s on is within exp(-zeta w 1.5) = 0.74 of F/k, not the undamped F/k.
  double late = 0;
  for (std::size_t i = 150; i < x.size(); ++i) late = std::max(late, std::abs(x[i] - 1 - F / k));
  EXPECT_LT(late, 0.76 * F / k);
}

TEST_F(DampingCli, SimulateRefusesAModalRatioAndAlphaWithWhy) {
  std::ofstream(dir_ / "step.dat") << dampedStepModel("");
  Result r = flexmb("simulate step.dat --damping-ratio 0.02 --out r");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("modal damping ratio has no form in a nonlinear time run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("beta = 2 zeta / omega_1"), std::string::npos) << r.err;
  r = flexmb("simulate step.dat --rayleigh 0.5,0.004 --out r");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("alpha M (mass-proportional damping) is not in the nonlinear equations"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "r_x.csv"));
}
