#include <algorithm>
#include <boost/program_options.hpp>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <tuple>

#include "analysis/InverseDynamics.hpp"
#include "analysis/ModelCheck.hpp"
#include "analysis/ModelJob.hpp"
#include "analysis/ModelSource.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/KeywordTable.hpp"
#include "io/formats/OutputFile.hpp"
#include "text/NumberText.hpp"
#include "tools/cli/Commands.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};

extern "C" void onInterrupt(int sig) {
  if (g_interrupted.load()) std::_Exit(sig == SIGTERM ? kTerminated : kInterrupted);  // the second: at once
  g_signal.store(sig);  // before the flag: whoever sees the flag sees the signal
  g_interrupted.store(true);
}

std::string shortNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A value the option parser rejected that is a number with a decimal comma ("1,5"): say so, as the
// .dat reader does (boost names the value as "('1,5')" in its message).
std::string decimalCommaHint(const std::vector<std::string>& args, const std::string& message) {
  for (const auto& arg : args) {
    const auto eq = arg.rfind("--", 0) == 0 ? arg.find('=') : std::string::npos;
    std::string value = eq == std::string::npos ? arg : arg.substr(eq + 1);
    const auto comma = value.find(',');
    if (comma == std::string::npos || value.find(',', comma + 1) != std::string::npos) continue;
    if (message.find("('" + value + "')") == std::string::npos) continue;
    value[comma] = '.';
    char* end = nullptr;
    std::strtod(value.c_str(), &end);
    if (!value.empty() && end == value.c_str() + value.size())
      return " (a decimal comma? write " + value + ": the decimal separator is '.', as in .dat files)";
  }
  return "";
}

}  // namespace

void installInterruptHandler() {
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}
const std::atomic<bool>* interruptFlag() { return &g_interrupted; }
const std::atomic<int>* interruptSignal() { return &g_signal; }
int interruptedExitCode() { return g_signal.load() == SIGTERM ? kTerminated : kInterrupted; }

std::function<void(const double&)> positive(const char* option) {
  return [option](const double& v) {
    if (!(std::isfinite(v) && v > 0))
      throw po::error(std::string("--") + option + " must be a positive finite number, not " + shortNumber(v));
  };
}
std::function<void(const double&)> finite(const char* option) {
  return [option](const double& v) {
    if (!std::isfinite(v)) throw po::error(std::string("--") + option + " must be a finite number");
  };
}
std::function<void(const int&)> atLeast(const char* option, int minimum) {
  return [option, minimum](const int& v) {
    if (v < minimum)
      throw po::error(std::string("--") + option + " must be at least " + std::to_string(minimum) + ", not " +
                      std::to_string(v));
  };
}

std::vector<double> numberList(const std::string& text, const char* option) {
  std::vector<double> out;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = text.find(',', from);
    const std::string t = text.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    double x = 0.0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), x);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(x))
      throw po::error(std::string("--") + option + " must be finite numbers separated by commas, not '" + text + "'");
    out.push_back(x);
    if (comma == std::string::npos) return out;
    from = comma + 1;
  }
}

void addDampingOptions(po::options_description& d, analysis::DampingOptions& damping) {
  d.add_options()("damping-ratio", po::value<std::string>()->notifier([&damping](const std::string& v) {
    damping.ratios = numberList(v, "damping-ratio");
  }),
                  "modal relative damping Z added to the model's EDAMP: one ratio for every mode, or Z1,Z2,... "
                  "for modes 1, 2, ... (the last for the higher ones)")(
      "rayleigh", po::value<std::string>()->notifier([&damping](const std::string& v) {
        const std::vector<double> ab = numberList(v, "rayleigh");
        if (ab.size() != 2) throw po::error("--rayleigh must be ALPHA,BETA, not '" + v + "'");
        damping.alpha = ab[0], damping.beta = ab[1];
      }),
      "Rayleigh damping alpha M + beta K added (ALPHA,BETA in 1/s and s; beta K is EDAMP = beta * ESTIFF)");
}

