// The fuzz seeds of tools/fuzz/seeds (tools/fuzz/README.md) are what the fuzzer mutates first: each
// must be an input the readers accept, so that mutations start inside the accepted language, and
// each .dat seed a well-posed model, so that the kinematic check behind the reader runs in full.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/kinematics/KinematicCheck.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/DatReader.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> seeds(const std::string& kind, const std::string& extension) {
  std::vector<fs::path> files;
  for (const auto& f : fs::directory_iterator(fs::path(FLEXMB_SOURCE_DIR) / "tools/fuzz/seeds" / kind))
    if (f.path().extension() == extension) files.push_back(f.path());
  return files;
}

}  // namespace

TEST(FuzzSeeds, DatSeedsAreWellPosedModels) {
  const std::vector<fs::path> files = seeds("dat", ".dat");
  EXPECT_GE(files.size(), 3u);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    flexmb::core::Model model;
    ASSERT_NO_THROW(model = flexmb::io::readDatFile(f.string()));
    const flexmb::core::KinematicReport r = flexmb::core::checkKinematics(model);
    EXPECT_TRUE(r.wellPosed()) << flexmb::core::formatReport(r);
    EXPECT_GT(r.dof, 0);
  }
}

TEST(FuzzSeeds, BasisSeedsAreReadable) {
  const std::vector<fs::path> files = seeds("basis", ".csv");
  EXPECT_GE(files.size(), 3u);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    flexmb::io::BasisInfo info;
    Eigen::MatrixXd V;
    ASSERT_NO_THROW(V = flexmb::io::readBasis(f.string(), &info));
    EXPECT_GT(V.size(), 0);
  }
}
