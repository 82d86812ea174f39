// A spatial frame against CalculiX (issue 11, acceptance "Frequencies"): a 3-D parallel guidance of
// four vertical wires (2 x 3 mm, 0.1 m) clamped at the base and carrying a stiff rectangular
// platform frame (20 x 20 mm beams, 0.16 x 0.12 m) at the top. The test writes the same structure
// as a flexmb .dat and as a CalculiX input (B32R beams, *BEAM SECTION RECT with its 1-direction,
// *DENSITY), runs `ccx`, and compares the lowest six eigenfrequencies and the static displacement
// of two platform corners under a corner force that bends the wires and twists the platform.
//
// CalculiX expands each B32R into C3D20R solids joined by rigid "knots"; its frequencies converge
// only at first order in the element length (measured: 8, 16, 32, 64, 128 elements per member
// halve the difference each time), so its reference is Richardson's extrapolation 2 f(128) - f(64).
// flexmb's BEAM (Timoshenko, Cowper shear factor) is converged at 8 elements per member.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/Statics.hpp"
#include "analysis/tests/Objectivity.hpp"
#include "analysis/tests/Sections.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;
using Vec3 = Eigen::Vector3d;

namespace {

constexpr double kE = 210e9, kNu = 0.3, kG = kE / (2 * (1 + kNu)), kRho = 7800.0;
constexpr double kA = 0.08, kB = 0.06, kL = 0.1;  // platform half-sizes, wire length
const Vec3 kLoad(0.5, 1.0, 0.0);                  // N, on the corner (a, b, L)

using flexmb::test::torsionConstant;

struct Section {
  double w, t;  // w along the local y axis (CalculiX: the 1-direction), t along local z
};

struct Frame {
  std::vector<Vec3> nodes;
  struct Beam {
    int p, q;
    Vec3 y;
    int section;  // 0 wire, 1 platform
  };
  std::vector<Beam> beams;
  std::vector<int> clamped;
  int loaded = -1, opposite = -1;
  std::vector<int> released;  // one beam per closed loop (SPACAR: RLSE closes the loop)
  std::array<Section, 2> sections{Section{0.002, 0.003}, Section{0.020, 0.020}};

  int node(const Vec3& p) {
    for (size_t i = 0; i < nodes.size(); ++i)
      if ((nodes[i] - p).norm() < 1e-12) return static_cast<int>(i);
    nodes.push_back(p);
    return static_cast<int>(nodes.size()) - 1;
  }

  explicit Frame(int n) {
    const Vec3 c[4] = {{kA, kB, 0}, {-kA, kB, 0}, {-kA, -kB, 0}, {kA, -kB, 0}};
    const Vec3 up(0, 0, kL);
    auto member = [&](const Vec3& p, const Vec3& q, const Vec3& y, int s) {
      std::vector<int> id;
      for (int k = 0; k <= n; ++k) id.push_back(node(p + (q - p) * (double(k) / n)));
      for (int k = 0; k < n; ++k) beams.push_back({id[k], id[k + 1], y, s});
    };
    for (const Vec3& p : c) member(p, p + up, Vec3::UnitX(), 0);
    for (int i = 0; i < 4; ++i) member(c[i] + up, c[(i + 1) % 4] + up, Vec3::UnitZ(), 1);
    for (const Vec3& p : c) clamped.push_back(node(p));
    loaded = node(c[0] + up);
    opposite = node(c[2] + up);
    // Four independent loops: wires 2..4 through the ground, and the platform ring.
    released = {2 * n - 1, 3 * n - 1, 4 * n - 1, 8 * n - 1};
  }

