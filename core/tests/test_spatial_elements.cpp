// Spatial element kernels (docs/theory/spatial-elements.md): analytic derivatives against central finite
// differences at random configurations, rigid-motion invariance with random initial Euler
// parameters, the linear stiffness of one BEAM against the classical 12 x 12 Timoshenko
// space-frame matrix, planar consistency with PLBEAM, and the inertia (symmetry, Lagrange
// consistency of the velocity forces, rigid-body kinetic energy, gravity resultant).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <Eigen/Dense>
#include <string>

#include "core/elements/Element.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/elements/SpatialBeam.hpp"
#include "core/tests/ElementSamples.hpp"

using namespace flexmb::core;
using euler::Mat3;
using euler::Vec3;
using euler::Vec4;

namespace {

using test::randomQuaternion;
using test::uniform;
Vec4 multiply(const Vec4& a, const Vec4& b) { return test::quaternionProduct(a, b); }  // R(a b) = R(a) R(b)

struct SpatialCase {
  std::string keyword;
};
const std::vector<std::string> kKeywords = {"BEAM", "BEAMNL", "TRUSS", "HINGE", "RBEAM"};

// Random initial coordinates: positions in [-1, 1]^3 at least 0.4 apart, random unit Euler
// parameters; a random direction vector not along the chord.
void randomInitial(const ElementTypeInfo& t, std::mt19937& rng, ElemVec& x, Vec3& v) {
  for (;;) {
    x.resize(t.numCoords());
    int k = 0;
    std::vector<Vec3> pos;
    for (NodeKind s : t.slots) {
      if (s == NodeKind::SpatialPosition) {
        Vec3 p(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        x.segment<3>(k) = p;
        pos.push_back(p);
        k += 3;
      } else {
        x.segment<4>(k) = randomQuaternion(rng);
        k += 4;
      }
    }
    v = Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    if (pos.size() == 2) {
      const Vec3 d = pos[1] - pos[0];
      if (d.norm() < 0.4) continue;
      if (std::abs(d.normalized().dot(v.normalized())) > 0.9) continue;
    }
    if (v.norm() < 0.3) continue;
    return;
  }
}

std::unique_ptr<Element> make(const ElementTypeInfo& t, const ElemVec& x0, const Vec3& v) {
  if (t.createWithVector) return t.createWithVector(x0, v.data(), {});
  return t.create(x0, {});
}

// An element of type t at random initial coordinates x0 with a random direction vector v.
std::unique_ptr<Element> randomElement(const ElementTypeInfo& t, std::mt19937& rng, ElemVec& x0, Vec3& v) {
  randomInitial(t, rng, x0, v);
  return make(t, x0, v);
}

// A deformed configuration near x0: positions moved by up to 0.15, parameters perturbed (not
// normalised: the derivatives hold for any lambda).
ElemVec perturb(const ElementTypeInfo& t, const ElemVec& x0, std::mt19937& rng, double size) {
  ElemVec x = x0;
  for (int i = 0; i < x.size(); ++i) x[i] += uniform(rng, -size, size);
  (void)t;
  return x;
}

double relErr(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / std::max(1.0, b.norm()); }

}  // namespace

TEST(SpatialElements, DerivativesAgainstFiniteDifferences) {
  std::mt19937 rng(11);
  for (const auto& kw : kKeywords) {
    const ElementTypeInfo* t = findElementType(kw);
    ASSERT_NE(t, nullptr) << kw;
    double worstJ = 0, worstH = 0, worstV = 0;
    for (int trial = 0; trial < 20; ++trial) {
      ElemVec x0;
      Vec3 v3;
      auto el = randomElement(*t, rng, x0, v3);
      const int n = el->numCoords(), m = el->numDeformations();
      ASSERT_EQ(n, t->numCoords());
      ASSERT_EQ(m, t->numDeformations());
      const ElemVec x = perturb(*t, x0, rng, 0.3);
      DefJac De;
      el->jacobian(x, De);
      const double h = 1e-6;
      const Eigen::MatrixXd Dfd = test::jacobianByDifferences(*el, x, h);
      worstJ = std::max(worstJ, relErr(Eigen::MatrixXd(De), Dfd));
      // Hessian of each deformation: finite differences of the analytic Jacobian.
      ElemVec v(n);
      for (int j = 0; j < n; ++j) v[j] = uniform(rng, -1, 1);
      DefVec d2;
      el->secondDerivative(x, v, d2);
      for (int i = 0; i < m; ++i) {
        DefVec s = DefVec::Zero(m);
        s[i] = 1.0;
        const Eigen::MatrixXd Hfd = test::stressHessianByDifferences(*el, x, s, h);
        ElemMat H;
        el->stressWeightedHessian(x, s, H);
        worstH = std::max(worstH, relErr(Eigen::MatrixXd(H), Hfd));
        const Eigen::VectorXd vv = v;
        const double ref = vv.dot(Hfd * vv);
        worstV = std::max(worstV, std::abs(d2[i] - ref) / std::max(1.0, std::abs(ref)));
      }
    }
    std::printf("%-7s FD relative errors: Jacobian %.2e, Hessian %.2e, D2e[v,v] %.2e\n", kw.c_str(), worstJ, worstH,
                worstV);
    EXPECT_LT(worstJ, 1e-6) << kw;
    EXPECT_LT(worstH, 1e-6) << kw;
    EXPECT_LT(worstV, 1e-6) << kw;
  }
}

TEST(SpatialElements, ZeroInitiallyAndInvariantUnderRigidMotion) {
  std::mt19937 rng(5);
  for (const auto& kw : kKeywords) {
    const ElementTypeInfo* t = findElementType(kw);
    double worst0 = 0, worst = 0;
    for (int trial = 0; trial < 50; ++trial) {
      ElemVec x0;
      Vec3 v3;
      auto el = randomElement(*t, rng, x0, v3);
      DefVec e0;
      el->deformations(x0, e0);
      worst0 = std::max(worst0, e0.cwiseAbs().maxCoeff());
      // A deformed configuration with unit parameters, then a large rigid motion of it.
      ElemVec x = perturb(*t, x0, rng, 0.2);
      int k = 0;
      for (NodeKind s : t->slots) {
        if (s == NodeKind::EulerParameters) x.segment<4>(k) = Vec4(x.segment<4>(k)).normalized();
        k += nodeKindDim(s);
      }
      const Vec4 qm = randomQuaternion(rng);
      const Mat3 Q = euler::rotation(qm);
      const Vec3 c(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
      ElemVec y = x;
      k = 0;
      for (NodeKind s : t->slots) {
        if (s == NodeKind::SpatialPosition)
          y.segment<3>(k) = Q * Vec3(x.segment<3>(k)) + c;
        else
          y.segment<4>(k) = multiply(qm, x.segment<4>(k));
        k += nodeKindDim(s);
      }
      DefVec ex, ey;
      el->deformations(x, ex);
      el->deformations(y, ey);
      worst = std::max(worst, (ex - ey).cwiseAbs().maxCoeff());
    }
    std::printf("%-7s initial |e| %.1e, rigid-motion change %.1e\n", kw.c_str(), worst0, worst);
    EXPECT_LT(worst0, 1e-12) << kw;
    EXPECT_LT(worst, 1e-12) << kw;
  }
}

// The classical 12 x 12 Timoshenko space-frame element in its local frame, DOFs
// (u, v, w, thx, thy, thz) at each end.
Eigen::Matrix<double, 12, 12> timoshenkoLocal(double L, double EA, double GJ, double EIy, double EIz, double cy,
                                              double cz) {
  Eigen::Matrix<double, 12, 12> K = Eigen::Matrix<double, 12, 12>::Zero();
  auto put = [&](int a, int b, double v) { K(a, b) += v; };
  const double ka = EA / L, kt = GJ / L;
  put(0, 0, ka), put(6, 6, ka), put(0, 6, -ka), put(6, 0, -ka);
  put(3, 3, kt), put(9, 9, kt), put(3, 9, -kt), put(9, 3, -kt);
  // x-y plane: v (1, 7), thz (5, 11), EIz, Phi = 12 cz / L^2.
  {
    const double F = 12 * cz / (L * L), k = EIz / (L * L * L * (1 + F));
    const int d[4] = {1, 5, 7, 11};
    const double m[4][4] = {{12, 6 * L, -12, 6 * L},
                            {6 * L, (4 + F) * L * L, -6 * L, (2 - F) * L * L},
                            {-12, -6 * L, 12, -6 * L},
                            {6 * L, (2 - F) * L * L, -6 * L, (4 + F) * L * L}};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) put(d[i], d[j], k * m[i][j]);
  }
  // x-z plane: w (2, 8), thy (4, 10), EIy, Phi = 12 cy / L^2 (w' = -thy).
  {
    const double F = 12 * cy / (L * L), k = EIy / (L * L * L * (1 + F));
    const int d[4] = {2, 4, 8, 10};
    const double m[4][4] = {{12, -6 * L, -12, -6 * L},
                            {-6 * L, (4 + F) * L * L, 6 * L, (2 - F) * L * L},
                            {-12, 6 * L, 12, 6 * L},
                            {-6 * L, (2 - F) * L * L, 6 * L, (4 + F) * L * L}};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) put(d[i], d[j], k * m[i][j]);
  }
  return K;
}

