#include "analysis/SweepJob.hpp"

#include <algorithm>
#include <stdexcept>

#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
constexpr int kMaxConfigurations = 1000000;
}

SweepJob::SweepJob(const ModelSource& source, SweepOptions options, const BasisInput& basis)
    : ModelJob(source), options_(std::move(options)) {
  if (!read() || !checkModel(model(), {true, true, false}, false)) return;
  if (options_.steps < 1 || options_.steps > kMaxConfigurations) {
    refuse(std::to_string(options_.steps) + " configurations: the sweep takes 1 to " +
           std::to_string(kMaxConfigurations));
    return;
  }
  if (!checkPrescribed() || !readBasis(model(), basis, options_.basis)) return;
  options_.nev = std::max(
      1, std::min(options_.nev, options_.basis ? static_cast<int>(options_.basis->cols()) : model().numDofs()));
}

bool SweepJob::checkPrescribed() {
  const core::Model& m = model();
  const auto it = m.nodeByLabel.find(options_.node);
  const bool rotation = it != m.nodeByLabel.end() && m.nodes[it->second].kind == core::NodeKind::EulerParameters;
  if (it == m.nodeByLabel.end() || options_.component < 1 ||
      options_.component > (rotation ? 3 : m.nodes[it->second].dim()))
    return refuse("no node " + std::to_string(options_.node) + " with component " + std::to_string(options_.component) +
                      (rotation ? " (an orientation node: components 1, 2, 3 are its rotations about global x, y, z "
                                  "in rad)"
                                : ""),
                  file_);
  // Absolute coordinates: a range that does not hold the node's initial value is probably meant as
  // a displacement, so the initial value is said.
  if (!rotation) {
    const double x0 = m.x0[m.nodes[it->second].firstCoord + options_.component - 1];
    if (x0 < std::min(options_.from, options_.to) || x0 > std::max(options_.from, options_.to))
      say(Diagnostic::Kind::Note,
          "the range's ends are absolute coordinates, not displacements: node " + std::to_string(options_.node) +
              " component " + std::to_string(options_.component) + " starts at " + text::shortest(x0) + ", outside " +
              text::shortest(options_.from) + " .. " + text::shortest(options_.to));
  }
  return true;
}

JobStatus SweepJob::run(const RunHooks& hooks) {
  if (status_ != JobStatus::Ready) return status_;
  options_.onPoint = hooks.progress;
  options_.interrupt = hooks.interrupt;
  options_.interruptSignal = hooks.interruptSignal;
  try {
    result_ = sweep(model(), options_);
  } catch (const std::invalid_argument& e) {
    refuse(e.what());
    return status_;
  }
  return finish(result_.completed, result_.interrupted, "sweep", result_.stopReason,
                std::to_string(result_.points.size()) + " configurations before it are kept");
}

}  // namespace flexmb::analysis
