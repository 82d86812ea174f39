#pragma once
// The configuration-independent part of the geometric transfer functions (paper Eq. 7-8) of one
// model, shared by every GeometricTransferFunctions of that model (the Model/Data split): the index
// maps between nodal coordinates, deformations, degrees of freedom and the rows and columns of the
// kinematic Jacobian J = dD_C/dx_calc, J's sparse pattern with each element entry's value slot, the
// open-chain placement order, KLU's analysis of J's pattern, and the per-call scratch vectors.
// What stays with each GeometricTransferFunctions is what one call leaves for the next: the
// configuration (x, e), the restart points, the predictor's curvature, the element Jacobians and the
// numeric factorisation of J (the chord steps and the first-order predictor reuse it, and KLU keeps
// its pivot order until it degrades), so evaluators sharing a workspace compute the same bits as
// evaluators with one each.
// Threading: a workspace serves one thread at a time, and one call at a time: the scratch holds
// nothing between calls, so evaluators sharing it may alternate call by call but must not run
// concurrently (one workspace per thread).
#include <Eigen/Core>
#include <vector>

#include "core/kinematics/SparseLU.hpp"
#include "core/model/Model.hpp"

namespace flexmb::core {

class KinematicsWorkspace {
 public:
  explicit KinematicsWorkspace(const Model& model);
  KinematicsWorkspace(const KinematicsWorkspace&) = delete;
  KinematicsWorkspace& operator=(const KinematicsWorkspace&) = delete;

  // An element placing one of its ends from the other by its closed form (Element::place).
  struct Placement {
    int element, to;
  };
  // Read-only after construction.
  struct Structure {
    std::vector<int> calcCoords, constrainedDefs;  // J's columns (x index), J's rows (e index)
    std::vector<int> colOfCoord, rowOfDef;         // the inverse maps (-1: not in J)
    std::vector<int> dofRow, dofCoord;             // per dof: J row (DYNE) or x index (DYNX), else -1
    std::vector<char> periodic;                    // per deformation: an angle known modulo 2 pi
    bool hasPeriodic = false;
    bool hasDynamicCoords = false;
    bool knownMoved = false;  // inputs or DYNX coordinates: the known coordinates move with (t, q)
    // J's pattern (compressed column) and the flat (value slot, entry of D_e) lists per element.
    std::vector<int> colPtr, rowIdx;
    std::vector<int> slotRange, slotFlat, slotLocal;
    // Open chains: the elements in placement order; empty when the kinematic equations are not
    // sequential (a closed loop, an element without a closed form).
    std::vector<Placement> placements;
    double lengthScale = 1.0;  // the model's extent (Newton tolerance)
    int numCalculable() const { return static_cast<int>(calcCoords.size()); }
    int numConstraints() const { return static_cast<int>(constrainedDefs.size()); }
    bool isSquare() const { return numCalculable() == numConstraints(); }
  };
  // Written and read within one call only (sized once: nothing is allocated per call).
  struct Scratch {
    std::vector<double> values;  // J's values, gathered for a factorisation
    Eigen::VectorXd target, rhs, work, workE, convectiveD2;
    Eigen::MatrixXd rhsMat;
  };

  const Model& model() const { return model_; }
  const Structure& structure() const { return s_; }
  Scratch& scratch() { return scratch_; }
  // KLU's analysis of J's pattern (no factorisation); each GeometricTransferFunctions factorises
  // with its own SparseLU on this analysis (SparseLU::shareAnalysis).
  const SparseLU& analysis() const { return analysis_; }

 private:
  void analysePlacements();

  const Model& model_;
  Structure s_;
  Scratch scratch_;
  SparseLU analysis_;
};

}  // namespace flexmb::core
