// Reduced models q = V eta (Eq. 17-23) against the full model and modal truncation theory.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/Linearization.hpp"
#include "io/DatReader.hpp"
#include "tools/analysis/Reduction.hpp"
#include "tools/analysis/Simulation.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

Eigen::VectorXd omegasAtInitial(const core::Model& m, std::optional<Eigen::MatrixXd> V) {
  core::Linearization lin(m, V);
  Eigen::VectorXd f, eta = Eigen::VectorXd::Zero(lin.size());
  lin.kinematics().solvePositions(0.0, lin.kinematics().initialDofs());
  lin.appliedForces(0.0, 0.0, f);
  core::LinearizedSystem sys;
  lin.atRest(0.0, eta, f, sys);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(sys.K + sys.G, sys.M);
  return es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

Eigen::MatrixXd projector(const Eigen::MatrixXd& V) {
  const Eigen::MatrixXd Q = V.householderQr().householderQ() * Eigen::MatrixXd::Identity(V.rows(), V.cols());
  return Q * Q.transpose();
}
}  // namespace

TEST(Reduction, IdentityBasisReproducesFullModelExactly) {
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  analysis::SimulationOptions full, ident;
  full.tEnd = ident.tEnd = 0.05;
  ident.basis = Eigen::MatrixXd::Identity(m.numDofs(), m.numDofs());
  const core::Trajectory a = analysis::simulate(m, full), b = analysis::simulate(m, ident);
  ASSERT_TRUE(a.completed && b.completed);
  EXPECT_EQ(a.nfevals, b.nfevals);
  EXPECT_EQ(a.nsteps, b.nsteps);
  EXPECT_EQ(a.nfailed, b.nfailed);
  ASSERT_EQ(a.time.size(), b.time.size());
  double worst = 0.0;
  for (size_t i = 0; i < a.time.size(); ++i) worst = std::max(worst, (a.states[i].x - b.states[i].x).lpNorm<Eigen::Infinity>());
  EXPECT_LT(worst, 1e-12);
}

TEST(Reduction, ModalBasisReproducesModalTruncation) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  const Eigen::VectorXd full = omegasAtInitial(m, std::nullopt);
  for (int r : {3, 5}) {
    analysis::ReductionOptions o;
    o.method = "modal";
    o.modes = r;
    const analysis::ReductionResult basis = analysis::buildBasis(m, "straight_guidance.dat", o);
    ASSERT_EQ(basis.V.cols(), r);
    const Eigen::VectorXd red = omegasAtInitial(m, basis.V);
    for (int i = 0; i < r; ++i) EXPECT_NEAR(red[i] / full[i], 1.0, 1e-10) << "mode " << i + 1 << " of MODAL-" << r;
  }
}

TEST(Reduction, ManipulatorModalBasisKeepsHingesAsIdentityColumns) {
  const core::Model m = io::readDatFile(dat("manipulator.dat"));
  const std::vector<int> large = analysis::defaultLargeCoordinates(m);
  ASSERT_EQ(large.size(), 2u);
  analysis::ReductionOptions o;
  o.modes = 2;
  const analysis::ReductionResult basis = analysis::buildBasis(m, "manipulator.dat", o);
  ASSERT_EQ(basis.V.rows(), 18);
  ASSERT_EQ(basis.V.cols(), 4);  // MODAL-2: two hinges + two modes
  for (int j = 0; j < 2; ++j) {
    EXPECT_DOUBLE_EQ(basis.V(large[j], j), 1.0);
    EXPECT_DOUBLE_EQ(basis.V.col(j).norm(), 1.0);
    EXPECT_DOUBLE_EQ(basis.V.row(large[j]).norm(), 1.0);
  }
}

TEST(Reduction, SvdModalOfOneConfigurationSpansTheModalBasis) {
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  analysis::ReductionOptions modal;
  modal.modes = 3;
  analysis::ReductionOptions svd = modal;
  svd.method = "svd-modal";
  svd.configs = 1;
  svd.node = 6;
  svd.component = 1;
  svd.from = svd.to = 0.0;  // the initial configuration
  svd.weight = 0.0;
  svd.threshold = 0.0;
  svd.count = 3;
  const auto a = analysis::buildBasis(m, "", modal), b = analysis::buildBasis(m, "", svd);
  ASSERT_EQ(b.V.cols(), 3);
  EXPECT_LT((projector(a.V) - projector(b.V)).norm(), 1e-8);
}
