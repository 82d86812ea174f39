#include <boost/program_options.hpp>
#include <iostream>

#include "analysis/ModelCheck.hpp"
#include "io/DatReader.hpp"
#include "io/KeywordTable.hpp"
#include "tools/cli/Commands.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

int runCheck(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  if (auto rc = parseCommand(args, d, m, "usage: flexmb check model.dat [options]")) return *rc;
  m.quiet = true;  // the notes are part of the report below
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
