#pragma once
// BEAMW: the spatial beam with warping (Vlasov non-uniform torsion), core/elements/BEAMW.md.
//
// Coordinates x = [x_p (3), lambda_p (4), w_p, x_q (3), lambda_q (4), w_q]: BEAM's fourteen with the
// warping coordinate of each end after its orientation, in SPACAR Light's slot order
// (BEAMW e p Rp Wp q Rq Wq y1 y2 y3). w is the rate of twist dphi/ds of the cross-section (rad per
// length), the amplitude of the warping displacement u = -omega(y, z) phi'.
//   e1..e6   exactly BEAM's (SpatialBeam.hpp), computed by a SpatialBeam on the fourteen
//   e7 = l0^2 (w_p - w_p0) - e2,   e8 = l0^2 (w_q - w_q0) - e2
// e7, e8 are l0 times the end twist rate minus the mean twist rate (l0 [l0 phi'_k - (phi_q - phi_p)]):
// zero for uniform torsion at any twist, nonzero where warping is restrained. Their second
// derivatives are -d2e2 (w enters linearly), so everything of BEAM is reused.
// Constitutive (ESTIFF EA GIt EIy EIz cy cz ECw): BEAM's 6 x 6 and the cubic Hermite Vlasov energy
//   S(7:8, 7:8) = GIt/(30 l0^3) [[4, -1], [-1, 4]] + ECw/l0^5 [[4, 2], [2, 4]].
// Inertia (EM rhoA Jxx Jyy Jzz Jyz Jw): BEAM's, plus the warping inertia lumped as Jw l0/2 on each
// warping coordinate (constant: no velocity forces, no gravity).
#include <Eigen/Core>

#include "core/elements/Element.hpp"
#include "core/elements/SpatialBeam.hpp"

namespace flexmb::core {

class SpatialWarpingBeam final : public Element {
 public:
  // x0: 16 initial coordinates; y: the cross-section y direction. Throws std::invalid_argument as BEAM.
  SpatialWarpingBeam(const ElemVec& x0, const double* y);
  static std::unique_ptr<Element> create(const ElemVec& x0, const double* y, const ElementOptions& o);

  int numCoords() const override { return 16; }
  int numDeformations() const override { return 8; }
  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void deformationsAndJacobian(const ElemVec& x, DefVec& e, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  // params = [EA, GIt, EIy, EIz, cy, cz, ECw] (missing trailing entries 0).
  void constitutive(std::span<const double> params, DefMat& S) const override;

  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const override;
  void dynamicTerms(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemMat& M, ElemVec& h,
                    DefVec& d2) const override;
  void gravityForces3(const ElemVec& x, const ElementInertia& inertia, const double* g, ElemVec& f) const override;
  ElementValidity validity(const ElemVec& x) const override;
  double referenceLength() const override { return beam_.l0(); }

  double l0() const { return beam_.l0(); }
  // BEAM's triad at end p (the `.sbd` rxyz).
  bool elementFrame(int end, Eigen::Matrix3d& A) const override { return beam_.elementFrame(end, A); }

  // Local indices of the warping coordinates.
  static constexpr int kWp = 7, kWq = 15;

 private:
  // BEAM's fourteen coordinates of x (the warping ones left out), and a BEAM vector put back.
  static void beamPart(const ElemVec& x, ElemVec& xb);
  static void fromBeam(const ElemVec& vb, ElemVec& v);
  static void fromBeam(const ElemMat& Mb, ElemMat& M);

  SpatialBeam beam_;
  double wp0_ = 0.0, wq0_ = 0.0;
};

}  // namespace flexmb::core
