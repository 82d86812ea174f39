// PLBEAM / PLBEAMNL kernels against a straightforward reference to round-off: Eq. 3 and the
// position field r(xi) (PlanarBeam.hpp) written literally, differentiated exactly by second-order
// Taylor jets (forward automatic differentiation) and integrated by 5-point Gauss quadrature (exact
// for the polynomial integrands in xi, degree <= 6). The kernels are closed-form rewritings of the same
// quantities, so the two must agree to round-off (1e-12 relative), not just to finite-difference accuracy.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/elements/PlanarBeam.hpp"

using namespace flexmb::core;

namespace {

constexpr double kPi = std::numbers::pi;

// f(x + s v) = v + s d + s^2/2 dd + O(s^3): d = f'(x) v, dd = v^T f''(x) v.
struct Jet {
  double v = 0.0, d = 0.0, dd = 0.0;
  Jet() = default;
  Jet(double c) : v(c) {}  // NOLINT: constants mix with jets
  Jet(double v_, double d_, double dd_) : v(v_), d(d_), dd(dd_) {}
};
Jet operator+(Jet a, Jet b) { return {a.v + b.v, a.d + b.d, a.dd + b.dd}; }
Jet operator-(Jet a, Jet b) { return {a.v - b.v, a.d - b.d, a.dd - b.dd}; }
Jet operator*(Jet a, Jet b) { return {a.v * b.v, a.v * b.d + a.d * b.v, a.v * b.dd + 2 * a.d * b.d + a.dd * b.v}; }
Jet operator/(Jet a, Jet b) {
  const double r = 1.0 / b.v;
  return a * Jet(r, -b.d * r * r, -b.dd * r * r + 2 * b.d * b.d * r * r * r);
}
Jet sin(Jet a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return {s, c * a.d, c * a.dd - s * a.d * a.d};
}
Jet cos(Jet a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return {c, -s * a.d, -s * a.dd - c * a.d * a.d};
}
Jet sqrt(Jet a) {
  const double s = std::sqrt(a.v);
  return {s, a.d / (2 * s), a.dd / (2 * s) - a.d * a.d / (4 * s * s * s)};
}
Jet atan2(Jet y, Jet x) {
  const double r2 = x.v * x.v + y.v * y.v, c = x.v * y.d - y.v * x.d;
  return {std::atan2(y.v, x.v), c / r2, (x.v * y.dd - y.v * x.dd) / r2 - 2 * c * (x.v * x.d + y.v * y.d) / (r2 * r2)};
}
using std::atan2, std::cos, std::sin, std::sqrt;

struct Ref {
  double l0, beta0, phi0p, phi0q;
  bool corrected;
};

template <class T>
using X6 = std::array<T, 6>;

// Eq. 3a-3c literally.
template <class T>
std::array<T, 3> deformationsRef(const X6<T>& x, const Ref& R) {
  const T dx = x[3] - x[0], dy = x[4] - x[1], l = sqrt(dx * dx + dy * dy);
  const T ap = x[2] - R.phi0p + R.beta0, aq = x[5] - R.phi0q + R.beta0;
  const T e2 = R.l0 / l * (dx * sin(ap) - dy * cos(ap));
  const T e3 = -R.l0 / l * (dx * sin(aq) - dy * cos(aq));
  T e1 = l - R.l0;
  if (R.corrected) e1 = e1 + (2.0 * e2 * e2 + e2 * e3 + 2.0 * e3 * e3) / (30.0 * R.l0);
  return {e1, e2, e3};
}

// r(xi) = (1-xi) rp + xi rq + n(alpha) w(xi), psi = alpha + w'(xi)/l0 (PlanarBeam.hpp).
template <class T>
std::array<T, 3> fieldRef(const X6<T>& x, const Ref& R, double xi) {
  const std::array<T, 3> e = deformationsRef(x, R);
  const T alpha = atan2(x[4] - x[1], x[3] - x[0]);
  const double H2 = xi * (1 - xi) * (1 - xi), H3 = xi * xi * (1 - xi);
  const double dH2 = (1 - xi) * (1 - xi) - 2 * xi * (1 - xi), dH3 = 2 * xi * (1 - xi) - xi * xi;
  const T w = H2 * e[1] + H3 * e[2], dw = dH2 * e[1] + dH3 * e[2];
  return {(1 - xi) * x[0] + xi * x[3] - sin(alpha) * w, (1 - xi) * x[1] + xi * x[4] + cos(alpha) * w,
          alpha + dw / R.l0};
}

// x + s v as jets.
X6<Jet> along(const ElemVec& x, const ElemVec& v) {
  X6<Jet> j;
  for (int i = 0; i < 6; ++i) j[i] = Jet(x[i], v[i], 0.0);
  return j;
}
ElemVec unit(int i) { return ElemVec::Unit(6, i); }

// 5-point Gauss-Legendre on [0, 1].
struct Gauss {
  std::array<double, 5> xi, w;
  Gauss() {
    const double a = std::sqrt(5.0 - 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
    const double b = std::sqrt(5.0 + 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
    const double wa = (322.0 + 13.0 * std::sqrt(70.0)) / 900.0, wb = (322.0 - 13.0 * std::sqrt(70.0)) / 900.0;
    const std::array<double, 5> s = {-b, -a, 0.0, a, b}, ws = {wb, wa, 128.0 / 225.0, wa, wb};
    for (int k = 0; k < 5; ++k) {
      xi[k] = 0.5 * (1.0 + s[k]);
      w[k] = 0.5 * ws[k];
    }
  }
};

// M = l0 int (rhoA J_r^T J_r + rhoI J_psi^T J_psi), h = l0 int (rhoA J_r^T r'' + rhoI J_psi^T psi'')
// with r'' = xd^T (d2 r) xd (xdd = 0), f = rhoA l0 int J_r^T g.
struct InertiaRef {
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> h = Eigen::Matrix<double, 6, 1>::Zero(), f = Eigen::Matrix<double, 6, 1>::Zero();
};
InertiaRef inertiaRef(const ElemVec& x, const ElemVec& xd, const Ref& R, const ElementInertia& in, double gx,
                      double gy) {
  static const Gauss G;
  InertiaRef out;
  for (int k = 0; k < 5; ++k) {
    Eigen::Matrix<double, 3, 6> J;  // rows rx, ry, psi
    for (int j = 0; j < 6; ++j) {
      const std::array<Jet, 3> p = fieldRef(along(x, unit(j)), R, G.xi[k]);
      for (int i = 0; i < 3; ++i) J(i, j) = p[i].d;
    }
    const std::array<Jet, 3> c = fieldRef(along(x, xd), R, G.xi[k]);
    const Eigen::Vector3d acc(in.rhoA * c[0].dd, in.rhoA * c[1].dd, in.rhoI * c[2].dd);
    const Eigen::Vector3d rho(in.rhoA, in.rhoA, in.rhoI);
    const double wl = G.w[k] * R.l0;
    out.M += wl * J.transpose() * rho.asDiagonal() * J;
    out.h += wl * J.transpose() * acc;
    out.f += wl * in.rhoA * (gx * J.row(0).transpose() + gy * J.row(1).transpose());
  }
  return out;
}

double uniform(std::mt19937& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

template <class A, class B>
double relErr(const A& a, const B& ref) {
  const double scale = std::max({a.cwiseAbs().maxCoeff(), ref.cwiseAbs().maxCoeff(), 1e-300});
  return (a - ref).cwiseAbs().maxCoeff() / scale;
}

}  // namespace

TEST(BeamKernels, MatchTheJetAndQuadratureReferenceToRoundOff) {
  std::mt19937 rng(21);
  enum { kE, kDe, kD2, kH, kM, kh, kf, kN };
  const char* names[kN] = {"e", "De", "D2e[xd,xd]", "H(sigma)", "M", "h", "gravity"};
  double worst[kN] = {};
  for (const bool corrected : {false, true}) {
    for (int k = 0; k < 60; ++k) {
      // Initial geometry: any chord angle and node angles; then positions moved by up to 0.25 l0 and
      // node rotations by up to 0.6 rad (large bending), and a rigid rotation by any angle.
      const double l0 = uniform(rng, 0.2, 3.0), b0 = uniform(rng, -kPi, kPi);
      ElemVec x0(6);
      x0 << uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -3, 3), 0.0, 0.0, uniform(rng, -3, 3);
      x0[3] = x0[0] + l0 * std::cos(b0);
      x0[4] = x0[1] + l0 * std::sin(b0);
      const PlanarBeam beam(x0, corrected ? ElongationDefinition::BendingCorrected : ElongationDefinition::Plain);
      const Ref R{beam.l0(), beam.beta0(), beam.phi0p(), beam.phi0q(), corrected};
      ElemVec xl = x0;
      for (int i : {0, 1, 3, 4}) xl[i] += uniform(rng, -0.25, 0.25) * l0;
      for (int i : {2, 5}) xl[i] += uniform(rng, -0.6, 0.6);
      const double th = uniform(rng, -kPi, kPi), c = std::cos(th), s = std::sin(th);
      ElemVec x = xl, xd(6);
      for (int p : {0, 3}) {
        x[p] = c * xl[p] - s * xl[p + 1];
        x[p + 1] = s * xl[p] + c * xl[p + 1];
      }
      x[2] += th;
      x[5] += th;
      for (int i = 0; i < 6; ++i) xd[i] = uniform(rng, -2, 2);
      ElementInertia in{uniform(rng, 0.5, 5.0), uniform(rng, 0.01, 0.5)};
      if (k % 6 == 1) in.rhoI = 0.0;
      if (k % 6 == 2) in.rhoA = 0.0;
      DefVec sigma(3);
      sigma << uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10);
      const double gx = uniform(rng, -3, 3), gy = -9.81;

      // Reference deformations, Jacobian, D2e[xd, xd] and the stress-weighted Hessian (by polarisation).
      const std::array<double, 3> eRef = deformationsRef(X6<double>{x[0], x[1], x[2], x[3], x[4], x[5]}, R);
      Eigen::Matrix<double, 3, 6> DeRef;
      for (int j = 0; j < 6; ++j) {
        const std::array<Jet, 3> e = deformationsRef(along(x, unit(j)), R);
        for (int i = 0; i < 3; ++i) DeRef(i, j) = e[i].d;
      }
      const std::array<Jet, 3> ec = deformationsRef(along(x, xd), R);
      const Eigen::Vector3d d2Ref(ec[0].dd, ec[1].dd, ec[2].dd);
      auto weighted = [&](const ElemVec& v) {
        const std::array<Jet, 3> e = deformationsRef(along(x, v), R);
        return sigma[0] * e[0].dd + sigma[1] * e[1].dd + sigma[2] * e[2].dd;
      };
      Eigen::Matrix<double, 6, 6> HRef;
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) HRef(i, j) = 0.25 * (weighted(unit(i) + unit(j)) - weighted(unit(i) - unit(j)));
      const InertiaRef I = inertiaRef(x, xd, R, in, gx, gy);

      DefVec e, d2;
      DefJac De;
      ElemMat M, H;
      ElemVec h, f;
      beam.deformationsAndJacobian(x, e, De);
      beam.dynamicTerms(x, xd, in, M, h, d2);
      beam.stressWeightedHessian(x, sigma, H);
      beam.gravityForces(x, in, gx, gy, f);
      ASSERT_EQ(e.size(), 3);
      ASSERT_EQ(De.rows(), 3);
      ASSERT_EQ(De.cols(), 6);
      ASSERT_EQ(M.rows(), 6);
      ASSERT_EQ(H.rows(), 6);
      ASSERT_EQ(h.size(), 6);
      ASSERT_EQ(f.size(), 6);
      // e1 = l - l0 loses digits to cancellation when the chord barely stretches: measured against l0.
      const double eErr = (e - Eigen::Vector3d(eRef[0], eRef[1], eRef[2])).cwiseAbs().maxCoeff() / l0;
      const double err[kN] = {eErr,
                              relErr(De, DeRef),
                              relErr(d2, d2Ref),
                              relErr(H, HRef),
                              relErr(M, I.M),
                              relErr(h, I.h),
                              in.rhoA != 0.0 ? relErr(f, I.f) : f.cwiseAbs().maxCoeff()};
      for (int q = 0; q < kN; ++q) {
        EXPECT_LT(err[q], 1e-12) << names[q] << (corrected ? " corrected" : " plain") << " state " << k;
        worst[q] = std::max(worst[q], err[q]);
      }
    }
  }
  std::printf("[ max rel err ]");
  for (int q = 0; q < kN; ++q) std::printf(" %s %.1e", names[q], worst[q]);
  std::printf("\n");
}
