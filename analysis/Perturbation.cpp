#include "analysis/Perturbation.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "io/formats/SpacarResults.hpp"

namespace flexmb::analysis {

core::Model withKnownAsDofs(const core::Model& model, const std::vector<int>& xCoords, const std::vector<int>& eDefs) {
  core::Model m = model;
  std::vector<core::Model::Dof> dynx, dyne;
  for (const auto& d : model.dofs) (d.isDeformation ? dyne : dynx).push_back(d);
  for (int j : xCoords) {
    if (j < 0 || j >= m.nx || (m.xRole[j] != core::Role::Fixed && m.xRole[j] != core::Role::Input))
      throw std::invalid_argument("withKnownAsDofs: " + (j >= 0 && j < m.nx ? m.coordName(j) : std::to_string(j)) +
                                  " is not a fixed or input coordinate");
    m.xRole[j] = core::Role::Dynamic;
    std::erase_if(m.inputX, [j](const core::Rheonomic& r) { return r.index == j; });
    dynx.push_back({false, j});
  }
  for (int j : eDefs) {
    if (j < 0 || j >= m.ne || m.eRole[j] != core::Role::Input)
      throw std::invalid_argument(
          "withKnownAsDofs: " + (j >= 0 && j < m.ne ? m.deformationName(j) : std::to_string(j)) +
          " is not an input deformation");
    m.eRole[j] = core::Role::Dynamic;
    std::erase_if(m.inputE, [j](const core::Rheonomic& r) { return r.index == j; });
    dyne.push_back({true, j});
  }
  m.dofs = dynx;
  m.dofs.insert(m.dofs.end(), dyne.begin(), dyne.end());
  return m;
}

DofPlaces dofPlaces(const core::Model& augmented) {
  DofPlaces p;
  p.x.assign(augmented.nx, -1);
  p.e.assign(augmented.ne, -1);
  for (std::size_t k = 0; k < augmented.dofs.size(); ++k) {
    const auto& d = augmented.dofs[k];
    (d.isDeformation ? p.e : p.x)[d.index] = static_cast<int>(k);
  }
  return p;
}

namespace {
// The equilibrium `step` of `augmented` in its degrees of freedom (inputs and supports among them).
core::EquilibriumPoint pointOf(const core::Model& augmented, const StaticStep& step) {
  core::EquilibriumPoint at;
  at.t = augmented.settings.t0;
  at.loadFactor = step.loadFactor, at.initialFactor = step.initialFactor;
  at.eta.resize(augmented.numDofs());
  for (int k = 0; k < at.eta.size(); ++k) {
    const auto& d = augmented.dofs[k];
    at.eta[k] = d.isDeformation ? step.e[d.index] : step.x[d.index];
  }
  at.x = &step.x;
  return at;
}
}  // namespace

Eigen::MatrixXd transferAt(const core::Model& augmented, const StaticStep& step) {
  return placedAt(augmented, step)->firstOrderTransfer();
}

std::unique_ptr<core::Linearization> placedAt(const core::Model& augmented, const StaticStep& step) {
  auto lin = std::make_unique<core::Linearization>(augmented);
  core::placeAt(*lin, pointOf(augmented, step));
  return lin;
}

PerturbedSystem linearizeAt(const core::Model& augmented, const StaticStep& step) {
  core::Linearization lin(augmented);
  PerturbedSystem out;
  core::linearizeAt(lin, pointOf(augmented, step), out.system);
  out.F = lin.transfer();
  return out;
}

KinematicDofMatrices kinematicDofMatrices(const core::Model& model, const StaticStep& step) {
  const io::SpacarLayout L = io::spacarLayout(model);
  std::vector<int> xs, es;
  for (const auto& c : L.dofColumns) {
    if (c.isDeformation && model.eRole[c.index] == core::Role::Input) es.push_back(c.index);
    if (!c.isDeformation && model.xRole[c.index] == core::Role::Input) xs.push_back(c.index);
  }
  const core::Model aug = withKnownAsDofs(model, xs, es);
  const PerturbedSystem p = linearizeAt(aug, step);
  const DofPlaces places = dofPlaces(aug);
  const Eigen::Index n = static_cast<Eigen::Index>(L.dofColumns.size());
  std::vector<int> at(n);
  for (Eigen::Index k = 0; k < n; ++k) at[k] = places.of({L.dofColumns[k].isDeformation, L.dofColumns[k].index});
  KinematicDofMatrices r;
  r.M0.resize(n, n);
  r.K0B.resize(n, n);
  const core::LinearizedSystem& s = p.system;
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i) {
      r.M0(i, j) = s.M(at[i], at[j]);
      r.K0B(i, j) = s.K(at[i], at[j]) + s.G(at[i], at[j]) + (s.N.size() ? s.N(at[i], at[j]) : 0.0);
    }
  return r;
}

}  // namespace flexmb::analysis
