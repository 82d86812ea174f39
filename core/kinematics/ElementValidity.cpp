#include "core/kinematics/ElementValidity.hpp"

#include <cstdio>
#include <numbers>

namespace flexmb::core {

std::optional<InvalidElement> firstInvalidElement(const Model& model, const Eigen::VectorXd& x) {
  ElemVec xe;
  for (size_t k = 0; k < model.elements.size(); ++k) {
    const ElementEntry& el = model.elements[k];
    el.gather(x, xe);
    const ElementValidity v = el.impl->validity(xe);
    if (v.valid) continue;
    InvalidElement out;
    out.element = static_cast<int>(k);
    out.detail = v;
    char degrees[32];
    std::snprintf(degrees, sizeof degrees, "%.1f", v.rotation * 180.0 / std::numbers::pi);
    out.message = "element " + std::to_string(el.label) + " (" + el.type->keyword + ")";
    if (v.slot >= 0 && v.slot < static_cast<int>(el.nodes.size()))
      out.message += ": node " + std::to_string(model.nodes[el.nodes[v.slot]].label);
    out.message += std::string(" rotated ") + degrees + " degrees " + (v.limit ? v.limit : "beyond its validity");
    return out;
  }
  return std::nullopt;
}

}  // namespace flexmb::core
