#pragma once
// Static equilibrium (mode 10): Newton on the independent coordinates with tangent Kbar + Gbar,
// over the load steps XF + s DELXF, INPUTX + s DELINPX (s = 1..n), cutting a load step into
// halves when Newton fails, and eigenfrequencies in each equilibrium.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/Linearization.hpp"
#include "solvers/StaticEquilibrium.hpp"

namespace flexmb::analysis {

// Equilibrium of lin's model at load factor s from the start eta (updated in place).
solvers::StaticResult equilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                  const solvers::NewtonOptions& options = {});

// Natural frequencies (rad/s, ascending) of (K + G) v = w^2 M v; negative eigenvalues give -sqrt(|l|).
struct Frequencies {
  Eigen::VectorXd lambda, omega;
  Eigen::MatrixXd modes;  // M-orthonormal columns in eta
};
Frequencies naturalFrequencies(const core::LinearizedSystem& sys, int nev);

struct StaticStep {
  double loadFactor = 0.0;
  Eigen::VectorXd eta, x, e, sigma;
  Frequencies frequencies;
  solvers::StaticResult newton;
  core::LinearizedSystem system;  // M0, K0, G0, ... in the equilibrium (SPACAR's .sbm)
};

struct StaticRun {
  std::vector<StaticStep> steps;
  bool completed = true;
  std::string stopReason;
};

StaticRun staticAnalysis(const core::Model& model, int nev, int loadSteps = 0 /* 0: from the file */);

}  // namespace flexmb::analysis
