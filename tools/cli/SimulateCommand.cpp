#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>

#include "analysis/SimulateJob.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/SimulationFiles.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/formats/RestartWriter.hpp"
#include "io/pictures/DesignPlots.hpp"
#include "text/NumberText.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Visuals.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {
// The command's arguments, parsed and checked.
struct SimulateArgs {
  ModelOptions m;
  double tEnd = 0, relTol = 0, absTol = 0, maxStep = 0;
  int intervals = -1, linearize = 0, bdfOrder = 0;
  double rhoInf = NAN;  // --rho-inf (NaN: not given)
  std::string out, format = "csv", echo, basisFile, dynamics = "auto", integrator = "auto", outputs = "all";
  bool matrices = false, vtk = false, html = false, noAccuracyCheck = false, fullKinematics = false;
  double target = NAN;  // --target: the reduction error target (NaN: not given)
  std::string plot;     // --plot COLUMN[,COLUMN...]: the time history <out>_history.svg
  std::string svdPath;  // --svd-path NODE,COMP,FROM,TO: --basis auto builds an SVD-modal basis along it
  analysis::Integrator chosen = analysis::Integrator::Auto;
  bool integratorGiven = false;  // --integrator given (an empty one is a usage error, not the default)
  core::DynamicsForm dynamicsForm = core::DynamicsForm::Automatic;
  // --damping-ratio, --rayleigh: a time run takes Rayleigh's beta (the job refuses the rest, with why)
  analysis::DampingOptions damping;
  AccuracyArgs accuracy;  // --error-estimate, --accuracy EPS
  bool csv() const { return format == "csv" || format == "both"; }
  bool mat() const { return format == "mat" || format == "both"; }
};

