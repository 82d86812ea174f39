#include "core/elements/PlanarBeam.hpp"

#include <cmath>
#include <stdexcept>

namespace flexmb::core {

namespace {

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// All deformations depend on x only through z = (dx, dy, phip, phiq), dx = xq - xp, dy = yq - yp.
// x index i maps to z index kZ[i] with sign kS[i].
constexpr int kZ[6] = {0, 1, 2, 0, 1, 3};
constexpr double kS[6] = {-1.0, -1.0, 1.0, 1.0, 1.0, 1.0};

inline Vec4 reduce(const ElemVec& v) {
  return Vec4(v[3] - v[0], v[4] - v[1], v[2], v[5]);
}
inline Vec6 expand(const Vec4& gz) {
  Vec6 g;
  g << -gz[0], -gz[1], gz[2], gz[0], gz[1], gz[3];
  return g;
}
inline void expandHessian(const Mat4& Hz, ElemMat& H) {
  H.resize(6, 6);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) H(i, j) = kS[i] * kS[j] * Hz(kZ[i], kZ[j]);
}

}  // namespace

struct PlanarBeam::Geometry {
  double dx, dy, l;
  double ex, ey;  // unit chord t = (cos alpha, sin alpha)
  double nx, ny;  // unit normal n = (-sin alpha, cos alpha)
  double sp, cp;  // sin, cos theta_p
  double sq, cq;  // sin, cos theta_q
  Vec4 gp, gq;    // gradients of theta_p, theta_q in z
  Vec4 G2, G3;    // gradients of D2, D3 in z
  double D2, D3;
};

PlanarBeam::PlanarBeam(const ElemVec& x0, ElongationDefinition elongation)
    : elongation_(elongation) {
  if (x0.size() != 6) throw std::invalid_argument("planar beam: expected 6 initial coordinates");
  const double dx = x0[3] - x0[0], dy = x0[4] - x0[1];
  l0_ = std::hypot(dx, dy);
  if (!(l0_ > 0.0)) throw std::invalid_argument("planar beam: end nodes coincide (zero length)");
  beta0_ = std::atan2(dy, dx);
  phi0p_ = x0[2];
  phi0q_ = x0[5];
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
  l0_ = l0;
  beta0_ = std::atan2(dy, dx);
  phi0p_ = x[2] - std::asin(e[1] / l0);
  phi0q_ = x[5] + std::asin(e[2] / l0);
}

std::unique_ptr<Element> PlanarBeam::create(const ElemVec& x0, const ElementOptions& options) {
  return std::make_unique<PlanarBeam>(x0, options.elongation);
}

std::unique_ptr<Element> PlanarBeam::createNonlinear(const ElemVec& x0, const ElementOptions&) {
  return std::make_unique<PlanarBeam>(x0, ElongationDefinition::BendingCorrected);
}

