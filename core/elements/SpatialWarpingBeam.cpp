#include "core/elements/SpatialWarpingBeam.hpp"

#include <stdexcept>

namespace flexmb::core {

namespace {
// BEAMW local index of BEAM's coordinate i (0..13): the warping coordinates sit at 7 and 15.
constexpr int fromBeamIndex(int i) { return i < 7 ? i : i + 1; }

ElemVec beamCoords(const ElemVec& x) {
  if (x.size() != 16) throw std::invalid_argument("spatial beam with warping: expected 16 initial coordinates");
  ElemVec xb(14);
  for (int i = 0; i < 14; ++i) xb[i] = x[fromBeamIndex(i)];
  return xb;
}
}  // namespace

SpatialWarpingBeam::SpatialWarpingBeam(const ElemVec& x0, const double* y)
    : beam_(beamCoords(x0), y, false), wp0_(x0[kWp]), wq0_(x0[kWq]) {}

std::unique_ptr<Element> SpatialWarpingBeam::create(const ElemVec& x0, const double* y, const ElementOptions&) {
  return std::make_unique<SpatialWarpingBeam>(x0, y);
}

void SpatialWarpingBeam::beamPart(const ElemVec& x, ElemVec& xb) {
  xb.resize(14);
  for (int i = 0; i < 14; ++i) xb[i] = x[fromBeamIndex(i)];
}

void SpatialWarpingBeam::fromBeam(const ElemVec& vb, ElemVec& v) {
  v.setZero(16);
  for (int i = 0; i < 14; ++i) v[fromBeamIndex(i)] = vb[i];
}

void SpatialWarpingBeam::fromBeam(const ElemMat& Mb, ElemMat& M) {
  M.setZero(16, 16);
  for (int j = 0; j < 14; ++j)
    for (int i = 0; i < 14; ++i) M(fromBeamIndex(i), fromBeamIndex(j)) = Mb(i, j);
}

void SpatialWarpingBeam::deformations(const ElemVec& x, DefVec& e) const {
  ElemVec xb;
  beamPart(x, xb);
  DefVec eb;
  beam_.deformations(xb, eb);
  const double l2 = l0() * l0();
  e.resize(8);
  e.head<6>() = eb;
  e[6] = l2 * (x[kWp] - wp0_) - eb[1];
  e[7] = l2 * (x[kWq] - wq0_) - eb[1];
}

namespace {
// BEAM's 6 x 14 Jacobian into BEAMW's 8 x 16: rows 7, 8 are -row 2 plus l0^2 on their w.
void warpingJacobian(const DefJac& Db, double l0, DefJac& De) {
  De.setZero(8, 16);
  for (int j = 0; j < 14; ++j) De.block<6, 1>(0, fromBeamIndex(j)) = Db.col(j);
  De.row(6) = -De.row(1);
  De.row(7) = -De.row(1);
  De(6, SpatialWarpingBeam::kWp) += l0 * l0;
  De(7, SpatialWarpingBeam::kWq) += l0 * l0;
}
}  // namespace

void SpatialWarpingBeam::jacobian(const ElemVec& x, DefJac& De) const {
  ElemVec xb;
  beamPart(x, xb);
  DefJac Db;
  beam_.jacobian(xb, Db);
  warpingJacobian(Db, l0(), De);
}

void SpatialWarpingBeam::deformationsAndJacobian(const ElemVec& x, DefVec& e, DefJac& De) const {
  ElemVec xb;
  beamPart(x, xb);
  DefVec eb;
  DefJac Db;
  beam_.deformationsAndJacobian(xb, eb, Db);
  const double l2 = l0() * l0();
  e.resize(8);
  e.head<6>() = eb;
  e[6] = l2 * (x[kWp] - wp0_) - eb[1];
  e[7] = l2 * (x[kWq] - wq0_) - eb[1];
  warpingJacobian(Db, l0(), De);
}

void SpatialWarpingBeam::secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const {
  ElemVec xb, vb;
  beamPart(x, xb);
  beamPart(v, vb);
  DefVec d2b;
  beam_.secondDerivative(xb, vb, d2b);
  d2.resize(8);
  d2.head<6>() = d2b;
  d2[6] = d2[7] = -d2b[1];
}

void SpatialWarpingBeam::stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const {
  // sum_i sigma_i d2e_i = BEAM's sum with sigma_2 replaced by sigma_2 - sigma_7 - sigma_8.
  ElemVec xb;
  beamPart(x, xb);
  DefVec sb = sigma.head<6>();
  sb[1] -= sigma[6] + sigma[7];
  ElemMat Hb;
  beam_.stressWeightedHessian(xb, sb, Hb);
  fromBeam(Hb, H);
}

void SpatialWarpingBeam::constitutive(std::span<const double> p, DefMat& S) const {
  DefMat Sb;
  beam_.constitutive(p.first(std::min<size_t>(p.size(), 6)), Sb);
  S.setZero(8, 8);
  S.topLeftCorner<6, 6>() = Sb;
  // Cubic Hermite twist field: St Venant part of the non-uniform twist plus the warping energy.
  const double GIt = p.size() > 1 ? p[1] : 0.0, ECw = p.size() > 6 ? p[6] : 0.0;
  const double l = l0(), l3 = l * l * l, a = GIt / (30.0 * l3), b = ECw / (l3 * l * l);
  S(6, 6) = S(7, 7) = 4.0 * a + 4.0 * b;
  S(6, 7) = S(7, 6) = -a + 2.0 * b;
}

void SpatialWarpingBeam::mass(const ElemVec& x, const ElementInertia& in, ElemMat& M) const {
  ElemVec xb;
  beamPart(x, xb);
  ElemMat Mb;
  beam_.mass(xb, in, Mb);
  fromBeam(Mb, M);
  M(kWp, kWp) = M(kWq, kWq) = 0.5 * l0() * in.jw;
}

void SpatialWarpingBeam::velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& in,
                                        ElemVec& h) const {
  ElemVec xb, xdb, hb;
  beamPart(x, xb);
  beamPart(xd, xdb);
  beam_.velocityForces(xb, xdb, in, hb);
  fromBeam(hb, h);
}

void SpatialWarpingBeam::dynamicTerms(const ElemVec& x, const ElemVec& xd, const ElementInertia& in, ElemMat& M,
                                      ElemVec& h, DefVec& d2) const {
  ElemVec xb, xdb, hb;
  beamPart(x, xb);
  beamPart(xd, xdb);
  ElemMat Mb;
  DefVec d2b;
  beam_.dynamicTerms(xb, xdb, in, Mb, hb, d2b);
  fromBeam(Mb, M);
  M(kWp, kWp) = M(kWq, kWq) = 0.5 * l0() * in.jw;
  fromBeam(hb, h);
  d2.resize(8);
  d2.head<6>() = d2b;
  d2[6] = d2[7] = -d2b[1];
}

void SpatialWarpingBeam::gravityForces3(const ElemVec& x, const ElementInertia& in, const double* g, ElemVec& f) const {
  ElemVec xb, fb;
  beamPart(x, xb);
  beam_.gravityForces3(xb, in, g, fb);
  fromBeam(fb, f);
}

ElementValidity SpatialWarpingBeam::validity(const ElemVec& x) const {
  ElemVec xb;
  beamPart(x, xb);
  ElementValidity v = beam_.validity(xb);
  if (v.slot >= 2) ++v.slot;  // BEAM's slots p Rp q Rq are BEAMW's 0 1 3 4
  return v;
}

}  // namespace flexmb::core
