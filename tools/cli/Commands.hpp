#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/program_options/options_description.hpp>
#include <optional>

#include "core/Model.hpp"
#include "io/DatReader.hpp"

namespace flexmb::cli {

int runCheck(const std::vector<std::string>& args);
int runSimulate(const std::vector<std::string>& args);
int runKeywords(const std::vector<std::string>& args);
int runModes(const std::vector<std::string>& args);
int runStatic(const std::vector<std::string>& args);
int runSweep(const std::vector<std::string>& args);
int runReduce(const std::vector<std::string>& args);
int runValidate(const std::vector<std::string>& args);
std::optional<Eigen::MatrixXd> readBasisFor(const std::string& path, const core::Model& model);

// Reads a model with the common options (--dialect, --elongation); prints errors, returns false.
struct ModelOptions {
  std::string file;
  std::string dialect;     // "", "95", "2013"
  std::string elongation;  // "", "plain", "corrected"
};
bool loadModel(const ModelOptions& o, core::Model& model);
// Every analysis stage of the file (SPACAR95 blocks), read with the same options.
bool loadStages(const ModelOptions& o, std::vector<io::AnalysisStage>& stages);

// The options every model command shares (--dialect, --elongation), and the parse of a command's
// options with the model file as positional argument (prints usage and errors; false on error).
boost::program_options::options_description commonModelOptions(ModelOptions& m);
bool parseCommand(const std::vector<std::string>& args, boost::program_options::options_description& d,
                  ModelOptions& m, const char* usage);

}  // namespace flexmb::cli