// Parses and checks the options; an exit code when the command should stop (help, usage errors).
std::optional<int> parseSimulate(const std::vector<std::string>& args, SimulateArgs& a) {
  po::options_description d = commonModelOptions(a.m);
  d.add_options()("t-end", po::value(&a.tEnd)->notifier(positive("t-end")), "end time (overrides TIMESTEP)")(
      "reltol", po::value(&a.relTol)->notifier(positive("reltol")),
      "relative tolerance (default from the file or 1e-3)")("abstol",
                                                            po::value(&a.absTol)->notifier(positive("abstol")),
                                                            "absolute tolerance (default from the file or 1e-6)")(
      "max-step", po::value(&a.maxStep)->notifier(positive("max-step")), "maximum step size")(
      "intervals", po::value(&a.intervals)->notifier(atLeast("intervals", 0)),
      "output intervals (0: every step; ode45 adds Refine 4's 3 points inside each)")(
      "integrator", po::value(&a.integrator)->notifier([&a](const std::string&) { a.integratorGiven = true; }),
      "auto (default: galpha from the start where the highest eigenfrequency at rest bounds ode45 to more than "
      "10,000 steps, else ode45, switching to galpha once its step is bound by stability rather than accuracy; says "
      "which; ode45 throughout on a model with USERSIG), ode45 (explicit, MATLAB's ode45 step by step: "
      "SPACAR's integrator and its counts), bdf (implicit: SUNDIALS CVODE's BDF with the analytic Jacobian of Eq. "
      "15, for stiff full models whose highest frequency bounds ode45's step) or galpha (implicit "
      "generalized-alpha: second order, numerical dissipation of the high frequencies set by --rho-inf, large steps "
      "on stiff spatial models)")("rho-inf", po::value(&a.rhoInf),
                                  "with --integrator galpha or auto (the default): the spectral radius at infinite "
                                  "step, 0 to 1 (default 0.8; 1: no numerical "
                                  "dissipation, energy kept; smaller: the unresolved high frequencies damped faster)")(
      "bdf-order", po::value(&a.bdfOrder)->notifier(atLeast("bdf-order", 1)),
      "with --integrator bdf: the highest BDF order, 1 to 5 (default 2: A-stable; 3-5 are more accurate per "
      "step but let undamped stiff modes bound the step)")(
      "out", po::value(&a.out),
      "output prefix or folder (default: the model's name in the current folder; with --basis the basis name is "
      "appended)")("format", po::value(&a.format),
                   "csv (default: the CSV tables <out>_x.csv ... _sig.csv), mat (<out>.mat and SPACAR's <out>.sbd, "
                   "which getfrsbf reads), both or none")(
      "echo", po::value(&a.echo),
      "write the end-of-run state as a .dat input that continues the run (SPACAR95 restart: elements, XY/BETA, "
      "LENGTH0, E/ED, input rates, TIME, loads and settings)")(
      "basis", po::value(&a.basisFile),
      "reduced model: q = V eta with V from this file (flexmb reduce), or auto: the smallest basis whose reduction "
      "error estimate meets --target")(
      "target", po::value(&a.target)->notifier(finite("target")),
      "the reduction error target EPS (0 < EPS < 1, largest position deviation relative to the motion): chooses the "
      "basis with --basis auto; with a basis file, the estimate above it is a warning (else above 10 RelTol)")(
      "full-kinematics", po::bool_switch(&a.fullKinematics),
      "with --basis FILE: Eq. 19 (the full kinematics at every evaluation) even where FILE's reduced operators "
      "(FILE.operators, written by flexmb reduce) hold, to compare the two on the same basis")(
      "outputs", po::value(&a.outputs),
      "all (default: every nodal coordinate, deformation and stress from the full kinematics at each output time) or "
      "tracked (with --basis FILE whose operators track nodes or elements, flexmb reduce --track: only those, from "
      "the operators' output fields, in <out>_tracked.csv; an output time then costs nothing that grows with the "
      "mesh)")(
      "svd-path", po::value(&a.svdPath),
      "--basis auto: an SVD-modal basis over NODE,COMP,FROM,TO (10 equilibria, 3 modes each) instead of a modal one")(
      "dynamics", po::value(&a.dynamics),
      (std::string("how the accelerations are solved: projected (Eq. 13 in the independent coordinates, dense), "
                   "saddle-point (sparse nodal form, full models) or auto (saddle-point from ") +
       std::to_string(flexmb::core::kSaddlePointDofs) + " DOF; reduced models always project)")
          .c_str())(
      "linearize", po::value(&a.linearize)->notifier(atLeast("linearize", 0)),
      "mode 4: the N lowest eigenfrequencies of the linearised equations (Eq. 15) along the trajectory (CSV)")(
      "matrices", po::bool_switch(&a.matrices),
      "mode 3: also write M0, K0, G0, C0, D0, N0 at every output time to <out>_linear.mat (implies --linearize 6 "
      "unless given)")("vtk", po::bool_switch(&a.vtk),
                       "ParaView time series: <out>.pvd and one .vtu per output time in <out>_vtu/")(
      "html", po::bool_switch(&a.html),
      (std::string("<out>.html: a self-contained page that plays the motion in a browser") + kHtmlUrlOptions).c_str())(
      "plot", po::value(&a.plot),
      "COLUMNS: the time history of these, separated by commas, in <out>_history.svg (a panel per quantity): "
      "coordinates as the CSV names them (node6.x, or x:node6.x; xd:, xdd: their rates), deformations with e:, "
      "ed:, edd: or sig: (their generalised stress: sig:PLBEAM3.e2_bending_p), and with VISUALIZATION sections "
      "the von Mises stress max_stress (the largest over the elements) or stress_PLBEAM3 (one element's)")(
      "no-accuracy-check", po::bool_switch(&a.noAccuracyCheck),
      "skip the a-posteriori accuracy check (three windows of the run integrated again at a 10x tighter "
      "tolerance: about a tenth of the run's cost or more; it warns when the result is not converged)");
  addDampingOptions(d, a.damping);
  addAccuracyOptions(d, a.accuracy);
  if (auto rc = parseCommand(args, d, a.m, "usage: flexmb simulate model.dat [options]")) return *rc;
  if (!a.csv() && !a.mat() && a.format != "none") {
    std::cerr << "flexmb: --format must be csv, mat, both or none, not '" << a.format << "'\n";
    return kUsageError;
  }
  const std::optional<analysis::Integrator> chosen = analysis::parseIntegrator(a.integrator);
  if (!chosen) {
    std::cerr << "flexmb: --integrator must be ode45, bdf, auto or galpha, not '" << a.integrator << "'\n";
    return kUsageError;
  }
  a.chosen = *chosen;
  if (!std::isnan(a.rhoInf) && !(a.rhoInf >= 0.0 && a.rhoInf <= 1.0)) {
    std::cerr << "flexmb: --rho-inf must lie in [0, 1], not " << a.rhoInf << "\n";
    return kUsageError;
  }
  if (!std::isnan(a.rhoInf) && a.chosen != analysis::Integrator::GeneralizedAlpha &&
      a.chosen != analysis::Integrator::Auto) {
    std::cerr << "flexmb: --rho-inf needs --integrator galpha or auto\n";
    return kUsageError;
  }
  if (a.bdfOrder > 5) {
    std::cerr << "flexmb: --bdf-order must be 1 to 5, not " << a.bdfOrder << "\n";
    return kUsageError;
  }
  if (a.bdfOrder > 0 && a.chosen != analysis::Integrator::Bdf) {
    std::cerr << "flexmb: --bdf-order needs --integrator bdf\n";
    return kUsageError;
  }
  if (a.dynamics == "projected")
    a.dynamicsForm = core::DynamicsForm::Projected;
  else if (a.dynamics == "saddle-point")
    a.dynamicsForm = core::DynamicsForm::SaddlePoint;
  else if (a.dynamics != "auto") {
    std::cerr << "flexmb: --dynamics must be auto, projected or saddle-point, not '" << a.dynamics << "'\n";
    return kUsageError;
  }
  if (a.matrices && a.linearize <= 0) a.linearize = 6;
  if (!std::isnan(a.target) && !(a.target > 0.0 && a.target < 1.0)) {
    std::cerr << "flexmb: --target must be between 0 and 1 (the reduction error relative to the motion), not "
              << text::shortest(a.target) << "\n";
    return kUsageError;
  }
  if (a.basisFile == "auto" && std::isnan(a.target)) {
    std::cerr << "flexmb: --basis auto needs --target EPS (the reduction error to meet)\n";
    return kUsageError;
  }
  if (a.outputs != "all" && a.outputs != "tracked") {
    std::cerr << "flexmb: --outputs must be all or tracked, not '" << a.outputs << "'\n";
    return kUsageError;
  }
  if (a.outputs == "tracked") {
    std::string clash;
    if (a.basisFile.empty() || a.basisFile == "auto")
      clash = "it needs --basis FILE (the operators beside FILE)";
    else if (a.fullKinematics)
      clash = "--full-kinematics computes every output from the full kinematics";
    else if (a.integratorGiven && a.chosen == analysis::Integrator::Bdf)
      clash = "the reduced operators serve ode45, galpha and auto, not bdf";
    else if (a.linearize > 0 || a.matrices)
      clash = "--linearize and --matrices need the full states";
    else if (!a.echo.empty() || a.vtk || a.html)
      clash = "--echo, --vtk and --html need the full states";
    else if (a.format == "mat")
      clash = "the tracked outputs are written as CSV (--format csv, both or none)";
    if (!clash.empty()) {
      std::cerr << "flexmb: --outputs tracked: " << clash << "\n";
      return kUsageError;
    }
  }
  if (!a.svdPath.empty() && a.basisFile != "auto") {
    std::cerr << "flexmb: --svd-path applies to --basis auto\n";
    return kUsageError;
  }
  return std::nullopt;
}

