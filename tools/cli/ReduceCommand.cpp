#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "analysis/BasisForTarget.hpp"
#include "analysis/ReduceJob.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionFiles.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/OperatorFile.hpp"
#include "io/formats/OutputFile.hpp"
#include "text/NumberText.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Progress.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
// The candidates a target scan ran: size, estimate, cost.
void printCandidates(std::ostream& out, const analysis::TargetResult& tr) {
  out << "basis for the target: " << tr.tried.size() << " candidate runs after the basis (" << tr.buildSeconds
      << " s), " << tr.seconds << " s in all\n  vectors  estimate     fevals   seconds\n";
  for (const auto& c : tr.tried) {
    char line[128];
    std::snprintf(line, sizeof line, "  %7d  %-11.3g  %6ld   %.4g%s\n", c.vectors,
                  c.estimate.estimated ? c.estimate.estimate : NAN, c.fevals, c.seconds,
                  c.completed ? "" : "  (the run stopped)");
    out << line;
  }
}
// Integers separated by commas (--track, --track-elements, --large), appended to `values`.
std::optional<int> parseIntegers(const char* option, const std::string& text, std::vector<int>& values) {
  std::stringstream ss(text);
  std::string tok;
  while (std::getline(ss, tok, ',')) {
    size_t used = 0;
    int v = 0;
    try {
      v = std::stoi(tok, &used);
    } catch (...) {
      used = 0;
    }
    if (used == 0 || used != tok.size()) {
      std::cerr << "flexmb: --" << option << ": '" << tok << "' is not an integer (integers separated by commas)\n";
      return kUsageError;
    }
    values.push_back(v);
  }
  return std::nullopt;
}

// --large: 1-based degree-of-freedom indices separated by commas, into o.large (0-based).
std::optional<int> parseLarge(const std::string& large, analysis::ReductionOptions& o) {
  if (large.empty()) return std::nullopt;
  std::vector<int> idx;
  if (auto rc = parseIntegers("large", large, idx)) return rc;
  for (int& v : idx) {
    if (v < 0) {
      std::cerr << "flexmb: --large: " << v << " is not an index (1-based)\n";
      return kUsageError;
    }
    if (v == 0) {
      std::cerr << "flexmb: --large: the indices are 1-based, as every number in flexmb (degree of freedom 1 is "
                   "the first in `flexmb check`'s list); 0 is not one (earlier flexmb versions read them 0-based: "
                   "add 1)\n";
      return kUsageError;
    }
    --v;
  }
  o.large = idx;
  return std::nullopt;
}

// The basis's method and parameters in the run manifest.
void describeReduction(io::OutputSet& files, const analysis::ReductionOptions& o) {
  files.setting("method", o.method);
  if (o.method == "modal") {
    files.setting("modes", std::to_string(o.modes));
    files.setting("normalise", o.normalise);
  } else {
    files.setting("modes per configuration", std::to_string(o.modes));
    files.setting("path", "node " + std::to_string(o.node) + " component " + std::to_string(o.component) + " from " +
                              text::shortest(o.from) + " to " + text::shortest(o.to) + " in " +
                              std::to_string(o.configs) + " configurations");
    files.setting("weight", o.weight);
    if (o.count > 0)
      files.setting("count", std::to_string(o.count));
    else
      files.setting("threshold", o.threshold);
  }
}

}  // namespace

