#pragma once
// USERSIG and USERINP as MATLAB/Octave functions, called back through the MEX API (mexCallMATLAB)
// with SPACAR's argument lists, in SPACAR's role-sorted layout (io/results.md):
//   [time, sig, f] = usersig(t, ne, le, e, ep, nx, lnp, x, xp)
//       e, ep (ne x 1), x, xp (nx x 1): deformations, their rates, coordinates, velocities;
//       returns sig (ne values, added to the elastic stresses; [] for none) and f (k x 3 rows
//       [node component value], nodal forces added to the loads; [] for none). time is not used.
//   [t, e, x] = userinp(t, is)
//       is = 0, 1, 2: values, rates, accelerations of the prescribed inputs at time t; returns e
//       (the input deformations: nep(3) values in their order in e, or all ne) and x (the input
//       coordinates: nxp(3) values, or all nx). Only the input entries are read.
// Every call goes through flexmb_usercall.m, which catches the function's error, so that an error
// never unwinds through the integrator: it becomes a core::UserFunctionError naming the function,
// the time and the reason, and the run stops with the results stored so far.
#include <memory>
#include <string>
#include <vector>

#include "core/Model.hpp"
#include "core/UserFunctions.hpp"
#include "io/SpacarResults.hpp"

namespace flexmb::octave_gateway {

class MatlabUserFunctions : public core::UserFunctions {
 public:
  // Installs the USERINP channels into the model's inputs (their TimeFunctions) when the file
  // names a USERINP function. The model must outlive this object.
  explicit MatlabUserFunctions(core::Model& model);
  bool active() const { return !stressFunction_.empty() || !inputFunction_.empty(); }
  bool hasLoads() const override { return !stressFunction_.empty(); }
  void loads(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& e,
             const Eigen::VectorXd& ed, Eigen::VectorXd& sigma, Eigen::VectorXd& f) override;
  // USERINP at (t, is): the value of input coordinate / deformation `index` (model order).
  double input(double t, int order, bool deformation, int index);

 private:
  const core::Model& model_;
  std::string stressFunction_, inputFunction_;
  io::SpacarLayout layout_;
  io::SpacarTopology topology_;
  std::vector<int> inputX_, inputE_;  // model indices of input coordinates / deformations, SPACAR order
  // Cache of the last USERINP call per order (the kinematics ask for every input at one t).
  struct Cached {
    bool valid = false;
    double t = 0.0;
    Eigen::VectorXd x, e;  // model order
  } cache_[3];
};

}  // namespace flexmb::octave_gateway
