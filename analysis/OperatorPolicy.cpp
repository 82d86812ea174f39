#include "analysis/OperatorPolicy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "analysis/OperatorDynamics.hpp"
#include "analysis/OperatorLoads.hpp"
#include "analysis/OperatorTraining.hpp"
#include "io/formats/OperatorFile.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

std::string operatorModelChecksum(const core::Model& model) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits
  auto bytes = [&](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  auto num = [&](double v) { bytes(&v, sizeof v); };
  auto integer = [&](long v) { bytes(&v, sizeof v); };
  auto vec = [&](const Eigen::VectorXd& v) {
    integer(v.size());
    for (Eigen::Index i = 0; i < v.size(); ++i) num(v[i]);
  };
  integer(model.nx);
  integer(model.ne);
  integer(model.spatial);
  vec(model.x0);
  for (core::Role r : model.xRole) integer(static_cast<long>(r));
  for (core::Role r : model.eRole) integer(static_cast<long>(r));
  for (const auto& d : model.dofs) integer(d.isDeformation ? -1 - d.index : d.index);
  for (const core::ElementEntry& E : model.elements) {
    bytes(E.type->keyword.data(), E.type->keyword.size());
    for (int c : E.coords) integer(c);
    integer(E.firstDef);
    integer(E.hasStiffness + 2 * E.hasDamping);
    for (const core::DefMat* A : {&E.S, &E.Sd})
      for (Eigen::Index i = 0; i < A->size(); ++i) num(A->data()[i]);
    const core::ElementInertia& J = E.inertia;
    for (double v : {J.rhoA, J.rhoI, J.jxx, J.jyy, J.jzz, J.jyz, J.jxy, J.jxz, J.jw}) num(v);
  }
  for (const core::LumpedMass& l : model.lumpedMasses) {
    integer(l.coord);
    num(l.value);
  }
  vec(model.f0);
  vec(model.sigma0);
  integer(model.hasGravity);
  for (double g : model.gravity) num(g);
  for (const auto* list : {&model.timeForces, &model.timeStresses, &model.references}) {
    integer(-1);
    for (const core::TimeLoad& l : *list) integer(l.index);
  }
  integer(static_cast<long>(model.moments.size()));
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

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
  // The model they were trained on, by its checksum (the data the fields depend on).
  if (ops.modelChecksum.empty())
    return "they carry no model checksum (made by an older flexmb): run flexmb reduce again";
  if (const std::string now = operatorModelChecksum(model); now != ops.modelChecksum) {
    s << "the model changed since they were made (its checksum is " << now << ", theirs " << ops.modelChecksum
      << "): run flexmb reduce again";
    return s.str();
  }
  // The fit as training measured it, at the same held-out configurations: on the same model it is at
  // most what they declare (training stores the larger), up to rounding of another build; more means
  // something the checksum does not cover (element options such as --elongation, an edited file).
  const OperatorFit fit = operatorFitAtHeldOut(model, V, ops);
  if (fit.configurations == 0) return "they carry no held-out configurations to check (made by an older flexmb)";
  if (fit.unsolved) {
    s << "the kinematics do not solve at " << fit.unsolved << " of their " << fit.configurations
      << " held-out configurations";
    return s.str();
  }
  auto beyond = [](double measured, double declared) { return measured > 1.01 * declared + 1e-10; };
  if (beyond(fit.force, ops.forceError) || beyond(fit.mass, ops.massError)) {
    s << "at their " << fit.configurations << " held-out configurations they fit Eq. 19 to "
      << text::significant(fit.force, 2) << " (force) / " << text::significant(fit.mass, 2)
      << " (mass) of the largest in their range, where training measured " << text::significant(ops.forceError, 2)
      << " / " << text::significant(ops.massError, 2);
    return s.str();
  }
  return "";
}

std::string operatorsMissTheirTarget(const ReducedOperators& ops) {
  const double force = kOperatorMostShare / kOperatorToleranceShare * ops.tolerance;
  const double mass = kOperatorInertiaShare * force;
  if (ops.forceError <= force && ops.massError <= mass) return "";
  std::ostringstream s;
  auto g2 = [](double v) { return text::significant(v, 2); };
  s << "their fit reaches " << g2(ops.forceError) << " (force) / " << g2(ops.massError)
    << " (mass) of the largest in their range after " << ops.terms() << " terms, where a run may take at most "
    << g2(force) << " / " << g2(mass) << " (a tenth of the basis' reduction error; target " << g2(ops.tolerance)
    << "): simulate --basis runs Eq. 19 on this basis";
  return s.str();
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
  if (ops.forceError > ops.tolerance || ops.massError > kOperatorInertiaShare * ops.tolerance)
    t << " (missed, within the tenth of the reduction error they may add: "
      << g2(kOperatorMostShare / kOperatorToleranceShare * ops.tolerance) << ")";
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
        c.note = "Eq. 19 (" + path + " does not fit " + modelFile + " with " + basisFile + ": " + why +
                 "; the run uses the full kinematics through the basis instead)";
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
