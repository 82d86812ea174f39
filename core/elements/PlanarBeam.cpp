#include "core/elements/PlanarBeam.hpp"

#include "core/elements/SinCos.hpp"

#include <cmath>
#include <stdexcept>

namespace flexmb::core {

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Jac36 = Eigen::Matrix<double, 3, 6>;

// Moments of the lateral shapes H2, H3 (see Inertia below), as products instead of divisions.
constexpr double k12 = 1.0 / 12.0, k15 = 1.0 / 15.0, k20 = 1.0 / 20.0, k30 = 1.0 / 30.0;
constexpr double k105 = 1.0 / 105.0, k140 = 1.0 / 140.0;

}  // namespace

// Derivatives in x: with t = (ex, ey), n = (-ey, ex) (the chord frame),
//   dl/dx = (-t, 0, t, 0),  dtheta_p/dx = (n/l, 1, -n/l, 0),  dtheta_q/dx = (n/l, 0, -n/l, 1),
// so every row is written entry by entry from a few scalars.
struct PlanarBeam::Geometry {
  double l, il;           // chord length, 1/l
  double ex, ey;          // unit chord t
  double sp, cp, sq, cq;  // sin, cos theta_p and theta_q
  double D2, D3;          // e2, e3 (Eq. 3b, 3c)
  double k2, k3;          // dD2/dtheta_p = l0 cp, dD3/dtheta_q = -l0 cq
};

PlanarBeam::PlanarBeam(const ElemVec& x0, ElongationDefinition elongation) : elongation_(elongation) {
  if (x0.size() != 6) throw std::invalid_argument("planar beam: expected 6 initial coordinates");
  const double dx = x0[3] - x0[0], dy = x0[4] - x0[1];
  setLength(std::hypot(dx, dy));
  if (!(l0_ > 0.0)) throw std::invalid_argument("planar beam: end nodes coincide (zero length)");
  setChordAngle(std::atan2(dy, dx));
  phi0p_ = x0[2];
  phi0q_ = x0[5];
}

void PlanarBeam::setLength(double l0) {
  l0_ = l0;
  c_ = elongation_ == ElongationDefinition::BendingCorrected ? 1.0 / (30.0 * l0) : 0.0;
  il02_ = 1.0 / (l0 * l0);
}

void PlanarBeam::setChordAngle(double beta0) {
  beta0_ = beta0;
  cb0_ = std::cos(beta0);
  sb0_ = std::sin(beta0);
}

void PlanarBeam::setReference(const ElemVec& x, const DefVec& e, double length0) {
  const double dx = x[3] - x[0], dy = x[4] - x[1];
  const double l = std::hypot(dx, dy);
  if (!(l > 0.0)) throw std::invalid_argument("planar beam: end nodes coincide (zero length)");
  double l0 = length0;
  if (!(l0 > 0.0)) {  // from the elongation e1 at x (Eq. 3a solved for l0 by a fixed point)
    const double c = 2.0 * e[1] * e[1] + e[1] * e[2] + 2.0 * e[2] * e[2];
    l0 = l - e[0];
    if (elongation_ == ElongationDefinition::BendingCorrected)
      for (int k = 0; k < 20 && l0 > 0.0; ++k) l0 = l - e[0] + c / (30.0 * l0);
  }
  if (!(l0 > 0.0) || !std::isfinite(l0))
    throw std::invalid_argument("planar beam: the reference length must be positive");
  if (std::abs(e[1]) > l0 || std::abs(e[2]) > l0)
    throw std::invalid_argument("planar beam: a bending deformation larger than the reference length");
  setLength(l0);
  setChordAngle(std::atan2(dy, dx));
  phi0p_ = x[2] - std::asin(e[1] / l0);
  phi0q_ = x[5] + std::asin(e[2] / l0);
}

std::unique_ptr<Element> PlanarBeam::create(const ElemVec& x0, const ElementOptions& options) {
  return std::make_unique<PlanarBeam>(x0, options.elongation);
}

std::unique_ptr<Element> PlanarBeam::createNonlinear(const ElemVec& x0, const ElementOptions&) {
  return std::make_unique<PlanarBeam>(x0, ElongationDefinition::BendingCorrected);
}

