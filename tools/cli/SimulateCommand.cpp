#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "analysis/Simulation.hpp"
#include "analysis/SpacarOutput.hpp"
#include "analysis/TrajectoryModes.hpp"
#include "core/Linearization.hpp"
#include "io/DatReader.hpp"
#include "io/OutputFile.hpp"
#include "io/RestartWriter.hpp"
#include "io/ResultWriter.hpp"
#include "io/SpacarResults.hpp"
#include "solvers/Bdf.hpp"
#include "solvers/Ode45.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Visuals.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
// Limits of what a run may keep in memory and the least number of steps it may need.
constexpr double kMaxSteps = 1e9;

double physicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * size : 8e9;
}

std::string bytes(double b) {
  std::ostringstream s;
  s.precision(3);
  if (b >= 1e9)
    s << b / 1e9 << " GB";
  else
    s << b / 1e6 << " MB";
  return s.str();
}

// The highest eigenfrequency of the (reduced) model at rest in the initial configuration, and the
// coordinates its mode lives in. An explicit Runge-Kutta method needs h < ~3.3 / omega_max.
struct Stiffness {
  double omegaMax = 0.0, omegaMin = 0.0;
  std::vector<std::string> where;
};
Stiffness highestFrequency(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis) {
  Stiffness s;
  core::Linearization lin(model, basis);
  if (lin.size() == 0 || lin.size() > 600) return s;  // dense eigenproblem: small models only
  const Eigen::VectorXd q0 = lin.kinematics().initialDofs();
  lin.kinematics().solvePositions(model.settings.t0, q0);
  Eigen::VectorXd f, eta = basis ? Eigen::VectorXd::Zero(lin.size()) : q0;
  lin.appliedForces(model.settings.t0, 0.0, f);
  core::LinearizedSystem sys;
  lin.atRest(model.settings.t0, eta, f, sys);
  const Eigen::MatrixXd K = 0.5 * ((sys.K + sys.G) + (sys.K + sys.G).transpose());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, sys.M);
  if (es.info() != Eigen::Success) return s;
  const Eigen::VectorXd lambda = es.eigenvalues();
  s.omegaMax = std::sqrt(std::max(0.0, lambda.maxCoeff()));
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    if (lambda[i] > 1e-9 * lambda.maxCoeff()) {
      s.omegaMin = std::sqrt(lambda[i]);
      break;
    }
  Eigen::VectorXd v = es.eigenvectors().col(lambda.size() - 1);
  if (basis) v = *basis * v;
  std::vector<std::pair<double, int>> w;
  for (Eigen::Index i = 0; i < v.size(); ++i) w.emplace_back(std::abs(v[i]), static_cast<int>(i));
  std::sort(w.rbegin(), w.rend());
  for (size_t i = 0; i < w.size() && i < 3 && w[i].first > 0.3 * w[0].first; ++i) {
    const auto& dof = model.dofs[w[i].second];
    s.where.push_back(dof.isDeformation ? model.deformationName(dof.index) : model.coordName(dof.index));
  }
  return s;
}
}  // namespace