TEST(SpatialElements, BeamStiffnessIsTimoshenkoSpaceFrame) {
  std::mt19937 rng(3);
  const ElementTypeInfo* t = findElementType("BEAM");
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    ElemVec x0;
    Vec3 y;
    auto el = randomElement(*t, rng, x0, y);
    const double EA = uniform(rng, 1, 100), GJ = uniform(rng, 0.1, 5), EIy = uniform(rng, 0.1, 5),
                 EIz = uniform(rng, 0.1, 5), cy = uniform(rng, 0, 0.05), cz = uniform(rng, 0, 0.05);
    const double p[6] = {EA, GJ, EIy, EIz, cy, cz};
    DefMat S;
    el->constitutive(p, S);
    DefJac D;
    el->jacobian(x0, D);
    // Coordinates -> (displacements, global rotations): delta lambda = 1/2 E^T delta theta.
    Eigen::Matrix<double, 14, 12> T = Eigen::Matrix<double, 14, 12>::Zero();
    T.block<3, 3>(0, 0).setIdentity();
    T.block<4, 3>(3, 3) = 0.5 * euler::globalRateMatrix(x0.segment<4>(3)).transpose();
    T.block<3, 3>(7, 6).setIdentity();
    T.block<4, 3>(10, 9) = 0.5 * euler::globalRateMatrix(x0.segment<4>(10)).transpose();
    const Eigen::MatrixXd Dm = D;
    const Eigen::MatrixXd K = T.transpose() * Dm.transpose() * Eigen::MatrixXd(S) * Dm * T;
    // Classical matrix in global components: local = F^T global per 3-vector.
    const Vec3 d = x0.segment<3>(7) - x0.segment<3>(0);
    const double L = d.norm();
    const Mat3 F = euler::elementFrame(d / L, y);
    Eigen::Matrix<double, 12, 12> Lam = Eigen::Matrix<double, 12, 12>::Zero();
    for (int b = 0; b < 4; ++b) Lam.block<3, 3>(3 * b, 3 * b) = F.transpose();
    const Eigen::MatrixXd Kc = Lam.transpose() * timoshenkoLocal(L, EA, GJ, EIy, EIz, cy, cz) * Lam;
    worst = std::max(worst, (K - Kc).norm() / Kc.norm());
  }
  std::printf("BEAM D^T S D vs Timoshenko 12x12: max relative error %.2e\n", worst);
  EXPECT_LT(worst, 1e-10);
}

