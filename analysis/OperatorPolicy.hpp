#pragma once
// Whether a reduced run evaluates its reduced operators (OperatorDynamics.hpp) or Eq. 19, and the
// words for them (issue 33): the checks that operators fit a model and a basis, the choice a run
// makes, and the lines of reduce's report, the screen and the manifest. Derivation, assumptions and
// limits: analysis/ReducedOperators.md.
#include <Eigen/Core>
#include <memory>
#include <string>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"

namespace flexmb::analysis {

using core::ReducedOperators;

// A number that changes with any entry of V (order-sensitive); kept in the operator file.
double basisChecksum(const Eigen::MatrixXd& V);

// 16 hex digits (FNV-1a) of the model data the operators' fields depend on: coordinates and their
// roles, the degrees of freedom, each element's type, nodes, stiffness, damping and inertia, lumped
// masses, constant forces, prestress and gravity, and which coordinates and deformations carry
// time-dependent loads (not the loads' time functions: a run evaluates a(t) itself).
std::string operatorModelChecksum(const core::Model& model);

// Why the model cannot have reduced operators (kinematic inputs, USERSIG, moments on spatial
// nodes), or empty.
std::string operatorsUnsupported(const core::Model& model);

// What keeps operators from serving this model and basis (the first difference found: degrees of
// freedom, basis columns or entries, time-dependent loads, the model's checksum ("the model
// changed"), and their fit at their held-out configurations beyond what they declare, measured as
// training measured it: operatorFitAtHeldOut), or empty.
std::string operatorsMismatch(const core::Model& model, const Eigen::MatrixXd& V, const ReducedOperators& ops);

// Why freshly trained operators are not worth writing, or empty: a fit that adds more than a tenth
// of the basis' reduction error estimate (above 0.1 / 0.03 of their target, force or mass), which
// a run would then carry (issue 33's bound; analysis/ReducedOperators.md).
std::string operatorsMissTheirTarget(const ReducedOperators& ops);

// Whether an evaluation of the operators, as timed at training, costs less than one of Eq. 19
// (what `simulate --basis` uses).
inline bool operatorsCheaper(const ReducedOperators& ops) {
  return !(ops.equation19Seconds > 0.0 && ops.operatorSeconds >= ops.equation19Seconds);
}

// Which reduced dynamics a run on the basis in `basisFile` uses: the operators beside it
// (io::operatorPathFor) where they fit the model and the basis and cost less than Eq. 19, else Eq. 19
// with the reason in `note` (the run's "reduced dynamics" line and manifest setting). Operators that
// do not fit never stop a run (issue 49): it goes on with Eq. 19, the full kinematics through the
// same basis, and the note names what differs. Only a file that cannot be read gives a `refusal`.
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

}  // namespace flexmb::analysis
