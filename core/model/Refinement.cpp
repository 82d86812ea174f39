#include "core/model/Refinement.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string_view>

namespace flexmb::core {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void append(Eigen::VectorXd& v, double value) {
  v.conservativeResize(v.size() + 1);
  v[v.size() - 1] = value;
}

bool splittable(const ElementTypeInfo& type) {
  for (std::string_view k : {"PLBEAM", "PLBEAMNL", "BEAM", "BEAMNL", "BEAMW"})
    if (type.keyword == k) return true;
  return false;
}

bool isTruss(const ElementTypeInfo& type) { return type.keyword == "TRUSS" || type.keyword == "PLTRUSS"; }

// Flexible: a deformation that is not fixed carries stiffness (the always-released warping ones
// aside: they carry stress in every BEAMW).
bool flexible(const Model& m, const ElementEntry& el) {
  for (int d = 0; d < el.type->numDeformations(); ++d)
    if (!el.type->isAlwaysReleased(d) && m.eRole[el.firstDef + d] != Role::Fixed && el.S.rows() > d && el.S(d, d) > 0.0)
      return true;
  return false;
}

// Why a flexible beam stays whole; empty: it is split.
std::string whyWhole(const Model& m, const ElementEntry& el, const std::set<int>& timed) {
  for (int d = 0; d < el.type->numDeformations(); ++d) {
    const int e = el.firstDef + d;
    if (m.eRole[e] == Role::Input) return "an input deformation (INPUTE)";
    if (timed.count(e)) return "a time-dependent stress (ESIGT or EREF)";
    const DeformationKind kind = el.type->deformationKind(d);
    if (m.sigma0.size() > e && m.sigma0[e] != 0.0 && kind != DeformationKind::Elongation &&
        kind != DeformationKind::Torsion)
      return "a bending prestress (ESIG)";
    for (const Eigen::VectorXd* v : {&m.e0, &m.ed0, &m.edd0})  // zero: the reference at rest, as in every part
      if (v->size() > e && !std::isnan((*v)[e]) && (*v)[e] != 0.0)
        return "initial values of its deformations (E, ED, STARTDE)";
  }
  return "";
}

// Where a released deformation stays released: a deformation at p in the first sub-element, one at q
// in the last, one of the whole element (elongation, torsion) in the last.
bool releasedAt(const ElementTypeInfo& type, int d, int k, int parts) {
  const std::string& name = type.deformationNames[d];
  const bool atP = name.size() > 2 && name.compare(name.size() - 2, 2, " p") == 0;
  return atP ? k == 0 : k == parts - 1;
}

class Splitter {
 public:
  Splitter(Model& m, int parts, const ElementOptions& options) : m_(m), parts_(parts), options_(options) {
    nodeLabel_ = m.nodeByLabel.empty() ? 0 : m.nodeByLabel.rbegin()->first;
    elementLabel_ = m.elementByLabel.empty() ? 0 : m.elementByLabel.rbegin()->first;
  }

