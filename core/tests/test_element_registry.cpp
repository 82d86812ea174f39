// Every registered element type (and the automatic L2MIN1), from sample elements generated from the
// type's slots (ElementSamples.hpp): analytic derivatives against central finite differences,
// deformations zero initially and invariant under rigid motions, the fused kernels equal to the
// separate calls, the inertia (symmetric, positive semidefinite, velocity forces from Lagrange's
// equations, the whole mass carried by a translation, gravity) and the closed-form placement. A
// new element type is tested here the moment it is registered; the per-element tests
// (test_elements.cpp, test_spatial_elements.cpp, test_beam_*.cpp) check the formulas themselves.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/tests/ElementSamples.hpp"

using namespace flexmb::core;
using namespace flexmb::core::test;

namespace {

constexpr int kConfigs = 12;
constexpr double kH = 1e-6;

template <class A, class B>
double relErr(const A& a, const B& ref, double floor = 1e-9) {
  return maxRelativeError(a, ref, floor);
}

// Runs body(element sample, deformed configuration, rng) at kConfigs samples of every case and
// prints the worst value body returns.
template <class Body>
void forEverySample(const char* what, unsigned seed, Body&& body) {
  std::mt19937 rng(seed);
  for (const ElementCase& c : allElementCases()) {
    double worst = 0.0;
    for (int k = 0; k < kConfigs; ++k) {
      const ElementSample s = sampleElement(c, rng);
      const ElemVec x = sampleConfiguration(*c.type, s.x0, rng);
      worst = std::max(worst, body(c, s, x, rng));
    }
    std::printf("[ registry ] %-28s %-18s %.2e\n", what, c.label.c_str(), worst);
  }
}

}  // namespace

TEST(ElementRegistry, EveryTypeIsCreatedFromItsSlots) {
  std::mt19937 rng(1);
  const auto types = allElementTypes();
  ASSERT_GE(types.size(), 10u);
  for (const ElementCase& c : allElementCases()) {
    const ElementTypeInfo& t = *c.type;
    ASSERT_FALSE(t.slots.empty()) << c.label;
    EXPECT_LE(t.numCoords(), kMaxElemCoords) << c.label;
    EXPECT_LE(t.numDeformations(), kMaxElemDefs) << c.label;
    ASSERT_TRUE(t.vector.empty() ? t.create != nullptr : t.createWithVector != nullptr) << c.label;
    const ElementSample s = sampleElement(c, rng);
    ASSERT_NE(s.element, nullptr) << c.label;
    EXPECT_EQ(s.element->numCoords(), t.numCoords()) << c.label;
    EXPECT_EQ(s.element->numDeformations(), t.numDeformations()) << c.label;
    // The constitutive matrix of any parameter set in the type's layout: square, symmetric.
    std::vector<double> p(t.stiffness.size());
    for (double& v : p) v = uniform(rng, 1, 10);
    DefMat S;
    s.element->constitutive(p, S);
    ASSERT_EQ(S.rows(), t.numDeformations()) << c.label;
    ASSERT_EQ(S.cols(), t.numDeformations()) << c.label;
    EXPECT_EQ(S, DefMat(S.transpose())) << c.label;
    EXPECT_TRUE(S.allFinite()) << c.label;
    // A keyword type says what each deformation measures, and every EM parameter of its layout
    // names an inertia field (ModelBuilder fills them by name).
    if (!t.internal) {
      EXPECT_EQ(static_cast<int>(t.deformationKinds.size()), t.numDeformations()) << c.label;
    }
    for (const ParameterSpec& em : t.inertia)
      EXPECT_NE(ElementInertia::field(em.name), nullptr) << c.label << " " << em.name;
  }
}

TEST(ElementRegistry, ZeroInitiallyAndInvariantUnderRigidMotion) {
  forEverySample("rigid-motion invariance", 2,
                 [](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937& rng) {
                   DefVec e0, e1, ex, ey;
                   s.element->deformations(s.x0, e0);
                   EXPECT_EQ(e0.size(), c.type->numDeformations()) << c.label;
                   EXPECT_LT(e0.cwiseAbs().maxCoeff(), 1e-12) << c.label;
                   s.element->deformations(randomRigidMotion(*c.type, s.x0, rng), e1);
                   EXPECT_LT(e1.cwiseAbs().maxCoeff(), 1e-12) << c.label;
                   s.element->deformations(x, ex);
                   s.element->deformations(randomRigidMotion(*c.type, x, rng), ey);
                   // Angles known modulo 2 pi (a spatial hinge's principal value) compare modulo 2 pi.
                   DefVec d = ey - ex;
                   for (int i = 0; i < d.size(); ++i)
                     if (s.element->isPeriodicAngle(i)) d[i] = std::remainder(d[i], 2 * M_PI);
                   const double err = d.cwiseAbs().maxCoeff() / std::max(1.0, ex.cwiseAbs().maxCoeff());
                   EXPECT_LT(err, 1e-12) << c.label;
                   return err;
                 });
}

