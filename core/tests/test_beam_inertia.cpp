// Consistent, configuration dependent inertia of PLBEAM / PLBEAMNL / PLTRUSS: Lagrange's equations
// against finite differences of M(x), an independent evaluation of the position field, the kinetic
// energy of rigid motion, the classical consistent mass matrices and gravity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/elements/Element.hpp"
#include "core/elements/PlanarBeam.hpp"
#include "core/elements/PlanarTruss.hpp"

using namespace flexmb::core;

namespace {

constexpr double kPi = std::numbers::pi;

double uniform(std::mt19937& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

template <class A, class B>
double relErr(const A& a, const B& ref, double floor = 1e-12) {
  const double scale = std::max({a.cwiseAbs().maxCoeff(), ref.cwiseAbs().maxCoeff(), floor});
  return (a - ref).cwiseAbs().maxCoeff() / scale;
}

ElemVec randomBeamInitial(std::mt19937& rng) {
  const double l0 = uniform(rng, 0.3, 2.5), beta = uniform(rng, -kPi, kPi);
  ElemVec x0(6);
  x0[0] = uniform(rng, -2, 2);
  x0[1] = uniform(rng, -2, 2);
  x0[2] = uniform(rng, -3, 3);
  x0[3] = x0[0] + l0 * std::cos(beta);
  x0[4] = x0[1] + l0 * std::sin(beta);
  x0[5] = uniform(rng, -3, 3);
  return x0;
}

// Deformed state: positions by up to 0.2 l0, node rotations by up to 0.5 rad (large bending), then
// a random rigid rotation.
ElemVec randomBeamState(const ElemVec& x0, std::mt19937& rng) {
  const double l0 = std::hypot(x0[3] - x0[0], x0[4] - x0[1]);
  ElemVec x = x0;
  for (int i : {0, 1, 3, 4}) x[i] += uniform(rng, -0.2, 0.2) * l0;
  for (int i : {2, 5}) x[i] += uniform(rng, -0.5, 0.5);
  const double th = uniform(rng, -kPi, kPi), c = std::cos(th), s = std::sin(th);
  ElemVec y = x;
  for (int p : {0, 3}) {
    y[p] = c * x[p] - s * x[p + 1];
    y[p + 1] = s * x[p] + c * x[p + 1];
  }
  y[2] += th;
  y[5] += th;
  return y;
}

ElemVec randomVector(int n, std::mt19937& rng, double a = 1.0) {
  ElemVec v(n);
  for (int i = 0; i < n; ++i) v[i] = uniform(rng, -a, a);
  return v;
}

// ---- An independent evaluation of SPACAR's beam field, written from the definitions. ----
struct Ref {
  double l0, beta0, phi0p, phi0q;
};
Ref refOf(const ElemVec& x0) {
  return {std::hypot(x0[3] - x0[0], x0[4] - x0[1]), std::atan2(x0[4] - x0[1], x0[3] - x0[0]), x0[2], x0[5]};
}
struct FieldPoint {
  double rx, ry, psi;
};
FieldPoint beamField(const ElemVec& x, const Ref& R, double xi) {
  const double dx = x[3] - x[0], dy = x[4] - x[1], l = std::sqrt(dx * dx + dy * dy);
  const double alpha = std::atan2(dy, dx);
  const double ap = x[2] - R.phi0p + R.beta0, aq = x[5] - R.phi0q + R.beta0;
  // Eq. 3b, 3c literally
  const double e2 = R.l0 / l * (dx * std::sin(ap) - dy * std::cos(ap));
  const double e3 = -R.l0 / l * (dx * std::sin(aq) - dy * std::cos(aq));
  const double H2 = xi * (1 - xi) * (1 - xi), H3 = xi * xi * (1 - xi);
  const double dH2 = (1 - xi) * (1 - xi) - 2 * xi * (1 - xi), dH3 = 2 * xi * (1 - xi) - xi * xi;
  const double w = H2 * e2 + H3 * e3, dw = dH2 * e2 + dH3 * e3;
  return {(1 - xi) * x[0] + xi * x[3] - std::sin(alpha) * w, (1 - xi) * x[1] + xi * x[4] + std::cos(alpha) * w,
          alpha + dw / R.l0};
}
double wrap(double a) { return std::remainder(a, 2 * kPi); }

// Kinetic energy by composite Simpson over xi, velocities of the field by central differences.
double fieldKineticEnergy(const ElemVec& x, const ElemVec& xd, const Ref& R, const ElementInertia& in) {
  const int N = 400;
  const double h = 1e-6;
  double sum = 0.0;
  for (int i = 0; i <= N; ++i) {
    const double xi = double(i) / N;
    const FieldPoint p = beamField(x + h * xd, R, xi), m = beamField(x - h * xd, R, xi);
    const double vx = (p.rx - m.rx) / (2 * h), vy = (p.ry - m.ry) / (2 * h);
    const double om = wrap(p.psi - m.psi) / (2 * h);
    const double f = in.rhoA * (vx * vx + vy * vy) + in.rhoI * om * om;
    sum += f * ((i == 0 || i == N) ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  return 0.5 * R.l0 * sum / (3.0 * N);
}

// Integral of r over xi (Simpson, exact for the cubic field).
Eigen::Vector2d fieldMoment(const ElemVec& x, const Ref& R) {
  const int N = 8;
  Eigen::Vector2d s = Eigen::Vector2d::Zero();
  for (int i = 0; i <= N; ++i) {
    const FieldPoint p = beamField(x, R, double(i) / N);
    s += Eigen::Vector2d(p.rx, p.ry) * ((i == 0 || i == N) ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  return s / (3.0 * N);
}

struct Variant {
  const char* label;
  ElongationDefinition def;
};
constexpr Variant kVariants[] = {{"plain", ElongationDefinition::Plain},
                                 {"corrected", ElongationDefinition::BendingCorrected}};

}  // namespace

// M xdd + h must equal d/dt(dT/dxd) - dT/dx = M xdd + (dM/dt) xd - dT/dx, T = xd^T M(x) xd / 2.
TEST(BeamInertia, LagrangeEquationsAgainstFiniteDifferences) {
  std::mt19937 rng(11);
  double worstH = 0.0, worstF = 0.0;
  for (const Variant& var : kVariants) {
    for (int k = 0; k < 25; ++k) {
      const ElemVec x0 = randomBeamInitial(rng);
      const PlanarBeam b(x0, var.def);
      const ElemVec x = randomBeamState(x0, rng);
      const ElemVec xd = randomVector(6, rng, 2.0), xdd = randomVector(6, rng, 2.0);
      ElementInertia in{uniform(rng, 0.5, 5.0), uniform(rng, 0.01, 0.5)};
      if (k % 5 == 1) in.rhoI = 0.0;
      if (k % 5 == 2) in.rhoA = 0.0;
      const double h = 1e-6;
      ElemMat M, Mp, Mm;
      b.mass(x, in, M);
      b.mass(x + h * xd, in, Mp);
      b.mass(x - h * xd, in, Mm);
      ElemVec ref = (Mp - Mm) / (2 * h) * xd;  // (dM/dt) xd
      for (int j = 0; j < 6; ++j) {
        ElemVec xp = x, xm = x;
        xp[j] += h;
        xm[j] -= h;
        b.mass(xp, in, Mp);
        b.mass(xm, in, Mm);
        ref[j] -= 0.5 * xd.dot((Mp - Mm) * xd) / (2 * h);  // dT/dx_j
      }
      ElemVec hv;
      b.velocityForces(x, xd, in, hv);
      ASSERT_EQ(hv.size(), 6);
      const double eh = relErr(hv, ref);
      const double ef = relErr(ElemVec(M * xdd + hv), ElemVec(M * xdd + ref));
      worstH = std::max(worstH, eh);
      worstF = std::max(worstF, ef);
      EXPECT_LT(eh, 1e-6) << var.label << " state " << k;
      EXPECT_LT(ef, 1e-6) << var.label << " state " << k;
      EXPECT_LT(relErr(M, ElemMat(M.transpose()), 1e-300), 1e-14);
    }
  }
  std::printf("[ max rel err ] Lagrange: h %.2e, M xdd + h %.2e\n", worstH, worstF);
}

// M(x) against an independent evaluation of the kinetic energy of the position field and the
// cross-section rotation, in deformed configurations.
TEST(BeamInertia, MassMatchesIndependentFieldKineticEnergy) {
  std::mt19937 rng(12);
  double worst = 0.0;
  for (const Variant& var : kVariants) {
    for (int k = 0; k < 20; ++k) {
      const ElemVec x0 = randomBeamInitial(rng);
      const PlanarBeam b(x0, var.def);
      const ElemVec x = randomBeamState(x0, rng);
      const ElemVec xd = randomVector(6, rng, 2.0);
      const ElementInertia in{uniform(rng, 0.5, 5.0), uniform(rng, 0.01, 0.5)};
      ElemMat M;
      b.mass(x, in, M);
      const double T = 0.5 * xd.dot(M * xd);
      const double Tref = fieldKineticEnergy(x, xd, refOf(x0), in);
      const double e = std::abs(T - Tref) / std::abs(Tref);
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-6) << var.label << " state " << k;
    }
  }
  std::printf("[ max rel err ] field kinetic energy %.2e\n", worst);
}

// The field of the test itself: its cross section at the ends follows the nodes to first order
// (H3 = +xi^2 (1 - xi) with e3 = -l0 theta_q), so the sign convention is the consistent one.
TEST(BeamInertia, FieldEndSlopesFollowNodes) {
  ElemVec x0(6);
  x0 << 0.5, -0.2, 0.7, 1.9, 0.4, -0.3;
  const Ref R = refOf(x0);
  ElemVec x = x0;
  x[2] += 1e-3;
  x[5] -= 2e-3;
  const FieldPoint p = beamField(x, R, 0.0), q = beamField(x, R, 1.0);
  EXPECT_NEAR(p.psi, R.beta0 + 1e-3, 1e-8);
  EXPECT_NEAR(q.psi, R.beta0 - 2e-3, 1e-8);
}

TEST(BeamInertia, RigidMotionKineticEnergy) {
  std::mt19937 rng(13);
  double worst = 0.0;
  for (int k = 0; k < 20; ++k) {
    const ElemVec x0 = randomBeamInitial(rng);
    const double l = std::hypot(x0[3] - x0[0], x0[4] - x0[1]);
    const double th = uniform(rng, -kPi, kPi), c = std::cos(th), s = std::sin(th);
    const Eigen::Vector2d t(uniform(rng, -1, 1), uniform(rng, -1, 1));
    // Straight, undeformed: the initial configuration moved rigidly.
    ElemVec x(6);
    for (int p : {0, 3}) {
      x[p] = c * x0[p] - s * x0[p + 1] + t[0];
      x[p + 1] = s * x0[p] + c * x0[p + 1] + t[1];
    }
    x[2] = x0[2] + th;
    x[5] = x0[5] + th;
    const Eigen::Vector2d vc(uniform(rng, -2, 2), uniform(rng, -2, 2));
    const double om = uniform(rng, -3, 3);
    const Eigen::Vector2d rc(0.5 * (x[0] + x[3]), 0.5 * (x[1] + x[4]));
    ElemVec xd(6);
    for (int p : {0, 3}) {
      const Eigen::Vector2d r(x[p] - rc[0], x[p + 1] - rc[1]);
      xd[p] = vc[0] - om * r[1];
      xd[p + 1] = vc[1] + om * r[0];
    }
    xd[2] = xd[5] = om;
    const ElementInertia in{uniform(rng, 0.5, 5.0), uniform(rng, 0.01, 0.5)};
    const double m = in.rhoA * l;
    for (const Variant& var : kVariants) {
      const PlanarBeam b(x0, var.def);
      ElemMat M;
      b.mass(x, in, M);
      const double T = 0.5 * xd.dot(M * xd);
      const double Tex = 0.5 * m * vc.squaredNorm() + 0.5 * (m * l * l / 12 + in.rhoI * l) * om * om;
      const double e = std::abs(T - Tex) / Tex;
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-12) << var.label;
    }
    // Truss: no rotary inertia.
    ElemVec xt0(4), xt(4), xdt(4);
    xt0 << x0[0], x0[1], x0[3], x0[4];
    xt << x[0], x[1], x[3], x[4];
    xdt << xd[0], xd[1], xd[3], xd[4];
    ElemMat Mt;
    PlanarTruss(xt0).mass(xt, in, Mt);
    const double Tt = 0.5 * xdt.dot(Mt * xdt);
    const double Ttex = 0.5 * m * vc.squaredNorm() + 0.5 * (m * l * l / 12) * om * om;
    EXPECT_LT(std::abs(Tt - Ttex) / Ttex, 1e-12);
    worst = std::max(worst, std::abs(Tt - Ttex) / Ttex);
  }
  std::printf("[ max rel err ] rigid kinetic energy %.2e\n", worst);
}

namespace {
// Textbook matrices (e.g. Przemieniecki; Cook et al.): cubic Hermite consistent mass in
// (v_p, theta_p, v_q, theta_q), rotary inertia of the cross sections, and the linear axial rod.
Eigen::Matrix4d textbookTransverse(double rhoA, double rhoI, double l) {
  Eigen::Matrix4d mt, mr;
  mt << 156, 22 * l, 54, -13 * l, 22 * l, 4 * l * l, 13 * l, -3 * l * l, 54, 13 * l, 156, -22 * l, -13 * l, -3 * l * l,
      -22 * l, 4 * l * l;
  mr << 36, 3 * l, -36, 3 * l, 3 * l, 4 * l * l, -3 * l, -l * l, -36, -3 * l, 36, -3 * l, 3 * l, -l * l, -3 * l,
      4 * l * l;
  return rhoA * l / 420.0 * mt + rhoI / (30.0 * l) * mr;
}
}  // namespace

TEST(BeamInertia, LinearisedMassEqualsClassicalMatrices) {
  const double l = 1.7;
  ElemVec x0(6);
  x0 << 0.3, -0.4, 0.0, 0.3 + l, -0.4, 0.0;  // straight, along x
  const int tr[4] = {1, 2, 4, 5}, ax[2] = {0, 3};
  for (const Variant& var : kVariants) {
    const PlanarBeam b(x0, var.def);
    for (const ElementInertia& in : {ElementInertia{2.5, 0.0}, ElementInertia{0.0, 0.3}, ElementInertia{2.5, 0.3}}) {
      ElemMat M;
      b.mass(x0, in, M);
      Eigen::Matrix4d Mt;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) Mt(i, j) = M(tr[i], tr[j]);
      EXPECT_LT(relErr(Mt, textbookTransverse(in.rhoA, in.rhoI, l)), 1e-12)
          << var.label << " rhoA " << in.rhoA << " rhoI " << in.rhoI << "\n"
          << Mt;
      Eigen::Matrix2d Ma, Maref;
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) Ma(i, j) = M(ax[i], ax[j]);
      Maref << 2, 1, 1, 2;
      Maref *= in.rhoA * l / 6.0;
      if (in.rhoA == 0.0)
        EXPECT_LT(Ma.cwiseAbs().maxCoeff(), 1e-14);
      else
        EXPECT_LT(relErr(Ma, Maref), 1e-12) << var.label;
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 4; ++j)
          EXPECT_LT(std::abs(M(ax[i], tr[j])), 1e-14 * M.cwiseAbs().maxCoeff()) << "axial coupling";
    }
  }
  // The same element at an angle (nonzero BETA on its nodes): M = T M_local T^T.
  const double beta = 0.83, c = std::cos(beta), s = std::sin(beta);
  ElemVec xr(6);
  xr << 1.0, 2.0, 0.4, 1.0 + l * c, 2.0 + l * s, -1.2;
  const PlanarBeam br(xr, ElongationDefinition::BendingCorrected);
  const ElementInertia in{1.3, 0.07};
  ElemMat M;
  br.mass(xr, in, M);
  Eigen::Matrix<double, 6, 6> Ml = Eigen::Matrix<double, 6, 6>::Zero(), T = Ml;
  Ml.block<4, 4>(0, 0).setZero();
  const Eigen::Matrix4d Mtr = textbookTransverse(in.rhoA, in.rhoI, l);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) Ml(tr[i], tr[j]) = Mtr(i, j);
  Ml(0, 0) = Ml(3, 3) = in.rhoA * l / 3;
  Ml(0, 3) = Ml(3, 0) = in.rhoA * l / 6;
  for (int p : {0, 3}) {
    T(p, p) = c;
    T(p, p + 1) = -s;
    T(p + 1, p) = s;
    T(p + 1, p + 1) = c;
  }
  T(2, 2) = T(5, 5) = 1.0;
  const Eigen::Matrix<double, 6, 6> Mref = T * Ml * T.transpose();
  EXPECT_LT(relErr(M, Mref), 1e-12) << M << "\n\n" << Mref;

  // Truss: rhoA l/6 [[2, 1], [1, 2]] on each direction.
  ElemVec xt(4);
  xt << 0.0, 0.0, l * c, l * s;
  ElemMat Mt;
  PlanarTruss(xt).mass(xt, in, Mt);
  Eigen::Matrix4d Mtref;
  Mtref << 2, 0, 1, 0, 0, 2, 0, 1, 1, 0, 2, 0, 0, 1, 0, 2;
  Mtref *= in.rhoA * l / 6;
  EXPECT_LT(relErr(Mt, Mtref), 1e-14);
}

