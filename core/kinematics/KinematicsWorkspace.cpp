#include "core/kinematics/KinematicsWorkspace.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace flexmb::core {

KinematicsWorkspace::KinematicsWorkspace(const Model& model) : model_(model) {
  Structure& s = s_;
  const int nx = model.nx, ne = model.ne;
  s.colOfCoord.assign(nx, -1);
  for (int i = 0; i < nx; ++i)
    if (model.xRole[i] == Role::Calculable) {
      s.colOfCoord[i] = static_cast<int>(s.calcCoords.size());
      s.calcCoords.push_back(i);
    }
  s.rowOfDef.assign(ne, -1);
  for (int k = 0; k < ne; ++k)
    if (model.eRole[k] != Role::Calculable) {
      s.rowOfDef[k] = static_cast<int>(s.constrainedDefs.size());
      s.constrainedDefs.push_back(k);
    }
  for (const auto& d : model.dofs) {
    s.dofRow.push_back(d.isDeformation ? s.rowOfDef[d.index] : -1);
    s.dofCoord.push_back(d.isDeformation ? -1 : d.index);
    s.hasDynamicCoords |= !d.isDeformation;
  }
  s.knownMoved = s.hasDynamicCoords || !model.inputX.empty();

  s.periodic.assign(ne, 0);
  for (const auto& E : model.elements)
    for (int i = 0; i < E.impl->numDeformations(); ++i)
      if (E.impl->isPeriodicAngle(i)) s.periodic[E.firstDef + i] = 1, s.hasPeriodic = true;

  // Pattern of J = dD_C/dx_calc, built once; every element entry gets its value slot.
  std::vector<std::tuple<int, int, int, int>> entries;        // col, row, element, local slot
  std::vector<std::vector<int>> slot(model.elements.size());  // per element ndef*ncoord slots (row-major)
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nd = E.impl->numDeformations(), nc = E.impl->numCoords();
    slot[el].assign(nd * nc, -1);
    for (int i = 0; i < nd; ++i) {
      const int row = s.rowOfDef[E.firstDef + i];
      if (row < 0) continue;
      for (int j = 0; j < nc; ++j) {
        const int col = s.colOfCoord[E.coords[j]];
        if (col >= 0) entries.emplace_back(col, row, static_cast<int>(el), i * nc + j);
      }
    }
  }
  std::sort(entries.begin(), entries.end());
  const int n = s.numCalculable();
  s.colPtr.assign(n + 1, 0);
  for (size_t k = 0; k < entries.size(); ++k) {
    const auto [col, row, el, sl] = entries[k];
    if (k > 0 && std::get<0>(entries[k - 1]) == col && std::get<1>(entries[k - 1]) == row) {
      // Two elements cannot share a deformation row, so duplicates do not occur.
      continue;
    }
    slot[el][sl] = static_cast<int>(s.rowIdx.size());
    s.rowIdx.push_back(row);
    ++s.colPtr[col + 1];
  }
  for (int c = 0; c < n; ++c) s.colPtr[c + 1] += s.colPtr[c];
  // Flat (value slot, entry of D_e) lists per element for evaluateElements: no branches there.
  s.slotRange.assign(1, 0);
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int nd = E.impl->numDeformations(), nc = E.impl->numCoords();
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nc; ++j)
        if (slot[el][i * nc + j] >= 0) {
          s.slotFlat.push_back(slot[el][i * nc + j]);
          s.slotLocal.push_back(i + j * nd);  // DefJac is column-major with leading dimension nd
        }
    s.slotRange.push_back(static_cast<int>(s.slotFlat.size()));
  }
  // Rows of J are deformation gradients of order 1 (lengths and unit vectors): no row scaling.
  analysis_.disableScaling();
  if (s.isSquare() && n > 0) analysis_.analyze(n, s.colPtr.data(), s.rowIdx.data());

  // Length scale for the Newton tolerance: the model's extent (at least the longest element).
  double scale = 0.0;
  for (int i = 0; i < nx; ++i)
    if (isTranslational(model.nodes[model.xOwnerNode[i]].kind)) scale = std::max(scale, std::abs(model.x0[i]));
  s.lengthScale = scale > 0.0 ? scale : 1.0;

  analysePlacements();

  scratch_.values.assign(s.rowIdx.size(), 0.0);
  scratch_.target = Eigen::VectorXd::Zero(s.numConstraints());
  scratch_.rhs = Eigen::VectorXd::Zero(std::max(n, 1));
  scratch_.work = Eigen::VectorXd::Zero(nx);
  scratch_.workE = Eigen::VectorXd::Zero(ne);
  scratch_.convectiveD2 = Eigen::VectorXd::Zero(ne);
}

void KinematicsWorkspace::analysePlacements() {
  // Repeatedly place an element whose deformations are all prescribed (fixed, input, dynamic) and
  // of whose two ends one is known and the other unknown; the chain is sequential when this places
  // every calculable coordinate and uses every such element exactly once (a closed loop leaves an
  // element with both ends known: its equations are not a placement).
  Structure& s = s_;
  if (!s.isSquare() || s.numCalculable() == 0) return;
  const auto& els = model_.elements;
  const int nx = model_.nx;
  std::vector<char> known(nx), done(els.size(), 0);
  for (int i = 0; i < nx; ++i) known[i] = s.colOfCoord[i] < 0;
  int pending = 0;
  for (size_t el = 0; el < els.size(); ++el) {
    const auto& E = els[el];
    int constrained = 0;
    for (int i = 0; i < E.impl->numDeformations(); ++i) constrained += s.rowOfDef[E.firstDef + i] >= 0;
    if (constrained == 0) {
      done[el] = 1;  // no equations of its own
    } else if (constrained < E.impl->numDeformations() || E.impl->endOfCoordinate(0) < 0) {
      return;  // partly released, or no closed form: Newton
    } else {
      ++pending;
    }
  }
  std::vector<Placement> order;
  for (bool progress = true; progress && pending > 0;) {
    progress = false;
    for (size_t el = 0; el < els.size(); ++el) {
      if (done[el]) continue;
      const auto& E = els[el];
      bool endKnown[2] = {true, true}, endUnknown[2] = {true, true};
      for (size_t j = 0; j < E.coords.size(); ++j) {
        const int end = E.impl->endOfCoordinate(static_cast<int>(j));
        (known[E.coords[j]] ? endUnknown : endKnown)[end] = false;
      }
      if (endKnown[0] && endKnown[1]) return;  // redundant equations: a closed loop
      for (int to = 0; to < 2; ++to)
        if (endKnown[1 - to] && endUnknown[to]) {
          order.push_back({static_cast<int>(el), to});
          for (size_t j = 0; j < E.coords.size(); ++j)
            if (E.impl->endOfCoordinate(static_cast<int>(j)) == to) known[E.coords[j]] = 1;
          done[el] = 1;
          --pending;
          progress = true;
          break;
        }
    }
  }
  if (pending > 0) return;
  for (int i = 0; i < nx; ++i)
    if (!known[i]) return;
  s.placements = std::move(order);
}

}  // namespace flexmb::core
