// io/formats/OutputFile: atomic, checked result files and run manifests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/formats/OutputFile.hpp"

namespace fs = std::filesystem;
using namespace flexmb::io;

namespace {
fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("flexmb_outputfile_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(OutputFile, NothingUnderTheFinalNameBeforeCommit) {
  const fs::path d = freshDir("commit");
  {
    OutputFile f((d / "a.csv").string());
    f << "x,y\n1,2\n";
    EXPECT_FALSE(fs::exists(d / "a.csv"));
    f.commit();
  }
  EXPECT_EQ(slurp(d / "a.csv"), "x,y\n1,2\n");
  {
    OutputFile g((d / "b.csv").string());
    g << "half";
  }  // not committed: no file, no temporary
  EXPECT_FALSE(fs::exists(d / "b.csv"));
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);
  fs::remove_all(d);
}

TEST(OutputFile, MissingFolderIsAnError) {
  EXPECT_THROW(OutputFile("/nonexistent/folder/a.csv"), std::runtime_error);
  OutputSet set("/nonexistent/folder/run");
  EXPECT_THROW(set.checkWritable(), std::runtime_error);
}

TEST(OutputFile, ResolvePrefixTreatsFoldersAsFolders) {
  const fs::path d = freshDir("prefix");
  EXPECT_EQ(OutputSet::resolvePrefix("", "models/arm.dat"), "arm");
  EXPECT_EQ(OutputSet::resolvePrefix("", "models/arm.dat", "_sweep"), "arm_sweep");
  EXPECT_EQ(OutputSet::resolvePrefix("outd/", "arm.dat"), "outd/arm");
  EXPECT_EQ(OutputSet::resolvePrefix(d.string(), "arm.dat"), (d / "arm").string());
  EXPECT_EQ(OutputSet::resolvePrefix("res", "arm.dat"), "res");
  fs::remove_all(d);
}

TEST(OutputFile, SetCommitsFilesThenTheManifest) {
  const fs::path d = freshDir("set");
  std::ofstream((d / "r_run.txt")) << "flexmb run\nstatus: complete\n";  // an earlier run
  {
    OutputSet set((d / "r").string());
    set.checkWritable();
    EXPECT_FALSE(fs::exists(d / "r_run.txt"));  // the earlier set is no longer complete
    std::ofstream(set.temporaryFor("_x.csv")) << "time\n0\n";
    set.setting("reltol", "0.001");
    const auto written = set.commit("complete");
    EXPECT_EQ(written.size(), 2u);
  }
  EXPECT_EQ(slurp(d / "r_x.csv"), "time\n0\n");
  const std::string manifest = slurp(d / "r_run.txt");
  EXPECT_NE(manifest.find("status: complete"), std::string::npos);
  EXPECT_NE(manifest.find("reltol: 0.001"), std::string::npos);
  EXPECT_NE(manifest.find("file: r_x.csv"), std::string::npos);
  {
    OutputSet set((d / "s").string());
    std::ofstream(set.temporaryFor("_x.csv")) << "partial";
  }  // destroyed without commit: temporaries removed
  EXPECT_FALSE(fs::exists(d / "s_x.csv"));
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().string().find(".part-"), std::string::npos) << e.path();
  fs::remove_all(d);
}

// Files from anywhere (a --svg path, <model>.sbd beside a CSV), files that name their own (a
// picture series, listed after the renames), numbers in their shortest exact form (issue 24).
TEST(OutputFile, ManifestListsEveryFileAndShortNumbers) {
  const fs::path d = freshDir("every");
  fs::create_directories(d / "pics");
  {
    OutputSet set((d / "r").string());
    std::ofstream(set.temporaryFor(".csv")) << "a\n";
    std::ofstream(set.temporaryPath((d / "pics/f.svg").string())) << "<svg/>";
    const std::string adopted = temporaryName((d / "m").string()) + ".txt";  // (a .sbd is checked as MAT v5)
    std::ofstream(adopted) << "sbd";
    set.adopt(adopted, (d / "m.txt").string());
    set.setting("end time", 0.7);
    set.setting("tolerance", 1e-3);
    const auto renamed = set.renameFiles();
    EXPECT_EQ(renamed.size(), 3u);
    fs::create_directories(d / "r_vtu");
    std::ofstream(d / "r.pvd") << "pvd";
    set.record((d / "r.pvd").string());
    set.record((d / "r_vtu").string());
    set.writeManifest("complete");
  }
  const std::string m = slurp(d / "r_run.txt");
  for (const char* f : {"file: r.csv", "file: pics/f.svg", "file: m.txt", "file: r.pvd", "file: r_vtu/"})
    EXPECT_NE(m.find(f), std::string::npos) << f << "\n" << m;
  EXPECT_NE(m.find("end time: 0.7\n"), std::string::npos) << m;
  EXPECT_NE(m.find("tolerance: 0.001\n"), std::string::npos) << m;
  EXPECT_EQ(slurp(d / "m.txt"), "sbd");
  EXPECT_EQ(slurp(d / "pics/f.svg"), "<svg/>");
  for (const auto& e : fs::recursive_directory_iterator(d))
    EXPECT_EQ(e.path().string().find(".part-"), std::string::npos) << e.path();
  fs::remove_all(d);
}

TEST(OutputFile, TruncatedMatFileIsDetected) {
  const fs::path d = freshDir("mat");
  // A v5 header and one miMATRIX element announcing 64 bytes of which only 16 are there.
  std::string bytes(128, ' ');
  bytes[124] = 0, bytes[125] = 1, bytes[126] = 'I', bytes[127] = 'M';
  const unsigned tag[2] = {14, 64};
  bytes.append(reinterpret_cast<const char*>(tag), 8);
  bytes.append(16, '\0');
  std::ofstream(d / "t.mat", std::ios::binary) << bytes;
  EXPECT_THROW(checkMatFileComplete((d / "t.mat").string()), std::runtime_error);
  bytes.append(48, '\0');
  std::ofstream(d / "t.mat", std::ios::binary) << bytes;
  EXPECT_NO_THROW(checkMatFileComplete((d / "t.mat").string()));
  fs::remove_all(d);
}

TEST(OutputFile, WriteThroughMemoryCopiesWhatTheWriterWrote) {
  const fs::path d = freshDir("memory");
  writeThroughMemory((d / "m.bin").string(), [](const std::string& p) { std::ofstream(p) << "payload"; });
  EXPECT_EQ(slurp(d / "m.bin"), "payload");
  EXPECT_THROW(writeThroughMemory("/nonexistent/m.bin", [](const std::string& p) { std::ofstream(p) << "x"; }),
               std::runtime_error);
  fs::remove_all(d);
}