  std::string flexmbDat(bool load) const {
    std::ostringstream s;
    s.precision(17);
    s << "# 3-D parallel guidance: four wires carrying a stiff platform frame (test_spatial_calculix)\n";
    for (size_t i = 0; i < nodes.size(); ++i)
      s << "X " << 2 * i + 1 << " " << nodes[i][0] << " " << nodes[i][1] << " " << nodes[i][2] << "\n";
    for (size_t e = 0; e < beams.size(); ++e) {
      const Beam& b = beams[e];
      s << "BEAM " << e + 1 << " " << 2 * b.p + 1 << " " << 2 * b.p + 2 << " " << 2 * b.q + 1 << " " << 2 * b.q + 2
        << " " << b.y[0] << " " << b.y[1] << " " << b.y[2] << "\n";
    }
    for (size_t e = 0; e < beams.size(); ++e) {
      const bool rl = std::find(released.begin(), released.end(), int(e)) != released.end();
      s << (rl ? "RLSE " : "DYNE ") << e + 1 << " 1 2 3 4 5 6\n";
    }
    for (int i : clamped) s << "FIX " << 2 * i + 1 << "\nFIX " << 2 * i + 2 << "\n";
    s << "END\nHALT\n";
    const double k = 10 * (1 + kNu) / (12 + 11 * kNu);  // Cowper, rectangle
    for (size_t e = 0; e < beams.size(); ++e) {
      const Section& c = sections[beams[e].section];
      const double A = c.w * c.t, Iy = c.w * c.t * c.t * c.t / 12, Iz = c.t * c.w * c.w * c.w / 12;
      s << "ESTIFF " << e + 1 << " " << kE * A << " " << kG * torsionConstant(c.w, c.t) << " " << kE * Iy << " "
        << kE * Iz << " " << kE * Iy / (k * kG * A) << " " << kE * Iz / (k * kG * A) << "\n";
      s << "EM " << e + 1 << " " << kRho * A << " " << kRho * (Iy + Iz) << " " << kRho * Iy << " " << kRho * Iz
        << " 0\n";
    }
    if (load) s << "XF " << 2 * loaded + 1 << " " << kLoad[0] << " " << kLoad[1] << " " << kLoad[2] << "\n";
    s << "ITERSTEP 20 1\nEND\nEND\n";
    return s.str();
  }

  std::string calculixInput() const {
    std::ostringstream s;
    s.precision(17);
    const int nn = static_cast<int>(nodes.size());
    s << "** 3-D parallel guidance (flexmb test_spatial_calculix)\n*NODE,NSET=NALL\n";
    for (int i = 0; i < nn; ++i) s << i + 1 << "," << nodes[i][0] << "," << nodes[i][1] << "," << nodes[i][2] << "\n";
    for (size_t e = 0; e < beams.size(); ++e) {  // B32R mid-side nodes
      const Vec3 m = 0.5 * (nodes[beams[e].p] + nodes[beams[e].q]);
      s << nn + e + 1 << "," << m[0] << "," << m[1] << "," << m[2] << "\n";
    }
    for (int sec = 0; sec < 2; ++sec) {
      s << "*ELEMENT,TYPE=B32R,ELSET=S" << sec << "\n";
      for (size_t e = 0; e < beams.size(); ++e)
        if (beams[e].section == sec)
          s << e + 1 << "," << beams[e].p + 1 << "," << nn + e + 1 << "," << beams[e].q + 1 << "\n";
    }
    s << "*MATERIAL,NAME=STEEL\n*ELASTIC\n" << kE << "," << kNu << "\n*DENSITY\n" << kRho << "\n";
    for (int sec = 0; sec < 2; ++sec) {
      // RECT: thickness along the 1-direction, then along the 2-direction; the third line is the
      // 1-direction, which we set to the .dat file's y vector (w lies along it).
      const Vec3 y = sec == 0 ? Vec3::UnitX() : Vec3::UnitZ();
      s << "*BEAM SECTION,ELSET=S" << sec << ",MATERIAL=STEEL,SECTION=RECT\n"
        << sections[sec].w << "," << sections[sec].t << "\n"
        << y[0] << "," << y[1] << "," << y[2] << "\n";
    }
    s << "*BOUNDARY\n";
    for (int i : clamped) s << i + 1 << ",1,6\n";
    s << "*NSET,NSET=NOUT\n" << loaded + 1 << "," << opposite + 1 << "\n";
    s << "*STEP\n*FREQUENCY\n6\n*END STEP\n";
    s << "*STEP\n*STATIC\n*CLOAD\n"
      << loaded + 1 << ",1," << kLoad[0] << "\n"
      << loaded + 1 << ",2," << kLoad[1] << "\n"
      << "*NODE PRINT,NSET=NOUT\nU\n*END STEP\n";
    return s.str();
  }
};

struct CalculixResult {
  std::vector<double> hz;
  std::map<int, Vec3> u;  // node (1-based) -> displacement
};

// Parses ccx's .dat: the eigenvalue table (mode, eigenvalue, rad/time, cycles/time, imaginary)
// and the "displacements (vx,vy,vz)" block.
CalculixResult runCalculix(const Frame& f, const std::filesystem::path& dir, const std::string& job) {
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / (job + ".inp")) << f.calculixInput(); }
  const std::string cmd = "cd '" + dir.string() + "' && ccx -i " + job + " > " + job + ".log 2>&1";
  const int rc = std::system(cmd.c_str());
  CalculixResult r;
  if (rc != 0) return r;
  std::ifstream in(dir / (job + ".dat"));
  std::string line;
  enum { None, Eigen, Disp } mode = None;
  while (std::getline(in, line)) {
    if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) {
      mode = Eigen;
      continue;
    }
    if (line.find("displacements (vx,vy,vz)") != std::string::npos) {
      mode = Disp;
      continue;
    }
    if (line.find("P A R T I C I P A T I O N") != std::string::npos) mode = None;
    std::istringstream ls(line);
    if (mode == Eigen) {
      int k;
      double ev, rad, cyc, im;
      if (ls >> k >> ev >> rad >> cyc >> im) r.hz.push_back(cyc);
    } else if (mode == Disp) {
      int k;
      double ux, uy, uz;
      if (ls >> k >> ux >> uy >> uz) r.u[k] = Vec3(ux, uy, uz);
    }
  }
  return r;
}