inline void PlanarBeam::geometry(const ElemVec& x, Geometry& g) const {
  // theta = a - alpha with the node angles a taken from the reference chord direction beta0: small
  // in a flexure, wherever it points, so that sinCos takes its polynomial path.
  const double ap = x[2] - phi0p_, aq = x[5] - phi0q_;
  double sap, cap, saq, caq;
  sinCos(ap, sap, cap);
  sinCos(aq, saq, caq);
  const double dx = x[3] - x[0], dy = x[4] - x[1];
  g.l = std::sqrt(dx * dx + dy * dy);
  g.il = 1.0 / g.l;
  g.ex = dx * g.il;
  g.ey = dy * g.il;
  // The chord in the reference chord's frame: (cos, sin) of alpha - beta0.
  const double cg = g.ex * cb0_ + g.ey * sb0_, sg = g.ey * cb0_ - g.ex * sb0_;
  g.sp = sap * cg - cap * sg;
  g.cp = cap * cg + sap * sg;
  g.sq = saq * cg - caq * sg;
  g.cq = caq * cg + saq * sg;
  g.D2 = l0_ * g.sp;
  g.D3 = -l0_ * g.sq;
  g.k2 = l0_ * g.cp;
  g.k3 = -l0_ * g.cq;
}

void PlanarBeam::deformations(const ElemVec& x, DefVec& e) const {
  Geometry g;
  geometry(x, g);
  deformationsAt(g, e);
}

void PlanarBeam::jacobian(const ElemVec& x, DefJac& De) const {
  Geometry g;
  geometry(x, g);
  jacobianAt(g, De);
}

void PlanarBeam::deformationsAndJacobian(const ElemVec& x, DefVec& e, DefJac& De) const {
  Geometry g;
  geometry(x, g);
  deformationsAt(g, e);
  jacobianAt(g, De);
}

inline void PlanarBeam::deformationsAt(const Geometry& g, DefVec& e) const {
  e.resize(3);
  e[0] = g.l - l0_ + c_ * (2.0 * g.D2 * g.D2 + g.D2 * g.D3 + 2.0 * g.D3 * g.D3);
  e[1] = g.D2;
  e[2] = g.D3;
}

inline void PlanarBeam::jacobianAt(const Geometry& g, DefJac& De) const {
  // de1/dx = dl/dx + b2 dtheta_p/dx + b3 dtheta_q/dx (Eq. 3a), so its q position part is t - b n.
  const double b2 = c_ * (4.0 * g.D2 + g.D3) * g.k2, b3 = c_ * (g.D2 + 4.0 * g.D3) * g.k3;
  const double b = (b2 + b3) * g.il, k2l = g.k2 * g.il, k3l = g.k3 * g.il;
  De.resize(3, 6);
  Eigen::Map<Jac36> J(De.data());
  J << -g.ex - b * g.ey, -g.ey + b * g.ex, b2, g.ex + b * g.ey, g.ey - b * g.ex, b3, -k2l * g.ey, k2l * g.ex, g.k2,
      k2l * g.ey, -k2l * g.ex, 0.0, -k3l * g.ey, k3l * g.ex, 0.0, k3l * g.ey, -k3l * g.ex, g.k3;
}

// Convective terms along xd: d2l = xd^T (d2 l) xd = (n.vd)^2 / l and
// xd^T (d2 theta) xd = 2 (t.vd)(n.vd) / l^2 (= -alpha ddot at xdd = 0), vd = vq - vp.
struct PlanarBeam::Rates {
  double ad;          // alpha dot
  double d2l, d2th;   // xd^T (d2 l) xd, xd^T (d2 theta) xd (the same for both nodes)
  double D2d, D3d;    // e2 dot, e3 dot
  double D2dd, D3dd;  // xd^T (d2 D2) xd, xd^T (d2 D3) xd
};

inline void PlanarBeam::rates(const Geometry& g, const ElemVec& v, Rates& r) const {
  const double vx = v[3] - v[0], vy = v[4] - v[1];
  const double tv = g.ex * vx + g.ey * vy, nv = g.ex * vy - g.ey * vx;
  r.ad = nv * g.il;
  r.d2l = nv * r.ad;
  r.d2th = 2.0 * tv * r.ad * g.il;
  const double tp = v[2] - r.ad, tq = v[5] - r.ad;  // theta_p dot, theta_q dot
  r.D2d = g.k2 * tp;
  r.D3d = g.k3 * tq;
  // D2 = l0 sin theta_p: D2dd = l0 (cp d2theta - sp thetad^2); likewise D3 = -l0 sin theta_q
  r.D2dd = g.k2 * r.d2th - g.D2 * tp * tp;
  r.D3dd = g.k3 * r.d2th - g.D3 * tq * tq;
}

