#include "analysis/SimulationFiles.hpp"

#include "analysis/LapClock.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "analysis/SpacarOutput.hpp"
#include "analysis/StaticDesign.hpp"
#include "io/formats/OriginalResults.hpp"
#include "io/formats/RestartWriter.hpp"
#include "io/formats/ResultWriter.hpp"
#include "io/formats/SpacarResults.hpp"
#include "io/formats/TextOutput.hpp"
#include "io/pictures/DesignPlots.hpp"
#include "io/pictures/HtmlAnimation.hpp"
#include "io/pictures/VtkWriter.hpp"
#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {

// Modes 4 and 3: the frequencies' table and (mode 3) the matrices; the linearisation is returned
// for the .sbm.
TrajectoryModes writeTrajectoryModes(io::OutputSet& files, const core::Model& model, const SimulationOptions& opt,
                                     const core::Trajectory& traj, const SimulationFiles& what, std::ostream& out,
                                     std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  TrajectoryModes tm = trajectoryModes(model, traj, what.linearize, opt.basis, what.matrices || what.mat);
  out << "linearised at " << tm.time.size() << " output times in "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
  if (!tm.completed) err << "flexmb: linearisation stopped early: " << tm.stopReason << "\n";
  io::writeTextFile(files.temporaryFor("_frequencies.csv"),
                    io::formatCsv(trajectoryFrequencyTable(tm, what.linearize)));
  if (what.matrices)
    io::writeThroughMemory(files.temporaryFor("_linear.mat"),
                           [&](const std::string& p) { io::writeLinearizedMat(p, tm.time, tm.matrices, tm.omega); });
  return tm;
}

}  // namespace

io::CsvTable trajectoryFrequencyTable(const TrajectoryModes& modes, int columns) {
  io::CsvTable t;
  t.columns.push_back("time");
  for (const char* stem : {"f", "zeta", "frozen_f"})
    for (int i = 1; i <= columns; ++i) t.columns.push_back(io::numberedColumn(stem, i, *stem == 'z' ? "" : "_Hz"));
  for (size_t k = 0; k < modes.time.size(); ++k) {
    std::vector<double> row{modes.time[k]};
    auto cells = [&](const Eigen::VectorXd& v, double scale) {
      for (int i = 0; i < columns; ++i) row.push_back(i < v.size() ? v[i] * scale : NAN);
    };
    cells(modes.omega[k], 1 / (2 * M_PI));
    cells(modes.damping[k], 1.0);
    cells(modes.omegaFrozen[k], 1 / (2 * M_PI));
    t.rows.push_back(std::move(row));
  }
  return t;
}

