// Validation (b) of BEAMW (core/elements/BEAMW.md section 5.2): SPACAR Light's cross-spring pivot
// (spacarexample.m: two crossed steel leaves 50 x 0.2 mm, 3 beams per leaf, a rigid body and 0.1 kg
// on top), modelled as SPACAR Light 1.38 writes it, with BEAMW and with BEAM, against CalculiX.
// The first torsion mode of the leaves (the 4th, a degenerate pair with the 5th) is where warping
// matters: each leaf is clamped at both ends (base and rigid body), so its cross-sections cannot
// warp there, and restrained warping stiffens a 50 mm wide strip of 141 mm by a fifth.
//
// The CalculiX reference is computed here: the deck is generated, `ccx` is run and its eigenvalue
// table parsed (as test_spatial_calculix.cpp does). The leaves are meshed with C3D20R solids (24 x 8
// per leaf, one layer through the 0.2 mm thickness; 48 x 16 and 96 x 32 change mode 4 by 0.05% and
// 0.005%), not with beams or shells: CalculiX expands B32 beams into bricks joined by knots that
// restrain the section's warping at every clamp and joint, so a beam reference would contain the
// effect it is meant to measure by construction; S8R shells expanded into bricks, tied to a
// *RIGID BODY by their edge nodes, were hinged there (the rigid body ties only the translations of
// the expanded nodes: bending modes 31% low). Solids restrain warping at the clamps exactly as a
// clamp does (all displacements of the end faces held). Material: SPACAR Light's E = 210 GPa and
// G = 70 GPa (not an isotropic pair), as engineering constants with nu = 0 along the leaf axes, the
// beam-theory-consistent reference (no anticlastic plate stiffening; EIy and E Cw as the beams have
// them). The body: a rigid 100 x 10 x 50 mm block of density 3000 (the inertia SPACAR Light's
// rigid BEAMW carries) and the 0.1 kg point mass, one *RIGID BODY with the top edges of the leaves.
#include <gtest/gtest.h>

#include <Eigen/Dense>
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
#include <tuple>
#include <vector>

#include "analysis/Statics.hpp"
#include "analysis/tests/Sections.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;
using Vec3 = Eigen::Vector3d;

