// Objectivity of the spatial elements the BEAM tests (test_spatial_models.cpp) do not reach (issue
// 22): a TRUSS tripod, an inverted double pendulum of HINGEs with springs and RBEAMs, and BEAMW
// cantilevers and the BEAMW cross-spring pivot, each solved as written and turned as a whole by a
// random rotation R (objectivity::rotatedDat: positions, element vectors, loads, gravity, initial
// Euler parameters). The turned model must give the turned answer: every load step's equilibrium
// R x, the same buckling load factors and frequencies, and the turned mode shapes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "analysis/tests/Objectivity.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

struct Turned {
  core::Model a, b;
  analysis::StaticRun ra, rb;
  double steps = 0.0, buckling = 0.0, frequencies = 0.0, modes = 0.0;
};

// Solves `dat` and its turned copy with nev frequencies and `buckling` factors per step and
// measures how far the answers are from being each other's rotation (length: the model's size).
Turned solveTurned(const std::string& dat, const Eigen::Matrix3d& R, double length, int nev, int buckling) {
  Turned t{io::readDatString(dat, "a.dat"), io::readDatString(objectivity::rotatedDat(dat, R), "b.dat"), {}, {}};
  t.ra = analysis::staticAnalysis(t.a, nev, 0, {}, buckling);
  t.rb = analysis::staticAnalysis(t.b, nev, 0, {}, buckling);
  EXPECT_TRUE(t.ra.completed) << t.ra.stopReason;
  EXPECT_TRUE(t.rb.completed) << t.rb.stopReason;
  EXPECT_EQ(t.ra.steps.size(), t.rb.steps.size());
  if (t.ra.steps.empty() || t.ra.steps.size() != t.rb.steps.size()) return t;
  for (size_t k = 0; k < t.ra.steps.size(); ++k)
    t.steps =
        std::max(t.steps, objectivity::configurationDifference(t.a, t.ra.steps[k].x, t.b, t.rb.steps[k].x, R, length));
  const auto &sa = t.ra.steps.back(), &sb = t.rb.steps.back();
  EXPECT_EQ(sa.buckling.size(), buckling);
  EXPECT_EQ(sb.buckling.size(), sa.buckling.size());
  if (sa.buckling.size() && sb.buckling.size() == sa.buckling.size())
    t.buckling = (sa.buckling - sb.buckling).cwiseQuotient(sa.buckling).cwiseAbs().maxCoeff();
  const auto &fa = sa.frequencies, &fb = sb.frequencies;
  EXPECT_EQ(fa.omega.size(), nev);
  EXPECT_EQ(fb.omega.size(), fa.omega.size());
  if (fa.omega.size() && fb.omega.size() == fa.omega.size()) {
    t.frequencies = (fa.omega - fb.omega).cwiseQuotient(fa.omega).cwiseAbs().maxCoeff();
    t.modes = objectivity::modeDifference(t.a, sa.x, fa.nodalModes, fa.omega, t.b, sb.x, fb.nodalModes, fb.omega, R);
  }
  return t;
}

void report(const char* name, const Turned& t) {
  std::printf(
      "objectivity, %s: %zu load steps differ by %.1e; buckling factors %s by %.1e; frequencies by %.1e, mode "
      "shapes by %.1e\n",
      name, t.ra.steps.size(), t.steps,
      t.ra.steps.empty() || t.ra.steps.back().buckling.size() == 0
          ? "(none)"
          : std::to_string(t.ra.steps.back().buckling[0]).c_str(),
      t.buckling, t.frequencies, t.modes);
}

// The turned model's load steps, buckling factors, frequencies and mode shapes are the model's.
void expectTurnedAlike(const Turned& t) {
  EXPECT_LT(t.steps, 1e-10);
  EXPECT_LT(t.buckling, 1e-8);
  EXPECT_LT(t.frequencies, 1e-9);
  EXPECT_LT(t.modes, 1e-8);
}

// A shallow tripod of three TRUSS members (different EA, with mass) from a base of radius 1 to the
// apex 0.3 above it, under gravity and an apex load DELXF that is mostly downward: the apex snaps
// through at a finite load factor (the buckling factors).
std::string tripod() {
  return "X 1 0 1 0\nX 3 -0.8660254037844386 -0.5 0\nX 5 0.8660254037844386 -0.5 0\nX 7 0.05 0.02 0.3\n"
         "TRUSS 1 1 7\nTRUSS 2 3 7\nTRUSS 3 5 7\nFIX 1\nFIX 3\nFIX 5\nDYNE 1 1\nDYNE 2 1\nDYNE 3 1\nEND\nHALT\n"
         "ESTIFF 1 100\nESTIFF 2 120\nESTIFF 3 90\nEM 1 0.5\nEM 2 0.4\nEM 3 0.6\nXM 7 0.3\n"
         "GRAVITY 0 0 -0.5\nDELXF 7 0.05 -0.03 -0.4\nITERSTEP 30 4\nEND\nEND\n";
}