namespace {
// A std::function, not a lambda, for the notifier (GCC 12 warns on Boost's copy of a lambda on double).
std::function<void(const double&)> accuracyInRange() {
  return [](const double& v) {
    if (!(v >= analysis::kSmallestAccuracy && v < 1.0))
      throw po::error("--accuracy must be at least " + text::shortest(analysis::kSmallestAccuracy) +
                      " (finer than double precision integrates) and below 1, not " + text::shortest(v));
  };
}
}  // namespace

void addAccuracyOptions(po::options_description& d, AccuracyArgs& a) {
  d.add_options()("error-estimate", po::bool_switch(&a.estimate),
                  "also estimate the discretization error against the converged model: the analysis runs again "
                  "with every flexible beam split in 2 and 4 (Richardson's extrapolation with the observed order; "
                  "the results written are the model's own mesh)")(
      "accuracy", po::value(&a.eps)->notifier(accuracyInRange()),
      "EPS: refine the mesh (and, for simulate, tighten the integrator's tolerance to EPS / 20) until the total "
      "error estimate against the converged model is at most EPS (positions relative to the motion; frequencies "
      "relative); the results written are the finest mesh's, at the original nodes")(
      "max-seconds", po::value(&a.maxSeconds)->notifier(positive("max-seconds")),
      "with --accuracy: start no mesh predicted to end after this many seconds in all (default 300)");
}

std::optional<analysis::AccuracyRequest> accuracyRequest(const AccuracyArgs& a, bool quiet, const std::string& clash) {
  if (a.estimate && a.eps > 0.0) {
    std::cerr << "flexmb: --accuracy estimates the error itself: give --accuracy or --error-estimate, not both\n";
    return std::nullopt;
  }
  if (!clash.empty()) {
    std::cerr << "flexmb: --accuracy and --error-estimate " << clash << "\n";
    return std::nullopt;
  }
  analysis::AccuracyRequest r;
  if (a.eps > 0.0) r.eps = a.eps;
  r.maxSeconds = a.maxSeconds;
  r.progress = [quiet](const analysis::Diagnostic& d) { printDiagnostics({d}, quiet); };
  return r;
}

void reportAccuracy(io::OutputSet& files, const analysis::ErrorBudget& budget, const analysis::Diagnostics& ladder,
                    bool quiet) {
  for (const auto& [key, value] : budget.settings) files.setting(key, value);
  for (const analysis::Diagnostic& d : ladder)
    if (d.kind != analysis::Diagnostic::Kind::Note) printDiagnostics({d}, quiet);  // the notes were said as they came
}

io::View viewNamed(const std::string& name) {
  if (name == "xy") return io::View::XY;
  if (name == "xz") return io::View::XZ;
  if (name == "yz") return io::View::YZ;
  if (name == "iso") return io::View::Isometric;
  return io::View::Auto;
}

void addViewOption(po::options_description& d, std::string& viewName, const char* autoMeaning) {
  d.add_options()("view", po::value(&viewName)->notifier([](const std::string& v) {
    if (v != "auto" && v != "xy" && v != "xz" && v != "yz" && v != "iso")
      throw po::error("--view must be auto, xy, xz, yz or iso, not '" + v + "'");
  }),
                  (std::string("projection: auto (default: ") + autoMeaning + "), xy, xz, yz or iso").c_str());
}

po::options_description commonModelOptions(ModelOptions& m) {
  po::options_description d("options");
  d.add_options()("dialect", po::value(&m.dialect), "force the dialect: 95 or 2013")(
      "elongation", po::value(&m.elongation), "PLBEAM elongation: plain (l - l0) or corrected (Eq. 3a)")(
      "refine", po::value(&m.refine)->notifier([](int n) {
        if (n < 1) throw po::error("--refine must be a whole number >= 1, not " + std::to_string(n));
      }),
      "split every flexible beam (PLBEAM, BEAM, BEAMW) in N elements; the original nodes keep their labels, and "
      "the result files hold them alone")(
      "refined-results", po::bool_switch(&m.refinedResults),
      "with --refine: the result files hold every node and element of the refined model")(
      "quiet,q", po::bool_switch(&m.quiet), "no progress lines and notes on stderr");
  return d;
}