// The run's files and its --echo can be written, and the model can have an echo.
bool simulateOutputsWritable(io::OutputSet& files, const SimulateArgs& a, const core::Model& model) {
  if (!outputsWritable(files, {a.echo})) return false;
  if (const std::string why = a.echo.empty() ? "" : io::restartUnsupportedReason(model); !why.empty()) {
    std::cerr << "flexmb: " << why << " (run without --echo)\n";
    return false;
  }
  return true;
}

// --svd-path NODE,COMP,FROM,TO: the SVD-modal basis --basis auto scans. Throws
// std::invalid_argument for a malformed one.
analysis::ReductionOptions svdPathBasis(const std::string& path) {
  analysis::ReductionOptions r;
  std::stringstream ss(path);
  char c1 = 0, c2 = 0, c3 = 0;
  r.method = "svd-modal";
  if (!(ss >> r.node >> c1 >> r.component >> c2 >> r.from >> c3 >> r.to) || c1 != ',' || c2 != ',' || c3 != ',' ||
      !ss.eof())
    throw std::invalid_argument("--svd-path must be NODE,COMP,FROM,TO (e.g. 6,1,-0.0833,0.0833), not '" + path + "'");
  return r;
}

analysis::SimulationOptions simulationOptions(const SimulateArgs& a) {
  analysis::SimulationOptions opt;
  opt.integrator = a.chosen;
  if (a.bdfOrder > 0) opt.bdfMaxOrder = a.bdfOrder;
  if (!std::isnan(a.rhoInf)) opt.rhoInf = a.rhoInf;
  if (a.tEnd > 0) opt.tEnd = a.tEnd;
  if (a.relTol > 0) opt.relTol = a.relTol;
  if (a.absTol > 0) opt.absTol = a.absTol;
  if (a.maxStep > 0) opt.maxStep = a.maxStep;
  if (a.intervals >= 0) opt.intervals = a.intervals;
  opt.dynamics = a.dynamicsForm;
  opt.progress = !a.m.quiet;
  opt.accuracyCheck = !a.noAccuracyCheck;
  return opt;
}

