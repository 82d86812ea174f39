#pragma once
// Mode 0: counts of coordinates and deformations by role, degrees of freedom, and a rank
// analysis of the kinematic Jacobian in the initial configuration naming what is under- or
// over-determined.
#include <string>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::core {

struct KinematicReport {
  int positionNodes = 0, orientationNodes = 0, warpingNodes = 0;
  int elements = 0;        // the file's elements (what `show` draws and lists)
  int normalisations = 0;  // the constraints flexmb adds, one per orientation node (L2MIN1)
  int nx = 0, ne = 0;
  int xFixed = 0, xInput = 0, xDynamic = 0, xCalculable = 0;
  int eFixed = 0, eInput = 0, eDynamic = 0, eReleased = 0;
  int dof = 0;
  int rank = 0;  // rank of dD_C/dx_calc
  // Coordinates no equation determines, most involved first (null space of the Jacobian).
  std::vector<std::string> underdetermined;
  // Kinematic constraints (deformations) that contradict or repeat others (left null space).
  std::vector<std::string> overdetermined;
  bool wellPosed() const { return underdetermined.empty() && overdetermined.empty(); }
};

KinematicReport checkKinematics(const Model& model);
std::string formatReport(const KinematicReport& report);

}  // namespace flexmb::core