namespace {
// "; did you mean --view?" for a mistyped option (within two edits of one of the command's own),
// as a mistyped command and .dat keyword get.
std::string nearestOptionHint(const po::options_description& d, const std::string& given) {
  std::string name = given;
  while (!name.empty() && name.front() == '-') name.erase(name.begin());
  if (const auto eq = name.find('='); eq != std::string::npos) name.resize(eq);
  std::string nearest;
  int best = 3;
  for (const auto& option : d.options()) {
    const std::string& candidate = option->long_name();
    if (candidate.empty()) continue;
    if (const int dist = io::editDistance(name, candidate); dist < best) best = dist, nearest = candidate;
  }
  return nearest.empty() ? std::string() : "; did you mean --" + nearest + "?";
}
}  // namespace

std::optional<int> parseCommand(const std::vector<std::string>& args, po::options_description& d, ModelOptions& m,
                                const char* usage, bool needsModel) {
  d.add_options()("help,h", "this help");
  po::options_description hidden;
  hidden.add_options()("model", po::value(&m.file), "model file");
  po::options_description all;
  all.add(d).add(hidden);
  po::positional_options_description pos;
  if (needsModel) pos.add("model", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
    if (vm.count("help")) {  // before notify: --help needs no required option
      std::cout << usage << "\n" << d;
      return kOk;
    }
    po::notify(vm);
  } catch (const po::unknown_option& e) {
    std::cerr << "flexmb: " << e.what() << nearestOptionHint(d, e.get_option_name()) << "\n"
              << usage << "\n(flexmb <command> --help lists the options)\n";
    return kUsageError;
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << decimalCommaHint(args, e.what()) << "\n"
              << usage << "\n(flexmb <command> --help lists the options)\n";
    return kUsageError;
  }
  if (needsModel && m.file.empty()) {
    std::cerr << "flexmb: no model file given\n" << usage << "\n";
    return kUsageError;
  }
  if (m.dialect != "" && m.dialect != "95" && m.dialect != "spacar95" && m.dialect != "2013" &&
      m.dialect != "spacar2013") {
    std::cerr << "flexmb: --dialect must be 95 or 2013, not '" << m.dialect << "'\n";
    return kUsageError;
  }
  if (m.elongation != "" && m.elongation != "plain" && m.elongation != "corrected") {
    std::cerr << "flexmb: --elongation must be plain or corrected, not '" << m.elongation << "'\n";
    return kUsageError;
  }
  return std::nullopt;
}

namespace {

io::ReadOptions readOptions(const ModelOptions& o) {
  io::ReadOptions ro;
  if (o.dialect == "95" || o.dialect == "spacar95")
    ro.dialect = core::Dialect::Spacar95;
  else if (o.dialect == "2013" || o.dialect == "spacar2013")
    ro.dialect = core::Dialect::Spacar2013;
  if (o.elongation == "plain")
    ro.elongation = core::ElongationDefinition::Plain;
  else if (o.elongation == "corrected")
    ro.elongation = core::ElongationDefinition::BendingCorrected;
  ro.refine = o.refine;
  ro.refinedResults = o.refinedResults;
  return ro;
}

}  // namespace

namespace {
// The text of the one file a command read ahead (--mode 3 reads it to choose the analysis): the
// analysis parses it again instead of opening the file a second time.
std::pair<std::string, std::shared_ptr<const std::string>> g_readAhead;
}  // namespace

std::shared_ptr<const std::string> readAhead(const std::string& file) {
  if (g_readAhead.first != file || !g_readAhead.second)
    g_readAhead = {file, std::make_shared<const std::string>(io::readDatText(file))};
  return g_readAhead.second;
}

analysis::ModelSource modelSource(const ModelOptions& o) {
  analysis::ModelSource s{o.file, readOptions(o), nullptr, nullptr};
  if (g_readAhead.first == o.file) s.text = g_readAhead.second;
  return s;
}

void recordModel(io::OutputSet& files, const ModelOptions& o, const core::Model& model) {
  files.setting("model", o.file);
  const std::string refined = "refined: ";
  for (const std::string& note : model.notes)
    if (note.rfind(refined, 0) == 0) {
      files.setting("refined", note.substr(refined.size()));
      files.setting("results", model.unrefined ? "at the original nodes and elements (--refined-results: every node)"
                                               : "every node and element of the refined model (--refined-results)");
    }
}