TEST(BeamInertia, Gravity) {
  std::mt19937 rng(14);
  double worst = 0.0;
  for (const Variant& var : kVariants) {
    for (int k = 0; k < 20; ++k) {
      const ElemVec x0 = randomBeamInitial(rng);
      const Ref R = refOf(x0);
      const PlanarBeam b(x0, var.def);
      const ElemVec x = randomBeamState(x0, rng);
      const ElementInertia in{uniform(rng, 0.5, 5.0), uniform(rng, 0.0, 0.5)};
      const double gx = uniform(rng, -3, 3), gy = -9.81;
      ElemVec f;
      b.gravityForces(x, in, gx, gy, f);
      ASSERT_EQ(f.size(), 6);
      const double m = in.rhoA * R.l0;
      EXPECT_NEAR(f[1] + f[4], m * gy, 1e-12 * m * 9.81) << var.label;
      EXPECT_NEAR(f[0] + f[3], m * gx, 1e-12 * m * 9.81) << var.label;
      // Generalised forces = -dV/dx with V = -rhoA l0 g . int r dxi (independent field, FD).
      ElemVec fref(6);
      const double h = 1e-6;
      for (int j = 0; j < 6; ++j) {
        const ElemVec xp = x + h * ElemVec::Unit(6, j), xm = x - h * ElemVec::Unit(6, j);
        const Eigen::Vector2d d = (fieldMoment(xp, R) - fieldMoment(xm, R)) / (2 * h);
        fref[j] = m * (gx * d[0] + gy * d[1]);
      }
      const double e = relErr(f, fref);
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-6) << var.label;
    }
  }
  std::printf("[ max rel err ] gravity vs potential %.2e\n", worst);
  // Truss: half the weight at each node.
  ElemVec xt(4);
  xt << 0, 0, 3, 4;
  ElemVec f;
  PlanarTruss(xt).gravityForces(xt, ElementInertia{2.0, 0.0}, 0.0, -10.0, f);
  EXPECT_DOUBLE_EQ(f[1], -50.0);
  EXPECT_DOUBLE_EQ(f[3], -50.0);
  EXPECT_DOUBLE_EQ(f[0], 0.0);
}

TEST(BeamInertia, NoInertiaGivesZero) {
  ElemVec x0(6);
  x0 << 0, 0, 0, 1, 0, 0;
  const PlanarBeam b(x0, ElongationDefinition::Plain);
  ElemMat M;
  ElemVec h, f, xd(6);
  xd << 1, 2, 3, 4, 5, 6;
  b.mass(x0, {}, M);
  b.velocityForces(x0, xd, {}, h);
  b.gravityForces(x0, {}, 0, -9.81, f);
  EXPECT_EQ(M.rows(), 6);
  EXPECT_EQ(M.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(h.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0);
}
