#pragma once
// Sample elements of every registered type, generated from the type's slots (node kinds) and its
// direction vector alone, so that the registry-driven tests (test_element_registry.cpp) cover an
// element type the moment it is registered.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/elements/Element.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/tests/Differences.hpp"

namespace flexmb::core::test {

inline double uniform(std::mt19937& rng, double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng);
}

// Every element type: the keyword registry and the automatic L2MIN1.
inline std::vector<const ElementTypeInfo*> allElementTypes() {
  std::vector<const ElementTypeInfo*> all;
  for (const ElementTypeInfo& t : elementTypes()) all.push_back(&t);
  all.push_back(&normalisationType());
  return all;
}

// A type under one set of element options (the planar beam's elongation follows them; every type
// is taken with both, so a new option-dependent type is covered too).
struct ElementCase {
  const ElementTypeInfo* type;
  ElementOptions options;
  std::string label;
};
inline std::vector<ElementCase> allElementCases() {
  std::vector<ElementCase> cases;
  for (const ElementTypeInfo* t : allElementTypes())
    for (ElongationDefinition d : {ElongationDefinition::Plain, ElongationDefinition::BendingCorrected})
      cases.push_back({t, ElementOptions{d}, t->keyword + (d == ElongationDefinition::Plain ? " (plain)" : "")});
  return cases;
}

// Positions of the position nodes of x (2 or 3 components each, zero-padded to 3).
inline std::vector<Eigen::Vector3d> positionsOf(const ElementTypeInfo& t, const ElemVec& x) {
  std::vector<Eigen::Vector3d> p;
  int k = 0;
  for (NodeKind s : t.slots) {
    if (isTranslational(s)) {
      Eigen::Vector3d v = Eigen::Vector3d::Zero();
      for (int c = 0; c < nodeKindDim(s); ++c) v[c] = x[k + c];
      p.push_back(v);
    }
    k += nodeKindDim(s);
  }
  return p;
}

// Smallest distance between two position nodes (infinity with fewer than two).
inline double closestNodes(const ElementTypeInfo& t, const ElemVec& x) {
  const auto p = positionsOf(t, x);
  double d = INFINITY;
  for (size_t a = 0; a < p.size(); ++a)
    for (size_t b = a + 1; b < p.size(); ++b) d = std::min(d, (p[b] - p[a]).norm());
  return d;
}

inline Eigen::Vector4d randomQuaternion(std::mt19937& rng) {
  Eigen::Vector4d q;
  do
    for (int i = 0; i < 4; ++i) q[i] = uniform(rng, -1, 1);
  while (q.norm() < 0.2);
  return q.normalized();
}

// R(a b) = R(a) R(b).
inline Eigen::Vector4d quaternionProduct(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  Eigen::Vector4d r;
  r[0] = a[0] * b[0] - a.tail<3>().dot(b.tail<3>());
  r.tail<3>() = a[0] * b.tail<3>() + b[0] * a.tail<3>() + a.tail<3>().cross(b.tail<3>());
  return r;
}

// An element in its initial configuration x0 (with its direction vector, when the type takes one).
struct ElementSample {
  ElemVec x0;
  std::array<double, 3> vector = {0.0, 0.0, 0.0};
  std::unique_ptr<Element> element;
};

// Random initial coordinates from the slots: positions in [-1.5, 1.5]^d at least 0.5 apart,
// planar angles in [-3, 3], unit Euler parameters; a direction vector at least 25 degrees off every
// chord.
inline ElementSample sampleElement(const ElementCase& c, std::mt19937& rng) {
  const ElementTypeInfo& t = *c.type;
  for (;;) {
    ElementSample s;
    s.x0.resize(t.numCoords());
    int k = 0;
    for (NodeKind kind : t.slots) {
      switch (kind) {
        case NodeKind::Position:
        case NodeKind::SpatialPosition:
          for (int i = 0; i < nodeKindDim(kind); ++i) s.x0[k + i] = uniform(rng, -1.5, 1.5);
          break;
        case NodeKind::Orientation:
          s.x0[k] = uniform(rng, -3, 3);
          break;
        case NodeKind::EulerParameters:
          s.x0.segment<4>(k) = randomQuaternion(rng);
          break;
        case NodeKind::Warping:  // an initial rate of twist (BEAMW)
          s.x0[k] = uniform(rng, -1, 1);
          break;
      }
      k += nodeKindDim(kind);
    }
    if (closestNodes(t, s.x0) < 0.5) continue;
    if (!t.vector.empty()) {
      Eigen::Vector3d v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      if (v.norm() < 0.3) continue;
      const auto p = positionsOf(t, s.x0);
      bool offChords = true;
      for (size_t a = 0; a < p.size(); ++a)
        for (size_t b = a + 1; b < p.size(); ++b)
          offChords = offChords && std::abs((p[b] - p[a]).normalized().dot(v.normalized())) < 0.9;
      if (!offChords) continue;
      s.vector = {v[0], v[1], v[2]};
      s.element = t.createWithVector(s.x0, s.vector.data(), c.options);
    } else {
      s.element = t.create(s.x0, c.options);
    }
    return s;
  }
}

