// `flexmb transfer` (SPACAR's mode 9): the state-space model of the last load step between the
// inputs and outputs of the .dat's transfer block; and `--mode 3`, which linearises along the
// trajectory of a file with TIMESTEP and in every load step of a static file.
#include <Eigen/LU>
#include <boost/program_options.hpp>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "analysis/Transfer.hpp"
#include "analysis/TransferFiles.hpp"
#include "analysis/TransferJob.hpp"
#include "io/formats/OutputFile.hpp"
#include "text/NumberText.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Progress.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
// --freq-range FMIN,FMAX: two finite frequencies in Hz, 0 < FMIN < FMAX; else a usage error.
void readFrequencyRange(const std::string& v, double& fmin, double& fmax) {
  const auto number = [](const std::string& t, double& x) {
    const auto r = std::from_chars(t.data(), t.data() + t.size(), x);
    return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(x);
  };
  const auto comma = v.find(',');
  double a = 0.0, b = 0.0;
  if (comma == std::string::npos || !number(v.substr(0, comma), a) || !number(v.substr(comma + 1), b) || !(a > 0.0) ||
      !(b > a))
    throw po::error("--freq-range must be FMIN,FMAX in Hz with 0 < FMIN < FMAX, not '" + v + "'");
  fmin = a, fmax = b;
}
}  // namespace

int runTransfer(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  int nev = 6, steps = 0;
  bool noBode = false, forceBode = false;
  std::string out;
  double fmin = 0.0, fmax = 0.0;  // --freq-range (0: automatic)
  d.add_options()("nev", po::value(&nev)->notifier(atLeast("nev", 0)),
                  "eigenfrequencies per load step in the .sbm (default 6)")(
      "steps", po::value(&steps)->notifier(atLeast("steps", 1)), "load steps (default: ITERSTEP's second field)")(
      "no-bode", po::bool_switch(&noBode), "do not draw the Bode diagrams")(
      "bode", po::bool_switch(&forceBode),
      "draw the Bode diagrams also for more than 400 states (400 frequencies, each an O(n^2) solve)")(
      "freq-range",
      po::value<std::string>()->notifier([&](const std::string& v) { readFrequencyRange(v, fmin, fmax); }),
      "the Bode diagrams' frequencies FMIN,FMAX in Hz (default: a decade below the lowest to a decade above the "
      "highest eigenfrequency, at most five decades)")(
      "out", po::value(&out), "output prefix or folder (default: the model's name in the current folder)");
  analysis::DampingOptions damping;
  addDampingOptions(d, damping);
  if (auto rc = parseCommand(args, d, m,
                             "usage: flexmb transfer model.dat [--nev N] [--steps n] [--damping-ratio Z[,Z2...]] "
                             "[--rayleigh ALPHA,BETA] [--no-bode | --bode] [--freq-range FMIN,FMAX] [--out prefix]"))
    return *rc;
  if (noBode && fmin > 0.0) {
    std::cerr << "flexmb: --freq-range sets the Bode diagrams' frequencies: it cannot go with --no-bode\n";
    return kUsageError;
  }
  const bool bode = !noBode;
  analysis::TransferOptions to;
  to.nev = nev;
  to.loadSteps = steps;
  to.damping = damping;
  analysis::TransferJob job(modelSource(m), to);
  std::size_t said = showDiagnostics(job, m.quiet);
  if (job.status() != analysis::JobStatus::Ready) return exitCodeOf(job.status());
  const core::Model& model = job.model();
  io::OutputSet files(io::OutputSet::resolvePrefix(out, m.file));
  if (!outputsWritable(files)) return kInputError;
  const std::string prefix = files.prefix();
  files.setting("command", "transfer");
  recordModel(files, m, model);
  if (damping.any()) files.setting("added damping", analysis::dampingText(damping));
  if (fmin > 0.0) files.setting("Bode frequency range", text::shortest(fmin) + "," + text::shortest(fmax) + " Hz");
  Progress progress("transfer", !m.quiet);
  job.run({[&](int i, int total) { progress.update(i, total, "load steps"); }, nullptr, nullptr});
  progress.finish();
  if (job.status() == analysis::JobStatus::Failed) {
    showDiagnostics(job, m.quiet, said);
    return kNumericalFailure;
  }
  const analysis::TransferRun& run = job.result();
  files.setting("load steps", std::to_string(run.statics.loadSteps));
  const analysis::StateSpace& ss = run.model;
  if (run.completed) {
    const Eigen::Index n = ss.A.rows(), ni = ss.B.cols(), no = ss.C.rows();
    std::cout << "state-space model at load step " << run.statics.loadSteps << " of " << m.file << ": " << n
              << " states (dq, dqd in the order of M0), " << ni << " inputs, " << no << " outputs\n";
    for (Eigen::Index k = 0; k < ni; ++k) std::cout << "  input " << k + 1 << ": " << ss.inputNames[k] << "\n";
    for (Eigen::Index k = 0; k < no; ++k) std::cout << "  output " << k + 1 << ": " << ss.outputNames[k] << "\n";
    if (damping.any()) std::cout << "  damping added to the model's: " << analysis::dampingText(damping) << "\n";
    if (const std::optional<Eigen::MatrixXd> G = analysis::staticGain(ss)) {
      std::cout << "  static gain -C A^-1 B + D (rows: outputs, columns: inputs):\n" << std::setprecision(8);
      for (Eigen::Index r = 0; r < no; ++r) {
        std::cout << "   ";
        for (Eigen::Index c = 0; c < ni; ++c) std::cout << " " << std::setw(15) << (*G)(r, c);
        std::cout << "\n";
      }
    } else {
      std::cout << "  no static gain: A is singular (a free motion without stiffness)\n";
    }
  }
  // The state-space matrices, SPACAR's files and the Bode diagrams (analysis::writeTransfer).
  analysis::TransferFiles what;
  what.bode = bode;
  what.forceBode = forceBode;
  what.modelFile = m.file;
  what.fminHz = fmin, what.fmaxHz = fmax;
  analysis::WrittenTransfer written;
  try {
    written = analysis::writeTransfer(files, model, run, what, std::cout, std::cerr);
    for (const auto& p : written.paths) std::cout << "wrote " << p << "\n";
    sayRemovedStale(files.removedStale());
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  showDiagnostics(job, m.quiet, said);  // a stop: why (the load steps reached are written)
  if (job.status() != analysis::JobStatus::Completed) return exitCodeOf(job.status());
  if (written.incomplete) return kWriteFailed;
  return kOk;
}

int runMode3(const std::vector<std::string>& args) {
  // A static file (ITERSTEP, no TIMESTEP) runs the load steps with the matrices of each (SPACAR
  // mode 3, as SPACAR Light's opt.mode = 3 and oopspa's perturb use it); otherwise the trajectory.
  // The file is read once here; the command parses the same text.
  bool staticFile = false;
  for (const auto& a : args) {
    if (a.size() > 4 && a.compare(a.size() - 4, 4, ".dat") == 0 && std::filesystem::is_regular_file(a)) {
      try {
        staticFile = analysis::isStaticFile(io::readDatStagesString(*readAhead(a), a));
      } catch (const std::exception&) {  // the command itself reports the reading error
      }
      break;
    }
  }
  std::vector<std::string> more = args;
  more.push_back(staticFile ? "--ltv" : "--matrices");
  return staticFile ? runStatic(more) : runSimulate(more);
}

}  // namespace flexmb::cli