bool haveCalculix() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

}  // namespace

TEST(SpatialCalculix, ParallelGuidanceFrequenciesAndStaticDeflection) {
  ASSERT_TRUE(haveCalculix()) << "CalculiX (ccx, Debian package calculix-ccx) is not on PATH: run tools/setup.sh. "
                                 "This comparison must not be skipped.";
  // flexmb, 8 BEAMs per member.
  const Frame fine(8);
  const core::Model free = io::readDatString(fine.flexmbDat(false), "guidance.dat");
  const auto modes = analysis::staticAnalysis(free, 6);
  ASSERT_TRUE(modes.completed) << modes.stopReason;
  const Eigen::VectorXd w = modes.steps.back().frequencies.omega;
  ASSERT_GE(w.size(), 6);
  const core::Model loaded = io::readDatString(fine.flexmbDat(true), "guidance_loaded.dat");
  const auto stat = analysis::staticAnalysis(loaded, 0);
  ASSERT_TRUE(stat.completed) << stat.stopReason;
  auto displacement = [&](int node) {
    const Vec3 x = stat.steps.back().x.segment<3>(loaded.nodes[loaded.nodeByLabel.at(2 * node + 1)].firstCoord);
    return Vec3(x - fine.nodes[node]);
  };
  const Vec3 uLoaded = displacement(fine.loaded), uOpposite = displacement(fine.opposite);

  // CalculiX at 64 and 128 B32R per member, extrapolated (first-order convergence).
  const std::filesystem::path dir = std::filesystem::path(FLEXMB_BINARY_DIR) / "calculix_guidance";
  const Frame c64(64), c128(128);
  const CalculixResult r64 = runCalculix(c64, dir, "guidance64"), r128 = runCalculix(c128, dir, "guidance128");
  ASSERT_GE(r64.hz.size(), 6u) << "ccx failed or wrote no eigenvalues: see " << (dir / "guidance64.log");
  ASSERT_GE(r128.hz.size(), 6u) << "ccx failed or wrote no eigenvalues: see " << (dir / "guidance128.log");
  ASSERT_EQ(r64.u.size(), 2u) << "ccx wrote no displacements: see " << (dir / "guidance64.log");
  ASSERT_EQ(r128.u.size(), 2u) << "ccx wrote no displacements: see " << (dir / "guidance128.log");

  std::printf("mode  flexmb [Hz]  ccx 64 [Hz]  ccx 128 [Hz]  ccx extrap. [Hz]  flexmb - extrap.\n");
  for (int i = 0; i < 6; ++i) {
    const double f = w[i] / (2 * std::numbers::pi), ref = 2 * r128.hz[i] - r64.hz[i];
    const double d = f / ref - 1;
    std::printf("%4d  %11.4f  %11.4f  %12.4f  %16.4f  %+.3f%% (vs 128: %+.3f%%)\n", i + 1, f, r64.hz[i], r128.hz[i],
                ref, 100 * d, 100 * (f / r128.hz[i] - 1));
    EXPECT_LT(std::abs(d), 1e-2) << "mode " << i + 1;
  }
  struct Corner {
    const char* name;
    Vec3 fx;
    int n64, n128;
  };
  for (const Corner& c : {Corner{"loaded corner", uLoaded, c64.loaded + 1, c128.loaded + 1},
                          Corner{"opposite corner", uOpposite, c64.opposite + 1, c128.opposite + 1}}) {
    const Vec3 ref = 2 * r128.u.at(c.n128) - r64.u.at(c.n64);
    std::printf("%-15s u [m]: flexmb (%.5e, %.5e, %.3e), ccx 128 (%.5e, %.5e, %.3e), ccx extrap. (%.5e, %.5e, %.3e)\n",
                c.name, c.fx[0], c.fx[1], c.fx[2], r128.u.at(c.n128)[0], r128.u.at(c.n128)[1], r128.u.at(c.n128)[2],
                ref[0], ref[1], ref[2]);
    // Horizontal components (wire bending and platform twist); the vertical ones are 1e-3 of
    // them (axial strain and second-order shortening in flexmb's geometrically exact statics).
    const double d = (c.fx.head<2>() - ref.head<2>()).norm() / ref.head<2>().norm();
    std::printf("                 horizontal difference %.3f%%\n", 100 * d);
    EXPECT_LT(d, 1e-2) << c.name;
  }
}