int runReduce(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  analysis::ReductionOptions o;
  std::string out, large, trackNodes, trackElements;
  double target = NAN;  // not given
  bool noOperators = false;
  d.add_options()("method", po::value(&o.method)->default_value("modal"), "modal or svd-modal")(
      "modes", po::value(&o.modes)->default_value(3)->notifier(atLeast("modes", 1)), "r: modes per configuration")(
      "normalise", po::value(&o.normalise)->default_value("mass"),
      "modal: mass (V^T M V = I, as MATLAB's eig) or unit columns")(
      "configs", po::value(&o.configs)->default_value(10)->notifier(atLeast("configs", 1)),
      "svd-modal: equidistant configurations")(
      "weight", po::value(&o.weight)->default_value(0.0)->notifier(finite("weight")), "svd-modal: a in omega^-a")(
      "threshold", po::value(&o.threshold)->default_value(0.01)->notifier(positive("threshold")),
      "svd-modal: keep singular values above this share")(
      "count", po::value(&o.count)->default_value(0)->notifier(atLeast("count", 0)),
      "svd-modal: keep exactly this many (overrides threshold)")("node", po::value(&o.node),
                                                                 "svd-modal path: node label")(
      "comp", po::value(&o.component)->default_value(1)->notifier(atLeast("comp", 1)), "its component")(
      "from", po::value(&o.from)->notifier(finite("from")), "path start value")(
      "to", po::value(&o.to)->notifier(finite("to")), "path end value")(
      "large", po::value(&large),
      "degrees of freedom kept with identity columns (Eq. 20), 1-based in `flexmb check`'s order (DYNX, then DYNE), "
      "comma-separated (default: the hinges)")("out", po::value(&out)->default_value("basis.csv"), "basis file")(
      "target", po::value(&target)->notifier(finite("target")),
      "choose the basis size from an error target EPS (0 < EPS < 1): the smallest basis of --method whose reduced run "
      "over the model's TIMESTEP span has a reduction error estimate of at most EPS (largest position deviation "
      "relative to the motion); --modes / --count are chosen")(
      "track", po::value(&trackNodes),
      "nodes (labels, comma-separated) whose coordinates the operators also fit, so that `simulate --basis FILE "
      "--outputs tracked` reports their x, xd, xdd without the full kinematics")(
      "track-elements", po::value(&trackElements),
      "elements (labels, comma-separated) whose deformations the operators also fit (e, ed, edd and sig with "
      "--outputs tracked)")(
      "no-operators", po::bool_switch(&noOperators),
      "do not build the reduced operators (basis.operators beside the basis: the reduced model's mass, potential and "
      "loads as polynomials in eta over the range of a pilot run, so that `simulate --basis` evaluates it without the "
      "full kinematics; analysis/ReducedOperators.md)");
  if (auto rc = parseCommand(args, d, m,
                             "usage: flexmb reduce model.dat --method modal|svd-modal --modes r [...] --out basis.csv"))
    return *rc;
  // Option values the command line refuses as usage errors (the job refuses them for every front end).
  if (o.method != "modal" && o.method != "svd-modal") {
    std::cerr << "flexmb: --method must be modal or svd-modal, not '" << o.method << "'\n";
    return kUsageError;
  }
  if (noOperators && (!trackNodes.empty() || !trackElements.empty())) {
    std::cerr
        << "flexmb: --track and --track-elements fit outputs into the reduced operators: not with --no-operators\n";
    return kUsageError;
  }
  analysis::ReduceOptions ro;
  if (auto rc = parseLarge(large, o)) return *rc;
  if (auto rc = parseIntegers("track", trackNodes, ro.trackNodes)) return *rc;
  if (auto rc = parseIntegers("track-elements", trackElements, ro.trackElements)) return *rc;
  ro.basis = o;
  ro.target = target;
  ro.operators = !noOperators;
  analysis::ReduceJob job(modelSource(m), ro);
  std::size_t said = showDiagnostics(job, m.quiet);
  if (job.status() != analysis::JobStatus::Ready) return exitCodeOf(job.status());
  // One file set: the basis and the manifest <basis without .csv>_run.txt.
  io::OutputSet files(std::filesystem::path(out).replace_extension("").string());
  if (!outputsWritable(files)) return kInputError;
  files.setting("command", "reduce");
  recordModel(files, m, job.model());
  describeReduction(files, o);
  installInterruptHandler();  // Ctrl-C in a target scan keeps the best basis so far
  {
    Progress progress("reduce", !m.quiet);
    job.run({[&](int i, int n) { progress.update(i, n, "configurations"); }, interruptFlag(), interruptSignal()});
  }
  said = showDiagnostics(job, m.quiet, said);
  if (job.status() == analysis::JobStatus::Interrupted && job.hasTarget()) {
    const analysis::TargetResult& tr = job.target();
    printCandidates(std::cout, tr);
    if (tr.bestTried >= 0) {
      analysis::BasisOperators none;
      none.note = "not built: the scan was interrupted";
      try {
        analysis::writeReduction(files, out, m.file, job.basis(), none);
        files.commit("stopped: " + tr.note);
      } catch (const std::exception& e) {
        std::cerr << "flexmb: " << e.what() << "\n";
        return kWriteFailed;
      }
      std::cout << "basis (the best so far) written to " << out << "\nwrote " << files.manifestPath() << "\n";
    }
    return interruptedExitCode();
  }
  if (job.status() != analysis::JobStatus::Completed) return exitCodeOf(job.status());
  if (job.hasTarget()) {
    const analysis::TargetResult& tr = job.target();
    printCandidates(std::cout, tr);
    files.setting("target", target);
    files.setting("choosing", text::shortest(std::round(tr.seconds * 1e4) / 1e4) + " s (" +
                                  std::to_string(tr.tried.size()) + " candidate runs)");
    if (tr.full) {
      std::cout << "target " << text::shortest(target) << ": " << tr.note << "; no basis written\n";
      files.commit("complete: " + tr.note);
      std::cout << "wrote " << files.manifestPath() << "\n";
      return kOk;
    }
  }
  const analysis::ReductionResult& r = job.basis();
  // The reduced operators beside the basis: their failure leaves the basis written, and says why.
  {
    Progress progress("operators", !m.quiet && !noOperators);
    job.trainOperators();
  }
  showDiagnostics(job, m.quiet, said);
  const analysis::BasisOperators& ops = job.operators();
  const std::string opsPath = io::operatorPathFor(out);
  try {
    analysis::writeReduction(files, out, m.file, r, ops);
    files.commit("complete");
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  std::cout << "basis " << r.V.rows() << " x " << r.V.cols() << " (" << r.large.size()
            << " identity columns) written to " << out << "\n";
  if (ops.operators)
    std::cout << "reduced operators written to " << opsPath << ": " << ops.note << "\n";
  else
    std::cout << "reduced operators " << ops.note << "\n";
  std::cout << "wrote " << files.manifestPath() << "\n";
  if (r.scaledSingularValues.size()) {
    std::cout << "scaled singular values:";
    for (Eigen::Index i = 0; i < r.scaledSingularValues.size(); ++i) std::cout << " " << r.scaledSingularValues[i];
    std::cout << "\n";
  }
  return kOk;
}

}  // namespace flexmb::cli
