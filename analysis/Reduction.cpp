#include "analysis/Reduction.hpp"

#include <stdexcept>

#include "analysis/Sweep.hpp"
#include "core/Linearization.hpp"
#include "solvers/EigenSolver.hpp"
#include "solvers/ReductionBasis.hpp"

namespace flexmb::analysis {

std::vector<int> defaultLargeCoordinates(const core::Model& model) {
  std::vector<int> large;
  for (int j = 0; j < model.numDofs(); ++j) {
    const auto& d = model.dofs[j];
    if (d.isDeformation) {
      if (model.elements[model.eOwnerElement[d.index]].type->keyword == "PLHINGE" ||
          (model.elements[model.eOwnerElement[d.index]].type->keyword == "HINGE" &&
           d.index == model.elements[model.eOwnerElement[d.index]].firstDef))
        large.push_back(j);
    } else if (!core::isTranslational(model.nodes[model.xOwnerNode[d.index]].kind)) {
      large.push_back(j);
    }
  }
  return large;
}

namespace {
// The lowest r modes of the q_s subproblem (Eq. 21): q_l held at zero, i.e. the small block.
solvers::EigenResult smallModes(const solvers::Partition& p, const Eigen::MatrixXd& KG, const Eigen::MatrixXd& M,
                                int r) {
  const Eigen::MatrixXd Ks = solvers::restrictToSmall(p, KG), Ms = solvers::restrictToSmall(p, M);
  if (r > Ks.rows())
    throw std::invalid_argument("asked for " + std::to_string(r) + " modes, the q_s subproblem has " +
                                std::to_string(Ks.rows()));
  solvers::EigenOptions o;
  o.nev = r;
  return r >= Ks.rows() ? solvers::solveDense(Ks, Ms, o) : solvers::solveLowest(Ks, Ms, o);
}
}  // namespace

ReductionResult buildBasis(const core::Model& model, const std::string& modelPath, const ReductionOptions& o) {
  const int nq = model.numDofs();
  const solvers::Partition p = solvers::Partition::make(nq, o.large ? *o.large : defaultLargeCoordinates(model));
  ReductionResult res;
  res.info.model = modelPath;
  res.info.large = p.large;
  res.info.method = o.method;
  res.info.parameters.push_back({"r", std::to_string(o.modes)});
  if (o.method == "modal") {
    // Initial configuration, loads at t0 (Eq. 21).
    core::Linearization lin(model);
    const Eigen::VectorXd q0 = lin.kinematics().initialDofs();
    Eigen::VectorXd f;
    lin.kinematics().solvePositions(model.settings.t0, q0);
    lin.appliedForces(model.settings.t0, 0.0, f);
    core::LinearizedSystem sys;
    lin.atRest(model.settings.t0, q0, f, sys);
    const solvers::EigenResult er = smallModes(p, sys.K + sys.G, sys.M, o.modes);
    if (er.status != solvers::EigenStatus::Converged) throw std::runtime_error("modal basis: " + er.message);
    if (o.normalise == "mass") {
      res.V = solvers::assembleBasis(
          p, solvers::massNormalisedModalBasis(er.vectors, solvers::restrictToSmall(p, sys.M), o.modes));
    } else if (o.normalise == "unit") {
      res.V = solvers::assembleBasis(p, solvers::modalBasis(er.vectors, o.modes));
    } else {
      throw std::invalid_argument("unknown normalisation '" + o.normalise + "' (mass or unit)");
    }
    res.info.parameters.push_back({"normalise", o.normalise});
    res.omegaSmall = er.omega;
  } else if (o.method == "svd-modal") {
    SweepOptions so;
    so.node = o.node;
    so.component = o.component;
    so.from = o.from;
    so.to = o.to;
    so.steps = o.configs;
    so.nev = 1;
    so.t = model.settings.t0;
    so.keepMatrices = true;
    so.onPoint = o.onConfig;
    const SweepResult sw = sweep(model, so);
    if (!sw.completed) throw std::runtime_error("SVD-modal configurations: " + sw.stopReason);
    std::vector<Eigen::MatrixXd> modes;
    std::vector<Eigen::VectorXd> omegas;
    for (const auto& pt : sw.points) {
      const solvers::EigenResult er = smallModes(p, pt.stiffness, pt.mass, o.modes);
      if (er.status != solvers::EigenStatus::Converged)
        throw std::runtime_error("SVD-modal eigenproblem: " + er.message);
      modes.push_back(er.vectors);
      omegas.push_back(er.omega);
    }
    const solvers::SvdModalResult svd = solvers::svdModalBasis(modes, omegas, o.modes, o.weight, o.threshold, o.count);
    res.V = solvers::assembleBasis(p, svd.Vs);
    res.scaledSingularValues = svd.scaledSingularValues;
    res.info.scaledSingularValues = svd.scaledSingularValues;
    res.info.parameters.push_back({"configs", std::to_string(o.configs)});
    res.info.parameters.push_back({"a", std::to_string(o.weight)});
    res.info.parameters.push_back({"threshold", std::to_string(o.threshold)});
    res.info.parameters.push_back({"kept", std::to_string(svd.kept)});
    res.info.parameters.push_back({"path", "node " + std::to_string(o.node) + " comp " + std::to_string(o.component) +
                                               " from " + std::to_string(o.from) + " to " + std::to_string(o.to)});
  } else {
    throw std::invalid_argument("unknown reduction method '" + o.method + "' (modal or svd-modal)");
  }
  return res;
}

}  // namespace flexmb::analysis