TEST(SpatialCalculix, GuidanceTurnsWithTheModel) {
  // Objectivity (issue 22): the guidance of the comparison above, turned by a random rotation, has
  // the same frequencies and the turned mode shapes, and the turned static deflection.
  const Eigen::Matrix3d R = objectivity::randomRotation(13);
  const Frame frame(4);
  const std::string freeDat = frame.flexmbDat(false), loadedDat = frame.flexmbDat(true);
  const core::Model a = io::readDatString(freeDat, "a.dat");
  const core::Model b = io::readDatString(objectivity::rotatedDat(freeDat, R), "b.dat");
  const auto ra = analysis::staticAnalysis(a, 6), rb = analysis::staticAnalysis(b, 6);
  ASSERT_TRUE(ra.completed && rb.completed);
  const auto &fa = ra.steps.back().frequencies, &fb = rb.steps.back().frequencies;
  ASSERT_EQ(fa.omega.size(), 6);
  ASSERT_EQ(fb.omega.size(), 6);
  const double df = ((fa.omega - fb.omega).cwiseQuotient(fa.omega)).cwiseAbs().maxCoeff();
  const double dm = objectivity::modeDifference(a, ra.steps.back().x, fa.nodalModes, fa.omega, b, rb.steps.back().x,
                                                fb.nodalModes, fb.omega, R);
  const core::Model la = io::readDatString(loadedDat, "la.dat");
  const core::Model lb = io::readDatString(objectivity::rotatedDat(loadedDat, R), "lb.dat");
  const auto sa = analysis::staticAnalysis(la, 0), sb = analysis::staticAnalysis(lb, 0);
  ASSERT_TRUE(sa.completed && sb.completed);
  // Relative to the corner's deflection (about 1e-4 m), not to the frame's size.
  const double u = (sa.steps.back().x - la.x0).lpNorm<Eigen::Infinity>();
  const double ds = objectivity::configurationDifference(la, sa.steps.back().x, lb, sb.steps.back().x, R, u);
  std::printf(
      "guidance turned by a random rotation: 6 frequencies differ by %.1e (relative), modes by %.1e, the static "
      "deflection by %.1e of itself\n",
      df, dm, ds);
  EXPECT_LT(df, 1e-9);
  EXPECT_LT(dm, 1e-7);
  EXPECT_LT(ds, 1e-7);
}
