// Issue 49, item 1: the operators `flexmb reduce` writes are the operators `simulate --basis` uses on
// the same model (the run measures their fit as training did, at the same held-out
// configurations); a misfit or a changed model never stops a run: it goes on with Eq. 19 (the full
// kinematics through the basis) and says why on the screen and in the manifest.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tools/tests/CliFixture.hpp"

namespace fs = std::filesystem;

namespace {

using namespace flexmb::cli_test;

class OperatorCli : public CliTest {
 protected:
  OperatorCli() : CliTest("flexmb_ops_") {}
  const std::string guidance = kData + "straight_guidance.dat";
  // reduce with `method`, then simulate on the basis: both exit 0, and the run uses the operators
  // reduce wrote, or (reduce said it wrote none) Eq. 19 with the reason.
  void reduceThenSimulate(const std::string& method, const std::string& out) {
    Result r = flexmb("reduce " + guidance + " " + method + " --out " + out + ".csv -q");
    ASSERT_EQ(r.code, 0) << r.err;
    const bool written = r.out.find("reduced operators written to " + out + ".operators") != std::string::npos;
    EXPECT_TRUE(written || r.out.find("reduced operators not built: ") != std::string::npos) << r.out;
    r = flexmb("simulate " + guidance + " --basis " + out + ".csv --out " + out + " --format none -q");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string used = written ? "reduced dynamics: reduced operators for" : "reduced dynamics: Eq. 19 (no";
    EXPECT_NE(r.out.find(used), std::string::npos) << r.out;
    EXPECT_NE(slurp(dir_ / (out + "_run.txt")).find(used), std::string::npos);
  }
};

}  // namespace

TEST_F(OperatorCli, ReducesOwnOperatorsServeTheRunOnTheSameModel) {
  const std::string svd = "--method svd-modal --weight 0 --node 6 --comp 1 --from -0.0833 --to 0.0833";
  reduceThenSimulate(svd + " --modes 3", "s3");
  reduceThenSimulate(svd + " --modes 5", "s5");
  reduceThenSimulate("--method modal --modes 3", "m3");
}

TEST_F(OperatorCli, AMisfitOrAChangedModelRunsEquation19AndSaysWhy) {
  ASSERT_EQ(flexmb("reduce " + guidance + " --modes 3 --out m3.csv -q").code, 0);
  // The same model read with the plain PLBEAM elongation: not in the checksum, seen by the fit.
  Result r = flexmb("simulate " + guidance + " --elongation plain --basis m3.csv --out plain --format none -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("reduced dynamics: Eq. 19 (m3.operators does not fit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("where training measured"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("the model changed"), std::string::npos) << r.out;
  EXPECT_NE(slurp(dir_ / "plain_run.txt").find("reduced dynamics: Eq. 19 (m3.operators does not fit"),
            std::string::npos);
  // A stiffer flexure: the checksum differs, "the model changed".
  const std::string stiffer = variant("straight_guidance.dat", "6\\.3e6  0\\.525", "6.3e6  0.6", "stiffer.dat");
  r = flexmb("simulate " + stiffer + " --basis m3.csv --out stiffer --format none -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("reduced dynamics: Eq. 19 (m3.operators does not fit stiffer.dat"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the model changed since they were made"), std::string::npos) << r.out;
  EXPECT_NE(slurp(dir_ / "stiffer_run.txt").find("the model changed since they were made"), std::string::npos);
  // A stronger force pulse (its time function only): the same checksum, the operators serve.
  const std::string stronger = variant("straight_guidance.dat", "50\\*\\(1-cos", "80*(1-cos", "stronger.dat");
  ASSERT_NE(slurp(dir_ / stronger).find("80*(1-cos"), std::string::npos);
  r = flexmb("simulate " + stronger + " --basis m3.csv --out stronger --format none -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("reduced dynamics: reduced operators for"), std::string::npos) << r.out;
}
