#include "core/elements/SpatialBeam.hpp"

#include <cmath>
#include <stdexcept>

#include "core/elements/CoRotatedCurve.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/elements/SpatialPrimitives.hpp"

namespace flexmb::core {

namespace {
using namespace spatial;
constexpr int XP = 0, LP = 3, XQ = 7, LQ = 10;
using S14 = Scalar<14>;

// 4-point Gauss on [0, 1] (exact to degree 7: the mass integrand J^T J is of degree 6).
constexpr double kGaussXi[4] = {0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563,
                                0.5 + 0.5 * 0.3399810435848563, 0.5 + 0.5 * 0.8611363115940526};
constexpr double kGaussW[4] = {0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461, 0.5 * 0.6521451548625461,
                               0.5 * 0.3478548451374538};
}  // namespace

SpatialBeam::SpatialBeam(const ElemVec& x0, const double* y, bool bendingCorrected) : corrected_(bendingCorrected) {
  if (x0.size() != 14) throw std::invalid_argument("spatial beam: expected 14 initial coordinates");
  const Vec3 d = x0.segment<3>(XQ) - x0.segment<3>(XP);
  l0_ = d.norm();
  if (!(l0_ > 0.0)) throw std::invalid_argument("end nodes coincide (zero length)");
  const Mat3 F = euler::elementFrame(d / l0_, Vec3(y[0], y[1], y[2]));
  // Body-frame triads: A_k = R(lambda_k0)^T F, with R of the normalised initial parameters.
  const Vec4 lp = x0.segment<4>(LP), lq = x0.segment<4>(LQ);
  if (!(lp.norm() > 0.0) || !(lq.norm() > 0.0)) throw std::invalid_argument("initial Euler parameters are zero");
  Ap_ = euler::rotation(lp.normalized()).transpose() * F;
  Aq_ = euler::rotation(lq.normalized()).transpose() * F;
}

std::unique_ptr<Element> SpatialBeam::create(const ElemVec& x0, const double* y, const ElementOptions&) {
  return std::make_unique<SpatialBeam>(x0, y, false);
}
std::unique_ptr<Element> SpatialBeam::createNonlinear(const ElemVec& x0, const double* y, const ElementOptions&) {
  return std::make_unique<SpatialBeam>(x0, y, true);
}

void SpatialBeam::evaluate(const ElemVec& xe, int order, Defs& D) const {
  const Vec14 x = xe;
  S14 l, a, b;
  chordLength<14>(x, XP, XQ, order, l);
  // Elongation.
  D.e[0].assign(l, order);
  D.e[0].v -= l0_;
  // Torsion.
  rotatedProduct<14>(x, LP, Ap_.col(2), LQ, Aq_.col(1), order, a);
  rotatedProduct<14>(x, LP, Ap_.col(1), LQ, Aq_.col(2), order, b);
  D.e[1].clear(order);
  D.e[1].add(0.5 * l0_, a, order);
  D.e[1].add(-0.5 * l0_, b, order);
  // Bending: (l0/l) (R_k a) . d with the signs of the header.
  rotatedOnChord<14>(x, LP, Ap_.col(2), XP, XQ, order, a);
  perLength<14>(a, l, l0_, order, D.e[2]);
  rotatedOnChord<14>(x, LQ, Aq_.col(2), XP, XQ, order, a);
  perLength<14>(a, l, -l0_, order, D.e[3]);
  rotatedOnChord<14>(x, LP, Ap_.col(1), XP, XQ, order, a);
  perLength<14>(a, l, -l0_, order, D.e[4]);
  rotatedOnChord<14>(x, LQ, Aq_.col(1), XP, XQ, order, a);
  perLength<14>(a, l, l0_, order, D.e[5]);
  if (corrected_) {
    // e1 += c(e), c = (2 e3^2 + e3 e4 + 2 e4^2 + 2 e5^2 + e5 e6 + 2 e6^2) / (30 l0).
    const double k = 1.0 / (30.0 * l0_);
    const S14 *e3 = &D.e[2], *e4 = &D.e[3], *e5 = &D.e[4], *e6 = &D.e[5];
    S14& e1 = D.e[0];
    e1.v += k * (2 * e3->v * e3->v + e3->v * e4->v + 2 * e4->v * e4->v + 2 * e5->v * e5->v + e5->v * e6->v +
                 2 * e6->v * e6->v);
    const double c3 = k * (4 * e3->v + e4->v), c4 = k * (e3->v + 4 * e4->v);
    const double c5 = k * (4 * e5->v + e6->v), c6 = k * (e5->v + 4 * e6->v);
    if (order >= 1) e1.g += c3 * e3->g + c4 * e4->g + c5 * e5->g + c6 * e6->g;
    if (order >= 2) {
      e1.H += c3 * e3->H + c4 * e4->H + c5 * e5->H + c6 * e6->H;
      e1.H += k * (4.0 * (e3->g * e3->g.transpose() + e4->g * e4->g.transpose() + e5->g * e5->g.transpose() +
                          e6->g * e6->g.transpose()) +
                   (e3->g * e4->g.transpose() + e4->g * e3->g.transpose()) +
                   (e5->g * e6->g.transpose() + e6->g * e5->g.transpose()));
    }
  }
}

void SpatialBeam::constitutive(std::span<const double> p, DefMat& S) const {
  auto at = [&](size_t i) { return i < p.size() ? p[i] : 0.0; };
  S.setZero(6, 6);
  const double l3 = l0_ * l0_ * l0_;
  S(0, 0) = at(0) / l0_;
  S(1, 1) = at(1) / l3;
  auto pair = [&](int i, double EI, double c) {
    const double F = 12.0 * c / (l0_ * l0_);
    const double k = EI / (l3 * (1.0 + F));
    S(i, i) = S(i + 1, i + 1) = k * (4.0 + F);
    S(i, i + 1) = S(i + 1, i) = k * (F - 2.0);
  };
  pair(2, at(2), at(4));
  pair(4, at(3), at(5));
}

// ---------------------------------------------------------------------------------------------
// Inertia.

Eigen::Matrix3d SpatialBeam::rotaryInertia(const Eigen::Matrix3d& A, const ElementInertia& in) const {
  Mat3 Jl;
  Jl << in.jxx, 0.0, 0.0, 0.0, in.jyy, in.jyz, 0.0, in.jyz, in.jzz;
  return (0.5 * l0_) * A * Jl * A.transpose();
}

namespace {
struct Field {
  double h10, h11;
};
inline Field shape(double xi) { return {xi * (1 - xi) * (1 - xi), xi * xi * (xi - 1)}; }

// J = dr/dx (3 x 14) of the translational field at xi.
void fieldJacobian(double xi, double l0, const Field& f, const Mat3& Pl, const Mat34& Jp, const Mat34& Jq,
                   Eigen::Matrix<double, 3, 14>& J) {
  const double c = l0 * (f.h10 + f.h11);
  J.block<3, 3>(0, XP) = (1.0 - xi) * Mat3::Identity() + c * Pl;
  J.block<3, 3>(0, XQ) = xi * Mat3::Identity() - c * Pl;
  J.block<3, 4>(0, LP) = (l0 * f.h10) * Jp;
  J.block<3, 4>(0, LQ) = (l0 * f.h11) * Jq;
}
// What every Gauss point's field Jacobian (fieldJacobian) needs of a configuration x: the chord's
// direction e and length l, the projector (I - e e^T) / l, and the end tangents' Jacobians.
struct ChordFrame {
  Vec3 e;
  double l;
  Mat3 Pl;
  Mat34 Jp, Jq;
  ChordFrame(const Eigen::Matrix<double, 14, 1>& x, const Mat3& Ap, const Mat3& Aq) {
    const Vec3 d = x.segment<3>(XQ) - x.segment<3>(XP);
    l = d.norm();
    e = d / l;
    Pl = (Mat3::Identity() - e * e.transpose()) / l;
    Jp = euler::rotatedJacobian(x.segment<4>(LP), Ap.col(0));
    Jq = euler::rotatedJacobian(x.segment<4>(LQ), Aq.col(0));
  }
};

}  // namespace

void SpatialBeam::mass(const ElemVec& xe, const ElementInertia& in, ElemMat& M) const {
  Mat14 Mf = Mat14::Zero();
  const Vec14 x = xe;
  if (in.rhoA != 0.0) {
    const ChordFrame c(x, Ap_, Aq_);
    Eigen::Matrix<double, 3, 14> J;
    for (int k = 0; k < 4; ++k) {
      fieldJacobian(kGaussXi[k], l0_, shape(kGaussXi[k]), c.Pl, c.Jp, c.Jq, J);
      Mf.noalias() += (kGaussW[k] * in.rhoA * l0_) * J.transpose() * J;
    }
  }
  const Mat3 Jrp = rotaryInertia(Ap_, in), Jrq = rotaryInertia(Aq_, in);
  const Mat34 Gp = euler::bodyRateMatrix(x.segment<4>(LP)), Gq = euler::bodyRateMatrix(x.segment<4>(LQ));
  Mf.block<4, 4>(LP, LP) += 4.0 * Gp.transpose() * Jrp * Gp;
  Mf.block<4, 4>(LQ, LQ) += 4.0 * Gq.transpose() * Jrq * Gq;
  M = Mf;
}

void SpatialBeam::velocityForces(const ElemVec& xe, const ElemVec& xde, const ElementInertia& in, ElemVec& h) const {
  Vec14 hf = Vec14::Zero();
  const Vec14 x = xe, xd = xde;
  if (in.rhoA != 0.0) {
    const ChordFrame c(x, Ap_, Aq_);
    const Vec3& e = c.e;
    const double l = c.l;
    // Second derivatives along xd: d2 t_k = 2 R(lambdad_k) a, d2 e_l[u, u] below.
    const Vec3 u = xd.segment<3>(XQ) - xd.segment<3>(XP);
    const Vec3 Pu = u - e * e.dot(u);
    const Vec3 d2e = -(2.0 * e.dot(u) * Pu + u.dot(Pu) * e) / (l * l);
    const Vec3 d2tp = 2.0 * euler::rotation(xd.segment<4>(LP)) * Ap_.col(0);
    const Vec3 d2tq = 2.0 * euler::rotation(xd.segment<4>(LQ)) * Aq_.col(0);
    Eigen::Matrix<double, 3, 14> J;
    for (int k = 0; k < 4; ++k) {
      const Field f = shape(kGaussXi[k]);
      fieldJacobian(kGaussXi[k], l0_, f, c.Pl, c.Jp, c.Jq, J);
      const Vec3 ac = l0_ * (f.h10 * d2tp + f.h11 * d2tq - (f.h10 + f.h11) * d2e);
      hf.noalias() += (kGaussW[k] * in.rhoA * l0_) * J.transpose() * ac;
    }
  }
  auto rotary = [&](int at, const Mat3& Jr) {
    const Vec4 lam = x.segment<4>(at), lamd = xd.segment<4>(at);
    const Mat34 G = euler::bodyRateMatrix(lam), Gd = euler::bodyRateMatrix(lamd);
    hf.segment<4>(at) += 8.0 * Gd.transpose() * (Jr * (G * lamd));
  };
  rotary(LP, rotaryInertia(Ap_, in));
  rotary(LQ, rotaryInertia(Aq_, in));
  h = hf;
}

void SpatialBeam::gravityForces3(const ElemVec& xe, const ElementInertia& in, const double* g, ElemVec& f) const {
  Vec14 ff = Vec14::Zero();
  if (in.rhoA != 0.0) {
    const Vec14 x = xe;
    const Vec3 gv(g[0], g[1], g[2]);
    const ChordFrame c(x, Ap_, Aq_);
    Eigen::Matrix<double, 3, 14> J;
    for (int k = 0; k < 4; ++k) {
      fieldJacobian(kGaussXi[k], l0_, shape(kGaussXi[k]), c.Pl, c.Jp, c.Jq, J);
      ff.noalias() += (kGaussW[k] * in.rhoA * l0_) * J.transpose() * gv;
    }
  }
  f = ff;
}

bool SpatialBeam::centreLine(const ElemVec& x, Eigen::Ref<Eigen::Matrix3Xd> points, Eigen::Matrix3Xd* ys,
                             Eigen::Matrix3Xd* zs) const {
  // Normalised Euler parameters: a mode shape x + s dx leaves |lambda| != 1.
  auto triad = [&](int at, const Eigen::Matrix3d& A) -> Eigen::Matrix3d {
    const Eigen::Vector4d l = x.segment<4>(at);
    const double n = l.norm();
    if (!(n > 0) || !std::isfinite(n)) return A;
    return euler::rotation(l / n) * A;
  };
  coRotatedCurve(x.segment<3>(0), triad(3, Ap_), x.segment<3>(7), triad(10, Aq_), l0_, true, points, ys, zs);
  return true;
}

}  // namespace flexmb::core
