#include "tools/analysis/TrajectoryModes.hpp"

#include <Eigen/QR>

#include "core/Inertia.hpp"
#include "tools/analysis/Statics.hpp"

namespace flexmb::analysis {

Eigen::VectorXd dofsOf(const core::Model& model, const core::StateOutputs& s) {
  Eigen::VectorXd q(model.numDofs());
  for (int j = 0; j < model.numDofs(); ++j) {
    const auto& d = model.dofs[j];
    q[j] = d.isDeformation ? s.e[d.index] : s.x[d.index];
  }
  return q;
}

TrajectoryModes trajectoryModes(const core::Model& model, const core::Trajectory& traj, int nev,
                                const std::optional<Eigen::MatrixXd>& basis, bool keepMatrices) {
  TrajectoryModes out;
  core::Linearization lin(model, basis);
  core::Inertia inertia(model);
  std::optional<Eigen::ColPivHouseholderQR<Eigen::MatrixXd>> qr;
  if (basis) qr.emplace(*basis);
  Eigen::VectorXd f, inert;
  core::LinearizedSystem sys;
  for (size_t i = 0; i < traj.time.size(); ++i) {
    const double t = traj.time[i];
    const core::StateOutputs& s = traj.states[i];
    const Eigen::VectorXd q = dofsOf(model, s);
    const Eigen::VectorXd eta = qr ? Eigen::VectorXd(qr->solve(q)) : q;
    lin.kinematics().solvePositions(t, basis ? Eigen::VectorXd(*basis * eta) : eta);
    lin.appliedForces(t, 0.0, f);
    inertia.update(s.x);
    inertia.multiply(s.xdd, inert);
    inertia.addVelocityForces(s.x, s.xd, inert);
    f -= inert;
    lin.atRest(t, eta, f, sys, true);
    const Frequencies fr = naturalFrequencies(sys, std::min<int>(nev, lin.size()));
    out.time.push_back(t);
    out.omega.push_back(fr.omega);
    if (keepMatrices) out.matrices.push_back(sys);
  }
  return out;
}

}  // namespace flexmb::analysis
