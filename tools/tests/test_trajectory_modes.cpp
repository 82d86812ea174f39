// Modes 3 and 4 (linearisation along a trajectory, paper Eq. 15 and Fig. 7b): the dynamic
// stiffening N and velocity sensitivity C against the classical rotating cantilever, and the
// matrices written by `flexmb --mode 3` against a direct evaluation.
#include <gtest/gtest.h>
#include <matio.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <string>

#include "core/Linearization.hpp"
#include "io/DatReader.hpp"
#include "solvers/QuadraticEigen.hpp"
#include "tools/analysis/Simulation.hpp"
#include "tools/analysis/Statics.hpp"
#include "tools/analysis/TrajectoryModes.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

namespace {

// Cantilever of n PLBEAMs (inextensible, bending DYNE) clamped to a hub that turns at the
// prescribed rate W about the beam's root (input hinge), hub radius 0.
std::string spinningBeam(int n, double L, double EI, double rhoA, double W, const std::string& extra = "") {
  std::ostringstream s;
  s.precision(17);
  s << "PLHINGE 100  200 201\n";
  for (int k = 1; k <= n; ++k) s << "PLBEAM " << k << "  " << k << " " << 200 + k << "  " << k + 1 << " " << 201 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << L * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 200\nINPUTE 100 1\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 2 3\n";
  s << "END\nHALT\n";
  s << "INPUTET 100 1 \"" << W << "*t\" \"" << W << "\" \"0\"\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " " << rhoA << "\nESTIFF " << k << " 0 " << EI << "\n";
  s << extra << "END\nEND\n";
  return s.str();
}

}  // namespace

// A cantilever spinning in its own plane about its root: the first in-plane bending frequency in
// the rotating frame follows omega^2 = omega0^2 + (K1 - 1) W^2 with Southwell's coefficient
// K1 = 1.193 for small W: the centrifugal tension stiffens (+K1 W^2, in G through the inertia
// loads) and the spin softens (-W^2, in N). Without C and N (the frozen spectrum) the softening
// is missing. Checked as the slope of omega^2 against W^2 at small W.
TEST(TrajectoryModes, SpinningCantileverFollowsSouthwell) {
  const int n = 12;
  const double L = 1.0, EI = 2.0, rhoA = 3.0;
  const double w0exact = 1.875104068711961 * 1.875104068711961 * std::sqrt(EI / (rhoA * L * L * L * L));
  auto lowest = [&](double W, double& frozen, double& zeta) {
    const core::Model m = io::readDatString(spinningBeam(n, L, EI, rhoA, W), "spinning.dat");
    core::Linearization lin(m);
    core::LinearizedSystem sys;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(lin.size());
    lin.inMotion(0.3, zero, zero, zero, sys);  // the straight beam in steady rotation solves Eq. 13
    EXPECT_LT(sys.Q.norm(), 1e-9 * (1 + sys.K.norm())) << "steady rotation is an exact motion";
    const auto q = solvers::quadraticModes(sys.M, sys.C + sys.D, sys.K + sys.N + sys.G, 1);
    EXPECT_TRUE(q.ok) << q.message;
    frozen = analysis::naturalFrequencies(sys, 1).omega[0];
    zeta = q.damping[0];
    return q.omega[0];
  };
  double f0, z0;
  const double w0 = lowest(0.0, f0, z0);
  EXPECT_NEAR(w0, w0exact, 1e-4 * w0exact);
  const double W = 0.1 * w0;
  double frozen, zeta;
  const double w = lowest(W, frozen, zeta);
  const double slope = (w * w - w0 * w0) / (W * W), slopeFrozen = (frozen * frozen - w0 * w0) / (W * W);
  std::printf("  spinning cantilever, W = 0.1 omega0: d(omega^2)/d(W^2) = %.4f with C and N (Southwell K1 - 1 = 0.193), "
              "%.4f frozen (K1 = 1.193); zeta %.1e\n", slope, slopeFrozen, zeta);
  EXPECT_NEAR(slope, 0.1932, 0.005);
  EXPECT_NEAR(slopeFrozen, 1.1932, 0.005);
  EXPECT_NEAR(zeta, 0.0, 1e-9) << "no damping: the gyroscopic terms do not dissipate";
}

// `flexmb --mode 3` writes M0 ... N0 per output time; they equal a direct linearisation of the
// same simulated states.
TEST(TrajectoryModes, ModeThreeWritesTheLinearisedMatrices) {
  const fs::path dir = fs::temp_directory_path() / ("flexmb_mode3_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string text = spinningBeam(4, 1.0, 2.0, 3.0, 1.5, "XF 5 0 0.3\nEDAMP 1 0 0.01\nTIMESTEP 0.2 4\n");
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
      const Eigen::MatrixXd& ref = name[0] == 'M' ? s.M : name[0] == 'K' ? s.K : name[0] == 'G' ? s.G
                                 : name[0] == 'C' ? s.C : name[0] == 'D' ? s.D : s.N;
      const Eigen::Map<const Eigen::MatrixXd> got(d + k * mdof * mdof, mdof, mdof);
      EXPECT_LE((got - ref).norm(), 1e-12 * std::max(1.0, ref.norm())) << name << " at t = " << tm.time[k];
      if (k > 0 && (name[0] == 'C' || name[0] == 'N')) EXPECT_GT(ref.norm(), 0.0) << name << " exercised";
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