namespace {

constexpr double kE = 210e9, kG = 70e9;
constexpr double kW = 50e-3, kT = 0.2e-3;  // leaf section: width along the y vector (global z), thickness

using flexmb::test::torsionConstant;

// ESTIFF (EA GIt EIy EIz cy cz ECw) and EM (rhoA Jxx Jyy Jzz Jyz Jw) of a w x t rectangle as SPACAR
// Light computes them (shear factor 10 (1 + nu)/(12 + 11 nu) with nu = E/2G - 1, Cw = w^3 t^3/144).
std::array<double, 7> stiffness(double w, double t) {
  const double nu = kE / (2 * kG) - 1, A = w * t, Iy = t * t * t * w / 12, Iz = t * w * w * w / 12;
  const double k = 10 * (1 + nu) / (12 + 11 * nu);
  return {kE * A,
          kG * torsionConstant(w, t),
          kE * Iy,
          kE * Iz,
          kE * Iy / (kG * A * k),
          kE * Iz / (kG * A * k),
          kE * w * w * w * t * t * t / 144};
}
std::array<double, 6> inertia(double rho, double w, double t) {
  const double A = w * t, Iy = t * t * t * w / 12, Iz = t * w * w * w / 12;
  return {rho * A, rho * (Iy + Iz), rho * Iy, rho * Iz, 0.0, rho * w * w * w * t * t * t / 144};
}

std::string fixed(double v) {  // SPACAR Light's %20.15f
  char b[64];
  std::snprintf(b, sizeof b, "%20.15f", v);
  return b;
}

// The pivot as SPACAR Light 1.38 writes it for spacarexample.m without loads: user node i has
// position node 3i-2, orientation 3i-1 and warping node 3i; intermediate nodes from 13 on. Leaf A =
// element 1 (1 -> 3), rigid body = element 2 (2 -> 3), leaf B = element 3 (2 -> 4). The six releases
// that open the loop ground-leaf-body-leaf-ground are all six of leaf B's last beam (SPACAR Light's
// autosolver picks six by an SVD; any valid choice has the same physics, RLSE keeps its stiffness).
std::string slPivot(bool warping) {
  const Vec3 user[4] = {{0, 0, 0}, {0, 0.1, 0}, {0.1, 0.1, 0}, {0.1, 0, 0}};
  std::ostringstream o;
  o << "#Dat-file in the layout of SPACAR Light 1.38 (spacarexample.m without loads); test_beamw_calculix\n";
  char line[256];
  for (int i = 0; i < 4; ++i) {
    std::snprintf(line, sizeof line, "X\t\t%3d\t\t\t%6f\t%6f\t%6f\n", 3 * i + 1, user[i][0], user[i][1], user[i][2]);
    o << line;
  }
  struct Beam {
    std::array<int, 3> p, q;
    bool flexible;
  };
  std::vector<Beam> beams;
  int next = 13;
  for (auto [p, q, nb, flex] : {std::tuple{1, 3, 3, true}, std::tuple{2, 3, 1, false}, std::tuple{2, 4, 3, true}}) {
    std::array<int, 3> prev{3 * p - 2, 3 * p - 1, 3 * p};
    for (int k = 1; k <= nb; ++k) {
      std::array<int, 3> cur{3 * q - 2, 3 * q - 1, 3 * q};
      if (k < nb) {
        const Vec3 X = user[p - 1] + (user[q - 1] - user[p - 1]) * (double(k) / nb);
        std::snprintf(line, sizeof line, "X\t\t%3d\t\t\t%6f\t%6f\t%6f\n", next, X[0], X[1], X[2]);
        o << line;
        cur = {next, next + 1, next + 2};
        next += 3;
      }
      beams.push_back({prev, cur, flex});
      prev = cur;
    }
  }
  for (size_t e = 0; e < beams.size(); ++e) {
    const Beam& b = beams[e];
    if (warping)
      std::snprintf(line, sizeof line, "BEAMW       %4zu%4d%4d%4d%6d%4d%4d    %6f\t%6f\t%6f\n", e + 1, b.p[0], b.p[1],
                    b.p[2], b.q[0], b.q[1], b.q[2], 0.0, 0.0, 1.0);
    else
      std::snprintf(line, sizeof line, "BEAM        %4zu%4d%4d%6d%4d    %6f\t%6f\t%6f\n", e + 1, b.p[0], b.p[1], b.q[0],
                    b.q[1], 0.0, 0.0, 1.0);
    o << line;
  }
  for (size_t e = 0; e < beams.size(); ++e)
    if (beams[e].flexible) o << (e + 1 == beams.size() ? "RLSE\t\t" : "DYNE\t\t") << e + 1 << "\t1 2 3 4 5 6\n";
  o << "FIX\t\t  1\nFIX\t\t  2\nFIX\t\t 10\nFIX\t\t 11\n";
  // Warping of the clamped nodes, and of both ends of the rigid BEAMW (SPACAR Light fixes the
  // clamped nodes' warping nodes for BEAM models too: unused nodes, a note).
  for (int w : warping ? std::vector<int>{3, 6, 9, 12} : std::vector<int>{3, 12}) o << "FIX\t\t" << w << "  #warping\n";
  o << "END\nHALT\n";
  const auto leaf = stiffness(kW, kT);
  const auto leafMass = inertia(7800, kW, kT), bodyMass = inertia(3000, kW, 10e-3);
  const size_t nst = warping ? 7 : 6, nem = warping ? 6 : 5;
  for (size_t e = 0; e < beams.size(); ++e) {
    if (beams[e].flexible) {
      o << "ESTIFF\t\t" << e + 1;
      for (size_t k = 0; k < nst; ++k) o << "\t" << fixed(leaf[k]);
      o << "\n";
    }
    o << "EM\t\t\t" << e + 1;
    for (size_t k = 0; k < nem; ++k) o << "\t" << fixed(beams[e].flexible ? leafMass[k] : bodyMass[k]);
    o << "\n";
  }
  o << "XM\t\t\t  7\t\t0.100000\nITERSTEP\t10\t1\t0.0000005\t1\t1\t0\nEND\nHALT\n";
  return o.str();
}

std::vector<double> flexmbHz(const core::Model& m, int nev) {
  const auto run = analysis::staticAnalysis(m, nev);
  EXPECT_TRUE(run.completed) << m.sourceFile << ": " << run.stopReason;
  std::vector<double> hz;
  const Eigen::VectorXd& w = run.steps.back().frequencies.omega;
  for (Eigen::Index i = 0; i < w.size(); ++i) hz.push_back(w[i] / (2 * std::numbers::pi));
  return hz;
}

// The CalculiX deck: nL x nW C3D20R per leaf, one layer through the thickness; the base end face of
// each leaf held (dofs 1-3 of all its nodes), the top end faces, the block and the point mass one
// rigid body.
std::string calculixPivot(int nL, int nW) {
  std::ostringstream s;
  s.precision(12);
  const double L = std::sqrt(2.0) * 0.1;
  const int ni = 2 * nL + 1, nj = 2 * nW + 1;
  std::map<std::array<int, 4>, int> id;  // (leaf, i, j, level) -> node
  std::vector<int> base, top;
  s << "** SPACAR Light's cross-spring pivot, leaves " << nL << " x " << nW
    << " C3D20R (flexmb test_beamw_calculix)\n*NODE, NSET=NALL\n";
  const Vec3 ez(0, 0, 1);
  const std::array<std::pair<Vec3, Vec3>, 2> leaves = {std::pair{Vec3(0, 0, 0), Vec3(0.1, 0.1, 0)},
                                                       std::pair{Vec3(0, 0.1, 0), Vec3(0.1, 0, 0)}};
  for (int leaf = 0; leaf < 2; ++leaf) {
    const auto& [p, q] = leaves[leaf];
    const Vec3 e = (q - p).normalized(), normal = e.cross(ez);
    const int clampedEnd = leaf == 0 ? 0 : ni - 1;  // leaf A starts at the base, leaf B ends there
    for (int level = -1; level <= 1; ++level)
      for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j) {
          if ((i % 2 && j % 2) || (level == 0 && (i % 2 || j % 2))) continue;  // 20-node serendipity
          const int n = 100000 * (leaf + 1) + 20000 * (level + 1) + i * nj + j + 1;
          const Vec3 x = p + (L * i / (ni - 1)) * e + (-kW / 2 + kW * j / (nj - 1)) * ez + (level * kT / 2) * normal;
          s << n << ", " << x[0] << ", " << x[1] << ", " << x[2] << "\n";
          id[{leaf, i, j, level}] = n;
          if (i == clampedEnd) base.push_back(n);
          if (i == ni - 1 - clampedEnd) top.push_back(n);
        }
  }
  const int bx = 10, by = 2, bz = 5;
  auto bid = [&](int a, int b, int c) { return 500000 + (a * (by + 1) + b) * (bz + 1) + c + 1; };
  std::vector<int> rigid = top;
  for (int a = 0; a <= bx; ++a)
    for (int b = 0; b <= by; ++b)
      for (int c = 0; c <= bz; ++c) {
        s << bid(a, b, c) << ", " << 0.1 * a / bx << ", " << 0.095 + 0.01 * b / by << ", " << -0.025 + 0.05 * c / bz
          << "\n";
        rigid.push_back(bid(a, b, c));
      }
  s << "900001, 0.1, 0.1, 0\n900002, 0.05, 0.1, 0\n900003, 0.05, 0.1, 0\n";
  rigid.push_back(900001);
  int eid = 0;
  for (int leaf = 0; leaf < 2; ++leaf) {
    s << "*ELEMENT, TYPE=C3D20R, ELSET=LEAF" << leaf << "\n";
    for (int a = 0; a < nL; ++a)
      for (int b = 0; b < nW; ++b) {
        const int i = 2 * a, j = 2 * b;
        const std::array<std::array<int, 2>, 4> quad = {{{i, j}, {i + 2, j}, {i + 2, j + 2}, {i, j + 2}}};
        const std::array<std::array<int, 2>, 4> mids = {{{i + 1, j}, {i + 2, j + 1}, {i + 1, j + 2}, {i, j + 1}}};
        std::vector<int> c;
        for (int level : {-1, 1})
          for (const auto& v : quad) c.push_back(id.at({leaf, v[0], v[1], level}));
        for (int level : {-1, 1})
          for (const auto& v : mids) c.push_back(id.at({leaf, v[0], v[1], level}));
        for (const auto& v : quad) c.push_back(id.at({leaf, v[0], v[1], 0}));
        s << ++eid;
        for (size_t k = 0; k < c.size(); ++k) s << (k == 15 ? ",\n" : ", ") << c[k];
        s << "\n";
      }
  }
  s << "*ELEMENT, TYPE=C3D8, ELSET=BLOCK\n";
  for (int a = 0; a < bx; ++a)
    for (int b = 0; b < by; ++b)
      for (int c = 0; c < bz; ++c)
        s << ++eid << ", " << bid(a, b, c) << ", " << bid(a + 1, b, c) << ", " << bid(a + 1, b + 1, c) << ", "
          << bid(a, b + 1, c) << ", " << bid(a, b, c + 1) << ", " << bid(a + 1, b, c + 1) << ", "
          << bid(a + 1, b + 1, c + 1) << ", " << bid(a, b + 1, c + 1) << "\n";
  s << "*ELEMENT, TYPE=MASS, ELSET=PMASS\n" << ++eid << ", 900001\n";
  auto nset = [&](const char* name, const std::vector<int>& v) {
    s << "*NSET, NSET=" << name << "\n";
    for (size_t k = 0; k < v.size(); ++k) s << v[k] << ((k % 8 == 7 || k + 1 == v.size()) ? "\n" : ", ");
  };
  nset("BASE", base);
  nset("RIGID", rigid);
  s << "*MATERIAL, NAME=LEAFMAT\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n"
    << kE << ", " << kE << ", " << kE << ", 0, 0, 0, " << kG << ", " << kG << "\n"
    << kG << ", 0.\n*DENSITY\n7800.\n"
    << "*MATERIAL, NAME=BODYMAT\n*ELASTIC\n210e9, 0.3\n*DENSITY\n3000.\n"
    // Material axes: 1 along the leaf, 2 along its width (z), 3 its normal.
    << "*ORIENTATION, NAME=ORA, SYSTEM=RECTANGULAR\n1., 1., 0., 0., 0., 1.\n"
    << "*ORIENTATION, NAME=ORB, SYSTEM=RECTANGULAR\n1., -1., 0., 0., 0., 1.\n"
    << "*SOLID SECTION, ELSET=LEAF0, MATERIAL=LEAFMAT, ORIENTATION=ORA\n"
    << "*SOLID SECTION, ELSET=LEAF1, MATERIAL=LEAFMAT, ORIENTATION=ORB\n"
    << "*SOLID SECTION, ELSET=BLOCK, MATERIAL=BODYMAT\n*MASS, ELSET=PMASS\n0.1\n"
    << "*RIGID BODY, NSET=RIGID, REF NODE=900002, ROT NODE=900003\n*BOUNDARY\nBASE, 1, 3\n"
    << "*STEP\n*FREQUENCY\n6\n*END STEP\n";
  return s.str();
}