bool PlanarBeam::place(const DefVec& e, int to, ElemVec& x) const {
  const double sp = e[1] / l0_, sq = -e[2] / l0_;
  if (!(std::abs(sp) < 1.0 && std::abs(sq) < 1.0)) return false;
  const double thetaP = std::asin(sp), thetaQ = std::asin(sq);
  double l = l0_ + e[0];
  if (elongation_ == ElongationDefinition::BendingCorrected)
    l -= (2.0 * e[1] * e[1] + e[1] * e[2] + 2.0 * e[2] * e[2]) / (30.0 * l0_);
  if (!(l > 0.0)) return false;
  // Node angles a = phi - phi0 + beta0 measured from the chord angle alpha: theta = a - alpha.
  if (to == 1) {
    const double alpha = x[2] - phi0p_ + beta0_ - thetaP;
    x[3] = x[0] + l * std::cos(alpha);
    x[4] = x[1] + l * std::sin(alpha);
    x[5] = alpha + thetaQ + phi0q_ - beta0_;
  } else {
    const double alpha = x[5] - phi0q_ + beta0_ - thetaQ;
    x[0] = x[3] - l * std::cos(alpha);
    x[1] = x[4] - l * std::sin(alpha);
    x[2] = alpha + thetaP + phi0p_ - beta0_;
  }
  return true;
}

void PlanarBeam::secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const {
  Geometry g;
  geometry(x, g);
  Rates r;
  rates(g, v, r);
  secondDerivativeAt(g, r, d2);
}

inline void PlanarBeam::secondDerivativeAt(const Geometry& g, const Rates& r, DefVec& d2) const {
  const double a = r.D2d, b = r.D3d;
  d2.resize(3);
  d2[0] = r.d2l +
          c_ * ((4.0 * g.D2 + g.D3) * r.D2dd + (g.D2 + 4.0 * g.D3) * r.D3dd + 4.0 * a * a + 2.0 * a * b + 4.0 * b * b);
  d2[1] = r.D2dd;
  d2[2] = r.D3dd;
}

void PlanarBeam::stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const {
  Geometry g;
  geometry(x, g);
  // sum sigma_i d2 D_i = s1 d2l + c2 d2 D2 + c3 d2 D3 + s1 c (4 dD2 dD2^T + dD2 dD3^T + ...), the
  // stresses c2, c3 on D2, D3 including the elongation's dependence on them (Eq. 3a). With
  // d2 D2 = k2 d2theta - D2 dtheta_p dtheta_p^T (likewise D3) this is
  //   s1 d2l + (c2 k2 + c3 k3) d2theta + [dtheta_p dtheta_q] [[app, apq], [apq, aqq]] [...]^T.
  const double s1 = sigma[0], k = s1 * c_;
  const double c2 = sigma[1] + k * (4.0 * g.D2 + g.D3), c3 = sigma[2] + k * (g.D2 + 4.0 * g.D3);
  const double app = 4.0 * k * g.k2 * g.k2 - c2 * g.D2, aqq = 4.0 * k * g.k3 * g.k3 - c3 * g.D3;
  const double apq = k * g.k2 * g.k3;
  // position block on d = rq - rp: beta n n^T + kth (t n^T + n t^T)
  const double il = g.il, beta = s1 * il + (app + 2.0 * apq + aqq) * il * il;
  const double kth = (c2 * g.k2 + c3 * g.k3) * il * il;
  const double exx = g.ex * g.ex, eyy = g.ey * g.ey, exy = g.ex * g.ey;
  const double B00 = beta * eyy - 2.0 * kth * exy, B11 = beta * exx + 2.0 * kth * exy;
  const double B01 = kth * (exx - eyy) - beta * exy;
  const double vp = il * (app + apq), vq = il * (apq + aqq);  // position-angle: +-v n
  H.resize(6, 6);
  Eigen::Map<Mat6> Hm(H.data());
  Hm << B00, B01, -vp * g.ey, -B00, -B01, -vq * g.ey, B01, B11, vp * g.ex, -B01, -B11, vq * g.ex, -vp * g.ey, vp * g.ex,
      app, vp * g.ey, -vp * g.ex, apq, -B00, -B01, vp * g.ey, B00, B01, vq * g.ey, -B01, -B11, -vp * g.ex, B01, B11,
      -vq * g.ex, -vq * g.ey, vq * g.ex, apq, vq * g.ey, -vq * g.ex, aqq;
}

