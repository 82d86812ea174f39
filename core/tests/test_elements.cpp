// Element kernels (Eq. 1-5): deformations against the paper's formulas, analytic derivatives
// against central finite differences, rigid-motion invariance, zero initial deformation,
// constitutive matrices and the keyword registry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

#include "core/elements/Element.hpp"
#include "core/elements/PlanarBeam.hpp"
#include "core/elements/PlanarHinge.hpp"
#include "core/elements/PlanarTruss.hpp"
#include "core/tests/ElementSamples.hpp"

using namespace flexmb::core;

namespace {

constexpr double kPi = std::numbers::pi;

struct Case {
  std::string keyword;
  ElongationDefinition elongation;
  std::string label;
};

const std::vector<Case>& cases() {
  static const std::vector<Case> c = {
      {"PLBEAM", ElongationDefinition::Plain, "PLBEAM plain"},
      {"PLBEAM", ElongationDefinition::BendingCorrected, "PLBEAM corrected"},
      {"PLBEAMNL", ElongationDefinition::Plain, "PLBEAMNL (option plain ignored)"},
      {"PLTRUSS", ElongationDefinition::BendingCorrected, "PLTRUSS"},
      {"PLHINGE", ElongationDefinition::BendingCorrected, "PLHINGE"},
  };
  return c;
}

double uniform(std::mt19937& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

// Random initial coordinates for the slots: positions in [-2, 2]^2 with the nodes at least 0.3
// apart (any chord angle), orientation (BETA) values in [-3, 3].
ElemVec randomInitial(const ElementTypeInfo& t, std::mt19937& rng) {
  for (;;) {
    ElemVec x(t.numCoords());
    int k = 0;
    for (NodeKind s : t.slots) {
      if (s == NodeKind::Position) {
        x[k++] = uniform(rng, -2, 2);
        x[k++] = uniform(rng, -2, 2);
      } else {
        x[k++] = uniform(rng, -3, 3);
      }
    }
    if (t.numCoords() == 6 && std::hypot(x[3] - x[0], x[4] - x[1]) < 0.3) continue;
    if (t.numCoords() == 4 && t.slots[1] == NodeKind::Position && std::hypot(x[2] - x[0], x[3] - x[1]) < 0.3) continue;
    return x;
  }
}

// Rigid motion: rotate positions by th about the origin, translate by (tx, ty), add th to angles.
ElemVec rigidMotion(const ElementTypeInfo& t, const ElemVec& x, double th, double tx, double ty) {
  ElemVec y(x.size());
  const double c = std::cos(th), s = std::sin(th);
  int k = 0;
  for (NodeKind kind : t.slots) {
    if (kind == NodeKind::Position) {
      y[k] = c * x[k] - s * x[k + 1] + tx;
      y[k + 1] = s * x[k] + c * x[k + 1] + ty;
      k += 2;
    } else {
      y[k] = x[k] + th;
      k += 1;
    }
  }
  return y;
}

// A deformed configuration: perturb the initial one (positions by up to 0.3, angles by up to 0.6),
// then move it rigidly by a random rotation and translation.
ElemVec randomConfiguration(const ElementTypeInfo& t, const ElemVec& x0, std::mt19937& rng) {
  ElemVec x = x0;
  int k = 0;
  for (NodeKind s : t.slots) {
    if (s == NodeKind::Position) {
      x[k++] += uniform(rng, -0.3, 0.3);
      x[k++] += uniform(rng, -0.3, 0.3);
    } else {
      x[k++] += uniform(rng, -0.6, 0.6);
    }
  }
  return rigidMotion(t, x, uniform(rng, -kPi, kPi), uniform(rng, -1, 1), uniform(rng, -1, 1));
}

ElemVec randomVector(int n, std::mt19937& rng) {
  ElemVec v(n);
  for (int i = 0; i < n; ++i) v[i] = uniform(rng, -1, 1);
  return v;
}

template <class A, class B>
double relErr(const A& a, const B& ref, double floor = 1e-9) {
  return test::maxRelativeError(a, ref, floor);
}

constexpr int kConfigs = 25;
constexpr double kH = 1e-6;

// Every case at kConfigs random configurations (the element made at a random initial one, then
// moved): check(case, element, x, rng, k) returns its relative error there; the largest per case is
// printed.
template <class Check>
void forEachConfiguration(unsigned seed, const char* what, Check check) {
  std::mt19937 rng(seed);
  for (const Case& c : cases()) {
    const ElementTypeInfo* t = findElementType(c.keyword);
    ASSERT_NE(t, nullptr);
    double worst = 0.0;
    for (int k = 0; k < kConfigs; ++k) {
      const ElemVec x0 = randomInitial(*t, rng);
      auto el = t->create(x0, ElementOptions{c.elongation});
      const ElemVec x = randomConfiguration(*t, x0, rng);
      worst = std::max(worst, check(c, *el, x, rng, k));
    }
    std::printf("[ max rel err ] %-17s %-32s %.2e\n", what, c.label.c_str(), worst);
  }
}

}  // namespace

TEST(Elements, JacobianMatchesFiniteDifferences) {
  forEachConfiguration(1, "jacobian", [](const Case& c, const Element& el, const ElemVec& x, std::mt19937&, int k) {
    DefJac J;
    el.jacobian(x, J);
    EXPECT_EQ(J.rows(), el.numDeformations());
    EXPECT_EQ(J.cols(), el.numCoords());
    if (J.rows() != el.numDeformations() || J.cols() != el.numCoords()) return 1.0;
    const double err = relErr(J, test::jacobianByDifferences(el, x, kH));
    EXPECT_LT(err, 1e-6) << c.label << " config " << k;
    return err;
  });
}

TEST(Elements, SecondDerivativeMatchesFiniteDifferences) {
  forEachConfiguration(2, "secondDerivative",
                       [](const Case& c, const Element& el, const ElemVec& x, std::mt19937& rng, int k) {
                         const int n = el.numCoords();
                         const ElemVec v = randomVector(n, rng);
                         DefVec d2;
                         el.secondDerivative(x, v, d2);
                         // d/ds [D'(x + s v) v] at s = 0, by central differences of the Jacobian.
                         DefJac Jp, Jm;
                         el.jacobian(x + kH * v, Jp);
                         el.jacobian(x - kH * v, Jm);
                         const DefVec ref = (Jp - Jm) * v / (2 * kH);
                         // And independently by second differences of the deformations (looser step).
                         const double h2 = 1e-4;
                         DefVec ep, e0, em;
                         el.deformations(x + h2 * v, ep);
                         el.deformations(x, e0);
                         el.deformations(x - h2 * v, em);
                         const DefVec ref2 = (ep - 2 * e0 + em) / (h2 * h2);
                         const double err = relErr(d2, ref);
                         EXPECT_LT(err, 1e-6) << c.label << " config " << k;
                         // Second differences lose ~eps |e| / h2^2 to cancellation: absolute tolerance on that scale.
                         const double tol2 = 1e-6 * (1.0 + d2.cwiseAbs().maxCoeff() + e0.cwiseAbs().maxCoeff());
                         EXPECT_LT((d2 - ref2).cwiseAbs().maxCoeff(), tol2) << c.label << " config " << k;
                         return err;
                       });
}

TEST(Elements, StressWeightedHessianMatchesFiniteDifferences) {
  forEachConfiguration(
      3, "stressWeightedHes", [](const Case& c, const Element& el, const ElemVec& x, std::mt19937& rng, int k) {
        DefVec sigma(el.numDeformations());
        for (int i = 0; i < sigma.size(); ++i) sigma[i] = uniform(rng, -10, 10);
        return test::checkStressWeightedHessian(el, x, sigma, rng, kH, c.label + " config " + std::to_string(k));
      });
}

// The beam deformations evaluated literally as printed in the paper (Eq. 3a-3c), with
// phi = BETA - BETA0 + beta0 as the nodal rotation measured like the paper's (phi + beta0).
TEST(Elements, BeamDeformationsMatchPaperFormulas) {
  std::mt19937 rng(4);
  for (const Case& c : cases()) {
    if (c.keyword.rfind("PLBEAM", 0) != 0) continue;
    const ElementTypeInfo* t = findElementType(c.keyword);
    const bool corrected = c.keyword == "PLBEAMNL" || c.elongation == ElongationDefinition::BendingCorrected;
    for (int k = 0; k < kConfigs; ++k) {
      const ElemVec x0 = randomInitial(*t, rng);
      auto el = t->create(x0, ElementOptions{c.elongation});
      const ElemVec x = randomConfiguration(*t, x0, rng);
      const double l0 = std::hypot(x0[3] - x0[0], x0[4] - x0[1]);
      const double beta0 = std::atan2(x0[4] - x0[1], x0[3] - x0[0]);
      const double php = x[2] - x0[2], phq = x[5] - x0[5];  // rotations since the start
      const double dx = x[3] - x[0], dy = x[4] - x[1], l = std::sqrt(dx * dx + dy * dy);
      const double e2 = l0 / l * (dx * std::sin(php + beta0) - dy * std::cos(php + beta0));
      const double e3 = -l0 / l * (dx * std::sin(phq + beta0) - dy * std::cos(phq + beta0));
      double e1 = l - l0;
      if (corrected) e1 += (2 * e2 * e2 + e2 * e3 + 2 * e3 * e3) / (30 * l0);
      DefVec e;
      el->deformations(x, e);
      ASSERT_EQ(e.size(), 3);
      EXPECT_NEAR(e[0], e1, 1e-13) << c.label;
      EXPECT_NEAR(e[1], e2, 1e-13) << c.label;
      EXPECT_NEAR(e[2], e3, 1e-13) << c.label;
    }
  }
}

TEST(Elements, TrussAndHingeDeformationsMatchDefinitions) {
  std::mt19937 rng(5);
  const ElementTypeInfo* truss = findElementType("PLTRUSS");
  const ElementTypeInfo* hinge = findElementType("PLHINGE");
  for (int k = 0; k < kConfigs; ++k) {
    ElemVec x0 = randomInitial(*truss, rng), x = randomConfiguration(*truss, x0, rng);
    DefVec e;
    truss->create(x0, {})->deformations(x, e);
    const double l0 = std::hypot(x0[2] - x0[0], x0[3] - x0[1]);
    EXPECT_NEAR(e[0], std::hypot(x[2] - x[0], x[3] - x[1]) - l0, 1e-13);
    x0 = randomInitial(*hinge, rng);
    x = randomConfiguration(*hinge, x0, rng);
    hinge->create(x0, {})->deformations(x, e);
    EXPECT_NEAR(e[0], (x[1] - x[0]) - (x0[1] - x0[0]), 1e-13);
  }
}

TEST(Elements, RigidMotionInvariance) {
  std::mt19937 rng(6);
  for (const Case& c : cases()) {
    const ElementTypeInfo* t = findElementType(c.keyword);
    double worst = 0.0;
    for (int k = 0; k < kConfigs; ++k) {
      const ElemVec x0 = randomInitial(*t, rng);
      auto el = t->create(x0, ElementOptions{c.elongation});
      const ElemVec x = randomConfiguration(*t, x0, rng);
      const ElemVec y = rigidMotion(*t, x, uniform(rng, -2 * kPi, 2 * kPi), uniform(rng, -3, 3), uniform(rng, -3, 3));
      DefVec ex, ey;
      el->deformations(x, ex);
      el->deformations(y, ey);
      const double err = relErr(ey, ex, 1e-2);  // coordinates are O(1)
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-12) << c.label;
    }
    std::printf("[ max rel err ] rigid invariance  %-32s %.2e\n", c.label.c_str(), worst);
  }
}

