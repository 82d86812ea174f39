#pragma once
// Loads and stresses computed by the user at run time (SPACAR's USERSIG), set on a model by a front
// end before an analysis (the Octave/MATLAB gateway implements it with MATLAB functions). core knows
// nothing of the interpreter: the equations of motion call `loads` at every evaluation with the
// current state and add the results to the stresses and nodal forces (Eq. 13's sigma and f).
// User-prescribed inputs (USERINP) need no hook here: they are the inputs' TimeFunctions.
#include <Eigen/Core>
#include <stdexcept>
#include <string>

namespace flexmb::core {

// A user function failed (threw, or returned something of the wrong shape): the message names the
// function and the time. Stops an integration like a failing right-hand side.
class UserFunctionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class UserFunctions {
 public:
  virtual ~UserFunctions() = default;
  virtual bool hasLoads() const = 0;
  // Additional stresses (size ne) and nodal forces (size nx), model order, at (t, x, xd, e, ed).
  // Both are set (zero where the user gives nothing). Throws UserFunctionError.
  virtual void loads(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& xd, const Eigen::VectorXd& e,
                     const Eigen::VectorXd& ed, Eigen::VectorXd& sigma, Eigen::VectorXd& f) = 0;
};

}  // namespace flexmb::core
