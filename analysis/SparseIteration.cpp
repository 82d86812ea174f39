#include "analysis/SparseIteration.hpp"

#include <utility>

#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "solvers/OdeTypes.hpp"

namespace flexmb::analysis {

SparseIteration::SparseIteration(core::Workspace& workspace, solvers::OdeRhs rhs, solvers::OdeStepHook accepted,
                                 std::function<const Eigen::VectorXd&()> anchor, double kinematicTolerance)
    : lin_(workspace, std::nullopt),
      rhs_(std::move(rhs)),
      accepted_(std::move(accepted)),
      anchor_(std::move(anchor)),
      m_(lin_.size()) {
  lin_.kinematics().setRelativeTolerance(kinematicTolerance);
  y_.resize(2 * m_);
  dy_.resize(2 * m_);
}

void SparseIteration::acceleration(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   Eigen::VectorXd& qdd) {
  y_ << q, qd;
  rhs_(t, y_, dy_);
  qdd = dy_.tail(m_);
}

void SparseIteration::jacobian(double t, const Eigen::VectorXd& q, const Eigen::VectorXd&, const Eigen::VectorXd&) {
  const Eigen::VectorXd& anchor = anchor_();
  if (anchor.size()) lin_.kinematics().setConfiguration(anchor);
  try {
    lin_.iterationMatrix(t, q);
  } catch (const core::KinematicsError& e) {
    throw solvers::RhsError(e.what());
  }
}

bool SparseIteration::factorize(double betaP, double gammaP) { return lin_.factorizeIteration(betaP, gammaP); }

void SparseIteration::solve(Eigen::VectorXd& r) {
  lin_.solveIteration(r, x_);
  r = x_;
}

void SparseIteration::accept(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  y_ << q, qd;
  accepted_(t, y_);
}

}  // namespace flexmb::analysis
