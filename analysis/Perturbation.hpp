#pragma once
// Linearisation of a static equilibrium over more coordinates than the model's degrees of freedom:
// the transfer functions of mode 9 need how the equations of the degrees of freedom q change with
// a prescribed input coordinate u (INX) and how the force a support takes changes (OUTF); SPACAR's
// mode 3 stores M0 and K0B over every kinematic degree of freedom, inputs included (oopspa reads
// them). Both come from one model in which those known coordinates are degrees of freedom too:
// its kinematics x(q, u) is the same map, so the rows and columns of q in its linearised system are
// the model's own (Eq. 16), the mixed blocks are the couplings -dQ_q/du, and the rows of a
// formerly fixed coordinate j give the change of the force it takes: fxt_j = f_j - Q_j (Q_j the
// generalised force of x_j; the reaction stresses of the fixed deformations do no work along it).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "analysis/Statics.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

// A copy of model in which the listed known coordinates (fixed or input, x indices) and input
// deformations (e indices) are degrees of freedom: DYNX / DYNE appended to their groups of q, in
// the order given. Listing a free coordinate or a deformation that is not an input throws
// std::invalid_argument.
core::Model withKnownAsDofs(const core::Model& model, const std::vector<int>& xCoords, const std::vector<int>& eDefs);

// The place of each of model's coordinates in the degrees of freedom of `augmented` (made from
// model by withKnownAsDofs): x index or e index -> index in augmented.dofs, -1 when not a dof.
struct DofPlaces {
  std::vector<int> x, e;
  int of(const core::Model::Dof& d) const { return d.isDeformation ? e[d.index] : x[d.index]; }
};
DofPlaces dofPlaces(const core::Model& augmented);

// Everything at rest in the equilibrium `step` of the model `augmented` was made from (its x, e,
// load factors): M, K, G, D (C = N = 0) over augmented's degrees of freedom, and F = dx/dq (nx x m).
struct PerturbedSystem {
  core::LinearizedSystem system;
  Eigen::MatrixXd F;
};
PerturbedSystem linearizeAt(const core::Model& augmented, const StaticStep& step);
// F = dx/dq alone at the equilibrium `step` (no projection): with no known coordinates the
// system is the step's own (StaticStep::system), and only F is missing.
Eigen::MatrixXd transferAt(const core::Model& augmented, const StaticStep& step);
// A linearisation of `augmented` (which must outlive it) with its positions solved at the
// equilibrium `step`: transferAt's F is its firstOrderTransfer(), and it factorises Mbar there.
std::unique_ptr<core::Linearization> placedAt(const core::Model& augmented, const StaticStep& step);

// SPACAR's mode-3 .ltv: M0 and K0B = K0 + N0 + G0 over every kinematic degree of freedom (ndof:
// [x^m input, x^m dynamic, e^m input, e^m dynamic], the columns of dx) in a static equilibrium.
struct KinematicDofMatrices {
  Eigen::MatrixXd M0, K0B;
};
KinematicDofMatrices kinematicDofMatrices(const core::Model& model, const StaticStep& step);

}  // namespace flexmb::analysis
