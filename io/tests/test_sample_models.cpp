// The core tests' sample models (core/tests/SampleModels.hpp, built in code) against the .dat files
// they mirror, read by the reader: same topology, roles, degrees of freedom, initial coordinates,
// element parameters, loads, inputs, settings, time functions and the same kinematic solve, so the
// in-code copies cannot drift from the files.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <string>

#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/tests/ModelTexts.hpp"
#include "core/tests/SampleModels.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;
namespace samples = flexmb::core::samples;

namespace {

std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

// The text of the gravity-loaded cantilever the linearisation test used (now
// samples::gravityCantilever).
std::string gravityCantileverText() {
  std::ostringstream s;
  for (int k = 1; k <= 4; ++k)
    s << "PLBEAM " << k << "  " << k << " " << 100 + k << "  " << k + 1 << " " << 101 + k << "\n";
  for (int k = 1; k <= 5; ++k) s << "X " << k << " " << 0.3 * (k - 1) << " " << 0.1 * (k - 1) << "\n";
  s << "FIX 1\nFIX 101\n";
  for (int k = 1; k <= 4; ++k) s << "DYNE " << k << " 1 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= 4; ++k) s << "EM " << k << " 2.5 3e-3\nESTIFF " << k << " 1e3 4\n";
  s << "GRAVITY 0.5 -9.81\nEND\nEND\n";
  return s.str();
}

// Equal vectors, NaN equal to NaN (the "not given" initial values).
void expectSame(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!(std::isnan(a[i]) && std::isnan(b[i]))) {
      EXPECT_EQ(a[i], b[i]) << what << "[" << i << "]";
    }
  }
}

// Two time functions (either may be null) agree on [t0, t1].
void expectSameFunction(const core::TimeFunctionPtr& a, const core::TimeFunctionPtr& b, double t0, double t1,
                        const std::string& what) {
  ASSERT_EQ(a == nullptr, b == nullptr) << what;
  if (!a) return;
  for (int k = 0; k <= 200; ++k) {
    const double t = t0 + (t1 - t0) * k / 200.0;
    const double va = a->value(t), vb = b->value(t);
    EXPECT_NEAR(va, vb, 1e-15 * std::max(1.0, std::abs(vb))) << what << " at t = " << t;
  }
}