io::CsvTable trackedOutputTable(const core::Model& model, const core::Trajectory& traj) {
  const core::TrackedOutputs& tr = traj.tracked;
  const std::vector<std::string> xNames = io::coordinateColumnNames(model), eNames = io::deformationColumnNames(model);
  io::CsvTable t;
  t.columns.push_back("time");
  for (const core::OperatorOutput& q : tr.quantities) {
    const bool def = q.kind == core::OperatorOutput::Kind::Deformation;
    const std::string& name = def ? eNames[q.index] : xNames[q.index];
    for (const char* stem :
         def ? std::vector<const char*>{"e:", "ed:", "edd:", "sig:"} : std::vector<const char*>{"x:", "xd:", "xdd:"})
      t.columns.push_back(stem + name);
  }
  for (size_t k = 0; k < traj.time.size(); ++k) {
    std::vector<double> row{traj.time[k]};
    for (size_t j = 0; j < tr.quantities.size(); ++j) {
      const int c = static_cast<int>(j);
      row.insert(row.end(), {tr.value[k][c], tr.rate[k][c], tr.acceleration[k][c]});
      if (tr.quantities[j].kind == core::OperatorOutput::Kind::Deformation) row.push_back(tr.stress[k][c]);
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

io::CsvTable nodalForceTable(const core::Model& model, const core::Trajectory& traj,
                             const std::vector<Eigen::VectorXd>& fxt) {
  io::CsvTable t;
  t.columns.push_back("time");
  for (const auto& name : io::coordinateColumnNames(model)) t.columns.push_back(name);
  for (size_t k = 0; k < fxt.size() && k < traj.time.size(); ++k) {
    std::vector<double> row{traj.time[k]};
    row.insert(row.end(), fxt[k].data(), fxt[k].data() + fxt[k].size());
    t.rows.push_back(std::move(row));
  }
  return t;
}

namespace {

// "stress_PLBEAM3" of each element with a von Mises stress (stressTable's names), in its order.
std::vector<std::string> stressColumnNames(const core::Model& model) {
  std::vector<std::string> names;
  for (int i : stressedElements(model))
    names.push_back("stress_" + model.elements[i].type->keyword + std::to_string(model.elements[i].label));
  return names;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

std::vector<std::string> historyColumns(const core::Model& model, const std::vector<std::string>& labels) {
  const std::vector<std::string> xNames = io::coordinateColumnNames(model), eNames = io::deformationColumnNames(model),
                                 stresses = stressColumnNames(model);
  std::vector<std::string> out;
  for (const std::string& label : labels) {
    const auto colon = label.find(':');
    const std::string stem = colon == std::string::npos ? "" : label.substr(0, colon);
    const std::string name = colon == std::string::npos ? label : label.substr(colon + 1);
    if ((stem.empty() || stem == "x" || stem == "xd" || stem == "xdd") && contains(xNames, name)) {
      out.push_back((stem.empty() ? "x" : stem) + ":" + name);
      continue;
    }
    if ((stem == "e" || stem == "ed" || stem == "edd" || stem == "sig") && contains(eNames, name)) {
      out.push_back(label);
      continue;
    }
    if (stem.empty() && ((label == "max_stress" && !stresses.empty()) || contains(stresses, label))) {
      out.push_back(label);
      continue;
    }
    std::string why = "--plot: '" + label + "' is not a quantity of " + model.sourceFile + ". It has the coordinates " +
                      io::listNames(xNames, 30) + " (as node6.x or x:node6.x, and xd:, xdd: for their rates)";
    if (!eNames.empty())
      why += "; the deformations " + io::listNames(eNames, 30) +
             " (with e:, ed:, edd: or sig: for the deformation, its rates or its generalised stress)";
    why += stresses.empty() ? "; no von Mises stress (no element has a VISUALIZATION section)"
                            : "; the von Mises stresses max_stress, " + io::listNames(stresses, 30);
    if (contains(eNames, name) && stem.empty())
      why = "--plot: '" + label + "' is a deformation: write e:" + label + " (the deformation) or sig:" + label +
            " (its generalised stress)";
    throw std::invalid_argument(why);
  }
  return out;
}

io::CsvTable historyTable(const core::Model& model, const core::Trajectory& traj,
                          const std::vector<std::string>& columns) {
  io::CsvTable t;
  t.columns.push_back("time");
  t.columns.insert(t.columns.end(), columns.begin(), columns.end());
  t.rows.assign(traj.time.size(), {});
  for (size_t k = 0; k < traj.time.size(); ++k) t.rows[k].push_back(traj.time[k]);
  if (!traj.tracked.empty()) {  // only what the operators tracked
    const io::CsvTable tracked = trackedOutputTable(model, traj);
    for (const std::string& c : columns) {
      const std::size_t j = io::tableColumn(tracked, c, "the run's tracked outputs (--outputs tracked)");
      for (size_t k = 0; k < traj.time.size() && k < tracked.rows.size(); ++k) t.rows[k].push_back(tracked.rows[k][j]);
    }
    return t;
  }
  const std::vector<std::string> xNames = io::coordinateColumnNames(model), eNames = io::deformationColumnNames(model),
                                 stresses = stressColumnNames(model);
  for (size_t k = 0; k < traj.time.size() && k < traj.states.size(); ++k) {
    const core::StateOutputs& s = traj.states[k];
    std::vector<ElementStress> vonMises;
    for (const std::string& c : columns) {
      const auto colon = c.find(':');
      if (colon == std::string::npos) {  // a von Mises stress, from the state's sig and e
        if (vonMises.empty()) {
          StaticStep step;
          step.sigma = s.sig, step.e = s.e;
          vonMises = elementStresses(model, step);
        }
        double v = 0.0;
        for (size_t i = 0; i < vonMises.size(); ++i)
          if (c == "max_stress" ? vonMises[i].vonMises > v : c == stresses[i]) v = vonMises[i].vonMises;
        t.rows[k].push_back(v);
        continue;
      }
      const std::string stem = c.substr(0, colon), name = c.substr(colon + 1);
      const bool nodal = stem[0] == 'x';
      const std::vector<std::string>& names = nodal ? xNames : eNames;
      const auto at = static_cast<Eigen::Index>(std::find(names.begin(), names.end(), name) - names.begin());
      const Eigen::VectorXd& v = stem == "x"     ? s.x
                                 : stem == "xd"  ? s.xd
                                 : stem == "xdd" ? s.xdd
                                 : stem == "e"   ? s.e
                                 : stem == "ed"  ? s.ed
                                 : stem == "edd" ? s.edd
                                                 : s.sig;
      t.rows[k].push_back(at < v.size() ? v[at] : NAN);
    }
  }
  return t;
}

void writeTrajectoryFiles(io::OutputSet& files, const core::Model& model, const core::Trajectory& traj,
                          const SimulationFiles& what) {
  if (traj.time.empty()) return;
  if (!traj.tracked.empty()) {  // the tracked outputs stand for the states: one table
    io::writeTextFile(files.temporaryFor("_tracked.csv"),
                      io::formatCsv(io::originalColumns(model, trackedOutputTable(model, traj))));
    return;
  }
  if (what.csv) {
    if (what.fxt)
      io::writeTextFile(files.temporaryFor("_fxt.csv"),
                        io::formatCsv(io::originalColumns(model, nodalForceTable(model, traj, *what.fxt))));
    for (const char* q : {"_x", "_xd", "_xdd", "_e", "_ed", "_edd", "_sig"})
      files.temporaryFor(std::string(q) + ".csv");
    io::writeCsv(files.temporaryPrefix(), model, traj);
    if (io::hasOrientationNodes(model)) {
      files.temporaryFor("_rot.csv");
      io::writeOrientationCsv(files.temporaryPrefix(), model, traj);
    }
  }
  if (what.mat)  // through memory: matio does not report a full disk
    io::writeThroughMemory(files.temporaryFor(".mat"), [&](const std::string& p) { io::writeMat(p, model, traj); });
}

void describeIntegration(io::OutputSet& files, const core::Model& model, const SimulationOptions& opt) {
  using text::shortest;
  files.setting("integrator", integratorDescription(opt));
  const double t0 = model.settings.t0, t1 = opt.tEnd.value_or(model.settings.tEnd);
  const double h = opt.maxStep.value_or(model.settings.hmax);
  const int n = opt.intervals.value_or(model.settings.outputIntervals);
  std::string s = shortest(t0) + " to " + shortest(t1) + " s, " +
                  (n > 0 ? std::to_string(n) + " output intervals" : std::string("output at every step")) +
                  ", reltol " + shortest(opt.relTol.value_or(model.settings.relTol)) + ", abstol " +
                  shortest(opt.absTol.value_or(model.settings.absTol)) + ", max step ";
  // A derived number in 15 digits (0.1 x 0.07 is 0.007000000000000001 in its shortest exact form).
  s += h > 0 ? shortest(std::min(h, t1 - t0)) + " s"
             : text::significant(0.1 * (t1 - t0), 15) +
                   " s (not limited by the file or --max-step: the integrator's default, a tenth of the span)";
  files.setting("integration", s);
}

WrittenSimulation writeSimulation(io::OutputSet& files, const core::Model& model, const SimulationOptions& opt,
                                  const core::Trajectory& traj, bool interrupted, const SimulationFiles& what,
                                  std::ostream& out, std::ostream& err) {
  WrittenSimulation w;
  const LapClock clock;
  auto attempt = [&](const std::string& product, const std::function<void()>& step) {
    if (!files.attempt(product, step, err)) w.incomplete = true;
  };
  // Tracked outputs only (simulate --outputs tracked): no state to derive the other products from.
  const bool any = !traj.time.empty() && traj.tracked.empty();
  if (!traj.time.empty() && !traj.tracked.empty()) {
    writeTrajectoryFiles(files, model, traj, what);
    files.renameFiles();
  }
  if (any) {
    writeTrajectoryFiles(files, model, traj, what);
    files.renameFiles();
    std::optional<TrajectoryModes> kept;  // for <prefix>.sbm
    if (what.linearize > 0 && !interrupted)
      attempt("the linearisation along the trajectory (linearize, matrices)",
              [&] { kept = writeTrajectoryModes(files, model, opt, traj, what, out, err); });
    if (what.mat)  // SPACAR's <name>.sbd / .sbm (io/results.md)
      attempt("SPACAR's .sbd/.sbm", [&] {
        SpacarOutputOptions so;
        so.transferFunctions = (model.settings.transferFunctionLevel >= 1);
        const int mode = what.matrices ? 3 : what.linearize > 0 ? 4 : 1;
        const io::SpacarResults sr = spacarFromTrajectory(model, traj, kept ? &*kept : nullptr, mode, so);
        const std::string temp = files.temporaryPrefix();
        for (const auto& p : io::writeSpacarResults(temp, model, sr)) files.temporaryFor(p.substr(temp.size()));
      });
  }
  if (!what.echo.empty() && any)
    attempt("the restart echo " + what.echo, [&] {
      // The settings this run used (the options over the file's): the echo continues this run.
      core::Model settled = model;
      core::AnalysisSettings& s = settled.settings;
      if (opt.tEnd) s.tEnd = *opt.tEnd;
      if (opt.intervals) s.outputIntervals = *opt.intervals;
      if (opt.relTol) s.relTol = *opt.relTol;
      if (opt.absTol) s.absTol = *opt.absTol;
      if (opt.maxStep) s.hmax = *opt.maxStep;
      io::writeRestart(files.temporaryPath(what.echo), settled, traj.time.back(), traj.states.back());
    });
  if (!traj.time.empty() && !what.plot.empty())
    attempt("the time history " + files.prefix() + "_history.svg", [&] {
      const std::string title = model.sourceFile + ": time history" + (traj.completed ? "" : " (stopped early)");
      std::vector<double> initial;  // positions and rotations drawn from the model's initial configuration
      for (const std::string& c : what.plot)
        initial.push_back(c.rfind("x:", 0) == 0 ? model.x0[io::coordinateIndex(model, c.substr(2))] : NAN);
      io::writeSvgStack(files.temporaryFor("_history.svg"),
                        io::timeHistoryPlots(historyTable(model, traj, what.plot), initial, title));
    });
  if (any && what.vtk)  // pictures of the motion (they name their own files), then the manifest
    attempt("the VTK series", [&] {
      const auto series = io::writeVtkSeries(files.prefix(), model, traj);
      out << "wrote " << series.front() << " (ParaView collection of " << series.size() - 1 << " .vtu files)\n";
      files.record(files.prefix() + ".pvd");
      files.record(files.prefix() + "_vtu");
    });
  if (any && what.html)
    attempt("the HTML animation", [&] {
      io::AnimationOptions o;
      o.title = model.sourceFile + ": t = " + io::shortNumber(traj.time.front(), 6) + " ... " +
                io::shortNumber(traj.time.back(), 6) + " s" + (traj.completed ? "" : " (stopped early)");
      io::writeHtmlAnimation(files.prefix() + ".html", model, traj, o);
      out << "wrote " << files.prefix() << ".html\n";
      files.record(files.prefix() + ".html");
    });
  w.paths = files.renameFiles();
  w.seconds = clock.total();
  files.setting("writing", text::significant(w.seconds, 2) + " s");
  if (what.secondsBefore >= 0.0)
    files.setting("wall time in all", text::significant(what.secondsBefore + w.seconds, 3) + " s");
  w.paths.push_back(files.writeManifest(traj.completed ? "complete" : "stopped: " + traj.stopReason));
  return w;
}

}  // namespace flexmb::analysis
