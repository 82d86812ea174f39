// End-to-end runs of the command line on models whose analyses are tested in analysis/tests: the
// files a run writes against the in-process analysis of the same model.
#include <gtest/gtest.h>
#include <matio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "analysis/Simulation.hpp"
#include "analysis/TrajectoryModes.hpp"
#include "core/tests/ModelTexts.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

// `flexmb --mode 3` writes M0 ... N0 per output time; they equal a direct linearisation of the
// same simulated states.
TEST(TrajectoryModes, ModeThreeWritesTheLinearisedMatrices) {
  const fs::path dir = fs::temp_directory_path() / ("flexmb_mode3_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string text = test::spinningBeam(4, 1.0, 2.0, 3.0, 1.5, "XF 5 0 0.3\nEDAMP 1 0 0.01\nTIMESTEP 0.2 4\n");
  const fs::path file = dir / "spin.dat";
  std::ofstream(file) << text;
  const std::string cmd = std::string(FLEXMB_BINARY_DIR) + "/flexmb --mode 3 " + file.string() + " --out " +
                          (dir / "spin").string() + " --format none -q > " + (dir / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(dir / "log.txt").rdbuf();
  ASSERT_TRUE(fs::exists(dir / "spin_linear.mat"));
  ASSERT_TRUE(fs::exists(dir / "spin_frequencies.csv"));

  const core::Model m = io::readDatString(text, "spin.dat");
  const core::Trajectory tr = analysis::simulate(m, {});
  ASSERT_TRUE(tr.completed);
  const auto tm = analysis::trajectoryModes(m, tr, 6, std::nullopt, true);
  ASSERT_EQ(tm.time.size(), 5u);

  mat_t* mat = Mat_Open((dir / "spin_linear.mat").c_str(), MAT_ACC_RDONLY);
  ASSERT_NE(mat, nullptr);
  const int mdof = m.numDofs();
  for (const char* name : {"M0", "K0", "G0", "C0", "D0", "N0"}) {
    matvar_t* v = Mat_VarRead(mat, name);
    ASSERT_NE(v, nullptr) << name;
    ASSERT_EQ(v->rank, 3) << name;
    EXPECT_EQ(v->dims[0], static_cast<size_t>(mdof));
    EXPECT_EQ(v->dims[1], static_cast<size_t>(mdof));
    ASSERT_EQ(v->dims[2], tm.time.size());
    const double* d = static_cast<const double*>(v->data);
    for (size_t k = 0; k < tm.time.size(); ++k) {
      const auto& s = tm.matrices[k];
      const Eigen::MatrixXd& ref = name[0] == 'M'   ? s.M
                                   : name[0] == 'K' ? s.K
                                   : name[0] == 'G' ? s.G
                                   : name[0] == 'C' ? s.C
                                   : name[0] == 'D' ? s.D
                                                    : s.N;
      const Eigen::Map<const Eigen::MatrixXd> got(d + k * mdof * mdof, mdof, mdof);
      EXPECT_LE((got - ref).norm(), 1e-12 * std::max(1.0, ref.norm())) << name << " at t = " << tm.time[k];
      if (k > 0 && (name[0] == 'C' || name[0] == 'N')) {
        EXPECT_GT(ref.norm(), 0.0) << name << " exercised";
      }
    }
    Mat_VarFree(v);
  }
  matvar_t* f = Mat_VarRead(mat, "freq");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->dims[0], tm.time.size());
  EXPECT_NEAR(static_cast<const double*>(f->data)[0], tm.omega[0][0] / (2 * M_PI), 1e-9);
  Mat_VarFree(f);
  Mat_Close(mat);
  fs::remove_all(dir);
}

// SPACAR Light style pivot files with SPACAR Light's own ITERSTEP line go through `check` and
// `static` unchanged (their equilibria: SpatialModels.SpaLightPivotFilesRunUnchangedWithTheirIterstep).
TEST(CliModels, SpaLightPivotFilesPassCheckAndStatic) {
  for (const char* name : {"cross_spring_pivot_coarse.dat", "cross_spring_pivot.dat"}) {
    const std::string path = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/" + name;
    // The command line, on the file as it is.
    const std::filesystem::path dir = std::filesystem::path(FLEXMB_BINARY_DIR) / "spalight_pivot";
    std::filesystem::create_directories(dir);
    const std::string flexmb = std::string(FLEXMB_BINARY_DIR) + "/flexmb";
    const std::string log = (dir / (std::string(name) + ".log")).string();
    ASSERT_EQ(std::system((flexmb + " check '" + path + "' > '" + log + "' 2>&1").c_str()), 0) << "see " << log;
    std::ifstream checkOut(log);
    const std::string checkText((std::istreambuf_iterator<char>(checkOut)), std::istreambuf_iterator<char>());
    EXPECT_NE(checkText.find("kinematics: well posed"), std::string::npos) << checkText;
    ASSERT_EQ(std::system((flexmb + " static '" + path + "' --out '" + (dir / (std::string(name) + ".csv")).string() +
                           "' > '" + log + "' 2>&1")
                              .c_str()),
              0)
        << "see " << log;
  }
}

// static --matrices (issue 38): all (the default, SPACAR's set: M0 .. N0 of every load step in the
// .sbm, dx and bigd in the .sbd, as SPACAR Light reads them) or none (states, stresses and
// frequencies only); bad values and --ltv with none are usage errors.
TEST(CliModels, StaticMatricesAllOrNone) {
  const std::filesystem::path dir = std::filesystem::path(FLEXMB_BINARY_DIR) / "static_matrices";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string flexmb = std::string(FLEXMB_BINARY_DIR) + "/flexmb";
  const std::string model = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_coarse.dat";
  const std::string log = (dir / "log.txt").string();
  auto has = [](const std::filesystem::path& file, const char* name) {
    mat_t* mat = Mat_Open(file.c_str(), MAT_ACC_RDONLY);
    if (!mat) return false;
    matvar_t* v = Mat_VarReadInfo(mat, name);
    const bool found = v != nullptr;
    if (v) Mat_VarFree(v);
    Mat_Close(mat);
    return found;
  };
  for (const std::string which : {"all", "none"}) {
    const std::filesystem::path sub = dir / which;
    std::filesystem::create_directories(sub);
    const std::string cmd = flexmb + " static '" + model + "' -q --matrices " + which + " --out '" + sub.string() +
                            "/' > '" + log + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(log).rdbuf();
    const bool all = which == "all";
    const std::filesystem::path sbd = sub / "cross_spring_pivot_coarse.sbd",
                                sbm = sub / "cross_spring_pivot_coarse.sbm";
    EXPECT_TRUE(has(sbd, "x")) << which;
    EXPECT_TRUE(has(sbd, "sig")) << which;
    EXPECT_EQ(has(sbd, "dx"), all) << which;
    EXPECT_EQ(has(sbd, "bigd"), all) << which;
    for (const char* m : {"M0", "K0", "G0", "N0"}) EXPECT_EQ(has(sbm, m), all) << which << " " << m;
    EXPECT_TRUE(has(sbm, "freq")) << which;
  }
  for (const std::string bad : {" --matrices some", " --ltv --matrices none"}) {
    const std::string cmd =
        flexmb + " static '" + model + "' -q --out '" + dir.string() + "/'" + bad + " > '" + log + "' 2>&1";
    const int rc = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(rc), 2) << bad;
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("--matrices"), std::string::npos) << text;
  }
  std::filesystem::remove_all(dir);
}