int runSimulate(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  double tEnd = 0, relTol = 0, absTol = 0, maxStep = 0;
  int intervals = -1;
  std::string out, format = "both", echo, basisFile, dynamics = "auto", integrator = "ode45";
  bool matrices = false, vtk = false, html = false;
  int linearize = 0, bdfOrder = 0;
  d.add_options()("t-end", po::value(&tEnd)->notifier(positive("t-end")), "end time (overrides TIMESTEP)")(
      "reltol", po::value(&relTol)->notifier(positive("reltol")), "relative tolerance (default from the file or 1e-3)")(
      "abstol", po::value(&absTol)->notifier(positive("abstol")), "absolute tolerance (default from the file or 1e-6)")(
      "max-step", po::value(&maxStep)->notifier(positive("max-step")), "maximum step size")(
      "intervals", po::value(&intervals)->notifier(atLeast("intervals", 0)),
      "output intervals (0: every step; ode45 adds Refine 4's 3 points inside each)")(
      "integrator", po::value(&integrator),
      "ode45 (default: explicit, MATLAB's ode45 step by step) or bdf (implicit: SUNDIALS CVODE's BDF with the "
      "analytic Jacobian of Eq. 15, for stiff full models whose highest frequency bounds ode45's step)")(
      "bdf-order", po::value(&bdfOrder)->notifier(atLeast("bdf-order", 1)),
      "with --integrator bdf: the highest BDF order, 1 to 5 (default 2: A-stable; 3-5 are more accurate per "
      "step but let undamped stiff modes bound the step)")(
      "out", po::value(&out),
      "output prefix or folder (default: the model's name in the current folder; with --basis the basis name is "
      "appended)")("format", po::value(&format), "csv, mat, both or none")(
      "echo", po::value(&echo),
      "write the end-of-run state as a .dat input that continues the run (SPACAR95 restart: elements, XY/BETA, "
      "LENGTH0, E/ED, input rates, TIME, loads and settings)")(
      "basis", po::value(&basisFile), "reduced model: q = V eta with V from this file (flexmb reduce)")(
      "dynamics", po::value(&dynamics),
      (std::string("how the accelerations are solved: projected (Eq. 13 in the independent coordinates, dense), "
                   "saddle-point (sparse nodal form, full models) or auto (saddle-point from ") +
       std::to_string(flexmb::core::kSaddlePointDofs) + " DOF; reduced models always project)")
          .c_str())(
      "linearize", po::value(&linearize)->notifier(atLeast("linearize", 0)),
      "mode 4: the N lowest eigenfrequencies of the linearised equations (Eq. 15) along the trajectory (CSV)")(
      "matrices", po::bool_switch(&matrices),
      "mode 3: also write M0, K0, G0, C0, D0, N0 at every output time to <out>_linear.mat (implies --linearize 6 "
      "unless given)")("vtk", po::bool_switch(&vtk),
                       "ParaView time series: <out>.pvd and one .vtu per output time in <out>_vtu/")(
      "html", po::bool_switch(&html), "<out>.html: a self-contained page that plays the motion in a browser");
  if (auto rc = parseCommand(args, d, m, "usage: flexmb simulate model.dat [options]")) return *rc;
  if (format != "csv" && format != "mat" && format != "both" && format != "none") {
    std::cerr << "flexmb: --format must be csv, mat, both or none, not '" << format << "'\n";
    return kUsageError;
  }
  const std::optional<analysis::Integrator> chosen = analysis::parseIntegrator(integrator);
  if (!chosen) {
    std::cerr << "flexmb: --integrator must be ode45 or bdf, not '" << integrator << "'\n";
    return kUsageError;
  }
  const bool bdf = *chosen == analysis::Integrator::Bdf;
  if (bdfOrder > 5) {
    std::cerr << "flexmb: --bdf-order must be 1 to 5, not " << bdfOrder << "\n";
    return kUsageError;
  }
  if (bdfOrder > 0 && !bdf) {
    std::cerr << "flexmb: --bdf-order needs --integrator bdf\n";
    return kUsageError;
  }
  core::DynamicsForm dynamicsForm = core::DynamicsForm::Automatic;
  if (dynamics == "projected")
    dynamicsForm = core::DynamicsForm::Projected;
  else if (dynamics == "saddle-point")
    dynamicsForm = core::DynamicsForm::SaddlePoint;
  else if (dynamics != "auto") {
    std::cerr << "flexmb: --dynamics must be auto, projected or saddle-point, not '" << dynamics << "'\n";
    return kUsageError;
  }
  std::vector<io::AnalysisStage> stages;
  if (!loadStages(m, stages, true)) return kInputError;
  // The stages that run an analysis (SPACAR95 blocks with TIMESTEP); none: the last, with defaults.
  std::vector<const core::Model*> runs;
  for (const auto& st : stages)
    if (st.runs) runs.push_back(&st.model);
  if (runs.empty()) runs.push_back(&stages.back().model);
  const core::Model& model = *runs.back();
  if (runs.size() > 1 && !m.quiet) std::cout << runs.size() << " analysis blocks, run in sequence\n";
  if (matrices && linearize <= 0) linearize = 6;

  analysis::SimulationOptions opt;
  opt.integrator = *chosen;
  if (bdfOrder > 0) opt.bdfMaxOrder = bdfOrder;
  if (tEnd > 0) opt.tEnd = tEnd;
  if (relTol > 0) opt.relTol = relTol;
  if (absTol > 0) opt.absTol = absTol;
  if (maxStep > 0) opt.maxStep = maxStep;
  if (intervals >= 0) opt.intervals = intervals;
  opt.dynamics = dynamicsForm;
  opt.progress = !m.quiet;
  try {
    opt.basis = readBasisFor(basisFile, model);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kInputError;
  }
  const double t0 = model.settings.t0, t1 = opt.tEnd.value_or(model.settings.tEnd);
  if (!(t1 > t0)) {
    std::cerr << "flexmb: the end time " << t1 << " is not after the start time " << t0
              << " (TIMESTEP's end time or --t-end)\n";
    return kInputError;
  }

  // Estimate the work and the output before running: refuse what cannot finish or fit.
  const double span = t1 - t0;
  const double h = opt.maxStep.value_or(model.settings.hmax);
  if (h > 0 && span / h > kMaxSteps) {
    std::cerr << "flexmb: a maximum step of " << h << " s over " << span << " s means at least " << span / h
              << " steps (the limit is " << kMaxSteps << "): raise --max-step (or HMAX)\n";
    return kInputError;
  }
  const long nOut = opt.intervals.value_or(model.settings.outputIntervals);
  if (nOut > 0) {
    const double values = 3.0 * model.nx + 4.0 * model.ne;
    const double memory = (nOut + 1.0) * (16.0 * values + 400.0);  // states, their copy for the .mat, overhead
    const double csv = (nOut + 1.0) * 24.0 * values;
    const double limit = 0.25 * physicalMemory();
    if (memory > limit) {
      std::cerr << "flexmb: " << nOut << " output intervals x " << values << " values would need about "
                << bytes(memory) << " of memory (the limit is a quarter of this machine's, " << bytes(limit)
                << ") and about " << bytes(csv) << " of CSV: lower the output intervals (TIMESTEP's second field or "
                << "--intervals)\n";
      return kInputError;
    }
  }
  // The explicit integrator's stability limit; an implicit integrator's step is not bounded by it.
  Stiffness stiff;
  try {
    if (!bdf) stiff = highestFrequency(model, opt.basis);
  } catch (const std::exception&) {}
  if (stiff.omegaMax > 0) {
    const double steps = span * stiff.omegaMax / 3.3;
    // Warn when the stability limit, not the output or the accuracy, sets the step: many more steps
    // than output intervals.
    if (steps > 1e4 && steps > 20.0 * std::max(1L, nOut) && !m.quiet) {
      std::cerr << "flexmb: warning: the highest eigenfrequency, " << stiff.omegaMax / (2 * M_PI)
                << " Hz, limits the explicit integrator's step to about " << 3.3 / stiff.omegaMax << " s: at least "
                << steps << " steps for " << span << " s. It lives in ";
      for (size_t i = 0; i < stiff.where.size(); ++i) std::cerr << (i ? ", " : "") << stiff.where[i];
      std::cerr << ". A reduced model removes it (flexmb reduce, then simulate --basis), the implicit "
                   "--integrator bdf steps over it, or make those deformations rigid.\n";
    }
    if (steps > kMaxSteps) {
      std::cerr << "flexmb: " << steps << " steps are more than the limit " << kMaxSteps
                << ": reduce the model, shorten the run or use --integrator bdf\n";
      return kInputError;
    }
  }

  // Output location checked before the analysis.
  std::string suffix;
  if (!basisFile.empty() && (out.empty() || out.back() == '/' || std::filesystem::is_directory(out)))
    suffix = "_" + std::filesystem::path(basisFile).stem().string();
  io::OutputSet files(io::OutputSet::resolvePrefix(out, m.file, suffix));
  try {
    files.checkWritable();
    if (!echo.empty()) io::OutputSet(echo).checkWritable();
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kInputError;
  }
  files.setting("command", "simulate");
  files.setting("model", m.file);
  if (!basisFile.empty()) files.setting("basis", basisFile);
  files.setting("integrator", bdf ? "bdf (" + solvers::Bdf::library() + ": BDF orders 1-" +
                                        std::to_string(opt.bdfMaxOrder) +
                                        ", Newton, dense LU, analytic Jacobian of Eq. 15)"
                                  : std::string("ode45 (Dormand-Prince 5(4), MATLAB's step control)"));
  {
    std::ostringstream s;
    s.precision(17);
    s << t0 << " to " << t1 << " s, " << nOut << " output intervals, reltol "
      << opt.relTol.value_or(model.settings.relTol) << ", abstol " << opt.absTol.value_or(model.settings.absTol)
      << ", max step " << h;
    files.setting("integration", s.str());
    files.setting("dynamics", dynamics);
  }

  installInterruptHandler();
  opt.interrupt = interruptFlag();
  const auto start = std::chrono::steady_clock::now();
  core::Trajectory traj;
  bool interrupted = false;
  try {
    traj = analysis::simulateStages(runs, opt, &interrupted);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: simulation could not start: " << e.what() << "\n";
    return kNumericalFailure;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  solvers::OdeStats st{traj.nsteps, traj.nfailed, traj.nfevals};
  st.njacevals = traj.njacevals;
  st.nrhsfailed = traj.nrhsfailed;
  st.nlinsetups = traj.nlinsetups;
  std::cout << (bdf ? solvers::Bdf::formatStats(st) : solvers::Ode45::formatStats(st));
  std::cout << "wall time " << wall << " s, " << traj.time.size() << " output times\n";
  if (!traj.completed) std::cerr << "flexmb: simulation stopped early: " << traj.stopReason << "\n";

  std::vector<std::string> report;
  try {
    if (!traj.time.empty()) {
      if (format == "csv" || format == "both") {
        for (const char* q : {"_x", "_xd", "_xdd", "_e", "_ed", "_edd", "_sig"})
          files.temporaryFor(std::string(q) + ".csv");
        io::writeCsv(files.temporaryPrefix(), model, traj);
        if (io::hasOrientationNodes(model)) {
          files.temporaryFor("_rot.csv");
          io::writeOrientationCsv(files.temporaryPrefix(), model, traj);
        }
      }
      if (format == "mat" || format == "both")  // through memory: matio does not report a full disk
        io::writeThroughMemory(files.temporaryFor(".mat"), [&](const std::string& p) { io::writeMat(p, model, traj); });
      const bool spacarFiles = format == "mat" || format == "both";
      std::optional<analysis::TrajectoryModes> kept;  // for <out>.sbm
      if (linearize > 0 && !interrupted) {
        const auto lt = std::chrono::steady_clock::now();
        const auto tm = analysis::trajectoryModes(model, traj, linearize, opt.basis, matrices || spacarFiles);
        std::cout << "linearised at " << tm.time.size() << " output times in "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - lt).count() << " s\n";
        if (!tm.completed) std::cerr << "flexmb: linearisation stopped early: " << tm.stopReason << "\n";
        // f: natural frequencies |s| of Eq. 15 (with C, D, N); zeta: damping ratios;
        // frozen_f: (K + G) v = w^2 M v at the same configuration, without C and N.
        std::ofstream f(files.temporaryFor("_frequencies.csv"));
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
        f.flush();
        if (!f) throw std::runtime_error("cannot write '" + files.prefix() + "_frequencies.csv': write failed");
        f.close();
        if (matrices)
          io::writeThroughMemory(files.temporaryFor("_linear.mat"), [&](const std::string& p) {
            io::writeLinearizedMat(p, tm.time, tm.matrices, tm.omega);
          });
        if (spacarFiles) kept = tm;
      }
      if (spacarFiles) {  // SPACAR's <name>.sbd / .sbm (io/results.md), renamed into place with the rest
        analysis::SpacarOutputOptions so;
        so.transferFunctions = (model.settings.transferFunctionLevel >= 1);
        const io::SpacarResults sr = analysis::spacarFromTrajectory(model, traj, kept ? &*kept : nullptr,
                                                                    matrices        ? 3
                                                                    : linearize > 0 ? 4
                                                                                    : 1,
                                                                    so);
        const std::string temp = files.temporaryPrefix();
        for (const auto& p : io::writeSpacarResults(temp, model, sr)) files.temporaryFor(p.substr(temp.size()));
      }
    }
    std::string status = traj.completed ? "complete" : "stopped: " + traj.stopReason;
    report = files.commit(status);
    if (!traj.time.empty()) {  // pictures of the motion, beside the committed result files
      if (vtk) writeVtk(files.prefix(), model, traj);
      if (html) writeAnimation(files.prefix(), model, traj);
    }
    if (!echo.empty() && !traj.time.empty()) {
      const std::string temp = io::temporaryName(echo);
      io::writeRestart(temp, model, traj.time.back(), traj.states.back());
      io::commitTemporary(temp, echo);
      report.push_back(echo);
    }
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  for (const auto& f : report) std::cout << "wrote " << f << "\n";
  if (interrupted) return kInterrupted;
  return traj.completed ? kOk : kNumericalFailure;
}

}  // namespace flexmb::cli
