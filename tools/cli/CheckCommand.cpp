#include <boost/program_options.hpp>
#include <iostream>

#include "core/KinematicCheck.hpp"
#include "io/DatReader.hpp"
#include "io/KeywordTable.hpp"
#include "tools/cli/Commands.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
po::options_description modelOptions(ModelOptions& m) {
  po::options_description d("model options");
  d.add_options()("dialect", po::value(&m.dialect), "force the dialect: 95 or 2013")(
      "elongation", po::value(&m.elongation), "PLBEAM elongation: plain (l - l0) or corrected (Eq. 3a)");
  return d;
}

bool parse(const std::vector<std::string>& args, po::options_description& d, ModelOptions& m,
           const char* usage) {
  d.add_options()("help,h", "this help")("model", po::value(&m.file), "model file");
  po::positional_options_description pos;
  pos.add("model", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(d).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n" << usage << "\n" << d;
    return false;
  }
  if (vm.count("help")) {
    std::cout << usage << "\n" << d;
    std::exit(0);
  }
  if (m.file.empty()) {
    std::cerr << "flexmb: no model file given\n" << usage << "\n" << d;
    return false;
  }
  return true;
}
}  // namespace

po::options_description commonModelOptions(ModelOptions& m) { return modelOptions(m); }
bool parseCommand(const std::vector<std::string>& args, po::options_description& d, ModelOptions& m,
                  const char* usage) {
  return parse(args, d, m, usage);
}

int runCheck(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = modelOptions(m);
  if (!parse(args, d, m, "usage: flexmb check model.dat [options]")) return 2;
  core::Model model;
  if (!loadModel(m, model)) return 2;
  std::cout << "model: " << model.sourceFile << " (" << io::dialectName(model.dialect) << ")\n";
  const core::KinematicReport r = core::checkKinematics(model);
  std::cout << core::formatReport(r);
  return r.wellPosed() ? 0 : 1;
}

int runKeywords(const std::vector<std::string>& args) {
  if (args.size() == 1 && args[0] == "--markdown") {
    io::printKeywordsMarkdown(std::cout);
    return 0;
  }
  if (!args.empty()) {
    std::cerr << "usage: flexmb keywords [--markdown]\n";
    return 2;
  }
  io::printKeywords(std::cout);
  return 0;
}

}  // namespace flexmb::cli
