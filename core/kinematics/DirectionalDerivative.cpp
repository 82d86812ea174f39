#include "core/kinematics/DirectionalDerivative.hpp"

namespace flexmb::core {

ElementSteps::ElementSteps(const Model& model) {
  scale_.resize(model.elements.size());
  for (size_t el = 0; el < model.elements.size(); ++el) {
    const auto& E = model.elements[el];
    const int n = static_cast<int>(E.coords.size());
    // Element length: the largest distance between its position nodes in the reference geometry.
    std::vector<int> pos;
    auto dimOf = [&](int x) { return model.nodes[model.xOwnerNode[x]].dim(); };
    for (int node : E.nodes)
      if (isTranslational(model.nodes[node].kind)) pos.push_back(model.nodes[node].firstCoord);
    double length = 0.0;
    for (size_t i = 0; i < pos.size(); ++i)
      for (size_t j = i + 1; j < pos.size(); ++j)
        length = std::max(length,
                          (model.x0.segment(pos[i], dimOf(pos[i])) - model.x0.segment(pos[j], dimOf(pos[j]))).norm());
    if (length <= 0.0) length = 1.0;
    scale_[el].resize(n);
    // Positions in lengths, rotations in radians, warping coordinates (rate of twist) per length.
    for (int j = 0; j < n; ++j) {
      const NodeKind kind = model.nodes[model.xOwnerNode[E.coords[j]]].kind;
      scale_[el][j] = isTranslational(kind) ? length : kind == NodeKind::Warping ? 1.0 / length : 1.0;
    }
  }
}

double ElementSteps::step(int el, const ElemVec& a) const {
  double m = 0.0;
  for (int j = 0; j < a.size(); ++j) m = std::max(m, std::abs(a[j]) / scale_[el][j]);
  return m > 0.0 ? 1e-3 / m : 0.0;
}

}  // namespace flexmb::core
