// End-to-end runs of the command line on models whose analyses are tested in analysis/tests: the
// files a run writes against the in-process analysis of the same model.
#include <gtest/gtest.h>
#include <matio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

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

namespace {
// A command's exit status and its stdout and stderr together.
std::pair<int, std::string> runFlexmb(const std::filesystem::path& dir, const std::string& args) {
  const std::string log = (dir / "log.txt").string();
  const int rc = std::system(
      ("cd '" + dir.string() + "' && " + std::string(FLEXMB_BINARY_DIR) + "/flexmb " + args + " > '" + log + "' 2>&1")
          .c_str());
  std::ifstream in(log);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1,
          std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>())};
}
const std::string kStage = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/parallel_leaf_stage.dat";
// An empty folder of that name in the build folder.
std::filesystem::path freshDir(const char* name) {
  const std::filesystem::path dir = std::filesystem::path(FLEXMB_BINARY_DIR) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}
}  // namespace

// Issue 51: `check` counted 43 elements where `show` says 22: it counted the 21 normalisation
// constraints flexmb adds (one per orientation node not fixed). Both count the file's elements; check
// says the others apart.
TEST(CliModels, CheckAndShowCountTheFilesElements) {
  const std::filesystem::path dir = freshDir("stage_count");
  auto [rc, text] = runFlexmb(dir, "check '" + kStage + "'");
  ASSERT_EQ(rc, 0) << text;
  EXPECT_NE(text.find("; elements: 22 (and 21 normalisation constraints of the Euler parameters that flexmb adds)\n"),
            std::string::npos)
      << text;
  std::tie(rc, text) = runFlexmb(dir, "show '" + kStage + "' -q --out stage.svg");
  ASSERT_EQ(rc, 0) << text;
  std::ifstream svg(dir / "stage.svg");
  const std::string picture((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_NE(picture.find("23 position and 23 orientation nodes, 22 elements;"), std::string::npos);
  // A planar model has none to say.
  std::tie(rc, text) = runFlexmb(dir, "check '" + std::string(FLEXMB_SOURCE_DIR) + "/datfiles/cantilever.dat'");
  ASSERT_EQ(rc, 0) << text;
  EXPECT_NE(text.find("; elements: 4\n"), std::string::npos) << text;
  std::filesystem::remove_all(dir);
}

// Issue 51: `static` wrote neither section forces nor the applied loads. Its CSV keeps its columns
// and adds, per load step, the largest section force of each kind (over the elements that deform)
// and the nodal loads applied; the screen gives the last step's, with the element of each largest.
TEST(CliModels, StaticWritesTheLargestSectionForcesAndTheLoads) {
  const std::filesystem::path dir = freshDir("stage_static");
  const auto [rc, text] = runFlexmb(dir, "static '" + kStage + "' --format csv --out stage.csv");
  ASSERT_EQ(rc, 0) << text;
  std::ifstream in(dir / "stage.csv");
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    rows.emplace_back();
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) rows.back().push_back(c);
  }
  ASSERT_EQ(rows.size(), 7u) << "header and load steps 0..5";
  const std::vector<std::string>& h = rows[0];
  const core::Model model = io::readDatFile(kStage);
  // The columns as before (load_step, initial_factor, load_factor, the coordinates, f1..f6), then the
  // section forces and loads, the largest stress and its element, the reactions of the two clamps.
  const size_t base = 3u + static_cast<size_t>(model.nx) + 6u;
  ASSERT_EQ(h.size(), base + 5u + 2u + 12u);
  EXPECT_EQ(h[3], "node1.x");
  EXPECT_EQ(h[3 + model.nx + 5], "f6_Hz");
  const std::vector<std::string> added(h.begin() + static_cast<long>(base), h.begin() + static_cast<long>(base) + 5);
  EXPECT_EQ(added, (std::vector<std::string>{"max_axial_force", "max_bending_moment_y", "max_bending_moment_z",
                                             "max_torsion_moment", "F.node45.x"}));
  EXPECT_EQ(h[base + 5], "max_stress");
  EXPECT_EQ(h[base + 7], "R.F.node1.x");
  EXPECT_EQ(h[base + 13], "R.F.node23.x");
  const size_t moment = base + 1, load = base + 4, stress = base + 5;
  // The reactions balance the 1 N along x; a leaf's stress is 3 E t d / L^2 (d the stage's travel).
  const size_t x45 = static_cast<size_t>(std::find(h.begin(), h.end(), "node45.x") - h.begin());
  const double d = std::stod(rows[6][x45]) - std::stod(rows[1][x45]);
  EXPECT_NEAR(std::stod(rows[6][base + 7]) + std::stod(rows[6][base + 13]), -1.0, 1e-9);
  EXPECT_NEAR(std::stod(rows[6][stress]) / (3 * 210e9 * 0.2e-3 * d / (0.05 * 0.05)), 1.0, 0.01) << rows[6][stress];
  for (size_t r = 1; r < rows.size(); ++r) EXPECT_NEAR(std::stod(rows[r][load]), (r - 1) / 5.0, 1e-12);
  // A guided leaf carries half the load with a moment F/2 L/2 at its ends (0.0125 N m under 1 N).
  EXPECT_NEAR(std::stod(rows[6][moment]) / 0.0125, 1.0, 0.05) << rows[6][moment];
  EXPECT_LT(std::stod(rows[1][moment]), 1e-9);  // load step 0: gravity alone bends no leaf
  EXPECT_NE(text.find("largest section forces at the last load step (over the elements that deform):\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  max_bending_moment_y = 0.0128"), std::string::npos) << text;
  EXPECT_NE(text.find(" N m (BEAM "), std::string::npos) << text;
  EXPECT_NE(text.find("nodal loads applied at the last load step (gravity apart):\n  F.node45.x = 1\n"),
            std::string::npos)
      << text;
  std::filesystem::remove_all(dir);
}
