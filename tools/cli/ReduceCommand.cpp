#include <boost/program_options.hpp>
#include <iostream>
#include <sstream>

#include "io/BasisFile.hpp"
#include "tools/analysis/Reduction.hpp"
#include "tools/cli/Commands.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

int runReduce(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  analysis::ReductionOptions o;
  std::string out, large;
  d.add_options()("method", po::value(&o.method)->default_value("modal"), "modal or svd-modal")(
      "modes", po::value(&o.modes)->default_value(3), "r: modes per configuration")(
      "normalise", po::value(&o.normalise)->default_value("mass"), "modal: mass (V^T M V = I, as MATLAB's eig) or unit columns")(
      "configs", po::value(&o.configs)->default_value(10), "svd-modal: equidistant configurations")(
      "weight", po::value(&o.weight)->default_value(0.0), "svd-modal: a in omega^-a")(
      "threshold", po::value(&o.threshold)->default_value(0.01), "svd-modal: keep singular values above this share")(
      "count", po::value(&o.count)->default_value(0), "svd-modal: keep exactly this many (overrides threshold)")(
      "node", po::value(&o.node), "svd-modal path: node label")("comp", po::value(&o.component)->default_value(1), "its component")(
      "from", po::value(&o.from), "path start value")("to", po::value(&o.to), "path end value")(
      "large", po::value(&large), "comma-separated q indices (0-based) kept with identity columns (default: hinges)")(
      "out", po::value(&out)->default_value("basis.csv"), "basis file");
  if (!parseCommand(args, d, m, "usage: flexmb reduce model.dat --method modal|svd-modal --modes r [...] --out basis.csv"))
    return 2;
  core::Model model;
  if (!loadModel(m, model)) return 2;
  if (!large.empty()) {
    std::vector<int> idx;
    std::stringstream ss(large);
    std::string tok;
    while (std::getline(ss, tok, ',')) {
      try {
        idx.push_back(std::stoi(tok));
      } catch (...) {
        std::cerr << "flexmb: --large: '" << tok << "' is not an index\n";
        return 2;
      }
    }
    o.large = idx;
  }
  try {
    const analysis::ReductionResult r = analysis::buildBasis(model, m.file, o);
    io::writeBasis(out, r.V, r.info);
    std::cout << "basis " << r.V.rows() << " x " << r.V.cols() << " (" << r.info.large.size()
              << " identity columns) written to " << out << "\n";
    if (r.scaledSingularValues.size()) {
      std::cout << "scaled singular values:";
      for (Eigen::Index i = 0; i < r.scaledSingularValues.size(); ++i) std::cout << " " << r.scaledSingularValues[i];
      std::cout << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace flexmb::cli