ElementValidity PlanarBeam::validity(const ElemVec& x) const {
  Geometry g;
  geometry(x, g);
  if (g.cp > 0.0 && g.cq > 0.0) return {};
  // Report the node turned furthest (slots: 0 p, 1 phi_p, 2 q, 3 phi_q).
  const double tp = std::atan2(g.sp, g.cp), tq = std::atan2(g.sq, g.cq);
  const bool p = std::abs(tp) >= std::abs(tq);
  return {false, p ? 1 : 3, p ? tp : tq,
          "against its chord, beyond the beam's small-rotation validity (Eq. 3b/3c: e = l0 sin theta)"};
}

void PlanarBeam::constitutive(std::span<const double> params, DefMat& S) const {
  const double EA = params.size() > 0 ? params[0] : 0.0;
  const double EI = params.size() > 1 ? params[1] : 0.0;
  S.setZero(3, 3);
  S(0, 0) = EA / l0_;
  const double k = EI / (l0_ * l0_ * l0_);
  S(1, 1) = 4.0 * k;
  S(2, 2) = 4.0 * k;
  S(1, 2) = -2.0 * k;
  S(2, 1) = -2.0 * k;
}

// ---------------------------------------------------------------------------------------------
// Inertia. The field velocity and the cross-section's angular velocity are linear in the seven rates
//   s = (t.vp, t.vq, n.vp, n.vq, D2d, D3d, alphad),  alphad = n.(vq - vp)/l,
//   D2d = k2 (phipd - alphad), D3d = k3 (phiqd - alphad):
//   rd = t ((1-xi) t.vp + xi t.vq - alphad w) + n ((1-xi) n.vp + xi n.vq + H2 D2d + H3 D3d),
//   psid = alphad + (H2' D2d + H3' D3d)/l0,
// so T = l0/2 s^T B s with B from the closed-form integrals over xi in [0, 1]
//   int (1-xi)^2 = int xi^2 = 1/3, int xi(1-xi) = 1/6,
//   int (1-xi) H2 = int xi H3 = 1/20, int xi H2 = int (1-xi) H3 = 1/30,
//   int H2^2 = int H3^2 = 1/105, int H2 H3 = 1/140,
//   int H2'^2 = int H3'^2 = 2/15, int H2' H3' = 1/30, int H2' = int H3' = 0.
// M = l0 (ds/dx)^T B (ds/dx) is written entry by entry in the chord frame: the position blocks are
// combinations of I, t n^T, n t^T and n n^T, the position-angle entries multiples of n.
// h = l0 (ds/dx)^T b with b = int (rhoA (drd/ds)^T r'' + rhoI (dpsid/ds)^T psi'') over xi and the
// convective accelerations (xdd = 0)
//   r'' = t (-alphadd w - 2 alphad wd) + n (-alphad^2 w + wdd),  psi'' = alphadd + (H2' D2dd + H3' D3dd)/l0,
// alphadd = -xd^T (d2 theta) xd.
struct PlanarBeam::Inertial {
  double rA, rI;        // l0 rhoA, l0 rhoI (the factor l0 of the integrals)
  double a20, a30;      // rA/20, rA/30
  double M1, Mx;        // rA int (1-xi) w, rA int xi w
  double W2, W3;        // rA int H2 w, rA int H3 w
  double cA, c22, c23;  // B entries of alphad^2, D2d^2 (and D3d^2), D2d D3d
};

inline void PlanarBeam::inertial(const Geometry& g, const ElementInertia& inertia, Inertial& c) const {
  c.rA = inertia.rhoA * l0_;
  c.rI = inertia.rhoI * l0_;
  c.a20 = k20 * c.rA;
  c.a30 = k30 * c.rA;
  const double a105 = k105 * c.rA, a140 = k140 * c.rA, rIl = il02_ * c.rI;
  c.M1 = c.a20 * g.D2 + c.a30 * g.D3;
  c.Mx = c.a30 * g.D2 + c.a20 * g.D3;
  c.W2 = a105 * g.D2 + a140 * g.D3;
  c.W3 = a140 * g.D2 + a105 * g.D3;
  c.cA = g.D2 * c.W2 + g.D3 * c.W3 + c.rI;
  c.c22 = a105 + 2.0 * k15 * rIl;
  c.c23 = a140 + k30 * rIl;
}

void PlanarBeam::mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const {
  if (!inertia.any()) {
    M.setZero(6, 6);
    return;
  }
  Geometry g;
  geometry(x, g);
  Inertial c;
  inertial(g, inertia, c);
  massAt(g, c, M);
}

