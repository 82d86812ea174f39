// `flexmb transfer` (SPACAR's mode 9): the state-space model of the last load step between the
// inputs and outputs of the .dat's transfer block; and `--mode 3`, which linearises along the
// trajectory of a file with TIMESTEP and in every load step of a static file.
#include <Eigen/LU>
#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "analysis/SpacarOutput.hpp"
#include "analysis/Transfer.hpp"
#include "io/OutputFile.hpp"
#include "io/ResultWriter.hpp"
#include "io/SpacarResults.hpp"
#include "io/SvgPlot.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Progress.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;

std::vector<std::string> stateNames(Eigen::Index m) {
  std::vector<std::string> n;
  for (Eigen::Index k = 0; k < m; ++k) n.push_back("dq" + std::to_string(k + 1));
  for (Eigen::Index k = 0; k < m; ++k) n.push_back("dqd" + std::to_string(k + 1));
  return n;
}

// Magnitude over phase of H(i w) against the frequency in Hz.
std::vector<io::Plot> bodePlots(const std::string& title, const Eigen::VectorXd& omega, const Eigen::VectorXcd& h,
                                const Eigen::VectorXd& phase, const std::string& note) {
  io::Plot mag, ph;
  mag.title = title;
  if (!note.empty()) mag.notes = {note};
  mag.x.label = "frequency [Hz]";
  mag.x.log = true;
  mag.y.label = "magnitude";
  mag.y.log = true;
  ph.x = mag.x;
  ph.y.label = "phase [deg]";
  mag.height = ph.height = 300;
  io::Series m, p;
  for (Eigen::Index k = 0; k < omega.size(); ++k) {
    m.x.push_back(omega[k] / kTwoPi);
    m.y.push_back(std::abs(h[k]));
    p.x.push_back(omega[k] / kTwoPi);
    p.y.push_back(phase[k]);  // analysis::bodePhase
  }
  mag.series = {m};
  ph.series = {p};
  return {mag, ph};
}
// One Bode diagram (magnitude over phase) per input-output pair: <prefix>_bode_in<i>_out<o>.svg.
void writeBodeDiagrams(io::OutputSet& files, const analysis::StateSpace& ss, const std::string& modelFile,
                       const std::string& note) {
  const Eigen::VectorXd omega = analysis::bodeFrequencies(ss);
  const std::vector<Eigen::VectorXcd> responses = analysis::frequencyResponses(ss, omega);
  for (Eigen::Index i = 0; i < ss.B.cols(); ++i)
    for (Eigen::Index o = 0; o < ss.C.rows(); ++o) {
      const Eigen::VectorXcd& h = responses[static_cast<std::size_t>(i * ss.C.rows() + o)];
      const std::string name = "_bode_in" + std::to_string(i + 1) + "_out" + std::to_string(o + 1) + ".svg";
      io::writeSvgStack(files.temporaryFor(name),
                        bodePlots(ss.outputNames[o] + " / " + ss.inputNames[i] + " (" + modelFile + ")", omega, h,
                                  analysis::bodePhase(ss, static_cast<int>(i), static_cast<int>(o), omega, h), note));
    }
}
}  // namespace