TEST(SpatialElements, BeamInPlaneEqualsPlanarBeam) {
  // A BEAM in the x-y plane moving in the plane has the PLBEAM deformations (e1, e5, e6) = (e1, e2,
  // e3), with the same elongation variant; torsion and out-of-plane bending stay zero.
  std::mt19937 rng(8);
  double worst = 0;
  for (const auto& [sk, pk, opt] : {std::tuple{"BEAM", "PLBEAM", ElongationDefinition::Plain},
                                    std::tuple{"BEAMNL", "PLBEAMNL", ElongationDefinition::BendingCorrected}}) {
    for (int trial = 0; trial < 20; ++trial) {
      const double xp = uniform(rng, -1, 1), yp = uniform(rng, -1, 1), xq = xp + uniform(rng, 0.5, 1.5),
                   yq = yp + uniform(rng, -1, 1), bp = uniform(rng, -3, 3), bq = uniform(rng, -3, 3);
      auto quat = [](double a) { return Vec4(std::cos(a / 2), 0, 0, std::sin(a / 2)); };
      ElemVec p0(6), s0(14);
      p0 << xp, yp, bp, xq, yq, bq;
      s0 << xp, yp, 0, quat(bp), xq, yq, 0, quat(bq);
      const double y[3] = {0, 0, 1};
      // y axis = global z would put bending 5/6 out of plane: the in-plane y axis is z x chord.
      const Vec3 chord(xq - xp, yq - yp, 0);
      const Vec3 yin = Vec3::UnitZ().cross(chord).normalized();
      (void)y;
      auto sb = findElementType(sk)->createWithVector(s0, yin.data(), {});
      auto pb = findElementType(pk)->create(p0, ElementOptions{opt});
      ElemVec p1 = p0;
      for (int i = 0; i < 6; ++i) p1[i] += uniform(rng, -0.3, 0.3);
      ElemVec s1(14);
      s1 << p1[0], p1[1], 0, quat(p1[2]), p1[3], p1[4], 0, quat(p1[5]);
      DefVec es, ep;
      sb->deformations(s1, es);
      pb->deformations(p1, ep);
      worst = std::max({worst, std::abs(es[0] - ep[0]), std::abs(es[4] - ep[1]), std::abs(es[5] - ep[2]),
                        std::abs(es[1]), std::abs(es[2]), std::abs(es[3])});
    }
  }
  std::printf("BEAM in plane vs PLBEAM: max deformation difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-13);
}

TEST(SpatialElements, BeamCentreLineIsTheCubicThroughItsEndTriads) {
  // Element::centreLine, the pictures' field: a beam along x of length 2, its end q turned by theta
  // about z. The co-rotated cubic puts the middle at the chord's middle plus l0/8 (t_p - t_q), the
  // planar beam's H3(1/2) e3 = -l0 sin(theta)/8 across the chord (and (1 - cos theta) l0/8
  // along it, past the middle); the section's z axis stays global z, y is normal to the tangent.
  const double l0 = 2.0, theta = 0.3;
  auto quat = [](double a) { return Vec4(std::cos(a / 2), 0, 0, std::sin(a / 2)); };
  ElemVec x0(14), x(14);
  x0 << 0, 0, 0, quat(0), l0, 0, 0, quat(0);
  x << 0, 0, 0, quat(0), l0, 0, 0, quat(theta);
  const double y[3] = {0, 1, 0};
  const auto beam = findElementType("BEAM")->createWithVector(x0, y, {});
  Eigen::Matrix3Xd pts(3, 5), ys(3, 5), zs(3, 5);
  ASSERT_TRUE(beam->centreLine(x, pts, &ys, &zs));
  EXPECT_LT((pts.col(0) - Vec3(0, 0, 0)).norm(), 1e-15);
  EXPECT_LT((pts.col(4) - Vec3(l0, 0, 0)).norm(), 1e-15);
  EXPECT_NEAR(pts(0, 2), l0 / 2 + l0 * (1 - std::cos(theta)) / 8, 1e-14);
  EXPECT_NEAR(pts(1, 2), -l0 * std::sin(theta) / 8, 1e-14);
  for (int k = 0; k < 5; ++k) {
    EXPECT_LT((zs.col(k) - Vec3::UnitZ()).norm(), 1e-14) << k;
    EXPECT_NEAR(ys.col(k).norm(), 1.0, 1e-14) << k;
  }
  // Undeformed: the straight chord; elements without a field of their own say so.
  ASSERT_TRUE(beam->centreLine(x0, pts));
  EXPECT_LT(std::abs(pts(1, 2)), 1e-15);
  ElemVec t0(6);
  t0 << 0, 0, 0, 1, 0, 0;
  EXPECT_FALSE(findElementType("TRUSS")->create(t0, {})->centreLine(t0, pts));
}

TEST(SpatialElements, BeamInertia) {
  std::mt19937 rng(21);
  const ElementTypeInfo* t = findElementType("BEAM");
  double worstSym = 0, worstH = 0, worstT = 0, worstG = 0;
  for (int trial = 0; trial < 10; ++trial) {
    ElemVec x0;
    Vec3 y;
    auto el = randomElement(*t, rng, x0, y);
    ElementInertia in;
    in.rhoA = uniform(rng, 0.5, 3);
    in.jxx = uniform(rng, 0.01, 0.1), in.jyy = uniform(rng, 0.01, 0.1), in.jzz = uniform(rng, 0.01, 0.1);
    in.jyz = uniform(rng, -0.005, 0.005);
    ElemVec x = perturb(*t, x0, rng, 0.2);
    ElemVec xd(14);
    for (int i = 0; i < 14; ++i) xd[i] = uniform(rng, -1, 1);
    ElemMat M;
    el->mass(x, in, M);
    worstSym = std::max(worstSym, (M - M.transpose()).norm() / M.norm());
    // Lagrange: h = (dM/dx xd) xd - 1/2 d(xd^T M xd)/dx.
    const double h = 1e-6;
    Eigen::VectorXd Mdot = Eigen::VectorXd::Zero(14), dT(14);
    {
      ElemMat Mp, Mm;
      ElemVec xp = x + h * xd, xm = x - h * xd;
      el->mass(xp, in, Mp);
      el->mass(xm, in, Mm);
      Mdot = (Mp - Mm) * Eigen::VectorXd(xd) / (2 * h);
    }
    for (int j = 0; j < 14; ++j) {
      ElemVec xp = x, xm = x;
      xp[j] += h;
      xm[j] -= h;
      ElemMat Mp, Mm;
      el->mass(xp, in, Mp);
      el->mass(xm, in, Mm);
      dT[j] = 0.5 * xd.dot((Mp - Mm) * xd) / (2 * h);
    }
    ElemVec hv;
    el->velocityForces(x, xd, in, hv);
    const Eigen::VectorXd ref = Mdot - dT;
    worstH = std::max(worstH, (Eigen::VectorXd(hv) - ref).norm() / std::max(1.0, ref.norm()));
    // Rigid motion of the initial configuration: velocity v + w x (r - x_p), lambdad = 1/2 E^T w.
    const Vec3 v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const Vec3 w(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    ElemVec xr = x0, xdr(14);
    xr.segment<4>(3).normalize();
    xr.segment<4>(10).normalize();
    SpatialBeam b(xr, y.data(), false);
    const Vec3 d = xr.segment<3>(7) - xr.segment<3>(0);
    xdr.segment<3>(0) = v;
    xdr.segment<3>(7) = v + w.cross(d);
    xdr.segment<4>(3) = 0.5 * euler::globalRateMatrix(xr.segment<4>(3)).transpose() * w;
    xdr.segment<4>(10) = 0.5 * euler::globalRateMatrix(xr.segment<4>(10)).transpose() * w;
    ElemMat Mr;
    b.mass(xr, in, Mr);
    const double T = 0.5 * xdr.dot(Mr * xdr);
    const double L = d.norm(), m = in.rhoA * L;
    const Vec3 vc = v + 0.5 * w.cross(d);
    const Mat3 F = euler::elementFrame(d / L, y);
    Mat3 Jl;
    Jl << in.jxx, 0, 0, 0, in.jyy, in.jyz, 0, in.jyz, in.jzz;
    const Mat3 Jrot = L * F * Jl * F.transpose();  // rotary, lumped halves at the ends
    const Vec3 e = d / L;
    const Mat3 Jrod = m * L * L / 12.0 * (Mat3::Identity() - e * e.transpose());
    const double Tex = 0.5 * m * vc.squaredNorm() + 0.5 * w.dot((Jrod + Jrot) * w);
    worstT = std::max(worstT, std::abs(T - Tex) / Tex);
    // Gravity resultant of a straight element: m g, and its moment about x_p: (d/2) x m g.
    const double g[3] = {uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10)};
    ElemVec f;
    b.gravityForces3(xr, in, g, f);
    const Vec3 gv(g[0], g[1], g[2]);
    const Vec3 work = f.segment<3>(0) + f.segment<3>(7);
    // Virtual rotation w: power of the gravity forces = (d/2 x m g) . w
    const double P = f.dot(xdr) - work.dot(v);
    const double Pex = (0.5 * d).cross(m * gv).dot(w);
    worstG = std::max({worstG, (work - m * gv).norm() / (m * gv.norm()), std::abs(P - Pex) / (m * gv.norm() * L)});
  }
  std::printf(
      "BEAM inertia: M symmetry %.1e, velocity forces vs Lagrange FD %.1e, rigid kinetic energy %.1e, "
      "gravity %.1e\n",
      worstSym, worstH, worstT, worstG);
  EXPECT_LT(worstSym, 1e-14);
  EXPECT_LT(worstH, 1e-6);
  EXPECT_LT(worstT, 1e-12);
  EXPECT_LT(worstG, 1e-12);
}

TEST(SpatialElements, HingeKeepsItsAxisThroughAFullTurn) {
  // The two tilt constraints must keep rank 2 at every rotation about the axis, or a free hinge
  // cannot turn through a half turn (the symmetric tilt form lost rank at e1 = pi). Jacobian with
  // respect to global rotations of q (dlambda_q = E(lambda_q)^T dtheta / 2): the 3 x 3 block must
  // be well conditioned at any angle, and e1 must equal the angle turned.
  const ElementTypeInfo* t = findElementType("HINGE");
  ASSERT_NE(t, nullptr);
  const Vec3 axis = Vec3(0.3, -1.0, 0.6).normalized();
  const Vec4 lp = Vec4(0.8, 0.1, -0.3, 0.5).normalized();
  ElemVec x0(8);
  x0 << lp, lp;
  const std::unique_ptr<Element> h = t->createWithVector(x0, axis.data(), {});
  const Vec3 globalAxis = axis;  // the HINGE vector is the axis in the initial configuration (global)
  for (double phi : {0.0, 1.0, 2.5, 3.0, std::numbers::pi, 3.3, 4.5, 6.0}) {
    const Vec4 turn(std::cos(phi / 2), std::sin(phi / 2) * globalAxis[0], std::sin(phi / 2) * globalAxis[1],
                    std::sin(phi / 2) * globalAxis[2]);
    const Mat3 Rq = euler::rotation(turn) * euler::rotation(lp);
    const Vec4 lq = euler::fromRotation(Rq);
    ElemVec x(8);
    x << lp, lq;
    DefVec e;
    DefJac De;
    h->deformations(x, e);
    h->jacobian(x, De);
    const Eigen::Matrix3d J = De.rightCols<4>() * (0.5 * euler::globalRateMatrix(lq).transpose());
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(J);
    EXPECT_NEAR(std::remainder(e[0] - phi, 2 * std::numbers::pi), 0.0, 1e-12) << "phi " << phi;
    EXPECT_NEAR(e[1], 0.0, 1e-12);
    EXPECT_NEAR(e[2], 0.0, 1e-12);
    EXPECT_NEAR(svd.singularValues().minCoeff(), 1.0, 1e-12) << "phi " << phi;  // J is a rotation
    EXPECT_NEAR(svd.singularValues().maxCoeff(), 1.0, 1e-12) << "phi " << phi;
  }
}
