#include "analysis/TrajectoryModes.hpp"

#include "analysis/Statics.hpp"
#include "solvers/QuadraticEigen.hpp"

namespace flexmb::analysis {

Eigen::VectorXd dofsOf(const core::Model& model, const core::StateOutputs& s, int rate) {
  const Eigen::VectorXd& x = rate == 0 ? s.x : rate == 1 ? s.xd : s.xdd;
  const Eigen::VectorXd& e = rate == 0 ? s.e : rate == 1 ? s.ed : s.edd;
  Eigen::VectorXd q(model.numDofs());
  for (int j = 0; j < model.numDofs(); ++j) {
    const auto& d = model.dofs[j];
    q[j] = d.isDeformation ? e[d.index] : x[d.index];
  }
  return q;
}

TrajectoryModes trajectoryModes(const core::Model& model, const core::Trajectory& traj, int nev,
                                const std::optional<Eigen::MatrixXd>& basis, bool keepMatrices) {
  TrajectoryModes out;
  core::Linearization lin(model, basis);
  auto reduce = [&](const Eigen::VectorXd& q) { return lin.coordinates().fromFull(q); };
  core::LinearizedSystem sys;
  const int k = std::min<int>(nev, lin.size());
  for (size_t i = 0; i < traj.time.size(); ++i) {
    const double t = traj.time[i];
    const core::StateOutputs& s = traj.states[i];
    try {
      lin.inMotion(t, reduce(dofsOf(model, s, 0)), reduce(dofsOf(model, s, 1)), reduce(dofsOf(model, s, 2)), sys);
    } catch (const core::KinematicsError& e) {
      out.completed = false;
      out.stopReason = std::string("linearisation failed: ") + e.what();
      break;
    }
    Eigen::MatrixXd stiffness = sys.K + sys.N + sys.G;
    if (sys.Gskew.size()) stiffness += sys.Gskew;  // moments on Euler parameters
    const solvers::QuadraticModes qm = solvers::quadraticModes(sys.M, sys.C + sys.D, stiffness, k);
    if (!qm.ok) {
      out.completed = false;
      out.stopReason = "eigenvalues at t = " + std::to_string(t) + ": " + qm.message;
      break;
    }
    out.time.push_back(t);
    out.omega.push_back(qm.omega);
    out.damping.push_back(qm.damping);
    out.omegaFrozen.push_back(naturalFrequencies(sys, k).omega);
    if (keepMatrices) out.matrices.push_back(sys);
  }
  return out;
}

}  // namespace flexmb::analysis
