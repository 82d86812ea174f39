#pragma once
// `study --accuracy EPS` and `study --error-estimate` (issue 50 item 3): the discretization error of a
// design study, measured once for all variants instead of per variant. The mesh ladder of the single
// jobs (analysis/AccuracyTarget.hpp) runs on the first variant (the nominal design) and, when there
// are more, on the last (the other end of the parameter range), for each of the study's analyses it
// supports (simulate, static, sweep, modes; each ladder is the single job's). Every variant then
// runs on the largest of the refinements chosen; its discretization error is the largest of the
// ladders' estimates scaled to that refinement (each relative to its own scale: an end's motion, a
// frequency; stated as measured at the two ends, not per variant), and it adds its own integration
// error (the accuracy check) and reduction error (its basis' estimate).
//
// The budget: without a reduction as the single jobs (the mesh kDiscretizationShare of EPS, RelTol =
// EPS / kToleranceDivisor); with one (`--reduce`), the mesh kReducedDiscretizationShare, the basis
// target kReductionShare of EPS, RelTol the same.
#include <string>
#include <utility>
#include <vector>

#include "analysis/AccuracyTarget.hpp"
#include "analysis/Study.hpp"

namespace flexmb::analysis {

constexpr double kReducedDiscretizationShare = 0.5;
constexpr double kReductionShare = 0.25;

// One end of the parameter range: a variant's name and its model (text and read options; the read
// options' refine is the ladder's first level).
struct StudyEnd {
  std::string name;
  ModelSource source;
};

struct StudyAccuracyPlan {
  bool ok = false;          // false: neither end's ladder ran (diagnostics say why); no variant should run
  int ladders = 0;          // the ladders that ran (analyses x ends)
  Diagnostics diagnostics;  // the choice, and the warnings (the ladders' level notes went to progress)
  // The study's record (study.txt): accuracy target, refinement chosen, integrator tolerance,
  // reduction target, where the discretization error was measured, whether EPS is reachable.
  std::vector<std::pair<std::string, std::string>> settings;
  double seconds = 0.0;  // the ladders' runs
};

// Runs the ladders on `ends` (one or two) with a.eps (NaN: --error-estimate; each end's read refine
// is then the mesh estimated) and sets analyses.accuracy (its refine is the mesh every variant must
// be read with), and with eps the simulation's RelTol (EPS / kToleranceDivisor unless given), AbsTol
// and accuracy check; `reduce` (simulate only, with eps): analyses.reductionTarget = kReductionShare
// EPS. a.maxSeconds bounds both ladders together. a.progress hears every level, named by its end.
// Throws std::invalid_argument when the study runs no analysis a ladder supports.
StudyAccuracyPlan planStudyAccuracy(const std::vector<StudyEnd>& ends, StudyAnalyses& analyses,
                                    const AccuracyRequest& a, bool reduce);

// The analyses the ladders run, in the order simulate, static, sweep, modes (empty: none supported).
std::vector<std::string> ladderAnalyses(const StudyAnalyses& analyses);

// A variant's error columns after its analyses (runVariant): discretization_error (the study's),
// integration_error (its accuracy check, relative to its own motion; 0 without simulate),
// reduction_error (its basis' estimate; 0 for the full model), total_error_estimate and accuracy_met
// (1 or 0; empty without a target). Empty cells (NaN) where an error is not known.
void addAccuracyQuantities(const core::Model& model, const StudyAnalyses& analyses, VariantResults& results);

}  // namespace flexmb::analysis