void PlanarBeam::velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const {
  if (!inertia.any()) {
    h.setZero(6);
    return;
  }
  Geometry g;
  geometry(x, g);
  Inertial c;
  inertial(g, inertia, c);
  Rates r;
  rates(g, xd, r);
  velocityForcesAt(g, c, r, h);
}

void PlanarBeam::dynamicTerms(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemMat& M,
                              ElemVec& h, DefVec& d2) const {
  Geometry g;
  geometry(x, g);
  Rates r;
  rates(g, xd, r);
  secondDerivativeAt(g, r, d2);
  if (!inertia.any()) {
    M.setZero(6, 6);
    h.setZero(6);
    return;
  }
  Inertial c;
  inertial(g, inertia, c);
  massAt(g, c, M);
  velocityForcesAt(g, c, r, h);
}

inline void PlanarBeam::massAt(const Geometry& g, const Inertial& c, ElemMat& M) const {
  // ds/dx: alphad has gradient (-n/l, 0, n/l, 0); with delta = (n, 0, -n, 0) in x,
  // dD2d/dx = k2/l delta + k2 e_phip, dD3d/dx = k3/l delta + k3 e_phiq, dalphad/dx = -delta/l.
  // The D2d, D3d, alphad part of B gives sig delta delta^T + sym(delta (pi2 e_phip + pi3 e_phiq)^T) + ...
  const double il = g.il, k2l = g.k2 * il, k3l = g.k3 * il;
  const double pi2 = g.k2 * (c.c22 * k2l + c.c23 * k3l), pi3 = g.k3 * (c.c22 * k3l + c.c23 * k2l);
  const double sig = il * (pi2 + pi3 + c.cA * il);
  // couplings rhoA (n.vp (D2d/20 + D3d/30) + n.vq (D2d/30 + D3d/20))
  const double p2 = c.a20 * g.k2, p3 = c.a30 * g.k3, q2 = c.a30 * g.k2, q3 = c.a20 * g.k3;
  const double fp = il * (p2 + p3), fq = il * (q2 + q3);
  // couplings -rhoA alphad (t.vp int (1-xi) w + t.vq int xi w)
  const double mu1 = c.M1 * il, mux = c.Mx * il;
  // n n^T coefficients of the position blocks beyond the rigid rod rhoA [[1/3, 1/6], [1/6, 1/3]] I2
  const double sP = sig + 2.0 * fp, sQ = sig - 2.0 * fq, sPQ = fq - fp - sig;
  // position-angle entries (along n)
  const double nPp = pi2 + p2, nQp = q2 - pi2, nPq = pi3 + p3, nQq = q3 - pi3;
  const double ex = g.ex, ey = g.ey, exx = ex * ex, eyy = ey * ey, exy = ex * ey, dxy = exx - eyy;
  const double r3 = c.rA / 3.0, r6 = c.rA / 6.0;
  // M_pp = r3 I + mu1 (t n^T + n t^T) + sP n n^T, M_qq = r3 I - mux (t n^T + n t^T) + sQ n n^T,
  // M_pq = r6 I - mu1 t n^T + mux n t^T + sPQ n n^T.
  const double M00 = r3 - 2.0 * mu1 * exy + sP * eyy, M01 = mu1 * dxy - sP * exy;
  const double M11 = r3 + 2.0 * mu1 * exy + sP * exx;
  const double M33 = r3 + 2.0 * mux * exy + sQ * eyy, M34 = -mux * dxy - sQ * exy;
  const double M44 = r3 - 2.0 * mux * exy + sQ * exx;
  const double M03 = r6 + (mu1 - mux) * exy + sPQ * eyy, M14 = r6 - (mu1 - mux) * exy + sPQ * exx;
  const double M04 = -mu1 * exx - mux * eyy - sPQ * exy, M13 = mu1 * eyy + mux * exx - sPQ * exy;
  const double M22 = c.c22 * g.k2 * g.k2, M55 = c.c22 * g.k3 * g.k3, M25 = c.c23 * g.k2 * g.k3;
  M.resize(6, 6);
  Eigen::Map<Mat6> Mm(M.data());
  Mm << M00, M01, -nPp * ey, M03, M04, -nPq * ey, M01, M11, nPp * ex, M13, M14, nPq * ex, -nPp * ey, nPp * ex, M22,
      -nQp * ey, nQp * ex, M25, M03, M13, -nQp * ey, M33, M34, -nQq * ey, M04, M14, nQp * ex, M34, M44, nQq * ex,
      -nPq * ey, nPq * ex, M25, -nQq * ey, nQq * ex, M55;
}

