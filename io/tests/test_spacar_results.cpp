// SPACAR-shaped result files (io/results.md): layout on a model with every role, the topology
// tables, and the writer's checks (sizes, finiteness, unwritable paths) before anything is written.
#include <gtest/gtest.h>
#include <matio.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <limits>

#include "io/formats/DatReader.hpp"
#include "io/formats/SpacarResults.hpp"

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

namespace {
// Reads a variable of a MAT file as a matrix (0 x 0 when missing).
Eigen::MatrixXd readMat(const std::string& path, const char* name) {
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (!mat) return {};
  matvar_t* v = Mat_VarRead(mat, name);
  Eigen::MatrixXd M;
  if (v && v->rank == 2 && v->class_type == MAT_C_DOUBLE) {
    M.resize(static_cast<Eigen::Index>(v->dims[0]), static_cast<Eigen::Index>(v->dims[1]));
    if (M.size()) std::copy_n(static_cast<const double*>(v->data), M.size(), M.data());
  }
  if (v) Mat_VarFree(v);
  Mat_Close(mat);
  return M;
}

Eigen::Matrix3d rowAsMatrix(const Eigen::MatrixXd& R, int label) {
  Eigen::Matrix3d A;
  for (int k = 0; k < 9; ++k) A(k % 3, k / 3) = R(label - 1, k);
  return A;
}

// R(lambda) of docs/theory/spatial-elements.md 1.2, written out here.
Eigen::Matrix3d rotationOf(const Eigen::Vector4d& l) {
  const Eigen::Quaterniond q(l[0], l[1], l[2], l[3]);
  return q.normalized().toRotationMatrix();
}
}  // namespace