TEST(Elements, ZeroDeformationInInitialConfiguration) {
  std::mt19937 rng(7);
  for (const Case& c : cases()) {
    const ElementTypeInfo* t = findElementType(c.keyword);
    for (int k = 0; k < kConfigs; ++k) {
      const ElemVec x0 = randomInitial(*t, rng);  // nonzero BETA, arbitrary chord angle
      auto el = t->create(x0, ElementOptions{c.elongation});
      DefVec e;
      el->deformations(x0, e);
      ASSERT_EQ(e.size(), t->numDeformations());
      EXPECT_LT(e.cwiseAbs().maxCoeff(), 1e-14) << c.label;
      // Still zero after a rigid motion of the initial configuration.
      el->deformations(rigidMotion(*t, x0, 1.234, -0.5, 2.0), e);
      EXPECT_LT(e.cwiseAbs().maxCoeff(), 1e-13) << c.label;
    }
  }
}

TEST(Elements, BeamBendingSignConvention) {
  // Straight beam along x, BETA = 0.3 at both nodes. Rotating node p counterclockwise by a small
  // angle gives e2 = +l0 * angle; rotating node q counterclockwise gives e3 = -l0 * angle.
  ElemVec x0(6);
  x0 << 1.0, 2.0, 0.3, 3.0, 2.0, 0.3;
  PlanarBeam b(x0, ElongationDefinition::Plain);
  EXPECT_DOUBLE_EQ(b.l0(), 2.0);
  EXPECT_DOUBLE_EQ(b.beta0(), 0.0);
  ElemVec x = x0;
  x[2] += 1e-3;
  DefVec e;
  b.deformations(x, e);
  EXPECT_NEAR(e[1], 2.0 * std::sin(1e-3), 1e-15);
  EXPECT_NEAR(e[2], 0.0, 1e-15);
  x = x0;
  x[5] += 1e-3;
  b.deformations(x, e);
  EXPECT_NEAR(e[1], 0.0, 1e-15);
  EXPECT_NEAR(e[2], -2.0 * std::sin(1e-3), 1e-15);
}

