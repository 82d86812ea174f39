#pragma once
// Modal participation factors and effective masses per global direction (`flexmb modes`; issue 53
// item 3): which mode moves the model along x, which turns it about z.
//
// A direction d is a rigid motion of the whole model, supports included: a unit translation along a
// global axis, or a unit rotation about a global axis through a reference point p. Its influence
// vector r_d in the nodal coordinates x is exact: positions move by e_d (translation) or a x (X - p)
// (rotation about axis a), a planar angle by 1 (rotation about z), Euler parameters by
// 1/2 E(lambda)^T a / |lambda|^2 (so that omega = 2 E lambdad = a), warping coordinates not at all.
// Support motion of that kind drives the degrees of freedom (relative to the moving supports) with
// the load -b_d times the acceleration, b_d = F^T M_x r_d (F = dx/dq V, M_x the nodal mass matrix,
// the consistent coupling of fixed and free coordinates included). For mode phi_i (in q or eta):
//   L_i = phi_i^T b_d,  mu_i = phi_i^T Mbar phi_i,  Gamma_i = L_i / mu_i,  m_eff,i = L_i^2 / mu_i.
// b_d = Mbar q_d for the M-weighted least-squares fit q_d of r_d (F q_d closest to r_d in the
// mass norm), so over all the modes the effective masses sum to
//   m_d = b_d^T Mbar^-1 b_d = (F q_d)^T M_x (F q_d),
// the mass the degrees of freedom can move in that direction: the whole mass of a free model, and of
// a supported one all but the mass that moves with the supports alone (fixed nodes, the share of a
// consistent element mass the fixed end keeps). r_d^T M_x r_d is the whole model's (supports
// included): the rigid-body mass matrix R^T M_x R about p gives the mass, the centre of mass and the
// inertia tensor. Units are the model's (kg and kg m^2 in SI).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"

namespace flexmb::analysis {

// The point rotations are about: a node's position in the configuration (label > 0) or a point.
struct ReferencePoint {
  int node = 0;  // node label; 0: `point`
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

struct ModalParticipation {
  std::vector<std::string> directions;                  // planar: x, y, rz; spatial: x, y, z, rx, ry, rz
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // p (planar: z = 0)
  Eigen::MatrixXd factors;                              // k x nd: Gamma_i
  Eigen::MatrixXd effective;                            // k x nd: m_eff,i
  Eigen::VectorXd total;      // nd: m_d, the sum over all the modes (NaN when Mbar is singular)
  Eigen::MatrixXd rigidBody;  // nd x nd: R^T M_x R, the whole model moved rigidly
  bool empty() const { return directions.empty(); }
  // The mass (planar: nd = 3; spatial: 6) and centre of mass from rigidBody (NaN without mass).
  double mass() const;
  Eigen::Vector3d centreOfMass() const;
};

// r_d per direction (nx x nd) in configuration x about point p.
Eigen::MatrixXd rigidBodyMotions(const core::Model& model, const Eigen::VectorXd& x, const Eigen::Vector3d& p);

// The position of the reference in configuration x; throws std::invalid_argument for a label that
// is no position node of the model.
Eigen::Vector3d referencePosition(const core::Model& model, const Eigen::VectorXd& x, const ReferencePoint& ref);

// The participation of modes (columns in q or eta, as Frequencies::modes) in configuration x: transfer is
// F_q V there (nx x m), mass Mbar (m x m).
ModalParticipation modalParticipation(const core::Model& model, const Eigen::VectorXd& x,
                                      const Eigen::MatrixXd& transfer, const Eigen::MatrixXd& mass,
                                      const Eigen::MatrixXd& modes, const Eigen::Vector3d& reference);

// The table `flexmb modes` and Python's write give as <prefix>_participation.csv: mode, f_Hz, then
// gamma_<d> per direction, meff_<d> per direction, meff_<d>_pct (of m_d) and meff_<d>_cum_pct (the
// sum over the modes so far, of m_d; its last row is the sum over the modes computed). Empty cells
// where m_d is not known (Mbar singular) or zero.
// zeta (non-null, one per mode): a column `zeta` after f_Hz, each mode's damping ratio.
io::CsvTable participationTable(const Eigen::VectorXd& omega, const ModalParticipation& p,
                                const Eigen::VectorXd* zeta = nullptr);

}  // namespace flexmb::analysis
