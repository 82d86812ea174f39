#pragma once
// Damping a designer states instead of EDAMP per element (issue 53 item 4): modal relative damping
// and Rayleigh damping, added to the damping of the degrees of freedom (the EDAMP one, D0, if the
// model has it):
//   C = M Phi diag(2 zeta_i omega_i) Phi^T M  +  alpha M  +  beta K0,
// Phi the M-orthonormal modes of (Kt, M) at the equilibrium (Kt = K0 + N0 + G0, the stiffness the
// eigenfrequencies come from), omega_i = sqrt(lambda_i) (no damping for rigid or unstable modes,
// lambda_i <= 0), zeta_i the ratio of mode i (ascending frequency; the last one given holds for the
// higher modes), K0 the structural stiffness E_q^T S E_q. Then mode i alone has
//   2 zeta_i omega_i + alpha + beta phi_i^T K0 phi_i   (phi_i^T C phi_i),
// i.e. zeta_i + alpha / (2 omega_i) + beta omega_i / 2 where G0 is small; the modal term has no
// coupling between the modes, the Rayleigh terms none either when G0 = 0.
// beta K0 is what EDAMP = beta * ESTIFF gives element by element (Sd = beta S, so D0 = beta K0): the
// transfer function applies it on every coordinate the linearisation holds, so that also the input
// motions (INX) and the support forces (OUTF) see it as they see EDAMP. The modal term and alpha M act
// on the degrees of freedom only: they have no support velocity and no support force (SPACAR Light's
// modal damping, too, replaces A's damping block only).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::analysis {

struct DampingOptions {
  std::vector<double> ratios;      // zeta per mode, ascending frequency; empty: no modal damping
  double alpha = 0.0, beta = 0.0;  // Rayleigh: alpha M + beta K0 (1/s and s)
  bool any() const { return !ratios.empty() || alpha != 0.0 || beta != 0.0; }
};

// Why the options cannot be used (a ratio or coefficient negative or not finite); empty: they can.
std::string dampingRefusal(const DampingOptions& options);
// The manifest's and the screen's wording: "modal ratio 0.01; Rayleigh alpha 0, beta 1e-4 s".
std::string dampingText(const DampingOptions& options);

// The modal term M Phi diag(2 zeta_i omega_i) Phi^T M (m x m) of (Kt, M); M symmetric positive
// definite. Throws std::runtime_error when the eigenproblem fails.
Eigen::MatrixXd modalDamping(const Eigen::MatrixXd& M, const Eigen::MatrixXd& Kt, const std::vector<double>& ratios);

// A nonlinear time run (simulate) takes Rayleigh's beta K0 the way EDAMP = beta * ESTIFF gives it:
// element damping Sd += beta S on every element with stiffness, so that sigma = S e + Sd ed holds in
// large motion too and linearises to D0 = beta K0. The other two terms have no such form: a modal
// ratio needs the modes of one configuration (they change along the motion), and alpha M is not a
// force of the elements (flexmb's equations of motion have no mass-proportional term). Why the
// options cannot be used in a time run (empty: they can).
std::string timeRunDampingRefusal(const DampingOptions& options);
// Sd += beta S on every element with stiffness (hasDamping set where beta > 0).
void addStiffnessProportionalDamping(core::Model& model, double beta);

// Everything above on the degrees of freedom: modalDamping + alpha M + beta K0.
Eigen::MatrixXd designDamping(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K0, const Eigen::MatrixXd& Kt,
                              const DampingOptions& options);

// The damping ratio each mode has, zeta_i = phi_i^T C phi_i / (2 omega_i mu_i) with
// mu_i = phi_i^T M phi_i (modes: columns; omega rad/s): exact for modal and Rayleigh damping (C
// diagonal in the modes), the modes' own share of any other C (EDAMP on some elements only couples
// the modes). NaN for omega_i <= 0.
Eigen::VectorXd modalDampingRatios(const Eigen::MatrixXd& modes, const Eigen::VectorXd& omega, const Eigen::MatrixXd& M,
                                   const Eigen::MatrixXd& C);

}  // namespace flexmb::analysis
