// Linear analyses: modes (initial configuration), static (mode 10), sweep (Fig. 5 style).
#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "core/Linearization.hpp"
#include "io/BasisFile.hpp"
#include "io/ResultWriter.hpp"
#include "io/SvgPlot.hpp"
#include "tools/analysis/Statics.hpp"
#include "tools/analysis/Sweep.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Visuals.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
void printFrequencies(std::ostream& o, const Eigen::VectorXd& omega) {
  o << "  mode   f [Hz]          omega [rad/s]\n";
  for (Eigen::Index i = 0; i < omega.size(); ++i) {
    o << "  " << std::setw(4) << i + 1 << "   " << std::setw(14) << std::setprecision(8) << omega[i] / (2 * M_PI)
      << "  " << std::setw(14) << omega[i];
    if (std::abs(omega[i]) < 1e-6 * std::max(1.0, omega.cwiseAbs().maxCoeff())) o << "   (rigid / mechanism mode)";
    else if (omega[i] < 0) o << "   (unstable: negative stiffness, reported as -sqrt|lambda|)";
    o << "\n";
  }
}

std::optional<Eigen::MatrixXd> loadBasis(const std::string& path, const core::Model& model) {
  if (path.empty()) return std::nullopt;
  Eigen::MatrixXd V = io::readBasis(path);
  if (V.rows() != model.numDofs())
    throw std::runtime_error(path + ": basis has " + std::to_string(V.rows()) + " rows, the model has " +
                             std::to_string(model.numDofs()) + " degrees of freedom");
  return V;
}
}  // namespace

std::optional<Eigen::MatrixXd> readBasisFor(const std::string& path, const core::Model& model) {
  return loadBasis(path, model);
}

int runModes(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  int nev = 6;
  std::string basisFile, svg;
  d.add_options()("nev", po::value(&nev), "number of eigenfrequencies (default 6)")(
      "basis", po::value(&basisFile), "reduced model: q = V eta with V from this file")(
      "svg", po::value(&svg), "also draw the mode shapes into this SVG file");
  if (!parseCommand(args, d, m, "usage: flexmb modes model.dat [--nev N]")) return 2;
  core::Model model;
  if (!loadModel(m, model)) return 2;
  try {
    core::Linearization lin(model, loadBasis(basisFile, model));
    Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size()), f;
    lin.kinematics().solvePositions(model.settings.t0, lin.kinematics().initialDofs());
    lin.appliedForces(model.settings.t0, 0.0, f);
    core::LinearizedSystem sys;
    if (!lin.basis()) eta = lin.kinematics().initialDofs();
    lin.atRest(model.settings.t0, eta, f, sys);
    const analysis::Frequencies fr = analysis::naturalFrequencies(sys, std::min<int>(nev, lin.size()));
    std::cout << "eigenfrequencies in the initial configuration (" << lin.size() << " degrees of freedom):\n";
    printFrequencies(std::cout, fr.omega);
    if (!svg.empty()) {
      ModeSet set{"", {}, lin.basis() ? Eigen::MatrixXd(*lin.basis() * fr.modes) : fr.modes, fr.omega, model.settings.t0};
      lin.dofs(eta, set.q);
      writeShapeFigure(svg, model, "Mode shapes of " + m.file, {}, {set});
      std::cout << "wrote " << svg << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return 3;
  }
  return 0;
}

int runStatic(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  int nev = 6, steps = 0;
  std::string out, svg;
  d.add_options()("nev", po::value(&nev), "eigenfrequencies per equilibrium (default 6)")(
      "steps", po::value(&steps), "load steps (default: ITERSTEP's second field)")(
      "out", po::value(&out), "CSV with the equilibria (default: <model>_static.csv)")(
      "svg", po::value(&svg), "also draw the equilibria and the last one's mode shapes into this SVG file");
  if (!parseCommand(args, d, m, "usage: flexmb static model.dat [--nev N] [--steps n]")) return 2;
  core::Model model;
  if (!loadModel(m, model)) return 2;
  const analysis::StaticRun run = analysis::staticAnalysis(model, std::min(nev, model.numDofs()), steps);
  if (out.empty()) out = std::filesystem::path(m.file).stem().string() + "_static.csv";
  std::ofstream csv(out);
  csv << std::setprecision(17) << "load_factor";
  for (const auto& name : io::coordinateColumnNames(model)) csv << "," << name;
  for (int i = 0; i < nev; ++i) csv << ",f" << i + 1 << "_Hz";
  csv << "\n";
  for (const auto& st : run.steps) {
    std::cout << "load step " << st.loadFactor << ": " << st.newton.iterations << " Newton iterations"
              << (st.newton.stable ? "" : " (UNSTABLE equilibrium)") << "\n";
    printFrequencies(std::cout, st.frequencies.omega);
    csv << st.loadFactor;
    for (int i = 0; i < model.nx; ++i) csv << "," << st.x[i];
    for (Eigen::Index i = 0; i < st.frequencies.omega.size(); ++i) csv << "," << st.frequencies.omega[i] / (2 * M_PI);
    csv << "\n";
  }
  std::cout << "wrote " << out << "\n";
  if (!svg.empty() && !writeStaticFigure(svg, model, m.file, run)) return 2;
  if (!run.completed) {
    std::cerr << "flexmb: static analysis stopped: " << run.stopReason << "\n";
    return 3;
  }
  return 0;
}

