#include "analysis/TransferFiles.hpp"

#include <cmath>

#include "analysis/SpacarOutput.hpp"
#include "io/formats/ResultWriter.hpp"
#include "io/formats/SpacarResults.hpp"
#include "io/formats/TextOutput.hpp"
#include "io/pictures/SvgPlot.hpp"

namespace flexmb::analysis {

namespace {

std::vector<std::string> stateNames(Eigen::Index m) {
  std::vector<std::string> n;
  for (Eigen::Index k = 0; k < m; ++k) n.push_back("dq" + std::to_string(k + 1));
  for (Eigen::Index k = 0; k < m; ++k) n.push_back("dqd" + std::to_string(k + 1));
  return n;
}

// The magnitude's unit: output per input ("m/N", "rad/(N m)"), else "(output/input)".
std::string magnitudeLabel(const std::string& out, const std::string& in) {
  if (out.empty() || in.empty()) return "magnitude (output/input)";
  const auto part = [](const std::string& u) { return u.find_first_of(" /") == std::string::npos ? u : "(" + u + ")"; };
  return "magnitude [" + part(out) + "/" + part(in) + "]";
}

// Magnitude over phase of H(i w) against the frequency in Hz (the axis spans omega's range).
std::vector<io::Plot> bodePlots(const std::string& title, const std::string& magnitude, const Eigen::VectorXd& omega,
                                const Eigen::VectorXcd& h, const Eigen::VectorXd& phase, const std::string& note) {
  io::Plot mag, ph;
  mag.title = title;
  if (!note.empty()) mag.notes = {note};
  mag.x.label = "frequency [Hz]";
  mag.x.log = true;
  if (omega.size() > 1) mag.x.min = omega[0] / (2 * M_PI), mag.x.max = omega[omega.size() - 1] / (2 * M_PI);
  mag.y.label = magnitude;
  mag.y.log = true;
  ph.x = mag.x;
  ph.y.label = "phase [deg]";
  mag.height = ph.height = 300;
  io::Series m, p;
  for (Eigen::Index k = 0; k < omega.size(); ++k) {
    m.x.push_back(omega[k] / (2 * M_PI));
    m.y.push_back(std::abs(h[k]));
    p.x.push_back(omega[k] / (2 * M_PI));
    p.y.push_back(phase[k]);  // analysis::bodePhase
  }
  mag.series = {m};
  ph.series = {p};
  return {mag, ph};
}

// One Bode diagram (magnitude over phase) per input-output pair: <prefix>_bode_in<i>_out<o>.svg.
void writeBodeDiagrams(io::OutputSet& files, const StateSpace& ss, const Eigen::VectorXd& omega,
                       const std::string& modelFile, const std::string& note) {
  const std::vector<Eigen::VectorXcd> responses = frequencyResponses(ss, omega);
  const auto unit = [](const std::vector<std::string>& units, Eigen::Index k) {
    return k < static_cast<Eigen::Index>(units.size()) ? units[static_cast<std::size_t>(k)] : std::string();
  };
  for (Eigen::Index i = 0; i < ss.B.cols(); ++i)
    for (Eigen::Index o = 0; o < ss.C.rows(); ++o) {
      const Eigen::VectorXcd& h = responses[static_cast<std::size_t>(i * ss.C.rows() + o)];
      const std::string name = "_bode_in" + std::to_string(i + 1) + "_out" + std::to_string(o + 1) + ".svg";
      io::writeSvgStack(
          files.temporaryFor(name),
          bodePlots(ss.outputNames[o] + " / " + ss.inputNames[i] + " (" + modelFile + ")",
                    magnitudeLabel(unit(ss.outputUnits, o), unit(ss.inputUnits, i)), omega, h, bodePhase(ss, h), note));
    }
}

}  // namespace

WrittenTransfer writeTransfer(io::OutputSet& files, const core::Model& model, const TransferRun& run,
                              const TransferFiles& what, std::ostream& out, std::ostream& err) {
  WrittenTransfer w;
  auto attempt = [&](const std::string& product, const std::function<void()>& step) {
    if (!files.attempt(product, step, err)) w.incomplete = true;
  };
  const StateSpace& ss = run.model;
  if (run.completed)
    attempt("the state-space matrices A, B, C, D", [&] {
      const std::vector<std::string> states = stateNames(ss.A.rows() / 2);
      io::writeMatrixCsv(files.temporaryFor("_A.csv"), ss.A, states, states, "A");
      io::writeMatrixCsv(files.temporaryFor("_B.csv"), ss.B, states, ss.inputNames, "B");
      io::writeMatrixCsv(files.temporaryFor("_C.csv"), ss.C, ss.outputNames, states, "C");
      io::writeMatrixCsv(files.temporaryFor("_D.csv"), ss.D, ss.outputNames, ss.inputNames, "D");
    });
  attempt("SPACAR's .sbd/.sbm/.ltv", [&] {
    SpacarOutputOptions so;
    so.transferFunctions = true;
    so.jacobian = true;
    const io::SpacarResults sr = spacarFromTransfer(model, run, so);
    const std::string tmp = files.temporaryPrefix();
    for (const auto& p : io::writeSpacarResults(tmp, model, sr)) files.temporaryFor(p.substr(tmp.size()));
  });
  // A large model's Bode diagrams cost seconds (a Hessenberg reduction of A and 400 O(n^2) solves)
  // that nobody asked for: drawn up to the limit, beyond it when forced.
  if (run.completed && what.bode && ss.A.rows() > TransferFiles::kBodeStateLimit && !what.forceBode) {
    out << "  Bode diagrams not drawn for " << ss.A.rows()
        << " states (asking for the Bode diagrams explicitly draws them)\n";
  } else if (run.completed && what.bode) {
    // No damping (A's velocity block is zero): the resonance peaks are infinite, the drawn ones are
    // only as high as the frequency grid comes to them.
    const std::string note = undamped(ss) ? "no damping in the model: the peaks are infinite at the eigenfrequencies "
                                            "(give EDAMP); the phase is H's own: 0, +-90 or -180 degrees"
                                          : "";
    if (!note.empty()) out << "  note: " << note << "\n";
    const Eigen::VectorXd omega = bodeFrequencies(ss, what.fminHz, what.fmaxHz);
    out << "  Bode diagrams from " << io::shortNumber(omega[0] / (2 * M_PI), 4) << " to "
        << io::shortNumber(omega[omega.size() - 1] / (2 * M_PI), 4) << " Hz"
        << (what.fminHz > 0.0 ? "" : " (a frequency range FMIN,FMAX in Hz sets it)") << "\n";
    attempt("the Bode diagrams", [&] { writeBodeDiagrams(files, ss, omega, what.modelFile, note); });
  }
  w.paths = files.commit(run.completed ? "complete" : "stopped: " + run.stopReason);
  return w;
}

}  // namespace flexmb::analysis
