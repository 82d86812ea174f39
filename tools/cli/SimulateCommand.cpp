#include <boost/program_options.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "io/DatReader.hpp"
#include "io/ResultWriter.hpp"
#include "solvers/Ode45.hpp"
#include "tools/analysis/Simulation.hpp"
#include "tools/analysis/TrajectoryModes.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Visuals.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

int runSimulate(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  double tEnd = 0, relTol = 0, absTol = 0, maxStep = 0;
  int intervals = -1;
  std::string out, format = "both", echo, basisFile;
  bool quiet = false, matrices = false, vtk = false, html = false;
  int linearize = 0;
  d.add_options()("t-end", po::value(&tEnd), "end time (overrides TIMESTEP)")(
      "reltol", po::value(&relTol), "relative tolerance (default from the file or 1e-3)")(
      "abstol", po::value(&absTol), "absolute tolerance (default from the file or 1e-6)")(
      "max-step", po::value(&maxStep), "maximum step size")(
      "intervals", po::value(&intervals), "output intervals (0: every step, Refine 4)")(
      "out", po::value(&out), "output prefix (default: the model's name in the current folder)")(
      "format", po::value(&format), "csv, mat, both or none")(
      "echo", po::value(&echo), "write the model and its final state the way SPACAR95 echoes it (XY/BETA, TIME, E/ED/EDD)")(
      "basis", po::value(&basisFile), "reduced model: q = V eta with V from this file (flexmb reduce)")(
      "linearize", po::value(&linearize),
      "mode 4: the N lowest eigenfrequencies of the linearised equations (Eq. 15) along the trajectory (CSV)")(
      "matrices", po::bool_switch(&matrices),
      "mode 3: also write M0, K0, G0, C0, D0, N0 at every output time to <out>_linear.mat (implies --linearize 6 "
      "unless given)")(
      "vtk", po::bool_switch(&vtk), "ParaView time series: <out>.pvd and one .vtu per output time in <out>_vtu/")(
      "html", po::bool_switch(&html), "<out>.html: a self-contained page that plays the motion in a browser")(
      "quiet,q", po::bool_switch(&quiet), "no progress line");
  if (!parseCommand(args, d, m, "usage: flexmb simulate model.dat [options]")) return 2;
  if (format != "csv" && format != "mat" && format != "both" && format != "none") {
    std::cerr << "flexmb: --format must be csv, mat, both or none\n";
    return 2;
  }
  core::Model model;
  if (!loadModel(m, model)) return 2;
  if (matrices && linearize <= 0) linearize = 6;

  analysis::SimulationOptions opt;
  if (tEnd > 0) opt.tEnd = tEnd;
  if (relTol > 0) opt.relTol = relTol;
  if (absTol > 0) opt.absTol = absTol;
  if (maxStep > 0) opt.maxStep = maxStep;
  if (intervals >= 0) opt.intervals = intervals;
  opt.progress = !quiet;
  try {
    opt.basis = readBasisFor(basisFile, model);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return 2;
  }

  const auto start = std::chrono::steady_clock::now();
  core::Trajectory traj;
  try {
    traj = analysis::simulate(model, opt);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: simulation could not start: " << e.what() << "\n";
    return 3;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  solvers::OdeStats st{traj.nsteps, traj.nfailed, traj.nfevals};
  std::cout << solvers::Ode45::formatStats(st);
  std::cout << "wall time " << wall << " s, " << traj.time.size() << " output times\n";
  if (!traj.completed) std::cerr << "flexmb: simulation stopped early: " << traj.stopReason << "\n";

  if (out.empty()) out = std::filesystem::path(m.file).stem().string();
  try {
    if (!traj.time.empty()) {
      if (format == "csv" || format == "both")
        for (const auto& f : io::writeCsv(out, model, traj)) std::cout << "wrote " << f << "\n";
      if (format == "mat" || format == "both") {
        io::writeMat(out + ".mat", model, traj);
        std::cout << "wrote " << out << ".mat\n";
      }
      if (vtk) writeVtk(out, model, traj);
      if (html) writeAnimation(out, model, traj);
      if (linearize > 0) {
        const auto lt = std::chrono::steady_clock::now();
        const auto tm = analysis::trajectoryModes(model, traj, linearize, opt.basis, matrices);
        std::cout << "linearised at " << tm.time.size() << " output times in "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - lt).count() << " s\n";
        if (!tm.completed) std::cerr << "flexmb: linearisation stopped early: " << tm.stopReason << "\n";
        // f: natural frequencies |s| of Eq. 15 (with C, D, N); zeta: damping ratios;
        // frozen_f: (K + G) v = w^2 M v at the same configuration, without C and N.
        std::ofstream f(out + "_frequencies.csv");
        f.precision(12);
        f << "time";
        for (int i = 0; i < linearize; ++i) f << ",f" << i + 1 << "_Hz";
        for (int i = 0; i < linearize; ++i) f << ",zeta" << i + 1;
        for (int i = 0; i < linearize; ++i) f << ",frozen_f" << i + 1 << "_Hz";
        f << "\n";
        auto cells = [&](const Eigen::VectorXd& v, double scale) {
          for (int i = 0; i < linearize; ++i) {
            f << ",";
            if (i < v.size()) f << v[i] * scale;
          }
        };
        for (size_t k = 0; k < tm.time.size(); ++k) {
          f << tm.time[k];
          cells(tm.omega[k], 1 / (2 * M_PI));
          cells(tm.damping[k], 1.0);
          cells(tm.omegaFrozen[k], 1 / (2 * M_PI));
          f << "\n";
        }
        std::cout << "wrote " << out << "_frequencies.csv\n";
        if (matrices) {
          io::writeLinearizedMat(out + "_linear.mat", tm.time, tm.matrices, tm.omega);
          std::cout << "wrote " << out << "_linear.mat\n";
        }
      }
      if (!echo.empty()) {
        std::ifstream in(m.file);
        std::stringstream text;
        text << in.rdbuf();
        io::writeEcho(echo, text.str(), model, traj.time.back(), traj.states.back());
        std::cout << "wrote " << echo << "\n";
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return 2;
  }
  return traj.completed ? 0 : 3;
}

}  // namespace flexmb::cli
