// Work-precision of the paper's two models (Boer et al. 2013, Section 4): wall time and evaluations
// against error for the full and the reduced models with ode45, and for the implicit integrators on
// the full models (tools/bench/README.md, item 1); and of the guidance with 20 PLBEAMs per leaf
// (issue 48): ode45 (stability-bound), generalized-alpha, BDF2 and auto on the full model against
// MODAL-3 with ode45, measured against a generalized-alpha reference. Every run is simulate's recipe
// (BenchRuns.hpp) but CVODE's difference-quotient variant, which simulate does not run.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/Simulation.hpp"
#include "io/formats/DatReader.hpp"
#include "io/pictures/SvgPlot.hpp"
#include "tools/bench/BenchRuns.hpp"
#include "tools/bench/BenchSections.hpp"
#include "tools/bench/BenchSupport.hpp"

namespace flexmb::bench {

namespace {

struct Reference {
  std::vector<Eigen::Vector2d> r;
  double scale = 1.0;  // max deflection (guidance) or reach (manipulator)
  std::string scaleText;
};

struct Method {
  std::string label;       // "full", "MODAL-3", ...
  std::string integrator;  // "ode45" or a kCvode name
  std::optional<Eigen::MatrixXd> basis;
  analysis::Integrator recipe = analysis::Integrator::Ode45;  // how simulate runs it
  int bdfOrder = 0;                                           // BDF's highest order (0: not BDF)
  bool differenceQuotients = false;                           // the bench's own CVODE run
  std::vector<double> tols;                                   // its tolerances (empty: the case's)
  double cap = NAN;                                           // its wall-time cap in seconds (NaN: Settings::hardCap)
  bool stabilityBound = false;  // known to be bound by stability here (said where it is capped)
};

Method method(const std::string& label, const std::string& integrator,
              const std::optional<Eigen::MatrixXd>& basis = std::nullopt,
              analysis::Integrator recipe = analysis::Integrator::Ode45, int bdfOrder = 0,
              bool differenceQuotients = false) {
  Method m;
  m.label = label;
  m.integrator = integrator;
  m.basis = basis;
  m.recipe = recipe;
  m.bdfOrder = bdfOrder;
  m.differenceQuotients = differenceQuotients;
  return m;
}

// What a point's runs give its judgement: the states at the output times (simulate's output
// quantities, with its reduction error estimate), the accuracy check's windows and the options the
// check runs them again with (the run's).
struct Outcome {
  std::string reason;  // why the run did not complete ("" when it did)
  bool capped = false;
  core::Trajectory states;
  analysis::DeferredAccuracy windows;
  analysis::SimulationOptions check;
};

// The response at the output times: x and y of the node.
std::vector<Eigen::Vector2d> responses(const core::Model& model, const core::Trajectory& run, int nodeLabel) {
  const int first = model.nodes[model.nodeByLabel.at(nodeLabel)].firstCoord;
  std::vector<Eigen::Vector2d> res;
  res.reserve(run.states.size());
  for (const core::StateOutputs& s : run.states) res.emplace_back(s.x[first], s.x[first + 1]);
  return res;
}

// NaN when the run did not reach every output time.
double errorAgainst(const std::vector<Eigen::Vector2d>& a, const Reference& ref, bool xOnly) {
  if (a.size() != ref.r.size()) return NAN;
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, xOnly ? std::abs(a[i].x() - ref.r[i].x()) : (a[i] - ref.r[i]).norm());
  return worst / ref.scale;
}

// The reference: the full model with the case's reference integrator (the recipe; ode45 on the
// paper's models) at the reference tolerance, and the error scale.
std::optional<Reference> referenceOf(const CaseSpec& cs, const core::Model& model, const Settings& set,
                                     WorkPrecisionResults& out) {
  const double rt = set.refTol.at(cs.key), at = rt * set.absFactor;
  const char* integ = analysis::integratorName(cs.reference);
  std::printf("[%s] reference: full model, %s, RelTol %s AbsTol %s ...\n", cs.key.c_str(), integ, tolText(rt).c_str(),
              tolText(at).c_str());
  const CappedRun run = runCapped(model, recipeOptions(model, cs.reference, rt, at), kNoCap);
  if (!run.completed()) {
    std::fprintf(stderr, "flexmb_bench: the reference run of %s failed: %s\n", cs.key.c_str(), run.reason.c_str());
    return std::nullopt;
  }
  Reference ref;
  ref.r = responses(model, run.trajectory, cs.node);
  if (cs.xOnly) {
    double d = 0;
    for (const auto& p : ref.r) d = std::max(d, std::abs(p.x() - ref.r.front().x()));
    ref.scale = d;
    ref.scaleText = "max |x(node " + std::to_string(cs.node) + ") - x0| = " + fmt("%.5f", d) + " m";
  } else {
    // Reach: base to elbow plus elbow to tip in the initial configuration.
    auto node = [&](int label) {
      const int f = model.nodes[model.nodeByLabel.at(label)].firstCoord;
      return Eigen::Vector2d(model.x0[f], model.x0[f + 1]);
    };
    ref.scale = (node(5) - node(1)).norm() + (node(9) - node(5)).norm();
    ref.scaleText = "reach |node 5 - node 1| + |node 9 - node 5| = " + fmt("%.4f", ref.scale) + " m";
  }
  const long fevals = run.trajectory.nfevals;
  std::printf("[%s] reference: %ld fevals, %s s; %s\n", cs.key.c_str(), fevals, secText(run.wall).c_str(),
              ref.scaleText.c_str());
  const std::string how = cs.reference == analysis::Integrator::Ode45
                              ? "ode45-equivalent"
                              : std::string(integ) + " (simulate's recipe; its RelTol is its global error)";
  out.refNotes[cs.key] = "full model, " + how + ", RelTol " + tolText(rt) + ", AbsTol " + tolText(at) + " (" +
                         withThousands(fevals) + " fevals, " + withThousands(run.trajectory.nsteps) + " steps, " +
                         secText(run.wall) + " s); error scale: " + ref.scaleText;
  return ref;
}

// The full model with ode45, the reduced ones (bases: analysis::buildBasis), then the implicit
// integrators on the full model. The refined guidance: ode45 at RelTol 1e-3 only (bound by
// stability), MODAL-3, then generalized-alpha, BDF2 and auto, all at Settings::stabilityCap.
std::vector<Method> methodsOf(const CaseSpec& cs, const core::Model& model, const Settings& set,
                              std::string& basisNote) {
  std::vector<Method> methods;
  methods.push_back(method("full", "ode45"));
  if (!cs.paper) {
    methods.back().tols = {1e-3};
    methods.back().cap = set.stabilityCap;
    methods.back().stabilityBound = true;
  }
  auto addBasis = [&](const std::string& label, const analysis::ReductionOptions& ro) {
    const auto b0 = Clock::now();
    const analysis::ReductionResult rr = analysis::buildBasis(model, ro);
    const double bt = since(b0);
    std::string lab = label;
    if (ro.method == "svd-modal") {  // the label's mode count is the number the 1% criterion keeps
      const int kept = static_cast<int>(rr.V.cols()) - static_cast<int>(rr.large.size());
      lab = "SVDm-" + std::to_string(kept) + "-a" + fmt("%g", ro.weight);
    }
    methods.push_back(method(lab, "ode45", rr.V));
    basisNote += (basisNote.empty() ? "" : "; ") + lab + ": " + std::to_string(rr.V.cols()) + " columns, built in " +
                 secText(bt) + " s";
  };
  auto modal = [](int r) {
    analysis::ReductionOptions ro;
    ro.method = "modal";
    ro.modes = r;
    return ro;
  };
  if (!cs.paper) {  // every run capped as one that may stall (BDF2 at RelTol 1e-5 does)
    addBasis("MODAL-3", modal(3));
    for (const CvodeVariant& v : kCvode)
      if (v.integrator == analysis::Integrator::GeneralizedAlpha || (!v.differenceQuotients && v.bdfOrder == 2))
        methods.push_back(method("full", v.name, std::nullopt, v.integrator, v.bdfOrder, v.differenceQuotients));
    methods.push_back(method("full", "auto", std::nullopt, analysis::Integrator::Auto));
    for (Method& m : methods) m.cap = set.stabilityCap;
    return methods;
  }
  if (cs.key == "straight_guidance") {
    for (int r : {3, 5}) addBasis("MODAL-" + std::to_string(r), modal(r));
    for (double a : {0.0, 1.0}) {
      analysis::ReductionOptions ro;
      ro.method = "svd-modal";
      ro.modes = 3;
      ro.configs = 10;
      ro.weight = a;
      ro.threshold = 0.01;
      ro.node = 6;
      ro.component = 1;
      ro.from = -0.0833;
      ro.to = 0.0833;
      addBasis("SVDm", ro);
    }
  } else {
    addBasis("MODAL-2", modal(2));
  }
  for (const CvodeVariant& v : kCvode)
    methods.push_back(method("full", v.name, std::nullopt, v.integrator, v.bdfOrder, v.differenceQuotients));
  return methods;
}

// A point's runs: timed (the median of 3 when one takes less than repeatBelow s), and the states
// they reach. simulate's recipe is timed without keeping its states (the figure is set-up and
// integration; output quantities are not part of it) and run once more, untimed, keeping them with
// the accuracy check's windows and the reduction error estimate. The bench's own CVODE run stores
// its states as it goes; their output quantities are evaluated afterwards, untimed.
Outcome measure(const core::Model& model, const Method& m, double tol, const Settings& set, Point& pt) {
  const double absTol = tol * set.absFactor;
  const double cap = std::isnan(m.cap) ? set.hardCap : m.cap;
  Outcome o;
  o.check = recipeOptions(model, m.recipe, tol, absTol, m.basis, m.bdfOrder);
  std::vector<double> walls;
  if (m.differenceQuotients) {
    auto once = [&] { return runCvodeDifferenceQuotients(model, tol, absTol, m.bdfOrder, cap); };
    const OwnRun r = once();
    walls.push_back(r.wall);
    if (r.reason.empty() && r.wall < set.repeatBelow)
      for (int k = 0; k < 2; ++k) walls.push_back(once().wall);
    pt.fevals = r.fevals, pt.jacFevals = r.jacFevals, pt.njac = r.njac, pt.nsteps = r.nsteps, pt.nfailed = r.nfailed;
    o.reason = r.reason;
    if (o.reason.empty()) o.states = statesOf(model, r, o.windows);
  } else {
    analysis::SimulationOptions timed = o.check;
    timed.keepStates = false;
    const CappedRun r = runCapped(model, timed, cap);
    walls.push_back(r.wall);
    const core::Trajectory& t = r.trajectory;
    pt.fevals = t.nfevals, pt.njac = t.njacevals, pt.nsteps = t.nsteps, pt.nfailed = t.nfailed;
    pt.jacFevals = 0;  // simulate's implicit integrators evaluate the analytic Jacobian
    o.reason = r.reason;
    o.capped = r.capped;
    if (r.capped && m.stabilityBound) o.reason += " (its step is bound by stability, not accuracy)";
    if (r.completed()) {
      analysis::SimulationOptions kept = o.check;
      kept.deferAccuracy = &o.windows;
      kept.reductionEstimate = m.basis.has_value();
      CappedRun s = runCapped(model, kept, cap);
      if (!s.completed()) o.reason = "the run that keeps its states: " + s.reason;
      if (s.completed() && s.trajectory.nfevals != t.nfevals)
        std::fprintf(stderr, "warning: the run that keeps its states took %ld evaluations, the timed one %ld\n",
                     s.trajectory.nfevals, t.nfevals);
      o.states = std::move(s.trajectory);
      if (r.wall < set.repeatBelow)
        for (int k = 0; k < 2; ++k) walls.push_back(runCapped(model, timed, cap).wall);
    }
  }
  pt.runs = static_cast<int>(walls.size());
  pt.wall = median(walls);
  pt.capped = o.capped;
  return o;
}

// The point's status: its error against the reference, the reduction error estimate, and "ok" only
// where simulate's accuracy check finds the run converged.
void judge(const core::Model& model, const CaseSpec& cs, const Reference& ref, const Outcome& o,
           const std::vector<Point>& done, Point& pt) {
  if (!o.reason.empty()) {
    pt.status = "failed";
    pt.note = o.reason;
    return;
  }
  try {
    pt.error = errorAgainst(responses(model, o.states, cs.node), ref, cs.xOnly);
    pt.status = std::isfinite(pt.error) ? "ok" : "failed";
    if (!std::isfinite(pt.error)) pt.note = "non-finite response";
  } catch (const std::exception& e) {
    pt.status = "failed";
    pt.note = std::string("response evaluation: ") + e.what();
  }
  if (pt.status != "failed" && o.states.reduction.estimated) pt.reduction = o.states.reduction.estimate;
  if (pt.status != "ok") return;
  // auto that ran generalized-alpha from the start (the same steps and evaluations as galpha's point)
  // is galpha's run: its check would repeat galpha's (3 s at RelTol 1e-5 on the 20-element guidance).
  if (pt.integrator == "auto")
    for (const Point& g : done)
      if (g.model == pt.model && g.method == pt.method && g.integrator == "generalized-alpha" &&
          g.relTol == pt.relTol && g.fevals == pt.fevals && g.nsteps == pt.nsteps && g.njac == pt.njac &&
          g.completed() && std::isfinite(g.estimate)) {
        pt.estimate = g.estimate;
        pt.status = g.status;
        pt.note = g.note.empty() ? "the run is generalized-alpha's: its accuracy check" : g.note;
        return;
      }
  try {  // "ok" means converged, as simulate's accuracy check says it
    const analysis::DeferredAccuracy& w = o.windows;
    if (!w.recorded) throw std::runtime_error("the run recorded no windows");
    const core::AccuracyEstimate acc = analysis::checkAccuracy(model, o.check, w.t0, w.tEnd, w.windows, w.galphaFrom);
    pt.estimate = acc.checked ? acc.estimate : NAN;
    if (!acc.converged()) {
      pt.status = "not converged";
      pt.note = "accuracy check: estimated error " + sci(acc.estimate, 1) + " > " + sci(acc.limit, 1) + " (10 RelTol)";
    } else if (!acc.checked) {
      pt.note = "accuracy check not run: " + acc.note;
    }
  } catch (const std::exception& e) {
    pt.note = std::string("accuracy check not run: ") + e.what();
  }
}

void printPoint(const std::string& tag, const Point& pt, bool implicit) {
  if (!pt.completed()) {
    std::printf("%s: FAILED after %s s, %ld fevals: %s\n", tag.c_str(), secText(pt.wall).c_str(), pt.fevals,
                pt.note.c_str());
    return;
  }
  const std::string jacobians = implicit ? " (" + std::to_string(pt.njac) + " Jacobians, " +
                                               std::to_string(pt.jacFevals) + " evaluations in them)"
                                         : "";
  std::printf("%s: %ld fevals%s, %s s (%s), error %s, accuracy check %s, reduction estimate %s%s\n", tag.c_str(),
              pt.fevals, jacobians.c_str(), secText(pt.wall).c_str(), pt.runs > 1 ? "median of 3" : "1 run",
              sci(pt.error).c_str(), std::isfinite(pt.estimate) ? sci(pt.estimate, 1).c_str() : "-",
              std::isfinite(pt.reduction) ? sci(pt.reduction, 1).c_str() : "-",
              pt.status == "ok" ? "" : " (NOT CONVERGED)");
}

// One method over the tolerances. Budget: a point predicted (last time x the growth of the
// evaluation count, at least 10^(1/5) per decade) to exceed skipAbove is skipped with the tighter ones,
// as are those after a run that hit the cap.
void sweep(const CaseSpec& cs, const core::Model& model, const Method& m, const Reference& ref, const Settings& set,
           WorkPrecisionResults& out) {
  double lastWall = NAN, lastFe = NAN, prevFe = NAN, predicted = NAN;
  bool stop = false;
  for (double tol : m.tols.empty() ? (cs.paper ? set.tols : set.refinedTols) : m.tols) {
    Point pt;
    pt.model = cs.key;
    pt.method = m.label;
    pt.integrator = m.integrator;
    pt.relTol = tol;
    pt.absTol = tol * set.absFactor;
    if (!stop && std::isfinite(lastWall)) {
      const double ratio = std::isfinite(prevFe) && prevFe > 0 ? lastFe / prevFe : 1.0;
      predicted = lastWall * std::max(ratio, std::pow(10.0, 0.2));
      if (predicted > set.skipAbove) stop = true;
    } else if (stop) {
      predicted *= std::pow(10.0, 0.2);
    }
    const std::string tag = "[" + cs.key + "] " + m.label + " / " + m.integrator + " RelTol " + tolText(tol);
    if (stop) {
      pt.status = "skipped";
      pt.note = "predicted > " + fmt("%.0f", predicted) + " s";
      std::printf("%s: skipped (predicted %.0f s > %.0f s)\n", tag.c_str(), predicted, set.skipAbove);
      out.skipped.push_back(cs.key + " " + m.label + " (" + m.integrator + ") RelTol " + tolText(tol) + ": " + pt.note);
      out.points.push_back(pt);
      continue;
    }
    judge(model, cs, ref, measure(model, m, tol, set, pt), out.points, pt);
    printPoint(tag, pt, m.integrator != "ode45");
    if (pt.completed()) {
      prevFe = lastFe;
      lastFe = static_cast<double>(pt.fevals);
      lastWall = pt.wall;
    } else if (pt.capped || pt.wall > set.skipAbove) {  // hit the cap: tighter tolerances only cost more
      stop = true;
      predicted = pt.wall;
    }
    out.points.push_back(pt);
  }
}

// The work-precision diagrams of a model: wall time and evaluations against error.
void plotCase(const CaseSpec& cs, const Settings& set, const std::string& dir, WorkPrecisionResults& out) {
  for (int kind = 0; kind < 2; ++kind) {
    io::Plot plot;
    plot.title = "Work-precision: " + cs.title;
    plot.x = {"error: max over output times of |response - reference| / " +
                  std::string(cs.xOnly ? "max deflection" : "reach"),
              true, std::nullopt, std::nullopt};
    plot.y = {kind == 0 ? "wall time in-process [s] (set-up + integration, median)" : "right-hand-side evaluations",
              true, std::nullopt, std::nullopt};
    const std::vector<double>& tols = cs.paper ? set.tols : set.refinedTols;
    plot.notes.push_back("RelTol " + tolText(tols.front()) + " ... " + tolText(tols.back()) +
                         " (AbsTol = 1e-3 RelTol); reference: full model, " + analysis::integratorName(cs.reference) +
                         ", RelTol " + tolText(set.refTol.at(cs.key)));
    plot.notes.push_back(cs.xOnly ? "response: x of node " + std::to_string(cs.node) + " (rigid body)"
                                  : "response: tip position (node 9)");
    for (const Point& pt : out.points)  // a capped run has no error: say so on the plot
      if (pt.model == cs.key && pt.capped)
        plot.notes.push_back(pt.method + " (" + pt.integrator + ") RelTol " + tolText(pt.relTol) + ": " + pt.note +
                             "; not plotted");
    std::map<std::string, size_t> seriesOf;
    for (const Point& pt : out.points) {
      if (pt.model != cs.key) continue;
      const std::string label = pt.method + " (" + pt.integrator + ")";
      if (!seriesOf.count(label)) {
        seriesOf[label] = plot.series.size();
        io::Series se;
        se.label = label;
        se.markers = true;
        se.dashed = pt.integrator != "ode45";
        plot.series.push_back(se);
      }
      if (!pt.completed()) continue;  // a run the accuracy check flags is still a measured point
      auto& se = plot.series[seriesOf[label]];
      se.x.push_back(pt.error);
      se.y.push_back(kind == 0 ? pt.wall : static_cast<double>(pt.fevals));
    }
    const std::string name = (kind == 0 ? "wp_" : "wp_fevals_") + cs.key + ".svg";
    io::writeSvg(dir + "/" + name, plot);
    out.svgFiles[cs.key + (kind == 0 ? "" : "_fevals")] = name;
  }
}

}  // namespace

