#include "analysis/ModesJob.hpp"

namespace flexmb::analysis {

ModesJob::ModesJob(const ModelSource& source, ModesOptions options) : ModelJob(source), options_(std::move(options)) {
  if (!read() || !checkModel(model(), {true, true, false}, false)) return;
  if (!readBasis(model(), options_.basis, basis_)) return;
  if (const std::string why = dampingRefusal(options_.damping); !why.empty()) {
    refuse(why);
    return;
  }
  if (options_.participation && options_.reference.node != 0) {
    const auto it = model().nodeByLabel.find(options_.reference.node);
    if (it == model().nodeByLabel.end() || !core::isTranslational(model().nodes[it->second].kind)) {
      refuse("the reference node " + std::to_string(options_.reference.node) +
             " is no position node of the model: rotations are about a position node or a point");
      return;
    }
  }
  options_.nev = std::max(1, std::min(options_.nev, basis_ ? static_cast<int>(basis_->cols()) : model().numDofs()));
}

JobStatus ModesJob::run() {
  if (status_ != JobStatus::Ready) return status_;
  try {
    modes_ = initialModes(model(), basis_, options_.nev, options_.participation ? &options_.reference : nullptr);
    if (!modes_.frequencies.omega.allFinite() || modes_.frequencies.omega.size() == 0)
      throw std::runtime_error("the eigenvalue problem gave no finite frequencies");
    const core::LinearizedSystem& sys = modes_.system;
    if (sys.D.size() || options_.damping.any()) {
      Eigen::MatrixXd C = Eigen::MatrixXd::Zero(sys.M.rows(), sys.M.cols());
      if (sys.D.size()) C += sys.D;
      if (options_.damping.any()) C += designDamping(sys.M, sys.K, sys.K + sys.G, options_.damping);
      zeta_ = modalDampingRatios(modes_.frequencies.modes, modes_.frequencies.omega, sys.M, C);
    }
  } catch (const std::exception& e) {
    fail(e.what());
    return status_;
  }
  return status_ = JobStatus::Completed;
}

}  // namespace flexmb::analysis
