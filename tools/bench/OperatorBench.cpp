// Reduced operators (issue 33): cost of one reduced right-hand side and of whole reduced runs with
// Eq. 19 (the full kinematics at every evaluation) against the precomputed operators
// (analysis/OperatorTraining.hpp, OperatorDynamics.hpp), their added error, their training cost, and the reduced
// right-hand side against the mesh. Printed and written as Markdown; never pass/fail.
#include <Eigen/Core>
#include <algorithm>
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
#include "tools/bench/BenchRuns.hpp"
#include "tools/bench/BenchSections.hpp"
#include "tools/bench/BenchSupport.hpp"

namespace flexmb::bench {

namespace {

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
// simulate's options for these runs (its recipe, BenchRuns.hpp): ode45, AbsTol 1e-3 RelTol, the
// operators given, no reduction estimate.
analysis::SimulationOptions runOptions(const core::Model& model, const std::optional<Eigen::MatrixXd>& V,
                                       std::shared_ptr<const analysis::ReducedOperators> ops, double relTol,
                                       bool keepStates) {
  analysis::SimulationOptions o = recipeOptions(model, analysis::Integrator::Ode45, relTol, 1e-3 * relTol, V);
  o.operators = std::move(ops);
  o.keepStates = keepStates;
  return o;
}

Timed timeRun(const core::Model& model, const std::optional<Eigen::MatrixXd>& V,
              std::shared_ptr<const analysis::ReducedOperators> ops, double relTol, int repeat) {
  Timed t;
  std::vector<double> walls;
  for (int k = 0; k < repeat; ++k) {
    const analysis::SimulationOptions o = runOptions(model, V, ops, relTol, false);
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
  return analysis::simulate(model, runOptions(model, V, std::move(ops), relTol, true));
}

analysis::ReductionOptions modal(int r) {
  analysis::ReductionOptions o;
  o.method = "modal";
  o.modes = r;
  return o;
}

struct Case {
  std::string model, label;
  const core::Model* m;
  analysis::ReductionOptions basis;
};

// The settings of the section (--quick: cheaper).
struct OperatorSettings {
  double budget, relTol, refTol;
  int repeat;
};

std::string caseTableHead(const OperatorSettings& s) {
  std::ostringstream md;
  md << "### Reduced operators (issue 33)\n\n"
     << "Reduced runs with Eq. 19 (the full kinematics at every evaluation) against the same basis with the "
        "precomputed reduced operators (analysis/ReducedOperators.md: Chebyshev polynomials in eta for the reduced "
        "mass matrix, potential and load fields, fitted at configurations of a trained range). ode45, RelTol "
     << fmt("%g", s.relTol)
     << ", AbsTol 1e-3 RelTol. *rhs*: median time of one evaluation at the state half-way "
        "through the run; the full model's at its own state there. *run*: set-up and "
        "integration, states at the output times, median of "
     << s.repeat
     << " runs. *simulate uses*: what `simulate --basis` chooses from the two evaluations timed at training. *error*: "
        "largest position deviation over all positions and output times from a full reference "
        "(ode45, RelTol "
     << fmt("%g", s.refTol)
     << "), relative to the motion (the reduction error estimate's measure). *training*: the operators' pilot run, "
        "sampling and fitting, as a share of one full run at RelTol 1e-3.\n\n"
     << "| model | basis | terms (all / Mr) | held-out fit error (force / mass) | training [s] (of a full run) | rhs "
        "full [us] | "
        "rhs Eq. 19 [us] | rhs operators [us] | operators / full | run Eq. 19 [ms] | run operators [ms] | speed-up | "
        "error Eq. 19 | error operators | simulate uses |\n"
     << "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  return md.str();
}

// The states [q; qd] of the full model at the reference's output time k, and the reduced ones
// (eta = V^+ q) there.
void statesAt(const core::Model& model, const core::Trajectory& reference, size_t k, const Eigen::MatrixXd& V,
              Eigen::VectorXd& yF, Eigen::VectorXd& yR) {
  const core::StateOutputs& s = reference.states[std::min(k, reference.states.size() - 1)];
  for (int j = 0; j < model.numDofs(); ++j) {  // x -> q through the DOF map
    const auto& d = model.dofs[j];
    yF[j] = d.isDeformation ? s.e[d.index] : s.x[d.index];
    yF[model.numDofs() + j] = d.isDeformation ? s.ed[d.index] : s.xd[d.index];
  }
  const Eigen::MatrixXd pinv = V.completeOrthogonalDecomposition().pseudoInverse();
  yR.resize(2 * V.cols());
  yR << pinv * yF.head(model.numDofs()), pinv * yF.tail(model.numDofs());
}

// One basis: Eq. 19 against the operators (a row of the first table).
std::string caseRow(const Case& c, const core::Trajectory& reference, const Timed& fullRun, const OperatorSettings& s) {
  const core::Model& model = *c.m;
  const Eigen::MatrixXd V = analysis::buildBasis(model, c.basis).V;
  const auto t0 = Clock::now();
  auto ops = std::make_shared<const analysis::ReducedOperators>(analysis::trainOperators(model, V));
  const double training = since(t0);
  const Eigen::VectorXi deg = ops->exponents.colwise().maxCoeff().transpose();
  std::printf("[operators] %s %s: degrees in the frame of principal directions", c.model.c_str(), c.label.c_str());
  for (int i = 0; i < deg.size(); ++i) std::printf(" %d", deg[i]);
  std::printf(", range");
  for (int i = 0; i < deg.size(); ++i) std::printf(" [%.3g, %.3g]", ops->lower[i], ops->upper[i]);
  std::printf("\n");
  const core::Trajectory eq19 = keptRun(model, V, nullptr, s.relTol), fitted = keptRun(model, V, ops, s.relTol);
  const double e19 = analysis::positionErrorAgainst(model, eq19, reference);
  const double eOps = analysis::positionErrorAgainst(model, fitted, reference);
  // One evaluation at the state half-way (reduced: eta from the full reference's state there).
  const size_t mid = eq19.states.size() / 2;
  core::EquationsOfMotion eomR(model, V), eomF(model);
  analysis::OperatorDynamics od(model, *ops);
  Eigen::VectorXd yF = eomF.initialState(), yR, dy;
  statesAt(model, reference, mid, V, yF, yR);
  const double t = eq19.time[mid];
  const double rhsFull = perCall([&] { eomF.rhs(t, yF, dy); }, s.budget);
  const double rhs19 = perCall([&] { eomR.rhs(t, yR, dy); }, s.budget);
  bool inside = true;
  const double rhsOps = perCall([&] { inside = od.rhs(t, yR, dy) && inside; }, s.budget);
  const Timed run19 = timeRun(model, V, nullptr, s.relTol, s.repeat);
  const Timed runOps = timeRun(model, V, ops, s.relTol, s.repeat);
  std::printf(
      "[operators] %s %s: %d terms (%ld for Mr) (fit %.1e / %.1e), training %.3f s (%.3f of a full run); rhs full "
      "%.2f us, Eq. "
      "19 %.2f us, operators %.2f us%s (%.3f of full); run Eq. 19 %.2f ms, operators %.2f ms (%ld operator "
      "evaluations, %ld by Eq. 19): x%.1f; error Eq. 19 %.2e, operators %.2e\n",
      c.model.c_str(), c.label.c_str(), ops->terms(), static_cast<long>(ops->mass.cols()), ops->forceError,
      ops->massError, training, training / fullRun.wall, rhsFull * 1e6, rhs19 * 1e6, rhsOps * 1e6,
      inside ? "" : " (state outside the range)", rhsOps / rhsFull, run19.wall * 1e3, runOps.wall * 1e3,
      runOps.operatorEvals, runOps.fallbacks, run19.wall / runOps.wall, e19, eOps);
  std::ostringstream md;
  md << "| " << c.model << " | " << c.label << " | " << ops->terms() << " / " << ops->mass.cols() << " | "
     << fmt("%.1e", ops->forceError) << " / " << fmt("%.1e", ops->massError) << " | " << fmt("%.3f", training) << " ("
     << fmt("%.3f", training / fullRun.wall) << ") | " << fmt("%.2f", rhsFull * 1e6) << " | "
     << fmt("%.2f", rhs19 * 1e6) << " | " << fmt("%.2f", rhsOps * 1e6) << " | " << fmt("%.3f", rhsOps / rhsFull)
     << " | " << fmt("%.2f", run19.wall * 1e3) << " | " << fmt("%.2f", runOps.wall * 1e3)
     << (runOps.fallbacks ? " (" + std::to_string(runOps.fallbacks) + " by Eq. 19)" : "") << " | "
     << fmt("%.1f", run19.wall / runOps.wall) << " | " << fmt("%.2e", e19) << " | " << fmt("%.2e", eOps) << " | "
     << (analysis::operatorsCheaper(*ops) ? "operators" : "Eq. 19") << " |\n";
  return md.str();
}

// The first table: the paper's models and the spatial wire guidance, Eq. 19 against the operators.
std::string caseTable(const OperatorSettings& s) {
  const std::string src = FLEXMB_SOURCE_DIR;
  const core::Model guidance = io::readDatFile(src + "/datfiles/straight_guidance.dat");
  const core::Model manipulator = io::readDatFile(src + "/datfiles/manipulator.dat");
  const core::Model wire = io::readDatFile(src + "/datfiles/spatial/wire_guidance.dat");
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
  std::string md = caseTableHead(s), lastModel;
  core::Trajectory reference;
  Timed fullRun;
  for (const Case& c : cases) {
    if (c.model != lastModel) {
      std::printf("[operators] %s: full reference (RelTol %g) ...\n", c.model.c_str(), s.refTol);
      reference = keptRun(*c.m, std::nullopt, nullptr, s.refTol);
      fullRun = timeRun(*c.m, std::nullopt, nullptr, s.relTol, 1);
      lastModel = c.model;
    }
    md += caseRow(c, reference, fullRun, s);
  }
  return md;
}

core::Model guidanceMesh(int n) {
  return io::readDatString(guidanceDat(n), "straight_guidance_n" + std::to_string(n) + ".dat");
}

// Mesh independence: one evaluation of MODAL-3 on the guidance with n elements per flexure.
std::string meshTable(const OperatorSettings& s) {
  std::ostringstream md;
  md << "\nMesh independence: the straight guidance with n PLBEAM elements per flexure (as the rhs-scaling table), "
        "MODAL-3 of each mesh, one evaluation at t = 0.05 s, eta = 0, etad = 1e-3 (full: q = 0, qd = 1e-3).\n\n"
     << "| n | DOF | terms (all / Mr) | training [s] | rhs full [us] | rhs Eq. 19 [us] | rhs operators [us] |\n"
     << "|---:|---:|---:|---:|---:|---:|---:|\n";
  for (int n : {5, 10, 20, 40, 80}) {
    const core::Model m = guidanceMesh(n);
    const Eigen::MatrixXd V = analysis::buildBasis(m, modal(3)).V;
    const auto t0 = Clock::now();
    const analysis::ReducedOperators ops = analysis::trainOperators(m, V);
    const double training = since(t0);
    core::EquationsOfMotion eomF(m), eomR(m, V);
    analysis::OperatorDynamics od(m, ops);
    Eigen::VectorXd yF = eomF.initialState(), yR = Eigen::VectorXd::Zero(2 * V.cols()), dy;
    yF.tail(m.numDofs()).setConstant(1e-3);
    yR.tail(V.cols()).setConstant(1e-3);
    const double rhsFull = perCall([&] { eomF.rhs(0.05, yF, dy); }, s.budget);
    const double rhs19 = perCall([&] { eomR.rhs(0.05, yR, dy); }, s.budget);
    const double rhsOps = perCall([&] { od.rhs(0.05, yR, dy); }, s.budget);
    std::printf(
        "[operators] mesh n = %d (%d DOF): %d terms (%ld for Mr), fit tolerance %.2e, training %.3f s; rhs full %.2f "
        "us, Eq. 19 %.2f us, operators %.2f us\n",
        n, m.numDofs(), ops.terms(), static_cast<long>(ops.mass.cols()), ops.tolerance, training, rhsFull * 1e6,
        rhs19 * 1e6, rhsOps * 1e6);
    md << "| " << n << " | " << m.numDofs() << " | " << ops.terms() << " / " << ops.mass.cols() << " | "
       << fmt("%.3f", training) << " | " << fmt("%.2f", rhsFull * 1e6) << " | " << fmt("%.2f", rhs19 * 1e6) << " | "
       << fmt("%.2f", rhsOps * 1e6) << " |\n";
  }
  return md.str();
}

// One mesh of the output-times table: an output time from the full kinematics against one from the
// operators' output fields, whole runs with each, and the tracked tip's difference.
std::string outputsRow(int n, const OperatorSettings& s) {
  const core::Model m = guidanceMesh(n);
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
  const double full = perCall([&] { probe.outputs(0.05, y, out); }, s.budget);
  const double fitted = perCall(
      [&] {
        tracked.value.clear(), tracked.rate.clear(), tracked.acceleration.clear(), tracked.stress.clear();
        od.rhs(0.05, y, dy);
        map.evaluate(0.05, y, dy.tail(V.cols()), tracked);
      },
      s.budget);
  std::vector<double> wAll, wTracked;
  core::Trajectory all, tr;
  for (int k = 0; k < s.repeat; ++k) {
    analysis::SimulationOptions o = runOptions(m, V, ops, s.relTol, true);
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
  std::ostringstream md;
  md << "| " << n << " | " << fmt("%.2f", full * 1e6) << " | " << fmt("%.2f", fitted * 1e6) << " | "
     << fmt("%.2f", median(wAll) * 1e3) << " | " << fmt("%.2f", median(wTracked) * 1e3) << " | " << fmt("%.2e", diff)
     << " |\n";
  return md.str();
}

std::string outputsTable(const OperatorSettings& s) {
  std::string md =
      "\nOutput times against the mesh (`reduce --track`, `simulate --outputs tracked`): the same meshes and "
      "MODAL-3, "
      "operators that also fit the tip node's coordinates and the root element's deformations. One output time "
      "from the full kinematics at the reduced state (simulate's default) against one from the operators' output "
      "fields (their right-hand side for the accelerations, then the fields); a whole run (RelTol 1e-3, 200 output "
      "intervals, no checks) with each; the tracked tip's largest difference from the full kinematics at the same "
      "states, relative to its motion.\n\n"
      "| n | output time full [us] | tracked [us] | run all outputs [ms] | run tracked [ms] | tip difference |\n"
      "|---:|---:|---:|---:|---:|---:|\n";
  for (int n : {5, 20, 80}) md += outputsRow(n, s);
  return md;
}

}  // namespace

std::string operatorFigures(bool quick) {
  const OperatorSettings s{quick ? 0.05 : 0.2, 1e-3, quick ? 1e-7 : 1e-9, quick ? 3 : 5};
  std::string md = caseTable(s);  // in this order (the operands of + would run in any)
  md += meshTable(s);
  md += outputsTable(s);
  return md + "\n";
}

}  // namespace flexmb::bench
