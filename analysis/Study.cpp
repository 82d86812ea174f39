#include "analysis/Study.hpp"

#include "analysis/ModesJob.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/StaticDesign.hpp"
#include "analysis/StaticJob.hpp"
#include "analysis/StudyAccuracy.hpp"
#include "analysis/SweepJob.hpp"
#include "analysis/TargetOperators.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "core/dynamics/Inertia.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/linearization/Linearization.hpp"
#include "core/linearization/ModelDiagnostics.hpp"

namespace flexmb::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string variantName(int number) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "v%04d", number);
  return buf;
}

std::string listed(const std::vector<std::string>& v, size_t shown = 6) {
  std::string s;
  for (size_t i = 0; i < v.size() && i < shown; ++i) s += (i ? ", " : "") + v[i];
  if (v.size() > shown) s += " and " + std::to_string(v.size() - shown) + " more";
  return s;
}

double hertz(double omega) { return omega / (2 * M_PI); }

// Nodes that carry a static load (XF, DELXF, moments), by label, ascending.
std::vector<int> loadedNodes(const core::Model& m) {
  std::set<int> labels;
  for (int i = 0; i < m.nx; ++i) {
    const bool loaded = (m.f0.size() == m.nx && m.f0[i] != 0.0) || (m.delf.size() == m.nx && m.delf[i] != 0.0);
    if (loaded) labels.insert(m.nodes[m.xOwnerNode[i]].label);
  }
  for (const auto& mo : m.moments)
    if (!mo.value.isZero(0.0) || !mo.increment.isZero(0.0)) labels.insert(m.nodes[mo.node].label);
  return {labels.begin(), labels.end()};
}

// Largest node displacement |x_n - x0_n| over the position nodes.
double maxDisplacement(const core::Model& m, const Eigen::VectorXd& x) {
  double d = 0.0;
  for (const auto& n : m.nodes)
    if (core::isTranslational(n.kind))
      d = std::max(d, (x.segment(n.firstCoord, n.dim()) - m.x0.segment(n.firstCoord, n.dim())).norm());
  return d;
}

void addFrequencies(const std::string& prefix, int count, const Eigen::VectorXd* omega,
                    std::vector<std::pair<std::string, double>>& q) {
  for (int i = 0; i < count; ++i)
    q.emplace_back(prefix + std::to_string(i + 1) + "_Hz", omega && i < omega->size() ? hertz((*omega)[i]) : kNaN);
}

std::string hex64(std::uint64_t h) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

// ---- variants ----------------------------------------------------------------------------------

std::vector<Variant> expandVariants(const io::ParameterTable* table, const std::vector<io::ParameterAxis>& grid) {
  std::set<std::string> names;
  if (table)
    for (const auto& p : table->parameters) names.insert(p);
  for (const auto& a : grid) {
    if (!names.insert(a.name).second)
      throw std::invalid_argument("the parameter '" + a.name + "' is given twice (" +
                                  (table && std::count(table->parameters.begin(), table->parameters.end(), a.name)
                                       ? "in the table and as --param"
                                       : "as --param") +
                                  ")");
    if (a.values.empty()) throw std::invalid_argument("the parameter '" + a.name + "' has no values");
  }
  if (names.empty()) throw std::invalid_argument("no parameters: give a table (--table) or grid axes (--param)");
  double count = table ? static_cast<double>(table->rows.size()) : 1.0;
  for (const auto& a : grid) count *= static_cast<double>(a.values.size());
  if (count > kMaxVariants)
    throw std::invalid_argument(std::to_string(static_cast<long long>(count)) +
                                " variants are too many (the limit is " + std::to_string(kMaxVariants) + ")");
  std::vector<Variant> out;
  const size_t rows = table ? table->rows.size() : 1;
  for (size_t r = 0; r < rows; ++r) {
    // Grid points of this row: odometer over the axes, the last axis fastest.
    std::vector<size_t> at(grid.size(), 0);
    for (;;) {
      Variant v;
      v.number = static_cast<int>(out.size()) + 1;
      if (table)
        for (size_t i = 0; i < table->parameters.size(); ++i)
          v.values.emplace_back(table->parameters[i], table->rows[r][i]);
      for (size_t i = 0; i < grid.size(); ++i) v.values.emplace_back(grid[i].name, grid[i].values[at[i]]);
      const bool named = table && !table->names[r].empty();
      v.name = named ? table->names[r] : variantName(v.number);
      if (named && !grid.empty()) {  // a named row with grid axes: one folder per grid point
        v.name += "_";
        for (size_t i = 0; i < grid.size(); ++i) {
          if (i) v.name += '_';
          v.name += std::to_string(at[i] + 1);
        }
      }
      out.push_back(std::move(v));
      size_t k = grid.size();
      while (k > 0 && ++at[k - 1] == grid[k - 1].values.size()) at[--k] = 0;
      if (k == 0) break;
    }
  }
  // A table's names and the generated ones must not collide (a row named v0002, say).
  std::set<std::string> folders;
  for (const auto& v : out)
    if (!folders.insert(v.name).second)
      throw std::invalid_argument("two variants are named '" + v.name +
                                  "' (the table's names must differ from each "
                                  "other and from the generated v0001, v0002, ...)");
  return out;
}