TEST(ElementRegistry, JacobianMatchesFiniteDifferences) {
  forEverySample("jacobian", 3, [](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937&) {
    const Element& el = *s.element;
    const int n = el.numCoords(), m = el.numDeformations();
    DefJac J;
    el.jacobian(x, J);
    EXPECT_EQ(J.rows(), m) << c.label;
    EXPECT_EQ(J.cols(), n) << c.label;
    const DefJac Jfd = jacobianByDifferences(el, x, kH);
    const double err = relErr(J, Jfd);
    EXPECT_LT(err, 1e-6) << c.label;
    // The fused call gives exactly the separate ones.
    DefVec e, e2;
    DefJac J2;
    el.deformations(x, e);
    el.deformationsAndJacobian(x, e2, J2);
    EXPECT_EQ(e, e2) << c.label;
    EXPECT_EQ(J, J2) << c.label;
    return err;
  });
}

TEST(ElementRegistry, SecondDerivativeMatchesFiniteDifferences) {
  forEverySample("secondDerivative", 4,
                 [](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937& rng) {
                   const Element& el = *s.element;
                   const ElemVec v = randomVector(el.numCoords(), rng);
                   DefVec d2;
                   el.secondDerivative(x, v, d2);
                   EXPECT_EQ(d2.size(), el.numDeformations()) << c.label;
                   // d/ds [D'(x + s v) v] at s = 0, by central differences of the analytic Jacobian.
                   DefJac Jp, Jm;
                   el.jacobian(x + kH * v, Jp);
                   el.jacobian(x - kH * v, Jm);
                   const DefVec ref = (Jp - Jm) * v / (2 * kH);
                   const double err = relErr(d2, ref);
                   EXPECT_LT(err, 1e-6) << c.label;
                   return err;
                 });
}

TEST(ElementRegistry, StressWeightedHessianMatchesFiniteDifferences) {
  forEverySample("stressWeightedHessian", 5,
                 [](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937& rng) {
                   const Element& el = *s.element;
                   const int m = el.numDeformations();
                   DefVec sigma(m);
                   for (int i = 0; i < m; ++i) sigma[i] = uniform(rng, -10, 10);
                   if (m > 1) sigma[m - 1] = 0.0;  // a deformation without stress
                   return checkStressWeightedHessian(el, x, sigma, rng, kH, c.label);
                 });
}

TEST(ElementRegistry, MassIsSymmetricPositiveAndItsVelocityForcesFollowFromLagrange) {
  const ElementInertia in = sampleInertia();
  forEverySample(
      "velocity forces (Lagrange)", 6,
      [&](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937& rng) {
        const Element& el = *s.element;
        const int n = el.numCoords();
        const ElemVec xd = randomVector(n, rng);
        ElemMat M;
        el.mass(x, in, M);
        EXPECT_EQ(M.rows(), n) << c.label;
        EXPECT_EQ(M.cols(), n) << c.label;
        const double scale = std::max(M.cwiseAbs().maxCoeff(), 1e-300);
        EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff() / scale, 1e-14) << c.label;
        const Eigen::MatrixXd Md = M;
        EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Md).eigenvalues().minCoeff(), -1e-12 * scale)
            << c.label;
        // h = (dM/dx xd) xd - 1/2 d(xd^T M xd)/dx (Lagrange's equations with T = 1/2 xd^T M(x) xd).
        ElemMat Mp, Mm;
        el.mass(x + kH * xd, in, Mp);
        el.mass(x - kH * xd, in, Mm);
        ElemVec ref = (Mp - Mm) * xd / (2 * kH);
        for (int j = 0; j < n; ++j) {
          ElemVec xp = x, xm = x;
          xp[j] += kH;
          xm[j] -= kH;
          el.mass(xp, in, Mp);
          el.mass(xm, in, Mm);
          ref[j] -= 0.5 * xd.dot((Mp - Mm) * xd) / (2 * kH);
        }
        ElemVec h;
        el.velocityForces(x, xd, in, h);
        EXPECT_EQ(h.size(), n) << c.label;
        const double err = (h - ref).cwiseAbs().maxCoeff() / std::max(1.0, ref.cwiseAbs().maxCoeff());
        EXPECT_LT(err, 1e-6) << c.label;
        // The fused call gives exactly the separate ones.
        ElemMat M2;
        ElemVec h2;
        DefVec d1, d2;
        el.secondDerivative(x, xd, d1);
        el.dynamicTerms(x, xd, in, M2, h2, d2);
        EXPECT_EQ(M, M2) << c.label;
        EXPECT_EQ(h, h2) << c.label;
        EXPECT_EQ(d1, d2) << c.label;
        return err;
      });
}

