#pragma once
// Reduced operators evaluated (issue 33): the reduced model of Eq. 19 without the full model.
// With q = V eta (Eq. 17) and V constant, Eq. 19 is Lagrange's equations of
//   T = 1/2 etad^T Mr(eta) etad,   Mr = (F_q V)^T M (F_q V),
//   U(eta) = elastic energy (sigma = S e + sigma0) - constant loads (XF, gravity) . x,
// plus the time-dependent loads a_k(t) grad phi_k(eta) (XFT: phi = x_j; ESIGT: phi = -e_k;
// EREF: phi = (S e)_k) and damping -Cr(eta) etad, Cr = (E_q V)^T S_d (E_q V). Each of Mr, Cr,
// U, phi_k is a Chebyshev polynomial in eta over a box, the trained range (OperatorTraining.hpp):
//   Mr etadd = -grad U + sum_k a_k(t) grad phi_k - Cr etad - (dMr/dt etad - 1/2 grad(etad^T Mr etad)),
// the last term being the velocity terms of the fitted Mr itself, so an undamped unforced reduced
// run conserves T + U of the fitted model to the integrator's tolerance. An evaluation costs
// O(terms x m^2), independent of the mesh. When a run uses them: OperatorPolicy.hpp. Derivation,
// assumptions and limits: analysis/ReducedOperators.md.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/dynamics/Stresses.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"
#include "core/model/TimeFunction.hpp"
#include "solvers/ChebyshevBasis.hpp"

namespace flexmb::analysis {

using core::OperatorLoad;
using core::ReducedOperators;

// The right-hand side of the reduced model from its operators. Nothing is allocated per call.
class OperatorDynamics {
 public:
  OperatorDynamics(const core::Model& model, const ReducedOperators& ops);
  int size() const { return m_; }
  const ReducedOperators& operators() const { return ops_; }
  // dy/dt for y = [eta; etad]; false (dydt untouched) when eta is outside the trained range.
  bool rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt);
  // J = d(dy/dt)/dy at (t, y) by forward differences of rhs: 2m evaluations, each independent of the
  // mesh, give generalized-alpha the small dense iteration matrix of the fitted model (issue 48).
  // units: per coordinate of eta a change small against none of the motion (1/|F_q V| column
  // maxima); each step is 1e-7 of it or of |y_j|. False where y or a step lies outside the range.
  bool stateJacobian(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& units, Eigen::Ref<Eigen::MatrixXd> J);
  // The coordinate outside the range at the last refused call ("eta_2 = 0.31 outside [-0.2, 0.3]").
  std::string whereOutside() const;
  // Mr(eta) and the generalised forces at (t, y) without the velocity terms (tests, checks).
  void massMatrix(const Eigen::VectorXd& eta, Eigen::MatrixXd& M);
  double potential(const Eigen::VectorXd& eta);
  // T + U of the fitted model (time-dependent loads not included).
  double energy(const Eigen::VectorXd& y);

 private:
  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& eta, bool gradient);
  template <int M>
  bool rhsFixed(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt);
  void loadScalars(double t);  // scalar_: -U_p + sum_l a_l(t) phi_lp per term
  void unpack(const Eigen::Ref<const Eigen::VectorXd>& packed, Eigen::MatrixXd& S) const;

  const ReducedOperators& ops_;
  int m_;
  solvers::ChebyshevBasis basis_;  // the operators' terms on their box
  int nPacked_;
  std::vector<core::TimeFunctionPtr> loadFunctions_;
  std::vector<double> loadSigns_;
  solvers::ChebyshevBasis::Scratch scratch_;
  int nU_, nM_, nC_, nL_;  // terms of each field
  Eigen::VectorXd phi_, coef_, scalar_, weights_, packed_, Mpacked_, force_, etadd_;
  Eigen::MatrixXd grad_, M_, Md_, C_, MD_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd lastEta_, zeta_, zetad_, shifted_;
  Eigen::VectorXd yStep_, f0_, f1_;  // stateJacobian's
  int lastOutside_ = -1;
};

// The operators' tracked outputs along a run (simulate --outputs tracked): values, rates and
// accelerations as the fitted fields' exact time derivatives (ChebyshevBasis::pathDerivatives), and the
// deformations' stresses from them (core::Stresses::stressOf): a cost per output time independent
// of the mesh. Nothing is allocated per call.
class OperatorOutputMap {
 public:
  OperatorOutputMap(const core::Model& model, const ReducedOperators& ops);
  int size() const { return static_cast<int>(ops_.outputs.size()); }
  // False (outputs untouched) when eta lies outside the trained range.
  bool evaluate(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& etadd, core::TrackedOutputs& into);
  // The same quantities from the full model's outputs at a state (outside the trained range).
  void fromStates(const core::StateOutputs& s, core::TrackedOutputs& into) const;

 private:
  const ReducedOperators& ops_;
  core::Stresses stresses_;
  solvers::ChebyshevBasis basis_;
  solvers::ChebyshevBasis::Scratch scratch_;
  std::vector<std::vector<int>> elementColumns_;  // per output: its element's deformations' columns (empty: none)
  Eigen::VectorXd zeta_, zetad_, zetadd_, phi_, dphi_, ddphi_, e_, ed_;
};

}  // namespace flexmb::analysis
