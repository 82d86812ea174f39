#pragma once
// Newton's method for static equilibrium Q(eta) = 0 with tangent T = -dQ/deta (Kbar + Gbar), with
// step cutting when an iterate makes the residual worse or the problem callable fails. Knows
// nothing of mechanics: the caller supplies the residual and the tangent.
#include <Eigen/Core>
#include <functional>
#include <string>

namespace flexmb::solvers {

struct NewtonOptions {
  double relativeTolerance = 1e-10;  // on ||Q|| relative to the reference force scale
  double stepTolerance = 1e-12;      // on ||d eta|| relative to max(1, ||eta||)
  int maxIterations = 50;
  int maxCuts = 10;                  // halvings of a step that does not reduce ||Q||
  // When no halving reduces ||Q||_inf, try the energy norm Q^T T^-1 Q (spatial models: axially
  // stiff closed loops). Off by default: planar load paths stay as they were.
  bool energyFallback = false;
};

enum class StaticStatus { Converged, NotConverged, SingularTangent, Failed };

struct StaticResult {
  StaticStatus status = StaticStatus::Converged;
  std::string message;
  int iterations = 0;
  double residual = 0.0;
  bool stable = true;  // tangent positive definite at the solution
};

// Residual Q(eta); when T is non-null also the tangent T = -dQ/deta. May throw (a failed kinematic
// solve): the solver treats that as a step to cut.
using StaticProblem = std::function<void(const Eigen::VectorXd& eta, Eigen::VectorXd& Q, Eigen::MatrixXd* T)>;

// forceScale: a typical generalised force magnitude (e.g. of the applied load) for the residual test.
StaticResult solveEquilibrium(const StaticProblem& problem, Eigen::VectorXd& eta, double forceScale,
                              const NewtonOptions& options = {});

}  // namespace flexmb::solvers
