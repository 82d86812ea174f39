#include "analysis/TargetOperators.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "analysis/OperatorPolicy.hpp"
#include "analysis/OperatorTraining.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
std::string seconds2(double s) { return text::significant(s, 2) + " s"; }
std::string micro2(double s) { return text::significant(s * 1e6, 2) + " us"; }
}  // namespace

OperatorPayoff operatorsPay(long evaluations, double equation19Seconds, double operatorSeconds,
                            double trainingSeconds) {
  OperatorPayoff p;
  const bool predicted = std::isnan(trainingSeconds);
  p.training = predicted ? kTrainingInEquation19 * equation19Seconds : trainingSeconds;
  const double saved = operatorSeconds > 0.0 ? equation19Seconds - operatorSeconds : kSavedShare * equation19Seconds;
  p.saving = static_cast<double>(evaluations) * std::max(0.0, saved);
  p.pays = p.saving > p.training;
  std::ostringstream s;
  s << (p.pays ? "they pay" : "they would not pay") << ": " << evaluations << " evaluations still to integrate x ";
  if (operatorSeconds > 0.0)
    s << "(" << micro2(equation19Seconds) << " for Eq. 19 - " << micro2(operatorSeconds) << " for the operators)";
  else
    s << text::shortest(kSavedShare) << " of " << micro2(equation19Seconds) << " for Eq. 19";
  s << " = " << seconds2(p.saving) << (p.pays ? " saved against " : " to save against ") << seconds2(p.training)
    << " of training";
  if (predicted) s << " (predicted: " << text::shortest(kTrainingInEquation19) << " Eq. 19 evaluations)";
  p.why = s.str();
  return p;
}

std::string reductionKey(const core::Model& model, double target) {
  return operatorModelChecksum(model) + " target " + text::g17(target);
}

TargetOperators operatorsForTarget(const core::Model& model, const Eigen::MatrixXd& V, long evaluations,
                                   double equation19Seconds, int sharedRuns) {
  TargetOperators t;
  const std::string none = "Eq. 19 (no reduced operators trained: ";
  if (const std::string why = operatorsUnsupported(model); !why.empty()) {
    t.note = "Eq. 19 (no reduced operators: " + why + ")";
    return t;
  }
  if (V.cols() > kMostOperatorColumns) {
    t.note = none + std::to_string(V.cols()) + " columns, more than the " + std::to_string(kMostOperatorColumns) +
             " whose operators fit within the terms training allows on the measured models)";
    return t;
  }
  const std::string runs =
      sharedRuns > 1 ? " (this run and the " + std::to_string(sharedRuns - 1) + " more that may share the basis)" : "";
  const OperatorPayoff before = operatorsPay(evaluations, equation19Seconds);
  if (!before.pays) {
    t.note = evaluations == 0 ? none +
                                    "the chosen candidate's run is this run, nothing is left for them to save; "
                                    "they could pay from " +
                                    std::to_string(static_cast<long>(kTrainingInEquation19 / kSavedShare)) +
                                    " evaluations still to integrate on the basis)"
                              : none + before.why + runs + ")";
    return t;
  }
  const std::string reason = before.why + runs;
  const auto start = std::chrono::steady_clock::now();
  std::shared_ptr<const core::ReducedOperators> ops;
  std::string miss;
  try {
    ops = std::make_shared<const core::ReducedOperators>(trainOperators(model, V));
    // The check a run makes before it uses operators beside a basis file, and what reduce writes.
    miss = operatorsMissTheirTarget(*ops);
    if (miss.empty()) miss = operatorsMismatch(model, V, *ops);
  } catch (const std::exception& e) {
    miss = std::string("training failed: ") + e.what();
  }
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!miss.empty()) {
    t.note = "Eq. 19 (reduced operators trained where " + reason + ", not used: " + miss + ")";
    return t;
  }
  if (!operatorsCheaper(*ops)) {
    t.note = "Eq. 19 (reduced operators trained where " + reason + ", not used: one evaluation " +
             micro2(ops->operatorSeconds) + " against " + micro2(ops->equation19Seconds) + " for Eq. 19)";
    return t;
  }
  t.operators = std::move(ops);
  t.note = "reduced operators (trained where " + reason + "; trained and checked in " + seconds2(t.seconds) + ": " +
           describeOperators(*t.operators) + ")";
  return t;
}

}  // namespace flexmb::analysis
