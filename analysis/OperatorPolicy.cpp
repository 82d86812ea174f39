#include "analysis/OperatorPolicy.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "analysis/OperatorDynamics.hpp"
#include "analysis/OperatorLoads.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "io/formats/OperatorFile.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

double basisChecksum(const Eigen::MatrixXd& V) {
  double s = 0.0;
  for (int j = 0; j < V.cols(); ++j)
    for (int i = 0; i < V.rows(); ++i) s += V(i, j) * (1.0 + 0.37 * i + 0.61 * j * j);
  return s;
}

std::string operatorsMismatch(const core::Model& model, const Eigen::MatrixXd& V, const ReducedOperators& ops) {
  std::ostringstream s;
  if (ops.dofs != model.numDofs()) {
    s << "they were made for a model with " << ops.dofs << " degrees of freedom, this one has " << model.numDofs();
    return s.str();
  }
  if (ops.size() != V.cols()) {
    s << "they were made for a basis of " << ops.size() << " columns, this one has " << V.cols();
    return s.str();
  }
  const double sum = basisChecksum(V);
  if (std::abs(sum - ops.basisChecksum) > 1e-12 * (std::abs(sum) + V.cwiseAbs().sum()))
    return "they were made for another basis of the same size (its entries differ): run flexmb reduce again";
  if (const std::string why = operatorsUnsupported(model); !why.empty()) return why;
  const std::vector<OperatorLoad> mine = timeLoads(model);
  auto same = [](const OperatorLoad& a, const OperatorLoad& b) { return a.kind == b.kind && a.index == b.index; };
  for (const OperatorLoad& l : ops.loads)
    if (std::none_of(mine.begin(), mine.end(), [&](const OperatorLoad& k) { return same(k, l); })) {
      s << "they have a time-dependent " << operatorLoadKeyword(l.kind) << " load (index " << l.index + 1
        << ") the model does not have";
      return s.str();
    }
  for (const OperatorLoad& l : mine)
    if (std::none_of(ops.loads.begin(), ops.loads.end(), [&](const OperatorLoad& k) { return same(k, l); })) {
      s << "the model has a time-dependent " << operatorLoadKeyword(l.kind) << " load (index " << l.index + 1
        << ") they do not have";
      return s.str();
    }
  for (const core::OperatorOutput& q : ops.outputs)
    if (q.index >= (q.kind == core::OperatorOutput::Kind::Deformation ? model.ne : model.nx)) {
      s << "they track " << core::operatorOutputKeyword(q.kind) << " index " << q.index + 1 << ", beyond the model's "
        << (q.kind == core::OperatorOutput::Kind::Deformation ? model.ne : model.nx);
      return s.str();
    }
  // The physics: accelerations at the range's centre, at rest and at t0, against Eq. 19's.
  const int m = ops.size();
  Eigen::VectorXd y(2 * m), a(2 * m), b(2 * m);
  y << ops.centre + ops.rotation * (0.5 * (ops.lower + ops.upper)), Eigen::VectorXd::Zero(m);
  OperatorDynamics od(model, ops);
  core::EquationsOfMotion eom(model, V);
  try {
    eom.rhs(model.settings.t0, y, b);
  } catch (const core::KinematicsError& e) {
    return std::string("the kinematics fail at the centre of their range: ") + e.what();
  }
  if (!od.rhs(model.settings.t0, y, a)) return "their own range does not hold its centre";
  const double diff = (a.tail(m) - b.tail(m)).norm() / std::max(b.tail(m).norm(), 1e-300);
  const double allowed = std::max(20.0 * std::max(ops.forceError, ops.massError), 1e-6);
  if (b.tail(m).norm() > 0.0 && diff > allowed) {
    s << "at the centre of their range their accelerations differ from Eq. 19's by " << text::shortest(diff)
      << " (relative; their fit allows " << text::shortest(allowed)
      << "): the model's mass, stiffness or loads changed since they were made";
    return s.str();
  }
  return "";
}