// The files the options ask for.
analysis::SimulationFiles filesAsked(const SimulateArgs& a) {
  analysis::SimulationFiles f;
  f.csv = a.csv();
  f.mat = a.mat();
  f.linearize = a.linearize;
  f.matrices = a.matrices;
  f.echo = a.echo;
  f.vtk = a.vtk;
  f.html = a.html;
  f.plot = io::commaList(a.plot);
  return f;
}

// The run manifest's settings: the command, then the job's (basis, reduced dynamics, run notes).
void describeRun(io::OutputSet& files, const SimulateArgs& a, const analysis::SimulateJob& job) {
  files.setting("command", "simulate");
  recordModel(files, a.m, job.model());
  if (!a.basisFile.empty() && a.basisFile != "auto") files.setting("basis", a.basisFile);
  analysis::describeIntegration(files, job.model(), job.options());
  files.setting("dynamics", a.dynamics);
  for (const auto& [key, value] : job.settings()) files.setting(key, value);
}

// The largest |force| each input needs over the run, as a SPACAR user reads it off fxt and sig.
void printInputForces(std::ostream& o, const core::Model& model, const core::Trajectory& traj,
                      const std::vector<Eigen::VectorXd>& fxt) {
  auto peak = [&](auto value) {
    double worst = 0.0, at = traj.time.empty() ? 0.0 : traj.time.front();
    for (size_t k = 0; k < traj.time.size(); ++k)
      if (std::abs(value(k)) > std::abs(worst)) worst = value(k), at = traj.time[k];
    return std::pair{worst, at};
  };
  for (const auto& in : model.inputX) {
    const auto [f, t] = peak([&](size_t k) { return fxt[k][in.index]; });
    o << "  input " << model.coordName(in.index) << ": largest force (fxt) " << text::shortest(f)
      << " at t = " << text::shortest(t) << "\n";
  }
  for (const auto& in : model.inputE) {
    const auto [f, t] = peak([&](size_t k) { return traj.states[k].sig[in.index]; });
    o << "  input " << model.deformationName(in.index) << ": largest stress (sig) " << text::shortest(f)
      << " at t = " << text::shortest(t) << " (the drive applies -sig in the direction of the deformation)\n";
  }
}

