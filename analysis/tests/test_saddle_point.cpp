// The two forms of the accelerations of Eq. 13 give the same right-hand side: the projected form
// Mbar qdd = F_q^T (f - h - M g - D_x^T sigma) (dense, independent coordinates) and the sparse
// nodal saddle-point form (core/dynamics/SaddlePointAccelerations), at random moving states of models with
// closed loops, inputs on coordinates and deformations (rheonomic), DYNX coordinates, damping,
// gravity, lumped and distributed masses, planar and spatial.
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <string>

#include "analysis/Simulation.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/tests/ModelTexts.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;
using Eigen::VectorXd;
using test::dat;
using test::swungArm;

namespace {

// A flexible pendulum on a cart: the cart's x is a DYNX coordinate (or, with `driven`, prescribed
// in time by INPUTXT), the pendulum hangs from a free hinge.
std::string cartPendulum(bool driven) {
  std::ostringstream s;
  s << "PLHINGE 1  100 101\n";
  s << "PLBEAM 2  1 101  2 102\nPLBEAM 3  2 102  3 103\n";
  s << "X 1 0 0\nX 2 0 -0.5\nX 3 0 -1\n";
  s << "FIX 100\nFIX 1 2\n" << (driven ? "INPUTX 1 1\n" : "DYNX 1 1\n");
  s << "DYNE 1 1\nDYNE 2 2 3\nDYNE 3 2 3\nEND\nHALT\n";
  if (driven) s << "INPUTXT 1 1 \"0.1*sin(7*t)\" \"0.7*cos(7*t)\" \"-4.9*sin(7*t)\"\n";
  s << "XM 1 2.0\nXM 3 0.4\nEM 2 0.8 1e-4\nEM 3 0.8 1e-4\nESTIFF 2 1e6 80\nESTIFF 3 1e6 80\n";
  s << "GRAVITY 0 -9.81\nEND\nEND\n";
  return s.str();
}

// Largest relative difference of the two forms' right-hand sides over a few random states.
double worstDifference(const core::Model& m, double qScale, double qdScale, unsigned seed) {
  core::EquationsOfMotion projected(m, std::nullopt, core::DynamicsForm::Projected);
  core::EquationsOfMotion saddle(m, std::nullopt, core::DynamicsForm::SaddlePoint);
  EXPECT_EQ(projected.form(), core::DynamicsForm::Projected);
  EXPECT_EQ(saddle.form(), core::DynamicsForm::SaddlePoint);
  projected.kinematics().setRelativeTolerance(1e-15);
  saddle.kinematics().setRelativeTolerance(1e-15);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const VectorXd y0 = projected.initialState();
  const int n = projected.size();
  double worst = 0.0;
  for (int trial = 0; trial < 4; ++trial) {
    VectorXd y = y0;
    for (int j = 0; j < n; ++j) {
      y[j] += qScale * u(rng);
      y[n + j] = trial == 0 ? 0.0 : qdScale * u(rng);  // the first state at rest
    }
    const double t = 0.05 * trial;
    VectorXd a(2 * n), b(2 * n);
    projected.rhs(t, y, a);
    saddle.rhs(t, y, b);
    const double scale = a.tail(n).lpNorm<Eigen::Infinity>();
    worst = std::max(worst, (a.tail(n) - b.tail(n)).lpNorm<Eigen::Infinity>() / std::max(scale, 1e-300));
    // The output quantities (xdd, edd) agree too.
    core::StateOutputs oa, ob;
    projected.outputs(t, y, oa);
    saddle.outputs(t, y, ob);
    const double xs = std::max(oa.xdd.lpNorm<Eigen::Infinity>(), 1e-300);
    worst = std::max(worst, (oa.xdd - ob.xdd).lpNorm<Eigen::Infinity>() / xs);
    const double es = std::max(oa.edd.lpNorm<Eigen::Infinity>(), 1e-300);
    worst = std::max(worst, (oa.edd - ob.edd).lpNorm<Eigen::Infinity>() / es);
  }
  return worst;
}

}  // namespace