int runTransfer(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  int nev = 6, steps = 0;
  bool noBode = false, forceBode = false;
  std::string out;
  d.add_options()("nev", po::value(&nev)->notifier(atLeast("nev", 0)),
                  "eigenfrequencies per load step in the .sbm (default 6)")(
      "steps", po::value(&steps)->notifier(atLeast("steps", 1)), "load steps (default: ITERSTEP's second field)")(
      "no-bode", po::bool_switch(&noBode), "do not draw the Bode diagrams")(
      "bode", po::bool_switch(&forceBode),
      "draw the Bode diagrams also for more than 400 states (400 frequencies, each an O(n^2) solve)")(
      "out", po::value(&out), "output prefix or folder (default: the model's name in the current folder)");
  if (auto rc = parseCommand(
          args, d, m, "usage: flexmb transfer model.dat [--nev N] [--steps n] [--no-bode | --bode] [--out prefix]"))
    return *rc;
  const bool bode = !noBode;
  core::Model model;
  if (!loadModelFor(m, model, true)) return kInputError;
  if (model.transferInputs.empty() || model.transferOutputs.empty()) {
    std::cerr << m.file
              << ": no transfer block: `flexmb transfer` needs at least one input (INPUTF, INX) and one output "
                 "(OUTX, OUTXP, OUTF) in a block after the dynamic block's END HALT (io/dat-language.md)\n";
    return kInputError;
  }
  io::OutputSet files(io::OutputSet::resolvePrefix(out, m.file));
  if (!outputsWritable(files)) return kInputError;
  const std::string prefix = files.prefix();
  files.setting("command", "transfer");
  files.setting("model", m.file);
  analysis::TransferOptions to;
  to.nev = std::min(nev, model.numDofs());
  to.loadSteps = steps;
  Progress progress("transfer", !m.quiet);
  to.onStep = [&](int i, int total) { progress.update(i, total, "load steps"); };
  analysis::TransferRun run;
  try {
    run = analysis::transferAnalysis(model, to);
  } catch (const std::exception& e) {
    progress.finish();
    std::cerr << "flexmb: " << m.file << ": " << e.what() << "\n";
    return kNumericalFailure;
  }
  progress.finish();
  files.setting("load steps", std::to_string(run.statics.loadSteps));
  const analysis::StateSpace& ss = run.model;
  if (run.completed) {
    const Eigen::Index n = ss.A.rows(), ni = ss.B.cols(), no = ss.C.rows();
    std::cout << "state-space model at load step " << run.statics.loadSteps << " of " << m.file << ": " << n
              << " states (dq, dqd in the order of M0), " << ni << " inputs, " << no << " outputs\n";
    for (Eigen::Index k = 0; k < ni; ++k) std::cout << "  input " << k + 1 << ": " << ss.inputNames[k] << "\n";
    for (Eigen::Index k = 0; k < no; ++k) std::cout << "  output " << k + 1 << ": " << ss.outputNames[k] << "\n";
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
  // The state-space matrices first, then SPACAR's files, then the Bode diagrams, each on its own
  // (tryProduct): a failure in a later one leaves the earlier ones written.
  bool complete = true;
  if (run.completed)
    complete &= tryProduct(files, "the state-space matrices A, B, C, D", [&] {
      const Eigen::Index mm = ss.A.rows() / 2;
      const std::vector<std::string> states = stateNames(mm);
      io::writeMatrixCsv(files.temporaryFor("_A.csv"), ss.A, states, states, "A");
      io::writeMatrixCsv(files.temporaryFor("_B.csv"), ss.B, states, ss.inputNames, "B");
      io::writeMatrixCsv(files.temporaryFor("_C.csv"), ss.C, ss.outputNames, states, "C");
      io::writeMatrixCsv(files.temporaryFor("_D.csv"), ss.D, ss.outputNames, ss.inputNames, "D");
    });
  complete &= tryProduct(files, "SPACAR's .sbd/.sbm/.ltv", [&] {
    analysis::SpacarOutputOptions so;
    so.transferFunctions = true;
    so.jacobian = true;
    const io::SpacarResults sr = analysis::spacarFromTransfer(model, run, so);
    const std::string tmp = files.temporaryPrefix();
    for (const auto& p : io::writeSpacarResults(tmp, model, sr)) files.temporaryFor(p.substr(tmp.size()));
  });
  // A large model's Bode diagrams cost seconds (a Hessenberg reduction of A and 400 O(n^2) solves)
  // that nobody asked for: drawn up to 400 states, beyond that with --bode.
  if (run.completed && bode && ss.A.rows() > 400 && !forceBode) {
    std::cout << "  Bode diagrams not drawn for " << ss.A.rows() << " states (--bode draws them)\n";
  } else if (run.completed && bode) {
    // No damping (A's velocity block is zero): the resonance peaks are infinite, the drawn ones are
    // only as high as the frequency grid comes to them.
    const bool undamped = analysis::undamped(ss);
    const std::string note = undamped ? "no damping in the model: the peaks are infinite at the eigenfrequencies "
                                        "(give EDAMP); the phase is a lightly damped model's"
                                      : "";
    if (undamped) std::cout << "  note: " << note << "\n";
    complete &= tryProduct(files, "the Bode diagrams", [&] { writeBodeDiagrams(files, ss, m.file, note); });
  }
  try {
    for (const auto& p : files.commit(run.completed ? "complete" : "stopped: " + run.stopReason))
      std::cout << "wrote " << p << "\n";
    sayRemovedStale(files.removedStale());
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  if (!run.completed) {
    std::cerr << "flexmb: transfer stopped: " << run.stopReason
              << " (the load steps reached are written; no state-space model)\n";
    return kNumericalFailure;
  }
  if (!complete) return kWriteFailed;
  return kOk;
}

int runMode3(const std::vector<std::string>& args) {
  // A static file (ITERSTEP, no TIMESTEP) runs the load steps with the matrices of each (SPACAR
  // mode 3, as SPACAR Light's opt.mode = 3 and oopspa's perturb use it); otherwise the trajectory.
  bool staticFile = false;
  for (const auto& a : args) {
    if (a.size() > 4 && a.compare(a.size() - 4, 4, ".dat") == 0 && std::filesystem::is_regular_file(a)) {
      try {
        staticFile = !io::readDatFile(a).settings.timestepGiven;
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
