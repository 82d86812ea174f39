#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <optional>

#include "core/Model.hpp"

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

}  // namespace flexmb::cli