// x moved rigidly: planar nodes rotated by angle about the origin and translated by (c0, c1), planar
// angles turned by angle; spatial positions rotated by the unit quaternion q and translated by c,
// Euler parameters premultiplied by q.
inline ElemVec rigidMotion(const ElementTypeInfo& t, const ElemVec& x, double angle, const Eigen::Vector4d& q,
                           const Eigen::Vector3d& c) {
  ElemVec y = x;
  const double cs = std::cos(angle), sn = std::sin(angle);
  const Eigen::Vector4d qn = q.normalized();
  const Eigen::Matrix3d R = euler::rotation(qn);
  int k = 0;
  for (NodeKind kind : t.slots) {
    switch (kind) {
      case NodeKind::Position:
        y[k] = cs * x[k] - sn * x[k + 1] + c[0];
        y[k + 1] = sn * x[k] + cs * x[k + 1] + c[1];
        break;
      case NodeKind::Orientation:
        y[k] = x[k] + angle;
        break;
      case NodeKind::SpatialPosition:
        y.segment<3>(k) = R * x.segment<3>(k) + c;
        break;
      case NodeKind::EulerParameters:
        y.segment<4>(k) = quaternionProduct(qn, x.segment<4>(k));
        break;
      case NodeKind::Warping:  // the rate of twist about the element's own axis: a scalar
        break;
    }
    k += nodeKindDim(kind);
  }
  return y;
}

// A random rigid motion of x.
inline ElemVec randomRigidMotion(const ElementTypeInfo& t, const ElemVec& x, std::mt19937& rng) {
  const Eigen::Vector3d c(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2));
  return rigidMotion(t, x, uniform(rng, -M_PI, M_PI), randomQuaternion(rng), c);
}

// A deformed configuration near x0: positions moved by up to 0.3, planar angles by up to 0.6, Euler
// parameters by up to 0.2 (not normalised: the derivatives hold for any lambda), warping coordinates
// by up to 0.3, then moved
// rigidly. Position nodes stay at least 0.2 apart (no chord near zero length).
inline ElemVec sampleConfiguration(const ElementTypeInfo& t, const ElemVec& x0, std::mt19937& rng) {
  for (;;) {
    ElemVec x = x0;
    int k = 0;
    for (NodeKind kind : t.slots) {
      const double size = kind == NodeKind::Orientation ? 0.6 : kind == NodeKind::EulerParameters ? 0.2 : 0.3;
      for (int i = 0; i < nodeKindDim(kind); ++i) x[k + i] += uniform(rng, -size, size);
      k += nodeKindDim(kind);
    }
    if (closestNodes(t, x) < 0.2) continue;
    return randomRigidMotion(t, x, rng);
  }
}

// Distributed inertia with every field set (each type reads its own: planar rhoA rhoI, spatial
// rhoA Jxx Jyy Jzz Jyz, BEAMW also Jw, L2MIN1 the full body tensor), positive definite.
inline ElementInertia sampleInertia() {
  ElementInertia in;
  in.rhoA = 1.3;
  in.rhoI = 2e-3;
  in.jxx = 0.05, in.jyy = 0.04, in.jzz = 0.06;
  in.jyz = 0.005, in.jxy = 0.002, in.jxz = -0.003;
  in.jw = 7e-3;
  return in;
}

inline ElemVec randomVector(int n, std::mt19937& rng) {
  ElemVec v(n);
  for (int i = 0; i < n; ++i) v[i] = uniform(rng, -1, 1);
  return v;
}

// The reference for an element's analytic Jacobian; a periodic angle's difference is taken modulo
// 2 pi.
inline DefJac jacobianByDifferences(const Element& el, const ElemVec& x, double h) {
  DefJac J = centralDifferences(
      [&](const Eigen::VectorXd& at) {
        DefVec e;
        el.deformations(at, e);
        return Eigen::VectorXd(e);
      },
      x, h);
  for (int i = 0; i < J.rows(); ++i)
    if (el.isPeriodicAngle(i))
      for (int j = 0; j < J.cols(); ++j) J(i, j) = std::remainder(J(i, j) * 2 * h, 2 * M_PI) / (2 * h);
  return J;
}

// The reference for the stress-weighted Hessian sum_i sigma_i d2 e_i / dx2: differences of
// D(x)^T sigma, the analytic Jacobian's.
inline ElemMat stressHessianByDifferences(const Element& el, const ElemVec& x, const DefVec& sigma, double h) {
  return centralDifferences(
      [&](const Eigen::VectorXd& at) {
        DefJac J;
        el.jacobian(at, J);
        return Eigen::VectorXd(J.transpose() * sigma);
      },
      x, h);
}

// The stress-weighted Hessian at x against central differences (step h) of D^T sigma, its symmetry,
// and its consistency with secondDerivative (v^T H v = sigma . D2e[v, v] for a random v); returns
// its relative error (1 when its size is wrong).
inline double checkStressWeightedHessian(const Element& el, const ElemVec& x, const DefVec& sigma, std::mt19937& rng,
                                         double h, const std::string& label) {
  const int n = el.numCoords();
  ElemMat H;
  el.stressWeightedHessian(x, sigma, H);
  EXPECT_EQ(H.rows(), n) << label;
  EXPECT_EQ(H.cols(), n) << label;
  if (H.rows() != n || H.cols() != n) return 1.0;
  const double err = maxRelativeError(H, stressHessianByDifferences(el, x, sigma, h));
  EXPECT_LT(err, 1e-6) << label;
  EXPECT_LT(maxRelativeError(H, ElemMat(H.transpose()), 1e-300), 1e-14) << "symmetry, " << label;
  const ElemVec v = randomVector(n, rng);
  DefVec d2;
  el.secondDerivative(x, v, d2);
  const double a = v.dot(H * v), b = sigma.dot(d2);
  EXPECT_NEAR(a, b, 1e-10 * std::max({1.0, std::abs(a), std::abs(b)})) << label;
  return err;
}

}  // namespace flexmb::core::test
