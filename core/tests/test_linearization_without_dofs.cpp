// A model without degrees of freedom (every coordinate fixed, input or calculable; statics of such
// models just place them): the linearisation is empty and must be so without undefined behaviour.
// Found by the sanitizer pass (tools/sanitize.sh): Eigen's triangular product in the projection
// A^T X A bound a reference to the first coefficient of an empty matrix (UBSan "reference binding
// to null pointer"); this test fails under UBSan without the guard in Linearization::project.
#include <gtest/gtest.h>

#include <vector>

#include "core/elements/Element.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/model/ModelBuilder.hpp"

using namespace flexmb::core;

namespace {

// PLTRUSS 1 1 2, X 2 1 0, FIX 1, INPUTX 2 1, FIX 2 2, RLSE 1 1: the input moves node 2 along x and
// the released elongation follows; nothing is left to solve.
Model inputDrivenTruss() {
  ModelBuilder b("zero_dof.dat");
  const ElementTypeInfo* truss = findElementType("PLTRUSS");
  EXPECT_NE(truss, nullptr);
  const std::vector<int> nodes = {1, 2};
  b.addElement(*truss, 1, nodes, 1);
  const std::vector<double> x2 = {1.0, 0.0};
  b.setCoordinates(2, x2, 2);
  b.setCoordinateRole(1, {}, Role::Fixed, 3);
  const std::vector<int> first = {1}, second = {2};
  b.setCoordinateRole(2, first, Role::Input, 4);
  b.setCoordinateRole(2, second, Role::Fixed, 5);
  b.setDeformationRole(1, first, Role::Calculable, 6);
  const std::vector<double> ea = {10.0};
  b.setStiffness(1, ea, 7);
  return b.finalize({});
}

}  // namespace

TEST(LinearizationWithoutDofs, AtRestAndTangentAreEmpty) {
  const Model m = inputDrivenTruss();
  ASSERT_EQ(m.numDofs(), 0);
  Linearization lin(m);
  ASSERT_EQ(lin.size(), 0);
  const Eigen::VectorXd eta(0);
  Eigen::VectorXd f;
  lin.appliedForces(0.0, 1.0, f);
  LinearizedSystem sys;
  lin.atRest(0.0, eta, f, sys, true);
  EXPECT_EQ(sys.M.size(), 0);
  EXPECT_EQ(sys.K.size(), 0);
  EXPECT_EQ(sys.G.size(), 0);
  EXPECT_EQ(sys.Q.size(), 0);
  Eigen::VectorXd Q;
  Eigen::MatrixXd T;
  lin.tangent(0.0, eta, f, Q, T);
  EXPECT_EQ(T.rows(), 0);
  EXPECT_EQ(T.cols(), 0);
  EXPECT_EQ(Q.size(), 0);
}