TEST(Elements, ConstitutiveMatrices) {
  std::mt19937 rng(8);
  for (int k = 0; k < 5; ++k) {
    const ElemVec x0 = randomInitial(*findElementType("PLBEAM"), rng);
    const double l0 = std::hypot(x0[3] - x0[0], x0[4] - x0[1]);
    const double EA = uniform(rng, 1e3, 1e8), EI = uniform(rng, 1, 1e4);
    const double p[2] = {EA, EI};
    for (const char* kw : {"PLBEAM", "PLBEAMNL"}) {
      auto el = findElementType(kw)->create(x0, {});
      DefMat S;
      el->constitutive(p, S);
      ASSERT_EQ(S.rows(), 3);
      ASSERT_EQ(S.cols(), 3);
      const double kb = EI / (l0 * l0 * l0);
      Eigen::Matrix3d ref;
      ref << EA / l0, 0, 0, 0, 4 * kb, -2 * kb, 0, -2 * kb, 4 * kb;
      EXPECT_LT(relErr(S, ref, 1e-300), 1e-14) << kw;
    }
    ElemVec xt(4);
    xt << x0[0], x0[1], x0[3], x0[4];
    DefMat S;
    findElementType("PLTRUSS")->create(xt, {})->constitutive(p, S);
    ASSERT_EQ(S.rows(), 1);
    EXPECT_NEAR(S(0, 0), EA / l0, 1e-14 * EA / l0);
    ElemVec xh(2);
    xh << 0.4, -1.1;
    const double kh[1] = {5e3};
    findElementType("PLHINGE")->create(xh, {})->constitutive(kh, S);
    ASSERT_EQ(S.rows(), 1);
    EXPECT_DOUBLE_EQ(S(0, 0), 5e3);
  }
}

