#include "analysis/Reduction.hpp"

#include <stdexcept>

#include "analysis/Modes.hpp"
#include "analysis/Sweep.hpp"
#include "core/linearization/Linearization.hpp"
#include "solvers/ReductionBasis.hpp"

namespace flexmb::analysis {

std::vector<int> defaultLargeCoordinates(const core::Model& model) {
  std::vector<int> large;
  for (int j = 0; j < model.numDofs(); ++j) {
    const auto& d = model.dofs[j];
    if (d.isDeformation) {
      const core::ElementEntry& el = model.elements[model.eOwnerElement[d.index]];
      if (el.type->isLargeRotation(d.index - el.firstDef)) large.push_back(j);
    } else if (core::isRotational(model.nodes[model.xOwnerNode[d.index]].kind)) {  // not a warping coordinate
      large.push_back(j);
    }
  }
  return large;
}

namespace {
// The rows of the q_s coordinates (Eq. 20) of modes given in q.
Eigen::MatrixXd smallRows(const solvers::Partition& p, const Eigen::MatrixXd& modesQ) {
  Eigen::MatrixXd s(p.nSmall(), modesQ.cols());
  for (int i = 0; i < p.nSmall(); ++i) s.row(i) = modesQ.row(p.small[i]);
  return s;
}
}  // namespace

ReductionResult buildBasis(const core::Model& model, const ReductionOptions& o) {
  const int nq = model.numDofs();
  const solvers::Partition p = solvers::Partition::make(nq, o.large ? *o.large : defaultLargeCoordinates(model));
  ReductionResult res;
  res.large = p.large;
  res.method = o.method;
  res.parameters.push_back({"r", std::to_string(o.modes)});
  if (o.method == "modal") {
    // Initial configuration, loads at t0 (Eq. 21).
    core::Linearization lin(model);
    Eigen::VectorXd q0;
    core::LinearizedSystem sys;
    lin.initialRest(sys, q0);
    const Frequencies fr = subproblemModes(p, sys, o.modes);
    const Eigen::MatrixXd vectors = smallRows(p, fr.modes);
    if (o.normalise == "mass") {
      res.V = solvers::assembleBasis(
          p, solvers::massNormalisedModalBasis(vectors, solvers::restrictToSmall(p, sys.M), o.modes));
    } else if (o.normalise == "unit") {
      res.V = solvers::assembleBasis(p, solvers::modalBasis(vectors, o.modes));
    } else {
      throw std::invalid_argument("unknown normalisation '" + o.normalise + "' (mass or unit)");
    }
    res.parameters.push_back({"normalise", o.normalise});
    res.omegaSmall = fr.omega;
  } else if (o.method == "svd-modal") {
    SweepOptions so;
    so.node = o.node;
    so.component = o.component;
    so.from = o.from;
    so.to = o.to;
    so.steps = o.configs;
    so.nev = o.modes;  // the q_s modes of every configuration, reused below (Eq. 22)
    so.heldCoordinates = p.large;
    so.t = model.settings.t0;
    so.onPoint = o.onConfig;
    const SweepResult sw = sweep(model, so);
    if (!sw.completed) throw std::runtime_error("SVD-modal configurations: " + sw.stopReason);
    std::vector<Eigen::MatrixXd> modes;
    std::vector<Eigen::VectorXd> omegas;
    for (const auto& pt : sw.points) {
      modes.push_back(smallRows(p, pt.modesAscending));
      omegas.push_back(pt.omegaSorted);
    }
    const solvers::SvdModalResult svd = solvers::svdModalBasis(modes, omegas, o.modes, o.weight, o.threshold, o.count);
    res.V = solvers::assembleBasis(p, svd.Vs);
    res.scaledSingularValues = svd.scaledSingularValues;
    res.parameters.push_back({"configs", std::to_string(o.configs)});
    res.parameters.push_back({"a", std::to_string(o.weight)});
    res.parameters.push_back({"threshold", std::to_string(o.threshold)});
    res.parameters.push_back({"kept", std::to_string(svd.kept)});
    res.parameters.push_back({"path", "node " + std::to_string(o.node) + " comp " + std::to_string(o.component) +
                                          " from " + std::to_string(o.from) + " to " + std::to_string(o.to)});
  } else {
    throw std::invalid_argument("unknown reduction method '" + o.method + "' (modal or svd-modal)");
  }
  return res;
}

}  // namespace flexmb::analysis