  void split(int ei) {
    const ElementEntry orig = m_.elements[ei];
    const size_t half = orig.type->slots.size() / 2;
    const std::vector<Role> roles(m_.eRole.begin() + orig.firstDef,
                                  m_.eRole.begin() + orig.firstDef + orig.type->numDeformations());
    // station[k][h]: the node of slot h (of an end) at k / parts along the element.
    std::vector<std::vector<int>> station(parts_ + 1, std::vector<int>(half));
    for (size_t h = 0; h < half; ++h) {
      station[0][h] = orig.nodes[h];
      station[parts_][h] = orig.nodes[half + h];
    }
    for (int k = 1; k < parts_; ++k)
      for (size_t h = 0; h < half; ++h)
        station[k][h] = addNode(orig.type->slots[h], orig.nodes[h], orig.nodes[half + h],
                                static_cast<double>(k) / parts_, orig.line);
    for (int k = 0; k < parts_; ++k) {
      ElementEntry sub = orig;
      if (k > 0) {
        sub.label = ++elementLabel_;
        sub.firstDef = m_.ne;
        for (int d = 0; d < orig.type->numDeformations(); ++d) {
          ++m_.ne;
          m_.eOwnerElement.push_back(static_cast<int>(m_.elements.size()));
          m_.eRole.push_back(Role::Fixed);
          for (Eigen::VectorXd* v : {&m_.e0, &m_.ed0, &m_.edd0}) append(*v, kNaN);
          append(m_.sigma0, m_.sigma0[orig.firstDef + d]);
        }
      }
      sub.nodes.clear();
      sub.coords.clear();
      for (int end = 0; end < 2; ++end)
        for (size_t h = 0; h < half; ++h) sub.nodes.push_back(station[k + end][h]);
      for (int ni : sub.nodes)
        for (int c = 0; c < m_.nodes[ni].dim(); ++c) sub.coords.push_back(m_.nodes[ni].firstCoord + c);
      sub.impl = create(sub);
      // S and Sd depend on the length (EI / l ...): from the parameters as given, for the part's own.
      if (sub.hasStiffness) sub.impl->constitutive(sub.stiffnessParams, sub.S);
      if (sub.hasDamping) sub.impl->constitutive(sub.dampingParams, sub.Sd);
      for (int d = 0; d < orig.type->numDeformations(); ++d) {
        Role role = roles[d];
        if (orig.type->isAlwaysReleased(d)) {
          role = Role::Calculable;
        } else if (role == Role::Calculable && !releasedAt(*orig.type, d, k, parts_)) {
          role = orig.S(d, d) > 0.0 ? Role::Dynamic : Role::Fixed;
        }
        const int e = sub.firstDef + d;
        if (role == Role::Dynamic && (k > 0 || m_.eRole[e] != Role::Dynamic)) newDeformationDofs.push_back({true, e});
        m_.eRole[e] = role;
      }
      if (k == 0) {
        m_.elements[ei] = std::move(sub);
      } else {
        if (auto a = m_.appearance.find(orig.label); a != m_.appearance.end()) m_.appearance[sub.label] = a->second;
        m_.elementByLabel[sub.label] = static_cast<int>(m_.elements.size());
        m_.elements.push_back(std::move(sub));
      }
    }
  }

  // L2MIN1 of the new orientation nodes (every one has calculable Euler parameters).
  void normalise(int fromNode) {
    for (int ni = fromNode; ni < static_cast<int>(m_.nodes.size()); ++ni) {
      const Node& n = m_.nodes[ni];
      if (n.kind != NodeKind::EulerParameters) continue;
      ElementEntry el;
      el.label = ++elementLabel_;
      el.type = &normalisationType();
      el.line = n.line;
      el.nodes = {ni};
      for (int c = 0; c < 4; ++c) el.coords.push_back(n.firstCoord + c);
      el.firstDef = m_.ne++;
      m_.eOwnerElement.push_back(static_cast<int>(m_.elements.size()));
      m_.eRole.push_back(Role::Fixed);
      for (Eigen::VectorXd* v : {&m_.e0, &m_.ed0, &m_.edd0}) append(*v, kNaN);
      append(m_.sigma0, 0.0);
      el.impl = create(el);
      el.S = DefMat::Zero(1, 1);
      el.Sd = el.S;
      m_.elementByLabel[el.label] = static_cast<int>(m_.elements.size());
      m_.elements.push_back(std::move(el));
    }
  }

  std::vector<Model::Dof> newCoordinateDofs, newDeformationDofs;

 private:
  std::shared_ptr<const Element> create(const ElementEntry& el) const {
    ElemVec x0e(static_cast<int>(el.coords.size()));
    for (size_t c = 0; c < el.coords.size(); ++c) x0e[static_cast<int>(c)] = m_.xRef[el.coords[c]];
    std::unique_ptr<Element> impl = el.type->createWithVector ? el.type->createWithVector(x0e, el.vec.data(), options_)
                                                              : el.type->create(x0e, options_);
    if (!impl)
      throw std::invalid_argument(el.type->keyword + " " + std::to_string(el.label) + ": could not be created");
    return impl;
  }