TEST(Elements, Registry) {
  using enum NodeKind;
  const ElementTypeInfo* b = findElementType("plbeam");
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->keyword, "PLBEAM");
  EXPECT_EQ(b->slots, (std::vector<NodeKind>{Position, Orientation, Position, Orientation}));
  EXPECT_EQ(b->numCoords(), 6);
  EXPECT_EQ(b->numDeformations(), 3);
  EXPECT_EQ(b->deformationNames, (std::vector<std::string>{"elongation", "bending p", "bending q"}));
  EXPECT_EQ(b->stiffness.size(), 2u);
  ASSERT_NE(findElementType("PlBeamNL"), nullptr);
  EXPECT_EQ(findElementType("PlBeamNL")->keyword, "PLBEAMNL");
  EXPECT_EQ(findElementType("PLBEAMNL")->numCoords(), 6);
  const ElementTypeInfo* t = findElementType("pltruss");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->slots, (std::vector<NodeKind>{Position, Position}));
  EXPECT_EQ(t->numCoords(), 4);
  EXPECT_EQ(t->numDeformations(), 1);
  EXPECT_EQ(t->stiffness.size(), 1u);
  const ElementTypeInfo* h = findElementType("PLHINGE");
  ASSERT_NE(h, nullptr);
  EXPECT_EQ(h->slots, (std::vector<NodeKind>{Orientation, Orientation}));
  EXPECT_EQ(h->numCoords(), 2);
  EXPECT_EQ(h->numDeformations(), 1);
  ASSERT_NE(findElementType("BEAM"), nullptr);  // spatial: test_spatial_elements.cpp
  EXPECT_EQ(findElementType("PLBEAMX"), nullptr);
  EXPECT_EQ(findElementType(""), nullptr);
  for (const ElementTypeInfo& info : elementTypes()) {
    if (isSpatial(info.slots[0])) continue;  // test_spatial_elements.cpp
    ASSERT_NE(info.create, nullptr) << info.keyword;
    std::mt19937 rng(9);
    auto el = info.create(randomInitial(info, rng), {});
    EXPECT_EQ(el->numCoords(), info.numCoords()) << info.keyword;
    EXPECT_EQ(el->numDeformations(), info.numDeformations()) << info.keyword;
  }
  // Element knowledge kept in the registry: hinge angles are large rotations (a reduction basis
  // keeps them), beams are drawn curved.
  EXPECT_EQ(h->largeRotations, std::vector<int>{0});
  EXPECT_TRUE(h->isLargeRotation(0));
  EXPECT_FALSE(b->isLargeRotation(0));
  EXPECT_TRUE(b->drawnCurved);
  EXPECT_FALSE(t->drawnCurved);
  ASSERT_NE(findElementType("HINGE"), nullptr);
  EXPECT_EQ(findElementType("HINGE")->largeRotations, std::vector<int>{0});  // the tilts stay small
  for (const ElementTypeInfo* info : test::allElementTypes()) {
    for (int i : info->largeRotations) {
      EXPECT_GE(i, 0) << info->keyword;
      EXPECT_LT(i, info->numDeformations()) << info->keyword;
    }
    // The planar curve is the planar beam's field from its bending deformations e2, e3; the spatial
    // one the cubic through the end triads (MechanismGeometry).
    if (info->drawnCurved && !isSpatial(info->slots[0])) {
      EXPECT_EQ(info->slots, (std::vector<NodeKind>{Position, Orientation, Position, Orientation})) << info->keyword;
      EXPECT_EQ(info->numDeformations(), 3) << info->keyword;
    }
    if (info->drawnCurved && isSpatial(info->slots[0])) {
      EXPECT_EQ(info->slots,
                (std::vector<NodeKind>{SpatialPosition, EulerParameters, SpatialPosition, EulerParameters}))
          << info->keyword;
    }
  }
  // SPACAR's type codes (the .sbd `it`, io/results.md) where they are known, flexmb's own above 100
  // otherwise; only an element's variants (the NL beams: same slots and deformations) share a code.
  EXPECT_EQ(b->spacarTypeId, 5);
  EXPECT_EQ(findElementType("PLBEAMNL")->spacarTypeId, 5);
  EXPECT_EQ(t->spacarTypeId, 7);
  EXPECT_EQ(findElementType("BEAM")->spacarTypeId, 1);
  EXPECT_EQ(findElementType("BEAMNL")->spacarTypeId, 1);
  EXPECT_EQ(findElementType("TRUSS")->spacarTypeId, 2);
  EXPECT_EQ(findElementType("HINGE")->spacarTypeId, 3);  // SPACAR's slidercrank.sbd (io/results.md)
  EXPECT_EQ(normalisationType().spacarTypeId, 4);
  for (const ElementTypeInfo* info : test::allElementTypes()) {
    EXPECT_GT(info->spacarTypeId, 0) << info->keyword;
    for (const ElementTypeInfo* other : test::allElementTypes())
      if (other != info && other->spacarTypeId == info->spacarTypeId) {
        EXPECT_EQ(other->slots, info->slots) << info->keyword << " and " << other->keyword;
        EXPECT_EQ(other->deformationNames, info->deformationNames) << info->keyword << " and " << other->keyword;
      }
  }
  // PLBEAMNL ignores the elongation option; PLBEAM follows it.
  ElemVec x0(6);
  x0 << 0, 0, 0, 1, 0, 0;
  ElemVec x = x0;
  x[2] = 0.2;
  DefVec ep, ec, enl;
  b->create(x0, ElementOptions{ElongationDefinition::Plain})->deformations(x, ep);
  b->create(x0, ElementOptions{ElongationDefinition::BendingCorrected})->deformations(x, ec);
  findElementType("PLBEAMNL")->create(x0, ElementOptions{ElongationDefinition::Plain})->deformations(x, enl);
  EXPECT_DOUBLE_EQ(ep[0], 0.0);
  EXPECT_GT(ec[0], 0.0);
  EXPECT_DOUBLE_EQ(enl[0], ec[0]);
}