TEST(SaddlePointDynamics, SameAccelerationsAsTheProjectedForm) {
  struct Entry {
    std::string name;
    core::Model model;
    double qScale, qdScale;
  };
  std::vector<Entry> cases;
  cases.push_back({"straight_guidance", io::readDatFile(dat("straight_guidance.dat")), 1e-4, 0.5});
  cases.push_back({"manipulator", io::readDatFile(dat("manipulator.dat")), 1e-3, 1.0});
  cases.push_back({"slider_crank_s95", io::readDatFile(dat("slider_crank_s95.dat")), 1e-3, 1.0});
  cases.push_back({"fourbar", io::readDatFile(dat("tests/fourbar.dat")), 1e-2, 1.0});
  cases.push_back({"swung arm", io::readDatString(swungArm(), "swung_arm.dat"), 1e-3, 0.5});
  cases.push_back({"cart pendulum", io::readDatString(cartPendulum(false), "cart.dat"), 1e-3, 0.5});
  cases.push_back({"driven cart", io::readDatString(cartPendulum(true), "driven_cart.dat"), 1e-3, 0.5});
  cases.push_back({"wire_guidance", io::readDatFile(dat("spatial/wire_guidance.dat")), 1e-5, 0.2});
  cases.push_back({"pivot (coarse)", io::readDatFile(dat("spatial/cross_spring_pivot_coarse.dat")), 1e-5, 0.2});
  unsigned seed = 7;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const double worst = worstDifference(c.model, c.qScale, c.qdScale, seed++);
    std::printf("  %-18s %3d DOF: largest relative difference %.2e\n", c.name.c_str(), c.model.numDofs(), worst);
    EXPECT_LT(worst, 1e-8);
  }
}

TEST(SaddlePointDynamics, SimulationsAgreeAndChooseTheFormBySize) {
  // The same run in both forms: the responses agree to well within the integration tolerance.
  const core::Model m = io::readDatFile(dat("straight_guidance.dat"));
  analysis::SimulationOptions o;
  o.tEnd = 0.02;
  o.relTol = 1e-8;
  o.absTol = 1e-11;
  o.dynamics = core::DynamicsForm::Projected;
  const core::Trajectory a = analysis::simulate(m, o);
  o.dynamics = core::DynamicsForm::SaddlePoint;
  const core::Trajectory b = analysis::simulate(m, o);
  ASSERT_EQ(a.time.size(), b.time.size());
  double worst = 0.0;
  for (size_t k = 0; k < a.time.size(); ++k)
    worst = std::max(worst, (a.states[k].x - b.states[k].x).lpNorm<Eigen::Infinity>());
  std::printf("  guidance, 0.02 s at RelTol 1e-8: largest x difference %.2e m\n", worst);
  EXPECT_LT(worst, 1e-9);
  // Automatic: projected below kSaddlePointDofs, saddle point from there on; a basis always projects.
  EXPECT_EQ(core::EquationsOfMotion(m).form(),
            m.numDofs() >= core::kSaddlePointDofs ? core::DynamicsForm::SaddlePoint : core::DynamicsForm::Projected);
  EXPECT_EQ(
      core::EquationsOfMotion(m, Eigen::MatrixXd::Identity(m.numDofs(), 3), core::DynamicsForm::SaddlePoint).form(),
      core::DynamicsForm::Projected);
}

TEST(ProjectedMass, ElementByElementEqualsTheDenseProduct) {
  // Mbar = F^T M F of Inertia::projectedMass (fixed-size kernels for narrow F, dynamic ones up to
  // kMaxProjectedColumns, M F beyond) against the dense M: lumped and distributed, planar and spatial.
  const std::vector<core::Model> models = {io::readDatFile(dat("straight_guidance.dat")),
                                           io::readDatString(cartPendulum(false), "cart.dat"),
                                           io::readDatFile(dat("spatial/cross_spring_pivot_coarse.dat"))};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const core::Model& m : models) {
    core::GeometricTransferFunctions gtf(m);
    gtf.solvePositions(0.0, gtf.initialDofs());
    core::Inertia inertia(m);
    inertia.update(gtf.x());
    const Eigen::MatrixXd M = inertia.dense();
    for (int cols : {1, 3, 5, 6, 7, core::Inertia::kMaxProjectedColumns, core::Inertia::kMaxProjectedColumns + 3}) {
      Eigen::MatrixXd F(m.nx, cols);
      for (Eigen::Index k = 0; k < F.size(); ++k) F.data()[k] = u(rng);
      Eigen::MatrixXd Mbar;
      inertia.projectedMass(F, Mbar);
      const Eigen::MatrixXd expected = F.transpose() * M * F;
      const double err = (Mbar - expected).lpNorm<Eigen::Infinity>() / expected.lpNorm<Eigen::Infinity>();
      EXPECT_LT(err, 1e-14) << m.nx << " coordinates, " << cols << " columns";
      if (cols <= core::Inertia::kMaxProjectedColumns) {  // the kernels fill one triangle and mirror it
        EXPECT_EQ((Mbar - Mbar.transpose()).lpNorm<Eigen::Infinity>(), 0.0);
      }
    }
  }
}
