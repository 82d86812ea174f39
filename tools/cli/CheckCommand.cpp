#include <boost/program_options.hpp>
#include <iostream>

#include "core/GeometricTransferFunctions.hpp"
#include "core/KinematicCheck.hpp"
#include "core/ModelDiagnostics.hpp"
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
  if (!loadModel(m, model)) return kInputError;
  std::cout << "model: " << model.sourceFile << " (" << io::dialectName(model.dialect) << ")\n";
  const core::KinematicReport r = core::checkKinematics(model);
  std::cout << core::formatReport(r);
  bool ok = r.wellPosed();
  const core::ModelDiagnosis diag = core::diagnoseModel(model);
  if (!diag.mechanismDeformations.empty()) {
    std::cout << "mechanism degrees of freedom: " << diag.mechanismDeformations.size()
              << " dynamic (DYNE) deformation(s) without stiffness move freely:\n";
    for (const auto& s : diag.mechanismDeformations) std::cout << "  " << s << "\n";
    std::cout << "  intended for a free hinge; for a flexible element give ESTIFF (else `modes` shows zero or\n"
                 "  negative frequencies and `static` has no unique equilibrium)\n";
  }
  if (ok) {
    try {
      const std::string assembly = core::initialAssemblyProblem(model);
      if (!assembly.empty()) {
        std::cout << "initial configuration: " << assembly << "\n";
        ok = false;
      }
    } catch (const core::KinematicsError& e) {
      std::cout << "initial configuration: cannot be assembled: " << e.what() << "\n";
      ok = false;
    }
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