  // A node at fraction t from node p to node q (same kind), in x0 and in the reference xRef.
  int addNode(NodeKind kind, int p, int q, double t, int line) {
    const int ni = static_cast<int>(m_.nodes.size());
    Node n;
    n.label = ++nodeLabel_;
    n.kind = kind;
    n.firstCoord = m_.nx;
    n.line = line;
    const int a = m_.nodes[p].firstCoord, b = m_.nodes[q].firstCoord, dim = n.dim();
    for (Eigen::VectorXd* x : {&m_.x0, &m_.xRef}) {
      Eigen::VectorXd pv = x->segment(a, dim), qv = x->segment(b, dim);
      if (kind == NodeKind::EulerParameters && pv.dot(qv) < 0.0) qv = -qv;  // the shorter way round
      Eigen::VectorXd v = (1.0 - t) * pv + t * qv;
      if (kind == NodeKind::EulerParameters) v.normalize();
      for (int c = 0; c < dim; ++c) append(*x, v[c]);
    }
    const Role role = kind == NodeKind::Warping ? Role::Dynamic : Role::Calculable;  // as the builder's
    for (int c = 0; c < dim; ++c) {
      m_.xRole.push_back(role);
      m_.xOwnerNode.push_back(ni);
      for (Eigen::VectorXd* v : {&m_.f0, &m_.delf}) append(*v, 0.0);
      append(m_.xd0, kNaN);
    }
    if (role == Role::Dynamic) newCoordinateDofs.push_back({false, n.firstCoord});
    m_.nx += dim;
    m_.nodeByLabel[n.label] = ni;
    m_.nodes.push_back(n);
    return ni;
  }

  Model& m_;
  int parts_;
  const ElementOptions& options_;
  int nodeLabel_ = 0, elementLabel_ = 0;
};

}  // namespace

std::string RefinementSummary::text() const {
  return "refined: every flexible beam split in " + std::to_string(parts) + " (" + std::to_string(elements) +
         " elements, " + std::to_string(nodes) + " nodes)";
}

RefinedModel refineModel(const Model& model, int parts, const ElementOptions& options) {
  if (parts < 1)
    throw std::invalid_argument("the refinement must be a whole number >= 1, found " + std::to_string(parts));
  if (model.restartState)
    throw std::invalid_argument(
        "a restart state (LENGTH0) cannot be refined: its X is the deformed configuration, "
        "not the reference the new nodes are placed on");
  if (model.xRef.size() == model.x0.size() && model.xRef != model.x0)
    throw std::invalid_argument(
        "a restart echo with reference coordinates (XREF) cannot be refined: its X is the "
        "deformed configuration, not the reference the new nodes are placed on");
  RefinedModel out{model, {}};
  Model& m = out.model;
  RefinementSummary& s = out.summary;
  s.parts = parts;
  s.originalNodes = static_cast<int>(model.nodes.size());
  s.originalElements = static_cast<int>(model.elements.size());
  if (parts > 1) {
    // Vectors a model built in code may leave empty: sized so that new entries line up.
    auto sized = [](Eigen::VectorXd& v, int n, double fill) {
      if (v.size() != n) v = Eigen::VectorXd::Constant(n, fill);
    };
    for (Eigen::VectorXd* v : {&m.f0, &m.delf}) sized(*v, m.nx, 0.0);
    sized(m.xd0, m.nx, kNaN);
    sized(m.sigma0, m.ne, 0.0);
    for (Eigen::VectorXd* v : {&m.e0, &m.ed0, &m.edd0}) sized(*v, m.ne, kNaN);
    std::set<int> timed;
    for (const std::vector<TimeLoad>* loads : {&m.timeStresses, &m.references})
      for (const TimeLoad& l : *loads) timed.insert(l.index);
    Splitter splitter(m, parts, options);
    for (int ei = 0; ei < s.originalElements; ++ei) {
      const ElementEntry& el = m.elements[ei];
      const std::string name = el.type->keyword + " " + std::to_string(el.label);
      if (isTruss(*el.type) && flexible(m, el))
        s.whole.push_back(name + ": a truss split in parts would be a chain of pins no deformation holds sideways");
      if (!splittable(*el.type) || !flexible(m, el)) continue;
      if (std::string why = whyWhole(m, el, timed); !why.empty()) {
        s.whole.push_back(name + ": " + why);
        continue;
      }
      splitter.split(ei);
      ++s.split;
    }
    splitter.normalise(s.originalNodes);
    std::vector<Model::Dof> dofs;
    for (bool deformations : {false, true}) {
      for (const Model::Dof& d : m.dofs)
        if (d.isDeformation == deformations) dofs.push_back(d);
      const auto& added = deformations ? splitter.newDeformationDofs : splitter.newCoordinateDofs;
      dofs.insert(dofs.end(), added.begin(), added.end());
    }
    m.dofs = std::move(dofs);
    // Refined twice: still the first model's.
    m.unrefined = model.unrefined ? model.unrefined : std::make_shared<const Model>(model);
  }
  for (const ElementEntry& el : m.elements) s.elements += el.type->internal ? 0 : 1;
  s.nodes = static_cast<int>(m.nodes.size());
  return out;
}

}  // namespace flexmb::core
