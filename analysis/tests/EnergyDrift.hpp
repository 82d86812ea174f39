#pragma once
// The energy tests' run: ode45 from y0 over [0, tEnd] with 50 output intervals, the total energy at
// each output time against its initial value.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "solvers/Ode45.hpp"

namespace flexmb::test {

// The largest relative deviation of energy(outputs) from its first value; ode45 at relTol with
// AbsTol = 1e-3 relTol, the kinematics of eom and probe (the outputs') to 1e-5 relTol, as
// analysis::simulate sets them. `result`: the integrator's.
template <class Energy>
double largestEnergyDeviation(core::EquationsOfMotion& eom, core::EquationsOfMotion& probe, const Eigen::VectorXd& y0,
                              double tEnd, double relTol, Energy&& energy, solvers::OdeResult& result) {
  eom.kinematics().setRelativeTolerance(1e-5 * relTol);
  probe.kinematics().setRelativeTolerance(1e-5 * relTol);
  solvers::Ode45Options o;
  o.relTol = relTol;
  o.absTol = Eigen::VectorXd::Constant(1, relTol * 1e-3);
  std::vector<double> tspan;
  for (int i = 0; i <= 50; ++i) tspan.push_back(tEnd * i / 50.0);
  double E0 = std::nan(""), worst = 0.0;
  auto f = [&](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) { eom.rhs(t, y, dy); };
  auto obs = [&](double t, const Eigen::VectorXd& y) {
    core::StateOutputs s;
    probe.outputs(t, y, s);
    const double E = energy(s);
    if (std::isnan(E0)) E0 = E;
    worst = std::max(worst, std::abs(E - E0) / std::abs(E0));
    return true;
  };
  result = solvers::Ode45(o).integrate(f, tspan, y0, obs);
  return worst;
}

}  // namespace flexmb::test
