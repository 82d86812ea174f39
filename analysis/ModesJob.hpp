#pragma once
// The modes job: the eigenfrequencies and mode shapes in the initial configuration (Eq. 21), of the
// full model or a reduced basis. The command line and Python call it.
#include "analysis/DesignDamping.hpp"
#include "analysis/ModelJob.hpp"
#include "analysis/Modes.hpp"

namespace flexmb::analysis {

struct ModesOptions {
  int nev = 6;       // lowered to the degrees of freedom (or the basis's columns)
  BasisInput basis;  // q = V eta; none: the full model
  // The participation factors and effective masses per global direction (analysis/Participation.hpp):
  // rotations about this node's position or point (default: the origin).
  bool participation = true;
  ReferencePoint reference;
  // Damping added to the model's EDAMP for the modes' damping ratios (analysis/DesignDamping.hpp).
  DampingOptions damping;
};

class ModesJob : public ModelJob {
 public:
  ModesJob(const ModelSource& source, ModesOptions options);
  const core::Model& model() const { return lastModel(); }
  const ModesOptions& options() const { return options_; }
  const std::optional<Eigen::MatrixXd>& basis() const { return basis_; }
  JobStatus run();  // Completed, or Failed (no finite frequency; the diagnostics say why)
  const InitialModes& result() const { return modes_; }
  // Each mode's damping ratio (modalDampingRatios) from EDAMP and the options' damping; empty when
  // the model has neither.
  const Eigen::VectorXd& dampingRatios() const { return zeta_; }

 private:
  ModesOptions options_;
  std::optional<Eigen::MatrixXd> basis_;
  InitialModes modes_;
  Eigen::VectorXd zeta_;
};

}  // namespace flexmb::analysis