int runSweep(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  analysis::SweepOptions o;
  std::string out, basisFile, svg;
  d.add_options()("node", po::value(&o.node)->required(), "node label of the prescribed coordinate")(
      "comp", po::value(&o.component)->default_value(1), "its component (1-based)")(
      "from", po::value(&o.from)->required(), "first value")("to", po::value(&o.to)->required(), "last value")(
      "steps", po::value(&o.steps)->default_value(10), "number of equidistant configurations")(
      "nev", po::value(&o.nev)->default_value(4), "eigenfrequencies per configuration")(
      "basis", po::value(&basisFile), "reduced model: q = V eta with V from this file")(
      "out", po::value(&out), "output prefix (default: <model>_sweep): CSV and SVG")(
      "svg", po::value(&svg), "also draw the configurations and the first and last mode shapes into this SVG file");
  if (!parseCommand(args, d, m, "usage: flexmb sweep model.dat --node N --comp i --from a --to b --steps n [--nev N]"))
    return 2;
  core::Model model;
  if (!loadModel(m, model)) return 2;
  analysis::SweepResult r;
  try {
    o.basis = loadBasis(basisFile, model);
    o.nev = std::min(o.nev, o.basis ? static_cast<int>(o.basis->cols()) : model.numDofs());
    r = analysis::sweep(model, o);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return 2;
  }
  if (out.empty()) out = std::filesystem::path(m.file).stem().string() + "_sweep";
  std::ofstream csv(out + ".csv");
  csv << std::setprecision(12) << "value,load";
  for (int i = 0; i < o.nev; ++i) csv << ",f" << i + 1 << "_Hz";
  for (int i = 0; i < o.nev; ++i) csv << ",tracked" << i + 1 << "_Hz";
  csv << "\n";
  io::Plot plot;
  plot.title = "Eigenfrequencies against " + model.coordName(model.nodes[model.nodeByLabel.at(o.node)].firstCoord + o.component - 1);
  plot.x.label = "prescribed coordinate";
  plot.y.label = "frequency [Hz]";
  plot.series.resize(o.nev);
  for (int i = 0; i < o.nev; ++i) plot.series[i].label = "f" + std::to_string(i + 1);
  std::cout << "  value          load           frequencies [Hz]\n";
  for (const auto& p : r.points) {
    csv << p.value << "," << p.load;
    std::cout << "  " << std::setw(12) << p.value << "  " << std::setw(12) << p.load << " ";
    for (Eigen::Index i = 0; i < p.omegaSorted.size(); ++i) {
      csv << "," << p.omegaSorted[i] / (2 * M_PI);
      std::cout << "  " << std::setw(10) << p.omegaSorted[i] / (2 * M_PI);
      plot.series[i].x.push_back(p.value);
      plot.series[i].y.push_back(p.omegaSorted[i] / (2 * M_PI));
    }
    for (Eigen::Index i = 0; i < p.omega.size(); ++i) csv << "," << p.omega[i] / (2 * M_PI);
    csv << "\n";
    std::cout << "\n";
  }
  io::writeSvg(out + ".svg", plot);
  std::cout << "wrote " << out << ".csv and " << out << ".svg\n";
  if (!svg.empty() && !writeSweepFigure(svg, model, m.file, r, o.t)) return 2;
  if (!r.completed) {
    std::cerr << "flexmb: sweep stopped: " << r.stopReason << "\n";
    return 3;
  }
  return 0;
}

}  // namespace flexmb::cli