std::vector<int> taskShare(int count, int task, int of) {
  if (of < 1 || task < 0 || task >= of)
    throw std::invalid_argument("task " + std::to_string(task) + " of " + std::to_string(of) +
                                ": the task is a number from 0 to " + std::to_string(of - 1));
  std::vector<int> share;
  for (int k = task; k < count; k += of) share.push_back(k);
  return share;
}

// ---- analyses ----------------------------------------------------------------------------------

std::string StudyAnalyses::describe() const {
  std::ostringstream s;
  s.precision(17);
  if (check) s << "check: rank\n";
  if (modes > 0) s << "modes: nev " << modes << "\n";
  if (statics)
    s << "static: nev " << statics->nev << ", steps "
      << (statics->loadSteps > 0 ? std::to_string(statics->loadSteps) : "file") << ", buckling " << statics->buckling
      << "\n";
  if (sweep)
    s << "sweep: node " << sweep->node << " component " << sweep->component << " from " << sweep->from << " to "
      << sweep->to << " steps " << sweep->steps << " nev " << sweep->nev << "\n";
  if (simulation) {
    const auto& o = *simulation;
    s << "simulate: integrator " << integratorName(o.integrator);
    if (o.integrator == Integrator::Bdf) s << " order " << o.bdfMaxOrder;
    auto opt = [&](const char* name, const auto& v) {
      if (v) s << ", " << name << " " << *v;
    };
    opt("t-end", o.tEnd), opt("reltol", o.relTol), opt("abstol", o.absTol), opt("max-step", o.maxStep);
    opt("intervals", o.intervals);
    s << ", dynamics " << static_cast<int>(o.dynamics);
    if (reductionTarget) s << ", reduction target " << *reductionTarget;
    s << "\n";
  }
  if (accuracy) {  // the mesh and the measured D: a changed target, or a new measurement, reruns every variant
    s << "accuracy: ";
    if (std::isnan(accuracy->eps))
      s << "error estimate";
    else
      s << "target " << accuracy->eps;
    s << ", refine " << accuracy->refine << ", discretization " << accuracy->discretization << " measured by "
      << accuracy->analysis << (accuracy->reachable ? "" : ", not reachable") << "\n";
  }
  if (!stiffnessNodes.empty()) {
    s << "stiffness nodes:";
    for (int n : stiffnessNodes) s << " " << n;
    s << "\n";
  }
  for (const auto& [name, expression] : derived) s << "derived: " << name << " = " << expression << "\n";
  return s.str();
}

