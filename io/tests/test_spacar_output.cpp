// SPACAR-shaped results (io/results.md): the role-sorted layout and the derived quantities of
// core::ResultQuantities. dx's columns of the dynamic degrees of freedom are F_q (checked against
// the kinematics' own first-order solve and against central differences of the positions); an
// input deformation's column equals the column of the same deformation made a degree of freedom.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/dynamics/ResultQuantities.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/SpacarResults.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

namespace {

// A hinge at the root of a two-beam cantilever; the hinge angle is `hingeRole` (INPUTE or DYNE).
core::Model hingedBeam(const std::string& hingeRole) {
  std::ostringstream s;
  s << "PLHINGE 100  200 201\nPLBEAM 1  1 201  2 202\nPLBEAM 2  2 202  3 203\n"
    << "X 1 0 0\nX 2 0.5 0.1\nX 3 1.0 0.15\nFIX 1\nFIX 200\n"
    << "DYNE 1 1 2 3\nDYNE 2 2 3\n"
    << hingeRole << " 100 1\nEND\nHALT\n";
  if (hingeRole == "INPUTE") s << "INPUTET 100 1 \"0\" \"0\" \"0\"\n";
  s << "EM 1 1.0\nEM 2 1.0\nESTIFF 1 1e4 1\nESTIFF 2 1e4 1\nTIMESTEP 1 10\nEND\nEND\n";
  const fs::path p = fs::temp_directory_path() / ("flexmb_spacar_output_" + hingeRole + ".dat");
  std::ofstream(p) << s.str();
  return io::readDatFile(p.string());
}

}  // namespace

TEST(SpacarOutput, LayoutSortsByRoleAndCountsAddUp) {
  const core::Model m = hingedBeam("INPUTE");
  const io::SpacarLayout L = io::spacarLayout(m);
  EXPECT_EQ(L.nxp[0] + L.nxp[1] + L.nxp[2] + L.nxp[3], m.nx);
  EXPECT_EQ(L.nep[0] + L.nep[1] + L.nep[2] + L.nep[3], m.ne);
  EXPECT_EQ(L.nep[2], 1);  // the input hinge
  EXPECT_EQ(L.nep[3], 5);  // DYNE 1 1 2 3, DYNE 2 2 3
  EXPECT_EQ(L.ndof(), 6);
  EXPECT_EQ(L.nddof(), 5);
  // x: fixed first; e: fixed, input, dynamic (in q order), released.
  for (int i = 0; i < L.nxp[0]; ++i) EXPECT_EQ(m.xRole[L.xOrder[i]], core::Role::Fixed);
  EXPECT_EQ(m.eRole[L.eOrder[L.nep[0]]], core::Role::Input);
  for (int j = 0; j < L.nep[3]; ++j) {
    ASSERT_TRUE(m.dofs[j].isDeformation);
    EXPECT_EQ(L.eOrder[L.nep[0] + L.nep[2] + j], m.dofs[j].index);
  }
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(m.nx, 1, m.nx);
  EXPECT_EQ(L.unsortX(L.sortX(v)), v);
}

TEST(SpacarOutput, TransferFunctionsAreFirstOrderSolutions) {
  const core::Model a = hingedBeam("INPUTE"), b = hingedBeam("DYNE");
  core::ResultQuantities ra(a), rb(b);
  core::GeometricTransferFunctions gb(b);
  Eigen::VectorXd qb = gb.initialDofs();
  qb.setConstant(0.01);
  for (int j = 0; j < b.numDofs(); ++j)
    if (b.dofs[j].index == b.elements[b.elementByLabel.at(100)].firstDef) qb[j] = 0.0;  // the input's value at t = 0
  Eigen::VectorXd qa(a.numDofs());
  for (int j = 0; j < a.numDofs(); ++j) qa[j] = 0.01;
  ra.setState(0.0, qa);
  rb.setState(0.0, qb);
  const io::SpacarLayout La = io::spacarLayout(a);
  Eigen::MatrixXd dxa, dxb, Fq;
  ra.transfer(La.dofColumns, dxa);
  std::vector<core::FreeCoordinate> colsB;
  for (const auto& d : b.dofs) colsB.push_back({d.isDeformation, d.index});
  rb.transfer(colsB, dxb);
  gb.solvePositions(0.0, qb);
  gb.firstOrder(nullptr, Fq);
  EXPECT_LT((dxb - Fq).cwiseAbs().maxCoeff(), 1e-12) << "dx of the dynamic coordinates is not F_q";
  // Central differences of the positions.
  const double h = 1e-5;  // truncation ~h^2; Newton residual noise ~1e-12 / h
  for (int j = 0; j < b.numDofs(); ++j) {
    Eigen::VectorXd qp = qb, qm = qb;
    qp[j] += h, qm[j] -= h;
    gb.solvePositions(0.0, qp);
    const Eigen::VectorXd xp = gb.x();
    gb.solvePositions(0.0, qm);
    const Eigen::VectorXd fd = (xp - gb.x()) / (2 * h);
    EXPECT_LT((fd - dxb.col(j)).cwiseAbs().maxCoeff(), 1e-6) << "column " << j;
  }
  // Same kinematics: every column of a (input included) equals b's column of that deformation.
  for (std::size_t c = 0; c < La.dofColumns.size(); ++c) {
    int jb = -1;
    for (int j = 0; j < b.numDofs(); ++j)
      if (b.dofs[j].isDeformation == La.dofColumns[c].isDeformation && b.dofs[j].index == La.dofColumns[c].index)
        jb = j;
    ASSERT_GE(jb, 0);
    EXPECT_LT((dxa.col(static_cast<int>(c)) - dxb.col(jb)).cwiseAbs().maxCoeff(), 1e-12) << "column " << c;
  }
}
