// spacar(mode, name[, opts]): SPACAR's MATLAB entry point over the flexmb libraries (MEX API only, so
// that Octave's `mkoctfile --mex` and MATLAB's `mex` both build it). Reads name.dat, runs the analysis
// of `mode` (0 kinematics, 1 dynamics, 3 linearised matrices (along the trajectory, or of every load
// step of a static file without TIMESTEP, with name.ltv), 4 eigenfrequencies along the trajectory,
// 9 transfer functions (name.ltv), 10 statics; a negative mode runs the same without console
// output), writes name.sbd / name.sbm (io/results.md), puts their variables into the caller's
// workspace from memory (also when a file cannot be written: a warning names it) and, when an
// output is requested, returns them in a struct. opts (modes 1, 3, 4): a
// struct choosing the integrator and its settings (parseOptions). Errors (input file:line, a failed
// run, a failing user function, Ctrl-C) are MATLAB errors; a run that stops writes and assigns the
// steps it stored first.
// USERSIG / USERINP functions named in the file are called back through mexCallMATLAB
// (tools/octave/MatlabUserFunctions.hpp).
#include "mex.h"

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "analysis/AccuracyTarget.hpp"
#include "analysis/SimulateJob.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/SpacarOutput.hpp"
#include "analysis/StaticDesign.hpp"
#include "analysis/StaticJob.hpp"
#include "analysis/Statics.hpp"
#include "analysis/TrajectoryModes.hpp"
#include "analysis/Transfer.hpp"
#include "analysis/TransferJob.hpp"
#include "io/formats/DatReader.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/formats/SpacarResults.hpp"
#include "tools/octave/MatlabUserFunctions.hpp"
#include "tools/octave/OctaveInterrupt.hpp"

using namespace flexmb;

