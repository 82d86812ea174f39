#include "analysis/ModelSource.hpp"

#include <algorithm>

#include "analysis/InverseDynamics.hpp"
#include "analysis/ModelCheck.hpp"
#include "core/model/UserFunctions.hpp"
#include "io/formats/MeshRefinement.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
std::string listed(const std::vector<std::string>& v, size_t shown = 8) {
  std::string s;
  for (size_t i = 0; i < v.size() && i < shown; ++i) s += (i ? ", " : "") + v[i];
  if (v.size() > shown) s += " and " + std::to_string(v.size() - shown) + " more";
  return s;
}
}  // namespace

bool hasError(const Diagnostics& d) {
  return std::any_of(d.begin(), d.end(), [](const Diagnostic& x) { return x.kind == Diagnostic::Kind::Error; });
}

std::string withOptions(const Diagnostic& d, const std::function<std::string(const std::string&)>& spell) {
  std::vector<std::string> names;
  std::size_t from = 0;
  while (spell && from < d.options.size()) {
    const std::size_t comma = std::min(d.options.find(',', from), d.options.size());
    if (std::string s = spell(d.options.substr(from, comma - from)); !s.empty()) names.push_back(std::move(s));
    from = comma + 1;
  }
  if (names.empty()) return d.text;
  std::string s = d.text + (names.size() == 1 ? " (option " : " (options ");
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s + ")";
}

std::string firstError(const Diagnostics& d, const std::function<std::string(const std::string&)>& spell) {
  for (const Diagnostic& x : d)
    if (x.kind == Diagnostic::Kind::Error) {
      const std::string text = withOptions(x, spell);
      return x.where.empty() ? text : x.where + ": " + text;
    }
  return "";
}

std::shared_ptr<const std::vector<io::AnalysisStage>> readStages(const ModelSource& source) {
  if (source.stages) {
    if (source.read.refine == 1) return source.stages;
    auto refined = std::make_shared<std::vector<io::AnalysisStage>>(*source.stages);  // read unrefined
    io::refineStages(*refined, source.read);
    return refined;
  }
  if (source.text)
    return std::make_shared<const std::vector<io::AnalysisStage>>(
        io::readDatStagesString(*source.text, source.file, source.read));
  return std::make_shared<const std::vector<io::AnalysisStage>>(io::readDatStages(source.file, source.read));
}

bool isStaticFile(const std::vector<io::AnalysisStage>& stages) {
  return !stages.empty() && !stages.back().model.settings.timestepGiven;
}

Diagnostics checkModelFor(const core::Model& model, const std::string& file, const ModelNeeds& needs) {
  using K = Diagnostic::Kind;
  Diagnostics d;
  for (const auto& note : model.notes) d.push_back({K::Note, "", note, "", ""});
  for (const auto& w : model.warnings) d.push_back({K::Warning, file, w, "", ""});
  const core::ModelDiagnosis diagnosis = diagnose(model);
  if (!diagnosis.overflow.empty()) {
    d.push_back({K::Error, file,
                 "values too large to compute with (above " + text::shortest(core::kOverflowLimit) +
                     "; products of them overflow): " + listed(diagnosis.overflow) +
                     ". Check the units and the exponents.",
                 "", ""});
    return d;
  }
  if (!diagnosis.mechanismDeformations.empty())
    d.push_back({K::Note, file,
                 std::to_string(diagnosis.mechanismDeformations.size()) +
                     " dynamic deformation(s) without stiffness, i.e. mechanism degrees of freedom: " +
                     listed(diagnosis.mechanismDeformations),
                 "", ""});
  if (!needs.degreesOfFreedom) return d;
  if (model.numDofs() == 0 && !(needs.allowDriven && isDrivenRigidMechanism(model))) {
    d.push_back(
        {K::Error, file,
         std::string("the model has no degrees of freedom (no DYNE deformation and no DYNX coordinate)") +
             (needs.allowDriven ? " and no input that moves in time: nothing moves, so there is nothing to simulate"
                                : ": there is no eigenfrequency and no elastic equilibrium to find") +
             ". Make the deformations that carry the motion DYNE (with ESTIFF), or drive the mechanism with "
             "INPUTX / INPUTE values that change in time (simulate then runs its kinematics and inverse "
             "dynamics)",
         "check", ""});
    return d;
  }
  AssemblyCheck a;
  try {
    a = checkAssembly(model, needs.mass);
  } catch (const core::UserFunctionError&) {
    return d;  // a USERINP that fails at t0: the run stops there with the function's own message
  }
  if (!a.error.empty()) {
    d.push_back({K::Error, file, "the initial configuration cannot be assembled: " + a.error, "check", ""});
  } else if (!a.problem.empty()) {
    d.push_back({K::Error, file, a.problem, "", ""});
  } else if (!a.massless.empty()) {
    d.push_back({K::Error, file,
                 "no mass on " + std::to_string(a.massless.size()) + " of " + std::to_string(model.numDofs()) +
                     " degrees of freedom: " + listed(a.massless) +
                     ". Dynamics and eigenfrequencies need mass on every one: give EM (mass per length) of the "
                     "elements or XM (lumped masses) at the nodes that move.",
                 "", ""});
  }
  return d;
}

}  // namespace flexmb::analysis