std::string optionSpelling(const std::string& name) {
  if (name == "load_steps") return "--steps";
  std::string flag = "--" + name;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

void printDiagnostics(const analysis::Diagnostics& d, bool quiet, std::size_t from, std::size_t to) {
  using K = analysis::Diagnostic::Kind;
  for (std::size_t k = from; k < std::min(to, d.size()); ++k) {
    const analysis::Diagnostic& x = d[k];
    if (x.kind == K::Note && quiet) continue;
    std::ostream& o = x.kind == K::Result ? std::cout : std::cerr;
    if (x.kind != K::Result) o << (x.where.empty() ? "flexmb" : x.where) << ": ";
    if (x.kind == K::Note) o << "note: ";
    if (x.kind == K::Warning) o << "warning: ";
    o << analysis::withOptions(x, optionSpelling);
    if (x.see == "check") o << " (run `flexmb check` for the kinematic rank analysis)";
    o << "\n";
  }
}

int exitCodeOf(analysis::JobStatus s) {
  switch (s) {
    case analysis::JobStatus::Ready:
    case analysis::JobStatus::Completed:
      return kOk;
    case analysis::JobStatus::InputError:
      return kInputError;
    case analysis::JobStatus::Interrupted:
      return interruptedExitCode();
    case analysis::JobStatus::Failed:
    case analysis::JobStatus::Stopped:
      break;
  }
  return kNumericalFailure;
}

std::size_t showDiagnostics(const analysis::ModelJob& job, bool quiet, std::size_t from) {
  printDiagnostics(job.diagnostics(), quiet, from);
  return job.diagnostics().size();
}

bool userFunctionsAllowed(const ModelOptions& o, const core::Model& model) {
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
}

std::shared_ptr<const std::vector<io::AnalysisStage>> loadChecked(const ModelOptions& o,
                                                                  const analysis::ModelNeeds& needs,
                                                                  bool acceptUserFunctions) {
  std::shared_ptr<const std::vector<io::AnalysisStage>> stages;
  try {
    stages = analysis::readStages(modelSource(o));
  } catch (const io::DatError& e) {
    std::cerr << e.what() << "\n";
    return nullptr;
  } catch (const std::exception& e) {
    std::cerr << o.file << ": " << e.what() << "\n";
    return nullptr;
  }
  const core::Model& model = stages->back().model;
  if (!acceptUserFunctions && (!model.userStressFunction.empty() || !model.userInputFunction.empty())) {
    printDiagnostics(analysis::checkModelFor(model, o.file, {false, false, false}), o.quiet);
    userFunctionsAllowed(o, model);  // says why not
    return nullptr;
  }
  const analysis::Diagnostics d = analysis::checkModelFor(model, o.file, needs);
  printDiagnostics(d, o.quiet);
  return analysis::hasError(d) ? nullptr : stages;
}

bool loadModel(const ModelOptions& o, core::Model& model, bool acceptUserFunctions) {
  const auto stages = loadChecked(o, {false, false, false}, acceptUserFunctions);
  if (!stages) return false;
  model = stages->back().model;
  return true;
}

bool loadModelFor(const ModelOptions& o, core::Model& model, bool needsMass, bool allowDriven) {
  const auto stages = loadChecked(o, {needsMass, true, allowDriven}, false);
  if (!stages) return false;
  model = stages->back().model;
  return true;
}

bool outputsWritable(io::OutputSet& files, const std::vector<std::string>& extras) {
  try {
    files.checkWritable();
    for (const std::string& extra : extras)
      if (!extra.empty()) io::OutputSet(extra).checkWritable();
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return false;
  }
  return true;
}

bool tryProduct(io::OutputSet& files, const std::string& what, const std::function<void()>& step) {
  return files.attempt(what, step, std::cerr);
}

void sayRemovedStale(const std::vector<std::string>& removed) {
  for (const auto& r : removed) std::cout << io::describeRemovedStale(r) << "\n";
}

}  // namespace flexmb::cli
