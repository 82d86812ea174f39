#pragma once
// Generalised stresses of the elastic deformations: sigma = S (e - eref(t)) + S_d ed + sigma0
// + sigma_t(t). Only dynamic and released deformations carry them here: fixed and input ones
// do no virtual work (their rows of E_q vanish), their reaction stresses come from statics.
#include <Eigen/Core>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::core {

class Stresses {
 public:
  explicit Stresses(const Model& model);
  bool hasDamping() const { return hasDamping_; }
  // ed may be null when there is no damping (or the rates are zero).
  void evaluate(double t, const Eigen::VectorXd& e, const Eigen::VectorXd* ed, Eigen::VectorXd& sigma) const;
  // sigma of deformation eIndex alone, from its element's deformations and rates (the element's
  // order; edElement may be null), as evaluate gives it: for output quantities without the full e.
  double stressOf(double t, int eIndex, const double* eElement, const double* edElement) const;
  // The constitutive matrix restricted to active deformations, as (element, active mask).
  bool isActive(int eIndex) const { return active_[eIndex]; }

 private:
  const Model& model_;
  std::vector<char> active_;  // per deformation: dynamic or released
  std::vector<int> stressedElements_;
  bool hasDamping_ = false;
  mutable Eigen::VectorXd eref_;
};

}  // namespace flexmb::core
