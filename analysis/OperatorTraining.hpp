#pragma once
// Reduced operators trained (issue 33): each field the evaluation reads (OperatorDynamics.hpp: Mr,
// Cr, U, phi_k of Eq. 19 in Lagrange's form, and the tracked outputs) fitted once as a Chebyshev
// polynomial in eta over a box, the trained range, from the full kinematics at sampled
// configurations (Eq. 19 at rest); the range from a pilot reduced run (Simulation.hpp); one
// evaluation timed against Eq. 19's (what operatorsCheaper weighs).
// Derivation, assumptions and limits: analysis/ReducedOperators.md.
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"

namespace flexmb::analysis {

using core::ReducedOperators;

// The fit target as a share of the pilot run's reduction error estimate; the inertia fields' (Mr,
// Cr) share of it (the error a run adds follows the mass fit); and the most of that estimate the
// operators may add, above which reduce writes none (operatorsMissTheirTarget).
constexpr double kOperatorToleranceShare = 0.03;
constexpr double kOperatorInertiaShare = 0.4;
constexpr double kOperatorMostShare = 0.1;

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

// The operators' fit measured as training measures it (each field's error at the held-out
// configurations over its largest value in the range, the scales stored with them), at the
// held-out configurations stored with them: the full kinematics solved anew there (Eq. 19 at rest)
// against the fields. Training stores the larger of this and its own figure, so that on the model
// they were trained on a run measures at most what they declare (analysis/ReducedOperators.md).
struct OperatorFit {
  double force = 0.0;  // -grad U and the load gradients, as forceError
  double mass = 0.0;   // Mr and Cr, as massError
  int configurations = 0, unsolved = 0;
};
OperatorFit operatorFitAtHeldOut(const core::Model& model, const Eigen::MatrixXd& V, const ReducedOperators& ops);

// Throws std::invalid_argument for an unsupported model (operatorsUnsupported, OperatorPolicy.hpp) and
// std::runtime_error when the range's configurations cannot be solved.
ReducedOperators trainOperators(const core::Model& model, const Eigen::MatrixXd& V,
                                const OperatorTrainingOptions& options = {});

}  // namespace flexmb::analysis