TEST(ElementRegistry, ATranslationCarriesTheWholeMassAndGravityActsOnIt) {
  // An element between two position nodes carries rhoA l0: moving every position node by u gives
  // u^T M u = rhoA l0 |u|^2 in any configuration, and gravity does work rhoA l0 g . u.
  const ElementInertia in = sampleInertia();
  forEverySample("translation mass, gravity", 7,
                 [&](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937& rng) {
                   const ElementTypeInfo& t = *c.type;
                   const auto p0 = positionsOf(t, s.x0);
                   if (p0.size() != 2) return 0.0;  // not a line element
                   const int d = nodeKindDim(*std::find_if(t.slots.begin(), t.slots.end(), isTranslational));
                   Eigen::Vector3d u = Eigen::Vector3d::Zero(), g = Eigen::Vector3d::Zero();
                   for (int i = 0; i < d; ++i) u[i] = uniform(rng, -1, 1), g[i] = uniform(rng, -10, 10);
                   ElemVec U = ElemVec::Zero(t.numCoords());
                   int k = 0;
                   for (NodeKind kind : t.slots) {
                     if (isTranslational(kind)) U.segment(k, d) = u.head(d);
                     k += nodeKindDim(kind);
                   }
                   const double m = in.rhoA * (p0[1] - p0[0]).norm();
                   ElemMat M;
                   s.element->mass(x, in, M);
                   ElemVec f;
                   s.element->gravityForces3(x, in, g.data(), f);
                   const double e1 = std::abs(U.dot(M * U) - m * u.squaredNorm()) / (m * u.squaredNorm());
                   const double e2 = std::abs(f.dot(U) - m * g.dot(u)) / (m * g.norm() * u.norm());
                   EXPECT_LT(e1, 1e-12) << c.label;
                   EXPECT_LT(e2, 1e-12) << c.label;
                   return std::max(e1, e2);
                 });
}

TEST(ElementRegistry, PlacementInvertsTheDeformations) {
  // Element::place (open chains in one pass): from one end and e = D(x), the other end is x's.
  forEverySample("placement", 8, [](const ElementCase& c, const ElementSample& s, const ElemVec& x, std::mt19937&) {
    const Element& el = *s.element;
    const ElementTypeInfo& t = *c.type;
    if (el.endOfCoordinate(0) < 0) return 0.0;  // no closed form
    std::vector<bool> angle;
    for (NodeKind kind : t.slots)
      for (int i = 0; i < nodeKindDim(kind); ++i) angle.push_back(kind == NodeKind::Orientation);
    DefVec e;
    el.deformations(x, e);
    double worst = 0.0;
    for (int to = 0; to < 2; ++to) {
      ElemVec y = x;
      for (int i = 0; i < y.size(); ++i)
        if (el.endOfCoordinate(i) == to) y[i] = 1e3;  // unknown
      if (!el.place(e, to, y)) {
        // Only a configuration off the valid branch has none.
        EXPECT_FALSE(el.validity(x).valid) << c.label;
        continue;
      }
      DefVec e2;
      el.deformations(y, e2);
      worst = std::max(worst, (e2 - e).cwiseAbs().maxCoeff());
      EXPECT_LT((e2 - e).cwiseAbs().maxCoeff(), 1e-12) << c.label << ", to " << to;
      if (el.validity(x).valid)  // on the valid branch: the configuration itself (angles modulo 2 pi)
        for (int i = 0; i < y.size(); ++i) {
          const double dy = angle[i] ? std::remainder(y[i] - x[i], 2 * M_PI) : y[i] - x[i];
          EXPECT_LT(std::abs(dy), 1e-10) << c.label << ", to " << to << ", coordinate " << i;
        }
    }
    return worst;
  });
}