void expectSameModel(const core::Model& a, const core::Model& b) {
  const double t0 = b.settings.t0, t1 = b.settings.tEnd;
  EXPECT_EQ(a.dialect, b.dialect);
  EXPECT_EQ(a.spatial, b.spatial);
  ASSERT_EQ(a.nx, b.nx);
  ASSERT_EQ(a.ne, b.ne);
  // Nodes and elements: labels, kinds, numbering, parameters.
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].label, b.nodes[i].label) << "node " << i;
    EXPECT_EQ(a.nodes[i].kind, b.nodes[i].kind) << "node " << i;
    EXPECT_EQ(a.nodes[i].firstCoord, b.nodes[i].firstCoord) << "node " << i;
  }
  ASSERT_EQ(a.elements.size(), b.elements.size());
  for (size_t i = 0; i < a.elements.size(); ++i) {
    const core::ElementEntry &ea = a.elements[i], &eb = b.elements[i];
    const std::string el = "element " + std::to_string(eb.label);
    EXPECT_EQ(ea.label, eb.label) << el;
    EXPECT_EQ(ea.type, eb.type) << el;
    EXPECT_EQ(ea.nodes, eb.nodes) << el;
    EXPECT_EQ(ea.coords, eb.coords) << el;
    EXPECT_EQ(ea.firstDef, eb.firstDef) << el;
    EXPECT_EQ(ea.hasStiffness, eb.hasStiffness) << el;
    EXPECT_EQ(ea.hasDamping, eb.hasDamping) << el;
    EXPECT_EQ(ea.stiffnessParams, eb.stiffnessParams) << el;
    EXPECT_EQ(ea.dampingParams, eb.dampingParams) << el;
    EXPECT_EQ(ea.S, eb.S) << el;
    EXPECT_EQ(ea.Sd, eb.Sd) << el;
    const core::ElementInertia &ia = ea.inertia, &ib = eb.inertia;
    EXPECT_TRUE(ia.rhoA == ib.rhoA && ia.rhoI == ib.rhoI && ia.jxx == ib.jxx && ia.jyy == ib.jyy && ia.jzz == ib.jzz &&
                ia.jyz == ib.jyz && ia.jxy == ib.jxy && ia.jxz == ib.jxz)
        << el << " inertia";
  }
  // Roles, degrees of freedom, initial values.
  EXPECT_EQ(a.x0, b.x0);
  EXPECT_EQ(a.xRole, b.xRole);
  EXPECT_EQ(a.eRole, b.eRole);
  EXPECT_EQ(a.xOwnerNode, b.xOwnerNode);
  EXPECT_EQ(a.eOwnerElement, b.eOwnerElement);
  ASSERT_EQ(a.dofs.size(), b.dofs.size());
  for (size_t j = 0; j < a.dofs.size(); ++j) {
    EXPECT_EQ(a.dofs[j].isDeformation, b.dofs[j].isDeformation) << "dof " << j;
    EXPECT_EQ(a.dofs[j].index, b.dofs[j].index) << "dof " << j;
  }
  expectSame(a.e0, b.e0, "e0");
  expectSame(a.ed0, b.ed0, "ed0");
  expectSame(a.edd0, b.edd0, "edd0");
  expectSame(a.xd0, b.xd0, "xd0");
  EXPECT_EQ(a.restartState, b.restartState);
  // Loads and stresses.
  EXPECT_EQ(a.f0, b.f0);
  EXPECT_EQ(a.delf, b.delf);
  EXPECT_EQ(a.hasGravity, b.hasGravity);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.gravity[k], b.gravity[k]);
  ASSERT_EQ(a.moments.size(), b.moments.size());
  for (size_t k = 0; k < a.moments.size(); ++k) {
    EXPECT_EQ(a.moments[k].node, b.moments[k].node);
    EXPECT_EQ(a.moments[k].value, b.moments[k].value);
    EXPECT_EQ(a.moments[k].increment, b.moments[k].increment);
  }
  EXPECT_EQ(a.sigma0, b.sigma0);
  ASSERT_EQ(a.lumpedMasses.size(), b.lumpedMasses.size());
  for (size_t k = 0; k < a.lumpedMasses.size(); ++k) {
    EXPECT_EQ(a.lumpedMasses[k].coord, b.lumpedMasses[k].coord);
    EXPECT_EQ(a.lumpedMasses[k].value, b.lumpedMasses[k].value);
  }
  auto sameLoads = [&](const std::vector<core::TimeLoad>& la, const std::vector<core::TimeLoad>& lb, const char* w) {
    ASSERT_EQ(la.size(), lb.size()) << w;
    for (size_t k = 0; k < la.size(); ++k) {
      EXPECT_EQ(la[k].index, lb[k].index) << w;
      expectSameFunction(la[k].f, lb[k].f, t0, t1, w);
    }
  };
  sameLoads(a.timeForces, b.timeForces, "XFT");
  sameLoads(a.timeStresses, b.timeStresses, "ESIGT");
  sameLoads(a.references, b.references, "EREF");
  auto sameInputs = [&](const std::vector<core::Rheonomic>& ra, const std::vector<core::Rheonomic>& rb, const char* w) {
    ASSERT_EQ(ra.size(), rb.size()) << w;
    for (size_t k = 0; k < ra.size(); ++k) {
      EXPECT_EQ(ra[k].index, rb[k].index) << w;
      EXPECT_EQ(ra[k].x0, rb[k].x0) << w;
      EXPECT_EQ(ra[k].v, rb[k].v) << w;
      EXPECT_EQ(ra[k].a, rb[k].a) << w;
      EXPECT_EQ(ra[k].delta, rb[k].delta) << w;
      EXPECT_EQ(ra[k].tRef, rb[k].tRef) << w;
      EXPECT_EQ(ra[k].base, rb[k].base) << w;
      expectSameFunction(ra[k].fx, rb[k].fx, t0, t1, w);
      expectSameFunction(ra[k].fv, rb[k].fv, t0, t1, w);
      expectSameFunction(ra[k].fa, rb[k].fa, t0, t1, w);
    }
  };
  sameInputs(a.inputX, b.inputX, "input coordinates");
  sameInputs(a.inputE, b.inputE, "input deformations");
  // Settings.
  const core::AnalysisSettings &sa = a.settings, &sb = b.settings;
  EXPECT_EQ(sa.t0, sb.t0);
  EXPECT_EQ(sa.tEnd, sb.tEnd);
  EXPECT_EQ(sa.outputIntervals, sb.outputIntervals);
  EXPECT_EQ(sa.relTol, sb.relTol);
  EXPECT_EQ(sa.absTol, sb.absTol);
  EXPECT_EQ(sa.hmax, sb.hmax);
  EXPECT_EQ(sa.kinematicTol, sb.kinematicTol);
  EXPECT_EQ(sa.kinematicTolGiven, sb.kinematicTolGiven);
  EXPECT_EQ(sa.maxIterations, sb.maxIterations);
  EXPECT_EQ(sa.loadSteps, sb.loadSteps);
  EXPECT_EQ(sa.initialLoadSteps, sb.initialLoadSteps);
  EXPECT_EQ(sa.timestepGiven, sb.timestepGiven);
  // The same kinematic solve away from the initial configuration (where the model is well posed).
  core::GeometricTransferFunctions ga(a), gb(b);
  if (!ga.isSquare()) return;
  Eigen::VectorXd q = gb.initialDofs();
  for (int j = 0; j < q.size(); ++j) q[j] += 1e-3 * std::sin(1.0 + j);
  const double t = t0 + 0.3 * (t1 - t0);
  ga.solvePositions(t, q);
  gb.solvePositions(t, q);
  EXPECT_EQ(ga.x(), gb.x());
  EXPECT_EQ(ga.e(), gb.e());
}

}  // namespace

