#pragma once
// What EigenSolver's symmetric and KineticStability's non-symmetric ARPACK loops share.
#include <Eigen/Core>
#include <mutex>

namespace flexmb::solvers {

// ARPACK keeps Fortran SAVE state between calls: every reverse-communication loop of the process
// holds this lock while it runs.
std::mutex& arpackMutex();

// The deterministic start vector (all ones plus a fixed, non-periodic sine pattern): equal inputs
// give bit-identical results.
void fillStartVector(double* x, int n);

// Positive diagonal scale s of the pencil A v = lambda B v: median(A_ii/B_ii) over B_ii > 0 if
// positive, else median |A_ii/B_ii|; 0 if neither is positive (the caller falls back).
double diagonalScale(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

}  // namespace flexmb::solvers
