// `--error-estimate` and `--accuracy EPS` on the command line (analysis/AccuracyTarget.hpp): the
// lines on the screen, the manifest's budget, the finest mesh's results written at the original
// nodes, and the usage errors.
#include "CliFixture.hpp"

using namespace flexmb::cli_test;

namespace {
class AccuracyCli : public CliTest {};

TEST_F(AccuracyCli, SimulateAccuracyMeetsItsTargetAndSaysHow) {
  const std::string model = std::string(kData) + "straight_guidance.dat";
  const Result r = flexmb("simulate " + model + " --accuracy 1e-2 --format csv --out g");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "discretization error estimate: ")) << r.out;
  EXPECT_TRUE(has(r.out, "total error estimate: ")) << r.out;
  EXPECT_FALSE(has(r.err, "is not met")) << r.err;
  const std::string manifest = slurp(dir_ / "g_run.txt");
  for (const char* key : {"\naccuracy target: 0.01", "\ntotal error estimate: ", "\ndiscretization error estimate: ",
                          "\nrefinement chosen: ", "\naccuracy target met: yes", "\nmeshes run: refine 1 ",
                          "\nintegrator tolerance: RelTol 0.0005"})
    EXPECT_TRUE(has(manifest, key)) << key << "\n" << manifest;
  // The finest mesh ran, its files hold the unrefined model's columns.
  const Result own = flexmb("simulate " + model + " --t-end 0.001 --format csv --out a --quiet");
  ASSERT_EQ(own.code, 0) << own.err;
  const std::string ta = slurp(dir_ / "a_x.csv"), tg = slurp(dir_ / "g_x.csv");
  EXPECT_EQ(ta.substr(0, ta.find('\n')), tg.substr(0, tg.find('\n')));
}

TEST_F(AccuracyCli, StaticAndModesErrorEstimateWriteTheModelsOwnMesh) {
  const std::string model = std::string(kData) + "cantilever.dat";
  const Result s = flexmb("static " + model + " --error-estimate --format csv --out s.csv");
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_TRUE(has(s.out, "at refine 1 (Richardson from refine 1, 2, 4")) << s.out;
  const Result m = flexmb("modes " + model + " --nev 4 --error-estimate --out m");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_TRUE(has(m.out, "relative (the largest over the 4 lowest frequencies) at refine 1")) << m.out;
  EXPECT_TRUE(has(slurp(dir_ / "m_run.txt"), "\ndiscretization error estimate: "));
}

TEST_F(AccuracyCli, ClashesAreUsageErrors) {
  const std::string model = std::string(kData) + "straight_guidance.dat";
  EXPECT_EQ(flexmb("simulate " + model + " --accuracy 2").code, 2);
  // Finer than double precision integrates: refused at once (it ran a mesh until the time limit).
  const Result fine = flexmb("simulate " + model + " --accuracy 1e-20");
  EXPECT_EQ(fine.code, 2);
  EXPECT_TRUE(has(fine.err, "at least 1e-10")) << fine.err;
  EXPECT_EQ(flexmb("simulate " + model + " --accuracy 1e-2 --error-estimate").code, 2);
  const Result b = flexmb("simulate " + model + " --accuracy 1e-2 --intervals 0");
  EXPECT_EQ(b.code, 2);
  EXPECT_TRUE(has(b.err, "--intervals 0")) << b.err;
  EXPECT_EQ(flexmb("static " + model + " --accuracy 1e-2 --max-seconds 0").code, 2);
  // A folder that does not exist is said before any mesh runs.
  const Result w = flexmb("simulate " + model + " --accuracy 1e-2 --out missing/g");
  EXPECT_EQ(w.code, 1);
  EXPECT_TRUE(has(w.err, "does not exist")) << w.err;
  EXPECT_FALSE(has(w.err, "simulate at refine")) << w.err;
}
}  // namespace