inline void PlanarBeam::velocityForcesAt(const Geometry& g, const Inertial& c, const Rates& r, ElemVec& h) const {
  const double ad = r.ad, ad2 = ad * ad, add = -r.d2th;
  // r'' = t (H2 t2 + H3 t3) + n (H2 n2 + H3 n3)
  const double t2 = -add * g.D2 - 2.0 * ad * r.D2d, t3 = -add * g.D3 - 2.0 * ad * r.D3d;
  const double n2 = r.D2dd - ad2 * g.D2, n3 = r.D3dd - ad2 * g.D3;
  // b on alphad, D2d, D3d (rhoA int (-w) t.r'' + rhoI int psi''; the H2, H3 moments of n.r'' and H2' psi'')
  const double bad = c.rI * add - (t2 * c.W2 + t3 * c.W3);
  const double bD2 = c.c22 * r.D2dd + c.c23 * r.D3dd - ad2 * c.W2;
  const double bD3 = c.c23 * r.D2dd + c.c22 * r.D3dd - ad2 * c.W3;
  // through ds/dx (see massAt): -gam n at p, gam n at q
  const double gam = g.il * (bad - g.k2 * bD2 - g.k3 * bD3);
  const double uP = c.a20 * t2 + c.a30 * t3, vP = c.a20 * n2 + c.a30 * n3 - gam;
  const double uQ = c.a30 * t2 + c.a20 * t3, vQ = c.a30 * n2 + c.a20 * n3 + gam;
  h.resize(6);
  h[0] = uP * g.ex - vP * g.ey;
  h[1] = uP * g.ey + vP * g.ex;
  h[2] = g.k2 * bD2;
  h[3] = uQ * g.ex - vQ * g.ey;
  h[4] = uQ * g.ey + vQ * g.ex;
  h[5] = g.k3 * bD3;
}

void PlanarBeam::gravityForces(const ElemVec& x, const ElementInertia& inertia, double gx, double gy,
                               ElemVec& f) const {
  if (inertia.rhoA == 0.0) {
    f.setZero(6);
    return;
  }
  Geometry g;
  geometry(x, g);
  // f = rhoA l0 int J^T g: int (1-xi) = int xi = 1/2 give g/2 at each position node; with
  // int H2 = int H3 = 1/12, the rotation of the chord (int w = (D2 + D3)/12) and the lateral
  // shapes add beta n at p, -beta n at q and gn k/12 at the angles.
  const double m = inertia.rhoA * l0_;
  const double gt = g.ex * gx + g.ey * gy, gn = g.ex * gy - g.ey * gx;
  const double beta = k12 * g.il * ((g.D2 + g.D3) * gt + (g.k2 + g.k3) * gn);
  f.resize(6);
  f[0] = m * (0.5 * gx - beta * g.ey);
  f[1] = m * (0.5 * gy + beta * g.ex);
  f[2] = m * k12 * gn * g.k2;
  f[3] = m * (0.5 * gx + beta * g.ey);
  f[4] = m * (0.5 * gy - beta * g.ex);
  f[5] = m * k12 * gn * g.k3;
}

bool PlanarBeam::centreLine(const ElemVec& x, Eigen::Ref<Eigen::Matrix3Xd> points, Eigen::Matrix3Xd* ys,
                            Eigen::Matrix3Xd* zs) const {
  (void)ys, (void)zs;
  DefVec e;
  deformations(x, e);
  const double px = x[0], py = x[1], qx = x[3], qy = x[4];
  const double alpha = std::atan2(qy - py, qx - px);
  const double nx = -std::sin(alpha), ny = std::cos(alpha);
  const double e2 = std::isfinite(e[1]) ? e[1] : 0.0, e3 = std::isfinite(e[2]) ? e[2] : 0.0;
  const Eigen::Index n = points.cols();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double xi = n > 1 ? static_cast<double>(k) / static_cast<double>(n - 1) : 0.0;
    const double w = xi * (1 - xi) * (1 - xi) * e2 + xi * xi * (1 - xi) * e3;
    points.col(k) << (1 - xi) * px + xi * qx + nx * w, (1 - xi) * py + xi * qy + ny * w, 0.0;
  }
  return true;
}

}  // namespace flexmb::core
