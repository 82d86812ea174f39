#include <boost/program_options.hpp>
#include <iostream>

#include "analysis/ModelCheck.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/KeywordTable.hpp"
#include "tools/cli/Commands.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

int runCheck(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  if (auto rc = parseCommand(args, d, m, "usage: flexmb check model.dat [options]")) return *rc;
  m.quiet = true;  // the notes and warnings are part of the report below
  core::Model model;
  if (!loadModel(m, model, true)) return kInputError;
  std::cout << "model: " << model.sourceFile << " (" << io::dialectName(model.dialect) << ")\n";
  for (const auto& [name, line, key, what] :
       {std::tuple{model.userStressFunction, model.userStressLine, "USERSIG", "loads and stresses"},
        std::tuple{model.userInputFunction, model.userInputLine, "USERINP", "input motion"}})
    if (!name.empty())
      std::cout << "note: " << model.sourceFile << ":" << line << ": " << key << " " << name << " (" << what
                << "): a MATLAB function that runs only when the model is run through spacar() in Octave or "
                   "MATLAB; this check does not call it"
                << (std::string(key) == "USERINP" ? " (the input coordinates are at their X values)" : "") << "\n";
  const analysis::ModelCheck c = analysis::checkModel(model);
  if (!c.kinematicsError.empty()) {
    std::cout << "kinematic check failed: " << c.kinematicsError << "\n";
    return kInputError;
  }
  std::cout << c.kinematicsText();
  bool ok = c.kinematics.wellPosed();
  // The degrees of freedom in q's order (DYNX, then DYNE, each in file order): the numbers that
  // reduce --large and a basis file's rows use.
  if (model.numDofs() > 0) {
    std::cout << "degrees of freedom in order (q1..q" << model.numDofs() << "; reduce --large uses these numbers):\n";
    for (int i = 0; i < model.numDofs(); ++i) {
      const auto& dof = model.dofs[i];
      std::cout << "  q" << i + 1 << " "
                << (dof.isDeformation ? model.deformationName(dof.index) : model.coordName(dof.index)) << "\n";
    }
  }
  // Every note and warning of the reader: extras that were ignored, and what probably is a mistake.
  if (!model.notes.empty()) {
    std::cout << "notes (harmless, ignored or not used):\n";
    for (const auto& n : model.notes) std::cout << "  " << n << "\n";
  }
  if (!model.warnings.empty()) {
    std::cout << "warnings (legal, but they change the model; check them):\n";
    for (const auto& w : model.warnings) std::cout << "  " << w << "\n";
  }
  if (!c.diagnosis.mechanismDeformations.empty()) {
    std::cout << "mechanism degrees of freedom: " << c.diagnosis.mechanismDeformations.size()
              << " dynamic (DYNE) deformation(s) without stiffness move freely:\n";
    for (const auto& s : c.diagnosis.mechanismDeformations) std::cout << "  " << s << "\n";
    std::cout << "  intended for a free hinge; for a flexible element give ESTIFF (else `modes` shows zero or\n"
                 "  negative frequencies and `static` has no unique equilibrium)\n";
  }
  if (ok && !c.assembly.problem.empty()) {
    std::cout << "initial configuration: " << c.assembly.problem << "\n";
    ok = false;
  }
  if (ok && !c.assembly.error.empty()) {
    std::cout << "initial configuration: cannot be assembled: " << c.assembly.error << "\n";
    ok = false;
  }
  if (ok && !model.warnings.empty())
    std::cout << "the model is well posed, with " << model.warnings.size() << " warning"
              << (model.warnings.size() == 1 ? "" : "s") << " above\n";
  return ok ? kOk : kInputError;
}

int runKeywords(const std::vector<std::string>& args) {
  ModelOptions m;
  bool markdown = false;
  po::options_description d("options");
  d.add_options()("markdown", po::bool_switch(&markdown), "the reference as Markdown (the text of io/dat-language.md)");
  if (auto rc = parseCommand(args, d, m, "usage: flexmb keywords [--markdown]", false)) return *rc;
  if (markdown) {
    io::printKeywordsMarkdown(std::cout);
    return kOk;
  }
  io::printKeywords(std::cout);
  return kOk;
}

}  // namespace flexmb::cli