bool workPrecision(const Options& opt, const Settings& set, WorkPrecisionResults& out) {
  const std::string src = FLEXMB_SOURCE_DIR;
  const std::vector<CaseSpec> cases = {
      {"straight_guidance", "straight guidance (0.2 s)", src + "/datfiles/straight_guidance.dat", 6, true},
      {"manipulator", "two-link manipulator (0.7 s)", src + "/datfiles/manipulator.dat", 9, false},
      // The rigid body's left node (the paper's node 6) is node 21 on this mesh.
      {"straight_guidance_20", "straight guidance, 20 PLBEAMs per leaf (0.2 s)",
       src + "/datfiles/tests/straight_guidance_20.dat", 21, true, false, analysis::Integrator::GeneralizedAlpha}};
  for (const CaseSpec& cs : cases) {
    if (opt.only == "rhs") break;  // development: the rhs scaling only
    const core::Model model = io::readDatFile(cs.file);
    std::vector<Method> methods;  // those --only selects; a case without any is left out, reference included
    for (Method& m : methodsOf(cs, model, set, out.basisNotes[cs.key]))
      if (opt.only.empty() || (cs.key + " " + m.label + " " + m.integrator).find(opt.only) != std::string::npos)
        methods.push_back(std::move(m));
    if (methods.empty()) continue;
    out.cases.push_back(cs);
    const std::optional<Reference> ref = referenceOf(cs, model, set, out);
    if (!ref) return false;
    for (const Method& m : methods) sweep(cs, model, m, *ref, set, out);
    plotCase(cs, set, opt.out, out);
  }
  return true;
}

}  // namespace flexmb::bench