TEST(SampleModels, EqualTheFilesTheyMirror) {
  struct Case {
    std::string name;
    std::function<core::Model()> read;
    std::function<core::Model()> build;
  };
  auto file = [](const char* name) { return [name] { return io::readDatFile(dat(name)); }; };
  const std::vector<Case> cases = {
      {"straight_guidance.dat", file("straight_guidance.dat"), samples::straightGuidance},
      {"tests/fourbar.dat", file("tests/fourbar.dat"), [] { return samples::fourBar(); }},
      {"tests/underconstrained.dat", file("tests/underconstrained.dat"),
       [] { return samples::fourBar(samples::FourBar::Underconstrained); }},
      {"tests/overconstrained.dat", file("tests/overconstrained.dat"),
       [] { return samples::fourBar(samples::FourBar::Overconstrained); }},
      {"swungArm()", [] { return io::readDatString(flexmb::test::swungArm(), "swung_arm.dat"); }, samples::swungArm},
      {"cantilever.dat", file("cantilever.dat"), samples::cantilever},
      {"portal.dat", file("portal.dat"), samples::portal},
      {"manipulator.dat", file("manipulator.dat"), samples::manipulator},
      {"slider_crank_s95.dat", file("slider_crank_s95.dat"), samples::sliderCrankS95},
      {"spatial/cross_spring_pivot_coarse.dat", file("spatial/cross_spring_pivot_coarse.dat"),
       samples::crossSpringPivot},
      {"gravity cantilever", [] { return io::readDatString(gravityCantileverText(), "gravity_cantilever.dat"); },
       samples::gravityCantilever},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    expectSameModel(c.build(), c.read());
  }
  // Every sample is checked here.
  EXPECT_EQ(samples::allSamples().size() + 2, cases.size());  // + the two four-bar variants
}