std::vector<std::pair<std::string, double>> nodeStiffness(const core::Model& model, const StaticStep& step,
                                                          int nodeLabel) {
  std::vector<std::pair<std::string, double>> out;
  const auto it = model.nodeByLabel.find(nodeLabel);
  if (it == model.nodeByLabel.end()) return out;
  const core::Node& node = model.nodes[it->second];
  core::Linearization lin(model);
  core::EquilibriumPoint at;
  at.t = model.settings.t0;
  at.loadFactor = step.loadFactor, at.initialFactor = step.initialFactor;
  at.eta = step.eta;
  at.x = &step.x;  // the equilibrium's assembly branch
  core::LinearizedSystem sys;
  core::linearizeAt(lin, at, sys, false);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(sys.K + sys.G);
  if (lu.rank() < sys.K.rows()) return out;
  const Eigen::MatrixXd A = lin.transfer().middleRows(node.firstCoord, node.dim());  // d x m
  Eigen::MatrixXd C = A * lu.solve(A.transpose());
  std::vector<std::string> names;
  const std::string base = "k_node" + std::to_string(nodeLabel) + "_";
  switch (node.kind) {
    case core::NodeKind::Position:
      names = {"x", "y"};
      break;
    case core::NodeKind::SpatialPosition:
      names = {"x", "y", "z"};
      break;
    case core::NodeKind::Orientation:
      names = {"angle"};
      break;
    case core::NodeKind::EulerParameters: {
      // A global moment M does the work of the generalised force 2 E(lambda)^T M = B M on the
      // Euler parameters, so the rotation compliance is B^T C_lambda B.
      const Eigen::Vector4d lambda = step.x.segment<4>(node.firstCoord);
      Eigen::Matrix<double, 4, 3> B;
      for (int k = 0; k < 3; ++k) B.col(k) = core::momentMatrix(Eigen::Vector3d::Unit(k)) * lambda;
      C = (B.transpose() * C * B).eval();
      names = {"rx", "ry", "rz"};
      break;
    }
    case core::NodeKind::Warping:
      names = {"warping"};  // BEAMW's warping coordinate (rate of twist)
      break;
  }
  for (size_t k = 0; k < names.size(); ++k)
    if (C(k, k) != 0.0) out.emplace_back(base + names[k], 1.0 / C(k, k));  // 0: a fixed coordinate
  return out;
}

namespace {
// A worker process's bases chosen for a target with their reduced operators, by reductionKey: the
// variants whose models share what the operators depend on (operatorModelChecksum) and the target
// share them (issue 49 item 3); a variant on which the shared basis misses the target chooses its
// own, which then replaces it. The most recent kMaxShared keys are kept.
std::shared_ptr<SharedReduction> sharedReductionFor(const core::Model& model, double target, int runs) {
  constexpr std::size_t kMaxShared = 16;
  static std::map<std::string, std::shared_ptr<SharedReduction>> kept;
  const std::string key = reductionKey(model, target);
  if (kept.size() >= kMaxShared && !kept.count(key)) kept.clear();
  std::shared_ptr<SharedReduction>& s = kept[key];
  if (!s) s = std::make_shared<SharedReduction>();
  s->runs = std::max(1, runs);
  return s;
}

// The simulate job every front end runs (analysis/SimulateJob.hpp), on a variant's model, and its
// summary quantities. A variant that cannot finish or fit fails with the reason instead of holding
// its worker.
void simulateVariant(const core::Model& model, const StudyAnalyses& a, VariantResults& r) {
  auto& q = r.quantities;
  SimulateRequest request;
  request.run = *a.simulation;
  request.run.progress = false;
  request.run.interrupt = nullptr;
  if (a.reductionTarget) {  // the variant's own basis for the target (none: the full model)
    request.basisFile = "auto";
    request.target = *a.reductionTarget;
    request.shared = sharedReductionFor(model, request.target, a.sharingVariants);
  }
  SimulateJob job(sourceOfModel(model), std::move(request));
  if (job.status() == JobStatus::InputError) throw std::runtime_error(firstError(job.diagnostics()));
  if (job.run() == JobStatus::Failed) throw std::runtime_error(firstError(job.diagnostics()));
  if (a.reductionTarget) {
    const bool met = job.options().basis.has_value();
    q.emplace_back("sim_basis_vectors", met ? static_cast<double>(job.options().basis->cols()) : kNaN);
    if (!met) r.notes.push_back("simulate: " + job.targetNote());
  }
  r.trajectory = std::move(job.trajectory());
  const core::Trajectory& tr = *r.trajectory;
  if (a.reductionTarget) {
    q.emplace_back("sim_reduction_estimate", tr.reduction.estimated ? tr.reduction.estimate : kNaN);
    // Right-hand sides evaluated by reduced operators (0: Eq. 19 throughout, or the full model).
    q.emplace_back("sim_operator_evaluations", static_cast<double>(tr.operators.evaluations));
  }
  q.emplace_back("sim_t_end", tr.time.empty() ? kNaN : tr.time.back());
  q.emplace_back("sim_steps", static_cast<double>(tr.nsteps));
  q.emplace_back("sim_fevals", static_cast<double>(tr.nfevals));
  double d = tr.states.empty() ? kNaN : 0.0;
  for (const auto& s : tr.states) d = std::max(d, maxDisplacement(model, s.x));
  q.emplace_back("sim_max_displacement", d);
  if (!tr.completed) r.failure = "simulate: " + tr.stopReason;
}
}  // namespace

