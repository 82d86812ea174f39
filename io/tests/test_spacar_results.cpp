// SPACAR-shaped result files (io/results.md): layout on a model with every role, the topology
// tables, and the writer's checks (sizes, finiteness, unwritable paths) before anything is written.
#include <gtest/gtest.h>
#include <matio.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <limits>

#include "io/DatReader.hpp"
#include "io/SpacarResults.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

namespace {

// Four-bar with every deformation role: crank hinge input, coupler bending dynamic, the other
// hinges released, the rest fixed.
core::Model fourbar() {
  return io::readDatString(
      "PLBEAM 1 1 11 2 12\nPLBEAM 2 2 21 3 22\nPLBEAM 3 4 31 3 32\nPLHINGE 4 10 11\nPLHINGE 5 12 21\n"
      "PLHINGE 6 22 32\nPLHINGE 7 10 31\nX 1 0 0\nX 2 0 0.1\nX 3 0.3 0.25\nX 4 0.3 0\nBETA 11 1.57\nBETA 12 1.57\n"
      "FIX 1\nFIX 4\nFIX 10\nINPUTE 4 1\nDYNE 2 2 3\nRLSE 5 1\nRLSE 6 1\nRLSE 7 1\nEND\nHALT\nEND\nEND\n",
      "fourbar.dat");
}

io::SpacarResults oneStep(const core::Model& m) {
  io::SpacarResults r;
  r.time = {0.0};
  io::SpacarStep s;
  s.x = s.xd = s.xdd = s.fxt = Eigen::VectorXd::Zero(m.nx);
  s.e = s.ed = s.edd = s.sig = Eigen::VectorXd::Zero(m.ne);
  r.steps.push_back(s);
  return r;
}

}  // namespace

TEST(SpacarResults, LayoutAndTopology) {
  const core::Model m = fourbar();
  const io::SpacarLayout L = io::spacarLayout(m);
  EXPECT_EQ(L.nxp[0], 5);  // nodes 1, 4 (2 each) and orientation 10
  EXPECT_EQ(L.nxp[2] + L.nxp[3], 0);
  EXPECT_EQ(L.nep[1], 3);  // released hinges 5, 6, 7
  EXPECT_EQ(L.nep[2], 1);  // input hinge 4
  EXPECT_EQ(L.nep[3], 2);  // DYNE 2 2 3
  EXPECT_EQ(L.ndof(), 3);
  EXPECT_EQ(L.nddof(), 2);
  const io::SpacarTopology T = io::spacarTopology(m, L);
  // x(lnp(n, k)) is coordinate k of node n: lnp points at the node's coordinates.
  for (const auto& n : m.nodes)
    for (int k = 0; k < n.dim(); ++k)
      EXPECT_EQ(L.xOrder[static_cast<int>(T.lnp(n.label - 1, k)) - 1], n.firstCoord + k);
  EXPECT_EQ(T.lnp.cols(), 2);
  EXPECT_EQ(T.lnp(10 - 1, 1), 0.0);  // an orientation node has one coordinate
  // e(le(el, j)) is deformation j of element el; the released ones come last.
  for (const auto& E : m.elements)
    for (int j = 0; j < E.impl->numDeformations(); ++j)
      EXPECT_EQ(L.eOrder[static_cast<int>(T.le(E.label - 1, j)) - 1], E.firstDef + j);
  EXPECT_GT(T.le(5 - 1, 0), m.ne - 3);
  EXPECT_EQ(T.ln.row(2 - 1).head(4), Eigen::RowVector4d(2, 21, 3, 22));
  EXPECT_NEAR(T.rl0(3 - 1), 0.25, 1e-15);
  EXPECT_EQ(T.rl0(4 - 1), 0.0);
  // it: SPACAR's type codes (PLBEAM 5, as SPACAR's spadraw and stressbeam read it; io/results.md);
  // the hinges have no known SPACAR code and get flexmb's own (101).
  EXPECT_EQ(T.it(1 - 1), 5);
  EXPECT_EQ(T.it(4 - 1), 101);
  EXPECT_EQ(io::elementTypeId(core::findElementType("PLBEAM")), 5);
}

