#pragma once
#include <string>
#include <vector>

#include "core/Model.hpp"

namespace flexmb::cli {

int runCheck(const std::vector<std::string>& args);
int runSimulate(const std::vector<std::string>& args);
int runKeywords(const std::vector<std::string>& args);

// Reads a model with the common options (--dialect, --elongation); prints errors, returns false.
struct ModelOptions {
  std::string file;
  std::string dialect;     // "", "95", "2013"
  std::string elongation;  // "", "plain", "corrected"
};
bool loadModel(const ModelOptions& o, core::Model& model);

}  // namespace flexmb::cli