VariantResults runVariant(const core::Model& model, const StudyAnalyses& a, const io::ParameterValues& parameters) {
  VariantResults r;
  auto& q = r.quantities;
  q.emplace_back("dofs", model.numDofs());
  const bool needsMass = a.modes > 0 || a.sweep || a.simulation;
  // What makes every analysis meaningless (the checks every job makes before it runs), once for
  // all analyses of the variant; their own notes beside the file's (said once for the study).
  auto diagnose = [&]() -> std::string {
    if (std::string why = userFunctionRefusal(model, model.sourceFile); !why.empty()) return why;
    const Diagnostics d = checkModelFor(model, "", {needsMass, true, false});
    for (std::size_t k = model.notes.size() + model.warnings.size(); k < d.size(); ++k)
      if (d[k].kind == Diagnostic::Kind::Note) r.notes.push_back(d[k].text);
    return firstError(d);
  };
  const ModelSource source = sourceOfModel(model);
  // A job's input error or failure as the variant's failure (its words).
  auto require = [](const ModelJob& job) {
    if (job.status() == JobStatus::InputError || job.status() == JobStatus::Failed)
      throw std::runtime_error(firstError(job.diagnostics()));
  };
  auto stage = [&](const char* name, const auto& body) {
    if (!r.failure.empty()) return;
    try {
      body();
    } catch (const core::KinematicsError& e) {
      r.failure = std::string(name) + ": the configuration cannot be assembled: " + e.what();
    } catch (const std::exception& e) {
      r.failure = std::string(name) + ": " + e.what();
    }
  };
  stage("model", [&] { r.failure = diagnose(); });
  if (a.check) {
    stage("check", [&] {
      r.check = core::checkKinematics(model);
      q.emplace_back("rank", r.check->rank);
      if (!r.check->wellPosed()) {
        std::string why = "check: the kinematics are not well posed";
        if (!r.check->underdetermined.empty()) why += "; undetermined: " + listed(r.check->underdetermined);
        if (!r.check->overdetermined.empty()) why += "; redundant: " + listed(r.check->overdetermined);
        r.failure = why;
      }
    });
  }
  if (a.modes > 0) {
    addFrequencies("f", std::min(a.modes, model.numDofs()), nullptr, q);
    stage("modes", [&] {
      ModesOptions mo;
      mo.nev = a.modes;
      ModesJob job(source, mo);  // as `flexmb modes`
      job.run();
      require(job);
      r.modes = job.result().frequencies;
      const size_t at = q.size() - std::min(a.modes, model.numDofs());
      for (Eigen::Index i = 0; i < r.modes->omega.size() && at + i < q.size(); ++i)
        q[at + i].second = hertz(r.modes->omega[i]);
    });
  }
  if (a.statics) {
    stage("static", [&] {
      StaticJob job(source, *a.statics);  // as `flexmb static`
      job.run();
      require(job);
      for (const Diagnostic& d : job.diagnostics())
        if (d.kind == Diagnostic::Kind::Note && d.text.rfind("no eigenfrequencies", 0) == 0)
          r.notes.push_back("static: " + d.text);
      const int nev = job.options().nev;
      r.statics = job.result();
      const StaticRun& run = *r.statics;
      const StaticStep* last = run.steps.empty() ? nullptr : &run.steps.back();
      q.emplace_back("static_steps", static_cast<double>(run.steps.size()));
      addFrequencies("static_f", nev, last ? &last->frequencies.omega : nullptr, q);
      for (int i = 0; i < a.statics->buckling; ++i)
        q.emplace_back("buckling" + std::to_string(i + 1),
                       last && i < last->buckling.size() ? last->buckling[i] : kNaN);
      q.emplace_back("max_displacement", last ? maxDisplacement(model, last->x) : kNaN);
      if (last)
        for (const SectionForceMaximum& f : sectionForceMaxima(model, last->sigma)) q.emplace_back(f.name, f.value);
      // The largest von Mises stress where VISUALIZATION gives sections (StaticDesign.hpp).
      if (last && !stressedElements(model).empty()) q.emplace_back("max_stress", largestStress(model, *last).vonMises);
      if (last) {
        const std::vector<int> nodes = a.stiffnessNodes.empty() ? loadedNodes(model) : a.stiffnessNodes;
        for (int label : nodes) {
          if (!model.nodeByLabel.count(label))
            throw std::invalid_argument("no node " + std::to_string(label) + " (--stiffness)");
          const auto k = nodeStiffness(model, *last, label);
          if (k.empty())
            r.notes.push_back("static: no stiffness at node " + std::to_string(label) + " (singular tangent)");
          q.insert(q.end(), k.begin(), k.end());
        }
      }
      if (!run.completed) r.failure = "static: " + run.stopReason;
    });
  }
  if (a.sweep) {
    stage("sweep", [&] {
      SweepJob job(source, *a.sweep);  // as `flexmb sweep`
      job.run();
      require(job);
      const SweepOptions& o = job.options();
      r.sweep = job.result();
      for (int i = 0; i < o.nev; ++i) {
        double lo = kNaN;
        for (const auto& p : r.sweep->points)
          if (i < p.omegaSorted.size()) lo = std::isnan(lo) ? p.omegaSorted[i] : std::min(lo, p.omegaSorted[i]);
        q.emplace_back("sweep_f" + std::to_string(i + 1) + "_min_Hz", std::isnan(lo) ? kNaN : hertz(lo));
      }
      double load = r.sweep->points.empty() ? kNaN : 0.0;
      for (const auto& p : r.sweep->points) load = std::max(load, std::abs(p.load));
      q.emplace_back("sweep_max_load", load);
      if (!r.sweep->completed) r.failure = "sweep: stopped " + r.sweep->stopReason;
    });
  }
  if (a.simulation) {
    stage("simulate", [&] { simulateVariant(model, a, r); });
  }
  if (a.accuracy) addAccuracyQuantities(model, a, r);
  if (r.failure.empty())
    for (const auto& [name, expression] : a.derived) {
      io::ParameterValues vars = parameters;
      vars.insert(vars.end(), q.begin(), q.end());
      try {
        const double v = io::evaluateExpression(expression, vars);
        q.emplace_back(name, std::isfinite(v) ? v : kNaN);
      } catch (const std::exception& e) {
        q.emplace_back(name, kNaN);
        r.failure = "derived quantity " + name + ": " + e.what();
        break;
      }
    }
  return r;
}