// An inverted double pendulum: RBEAM links along z on HINGEs with rotational springs, the first
// axis along x, the second along (0, 1, 1) (non-parallel: the motion is spatial), line masses and
// a tip mass, gravity and a tip load that compresses it and pushes it sideways.
std::string hingedPendulum() {
  return "X 1 0 0 0\nX 3 0 0 1\nX 5 0.1 0 2\n"
         "HINGE 1 2 4 1 0 0\nRBEAM 2 1 4 3 1 0 0\nHINGE 3 4 6 0 1 1\nRBEAM 4 3 6 5 1 0 0\n"
         "FIX 1\nFIX 2\nDYNE 1 1\nDYNE 3 1\nEND\nHALT\n"
         "ESTIFF 1 50\nESTIFF 3 30\nEM 2 1.0\nEM 4 0.7\nXM 5 0.2\n"
         "GRAVITY 0 0 -9.81\nDELXF 5 0.5 -0.3 -3\nITERSTEP 30 4\nEND\nEND\n";
}

// A BEAMW cantilever along x (n elements, SPACAR Light's node numbering: position 3i+1,
// orientation 3i+2, warping 3i+3), warping restrained at the clamp, tip force and moment DELXF.
std::string beamwCantilever(int n, double EIy, double EIz, double GIt, double ECw, const Eigen::Vector3d& f,
                            const Eigen::Vector3d& moment, int steps) {
  std::ostringstream o;
  o.precision(17);
  for (int i = 0; i <= n; ++i) o << "X " << 3 * i + 1 << " " << 1.0 * i / n << " 0 0\n";
  for (int k = 1; k <= n; ++k) {
    const int p = 3 * (k - 1), q = 3 * k;
    o << "BEAMW " << k << " " << p + 1 << " " << p + 2 << " " << p + 3 << " " << q + 1 << " " << q + 2 << " " << q + 3
      << " 0 1 0\nDYNE " << k << " 1 2 3 4 5 6\n";
  }
  o << "FIX 1\nFIX 2\nFIX 3\nEND\nHALT\n";
  for (int k = 1; k <= n; ++k) {
    o << "ESTIFF " << k << " 1e5 " << GIt << " " << EIy << " " << EIz << " 0 0 " << ECw << "\n";
    o << "EM " << k << " 1 0.02 0.01 0.01 0 0.001\n";
  }
  if (!f.isZero(0.0)) o << "DELXF " << 3 * n + 1 << " " << f[0] << " " << f[1] << " " << f[2] << "\n";
  if (!moment.isZero(0.0))
    o << "DELXF " << 3 * n + 2 << " " << moment[0] << " " << moment[1] << " " << moment[2] << "\n";
  o << "ITERSTEP 30 " << steps << "\nEND\nEND\n";
  return o.str();
}

}  // namespace

TEST(SpatialObjectivity, TrussTripodTurnsWithTheModel) {
  const Turned t = solveTurned(tripod(), objectivity::randomRotation(21), 1.0, 3, 2);
  report("TRUSS tripod", t);
  ASSERT_EQ(t.ra.steps.size(), 5u);  // load steps 0..4
  // The load is well below the snap-through: the apex moved, the factors are finite and above 1.
  EXPECT_GT((t.ra.steps.back().x - t.a.x0).norm(), 1e-3);
  EXPECT_GT(t.ra.steps.back().buckling[0], 1.0);
  expectTurnedAlike(t);
}

TEST(SpatialObjectivity, HingesAndRigidBeamsTurnWithTheModel) {
  const Turned t = solveTurned(hingedPendulum(), objectivity::randomRotation(22), 2.0, 2, 2);
  report("HINGE + RBEAM pendulum", t);
  ASSERT_EQ(t.ra.steps.size(), 5u);
  EXPECT_GT((t.ra.steps.back().x - t.a.x0).norm(), 1e-2);  // a large, spatial deflection
  EXPECT_GT(t.ra.steps.back().buckling[0], 1.0);
  expectTurnedAlike(t);
}

TEST(SpatialObjectivity, BeamWCantileversTurnWithTheModel) {
  // Twisted and bent (an end torque with restrained warping and a lateral force), then lateral-
  // torsional buckling of a narrow BEAMW strip under a tip force in its stiff plane.
  const Turned bent = solveTurned(beamwCantilever(4, 50, 80, 2, 0.5, {0.2, 3, -2}, {0.8, 0.1, 0}, 4),
                                  objectivity::randomRotation(23), 1.0, 4, 0);
  report("BEAMW cantilever, twisted and bent", bent);
  ASSERT_EQ(bent.ra.steps.size(), 5u);
  EXPECT_GT((bent.ra.steps.back().x - bent.a.x0).norm(), 1e-2);
  EXPECT_LT(bent.steps, 1e-10);
  EXPECT_LT(bent.frequencies, 1e-9);
  EXPECT_LT(bent.modes, 1e-8);
  const Turned strip = solveTurned(beamwCantilever(8, 1, 1e4, 1, 0.05, {0, -1e-3, 0}, {0, 0, 0}, 1),
                                   objectivity::randomRotation(24), 1.0, 0, 3);
  report("BEAMW strip, lateral-torsional buckling", strip);
  EXPECT_LT(strip.steps, 1e-10);
  EXPECT_LT(strip.buckling, 1e-8);
}

TEST(SpatialObjectivity, BeamWPivotTurnsWithTheModel) {
  std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot_beamw.dat");
  std::ostringstream text;
  text << in.rdbuf();
  const Turned t = solveTurned(text.str(), objectivity::randomRotation(25), 0.1, 4, 0);
  report("BEAMW cross-spring pivot", t);
  EXPECT_LT(t.steps, 1e-10);
  EXPECT_LT(t.frequencies, 1e-9);
  EXPECT_LT(t.modes, 1e-7);
}