TEST(Elements, ZeroLengthRejected) {
  ElemVec x0(6);
  x0 << 1, 1, 0, 1, 1, 0;
  EXPECT_THROW(findElementType("PLBEAM")->create(x0, {}), std::invalid_argument);
  ElemVec xt(4);
  xt << 1, 1, 1, 1;
  EXPECT_THROW(findElementType("PLTRUSS")->create(xt, {}), std::invalid_argument);
}

TEST(Elements, FusedKernelsEqualTheSeparateCalls) {
  // deformationsAndJacobian and dynamicTerms (one geometry evaluation) give exactly what
  // the separate calls give.
  std::mt19937 rng(11);
  ElementOptions opt;
  for (const auto& c : cases()) {
    const ElementTypeInfo* t = findElementType(c.keyword);
    ASSERT_NE(t, nullptr);
    opt.elongation = c.elongation;
    ElementInertia inertia;
    inertia.rhoA = 1.3;
    inertia.rhoI = 2e-3;
    for (int k = 0; k < 5; ++k) {
      const ElemVec x0 = randomInitial(*t, rng);
      const auto el = t->create(x0, opt);
      const ElemVec x = randomConfiguration(*t, x0, rng), v = randomVector(t->numCoords(), rng);
      DefVec e1, e2;
      DefJac J1, J2;
      el->deformations(x, e1);
      el->jacobian(x, J1);
      el->deformationsAndJacobian(x, e2, J2);
      EXPECT_EQ(e1, e2) << c.label;
      EXPECT_EQ(J1, J2) << c.label;
      ElemMat M1, M2;
      ElemVec h1, h2;
      DefVec d1, d2;
      el->mass(x, inertia, M1);
      el->velocityForces(x, v, inertia, h1);
      el->secondDerivative(x, v, d1);
      el->dynamicTerms(x, v, inertia, M2, h2, d2);
      EXPECT_EQ(M1, M2) << c.label;
      EXPECT_EQ(h1, h2) << c.label;
      EXPECT_EQ(d1, d2) << c.label;
    }
  }
}

