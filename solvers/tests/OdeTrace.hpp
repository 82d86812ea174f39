#pragma once
// What an integrator test records of a run: the result and every (t, y) the observer saw.
#include <Eigen/Core>
#include <vector>

#include "solvers/OdeTypes.hpp"

namespace flexmb::solvers::test {

struct Trace {
  OdeResult res;
  std::vector<double> t;
  std::vector<Eigen::VectorXd> y;
};

// An observer that appends to r and never stops the run.
inline OdeObserver recorder(Trace& r) {
  return [&r](double t, const Eigen::VectorXd& y) {
    r.t.push_back(t);
    r.y.push_back(y);
    return true;
  };
}

}  // namespace flexmb::solvers::test
