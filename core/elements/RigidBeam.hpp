#pragma once
// RBEAM (docs/theory/spatial-elements.md 5.2): rigid link from position node p with orientation Rp to a second
// position node q. x = [x_p (3), lambda_p (4), x_q (3)]. Three deformations, fixed by default:
//   e1 = l - l0,  e2 = e_y^p . d,  e3 = e_z^p . d   (d = x_q - x_p, e^p the element triad at p)
// which keep q at its initial place in the body frame of Rp. Mass (EM rhoA): rigid rod
// (rhoA l0/6) [[2I, I], [I, 2I]] on (x_p, x_q).
#include <Eigen/Core>

#include "core/elements/EvaluatedElement.hpp"

namespace flexmb::core {

class RigidBeam final : public EvaluatedElement<RigidBeam, 10, 3> {
 public:
  RigidBeam(const ElemVec& x0, const double* y);
  static std::unique_ptr<Element> create(const ElemVec& x0, const double* y, const ElementOptions& o);
  void constitutive(std::span<const double> params, DefMat& S) const override;
  void mass(const ElemVec& x, const ElementInertia& inertia, ElemMat& M) const override;
  void gravityForces3(const ElemVec& x, const ElementInertia& inertia, const double* g, ElemVec& f) const override;

  double referenceLength() const override { return l0_; }
  bool elementFrame(int end, Eigen::Matrix3d& A) const override {
    if (end != 0) return false;
    A = Ap_;
    return true;
  }

 private:
  friend class EvaluatedElement<RigidBeam, 10, 3>;
  // e1..e3 of the header with their derivatives up to order (EvaluatedElement).
  void evaluate(const ElemVec& x, int order, Defs& d) const;
  double l0_ = 0.0;
  Eigen::Matrix3d Ap_;
};

}  // namespace flexmb::core