TEST(Elements, PlacementInvertsTheDeformations) {
  // Element::place (open chains in one pass): from one end and e = D(x), the other end is x's.
  std::mt19937 rng(5);
  ElementOptions opt;
  for (const auto& c : cases()) {
    const ElementTypeInfo* t = findElementType(c.keyword);
    opt.elongation = c.elongation;
    const auto probe = t->create(randomInitial(*t, rng), opt);
    if (probe->endOfCoordinate(0) < 0) continue;  // no closed form (PLTRUSS)
    for (int k = 0; k < 10; ++k) {
      const ElemVec x0 = randomInitial(*t, rng);
      const auto el = t->create(x0, opt);
      const ElemVec x = randomConfiguration(*t, x0, rng);
      DefVec e;
      el->deformations(x, e);
      for (int to = 0; to < 2; ++to) {
        ElemVec y = x;
        for (int i = 0; i < y.size(); ++i)
          if (el->endOfCoordinate(i) == to) y[i] = 1e3;  // unknown
        if (!el->place(e, to, y)) {
          // Only a configuration off the valid branch (a node turned past 90 degrees) has none.
          EXPECT_FALSE(el->validity(x).valid) << c.label;
          continue;
        }
        DefVec e2;
        el->deformations(y, e2);
        EXPECT_LT((e2 - e).cwiseAbs().maxCoeff(), 1e-12) << c.label << ", to " << to;
        if (el->validity(x).valid) {
          // On the valid branch the placement is the configuration itself (angles modulo 2 pi).
          for (int i = 0; i < y.size(); ++i) {
            const double d = t->slots[0] == NodeKind::Orientation || (i == 2 || i == 5)
                                 ? std::remainder(y[i] - x[i], 2 * kPi)
                                 : y[i] - x[i];
            EXPECT_LT(std::abs(d), 1e-10) << c.label << ", to " << to << ", coordinate " << i;
          }
        }
      }
    }
  }
}
