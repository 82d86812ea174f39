#pragma once
// Reduced operators for a basis chosen for a target (`simulate --basis auto`, issue 49 item 3):
// whether they pay for the runs still to be integrated on it, their training and the check a run
// makes before it uses them (operatorsMismatch, as for a basis file), and their reuse by later runs
// whose model they fit (the variants of a study). Measurements and the rule's constants:
// docs/analyses/reduce.md and tools/bench/README.md (issue 49 item 3).
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>

#include "core/model/Model.hpp"
#include "core/model/ReducedOperatorData.hpp"

namespace flexmb::analysis {

// The rule's two figures, in Eq. 19 evaluations of the run (its integration time over its
// evaluations, galpha's Jacobians included), measured on the scan's bases for the guidance with 5, 20
// and 40 elements per leaf and the manipulator (1 to 4 reduced columns; tools/bench/README.md):
// training cost 3,800 to 9,900 of them (the least taken), and an evaluation on the operators saved
// 0.30 to 0.73 of one (the least taken: the integrator's own work stays). Break-even: 12,700
// evaluations still to integrate, about 17 runs of the guidance's 750.
constexpr double kTrainingInEquation19 = 3800.0;
constexpr double kSavedShare = 0.3;
// Operators for more columns are not trained: on the 5-element guidance 6, 8 and 10 modal vectors
// missed their fit target after the 300 terms training allows (5 needed all 300 and saved 20% of an
// Eq. 19 evaluation), so their training would be spent for Eq. 19.
constexpr int kMostOperatorColumns = 5;

struct OperatorPayoff {
  bool pays = false;
  double saving = 0.0;    // seconds: evaluations x (Eq. 19 - operators) per evaluation
  double training = 0.0;  // seconds: measured, or predicted
  std::string why;        // the comparison in words, with its figures
};

// The rule: operators pay when what they save on the evaluations still to be integrated on the
// basis exceeds their training. operatorSeconds 0 (before training): the saving predicted as
// kSavedShare of Eq. 19's cost; trainingSeconds NaN: predicted as kTrainingInEquation19 Eq. 19
// evaluations.
OperatorPayoff operatorsPay(long evaluations, double equation19Seconds, double operatorSeconds = 0.0,
                            double trainingSeconds = std::numeric_limits<double>::quiet_NaN());

// A basis chosen for a target with its operators, kept for the runs on models that share them: the
// same operator checksum (operatorModelChecksum: what the fields depend on) and target.
struct SharedReduction {
  std::string key;  // reductionKey of the model it was chosen on ("": none yet)
  Eigen::MatrixXd V;
  std::shared_ptr<const core::ReducedOperators> operators;  // null: Eq. 19 (note says why)
  std::string note;                                         // how they were made
  int runs = 1;  // the runs that may use it (a study's variants): what the rule weighs
};
std::string reductionKey(const core::Model& model, double target);

struct TargetOperators {
  std::shared_ptr<const core::ReducedOperators> operators;  // null: Eq. 19
  std::string note;      // the run's "reduced dynamics": "Eq. 19 (why)" or why the operators are used
  double seconds = 0.0;  // training and its check
};

// The operators for basis V after the target scan: `evaluations` are the right-hand sides still to be
// integrated on V by this run and the runs that share it (0 where the chosen candidate's run is the
// run and nothing is shared), `equation19Seconds` one evaluation of the scan's run. Trained where V
// has at most kMostOperatorColumns columns and operatorsPay says so; used where they pass the run's
// own check (operatorsMismatch, operatorsMissTheirTarget) and cost less than Eq. 19 per evaluation.
// `sharedRuns` (> 1: a study's variants) only words the note. Never throws: a failed training is
// Eq. 19 with the reason.
TargetOperators operatorsForTarget(const core::Model& model, const Eigen::MatrixXd& V, long evaluations,
                                   double equation19Seconds, int sharedRuns = 1);

}  // namespace flexmb::analysis
