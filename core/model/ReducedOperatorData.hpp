#pragma once
// The data of reduced operators (the analysis floor trains and evaluates them,
// io/formats/OperatorFile.hpp writes and reads them): polynomial fields of the reduced coordinates that
// replace Eq. 19's full kinematics within a trained range.
#include <Eigen/Core>
#include <algorithm>
#include <string>
#include <vector>

namespace flexmb::core {

// A time-dependent load's generalised force a(t) grad phi(eta).
struct OperatorLoad {
  enum class Kind { NodalForce, Stress, Reference };  // XFT (x index), ESIGT (e index), EREF (e index)
  Kind kind = Kind::NodalForce;
  int index = 0;
};
inline const char* operatorLoadKeyword(OperatorLoad::Kind kind) {
  return kind == OperatorLoad::Kind::Stress ? "ESIGT" : kind == OperatorLoad::Kind::Reference ? "EREF" : "XFT";
}

// A quantity the operators also map eta to, so that a run can report it without the full kinematics
// (simulate --outputs tracked): a nodal coordinate x_i or a deformation e_k.
struct OperatorOutput {
  enum class Kind { Coordinate, Deformation };
  Kind kind = Kind::Coordinate;
  int index = 0;
};
inline const char* operatorOutputKeyword(OperatorOutput::Kind kind) {
  return kind == OperatorOutput::Kind::Deformation ? "e" : "x";
}

struct ReducedOperators {
  // The fields are polynomials in zeta = R^T (eta - c), the principal directions of the pilot run's
  // states (a tight box for correlated coordinates); R = I, c = 0 with a given range.
  Eigen::VectorXd centre;
  Eigen::MatrixXd rotation;
  // Products of Chebyshev polynomials T_k(zeta_i) on the box lower <= zeta <= upper (the trained
  // range), one row of exponents per term (solvers::ChebyshevBasis).
  Eigen::VectorXd lower, upper;
  Eigen::MatrixXi exponents;
  // Each field uses the leading terms it needs (its coefficients' length).
  Eigen::VectorXd potential;  // U: coefficients
  Eigen::MatrixXd mass;       // Mr: m(m+1)/2 x its terms (packed upper triangle, row by row)
  Eigen::MatrixXd damping;    // Cr, the same layout; empty without damping
  std::vector<OperatorLoad> loads;
  Eigen::MatrixXd loadFields;  // its terms x loads: phi_k
  std::vector<OperatorOutput> outputs;
  Eigen::MatrixXd outputFields;  // its terms x outputs: x_i(zeta) or e_k(zeta); not in the right-hand side
  // What it was made for and how well it fits (held-out samples, relative to the largest value).
  int dofs = 0;                // rows of V
  double basisChecksum = 0.0;  // of V's entries (order-sensitive): recognises the basis
  std::string modelChecksum;   // of the model data the fields depend on (16 hex digits); empty: unknown
  double tolerance = 0.0;      // the fit target it was trained for
  double forceError = 0.0;     // max |Q_fit - Q| / max |Q| over held-out configurations
  double massError = 0.0;      // max |Mr_fit - Mr|_F / max |Mr|_F over them
  double outputError = 0.0;    // max |fit - value| over them / the output's range over all samples
  // The held-out configurations (zeta, one row each) and the largest values the errors above are
  // relative to (force, mass, damping, load gradient): a run measures the same errors at the same
  // states before it uses the fields (analysis::operatorFitAtHeldOut).
  Eigen::MatrixXd heldOut;
  double forceScale = 0.0, massScale = 0.0, dampingScale = 0.0, loadScale = 0.0;
  int trainingSamples = 0, validationSamples = 0;
  double trainingSeconds = 0.0;  // sampling, fitting and the range's pilot run
  // One evaluation, measured at training at the range's centre: operators and Eq. 19 (seconds).
  double operatorSeconds = 0.0, equation19Seconds = 0.0;
  std::string range;  // where the box came from, in words

  int size() const { return static_cast<int>(lower.size()); }
  // The terms an evaluation of the right-hand side computes: the longest of its fields.
  int terms() const {
    return static_cast<int>(std::max({potential.size(), mass.cols(), damping.cols(), loadFields.rows()}));
  }
};

}  // namespace flexmb::core
