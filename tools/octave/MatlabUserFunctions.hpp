#pragma once
// USERSIG and USERINP as MATLAB/Octave functions, called back through the MEX API (mexCallMATLAB)
// with SPACAR's argument lists and shapes as its only public user, FlexibleInstrumentSimulation
// (FFESFVA / FFESMVA), relies on them, in SPACAR's role-sorted layout (io/results.md):
//   [time, sig, f] = usersig(t, ne, le, e, ep, nx, lnp, x, xp)
//       e, ep (1 x ne), x, xp (1 x nx): deformations, their rates, coordinates, velocities, as ROWS;
//       returns sig (ne values, added to the elastic stresses; [] for none) and f (k x 3 rows
//       [node component value], nodal forces added to the loads; on an Euler-parameter node
//       components 1-4 are generalised forces on lambda0..lambda3; [] for none). time is not used.
//   [t, e, x] = userinp(t, is)
//       returns x: one row [node component value rate acceleration] per input coordinate (INPUTX)
//       and e: one row [element deformation value rate acceleration] per input deformation
//       (INPUTE), [] when there are none. One call per time gives all three orders; is = 0 (FIS
//       ignores it). Every input must have exactly one row; rows naming anything else are errors.
// Every call goes through flexmb_usercall.m, which catches the function's error, so that an error
// never unwinds through the integrator: it becomes a core::UserFunctionError naming the function,
// the time and the reason, and the run stops with the results stored so far.
#include "mex.h"

#include <memory>
#include <string>
#include <vector>

#include "core/model/Model.hpp"
#include "core/model/UserFunctions.hpp"
#include "io/formats/SpacarResults.hpp"

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
  // Calls into the interpreter and their wall time (the function's own time plus the argument
  // and result copies), per function.
  struct CallStats {
    long calls = 0;
    double seconds = 0.0;
  };
  const CallStats& stressCalls() const { return stressStats_; }
  const CallStats& inputCalls() const { return inputStats_; }
  // "USERSIG f: n calls, s s (ms per call); USERINP g: ..." for the functions the file names.
  std::string timing() const;

 private:
  const core::Model& model_;
  std::string stressFunction_, inputFunction_;
  io::SpacarLayout layout_;
  io::SpacarTopology topology_;
  std::vector<int> inputX_, inputE_;  // model indices of input coordinates / deformations, SPACAR order
  CallStats stressStats_, inputStats_;
  // The rows of USERINP's e or x output into dst (n x 3: value, rate, acceleration per model
  // index; NaN where no row), checked. Throws core::UserFunctionError.
  void readInputRows(const mxArray* a, bool deformation, const std::string& what, Eigen::MatrixXd& dst) const;
  // The last USERINP call (the kinematics ask for every input and order at one t).
  struct Cached {
    bool valid = false;
    double t = 0.0;
    Eigen::MatrixXd x, e;  // model order x (value, rate, acceleration)
  } cache_;
};

}  // namespace flexmb::octave_gateway
