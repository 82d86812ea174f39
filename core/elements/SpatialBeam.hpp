#pragma once
// BEAM / BEAMNL: the spatial flexible beam (docs/theory/spatial-elements.md section 4).
//
// Coordinates x = [x_p (3), lambda_p (4), x_q (3), lambda_q (4)]. The element triad at node k is
// R(lambda_k) A_k, with A_k = R(lambda_k0)^T [e_x0 e_y0 e_z0] fixed at creation (e_x0 the initial
// chord, e_y0 the given y vector orthogonalised against it). With d = x_q - x_p, l = |d|:
//   e1 = l - l0                                            elongation
//   e2 = l0 (e_z^p . e_y^q - e_y^p . e_z^q) / 2            torsion (~ l0 (phi_q - phi_p))
//   e3 = +(l0/l) e_z^p . d,  e4 = -(l0/l) e_z^q . d      bending in the x-z plane (EIy)
//   e5 = -(l0/l) e_y^p . d,  e6 = +(l0/l) e_y^q . d      bending in the x-y plane (EIz)
// Bending is measured as the planar PLBEAM does (Eq. 3b/3c: l0 sin theta, positive for a positive
// rotation of node p about the local axis relative to the chord), so a BEAM model lying in the
// x-y plane has exactly the deformations (e1, e5, e6) of the PLBEAM model (e1, e2, e3).
// BEAMNL adds the bending correction (Eq. 3a in both planes) to e1:
//   e1 += (2 e3^2 + e3 e4 + 2 e4^2 + 2 e5^2 + e5 e6 + 2 e6^2) / (30 l0).
// Every deformation is zero in the initial configuration and invariant under rigid motions.
//
// Inertia (EM rhoA Jxx Jyy Jzz Jyz per length): translational mass consistent with the
// co-rotated cubic field r(xi) = (1-xi) x_p + xi x_q + l0 [H10 (t_p - e_l) + H11 (t_q - e_l)],
// t_k = R(lambda_k) A_k e_x, exact by 4-point Gauss, with its exact velocity forces; rotary inertia
// of the cross-section lumped at the ends (half the element each) as a rigid body on lambda_k:
// M = 4 G^T J G, h = 8 G(lambdad)^T J G lambdad.
#include <Eigen/Core>

#include "core/elements/EvaluatedElement.hpp"

namespace flexmb::core {

class SpatialBeam final : public EvaluatedElement<SpatialBeam, 14, 6> {
 public:
  // x0: 14 initial coordinates; y: the cross-section y direction. Throws std::invalid_argument for
  // coincident end nodes or y along the chord.
  SpatialBeam(const ElemVec& x0, const double* y, bool bendingCorrected);
  static std::unique_ptr<Element> create(const ElemVec& x0, const double* y, const ElementOptions& o);
  static std::unique_ptr<Element> createNonlinear(const ElemVec& x0, const double* y, const ElementOptions& o);

  // params = [EA, GIt, EIy, EIz, cy, cz] (missing trailing entries 0), docs/theory/spatial-elements.md 4.2:
  // S11 = EA/l0, S22 = GIt/l0^3, per bending pair EI/(l0^3 (1+F)) [[4+F, F-2], [F-2, 4+F]],
  // F = 12 c/l0^2 (shear flexibility c = EI/(k G A)).
  void constitutive(std::span<const double> params, DefMat& S) const override;

  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const override;
  void gravityForces3(const ElemVec& x, const ElementInertia& inertia, const double* g, ElemVec& f) const override;

  double l0() const { return l0_; }
  bool elementFrame(int end, Eigen::Matrix3d& A) const override {
    if (end < 0 || end > 1) return false;
    A = end == 0 ? Ap_ : Aq_;
    return true;
  }
  double referenceLength() const override { return l0_; }
  // The co-rotated cubic field of the mass matrix (header) through the end triads, with the section
  // axes interpolated between the ends and kept normal to the tangent.
  bool centreLine(const ElemVec& x, Eigen::Ref<Eigen::Matrix3Xd> points, Eigen::Matrix3Xd* ys,
                  Eigen::Matrix3Xd* zs) const override;

 private:
  friend class EvaluatedElement<SpatialBeam, 14, 6>;
  using Vec14 = Vec;
  using Mat14 = Mat;
  // The six deformations of the header with their derivatives up to order (EvaluatedElement).
  void evaluate(const ElemVec& x, int order, Defs& d) const;
  Eigen::Matrix3d rotaryInertia(const Eigen::Matrix3d& A, const ElementInertia& in) const;

  double l0_ = 0.0;
  Eigen::Matrix3d Ap_, Aq_;
  bool corrected_ = false;
};

}  // namespace flexmb::core