// A dead end torque on a cantilever of equal bending stiffnesses flutters at any torque (Nikolai;
// analysis/tests/test_dead_moment_stability.cpp): the static screen output names the verdict, the
// eigenvalue and the criterion, and says which matrices the printed frequencies come from.
TEST(CliModels, StaticFlagUnderADeadMomentNamesTheKineticVerdict) {
  const std::filesystem::path dir = std::filesystem::path(FLEXMB_BINARY_DIR) / "static_dead_moment";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ostringstream dat;
  const int n = 4;
  for (int i = 1; i <= n + 1; ++i) dat << "X " << 2 * i - 1 << " " << (i - 1.0) / n << " 0 0\n";
  for (int e = 1; e <= n; ++e)
    dat << "BEAM " << e << " " << 2 * e - 1 << " " << 2 * e << " " << 2 * e + 1 << " " << 2 * e + 2 << " 0 1 0\n";
  for (int e = 1; e <= n; ++e) dat << "DYNE " << e << " 1 2 3 4 5 6\n";
  dat << "FIX 1\nFIX 2\nEND\nHALT\n";
  for (int e = 1; e <= n; ++e) dat << "ESTIFF " << e << " 1e7 10 1 1 0 0\nEM " << e << " 1 1e-3 1e-3 1e-3 0\n";
  dat << "DELXF " << 2 * (n + 1) << " 1 0 0\nITERSTEP 50 2\nEND\nEND\n";
  const std::filesystem::path file = dir / "torque.dat";
  std::ofstream(file) << dat.str();
  const std::string log = (dir / "log.txt").string();
  const std::string cmd = std::string(FLEXMB_BINARY_DIR) + "/flexmb static '" + file.string() + "' --out '" +
                          dir.string() + "/' > '" + log + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(log).rdbuf();
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("(UNSTABLE equilibrium: flutter (lambda = "), std::string::npos) << text;
  EXPECT_NE(text.find("under the dead moments)"), std::string::npos) << text;
  EXPECT_NE(text.find("the frequencies above are those of K0 + G0 alone"), std::string::npos) << text;
  const std::size_t step0 = text.find("load step 0 of 2");
  ASSERT_NE(step0, std::string::npos) << text;
  const std::string line0 = text.substr(step0, text.find('\n', step0) - step0);
  EXPECT_EQ(line0.find("UNSTABLE"), std::string::npos) << "no moment at load step 0, no flag: " << line0;
  std::filesystem::remove_all(dir);
}