// ccx's eigenvalue table: mode, eigenvalue, rad/time, cycles/time, imaginary part.
std::vector<double> runCalculix(const std::string& deck, const std::filesystem::path& dir, const std::string& job) {
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / (job + ".inp")) << deck; }
  const std::string cmd = "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i " + job + " > " + job + ".log 2>&1";
  std::vector<double> hz;
  if (std::system(cmd.c_str()) != 0) return hz;
  std::ifstream in(dir / (job + ".dat"));
  std::string line;
  bool table = false;
  while (std::getline(in, line)) {
    if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) table = true;
    if (line.find("P A R T I C I P A T I O N") != std::string::npos) table = false;
    std::istringstream ls(line);
    int k;
    double ev, rad, cyc, im;
    if (table && ls >> k >> ev >> rad >> cyc >> im) hz.push_back(cyc);
  }
  return hz;
}

bool haveCalculix() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

}  // namespace

TEST(BeamWCalculix, CrossSpringPivotTorsionModeAsSpacarLightWritesIt) {
  if (!haveCalculix())
    GTEST_SKIP() << "CalculiX (ccx, Debian package calculix-ccx) is not on PATH: the reference cannot be computed "
                    "(tools/setup.sh installs it)";
  const std::vector<double> beamw = flexmbHz(io::readDatString(slPivot(true), "pivot_beamw.dat"), 6);
  const std::vector<double> beam = flexmbHz(io::readDatString(slPivot(false), "pivot_beam.dat"), 6);
  ASSERT_GE(beamw.size(), 6u);
  ASSERT_GE(beam.size(), 6u);
  // The shipped model is this file (its header aside).
  const std::vector<double> shipped =
      flexmbHz(io::readDatFile(FLEXMB_SOURCE_DIR "/datfiles/spatial/cross_spring_pivot_beamw.dat"), 6);
  ASSERT_EQ(shipped.size(), beamw.size());
  for (size_t i = 0; i < shipped.size(); ++i) EXPECT_NEAR(shipped[i] / beamw[i], 1.0, 1e-12) << "mode " << i + 1;
  const std::filesystem::path dir = std::filesystem::path(FLEXMB_BINARY_DIR) / "calculix_pivot";
  const std::vector<double> ref = runCalculix(calculixPivot(24, 8), dir, "pivot_C3D20R_24x8");
  ASSERT_GE(ref.size(), 6u) << "ccx failed or wrote no eigenvalues: see " << (dir / "pivot_C3D20R_24x8.log");
  std::printf("mode  CalculiX C3D20R [Hz]  BEAMW [Hz]  (diff)     BEAM [Hz]  (diff)\n");
  for (int i = 0; i < 6; ++i)
    std::printf("%4d  %20.3f  %10.3f  (%+6.2f%%)  %9.3f  (%+6.2f%%)\n", i + 1, ref[i], beamw[i],
                100 * (beamw[i] / ref[i] - 1), beam[i], 100 * (beam[i] / ref[i] - 1));
  // Modes 1-3 (rotation of the pivot, bending of the leaves): warping plays no part.
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(beamw[i] / ref[i], 1.0, 0.01) << "mode " << i + 1;
    EXPECT_NEAR(beam[i] / ref[i], 1.0, 0.01) << "mode " << i + 1;
  }
  // Modes 4 and 5, the leaves' first torsion: BEAMW within 3%, BEAM (free warping) far below.
  for (int i = 3; i < 5; ++i) {
    EXPECT_NEAR(beamw[i] / ref[i], 1.0, 0.03) << "mode " << i + 1;
    EXPECT_LT(beam[i] / ref[i], 0.85) << "mode " << i + 1;
  }
}
