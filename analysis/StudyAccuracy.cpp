#include "analysis/StudyAccuracy.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// What one end's ladder found.
struct EndLadder {
  std::string name;
  bool ran = false;
  std::string why;  // why it did not run
  LadderResult ladder;
  int refine = 1;  // the level the ladder chose (with a target: the finest that completed)
  double seconds = 0.0;
};

template <class Job>
EndLadder endOf(const std::string& name, AccurateRun<Job> run) {
  EndLadder e;
  e.name = name;
  e.ladder = std::move(run.ladder);
  const DiscretizationEstimate& est = e.ladder.estimate;
  for (const MeshLevel& l : est.levels) e.seconds += l.seconds;
  const bool levelOk = !est.levels.empty() && est.levels[static_cast<size_t>(e.ladder.chosen)].ok;
  if (!run.job || !levelOk) {
    std::string why = firstError(run.diagnostics);
    if (why.empty() && run.job) why = firstError(run.job->diagnostics());
    if (why.empty() && !est.levels.empty()) why = est.levels.front().reason;
    e.why = why.empty() ? "the analysis did not complete" : why;
    return e;
  }
  e.ran = true;
  e.refine = est.levels[static_cast<size_t>(e.ladder.chosen)].refine;
  return e;
}

// The end's estimate carried to refine r along its order (NaN: not estimated).
double estimateAt(const EndLadder& e, int r) {
  const DiscretizationEstimate& est = e.ladder.estimate;
  if (!e.ran || !est.estimated) return kNoValue;
  return est.estimate * std::pow(static_cast<double>(est.ofRefine) / r, est.order);
}

// Runs the study's laddered analysis on one end.
EndLadder climbEnd(const StudyEnd& end, const StudyAnalyses& s, const std::string& analysis, const AccuracyRequest& a) {
  if (analysis == "simulate") {
    SimulateRequest request;
    request.run = *s.simulation;
    request.run.progress = false;
    return endOf(end.name, simulateToAccuracy(end.source, std::move(request), a));
  }
  if (analysis == "static") return endOf(end.name, staticToAccuracy(end.source, *s.statics, a));
  if (analysis == "sweep") return endOf(end.name, sweepToAccuracy(end.source, *s.sweep, a));
  ModesOptions mo;
  mo.nev = s.modes;
  mo.participation = false;
  return endOf(end.name, modesToAccuracy(end.source, mo, a));
}

// The largest displacement of a file's own position coordinate over the run, or the model size where
// it is below a thousandth of it: the scale of the integration and reduction estimates (as the
// single jobs' ladder measures the motion).
double motionScale(const core::Model& model, const core::Trajectory& t) {
  const int nx = model.unrefined ? model.unrefined->nx : model.nx;
  double motion = 0.0;
  for (const auto& s : t.states)
    for (int i = 0; i < nx && i < s.x.size(); ++i)
      if (core::isTranslational(model.nodes[model.xOwnerNode[i]].kind))
        motion = std::max(motion, std::abs(s.x[i] - model.x0[i]));
  const double size = model.lengthScale() > 0.0 ? model.lengthScale() : 1.0;
  return motion >= 1e-3 * size ? motion : size;
}

double quantity(const VariantResults& r, const std::string& name) {
  for (const auto& [n, v] : r.quantities)
    if (n == name) return v;
  return kNoValue;
}

}  // namespace

std::vector<std::string> ladderAnalyses(const StudyAnalyses& s) {
  std::vector<std::string> out;
  if (s.simulation) out.emplace_back("simulate");
  if (s.statics) out.emplace_back("static");
  if (s.sweep) out.emplace_back("sweep");
  if (s.modes > 0) out.emplace_back("modes");
  return out;
}

