#include <iostream>
#include <tuple>

#include "io/DatReader.hpp"
#include "tools/cli/Commands.hpp"

namespace flexmb::cli {

bool loadModel(const ModelOptions& o, core::Model& model) {
  io::ReadOptions ro;
  if (o.dialect == "95" || o.dialect == "spacar95") ro.dialect = core::Dialect::Spacar95;
  else if (o.dialect == "2013" || o.dialect == "spacar2013") ro.dialect = core::Dialect::Spacar2013;
  else if (!o.dialect.empty()) {
    std::cerr << "flexmb: --dialect must be 95 or 2013, not '" << o.dialect << "'\n";
    return false;
  }
  if (o.elongation == "plain") ro.elongation = core::ElongationDefinition::Plain;
  else if (o.elongation == "corrected") ro.elongation = core::ElongationDefinition::BendingCorrected;
  else if (!o.elongation.empty()) {
    std::cerr << "flexmb: --elongation must be plain or corrected, not '" << o.elongation << "'\n";
    return false;
  }
  try {
    model = io::readDatFile(o.file, ro);
    // USERSIG / USERINP name MATLAB functions: only the Octave/MATLAB gateway can call them.
    for (const auto& [name, line, key] : {std::tuple{model.userStressFunction, model.userStressLine, "USERSIG"},
                                          std::tuple{model.userInputFunction, model.userInputLine, "USERINP"}})
      if (!name.empty()) {
        std::cerr << o.file << ":" << line << ": " << key << " " << name
                  << ": a MATLAB user function runs only when the model is run through spacar() in Octave or "
                     "MATLAB (addpath the folder with spacar.mex, see README); from the command line give the "
                     "loads and inputs as time expressions (XFT, ESIGT, INPUTXT, INPUTET)\n";
        return false;
      }
    return true;
  } catch (const io::DatError& e) {
    std::cerr << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << o.file << ": " << e.what() << "\n";
  }
  return false;
}

}  // namespace flexmb::cli
