#include "core/dynamics/Stresses.hpp"

namespace flexmb::core {

Stresses::Stresses(const Model& model) : model_(model) {
  active_.assign(model.ne, 0);
  for (int k = 0; k < model.ne; ++k) active_[k] = model.eRole[k] == Role::Dynamic || model.eRole[k] == Role::Calculable;
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    if (E.hasStiffness || E.hasDamping) stressedElements_.push_back(static_cast<int>(el));
    hasDamping_ |= E.hasDamping;
  }
  eref_ = Eigen::VectorXd::Zero(model.ne);
}

void Stresses::evaluate(double t, const Eigen::VectorXd& e, const Eigen::VectorXd* ed, Eigen::VectorXd& sigma) const {
  sigma.setZero(model_.ne);
  for (const auto& r : model_.references) eref_[r.index] = r.f->value(t);
  for (int el : stressedElements_) {
    const auto& E = model_.elements[el];
    const int nd = E.impl->numDeformations(), k0 = E.firstDef;
    for (int i = 0; i < nd; ++i) {
      if (!active_[k0 + i]) continue;
      double s = 0.0;
      for (int j = 0; j < nd; ++j) {
        if (E.hasStiffness) s += E.S(i, j) * (e[k0 + j] - eref_[k0 + j]);
        if (E.hasDamping && ed) s += E.Sd(i, j) * (*ed)[k0 + j];
      }
      sigma[k0 + i] = s;
    }
  }
  if (model_.sigma0.size() == model_.ne)
    for (int k = 0; k < model_.ne; ++k)
      if (active_[k]) sigma[k] += model_.sigma0[k];
  for (const auto& r : model_.timeStresses)
    if (active_[r.index]) sigma[r.index] += r.f->value(t);
}

double Stresses::stressOf(double t, int eIndex, const double* eElement, const double* edElement) const {
  if (!active_[eIndex]) return 0.0;
  const auto& E = model_.elements[model_.eOwnerElement[eIndex]];
  const int nd = E.impl->numDeformations(), i = eIndex - E.firstDef;
  auto reference = [&](int k) {
    for (const auto& r : model_.references)
      if (r.index == k) return r.f->value(t);
    return 0.0;
  };
  double s = 0.0;
  for (int j = 0; j < nd; ++j) {
    if (E.hasStiffness && E.S(i, j) != 0.0) s += E.S(i, j) * (eElement[j] - reference(E.firstDef + j));
    if (E.hasDamping && edElement) s += E.Sd(i, j) * edElement[j];
  }
  if (model_.sigma0.size() == model_.ne) s += model_.sigma0[eIndex];
  for (const auto& r : model_.timeStresses)
    if (r.index == eIndex) s += r.f->value(t);
  return s;
}

}  // namespace flexmb::core
