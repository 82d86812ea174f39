#include "core/dynamics/ResultQuantities.hpp"

namespace flexmb::core {

ResultQuantities::ResultQuantities(const Model& model)
    : ResultQuantities(std::make_unique<Workspace>(model), nullptr) {}

ResultQuantities::ResultQuantities(Workspace& workspace) : ResultQuantities(nullptr, &workspace) {}

ResultQuantities::ResultQuantities(std::unique_ptr<Workspace> own, Workspace* shared)
    : own_(std::move(own)),
      model_((shared ? *shared : *own_).model()),
      gtf_((shared ? *shared : *own_).kinematics()),
      inertia_((shared ? *shared : *own_).inertia()),
      calculable_(model_.nx, 0) {
  for (int c : gtf_.calculableCoords()) calculable_[c] = 1;
}

void ResultQuantities::setState(double t, const Eigen::VectorXd& q, double inputLoadFactor, double initialFactor,
                                const Eigen::VectorXd* near) {
  if (near && near->size() == model_.nx) gtf_.setConfiguration(*near);
  gtf_.setInputLoadFactor(inputLoadFactor, initialFactor);
  gtf_.solvePositions(t, q);
}

void ResultQuantities::forces(double t, double loadFactor, const StateOutputs& s, const Eigen::VectorXd& userForces,
                              Eigen::VectorXd& sigmaTotal, Eigen::VectorXd& fxt, double initialFactor,
                              AppliedForces* applied) {
  const Eigen::VectorXd& x = gtf_.x();
  Eigen::VectorXd f;
  appliedLoads(model_, inertia_, t, loadFactor, x, f, initialFactor);
  Eigen::VectorXd user;
  if (userForces.size() == f.size()) {
    user = userForces;
  } else if (model_.userFunctions && model_.userFunctions->hasLoads()) {
    if (s.userForces.size() == f.size()) {
      user = s.userForces;
    } else {
      Eigen::VectorXd us;  // USERSIG at this state (its stresses are in s.sig already)
      model_.userFunctions->loads(t, x, s.xd, s.e, s.ed, us, user);
    }
  }
  if (user.size()) f += user;
  if (applied) {
    applied->gravity = Eigen::VectorXd::Zero(model_.nx);
    inertia_.addGravity(x, applied->gravity, initialFactor);
    nodalLoads(model_, t, loadFactor, x, applied->loads, initialFactor);
    if (user.size()) applied->loads += user;
  }
  // Inertia forces M xdd + h of the state (zero at rest).
  Eigen::VectorXd inert = Eigen::VectorXd::Zero(model_.nx);
  if (inertia_.hasMass()) {
    inertia_.update(x);
    if (s.xdd.size() == model_.nx) inertia_.multiply(s.xdd, inert);
    if (s.xd.size() == model_.nx && !s.xd.isZero(0.0)) inertia_.addVelocityForces(x, s.xd, inert);
  }
  // Residual on the nodes; the constrained rows' stresses make it vanish on the calculable ones.
  Eigen::VectorXd r = f - inert;
  gtf_.addTransposedJacobianProduct(s.sig, r, -1.0);
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(model_.ne);
  gtf_.addConstraintStresses(r, lambda);
  // Dynamic deformations keep their elastic stress: their reaction part is the equation of motion's
  // residual (round-off on a trajectory). Fixed and input deformations carry the reaction stress.
  sigmaTotal = s.sig;
  Eigen::VectorXd full = s.sig + lambda;
  for (int j = 0; j < model_.ne; ++j)
    if (model_.eRole[j] == Role::Fixed || model_.eRole[j] == Role::Input) sigmaTotal[j] = full[j];
  // Total force: the applied one on free coordinates; on fixed and input coordinates what the
  // elements and the inertia take, i.e. applied load plus support reaction.
  Eigen::VectorXd taken = inert;
  gtf_.addTransposedJacobianProduct(full, taken, 1.0);
  fxt = f;
  for (int i = 0; i < model_.nx; ++i)
    if (model_.xRole[i] == Role::Fixed || model_.xRole[i] == Role::Input) fxt[i] = taken[i];
}

void ResultQuantities::jacobian(Eigen::MatrixXd& D) const {
  D.setZero(model_.ne, model_.nx);
  for (size_t el = 0; el < model_.elements.size(); ++el) {
    const auto& E = model_.elements[el];
    const DefJac& De = gtf_.elementJacobian(static_cast<int>(el));
    for (int i = 0; i < De.rows(); ++i)
      for (int j = 0; j < De.cols(); ++j) D(E.firstDef + i, E.coords[j]) += De(i, j);
  }
}

void ResultQuantities::transfer(const std::vector<FreeCoordinate>& cols, Eigen::MatrixXd& dx) {
  Eigen::MatrixXd D;
  jacobian(D);
  const int m = static_cast<int>(cols.size());
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(model_.ne, m);
  for (int j = 0; j < m; ++j) {
    if (cols[j].isDeformation)
      R(cols[j].index, j) = 1.0;  // the deformation moves
    else
      R.col(j) = -D.col(cols[j].index);  // the coordinate moves
  }
  gtf_.solveConstrained(R, dx);
  for (int j = 0; j < m; ++j)
    if (!cols[j].isDeformation) dx(cols[j].index, j) = 1.0;
}

}  // namespace flexmb::core
