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

// Buckling load factors (SPACAR mode 8): mu with (K0 + mu G0) v = 0, K0 the structural and G0 the
// geometric stiffness of sys; the smallest positive ones, ascending (at most count). The load that
// produced G0 times mu is the critical load (linear pre-buckling). Empty when K0 is not definite.
Eigen::VectorXd bucklingFactors(const core::LinearizedSystem& sys, int count);

struct StaticStep {
  double loadFactor = 0.0;
  Eigen::VectorXd eta, x, e, sigma;
  Frequencies frequencies;
  Eigen::VectorXd buckling;  // load factors (only when asked for)
  solvers::StaticResult newton;
};

struct StaticRun {
  std::vector<StaticStep> steps;
  bool completed = true;
  std::string stopReason;
};

StaticRun staticAnalysis(const core::Model& model, int nev, int loadSteps = 0 /* 0: from the file */,
                         int buckling = 0 /* number of buckling load factors per step */);

}  // namespace flexmb::analysis