// The per-element variables of a spatial model (issue 22) against values computed here from the
// file's numbers: a BEAM (1), a HINGE (2), an RBEAM (3), a TRUSS (4) and a BEAMW (5), nodes turned
// by LAMBDA.
//   rl0   the distance of the element's position nodes in the initial configuration (0: hinge);
//   rxyz  R(lambda_p0)^T [e_x e_y e_z] at the first orientation node (BEAM, RBEAM: e_x the chord,
//         e_y the given y vector made normal to it; HINGE: e_x the axis);
//   rxyzq the same at the second orientation node (BEAM, BEAMW, HINGE);
//   estiff/stif, edamp, em, esig: the ESTIFF, EDAMP, EM and ESIG values as the file gives them.
TEST(SpacarResults, SpatialElementVariables) {
  const std::string dat =
      "BEAM 1 1 2 3 4 0 0.3 1\nHINGE 2 4 6 0.2 1 0.1\nRBEAM 3 3 6 5 0 0 1\nTRUSS 4 5 7\n"
      "X 1 0 0 0\nX 3 0.6 0.8 0\nX 5 1.1 0.9 0.3\nX 7 1.5 0.2 0.4\n"
      "BEAMW 5 7 8 9 10 11 12 1 1 1\nX 10 2.0 0.6 0.9\n"
      "LAMBDA 4 0.9 0.1 -0.3 0.2\nLAMBDA 6 0.7 -0.2 0.5 0.1\nLAMBDA 8 0.5 0.5 -0.5 0.5\nLAMBDA 11 0.8 0 0.6 0\n"
      "FIX 1\nFIX 2\nFIX 7\nFIX 8\nFIX 9\nDYNE 1 1 2 3 4 5 6\nDYNE 2 1\nDYNE 4 1\nDYNE 5 1 2 3 4 5 6\n"
      "END\nHALT\n"
      "ESTIFF 1 100 2 3 4 0.01 0.02\nEDAMP 1 0.1 0.2 0.3 0.4\nEM 1 1.5 0.01 0.02 0.03 0.004\n"
      "ESTIFF 2 7\nEM 3 0.8\nESTIFF 4 50\nEM 4 0.25\nESIG 4 3.5\n"
      "ESTIFF 5 200 5 6 8 0 0 0.5\nEM 5 2 0.1 0.2 0.3 0 0.05\nESIG 5 0 0 0 0 0 1.25\nEND\nEND\n";
  const core::Model m = io::readDatString(dat, "spatial_vars.dat");
  const fs::path dir = fs::temp_directory_path() / "flexmb_spacar_spatial_vars";
  fs::create_directories(dir);
  const auto written = io::writeSpacarResults((dir / "s").string(), m, oneStep(m));
  const std::string sbd = written.at(0);

  const Eigen::Vector3d x1(0, 0, 0), x3(0.6, 0.8, 0), x5(1.1, 0.9, 0.3), x7(1.5, 0.2, 0.4), x10(2.0, 0.6, 0.9);
  const Eigen::Vector4d l2(1, 0, 0, 0), l4 = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized(),
                                        l6 = Eigen::Vector4d(0.7, -0.2, 0.5, 0.1).normalized(), l8(0.5, 0.5, -0.5, 0.5),
                                        l11(0.8, 0, 0.6, 0);
  // Rows by element label: the five elements and the normalisation elements (L2MIN1) flexmb adds
  // for the free orientation nodes after them (labels 6, 7, 8: nodes 4, 6, 11), zeros there.
  int rows = 0;
  for (const auto& el : m.elements) rows = std::max(rows, el.label);
  ASSERT_EQ(rows, 8);
  const Eigen::MatrixXd rl0 = readMat(sbd, "rl0");
  ASSERT_EQ(rl0.rows(), rows);
  EXPECT_EQ(rl0.bottomRows(3).norm(), 0.0);
  EXPECT_NEAR(rl0(4), (x10 - x7).norm(), 1e-15);
  // `it` is a row, as IT in SPACAR's own slidercrank.sbd (1 x 9: 3 1 3 1 4 4 4 4 4 for its
  // HINGE, BEAM, HINGE, BEAM and five Euler-parameter normalisations; io/results.md).
  const Eigen::MatrixXd it = readMat(sbd, "it");
  ASSERT_EQ(it.rows(), 1);
  ASSERT_EQ(it.cols(), rows);
  EXPECT_EQ(it(0), 1.0);   // BEAM
  EXPECT_EQ(it(1), 3.0);   // HINGE
  EXPECT_EQ(it(3), 2.0);   // TRUSS
  EXPECT_EQ(it(4), 18.0);  // BEAMW
  for (int k = 5; k < rows; ++k) EXPECT_EQ(it(k), 4.0) << "L2MIN1 " << k + 1;
  EXPECT_NEAR(rl0(0), (x3 - x1).norm(), 1e-15);
  EXPECT_EQ(rl0(1), 0.0);
  EXPECT_NEAR(rl0(2), (x5 - x3).norm(), 1e-15);
  EXPECT_NEAR(rl0(3), (x7 - x5).norm(), 1e-15);

  auto frame = [](const Eigen::Vector3d& ex, Eigen::Vector3d y) {
    y = (y - y.dot(ex) * ex).normalized();
    Eigen::Matrix3d F;
    F << ex, y, ex.cross(y);
    return F;
  };
  const Eigen::Matrix3d beam = frame((x3 - x1).normalized(), Eigen::Vector3d(0, 0.3, 1));
  const Eigen::Matrix3d rbeam = frame((x5 - x3).normalized(), Eigen::Vector3d(0, 0, 1));
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, 1, 0.1).normalized();
  const Eigen::MatrixXd rxyz = readMat(sbd, "rxyz"), rxyzq = readMat(sbd, "rxyzq");
  ASSERT_EQ(rxyz.rows(), rows);
  ASSERT_EQ(rxyz.cols(), 9);
  ASSERT_EQ(rxyzq.rows(), rows);
  EXPECT_LT((rowAsMatrix(rxyz, 1) - rotationOf(l2).transpose() * beam).norm(), 1e-14);
  EXPECT_LT((rowAsMatrix(rxyzq, 1) - rotationOf(l4).transpose() * beam).norm(), 1e-14);
  EXPECT_LT((rowAsMatrix(rxyz, 3) - rotationOf(l6).transpose() * rbeam).norm(), 1e-14);
  const Eigen::Matrix3d beamw = frame((x10 - x7).normalized(), Eigen::Vector3d(1, 1, 1));
  EXPECT_LT((rowAsMatrix(rxyz, 5) - rotationOf(l8).transpose() * beamw).norm(), 5e-14);
  EXPECT_LT((rowAsMatrix(rxyzq, 5) - rotationOf(l11).transpose() * beamw).norm(), 5e-14);
  EXPECT_EQ(rxyzq.row(2).norm(), 0.0);  // an RBEAM has no second orientation node
  // The hinge: e_x is the axis in either node's frame, the triad proper and orthonormal.
  for (const auto& [R, l] : {std::pair{rxyz, l4}, std::pair{rxyzq, l6}}) {
    const Eigen::Matrix3d A = rowAsMatrix(R, 2);
    EXPECT_LT((rotationOf(l) * A.col(0) - axis).norm(), 1e-14);
    EXPECT_LT((A.transpose() * A - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_NEAR(A.determinant(), 1.0, 1e-14);
  }
  EXPECT_EQ(rxyz.row(3).norm(), 0.0);  // a truss has no triad

  const Eigen::MatrixXd estiff = readMat(sbd, "estiff"), stif = readMat(sbd, "stif"), em = readMat(sbd, "em"),
                        edamp = readMat(sbd, "edamp"), esig = readMat(sbd, "esig");
  ASSERT_EQ(estiff.rows(), rows);
  ASSERT_EQ(estiff.cols(), 7);  // BEAMW's seven values
  EXPECT_EQ(Eigen::RowVectorXd(estiff.row(0)), (Eigen::RowVectorXd(7) << 100, 2, 3, 4, 0.01, 0.02, 0).finished());
  EXPECT_EQ(Eigen::RowVectorXd(estiff.row(4)), (Eigen::RowVectorXd(7) << 200, 5, 6, 8, 0, 0, 0.5).finished());
  EXPECT_EQ(estiff(1, 0), 7.0);
  EXPECT_EQ(estiff.row(2).norm(), 0.0);
  EXPECT_EQ(estiff(3, 0), 50.0);
  EXPECT_EQ(stif, estiff);
  ASSERT_EQ(em.rows(), rows);
  ASSERT_EQ(em.cols(), 6);
  EXPECT_EQ(Eigen::RowVectorXd(em.row(0)), (Eigen::RowVectorXd(6) << 1.5, 0.01, 0.02, 0.03, 0.004, 0).finished());
  EXPECT_EQ(Eigen::RowVectorXd(em.row(4)), (Eigen::RowVectorXd(6) << 2, 0.1, 0.2, 0.3, 0, 0.05).finished());
  EXPECT_EQ(em(2, 0), 0.8);
  EXPECT_EQ(em(3, 0), 0.25);
  ASSERT_EQ(edamp.rows(), rows);
  EXPECT_EQ(Eigen::RowVectorXd(edamp.row(0).head(4)), Eigen::RowVector4d(0.1, 0.2, 0.3, 0.4));
  ASSERT_EQ(esig.rows(), rows);
  ASSERT_EQ(esig.cols(), 8);  // BEAMW's eight deformations
  EXPECT_EQ(esig(3, 0), 3.5);
  EXPECT_EQ(esig(4, 5), 1.25);  // BEAMW's 6th deformation
  EXPECT_EQ(esig.row(0).norm(), 0.0);
  EXPECT_EQ(esig.norm(), std::hypot(3.5, 1.25));  // nothing else
  fs::remove_all(dir);
}

// The files in memory (what the gateway puts into the workspace, issue 52) hold exactly what the
// writer writes: the same variables in the same order, the same sizes and values; `t` is `time`
// (SPACAR's name); a file that cannot be written throws naming it and leaves nothing behind.
TEST(SpacarResults, FilesInMemoryAreTheFilesWritten) {
  const core::Model m = fourbar();
  const fs::path dir = fs::temp_directory_path() / "flexmb_spacar_memory_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  io::SpacarResults r = oneStep(m);
  r.time = {0.25};
  r.steps[0].x.setLinSpaced(m.nx, 1.0, 2.0);
  const int n = 2;  // nddof: an .sbm as well
  r.steps[0].M0 = r.steps[0].K0 = r.steps[0].G0 = Eigen::MatrixXd::Identity(n, n);
  r.steps[0].C0 = r.steps[0].D0 = r.steps[0].N0 = Eigen::MatrixXd::Zero(n, n);
  const std::string base = (dir / "mem").string();
  const auto written = io::writeSpacarResults(base, m, r);
  const auto files = io::spacarResultFiles(base, m, r);
  ASSERT_EQ(files.size(), written.size());
  ASSERT_EQ(files.size(), 2u);
  for (std::size_t f = 0; f < files.size(); ++f) {
    EXPECT_EQ(files[f].path, written[f]);
    mat_t* mat = Mat_Open(written[f].c_str(), MAT_ACC_RDONLY);
    ASSERT_NE(mat, nullptr);
    std::size_t k = 0;
    while (matvar_t* v = Mat_VarReadNext(mat)) {
      ASSERT_LT(k, files[f].variables.size()) << written[f] << ": more variables than in memory";
      const io::SpacarVariable& mem = files[f].variables[k++];
      EXPECT_EQ(mem.name, v->name);
      std::size_t count = 1;
      for (int d = 0; d < v->rank; ++d) count *= v->dims[d];
      ASSERT_EQ(mem.data.size(), count) << mem.name;
      for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(mem.data[i], static_cast<const double*>(v->data)[i]);
      Mat_VarFree(v);
    }
    Mat_Close(mat);
    EXPECT_EQ(k, files[f].variables.size()) << written[f];
  }
  auto find = [&](std::size_t f, const std::string& name) -> const io::SpacarVariable* {
    for (const auto& v : files[f].variables)
      if (v.name == name) return &v;
    return nullptr;
  };
  for (std::size_t f = 0; f < 2; ++f) {
    ASSERT_NE(find(f, "t"), nullptr);
    EXPECT_EQ(find(f, "t")->data, std::vector<double>{0.25});
  }
  ASSERT_NE(find(1, "ndof"), nullptr);
  EXPECT_EQ(find(1, "ndof")->data, std::vector<double>{3.0});
  EXPECT_EQ(find(1, "nddof")->data, std::vector<double>{2.0});
  // A folder of the file's name: an error naming the path, and the folder left as it was.
  io::SpacarFileContents blocked = files[0];
  blocked.path = (dir / "blocked.sbd").string();
  fs::create_directory(blocked.path);
  try {
    io::writeSpacarFile(blocked);
    FAIL() << "a folder accepted as the .sbd";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("blocked.sbd"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(blocked.path));
  fs::remove_all(dir);
}