TEST(SpacarResults, WriterChecksBeforeWriting) {
  const core::Model m = fourbar();
  const fs::path dir = fs::temp_directory_path() / "flexmb_spacar_results_test";
  fs::create_directories(dir);
  io::SpacarResults r = oneStep(m);
  r.steps[0].sig[2] = std::numeric_limits<double>::quiet_NaN();
  try {
    io::writeSpacarResults((dir / "nan").string(), m, r);
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite sig at step 1"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "nan.sbd"));
  r = oneStep(m);
  r.steps[0].x.resize(3);
  EXPECT_THROW(io::writeSpacarResults((dir / "size").string(), m, r), std::invalid_argument);
  r = oneStep(m);
  try {
    io::writeSpacarResults((dir / "no_such_dir" / "r").string(), m, r);
    FAIL() << "unwritable path accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dir"), std::string::npos) << e.what();
  }
  // No matrices: only the .sbd.
  const auto written = io::writeSpacarResults((dir / "ok").string(), m, r);
  ASSERT_EQ(written.size(), 1u);
  mat_t* mat = Mat_Open(written[0].c_str(), MAT_ACC_RDONLY);
  ASSERT_NE(mat, nullptr);
  matvar_t* v = Mat_VarRead(mat, "nep");
  ASSERT_NE(v, nullptr);
  const double* nep = static_cast<const double*>(v->data);
  EXPECT_EQ(nep[0] + nep[1] + nep[2] + nep[3], m.ne);
  Mat_VarFree(v);
  Mat_Close(mat);
  fs::remove_all(dir);
}

TEST(SpacarResults, UserFunctionNamesAreReadForTheGateway) {
  const std::string kin = "PLBEAM 1 1 2 3 4\nX 1 0 0\nX 3 1 0\nFIX 1\nFIX 2\nDYNE 1 2 3\nEND\nHALT\n";
  const core::Model m = io::readDatString(kin + "USERSIG my_loads\nUSERINP motion_2\nEND\nEND\n", "u.dat");
  EXPECT_EQ(m.userStressFunction, "my_loads");
  EXPECT_EQ(m.userStressLine, 9);
  EXPECT_EQ(m.userInputFunction, "motion_2");
  EXPECT_EQ(m.userInputLine, 10);
  EXPECT_EQ(m.userFunctions, nullptr);  // the gateway sets it; nothing else does
  try {
    io::readDatString(kin + "USERSIG \"f(t)\"\nEND\nEND\n", "u.dat");
    FAIL() << "a quoted expression accepted as a function name";
  } catch (const io::DatError& e) {
    EXPECT_EQ(e.line(), 9);
    EXPECT_NE(std::string(e.what()).find("expected a MATLAB function name"), std::string::npos) << e.what();
  }
}

// rxyz of a spatial model: row el = element el's initial triad (e_x along the chord, e_y the given
// cross-section direction made normal to it, e_z = e_x x e_y), column-wise, as SPACAR Light reads
// it (reshape(rxyz(el, :), 3, 3)); rows of unused labels are zero; planar models store 0 x 0.
TEST(SpacarResults, ElementTriadsOfSpatialBeams) {
  const core::Model m = io::readDatString(
      "BEAM 2 1 2 3 4 0 1 1\nX 1 0 0 0\nX 3 1 1 0\nFIX 1\nFIX 2\nDYNE 2 1 2 3 4 5 6\nEND\nHALT\nEND\nEND\n", "b.dat");
  const Eigen::MatrixXd R = io::spacarElementTriads(m, 3);
  ASSERT_EQ(R.rows(), 3);
  ASSERT_EQ(R.cols(), 9);
  EXPECT_EQ(R.row(0).norm(), 0.0);
  EXPECT_EQ(R.row(2).norm(), 0.0);
  const Eigen::Vector3d ex = Eigen::Vector3d(1, 1, 0).normalized();
  Eigen::Vector3d ey(0, 1, 1);
  ey = (ey - ey.dot(ex) * ex).normalized();
  const Eigen::Vector3d ez = ex.cross(ey);
  Eigen::Matrix3d A;
  A << ex, ey, ez;
  Eigen::Matrix3d got;
  for (int k = 0; k < 9; ++k) got(k % 3, k / 3) = R(1, k);
  EXPECT_LT((got - A).norm(), 1e-14) << got;
  EXPECT_EQ(io::spacarElementTriads(fourbar(), 7).size(), 0);
  // rl0 of a spatial beam: its initial length (stressbeam and SPACAR Light turn sig into forces with it).
  const io::SpacarTopology T = io::spacarTopology(m, io::spacarLayout(m));
  EXPECT_NEAR(T.rl0(2 - 1), std::sqrt(2.0), 1e-15);
}
