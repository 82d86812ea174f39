#pragma once
// PLBEAM / PLBEAMNL: the planar flexible beam of Boer et al. 2013, Eq. 2-3, with SPACAR's
// consistent, configuration dependent mass (cubic lateral field in the current chord frame).
//
// Coordinates x = [xp, yp, phip, xq, yq, phiq]. The orientation coordinates are absolute angles
// (the .dat BETA values); the element keeps their initial values phi0p, phi0q and the initial chord
// angle beta0, so that with a_p = phip - phi0p + beta0 (likewise a_q) and the current chord angle
// alpha:
//   theta_p = a_p - alpha, theta_q = a_q - alpha   (node rotations relative to the chord),
//   e1 = l - l0                                   (Plain), or
//   e1 = l - l0 + (2 e2^2 + e2 e3 + 2 e3^2)/(30 l0) (BendingCorrected, Eq. 3a),
//   e2 = l0 sin(theta_p)  = (l0/l)((xq-xp) sin a_p - (yq-yp) cos a_p)        (Eq. 3b),
//   e3 = -l0 sin(theta_q) = -(l0/l)((xq-xp) sin a_q - (yq-yp) cos a_q)       (Eq. 3c).
// Every deformation is zero in the initial configuration.
//
// Inertia (exact closed-form integrals over xi in [0, 1]): r(xi) = (1-xi) rp + xi rq + n(alpha) w(xi), w = H2 e2 + H3
// e3 with H2 = xi (1-xi)^2, H3 = xi^2 (1-xi) (e2 ~ l0 theta_p, e3 ~ -l0 theta_q, so w'(0)/l0 = theta_p and w'(1)/l0 =
// theta_q), n = (-sin alpha, cos alpha); cross-section angle psi = alpha + w'(xi)/l0.
#include "core/elements/Element.hpp"

namespace flexmb::core {

class PlanarBeam final : public Element {
 public:
  // x0: initial nodal coordinates (6). Throws std::invalid_argument for coincident end nodes.
  PlanarBeam(const ElemVec& x0, ElongationDefinition elongation);

  static std::unique_ptr<Element> create(const ElemVec& x0, const ElementOptions& options);
  // PLBEAMNL: always the bending-corrected elongation.
  static std::unique_ptr<Element> createNonlinear(const ElemVec& x0, const ElementOptions& options);

  int numCoords() const override { return 6; }
  int numDeformations() const override { return 3; }

  void deformations(const ElemVec& x, DefVec& e) const override;
  void jacobian(const ElemVec& x, DefJac& De) const override;
  void deformationsAndJacobian(const ElemVec& x, DefVec& e, DefJac& De) const override;
  void secondDerivative(const ElemVec& x, const ElemVec& v, DefVec& d2) const override;
  // Ends: (xp, yp, phip) and (xq, yq, phiq). From e: theta_p = asin(e2/l0), theta_q = asin(-e3/l0)
  // (|theta| < 90 degrees, the valid branch), the chord angle from the known end's angle, the
  // length from Eq. 3a.
  int endOfCoordinate(int i) const override { return i < 3 ? 0 : 1; }
  bool place(const DefVec& e, int to, ElemVec& x) const override;
  void stressWeightedHessian(const ElemVec& x, const DefVec& sigma, ElemMat& H) const override;
  // params = [EA, EI]: S = diag(EA/l0, EI/l0^3 [[4, -2], [-2, 4]]). Missing entries count as 0.
  void constitutive(std::span<const double> params, DefMat& S) const override;

  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void velocityForces(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemVec& h) const override;
  void dynamicTerms(const ElemVec& x, const ElemVec& xd, const ElementInertia& inertia, ElemMat& M, ElemVec& h,
                    DefVec& d2) const override;
  void gravityForces(const ElemVec& x, const ElementInertia& inertia, double gx, double gy, ElemVec& f) const override;
  // Valid while both node rotations against the chord, theta_p and theta_q, keep cos theta > 0:
  // e2 = l0 sin theta_p (Eq. 3b) has its maximum at 90 degrees and returns to zero at 180, so
  // beyond 90 degrees a bent element looks less bent (a spurious, nearly stress-free fold).
  // theta is measured from the reference configuration, so rigid rotations are always valid.
  ElementValidity validity(const ElemVec& x) const override;
  double referenceLength() const override { return l0_; }
  // The chord plus n(alpha) (H2 e2 + H3 e3): the cubic the bending deformations describe (no axes:
  // planar).
  bool centreLine(const ElemVec& x, Eigen::Ref<Eigen::Matrix3Xd> points, Eigen::Matrix3Xd* ys,
                  Eigen::Matrix3Xd* zs) const override;
  // Restart: l0 = length0 (or from e1), beta0 = the chord angle at x, phi0p/phi0q such that the
  // bending deformations at x are e2, e3 (theta_p = asin(e2/l0), theta_q = asin(-e3/l0)).
  void setReference(const ElemVec& x, const DefVec& e, double length0) override;

  double l0() const { return l0_; }
  double beta0() const { return beta0_; }
  double phi0p() const { return phi0p_; }
  double phi0q() const { return phi0q_; }
  ElongationDefinition elongation() const { return elongation_; }

 private:
  struct Geometry;  // chord and node angles at x, shared by every kernel
  struct Rates;     // velocity terms at (x, xd): shared by D2e[xd, xd] and h_e
  struct Inertial;  // moments of the lateral field and inertia coefficients at x: shared by M_e and h_e
  void setLength(double l0);
  void setChordAngle(double beta0);
  void geometry(const ElemVec& x, Geometry& g) const;
  void rates(const Geometry& g, const ElemVec& xd, Rates& r) const;
  void inertial(const Geometry& g, const ElementInertia& inertia, Inertial& c) const;
  void deformationsAt(const Geometry& g, DefVec& e) const;
  void jacobianAt(const Geometry& g, DefJac& De) const;
  void secondDerivativeAt(const Geometry& g, const Rates& r, DefVec& d2) const;
  void massAt(const Geometry& g, const Inertial& c, ElemMat& M) const;
  void velocityForcesAt(const Geometry& g, const Inertial& c, const Rates& r, ElemVec& h) const;

  double l0_ = 0.0;
  double c_ = 0.0;     // Eq. 3a correction factor: 1/(30 l0) bending-corrected, 0 plain (no branch)
  double il02_ = 0.0;  // 1/l0^2 (rotary inertia of w'/l0)
  double beta0_ = 0.0;
  double cb0_ = 1.0, sb0_ = 0.0;  // cos, sin beta0
  double phi0p_ = 0.0;
  double phi0q_ = 0.0;
  ElongationDefinition elongation_ = ElongationDefinition::BendingCorrected;
};

}  // namespace flexmb::core