// Mode 1 on a driven rigid mechanism (analysis/InverseDynamics.hpp): the same files as a
// simulation, plus <out>_fxt.csv with the forces the inputs need.
int runDrivenMechanism(const SimulateArgs& a, analysis::SimulateJob& job) {
  const core::Model& model = job.model();
  if (a.linearize > 0 || a.matrices || a.intervals == 0) {
    std::cerr << "flexmb: " << a.m.file
              << " is a driven rigid mechanism (no degrees of freedom): there is no linearisation (--linearize, "
                 "--matrices, modes 3 and 4) and no integrator step to output at (--intervals 0)\n";
    return kUsageError;
  }
  if (!a.m.quiet && (a.relTol > 0 || a.absTol > 0 || a.maxStep > 0 || a.integratorGiven || a.bdfOrder > 0))
    std::cerr << "flexmb: note: no integrator runs (no degrees of freedom): --integrator, --reltol, --abstol, "
                 "--max-step and --bdf-order are ignored\n";
  io::OutputSet files(io::OutputSet::resolvePrefix(a.out, a.m.file));
  if (!simulateOutputsWritable(files, a, model)) return kInputError;
  files.setting("command", "simulate");
  recordModel(files, a.m, job.model());
  files.setting("analysis",
                "driven rigid mechanism (no degrees of freedom): kinematics and inverse dynamics at the output "
                "times, no integrator");
  {
    const double t0 = model.settings.t0, t1 = job.options().tEnd.value_or(model.settings.tEnd);
    files.setting("time", text::shortest(t0) + " to " + text::shortest(t1) + " s, " +
                              std::to_string(job.options().intervals.value_or(model.settings.outputIntervals)) +
                              " output intervals");
  }
  const std::size_t said = job.diagnostics().size();
  job.run();
  printDiagnostics(job.diagnostics(), a.m.quiet, said, said + 1);  // how many output times
  const core::Trajectory& traj = job.trajectory();
  if (!traj.time.empty()) printInputForces(std::cout, model, traj, job.fxt());
  printDiagnostics(job.diagnostics(), a.m.quiet, said + 1);
  analysis::SimulationFiles what = filesAsked(a);
  what.plot = analysis::historyColumns(model, what.plot);
  what.fxt = &job.fxt();
  analysis::WrittenSimulation written;
  try {
    written = analysis::writeSimulation(files, model, analysis::SimulationOptions(), traj, job.interrupted(), what,
                                        std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  for (const auto& f : written.paths) std::cout << "wrote " << f << "\n";
  sayRemovedStale(files.removedStale());
  if (job.interrupted()) return interruptedExitCode();
  if (written.incomplete) return kWriteFailed;
  return traj.completed ? kOk : kNumericalFailure;
}

}  // namespace

int runSimulate(const std::vector<std::string>& args) {
  SimulateArgs a;
  if (auto rc = parseSimulate(args, a)) return *rc;
  analysis::SimulateRequest request;
  request.run = simulationOptions(a);
  request.basisFile = a.basisFile;
  request.target = a.target;
  request.fullKinematics = a.fullKinematics;
  request.damping = a.damping;
  request.trackedOutputs = a.outputs == "tracked";
  // The default (auto; ode45 for a run with reduced operators): neither --integrator nor --rho-inf
  // (galpha's setting, which asks for auto) given.
  request.defaultIntegrator = !a.integratorGiven && std::isnan(a.rhoInf);
  if (!a.svdPath.empty()) {
    try {
      request.autoBasis = svdPathBasis(a.svdPath);
    } catch (const std::invalid_argument& e) {
      std::cerr << "flexmb: " << e.what() << "\n";
      return kUsageError;
    }
  }
  installInterruptHandler();
  request.run.interrupt = interruptFlag();
  request.run.interruptSignal = interruptSignal();
  // --accuracy / --error-estimate: the job is the ladder's answer, already run (AccuracyTarget.hpp).
  std::unique_ptr<analysis::SimulateJob> owned;
  analysis::AccurateRun<analysis::SimulateJob> accurate;
  if (a.accuracy.asked()) {
    const bool clash = !a.basisFile.empty() || a.intervals == 0 || a.noAccuracyCheck;
    const std::optional<analysis::AccuracyRequest> ask = accuracyRequest(
        a.accuracy, a.m.quiet,
        clash ? "compare full runs on several meshes at the output times, with the accuracy check's integration "
                "error: they go with no --basis, --intervals 0 or --no-accuracy-check"
              : "");
    if (!ask) return kUsageError;
    // The output location before the meshes run (the job's own check comes after them).
    io::OutputSet probe(io::OutputSet::resolvePrefix(a.out, a.m.file));
    if (!outputsWritable(probe, {a.echo})) return kInputError;
    accurate = analysis::simulateToAccuracy(modelSource(a.m), std::move(request), *ask);
    if (!accurate.job) {
      printDiagnostics(accurate.diagnostics, a.m.quiet);
      return kInputError;
    }
    owned = std::move(accurate.job);
  } else {
    owned = std::make_unique<analysis::SimulateJob>(modelSource(a.m), std::move(request));
  }
  analysis::SimulateJob& job = *owned;
  printDiagnostics(job.diagnostics(), a.m.quiet);
  if (job.status() == analysis::JobStatus::InputError) return kInputError;
  if (!userFunctionsAllowed(a.m, job.model())) return kInputError;
  if (!a.plot.empty()) {  // the labels checked before the run
    try {
      analysis::historyColumns(job.model(), io::commaList(a.plot));
    } catch (const std::invalid_argument& e) {
      std::cerr << "flexmb: " << e.what() << "\n";
      return kUsageError;
    }
  }
  if (job.driven()) return runDrivenMechanism(a, job);

  // Output location checked before the analysis (and before choosing a basis).
  std::string suffix;
  if (!a.basisFile.empty() && (a.out.empty() || a.out.back() == '/' || std::filesystem::is_directory(a.out)))
    suffix = "_" + std::filesystem::path(a.basisFile).stem().string();
  io::OutputSet files(io::OutputSet::resolvePrefix(a.out, a.m.file, suffix));
  if (!simulateOutputsWritable(files, a, job.model())) return kInputError;

  const std::size_t said = job.diagnostics().size();
  job.run();
  printDiagnostics(job.diagnostics(), a.m.quiet, said);
  if (job.status() == analysis::JobStatus::Failed) return kNumericalFailure;
  describeRun(files, a, job);
  if (a.accuracy.asked()) reportAccuracy(files, accurate.budget, accurate.diagnostics, a.m.quiet);
  analysis::WrittenSimulation written;
  analysis::SimulationFiles what = filesAsked(a);
  what.plot = analysis::historyColumns(job.model(), what.plot);
  what.secondsBefore = job.wallSeconds();
  try {
    written = analysis::writeSimulation(files, job.model(), job.options(), job.trajectory(), job.interrupted(), what,
                                        std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  for (const auto& f : written.paths) std::cout << "wrote " << f << "\n";
  if (!a.m.quiet)
    std::cout << "wall time in all "
              << text::significant(std::max(job.wallSeconds(), accurate.budget.seconds) + written.seconds, 3)
              << " s (writing " << text::significant(written.seconds, 2) << " s"
              << (a.accuracy.asked() ? ", " + std::to_string(accurate.ladder.estimate.levels.size()) + " meshes" : "")
              << ")\n";
  sayRemovedStale(files.removedStale());
  // Ctrl-C during --accuracy's meshes stops the ladder: the finest completed mesh is written, and
  // the exit says it was interrupted.
  if (job.interrupted() || (a.accuracy.asked() && interruptFlag()->load())) return interruptedExitCode();
  if (written.incomplete) return kWriteFailed;
  return exitCodeOf(job.status());
}

}  // namespace flexmb::cli
