#include <iostream>

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
    for (const auto& note : model.notes) std::cerr << "flexmb: note: " << note << "\n";
    return true;
  } catch (const io::DatError& e) {
    std::cerr << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << o.file << ": " << e.what() << "\n";
  }
  return false;
}

bool loadStages(const ModelOptions& o, std::vector<io::AnalysisStage>& stages) {
  core::Model probe;
  if (!loadModel(o, probe)) return false;  // options, errors and notes, once
  io::ReadOptions ro;
  if (o.dialect == "95" || o.dialect == "spacar95") ro.dialect = core::Dialect::Spacar95;
  else if (o.dialect == "2013" || o.dialect == "spacar2013") ro.dialect = core::Dialect::Spacar2013;
  if (o.elongation == "plain") ro.elongation = core::ElongationDefinition::Plain;
  else if (o.elongation == "corrected") ro.elongation = core::ElongationDefinition::BendingCorrected;
  try {
    stages = io::readDatStages(o.file, ro);
    return true;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
  }
  return false;
}

}  // namespace flexmb::cli