io::StudyRecord summaryRecord(const Variant& variant, const VariantResults& results) {
  io::StudyRecord rec;
  rec.variant = variant.number;
  rec.name = variant.name;
  rec.parameters = variant.values;
  rec.status = results.failure.empty() ? "ok" : "failed";
  rec.reason = results.failure;
  for (const auto& n : results.notes) rec.reason += (rec.reason.empty() ? "note: " : "; note: ") + n;
  rec.quantities = results.quantities;
  return rec;
}

io::StudyRecord failedRecord(const Variant& variant, const std::string& reason) {
  io::StudyRecord rec;
  rec.variant = variant.number;
  rec.name = variant.name;
  rec.parameters = variant.values;
  rec.status = "failed";
  rec.reason = reason;
  return rec;
}

// ---- resume ------------------------------------------------------------------------------------

std::string variantFingerprint(const std::string& templateText, const io::ParameterValues& values,
                               const StudyAnalyses& analyses, const std::string& version) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64
  auto add = [&](const std::string& s) {
    for (unsigned char c : s) {
      h ^= c;
      h *= 1099511628211ull;
    }
    h ^= 0xff;  // separator
    h *= 1099511628211ull;
  };
  add(templateText);
  for (const auto& [name, v] : values) add(name + "=" + io::roundTripNumber(v));
  add(analyses.describe());
  add(version);
  return hex64(h);
}

VariantState variantState(const std::string& manifestPath, const std::string& fingerprint,
                          const std::string& summaryPath) {
  std::ifstream in(manifestPath);
  if (!in) return VariantState::NotRun;
  std::string status, print;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("status: ", 0) == 0) status = line.substr(8);
    if (line.rfind("fingerprint: ", 0) == 0) print = line.substr(13);
  }
  if (status.empty()) return VariantState::NotRun;
  if (print != fingerprint) return VariantState::Stale;
  try {
    io::readStudyRecord(summaryPath);
  } catch (const std::exception&) {
    return VariantState::NotRun;
  }
  return status.rfind("failed", 0) == 0 ? VariantState::FinishedFailed : VariantState::Finished;
}

}  // namespace flexmb::analysis