namespace {

// Every ladder asked: each analysis on each end, the time allowed shared by all.
std::vector<EndLadder> climbAll(const std::vector<StudyEnd>& ends, const StudyAnalyses& s,
                                const std::vector<std::string>& analyses, const AccuracyRequest& ask, double& spent) {
  std::vector<EndLadder> done;
  for (const std::string& analysis : analyses)
    for (const StudyEnd& end : ends) {
      const std::string label = analyses.size() > 1 ? end.name + " " + analysis : end.name;
      AccuracyRequest one = ask;
      one.maxSeconds = std::max(ask.maxSeconds - spent, 1e-3);
      if (ask.progress)
        one.progress = [&ask, label](const Diagnostic& d) {
          Diagnostic named = d;
          named.text = label + ": " + d.text;
          ask.progress(named);
        };
      const auto start = std::chrono::steady_clock::now();
      done.push_back(climbEnd(end, s, analysis, one));
      done.back().name = label;
      spent += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  return done;
}

std::string joined(const std::vector<std::string>& v, const std::string& last) {
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) out += (i == 0 ? "" : i + 1 == v.size() ? last : ", ") + v[i];
  return out;
}

}  // namespace

StudyAccuracyPlan planStudyAccuracy(const std::vector<StudyEnd>& ends, StudyAnalyses& s, const AccuracyRequest& a,
                                    bool reduce) {
  StudyAccuracyPlan plan;
  const std::vector<std::string> analyses = ladderAnalyses(s);
  if (analyses.empty())
    throw std::invalid_argument("the accuracy of a study is measured on simulate, static, sweep or modes: ask one");
  if (reduce && !s.simulation) throw std::invalid_argument("a reduction goes with simulate");
  const std::string analysis = joined(analyses, " and ");
  const bool eps = !std::isnan(a.eps);
  if (s.simulation && eps) {
    if (!s.simulation->relTol) s.simulation->relTol = a.eps / kToleranceDivisor;
    if (!s.simulation->absTol) s.simulation->absTol = *s.simulation->relTol * 1e-2;
  }
  if (s.simulation) s.simulation->accuracyCheck = true;  // it measures each variant's integration error
  if (reduce && eps) s.reductionTarget = kReductionShare * a.eps;
  AccuracyRequest ask = a;  // the mesh's share of EPS
  ask.discretizationShare = s.reductionTarget && eps ? kReducedDiscretizationShare : kDiscretizationShare;
  const std::vector<EndLadder> done = climbAll(ends, s, analyses, ask, plan.seconds);
  // The mesh: the largest of the ladders' choices (a ladder that did not run is said and left out).
  int refine = 0;
  std::vector<std::string> ran, choices, measures;
  bool reachable = eps;
  for (const EndLadder& e : done) {
    if (!e.ran) {
      plan.diagnostics.emplace_back(Diagnostic::Kind::Warning, "",
                                    "the ladder of " + e.name + " did not run: " + e.why);
      reachable = false;
      continue;
    }
    ++plan.ladders;
    refine = std::max(refine, e.refine);
    choices.push_back(e.name + " " + std::to_string(e.refine));
    if (eps && !e.ladder.met) reachable = false;
    // Each estimate is relative to its own scale (an end's motion, a frequency): the words alone.
    const std::string m = e.ladder.estimate.measure.substr(0, e.ladder.estimate.measure.find(" ("));
    if (std::find(measures.begin(), measures.end(), m) == measures.end()) measures.push_back(m);
  }
  for (const StudyEnd& end : ends) ran.push_back(end.name);
  if (refine == 0) {
    plan.diagnostics.emplace_back(Diagnostic::Kind::Error, "",
                                  "the discretization error could not be measured: " + done.front().why);
    return plan;
  }
  plan.ok = true;
  double D = 0.0;
  for (const EndLadder& e : done) {
    const double d = e.ran ? estimateAt(e, refine) : 0.0;
    D = std::isnan(d) || std::isnan(D) ? kNoValue : std::max(D, d);
  }
  const std::string measure = joined(measures, " or ");
  StudyAccuracy acc;
  acc.eps = a.eps;
  acc.refine = refine;
  acc.discretization = D;
  acc.reachable = reachable && !std::isnan(D) && D <= ask.discretizationShare * a.eps * (1 + 1e-12);
  acc.analysis = analysis;
  s.accuracy = acc;
  // The record.
  auto setting = [&](const std::string& k, const std::string& v) { plan.settings.emplace_back(k, v); };
  const std::string dText = std::isnan(D) ? std::string("not estimated") : text::significant(D, 2) + " " + measure;
  const std::string larger =
      done.size() > 1 ? (done.size() > 2 ? " (the largest of " : " (the larger of ") + joined(choices, ", ") + ")" : "";
  setting("accuracy target", eps ? text::significant(a.eps, 3) + " " + measure + " (each variant's own)"
                                 : "none (--error-estimate: the model's own mesh, estimated)");
  for (const EndLadder& e : done)
    if (e.ran)
      setting("discretization ladder", e.name + ": " + describeDiscretization(e.ladder.estimate) + "; " +
                                           std::to_string(e.ladder.estimate.levels.size()) + " meshes, " +
                                           text::significant(e.seconds, 2) + " s");
  setting("discretization measured", "by " + analysis + " at the parameter range's ends (" + joined(ran, " and ") +
                                         "), not per variant: every variant's D is the larger estimate, " + dText +
                                         " at refine " + std::to_string(refine));
  setting("refinement chosen", std::to_string(refine) + (refine == 1 ? " part" : " parts") +
                                   " per flexible beam for every variant" + larger);
  if (s.simulation && s.simulation->relTol)
    setting("integrator tolerance",
            "RelTol " + text::significant(*s.simulation->relTol, 3) + (eps ? " (the accuracy target / 20)" : ""));
  if (s.reductionTarget)
    setting("reduction target",
            text::significant(*s.reductionTarget, 3) + (reduce && eps ? " (a quarter of the accuracy target)" : ""));
  if (eps)
    setting("accuracy reachable",
            acc.reachable ? "yes" : "no: the variants run on refine " + std::to_string(refine) + ", accuracy_met 0");
  // The screen.
  plan.diagnostics.emplace_back(Diagnostic::Kind::Result, "",
                                "study mesh: refine " + std::to_string(refine) + " for every variant" + larger +
                                    "; discretization error " + dText + ", measured by " + analysis + " at " +
                                    joined(ran, " and ") + " (the range's ends, not per variant)");
  if (eps && !acc.reachable) {
    std::string why;
    for (const EndLadder& e : done)
      if (e.ran && !e.ladder.stopNote.empty()) why += (why.empty() ? "" : "; ") + e.name + ": " + e.ladder.stopNote;
    plan.diagnostics.emplace_back(Diagnostic::Kind::Warning, "",
                                  "the accuracy target " + text::significant(a.eps, 2) + " cannot be reached" +
                                      (why.empty() ? std::string() : " (" + why + ")") +
                                      ": the variants run on refine " + std::to_string(refine) +
                                      ", the finest mesh the ladder reached, and are marked accuracy_met 0",
                                  "", "", "max_seconds");
  }
  return plan;
}

void addAccuracyQuantities(const core::Model& model, const StudyAnalyses& a, VariantResults& r) {
  const StudyAccuracy& acc = *a.accuracy;
  double integration = 0.0, reduction = 0.0;
  if (a.simulation) {
    integration = kNoValue;
    if (r.trajectory && r.trajectory->accuracy.checked)
      integration = r.trajectory->accuracy.positionEstimate * model.lengthScale() / motionScale(model, *r.trajectory);
    // A reduced run adds its estimate; where no basis met the target the full model ran (0).
    if (a.reductionTarget && !std::isnan(quantity(r, "sim_basis_vectors")))
      reduction = quantity(r, "sim_reduction_estimate");
  }
  const double total = acc.discretization + integration + reduction;
  auto& q = r.quantities;
  q.emplace_back("discretization_error", acc.discretization);
  q.emplace_back("integration_error", integration);
  q.emplace_back("reduction_error", reduction);
  q.emplace_back("total_error_estimate", total);
  q.emplace_back("accuracy_met", std::isnan(acc.eps) ? kNoValue
                                 : (acc.reachable && r.failure.empty() && total <= acc.eps)
                                     ? 1.0
                                     : 0.0);  // NaN total: not met
}

}  // namespace flexmb::analysis