std::string describeTrackedOutputs(const core::TrackedOutputs& tracked, const ReducedOperators& ops) {
  std::ostringstream s;
  s << tracked.quantities.size() << " quantities at " << tracked.fromOperators + tracked.fromKinematics
    << " output times: " << tracked.fromOperators << " from the operators' output fields (fit "
    << text::significant(ops.outputError, 2) << " of each one's range at held-out configurations), "
    << tracked.fromKinematics << " from the full kinematics (outside their range)";
  return s.str();
}

std::string describeOperators(const ReducedOperators& ops) {
  auto g2 = [](double v) { return text::significant(v, 2); };
  std::ostringstream t;
  t << ops.terms() << " terms, fit " << g2(ops.forceError) << " (force) / " << g2(ops.massError)
    << " (mass) of their largest in the range, target " << g2(ops.tolerance);
  if (!ops.outputs.empty())
    t << "; " << ops.outputs.size() << " tracked outputs on " << ops.outputFields.rows() << " terms, fit "
      << g2(ops.outputError) << " of each one's range";
  t << "; one evaluation " << g2(ops.operatorSeconds * 1e6) << " us against " << g2(ops.equation19Seconds * 1e6)
    << " us for Eq. 19; trained in " << g2(ops.trainingSeconds) << " s (" << ops.trainingSamples << " + "
    << ops.validationSamples << " configurations); range: " << ops.range;
  return t.str();
}

std::string describeOperatorUse(const core::OperatorUse& use, const ReducedOperators& ops) {
  std::ostringstream s;
  if (!use.notUsed.empty()) return "Eq. 19 (" + use.notUsed + ")";
  const std::string fit = text::significant(std::max(ops.forceError, ops.massError), 2);
  s << "reduced operators for " << use.evaluations << " evaluations (" << ops.terms() << " terms, fit " << fit
    << " of the largest force or mass in their range)";
  if (use.fallbacks)
    s << "; Eq. 19 for " << use.fallbacks
      << " evaluations outside their range, the first at t = " << text::shortest(use.firstFallback) << " s ("
      << use.where << ")";
  else
    s << "; the run stayed in their range";
  return s.str();
}

std::string operatorsUnsupported(const core::Model& model) {
  if (!model.inputX.empty() || !model.inputE.empty())
    return "the model has kinematic inputs (INPUTX/INPUTE): its kinematics depend on time";
  if (model.userFunctions) return "the model has user functions (USERSIG/USERINP)";
  if (!model.moments.empty()) return "the model has moments on spatial orientation nodes (not a potential)";
  return "";
}

OperatorChoice chooseOperators(const core::Model& model, const std::string& modelFile, const Eigen::MatrixXd& V,
                               const std::string& basisFile, bool fullKinematics) {
  OperatorChoice c;
  const std::string path = io::operatorPathFor(basisFile);
  if (fullKinematics) {
    c.note = "Eq. 19 (--full-kinematics)";
  } else if (const std::string unsupported = operatorsUnsupported(model); !unsupported.empty()) {
    c.note = "Eq. 19 (no reduced operators: " + unsupported + ")";
  } else if (!std::filesystem::exists(path)) {
    c.note = "Eq. 19 (no reduced operators beside the basis: flexmb reduce writes " + path + ")";
  } else {
    try {
      auto ops = std::make_shared<const ReducedOperators>(io::readOperators(path));
      if (const std::string why = operatorsMismatch(model, V, *ops); !why.empty())
        c.refusal = path + " does not fit " + modelFile + " with " + basisFile + ": " + why +
                    " (flexmb reduce builds them anew; --full-kinematics runs without them)";
      else if (!operatorsCheaper(*ops))
        c.note = "Eq. 19 (the reduced operators in " + path + " cost " +
                 text::shortest(std::round(ops->operatorSeconds * 1e8) / 100) + " us per evaluation, Eq. 19 " +
                 text::shortest(std::round(ops->equation19Seconds * 1e8) / 100) + " us: too many terms for this basis)";
      else
        c.operators = std::move(ops);
    } catch (const std::exception& e) {
      c.refusal = e.what();
    }
  }
  return c;
}

}  // namespace flexmb::analysis