namespace {

using Variables = std::vector<std::pair<std::string, mxArray*>>;

// The double variables of a result file as mxArrays, from memory (the workspace gets what the
// file holds, whether or not it could be written), leaving out names already there (the .sbm's
// time, tdef, ndof, nddof repeat the .sbd's) and `t` (SPACAR's file name of `time`; its loadsbd
// puts `time` into the workspace). Each variable's data is released once it is copied.
void toVariables(io::SpacarFileContents& file, Variables& vars) {
  for (auto& v : file.variables) {
    bool have = v.isText || v.name == "t";
    for (const auto& w : vars) have = have || w.first == v.name;
    if (have) continue;
    std::vector<mwSize> dims(v.dims.begin(), v.dims.end());
    mxArray* a = mxCreateNumericArray(dims.size(), dims.data(), mxDOUBLE_CLASS, mxREAL);
    if (!v.data.empty()) std::memcpy(mxGetPr(a), v.data.data(), v.data.size() * sizeof(double));
    std::vector<double>().swap(v.data);
    vars.emplace_back(v.name, a);
  }
}

// spacar(mode, name, opts): the fields of opts (names case-insensitive), all optional:
//   integrator  'auto' (default: galpha from the start where the highest frequency at rest bounds
//               ode45's step, else ode45 until its step is bound by stability), 'ode45' (MATLAB's
//               ode45 step by step, SPACAR's integrator), 'bdf' or 'galpha' (analysis::Integrator)
//   rhoinf      galpha: the spectral radius at infinite step, 0 to 1 (default 0.8)
//   reltol, abstol, maxstep, tend   positive numbers overriding the file's ERROR / TIMESTEP / HMAX
//   intervals   output intervals (a whole number >= 0; 0: every step)
//   bdforder    the highest BDF order, 1 to 5 (bdf)
//   target      a reduction error target (0 < target < 1): the run is reduced with the smallest modal
//               basis whose reduction error estimate meets it (analysis/BasisForTarget.hpp)
//   dampingratio, rayleigh   damping a designer states, added to the model's EDAMP
//               (analysis/DesignDamping.hpp): the modal ratio (a number, or one per mode) and
//               [alpha beta]; mode 9 takes both, modes 1, 3, 4 (a time run) beta alone, the
//               simulate job refusing the others with why. `integration`: a field of the time
//               integration was given (modes 1, 3, 4 only).
//   refine      every flexible beam split in this many elements, for every mode
//               (io/formats/MeshRefinement.hpp); the results at the original nodes and elements
//   refinedresults  true: with refine, the refined model's own results, every node and element
//               (io::ReadOptions::refinedResults)
//   accuracy    modes 1, 3, 4 and 10: the total error target against the converged model (0 < EPS < 1):
//               the mesh refined (and a time run's tolerance tightened) until the estimate meets it
//               (analysis/AccuracyTarget.hpp); the finest mesh's results
//   errorestimate  true: also the discretization error of the model's own mesh (its results)
// Returns an error message (empty: fine).
std::string parseDamping(const std::string& name, const mxArray* v, analysis::DampingOptions& damping) {
  const bool real = v && mxIsDouble(v) && !mxIsComplex(v) && mxGetNumberOfElements(v) >= 1;
  const std::vector<double> values =
      real ? std::vector<double>(mxGetPr(v), mxGetPr(v) + mxGetNumberOfElements(v)) : std::vector<double>();
  if (name == "rayleigh") {
    if (values.size() != 2) return "spacar: opts.rayleigh must be [alpha beta] (1/s and s: alpha M + beta K)";
    damping.alpha = values[0], damping.beta = values[1];
  } else {
    if (values.empty())
      return "spacar: opts.dampingratio must be a number, or one per mode (modes 1, 2, ...; the last for the higher)";
    damping.ratios = values;
  }
  const std::string why = analysis::dampingRefusal(damping);
  return why.empty() ? "" : "spacar: opts." + name + ": " + why;
}

std::string parseOptions(const mxArray* o, analysis::SimulationOptions& opt, double& target,
                         analysis::DampingOptions& damping, io::ReadOptions& read, bool& integration,
                         std::optional<analysis::AccuracyRequest>& accuracy) {
  if (!mxIsStruct(o) || mxGetNumberOfElements(o) != 1)
    return "spacar: the third argument must be a struct of options (integrator, reltol, abstol, maxstep, tend, "
           "intervals, bdforder)";
  for (int k = 0; k < mxGetNumberOfFields(o); ++k) {
    std::string name = mxGetFieldNameByNumber(o, k);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const mxArray* v = mxGetFieldByNumber(o, 0, k);
    if (name == "dampingratio" || name == "rayleigh") {
      if (std::string e = parseDamping(name, v, damping); !e.empty()) return e;
      continue;
    }
    if (name == "refine") {  // every mode: the flexible beams split (io/formats/MeshRefinement.hpp)
      const bool whole = v && mxIsNumeric(v) && !mxIsComplex(v) && mxGetNumberOfElements(v) == 1;
      const double x = whole ? mxGetScalar(v) : std::nan("");
      if (!(x >= 1 && x == std::floor(x) && x <= 1000))
        return "spacar: opts.refine must be a whole number from 1 to 1000 (elements per flexible beam)";
      read.refine = static_cast<int>(x);
      continue;
    }
    if (name == "accuracy" || name == "errorestimate") {  // modes 1, 3, 4, 10 (analysis/AccuracyTarget.hpp)
      const bool scalar = v && (mxIsNumeric(v) || mxIsLogical(v)) && !mxIsComplex(v) && mxGetNumberOfElements(v) == 1;
      const double x = scalar ? mxGetScalar(v) : std::nan("");
      if (name == "accuracy" && !(x >= analysis::kSmallestAccuracy && x < 1))
        return "spacar: opts.accuracy must be a number from 1e-10 (finer than double precision integrates) to below 1 "
               "(the total error against the converged model)";
      if (name == "errorestimate" && !(x == 0 || x == 1)) return "spacar: opts.errorestimate must be true or false";
      if (x == 0) continue;
      if (accuracy)
        return "spacar: opts.accuracy estimates the error itself: give opts.accuracy or opts.errorestimate, not both";
      accuracy.emplace();
      if (name == "accuracy") accuracy->eps = x;
      continue;
    }
    if (name == "refinedresults") {
      if (!v || !(mxIsLogicalScalar(v) || (mxIsNumeric(v) && mxGetNumberOfElements(v) == 1)))
        return "spacar: opts.refinedresults must be true or false";
      read.refinedResults = mxGetScalar(v) != 0.0;
      continue;
    }
    integration = true;
    if (name == "integrator") {
      char* text = v && mxIsChar(v) ? mxArrayToString(v) : nullptr;
      const std::string value = text ? text : "";
      mxFree(text);
      const auto integrator = analysis::parseIntegrator(value);
      if (!integrator) return "spacar: opts.integrator must be 'ode45', 'bdf', 'auto' or 'galpha'";
      opt.integrator = *integrator;
      continue;
    }
    const bool scalar = v && mxIsNumeric(v) && !mxIsComplex(v) && mxGetNumberOfElements(v) == 1;
    const double x = scalar ? mxGetScalar(v) : std::nan("");
    if (name == "intervals") {
      if (!(x >= 0 && x == std::floor(x) && x < 1e9)) return "spacar: opts.intervals must be a whole number >= 0";
      opt.intervals = static_cast<int>(x);
    } else if (name == "bdforder") {
      if (!(x >= 1 && x <= 5 && x == std::floor(x))) return "spacar: opts.bdforder must be 1, 2, 3, 4 or 5";
      opt.bdfMaxOrder = static_cast<int>(x);
    } else if (name == "rhoinf") {
      if (!(x >= 0 && x <= 1)) return "spacar: opts.rhoinf must lie in [0, 1]";
      opt.rhoInf = x;
    } else if (name == "target") {
      if (!(x > 0 && x < 1)) return "spacar: opts.target must be a number between 0 and 1 (the reduction error)";
      target = x;
    } else if (name == "reltol" || name == "abstol" || name == "maxstep" || name == "tend") {
      if (!(std::isfinite(x) && x > 0)) return "spacar: opts." + name + " must be a positive finite number";
      (name == "reltol" ? opt.relTol : name == "abstol" ? opt.absTol : name == "maxstep" ? opt.maxStep : opt.tEnd) = x;
    } else {
      return "spacar: unknown option '" + name +
             "' (opts may hold integrator, reltol, abstol, maxstep, tend, intervals, bdforder, rhoinf, target, "
             "dampingratio, rayleigh, refine, refinedresults, accuracy, errorestimate)";
    }
  }
  return "";
}

struct Run {
  std::string error;  // empty: success
  std::string errorId = "flexmb:spacar:run";
  Variables vars;
  std::string unwritten;  // the result files that could not be written, and why (a warning)
};

void usageError(Run& run, std::string text) {
  run.error = std::move(text);
  run.errorId = "flexmb:spacar:usage";
}

void say(bool silent, const std::string& s) {
  if (!silent) mexPrintf("%s", s.c_str());
}

// The result files of a run: each written on its own (one that cannot be written, for a full disk,
// no permission or a folder of that name, is named in run.unwritten) and the variables of the .sbd
// and .sbm put into run.vars from memory, whatever happened to the files.
void writeAndAssign(const std::string& name, bool silent, const core::Model& model, const io::SpacarResults& results,
                    Run& run) {
  std::vector<io::SpacarFileContents> files;
  try {
    files = io::spacarResultFiles(name, model, results);
  } catch (const std::exception& e) {
    if (run.error.empty()) run.error = e.what();
    return;
  }
  // Each file on its own: one that cannot be written (full disk, a folder of that name, no
  // permission) is named in a warning; the workspace gets the variables from memory all the same.
  std::vector<std::string> written, tried;
  for (const auto& f : files) {
    tried.push_back(f.path);
    try {
      io::writeSpacarFile(f);
      written.push_back(f.path);
      say(silent, "spacar: wrote " + f.path + "\n");
    } catch (const std::exception& e) {
      run.unwritten += std::string(run.unwritten.empty() ? "" : ", ") + f.path + " (" + e.what() + ")";
    }
  }
  // getfrsbf reads <name>.sbd with <name>.sbm: an earlier run's .sbm must not pass for this one's
  // (a file this run tried and failed to write is not an earlier run's).
  if (!written.empty() && written[0] == files[0].path)
    for (const auto& p : io::removeStaleSpacarCompanions(tried))
      say(silent, "spacar: " + io::describeRemovedStale(p) + "\n");
  for (auto& f : files)
    if (f.path.size() > 4 && f.path.compare(f.path.size() - 4, 4, ".ltv") != 0) toVariables(f, run.vars);
  // SPACAR's workspace name of the total nodal forces (the .sbd's fxt): FIS and oopspa read fxtot.
  for (std::size_t k = 0, n = run.vars.size(); k < n; ++k)
    if (run.vars[k].first == "fxt") run.vars.emplace_back("fxtot", mxDuplicateArray(run.vars[k].second));
}

// Modes 1, 3 (with TIMESTEP) and 4: the simulate job (analysis/SimulateJob.hpp: reduced with
// opts.target), what it says in `out`, and SPACAR's results from it. False (run.error set) when the
// run is refused before it starts.
// An option of a diagnostic as spacar() spells it: a field of opts ("" where opts has none).
std::string optsField(const std::string& name) {
  if (name == "load_steps") return "";
  std::string field = "opts.";
  for (char c : name)
    if (c != '_') field += c;
  return field;
}

// A job's diagnostics from `said` on, in spacar()'s words: warnings as MATLAB warnings, results and
// notes as "spacar: " lines (the statistics and the wall time are worded by the caller), errors left
// to the caller (refused, or the run's stop).
void show(const analysis::ModelJob& job, std::size_t& said, bool silent, std::ostringstream& out) {
  for (; said < job.diagnostics().size(); ++said) {
    const analysis::Diagnostic& d = job.diagnostics()[said];
    if (d.kind == analysis::Diagnostic::Kind::Warning && !silent)
      mexWarnMsgIdAndTxt("flexmb:spacar:run", "%s: %s", job.file().c_str(),
                         analysis::withOptions(d, optsField).c_str());
    else if ((d.kind == analysis::Diagnostic::Kind::Result || d.kind == analysis::Diagnostic::Kind::Note) &&
             d.topic.empty())
      out << "spacar: " << analysis::withOptions(d, optsField) << "\n";
  }
}

// The ladder's own lines (analysis/AccuracyTarget.hpp): results and notes on the console, warnings as
// MATLAB warnings.
void showLadder(const analysis::Diagnostics& d, const std::string& file, bool silent, std::ostringstream& out) {
  for (const analysis::Diagnostic& x : d)
    if (x.kind == analysis::Diagnostic::Kind::Warning && !silent)
      mexWarnMsgIdAndTxt("flexmb:spacar:accuracy", "%s: %s", file.c_str(), analysis::withOptions(x, optsField).c_str());
    else if (x.kind != analysis::Diagnostic::Kind::Warning)
      out << "spacar: " << analysis::withOptions(x, optsField) << "\n";
}

// A job's first error, named by its file.
std::string errorOf(const analysis::ModelJob& job) {
  const std::string e = analysis::firstError(job.diagnostics(), optsField);
  return e.rfind(job.file(), 0) == 0 ? e : job.file() + ": " + e;
}

// A job refused before it ran: its first error as spacar()'s input error.
bool refused(const analysis::ModelJob& job, Run& run) {
  if (job.status() != analysis::JobStatus::InputError) return false;
  run.error = errorOf(job);
  run.errorId = "flexmb:spacar:input";
  return true;
}

bool runDynamics(int mode, bool silent, const std::string& name, const std::string& datFile,
                 std::shared_ptr<const std::vector<io::AnalysisStage>> stages,
                 const octave_gateway::MatlabUserFunctions& user, const analysis::SimulationOptions& simOptions,
                 double target, const analysis::DampingOptions& damping, std::ostringstream& out,
                 io::SpacarResults& results, bool& interrupted, std::string& afterRun, Run& run,
                 const core::Model*& resultModel, std::shared_ptr<const std::vector<io::AnalysisStage>>& kept,
                 const std::optional<analysis::AccuracyRequest>& accuracy) {
  analysis::SimulateRequest request;
  request.run = simOptions;
  request.damping = damping;
  request.target = target;
  if (!std::isnan(target)) request.basisFile = "auto";  // opts.target: the smallest modal basis meeting it
  octave_gateway::InterruptWatch watch;                 // Ctrl-C stops the run; the steps so far are written below
  request.run.interrupt = watch.flag();
  const analysis::ModelSource source{datFile, {}, std::move(stages), nullptr};
  std::unique_ptr<analysis::SimulateJob> owned;
  analysis::Diagnostics ladder;  // opts.accuracy / opts.errorestimate: the meshes' lines, the estimate
  if (accuracy) {
    analysis::AccurateRun<analysis::SimulateJob> a =
        analysis::simulateToAccuracy(source, std::move(request), *accuracy);
    ladder = std::move(a.diagnostics);
    if (!a.job) return usageError(run, "spacar: " + analysis::firstError(ladder, optsField)), false;
    owned = std::move(a.job);
  } else {
    owned = std::make_unique<analysis::SimulateJob>(source, std::move(request));
  }
  analysis::SimulateJob& job = *owned;
  // What the command line says before and after a run, with spacar()'s own voice: notes and results
  // on the console, warnings as MATLAB warnings, an error as the run's error.
  std::size_t said = 0;
  show(job, said, silent, out);
  if (refused(job, run)) return false;
  job.run();
  interrupted = watch.interrupted();
  show(job, said, silent, out);
  showLadder(ladder, datFile, silent, out);
  if (job.status() == analysis::JobStatus::Failed) {
    run.error = errorOf(job);
    return false;
  }
  const core::Model& model = job.model();
  resultModel = &model;
  kept = job.allStages();  // the job's models (copies when it added damping) outlive it: resultModel
  const core::Trajectory& traj = job.trajectory();
  const double wall = job.wallSeconds();
  out << "spacar: " << traj.time.size() << " output times, " << traj.nsteps << " steps, " << traj.nfailed
      << " failed attempts, " << traj.nfevals << " function evaluations ("
      << (traj.integrator == "ode45+galpha" ? "auto: ode45, then galpha" : traj.integrator) << ")\n";
  // Where the time goes: the interpreter (user functions) against flexmb itself.
  if (user.active()) {
    const double inUser = user.stressCalls().seconds + user.inputCalls().seconds;
    out << "spacar: wall time " << wall << " s: " << user.timing() << "; flexmb " << wall - inUser << " s";
    if (traj.nfevals > 0)
      out << " (" << 1e3 * (wall - inUser) / static_cast<double>(traj.nfevals) << " ms per evaluation)";
    out << "\n";
  } else {
    out << "spacar: wall time " << wall << " s\n";
  }
  if (std::isnan(traj.switchedAt) && job.options().integrator == analysis::Integrator::Ode45 &&
      traj.stiffBoundSteps >= 1000)
    out << "spacar: note: ode45's step was bound by stability from t = " << traj.stiffSince << " s on ("
        << traj.stiffBoundSteps << " steps at the limit of |lambda| about " << traj.stiffLambda << " 1/s): spacar("
        << mode << ", '" << name << "', struct('integrator', 'auto')) or 'galpha' would be "
        << "faster\n";
  analysis::SpacarOutputOptions so;
  so.transferFunctions = (model.settings.transferFunctionLevel >= 1);
  // The trajectory stands whatever happens after it: a failing linearisation (modes 3, 4) or
  // derived quantity leaves the states written, with the reason as the error after them.
  try {
    std::optional<analysis::TrajectoryModes> tm;
    if (mode != 1 && !traj.time.empty())
      tm = analysis::trajectoryModes(model, traj, std::min(6, model.numDofs()), std::nullopt, true);
    results = analysis::spacarFromTrajectory(model, traj, tm ? &*tm : nullptr, mode, so);
  } catch (const std::exception& e) {
    afterRun = std::string("the run's results are written, but ") +
               (mode != 1 ? "the linearisation along it" : "its derived quantities") + " failed: " + e.what();
    results = analysis::spacarFromTrajectory(model, traj, nullptr, 1, analysis::SpacarOutputOptions());
  }
  return true;
}

// The static job of modes 10 and 3 (a static file): six eigenfrequencies per load step, as SPACAR.
// Nothing when the job refused the model (run.error says why).
// opts.accuracy / opts.errorestimate: the ladder's answer, whose model (refined) resultModel then names
// (kept holds it).
std::optional<analysis::StaticRun> runStatic(const std::string& datFile,
                                             std::shared_ptr<const std::vector<io::AnalysisStage>> stages, bool silent,
                                             std::ostringstream& out, Run& run,
                                             const std::optional<analysis::AccuracyRequest>& accuracy = std::nullopt,
                                             const core::Model** resultModel = nullptr,
                                             std::shared_ptr<const std::vector<io::AnalysisStage>>* kept = nullptr) {
  analysis::StaticOptions so;
  so.nev = 6;
  const analysis::ModelSource source{datFile, {}, std::move(stages), nullptr};
  analysis::AccurateRun<analysis::StaticJob> a;
  auto owned = accuracy ? (a = analysis::staticToAccuracy(source, so, *accuracy), std::move(a.job))
                        : std::make_unique<analysis::StaticJob>(source, so);
  analysis::StaticJob& job = *owned;
  std::size_t said = 0;
  show(job, said, silent, out);
  if (refused(job, run)) return std::nullopt;
  job.run();
  show(job, said, silent, out);
  showLadder(a.diagnostics, datFile, silent, out);
  if (resultModel && kept) *kept = job.allStages(), *resultModel = &job.model();
  return job.result();
}

void runSpacar(int mode, bool silent, std::string name, const analysis::SimulationOptions& simOptions, double target,
               const analysis::DampingOptions& damping, const io::ReadOptions& read, Run& run,
               const std::optional<analysis::AccuracyRequest>& accuracy) {
  if (name.size() > 4 && name.compare(name.size() - 4, 4, ".dat") == 0) name.resize(name.size() - 4);
  const std::string datFile = name + ".dat";
  // The file is read once; the dynamics modes run its SPACAR95 stages (analysis/SimulateJob.hpp).
  std::shared_ptr<std::vector<io::AnalysisStage>> stages;
  try {
    stages = std::make_shared<std::vector<io::AnalysisStage>>(io::readDatStages(datFile, read));
  } catch (const std::exception& e) {
    run.error = e.what();
    run.errorId = "flexmb:spacar:input";
    return;
  }
  core::Model& model = stages->back().model;
  const bool staticFile = analysis::isStaticFile(*stages);
  // Where name.sbd goes, probed before the analysis: a run whose results cannot be written would
  // give the workspace nothing (the variables are read back from the files).
  try {
    io::OutputSet(name).checkWritable();
  } catch (const std::exception& e) {
    run.error = datFile + ": " + e.what();
    run.errorId = "flexmb:spacar:output";
    return;
  }
  // Legal input that is probably a mistake (a load on a fixed coordinate, a node without X): said
  // here for mode 0, by the other modes' jobs (as on the command line).
  if (!silent && mode == 0)
    for (const auto& w : model.warnings)
      mexWarnMsgIdAndTxt("flexmb:spacar:model", "%s: %s", datFile.c_str(), w.c_str());
  std::shared_ptr<octave_gateway::MatlabUserFunctions> user;  // the last stage's, for its timing
  for (auto& stage : *stages) {
    user = std::make_shared<octave_gateway::MatlabUserFunctions>(stage.model);
    if (user->active()) stage.model.userFunctions = user;
  }
  if (user->active() && mode != 1 && mode != 0) {
    run.error = datFile + ": USERSIG / USERINP user functions are supported in mode 1 (dynamics); mode " +
                std::to_string(mode) + " needs time expressions (XFT, ESIGT, INPUTXT)";
    run.errorId = "flexmb:spacar:input";
    return;
  }
  io::SpacarResults results;
  const core::Model* resultModel = &model;  // the model the results belong to (dynamics: the last stage run)
  std::shared_ptr<const std::vector<io::AnalysisStage>> kept;  // what resultModel points into
  std::ostringstream out;
  bool interrupted = false;
  std::string afterRun;  // a step after a completed run that failed (its results are still written)
  try {
    switch (mode) {
      case 0:
        results = analysis::spacarKinematic(model);
        out << "spacar: kinematic analysis of " << datFile << ": " << model.numDofs()
            << " dynamic degrees of freedom\n";
        break;
      case 3:
        if (staticFile) {  // a static file: SPACAR's mode 3 perturbs its load steps
          if (damping.any())
            return usageError(run,
                              "spacar: opts.dampingratio / opts.rayleigh: mode 3 on a static file (no "
                              "TIMESTEP) stores the load steps' matrices, which the damping a designer "
                              "states does not enter; mode 9 takes it");
          const auto st = runStatic(datFile, stages, silent, out, run, accuracy, &resultModel, &kept);
          if (!st) return;
          out << "spacar: static analysis with linearised matrices, " << st->steps.size() << " load steps\n";
          analysis::SpacarOutputOptions so;
          so.transferFunctions = true;
          so.jacobian = true;
          results = analysis::spacarFromStaticPerturbation(*resultModel, *st, so);
          break;
        }
        [[fallthrough]];
      case 1:
      case 4:
        if (!runDynamics(mode, silent, name, datFile, stages, *user, simOptions, target, damping, out, results,
                         interrupted, afterRun, run, resultModel, kept, accuracy))
          return;
        break;
      case 10: {
        const auto st = runStatic(datFile, stages, silent, out, run, accuracy, &resultModel, &kept);
        if (!st) return;
        out << "spacar: static analysis, " << st->steps.size() << " load steps\n";
        analysis::SpacarOutputOptions so;
        so.transferFunctions = true;  // as the command line: few steps, compliance scripts read dx
        so.jacobian = true;
        results = analysis::spacarFromStatics(*resultModel, *st, so);
        // SPACAR Light's stressmax, Freac and Mreac beside SPACAR's variables (analysis/StaticDesign.hpp).
        results.extraSbd = analysis::spacarDesignVariables(*resultModel, *st, {});
        break;
      }
      case 9: {
        analysis::TransferOptions to;
        to.nev = 6;  // as flexmb transfer (capped at the degrees of freedom)
        to.damping = damping;
        analysis::TransferJob job(analysis::ModelSource{datFile, {}, stages, nullptr}, to);
        std::size_t said = 0;
        show(job, said, silent, out);
        if (refused(job, run)) return;
        job.run();
        if (job.status() == analysis::JobStatus::Failed)
          throw std::runtime_error(analysis::firstError(job.diagnostics()));
        const analysis::TransferRun& tr = job.result();
        out << "spacar: transfer functions at the last of " << tr.statics.steps.size()
            << " load steps: " << tr.model.B.cols() << " inputs, " << tr.model.C.rows() << " outputs, "
            << tr.model.A.rows() << " states\n";
        analysis::SpacarOutputOptions so;
        so.transferFunctions = true;
        so.jacobian = true;
        results = analysis::spacarFromTransfer(model, tr, so);
        break;
      }
      default:
        run.error =
            "spacar: mode " + std::to_string(mode) + " is not supported (0, 1, 3, 4, 9, 10 and their negatives)" +
            (mode == 8
                 ? std::string("; buckling load factors (SPACAR's mode 8) come from mode 10's K0 and G0 (the .sbm: "
                               "getfrsbf), or from the command line: flexmb static --buckling N " +
                               datFile)
             : mode == 2 ? std::string("; SPACAR's mode 2 (inverse dynamic analysis with setpoint generation) is "
                                       "not in flexmb: no public source says how its setpoint is given or what it "
                                       "writes (docs/frontends/octave.md); a driven rigid mechanism (no degrees of "
                                       "freedom, moving inputs) gets its inverse dynamics from mode 1")
                         : std::string());
        run.errorId = "flexmb:spacar:mode";
        return;
    }
  } catch (const std::exception& e) {
    run.error = datFile + ": " + e.what();
    return;
  }
  // A user-function failure stops the integration like any right-hand-side failure: its message
  // (function, time, reason) is the stop reason.
  if (interrupted) {
    std::ostringstream m;
    m << datFile << ": interrupted (Ctrl-C)";
    if (!results.time.empty()) m << " after t = " << results.time.back();
    m << "; the " << results.time.size() << " output times computed so far are in " << name
      << ".sbd and the workspace (tdef)";
    run.error = m.str();
    run.errorId = "flexmb:spacar:interrupted";
  } else if (!results.completed) {
    run.error = datFile + ": run stopped: " + results.stopReason;
  } else if (!afterRun.empty()) {
    run.error = datFile + ": " + afterRun;
  }
  say(silent, out.str());
  if (!results.warning.empty() && !silent)
    mexWarnMsgIdAndTxt("flexmb:spacar:kinematics", "%s: %s", datFile.c_str(), results.warning.c_str());
  writeAndAssign(name, silent, *resultModel, results, run);
}

}  // namespace