void PlanarBeam::geometry(const ElemVec& x, Geometry& g) const {
  g.dx = x[3] - x[0];
  g.dy = x[4] - x[1];
  g.l = std::sqrt(g.dx * g.dx + g.dy * g.dy);
  const double il = 1.0 / g.l;
  g.ex = g.dx * il;
  g.ey = g.dy * il;
  g.nx = -g.ey;
  g.ny = g.ex;
  const double ap = x[2] - phi0p_ + beta0_, aq = x[5] - phi0q_ + beta0_;
  const double sap = std::sin(ap), cap = std::cos(ap), saq = std::sin(aq), caq = std::cos(aq);
  // theta = a - alpha
  g.sp = sap * g.ex - cap * g.ey;
  g.cp = cap * g.ex + sap * g.ey;
  g.sq = saq * g.ex - caq * g.ey;
  g.cq = caq * g.ex + saq * g.ey;
  // d alpha / d d = n / l
  g.gp = Vec4(-g.nx * il, -g.ny * il, 1.0, 0.0);
  g.gq = Vec4(-g.nx * il, -g.ny * il, 0.0, 1.0);
  g.G2 = (l0_ * g.cp) * g.gp;
  g.G3 = (-l0_ * g.cq) * g.gq;
  g.D2 = l0_ * g.sp;
  g.D3 = -l0_ * g.sq;
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

void PlanarBeam::deformationsAt(const Geometry& g, DefVec& e) const {
  e.resize(3);
  e[0] = g.l - l0_;
  if (elongation_ == ElongationDefinition::BendingCorrected)
    e[0] += (2.0 * g.D2 * g.D2 + g.D2 * g.D3 + 2.0 * g.D3 * g.D3) / (30.0 * l0_);
  e[1] = g.D2;
  e[2] = g.D3;
}

void PlanarBeam::jacobianAt(const Geometry& g, DefJac& De) const {
  Vec4 G1(g.ex, g.ey, 0.0, 0.0);
  if (elongation_ == ElongationDefinition::BendingCorrected) {
    const double c = 1.0 / (30.0 * l0_);
    G1 += (c * (4.0 * g.D2 + g.D3)) * g.G2 + (c * (g.D2 + 4.0 * g.D3)) * g.G3;
  }
  De.resize(3, 6);
  De.row(0) = expand(G1).transpose();
  De.row(1) = expand(g.G2).transpose();
  De.row(2) = expand(g.G3).transpose();
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
  secondDerivativeAt(g, v, d2);
}

void PlanarBeam::secondDerivativeAt(const Geometry& g, const ElemVec& v, DefVec& d2) const {
  const Vec4 vz = reduce(v);
  const double tv = g.ex * vz[0] + g.ey * vz[1];  // t . delta d
  const double nv = g.nx * vz[0] + g.ny * vz[1];  // n . delta d
  const double il = 1.0 / g.l;
  const double hl = nv * nv * il;              // v^T (d2 l) v
  const double hth = 2.0 * tv * nv * il * il;  // v^T (d2 theta) v = -v^T (d2 alpha) v
  const double tp = g.gp.dot(vz), tq = g.gq.dot(vz);
  const double h2 = l0_ * (-g.sp * tp * tp + g.cp * hth);
  const double h3 = -l0_ * (-g.sq * tq * tq + g.cq * hth);
  d2.resize(3);
  d2[0] = hl;
  if (elongation_ == ElongationDefinition::BendingCorrected) {
    const double c = 1.0 / (30.0 * l0_);
    const double a = g.G2.dot(vz), b = g.G3.dot(vz);
    d2[0] += c * ((4.0 * g.D2 + g.D3) * h2 + (g.D2 + 4.0 * g.D3) * h3 +
                  4.0 * a * a + 2.0 * a * b + 4.0 * b * b);
  }
  d2[1] = h2;
  d2[2] = h3;
}

void PlanarBeam::stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const {
  Geometry g;
  geometry(x, g);
  const double il = 1.0 / g.l;
  const double s1 = sigma[0];
  double c2 = sigma[1], c3 = sigma[2];
  Mat4 Hz = Mat4::Zero();
  // sigma1 * d2 l = sigma1 n n^T / l on the d block
  Hz(0, 0) = s1 * g.nx * g.nx * il;
  Hz(0, 1) = s1 * g.nx * g.ny * il;
  Hz(1, 1) = s1 * g.ny * g.ny * il;
  if (elongation_ == ElongationDefinition::BendingCorrected) {
    const double c = 1.0 / (30.0 * l0_);
    c2 += s1 * c * (4.0 * g.D2 + g.D3);
    c3 += s1 * c * (g.D2 + 4.0 * g.D3);
    const double k = s1 * c;
    Hz.noalias() += (4.0 * k) * (g.G2 * g.G2.transpose() + g.G3 * g.G3.transpose()) +
                    k * (g.G2 * g.G3.transpose() + g.G3 * g.G2.transpose());
  }
  // c2 d2 D2 + c3 d2 D3, with d2 D2 = l0(-sp gp gp^T + cp Hth), d2 D3 = -l0(-sq gq gq^T + cq Hth)
  Hz.noalias() += (-c2 * l0_ * g.sp) * (g.gp * g.gp.transpose()) +
                  (c3 * l0_ * g.sq) * (g.gq * g.gq.transpose());
  const double kth = l0_ * (c2 * g.cp - c3 * g.cq) * il * il;  // times (t n^T + n t^T)
  Hz(0, 0) += kth * 2.0 * g.ex * g.nx;
  Hz(0, 1) += kth * (g.ex * g.ny + g.nx * g.ey);
  Hz(1, 1) += kth * 2.0 * g.ey * g.ny;
  Hz(1, 0) = Hz(0, 1);
  expandHessian(Hz, H);
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
// Inertia. With t, n the chord frame, J = dr/dx has components
//   t.J = (1-xi) t^T E_p + xi t^T E_q - w A,   n.J = (1-xi) n^T E_p + xi n^T E_q + H2 G2 + H3 G3,
// A = d alpha/dx, G2/G3 = dD2/dx, dD3/dx, and Jpsi = A + (H2' G2 + H3' G3)/l0. The convective
// acceleration (xdd = 0) is
//   r'' = t(-alphadd w - 2 alphad wd) + n(-alphad^2 w + wdd),  psi'' = alphadd + (H2' D2dd + H3' D3dd)/l0,
// with alphadd = -2 alphad ldot / l and D2dd = xd^T d2D2 xd etc.
// All integrands are polynomials in xi, integrated exactly in closed form with the moments
//   int (1-xi)^2 = int xi^2 = 1/3, int xi(1-xi) = 1/6,
//   int (1-xi) H2 = int xi H3 = 1/20, int xi H2 = int (1-xi) H3 = 1/30,
//   int H2^2 = int H3^2 = 1/105, int H2 H3 = 1/140,
//   int H2'^2 = int H3'^2 = 2/15, int H2' H3' = 1/30, int H2' = int H3' = 0.

namespace {

// Moments of f = H2 f2 + H3 f3 against (1-xi), xi, H2, H3.
struct Moments {
  double m1, mx, mH2, mH3;
};
inline Moments moments(double f2, double f3) {
  return {f2 / 20.0 + f3 / 30.0, f2 / 30.0 + f3 / 20.0, f2 / 105.0 + f3 / 140.0,
          f2 / 140.0 + f3 / 105.0};
}

struct InertiaRows {
  Vec6 A, G2, G3;  // d alpha/dx, dD2/dx, dD3/dx
};
inline void inertiaRows(const Vec4& G2z, const Vec4& G3z, double nx, double ny, double il,
                        InertiaRows& r) {
  r.A = expand(Vec4(nx * il, ny * il, 0.0, 0.0));
  r.G2 = expand(G2z);
  r.G3 = expand(G3z);
}

}  // namespace

void PlanarBeam::mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const {
  if (!inertia.any()) {
    M.setZero(6, 6);
    return;
  }
  Geometry g;
  geometry(x, g);
  massAt(g, inertia, M);
}

void PlanarBeam::velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia,
                                ElemVec& h) const {
  if (!inertia.any()) {
    h.setZero(6);
    return;
  }
  Geometry g;
  geometry(x, g);
  velocityForcesAt(g, xd, inertia, h);
}

void PlanarBeam::dynamicTerms(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemMat& M,
                              ElemVec& h, DefVec& d2) const {
  Geometry g;
  geometry(x, g);
  secondDerivativeAt(g, xd, d2);
  if (!inertia.any()) {
    M.setZero(6, 6);
    h.setZero(6);
    return;
  }
  massAt(g, inertia, M);
  velocityForcesAt(g, xd, inertia, h);
}

void PlanarBeam::massAt(const Geometry& g, const ElementInertia& inertia, ElemMat& M) const {
  InertiaRows R;
  inertiaRows(g.G2, g.G3, g.nx, g.ny, 1.0 / g.l, R);
  const double rA = inertia.rhoA, rI = inertia.rhoI, il02 = 1.0 / (l0_ * l0_);
  const Moments w = moments(g.D2, g.D3);  // moments of w
  const double ww = g.D2 * w.mH2 + g.D3 * w.mH3;  // int w^2
  // M / l0 = rhoA * rod + U V^T + V U^T + U C U^T, U = [A, G2, G3], with
  //   V = rhoA [-(int (1-xi) w) Tp - (int xi w) Tq, Np/20 + Nq/30, Np/30 + Nq/20],
  //   C = [[rhoA int w^2 + rhoI, 0, 0], [0, c22, c23], [0, c23, c22]].
  // Written as U Y^T + Y U^T with Y = V + U C / 2.
  Eigen::Matrix<double, 6, 3> U, Y;
  U.col(0) = R.A;
  U.col(1) = R.G2;
  U.col(2) = R.G3;
  const double c22 = rA / 105.0 + rI * il02 * (2.0 / 15.0);
  const double c23 = rA / 140.0 + rI * il02 / 30.0;
  const double cA = rA * ww + rI;
  Y.col(0) = (0.5 * cA) * R.A;
  Y.col(1) = (0.5 * c22) * R.G2 + (0.5 * c23) * R.G3;
  Y.col(2) = (0.5 * c23) * R.G2 + (0.5 * c22) * R.G3;
  if (rA != 0.0) {
    const double a1 = -rA * w.m1, a2 = -rA * w.mx;
    Y(0, 0) += a1 * g.ex;
    Y(1, 0) += a1 * g.ey;
    Y(3, 0) += a2 * g.ex;
    Y(4, 0) += a2 * g.ey;
    const double p20 = rA / 20.0, p30 = rA / 30.0;
    Y(0, 1) += p20 * g.nx;
    Y(1, 1) += p20 * g.ny;
    Y(3, 1) += p30 * g.nx;
    Y(4, 1) += p30 * g.ny;
    Y(0, 2) += p30 * g.nx;
    Y(1, 2) += p30 * g.ny;
    Y(3, 2) += p20 * g.nx;
    Y(4, 2) += p20 * g.ny;
  }
  Mat6 Mf;
  Mf.noalias() = U * Y.transpose();
  Mf += Mf.transpose().eval();
  // rigid-rod part: rhoA [[1/3, 1/6], [1/6, 1/3]] (x) I2 on the positions
  const double r3 = rA / 3.0, r6 = rA / 6.0;
  Mf(0, 0) += r3;
  Mf(1, 1) += r3;
  Mf(3, 3) += r3;
  Mf(4, 4) += r3;
  Mf(0, 3) += r6;
  Mf(3, 0) += r6;
  Mf(1, 4) += r6;
  Mf(4, 1) += r6;
  M = l0_ * Mf;
}

void PlanarBeam::velocityForcesAt(const Geometry& g, const ElemVec& xd, const ElementInertia& inertia,
                                  ElemVec& h) const {
  const double il = 1.0 / g.l;
  InertiaRows R;
  inertiaRows(g.G2, g.G3, g.nx, g.ny, il, R);
  const Vec4 vz = reduce(xd);
  const double tv = g.ex * vz[0] + g.ey * vz[1];  // ldot
  const double nv = g.nx * vz[0] + g.ny * vz[1];
  const double ad = nv * il;                       // alpha dot
  const double add = -2.0 * ad * tv * il;          // convective alpha ddot
  const double hth = 2.0 * tv * nv * il * il;
  const double tp = g.gp.dot(vz), tq = g.gq.dot(vz);
  const double D2d = g.G2.dot(vz), D3d = g.G3.dot(vz);
  const double D2dd = l0_ * (-g.sp * tp * tp + g.cp * hth);
  const double D3dd = -l0_ * (-g.sq * tq * tq + g.cq * hth);
  const double rA = inertia.rhoA, rI = inertia.rhoI, il0 = 1.0 / l0_;
  // a_t = H2 t2 + H3 t3, a_n = H2 n2 + H3 n3
  const Moments at = moments(-add * g.D2 - 2.0 * ad * D2d, -add * g.D3 - 2.0 * ad * D3d);
  const Moments an = moments(-ad * ad * g.D2 + D2dd, -ad * ad * g.D3 + D3dd);
  const double atw = g.D2 * at.mH2 + g.D3 * at.mH3;  // int w a_t
  // int Jt a_t = Tp int(1-xi) a_t + Tq int xi a_t - A int w a_t
  // int Jn a_n = Np int(1-xi) a_n + Nq int xi a_n + G2 int H2 a_n + G3 int H3 a_n
  // int Jpsi psidd = A alphadd + (G2 int H2' psidd + G3 int H3' psidd)/l0
  Vec6 hf = (rI * add - rA * atw) * R.A;
  hf.noalias() += (rA * an.mH2 + rI * il0 * il0 * (2.0 / 15.0 * D2dd + D3dd / 30.0)) * R.G2;
  hf.noalias() += (rA * an.mH3 + rI * il0 * il0 * (D2dd / 30.0 + 2.0 / 15.0 * D3dd)) * R.G3;
  hf[0] += rA * (at.m1 * g.ex + an.m1 * g.nx);
  hf[1] += rA * (at.m1 * g.ey + an.m1 * g.ny);
  hf[3] += rA * (at.mx * g.ex + an.mx * g.nx);
  hf[4] += rA * (at.mx * g.ey + an.mx * g.ny);
  h = l0_ * hf;
}

void PlanarBeam::gravityForces(const ElemVec& x, const ElementInertia& inertia, double gx, double gy,
                               ElemVec& f) const {
  if (inertia.rhoA == 0.0) {
    f.setZero(6);
    return;
  }
  Geometry g;
  geometry(x, g);
  const double il = 1.0 / g.l;
  const Vec6 A = expand(Vec4(g.nx * il, g.ny * il, 0.0, 0.0));
  const Vec6 G2 = expand(g.G2), G3 = expand(g.G3);
  const double gt = g.ex * gx + g.ey * gy, gn = g.nx * gx + g.ny * gy;
  // integral of J^T g = integral of (Jt gt + Jn gn), with the xi-moments of the shape functions:
  // int (1-xi) = int xi = 1/2, int H2 = int H3 = 1/12.
  const double iw = (g.D2 + g.D3) / 12.0;  // integral of w
  // The linear part gives (t gt + n gn)/2 = g/2 at each position node.
  Vec6 hf;
  hf << 0.5 * gx, 0.5 * gy, 0.0, 0.5 * gx, 0.5 * gy, 0.0;
  hf.noalias() += (-iw * gt) * A + (gn / 12.0) * (G2 + G3);
  f = (inertia.rhoA * l0_) * hf;
}

}  // namespace flexmb::core
