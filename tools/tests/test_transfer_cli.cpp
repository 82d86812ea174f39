// `flexmb transfer` and `--mode 9` (issue 21 item 3) and `--mode 3` on a static file (item 6) as a
// user meets them: the files each writes, what they hold (read back from the CSV), the Bode
// diagrams, a model without a transfer block, and the .ltv of mode 3.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tools/tests/CliFixture.hpp"

namespace fs = std::filesystem;

namespace {

using namespace flexmb::cli_test;

// Mass 4 on a spring 400 with damper 2 (PLTRUSS, l0 = 1): input force on the mass, outputs its
// displacement and velocity.
const char* kMassSpring =
    "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\n"
    "ESTIFF 1 400\nEDAMP 1 2\nXM 2 4\nITERSTEP 10 1\nEND\nHALT\n"
    "INPUTF 1 2 1\nOUTX 1 2 1\nOUTXP 2 2 1\nEND\nEND\n";

class TransferCli : public CliTest {
 protected:
  TransferCli() : CliTest("flexmb_tf_") {}
  int run(const std::string& args, std::string* out = nullptr) {
    const std::string cmd = "cd '" + dir_.string() + "' && timeout 120 '" + kFlexmb + "' " + args + " >out.txt 2>&1";
    const int status = std::system(cmd.c_str());
    if (out) *out = slurp(dir_ / "out.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  }
  std::vector<std::vector<std::string>> csv(const std::string& name) {
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(dir_ / name);
    for (std::string line; std::getline(in, line);) {
      rows.emplace_back();
      std::stringstream s(line);
      for (std::string c; std::getline(s, c, ',');) rows.back().push_back(c);
    }
    return rows;
  }
};

}  // namespace

TEST_F(TransferCli, WritesTheStateSpaceModelAndBodeDiagrams) {
  std::ofstream(dir_ / "ms.dat") << kMassSpring;
  std::string out;
  ASSERT_EQ(run("transfer ms.dat", &out), 0) << out;
  for (const char* f : {"ms.sbd", "ms.sbm", "ms.ltv", "ms_A.csv", "ms_B.csv", "ms_C.csv", "ms_D.csv",
                        "ms_bode_in1_out1.svg", "ms_bode_in1_out2.svg", "ms_run.txt"})
    EXPECT_TRUE(fs::exists(dir_ / f)) << f << "\n" << out;
  // A = [0 1; -k/m -d/m] read back from the CSV (header row and a name column).
  const auto A = csv("ms_A.csv");
  ASSERT_EQ(A.size(), 3u);
  EXPECT_NEAR(std::stod(A[1][2]), 1.0, 1e-15);
  EXPECT_NEAR(std::stod(A[2][1]), -100.0, 1e-12);
  EXPECT_NEAR(std::stod(A[2][2]), -0.5, 1e-14);
  const auto B = csv("ms_B.csv");
  EXPECT_NEAR(std::stod(B[2][1]), 0.25, 1e-15);
  // The static gain printed: 1/k.
  EXPECT_NE(out.find("0.0025"), std::string::npos) << out;
  const std::string svg = slurp(dir_ / "ms_bode_in1_out1.svg");
  // The magnitude in the output's unit per the input's (issue 51): displacement per force, velocity per force.
  EXPECT_NE(svg.find(">magnitude [m/N]<"), std::string::npos);
  EXPECT_NE(slurp(dir_ / "ms_bode_in1_out2.svg").find(">magnitude [(m/s)/N]<"), std::string::npos);
  EXPECT_NE(svg.find("phase [deg]"), std::string::npos);
  // The range drawn, by default a decade either side of the eigenfrequency (1.59 Hz).
  EXPECT_NE(out.find("  Bode diagrams from 0.1592 to 15.92 Hz (a frequency range FMIN,FMAX in Hz sets it)\n"),
            std::string::npos)
      << out;
  EXPECT_NE(slurp(dir_ / "ms_run.txt").find("status: complete"), std::string::npos);
  // --mode 9 is the same command (files with the same content).
  fs::create_directories(dir_ / "m9");
  ASSERT_EQ(run("--mode 9 ms.dat --out m9/ --no-bode", &out), 0) << out;
  EXPECT_EQ(slurp(dir_ / "m9/ms_A.csv"), slurp(dir_ / "ms_A.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "m9/ms_bode_in1_out1.svg"));
  EXPECT_EQ(svg.find("no damping"), std::string::npos) << "the damped model has no undamped note";
}

// Issue 35: an undamped model's Bode diagrams say that their peaks are infinite (give EDAMP), on
// the screen and in the picture; the phase is continuous (unwrapped) through the resonance.
TEST_F(TransferCli, AnUndampedModelsBodeDiagramSaysSo) {
  std::string text = kMassSpring;
  text.replace(text.find("EDAMP 1 2\n"), 10, "");
  std::ofstream(dir_ / "ms.dat") << text;
  std::string out;
  ASSERT_EQ(run("transfer ms.dat", &out), 0) << out;
  EXPECT_NE(out.find("no damping in the model: the peaks are infinite"), std::string::npos) << out;
  const std::string svg = slurp(dir_ / "ms_bode_in1_out1.svg");
  EXPECT_NE(svg.find("give EDAMP"), std::string::npos);
}

TEST_F(TransferCli, RefusesAModelWithoutATransferBlock) {
  std::string text = kMassSpring;
  text = text.substr(0, text.find("HALT\nINPUTF")) + "END\n";
  std::ofstream(dir_ / "plain.dat") << text;
  std::string out;
  EXPECT_EQ(run("transfer plain.dat", &out), 1) << out;
  EXPECT_NE(out.find("no transfer block"), std::string::npos) << out;
  // A bad channel is an input error with file:line.
  text = kMassSpring;
  text.replace(text.find("OUTX 1 2 1"), 10, "OUTX 1 1 1");
  std::ofstream(dir_ / "bad.dat") << text;
  EXPECT_EQ(run("transfer bad.dat", &out), 1) << out;
  EXPECT_NE(out.find("bad.dat:16: OUTX: coordinate 1 of node 1 is fixed"), std::string::npos) << out;
}

// --mode 3 on a static file: the load steps with the .ltv of M0 and K0B over the kinematic degrees
// of freedom (here the prescribed base coordinate and the spring), mode 3 in the .sbd.
TEST_F(TransferCli, Mode3OnAStaticFileWritesTheLtv) {
  std::ofstream(dir_ / "base.dat")
      << "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nINPUTX 1 1\nFIX 1 2\nFIX 2 2\nDYNE 1 1\nEND\nHALT\n"
         "ESTIFF 1 300\nEM 1 0.6\nXM 2 2\nDELINPX 1 1 0.1\nITERSTEP 10 4\nEND\nEND\n";
  std::string out;
  ASSERT_EQ(run("--mode 3 base.dat -q --out base_static.csv", &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir_ / "base.ltv")) << out;
  EXPECT_TRUE(fs::exists(dir_ / "base.sbd")) << out;
  // Load steps 0..4 in the CSV (the first column is the SPACAR load step).
  const auto rows = csv("base_static.csv");
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0][0], "load_step");
  EXPECT_EQ(rows[1][0], "0");
  EXPECT_EQ(rows[5][0], "4");
}

// Issue 35: the shipped pivot with a transfer block (moment about z in, rotation about z out): its
// static gain is the compliance that `static` gives under a small moment on the same model (the
// rotation from load step 0, gravity only, to load step 1, divided by the moment).
TEST_F(TransferCli, ThePivotsStaticGainIsItsStaticCompliance) {
  const std::string path = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_transfer.dat";
  std::string out;
  ASSERT_EQ(run("transfer '" + path + "' --no-bode", &out), 0) << out;
  const auto at = out.find("static gain");
  ASSERT_NE(at, std::string::npos) << out;
  const double gain = std::stod(out.substr(out.find('\n', at) + 1));
  // The same model with a moment instead of the transfer block.
  std::string text = slurp(path);
  const auto iter = text.find("\nITERSTEP");
  text.replace(iter + 1, text.find('\n', iter + 1) - iter - 1, "ITERSTEP 10 1");
  text.resize(text.find("END\nHALT\nINPUTF"));
  const double moment = 1e-4;
  text += "DELXF 4 0 0 " + std::to_string(moment) + "\nEND\nEND\n";
  std::ofstream(dir_ / "moment.dat") << text;
  ASSERT_EQ(run("static moment.dat --format csv --out m.csv -q", &out), 0) << out;
  const auto rows = csv("m.csv");
  ASSERT_EQ(rows.size(), 3u) << "header, load steps 0 and 1";
  int l0 = -1;
  for (size_t c = 0; c < rows[0].size(); ++c)
    if (rows[0][c] == "node4.lambda0") l0 = static_cast<int>(c);
  ASSERT_GE(l0, 0);
  auto angle = [&](int r) { return 2.0 * std::atan2(std::stod(rows[r][l0 + 3]), std::stod(rows[r][l0])); };
  const double compliance = (angle(2) - angle(1)) / moment;
  std::printf("pivot: static gain %.8g rad/(N m), static compliance %.8g\n", gain, compliance);
  EXPECT_NEAR(gain / compliance, 1.0, 1e-4);
}

// transfer --freq-range FMIN,FMAX (issue 51): the Bode diagrams' frequencies in Hz; the axis spans
// them, the screen and the manifest say them; a bad value or one with --no-bode is a usage error.
TEST_F(TransferCli, FreqRangeSetsTheBodeDiagramsFrequencies) {
  const std::string pivot = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_transfer.dat";
  std::string out;
  ASSERT_EQ(run("transfer '" + pivot + "' --out p --freq-range 1,100", &out), 0) << out;
  EXPECT_NE(out.find("  Bode diagrams from 1 to 100 Hz\n"), std::string::npos) << out;
  EXPECT_NE(slurp(dir_ / "p_run.txt").find("Bode frequency range: 1,100 Hz"), std::string::npos);
  const std::string svg = slurp(dir_ / "p_bode_in1_out1.svg");
  // The frequency axis (its labels centred under it) from 10^0 to 10^2, the magnitude a rotation per moment.
  const auto xTick = [](int k) {
    return "text-anchor=\"middle\">10<tspan dy=\"-5\" font-size=\"8\">" + std::to_string(k) + "</tspan>";
  };
  EXPECT_NE(svg.find(xTick(0)), std::string::npos);
  EXPECT_NE(svg.find(xTick(2)), std::string::npos);
  EXPECT_EQ(svg.find(xTick(3)), std::string::npos);
  EXPECT_EQ(svg.find(xTick(-1)), std::string::npos);
  EXPECT_NE(svg.find(">magnitude [rad/(N m)]<"), std::string::npos);
  EXPECT_NE(slurp(dir_ / "p_bode_in1_out2.svg").find(">magnitude [(rad/s)/(N m)]<"), std::string::npos);
  for (const std::string bad : {"100,1", "0,10", "-1,5", "10", "x,10", "10,20,30", "10,inf"}) {
    EXPECT_EQ(run("transfer '" + pivot + "' --out b --freq-range " + bad, &out), 2) << bad;
    EXPECT_NE(out.find("--freq-range must be FMIN,FMAX in Hz with 0 < FMIN < FMAX, not '" + bad + "'"),
              std::string::npos)
        << out;
  }
  EXPECT_EQ(run("transfer '" + pivot + "' --out b --freq-range 1,10 --no-bode", &out), 2) << out;
  EXPECT_NE(out.find("it cannot go with --no-bode"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ / "b_run.txt")) << "a usage error writes nothing";
}