void mexFunction(int nlhs, mxArray* plhs[], int nrhs, const mxArray* prhs[]) {
  if (nrhs < 2 || nrhs > 3 || !mxIsNumeric(prhs[0]) || mxGetNumberOfElements(prhs[0]) != 1 || !mxIsChar(prhs[1]))
    mexErrMsgIdAndTxt("flexmb:spacar:usage",
                      "usage: spacar(mode, 'name'[, opts]) with mode 0, 1, 3, 4, 9 or 10 (negative: silent) and opts "
                      "a struct (integrator, reltol, abstol, maxstep, tend, intervals, bdforder) for modes 1, 3, 4");
  if (nlhs > 1) mexErrMsgIdAndTxt("flexmb:spacar:usage", "spacar returns at most one output (a struct)");
  const double m = mxGetScalar(prhs[0]);
  char* nameC = mxArrayToString(prhs[1]);
  const std::string name = nameC ? nameC : "";
  mxFree(nameC);
  Run run;
  double target = std::nan("");                       // opts.target
  analysis::DampingOptions damping;                   // opts.dampingratio, opts.rayleigh
  bool integration = false;                           // opts has a field of the time integration
  io::ReadOptions read;                               // opts.refine, opts.refinedresults
  std::optional<analysis::AccuracyRequest> accuracy;  // opts.accuracy, opts.errorestimate
  analysis::SimulationOptions options;
  options.integrator = analysis::Integrator::Auto;  // the default of modes 1, 3, 4 (opts.integrator: another)
  if (m != std::floor(m)) {
    run.error = "spacar: the mode must be an integer";
    run.errorId = "flexmb:spacar:mode";
  } else if (nrhs == 3 &&
             !(run.error = parseOptions(prhs[2], options, target, damping, read, integration, accuracy)).empty()) {
    run.errorId = "flexmb:spacar:usage";
  } else if (nrhs == 3 && std::abs(m) != 1 && std::abs(m) != 3 && std::abs(m) != 4 &&
             (integration || (damping.any() && std::abs(m) != 9))) {
    run.error =
        "spacar: options (the third argument) apply to modes 1, 3 and 4 (time integration); mode 9 takes "
        "opts.dampingratio and opts.rayleigh alone; opts.refine applies to every mode";
    run.errorId = "flexmb:spacar:usage";
  } else if (accuracy && (std::abs(m) == 0 || std::abs(m) == 9)) {
    run.error = "spacar: opts.accuracy and opts.errorestimate apply to modes 1, 3, 4 and 10";
    run.errorId = "flexmb:spacar:usage";
  } else {
    runSpacar(static_cast<int>(std::abs(m)), m < 0, name, options, target, damping, read, run, accuracy);
  }
  // Results so far go to the workspace even when the run stopped.
  // `mode` stays in the struct and the file only: in the workspace it would hide Octave's mode().
  for (const auto& [n, a] : run.vars)
    if (n != "mode") mexPutVariable("caller", n.c_str(), a);
  if (nlhs > 0) {
    std::vector<const char*> names;
    for (const auto& v : run.vars) names.push_back(v.first.c_str());
    plhs[0] = mxCreateStructMatrix(1, 1, static_cast<int>(names.size()), names.data());
    for (std::size_t k = 0; k < run.vars.size(); ++k)
      mxSetFieldByNumber(plhs[0], 0, static_cast<int>(k), run.vars[k].second);
  } else {
    for (auto& v : run.vars) mxDestroyArray(v.second);
  }
  run.vars.clear();
  if (!run.unwritten.empty()) {
    static std::string unwritten;
    unwritten = run.unwritten;
    run.unwritten.clear();
    // (Octave puts the function's name before the message.)
    mexWarnMsgIdAndTxt("flexmb:spacar:write",
                       "could not write %s; the results are in the workspace (and the output struct) all the same",
                       unwritten.c_str());
  }
  if (!run.error.empty()) {
    // Static copies: MATLAB's error may leave this frame without running destructors.
    static std::string msg, id;
    msg = run.error, id = run.errorId;
    run = Run();
    mexErrMsgIdAndTxt(id.c_str(), "%s", msg.c_str());
  }
}
