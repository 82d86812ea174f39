#pragma once
// Reduced operators (issue 33): the reduced model of Eq. 19 evaluated without the full model.
// With q = V eta (Eq. 17) and V constant, Eq. 19 is Lagrange's equations of
//   T = 1/2 etad^T Mr(eta) etad,   Mr = (F_q V)^T M (F_q V),
//   U(eta) = elastic energy (sigma = S e + sigma0) - constant loads (XF, gravity) . x,
// plus the time-dependent loads a_k(t) grad phi_k(eta) (XFT: phi = x_j; ESIGT: phi = -e_k;
// EREF: phi = (S e)_k) and damping -Cr(eta) etad, Cr = (E_q V)^T S_d (E_q V). Each of Mr, Cr,
// U, phi_k is fitted once as a Chebyshev polynomial in eta over a box (the trained range):
//   Mr etadd = -grad U + sum_k a_k(t) grad phi_k - Cr etad - (dMr/dt etad - 1/2 grad(etad^T Mr etad)),
// the last term being the velocity terms of the fitted Mr itself, so an undamped unforced reduced
// run conserves T + U of the fitted model to the integrator's tolerance. An evaluation costs
// O(terms x m^2), independent of the mesh. Derivation, assumptions and limits:
// analysis/ReducedOperators.md.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/dynamics/Stresses.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "core/model/ReducedOperators.hpp"
#include "core/model/TimeFunction.hpp"
#include "solvers/ChebyshevBasis.hpp"

namespace flexmb::analysis {

using core::OperatorLoad;
using core::ReducedOperators;

// A number that changes with any entry of V (order-sensitive); kept in the operator file.
double basisChecksum(const Eigen::MatrixXd& V);

// Why the model cannot have reduced operators (kinematic inputs, USERSIG, moments on spatial
// nodes), or empty.
std::string operatorsUnsupported(const core::Model& model);

// What keeps operators from serving this model and basis (the first difference found: degrees of
// freedom, basis columns or entries, time-dependent loads, and at the range's centre the
// accelerations against Eq. 19's beyond what the fit allows), or empty.
std::string operatorsMismatch(const core::Model& model, const Eigen::MatrixXd& V, const ReducedOperators& ops);

// Whether an evaluation of the operators, as timed at training, costs less than one of Eq. 19
// (what `simulate --basis` uses).
inline bool operatorsCheaper(const ReducedOperators& ops) {
  return !(ops.equation19Seconds > 0.0 && ops.operatorSeconds >= ops.equation19Seconds);
}

// Which reduced dynamics a run on the basis in `basisFile` uses: the operators beside it
// (io::operatorPathFor) where they fit the model and the basis and cost less than Eq. 19, else Eq. 19
// with the reason in `note`. Operators that are there but do not fit, or cannot be read, give a
// `refusal` (the run must not start: they are not silently replaced).
struct OperatorChoice {
  std::shared_ptr<const ReducedOperators> operators;  // null: Eq. 19
  std::string note;                                   // "Eq. 19 (why)" without operators
  std::string refusal;
};
OperatorChoice chooseOperators(const core::Model& model, const std::string& modelFile, const Eigen::MatrixXd& V,
                               const std::string& basisFile, bool fullKinematics);

// "63 terms, fit 5.4e-04 (force) / 4.5e-04 (mass) of their largest in the range, target ...; one
// evaluation ... us against ... us for Eq. 19; trained in ... s (...); range: ..." (reduce's report).
std::string describeOperators(const ReducedOperators& ops);

// "reduced operators: 763 evaluations (63 terms, ...); Eq. 19 for 12 from t = ... (where)" for the
// screen and the manifest.
std::string describeOperatorUse(const core::OperatorUse& use, const ReducedOperators& ops);

// "4 quantities at 701 output times: 701 from the operators' output fields (fit ...), 0 from the full
// kinematics" (simulate --outputs tracked).
std::string describeTrackedOutputs(const core::TrackedOutputs& tracked, const ReducedOperators& ops);

struct OperatorTrainingOptions {
  // The trained range (in eta; the frame is then the identity); empty: from a pilot reduced run
  // (Eq. 19, ode45 at pilotRelTol over the model's time span), in the frame of its states'
  // principal directions, widened by `margin` of its width on each side.
  Eigen::VectorXd lower, upper;
  // NaN: the model's own (ERROR). 1e-2 by default: measured, the model's 1e-3 gave the manipulator
  // 147 terms instead of 92 (a wider range) and did not keep the portal's 1e-8 motion in range
  // (ode45's trial states there go beyond the accepted ones: AbsTol dominates; those evaluations
  // fall back to Eq. 19).
  double pilotRelTol = 1e-2;
  double margin = 0.15;
  // Fit target (held-out, relative); the adaptive set grows until it is met or has maxTerms terms
  // of at most maxDegree per variable. NaN: 0.03 of the pilot run's reduction error estimate
  // (within 1e-7..1e-3), 1e-6 with a given range.
  double tolerance = std::numeric_limits<double>::quiet_NaN();
  int maxTerms = 300;
  int maxDegree = 14;
  // Quantities to fit as well (x_i, e_k: `reduce --track`), judged at the same tolerance relative to
  // each one's range; they do not enter the right-hand side.
  std::vector<core::OperatorOutput> outputs;
};

// The x_i / e_k of a trajectory's tracked outputs for nodes and elements given by their labels
// (all coordinates of each node, all deformations of each element). Throws std::invalid_argument
// naming a label the model does not have.
std::vector<core::OperatorOutput> trackedQuantities(const core::Model& model, const std::vector<int>& nodeLabels,
                                                    const std::vector<int>& elementLabels);

// Throws std::invalid_argument for an unsupported model (operatorsUnsupported) and
// std::runtime_error when the range's configurations cannot be solved.
ReducedOperators trainOperators(const core::Model& model, const Eigen::MatrixXd& V,
                                const OperatorTrainingOptions& options = {});

// The right-hand side of the reduced model from its operators. Nothing is allocated per call.
class OperatorDynamics {
 public:
  OperatorDynamics(const core::Model& model, const ReducedOperators& ops);
  int size() const { return m_; }
  const ReducedOperators& operators() const { return ops_; }
  // dy/dt for y = [eta; etad]; false (dydt untouched) when eta is outside the trained range.
  bool rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt);
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
