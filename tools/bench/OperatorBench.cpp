// Reduced operators (issue 33): cost of one reduced right-hand side and of whole reduced runs with
// Eq. 19 (the full kinematics at every evaluation) against the precomputed operators
// (analysis/OperatorTraining.hpp, OperatorDynamics.hpp), their added error, their training cost, and the reduced
// right-hand side against the mesh. Printed and written as Markdown; never pass/fail.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/OperatorDynamics.hpp"
#include "analysis/OperatorPolicy.hpp"
#include "analysis/OperatorTraining.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/Simulation.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "io/formats/DatReader.hpp"

namespace flexmb::bench {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
std::string f(const char* format, double v) {
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median seconds of one call over about `budget` seconds.
double perCall(const std::function<void()>& call, double budget) {
  const auto w0 = Clock::now();
  for (int i = 0; i < 3; ++i) call();
  const double est = since(w0) / 3;
  const int calls = static_cast<int>(std::clamp(budget / std::max(est, 1e-9), 9.0, 100000.0));
  std::vector<double> times(calls);
  for (int i = 0; i < calls; ++i) {
    const auto c0 = Clock::now();
    call();
    times[i] = since(c0);
  }
  return median(times);
}

// A whole ode45 run as `simulate` integrates it (set-up included, no output quantities): median of
// `repeat` wall times, and its evaluation count.
struct Timed {
  double wall = NAN;
  long fevals = 0, operatorEvals = 0, fallbacks = 0;
};
// simulate's options for these runs: AbsTol 1e-3 RelTol, no reduction estimate.
analysis::SimulationOptions runOptions(const std::optional<Eigen::MatrixXd>& V,
                                       std::shared_ptr<const analysis::ReducedOperators> ops, double relTol,
                                       bool keepStates) {
  analysis::SimulationOptions o;
  o.basis = V;
  o.operators = std::move(ops);
  o.relTol = relTol;
  o.absTol = 1e-3 * relTol;
  o.keepStates = keepStates;
  o.reductionEstimate = false;
  return o;
}

Timed timeRun(const core::Model& model, const std::optional<Eigen::MatrixXd>& V,
              std::shared_ptr<const analysis::ReducedOperators> ops, double relTol, int repeat) {
  Timed t;
  std::vector<double> walls;
  for (int k = 0; k < repeat; ++k) {
    const analysis::SimulationOptions o = runOptions(V, ops, relTol, false);
    const auto w0 = Clock::now();
    const core::Trajectory r = analysis::simulate(model, o);
    walls.push_back(since(w0));
    t.fevals = r.nfevals;
    t.operatorEvals = r.operators.evaluations;
    t.fallbacks = r.operators.fallbacks;
  }
  t.wall = median(walls);
  return t;
}

core::Trajectory keptRun(const core::Model& model, const std::optional<Eigen::MatrixXd>& V,
                         std::shared_ptr<const analysis::ReducedOperators> ops, double relTol) {
  return analysis::simulate(model, runOptions(V, std::move(ops), relTol, true));
}

struct Case {
  std::string model, label;
  const core::Model* m;
  analysis::ReductionOptions basis;
};

}  // namespace

std::string operatorFigures(bool quick, const std::function<std::string(int)>& guidanceDat) {
  const std::string src = FLEXMB_SOURCE_DIR;
  const double budget = quick ? 0.05 : 0.2, relTol = 1e-3, refTol = quick ? 1e-7 : 1e-9;
  const int repeat = quick ? 3 : 5;
  const core::Model guidance = io::readDatFile(src + "/datfiles/straight_guidance.dat");
  const core::Model manipulator = io::readDatFile(src + "/datfiles/manipulator.dat");
  const core::Model wire = io::readDatFile(src + "/datfiles/spatial/wire_guidance.dat");
  auto modal = [](int r) {
    analysis::ReductionOptions o;
    o.method = "modal";
    o.modes = r;
    return o;
  };
  analysis::ReductionOptions svd;
  svd.method = "svd-modal";
  svd.modes = 3;
  svd.node = 6;
  svd.component = 1;
  svd.from = -0.0833;
  svd.to = 0.0833;
  const std::vector<Case> cases = {{"straight guidance", "MODAL-3", &guidance, modal(3)},
                                   {"straight guidance", "MODAL-5", &guidance, modal(5)},
                                   {"straight guidance", "SVDm-5-a0", &guidance, svd},
                                   {"manipulator", "MODAL-2", &manipulator, modal(2)},
                                   {"wire guidance (spatial)", "MODAL-3", &wire, modal(3)}};
  std::ostringstream md;
  md << "### Reduced operators (issue 33)\n\n"
     << "Reduced runs with Eq. 19 (the full kinematics at every evaluation) against the same basis with the "
        "precomputed reduced operators (analysis/ReducedOperators.md: Chebyshev polynomials in eta for the reduced "
        "mass matrix, potential and load fields, fitted at configurations of a trained range). ode45, RelTol "
     << f("%g", relTol)
     << ", AbsTol 1e-3 RelTol. *rhs*: median time of one evaluation at the state half-way "
        "through the run; the full model's at its own state there. *run*: set-up and "
        "integration, states at the output times, median of "
     << repeat
     << " runs. *simulate uses*: what `simulate --basis` chooses from the two evaluations timed at training. *error*: "
        "largest position deviation over all positions and output times from a full reference "
        "(ode45, RelTol "
     << f("%g", refTol)
     << "), relative to the motion (the reduction error estimate's measure). *training*: the operators' pilot run, "
        "sampling and fitting, as a share of one full run at RelTol 1e-3.\n\n"
     << "| model | basis | terms (all / Mr) | held-out fit error (force / mass) | training [s] (of a full run) | rhs "
        "full [us] | "
        "rhs Eq. 19 [us] | rhs operators [us] | operators / full | run Eq. 19 [ms] | run operators [ms] | speed-up | "
        "error Eq. 19 | error operators | simulate uses |\n"
     << "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  std::string lastModel;
  core::Trajectory reference;
  Timed fullRun;
  for (const Case& c : cases) {
    const core::Model& model = *c.m;
    if (c.model != lastModel) {
      std::printf("[operators] %s: full reference (RelTol %g) ...\n", c.model.c_str(), refTol);
      reference = keptRun(model, std::nullopt, nullptr, refTol);
      fullRun = timeRun(model, std::nullopt, nullptr, relTol, 1);
      lastModel = c.model;
    }
    const Eigen::MatrixXd V = analysis::buildBasis(model, c.basis).V;
    const auto t0 = Clock::now();
    auto ops = std::make_shared<const analysis::ReducedOperators>(analysis::trainOperators(model, V));
    const double training = since(t0);
    {
      const Eigen::VectorXi deg = ops->exponents.colwise().maxCoeff().transpose();
      std::printf("[operators] %s %s: degrees in the frame of principal directions", c.model.c_str(), c.label.c_str());
      for (int i = 0; i < deg.size(); ++i) std::printf(" %d", deg[i]);
      std::printf(", range");
      for (int i = 0; i < deg.size(); ++i) std::printf(" [%.3g, %.3g]", ops->lower[i], ops->upper[i]);
      std::printf("\n");
    }
    const core::Trajectory eq19 = keptRun(model, V, nullptr, relTol), fitted = keptRun(model, V, ops, relTol);
    const double e19 = analysis::positionErrorAgainst(model, eq19, reference);
    const double eOps = analysis::positionErrorAgainst(model, fitted, reference);
    // One evaluation at the state half-way (reduced: eta from the Eq. 19 run's configuration there).
    const size_t mid = eq19.states.size() / 2;
    core::EquationsOfMotion eomR(model, V), eomF(model);
    analysis::OperatorDynamics od(model, *ops);
    Eigen::VectorXd yF = eomF.initialState(), yR(2 * V.cols()), dy;
    {  // q from the full reference's state there: x -> q through the DOF map
      const core::StateOutputs& s = reference.states[std::min(mid, reference.states.size() - 1)];
      for (int j = 0; j < model.numDofs(); ++j) {
        const auto& d = model.dofs[j];
        yF[j] = d.isDeformation ? s.e[d.index] : s.x[d.index];
        yF[model.numDofs() + j] = d.isDeformation ? s.ed[d.index] : s.xd[d.index];
      }
      const Eigen::MatrixXd pinv = V.completeOrthogonalDecomposition().pseudoInverse();
      yR << pinv * yF.head(model.numDofs()), pinv * yF.tail(model.numDofs());
    }
    const double t = eq19.time[mid];
    const double rhsFull = perCall([&] { eomF.rhs(t, yF, dy); }, budget);
    const double rhs19 = perCall([&] { eomR.rhs(t, yR, dy); }, budget);
    bool inside = true;
    const double rhsOps = perCall([&] { inside = od.rhs(t, yR, dy) && inside; }, budget);
    const Timed run19 = timeRun(model, V, nullptr, relTol, repeat), runOps = timeRun(model, V, ops, relTol, repeat);
    std::printf(
        "[operators] %s %s: %d terms (%ld for Mr) (fit %.1e / %.1e), training %.3f s (%.3f of a full run); rhs full "
        "%.2f us, Eq. "
        "19 %.2f us, operators %.2f us%s (%.3f of full); run Eq. 19 %.2f ms, operators %.2f ms (%ld operator "
        "evaluations, %ld by Eq. 19): x%.1f; error Eq. 19 %.2e, operators %.2e\n",
        c.model.c_str(), c.label.c_str(), ops->terms(), static_cast<long>(ops->mass.cols()), ops->forceError,
        ops->massError, training, training / fullRun.wall, rhsFull * 1e6, rhs19 * 1e6, rhsOps * 1e6,
        inside ? "" : " (state outside the range)", rhsOps / rhsFull, run19.wall * 1e3, runOps.wall * 1e3,
        runOps.operatorEvals, runOps.fallbacks, run19.wall / runOps.wall, e19, eOps);
    md << "| " << c.model << " | " << c.label << " | " << ops->terms() << " / " << ops->mass.cols() << " | "
       << f("%.1e", ops->forceError) << " / " << f("%.1e", ops->massError) << " | " << f("%.3f", training) << " ("
       << f("%.3f", training / fullRun.wall) << ") | " << f("%.2f", rhsFull * 1e6) << " | " << f("%.2f", rhs19 * 1e6)
       << " | " << f("%.2f", rhsOps * 1e6) << " | " << f("%.3f", rhsOps / rhsFull) << " | "
       << f("%.2f", run19.wall * 1e3) << " | " << f("%.2f", runOps.wall * 1e3)
       << (runOps.fallbacks ? " (" + std::to_string(runOps.fallbacks) + " by Eq. 19)" : "") << " | "
       << f("%.1f", run19.wall / runOps.wall) << " | " << f("%.2e", e19) << " | " << f("%.2e", eOps) << " | "
       << (analysis::operatorsCheaper(*ops) ? "operators" : "Eq. 19") << " |\n";
  }
  md << "\nMesh independence: the straight guidance with n PLBEAM elements per flexure (as the rhs-scaling table), "
        "MODAL-3 of each mesh, one evaluation at t = 0.05 s, eta = 0, etad = 1e-3 (full: q = 0, qd = 1e-3).\n\n"
     << "| n | DOF | terms (all / Mr) | training [s] | rhs full [us] | rhs Eq. 19 [us] | rhs operators [us] |\n"
     << "|---:|---:|---:|---:|---:|---:|---:|\n";
  for (int n : {5, 10, 20, 40, 80}) {
    const core::Model m = io::readDatString(guidanceDat(n), "straight_guidance_n" + std::to_string(n) + ".dat");
    const Eigen::MatrixXd V = analysis::buildBasis(m, modal(3)).V;
    const auto t0 = Clock::now();
    const analysis::ReducedOperators ops = analysis::trainOperators(m, V);
    const double training = since(t0);
    core::EquationsOfMotion eomF(m), eomR(m, V);
    analysis::OperatorDynamics od(m, ops);
    Eigen::VectorXd yF = eomF.initialState(), yR = Eigen::VectorXd::Zero(2 * V.cols()), dy;
    yF.tail(m.numDofs()).setConstant(1e-3);
    yR.tail(V.cols()).setConstant(1e-3);
    const double rhsFull = perCall([&] { eomF.rhs(0.05, yF, dy); }, budget);
    const double rhs19 = perCall([&] { eomR.rhs(0.05, yR, dy); }, budget);
    const double rhsOps = perCall([&] { od.rhs(0.05, yR, dy); }, budget);
    std::printf(
        "[operators] mesh n = %d (%d DOF): %d terms (%ld for Mr), fit tolerance %.2e, training %.3f s; rhs full %.2f "
        "us, Eq. 19 %.2f us, operators %.2f us\n",
        n, m.numDofs(), ops.terms(), static_cast<long>(ops.mass.cols()), ops.tolerance, training, rhsFull * 1e6,
        rhs19 * 1e6, rhsOps * 1e6);
    md << "| " << n << " | " << m.numDofs() << " | " << ops.terms() << " / " << ops.mass.cols() << " | "
       << f("%.3f", training) << " | " << f("%.2f", rhsFull * 1e6) << " | " << f("%.2f", rhs19 * 1e6) << " | "
       << f("%.2f", rhsOps * 1e6) << " |\n";
  }
  md << "\nOutput times against the mesh (`reduce --track`, `simulate --outputs tracked`): the same meshes and "
        "MODAL-3, "
        "operators that also fit the tip node's coordinates and the root element's deformations. One output time "
        "from the full kinematics at the reduced state (simulate's default) against one from the operators' output "
        "fields (their right-hand side for the accelerations, then the fields); a whole run (RelTol 1e-3, 200 output "
        "intervals, no checks) with each; the tracked tip's largest difference from the full kinematics at the same "
        "states, relative to its motion.\n\n"
     << "| n | output time full [us] | tracked [us] | run all outputs [ms] | run tracked [ms] | tip difference |\n"
     << "|---:|---:|---:|---:|---:|---:|\n";
  for (int n : {5, 20, 80}) {
    const core::Model m = io::readDatString(guidanceDat(n), "straight_guidance_n" + std::to_string(n) + ".dat");
    const Eigen::MatrixXd V = analysis::buildBasis(m, modal(3)).V;
    analysis::OperatorTrainingOptions to;
    to.outputs = analysis::trackedQuantities(m, {n + 1}, {1});
    const auto ops = std::make_shared<const analysis::ReducedOperators>(analysis::trainOperators(m, V, to));
    analysis::OperatorDynamics od(m, *ops);
    analysis::OperatorOutputMap map(m, *ops);
    core::EquationsOfMotion probe(m, V);
    Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * V.cols()), dy(2 * V.cols());
    y.tail(V.cols()).setConstant(1e-3);
    core::StateOutputs out;
    core::TrackedOutputs tracked;
    const double full = perCall([&] { probe.outputs(0.05, y, out); }, budget);
    const double fitted = perCall(
        [&] {
          tracked.value.clear(), tracked.rate.clear(), tracked.acceleration.clear(), tracked.stress.clear();
          od.rhs(0.05, y, dy);
          map.evaluate(0.05, y, dy.tail(V.cols()), tracked);
        },
        budget);
    std::vector<double> wAll, wTracked;
    core::Trajectory all, tr;
    for (int k = 0; k < repeat; ++k) {
      analysis::SimulationOptions o = runOptions(V, ops, relTol, true);
      auto w0 = Clock::now();
      all = analysis::simulate(m, o);
      wAll.push_back(since(w0));
      o.trackedOutputs = true;
      w0 = Clock::now();
      tr = analysis::simulate(m, o);
      wTracked.push_back(since(w0));
    }
    // The tip's x (first tracked quantity) against the full kinematics at the same output times.
    const int tip = to.outputs.front().index;
    double worst = 0.0, lo = INFINITY, hi = -INFINITY;
    for (size_t k = 0; k < all.time.size() && k < tr.time.size(); ++k) {
      worst = std::max(worst, std::abs(tr.tracked.value[k][0] - all.states[k].x[tip]));
      lo = std::min(lo, all.states[k].x[tip]);
      hi = std::max(hi, all.states[k].x[tip]);
    }
    const double diff = worst / std::max(hi - lo, 1e-300);
    std::printf(
        "[operators] outputs n = %d: one output time full %.2f us, tracked %.2f us; run all outputs %.2f ms, tracked "
        "%.2f ms; tip difference %.2e of its motion\n",
        n, full * 1e6, fitted * 1e6, median(wAll) * 1e3, median(wTracked) * 1e3, diff);
    md << "| " << n << " | " << f("%.2f", full * 1e6) << " | " << f("%.2f", fitted * 1e6) << " | "
       << f("%.2f", median(wAll) * 1e3) << " | " << f("%.2f", median(wTracked) * 1e3) << " | " << f("%.2e", diff)
       << " |\n";
  }
  md << "\n";
  return md.str();
}

}  // namespace flexmb::bench
