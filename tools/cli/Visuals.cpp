#include "tools/cli/Visuals.hpp"

#include <cmath>
#include <iostream>

#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "io/formats/TextOutput.hpp"
#include "io/pictures/HtmlAnimation.hpp"
#include "io/pictures/MechanismSvg.hpp"
#include "io/pictures/VtkWriter.hpp"

namespace flexmb::cli {

namespace {
// A load step's name in figures: SPACAR's load step k with the fraction of the DEL* totals, or the
// fraction of the initial loads for a ramp step before load step 0 (analysis/Statics.hpp: the load
// schedule). Load step 0 has the initial loads and no DEL* share: "load step 0, load factor 0".
std::string loadLabel(const analysis::StaticStep& st) {
  if (st.loadStep < 0) return "initial loads x " + io::shortNumber(st.initialFactor, 6);
  std::string s = "load step " + std::to_string(st.loadStep);
  s += ", load factor ";
  s += io::shortNumber(st.loadFactor, 6);
  return s;
}
}  // namespace

namespace {
// Light to dark blue for a sequence of configurations.
std::string sequenceColor(size_t i, size_t n) {
  const double a = n > 1 ? static_cast<double>(i) / static_cast<double>(n - 1) : 1.0;
  const int r = static_cast<int>(std::lround(160 - 160 * a)), g = static_cast<int>(std::lround(200 - 126 * a)),
            b = static_cast<int>(std::lround(240 - 62 * a));
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02X%02X%02X", r, g, b);
  return buf;
}
}  // namespace

std::vector<Eigen::VectorXd> positionsOf(const core::Model& model, const std::vector<Eigen::VectorXd>& qs, double t) {
  core::GeometricTransferFunctions gtf(model);
  std::vector<Eigen::VectorXd> xs;
  for (const auto& q : qs) {
    gtf.solvePositions(t, q);
    xs.push_back(gtf.x());
  }
  return xs;
}

namespace {
// The configuration of a mode set and its mode shapes in x (F_q v), by the model's kinematics.
struct NodalShapes {
  Eigen::VectorXd x;
  Eigen::MatrixXd shapes;  // nx x k
};
NodalShapes nodalShapes(const core::Model& model, const ModeSet& set) {
  core::GeometricTransferFunctions gtf(model);
  gtf.setInputLoadFactor(set.inputLoadFactor);
  gtf.solvePositions(set.t, set.q);
  NodalShapes n{gtf.x(), {}};
  gtf.firstOrder(&set.modes, n.shapes);
  return n;
}

std::string modeName(const ModeSet& set, Eigen::Index j) {
  const double f = j < set.omega.size() ? set.omega[j] / (2 * M_PI) : NAN;
  std::string s = (set.title.empty() ? "" : set.title + ": ") + "mode " + std::to_string(j + 1);
  if (std::isfinite(f)) s += ", " + io::shortNumber(f, 5) + " Hz";
  return s;
}

std::vector<io::AnimationSequence> modeSequences(const core::Model& model, const ModeSet& set) {
  std::vector<io::AnimationSequence> seqs;
  if (set.modes.cols() == 0) return seqs;
  const NodalShapes n = nodalShapes(model, set);
  for (Eigen::Index j = 0; j < set.modes.cols(); ++j)
    seqs.push_back(io::modeSequence(model, modeName(set, j), n.x, n.shapes.col(j)));
  return seqs;
}

// A state of the ParaView series from a configuration (rates zero).
core::StateOutputs restState(const core::Model& model, const Eigen::VectorXd& x, const Eigen::VectorXd& e,
                             const Eigen::VectorXd& sig) {
  core::StateOutputs s;
  s.x = x;
  s.xd = s.xdd = Eigen::VectorXd::Zero(model.nx);
  s.e = e.size() == model.ne ? e : Eigen::VectorXd::Zero(model.ne);
  s.sig = sig.size() == model.ne ? sig : Eigen::VectorXd::Zero(model.ne);
  s.ed = s.edd = Eigen::VectorXd::Zero(model.ne);
  return s;
}

template <class Write>
bool reported(const std::string& path, Write&& write) {
  try {
    write();
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << path << ": " << e.what() << "\n";
    return false;
  }
  return true;
}
}  // namespace

bool writeModelPage(const std::string& path, const core::Model& model, const std::string& title) {
  return reported(path, [&] {
    io::AnimationSequence s;
    s.name = "initial configuration";
    s.x.push_back(model.x0);
    s.labels.push_back("initial configuration");
    io::AnimationOptions o;
    o.title = title;
    o.numbers = true;
    io::writeHtmlPage(path, model, {s}, o);
    std::cout << "wrote " << path << "\n";
  });
}

bool writeStaticPage(const std::string& path, const core::Model& model, const std::string& modelFile,
                     const analysis::StaticRun& run) {
  return reported(path, [&] {
    io::AnimationSequence steps;
    steps.name = "load steps";
    steps.x.push_back(model.x0);
    steps.labels.push_back("initial configuration");
    for (const auto& st : run.steps) {
      steps.x.push_back(st.x);
      steps.labels.push_back(loadLabel(st));
    }
    std::vector<io::AnimationSequence> seqs{steps};
    if (!run.steps.empty() && run.steps.back().frequencies.modes.cols() > 0) {
      const auto& st = run.steps.back();
      const ModeSet set{loadLabel(st),     st.eta,       st.frequencies.modes, st.frequencies.omega,
                        model.settings.t0, st.loadFactor};
      for (auto& m : modeSequences(model, set)) seqs.push_back(std::move(m));
    }
    io::AnimationOptions o;
    o.title = "Static equilibria of " + modelFile + (run.completed ? "" : " (stopped early)");
    io::writeHtmlPage(path, model, seqs, o);
    std::cout << "wrote " << path << "\n";
  });
}

namespace {
// The ParaView series of configurations, said on stdout.
void writeVtkSaid(const std::string& prefix, const core::Model& model, const core::Trajectory& traj) {
  const auto files = io::writeVtkSeries(prefix, model, traj);
  std::cout << "wrote " << files.front() << " (ParaView collection of " << files.size() - 1 << " .vtu files)\n";
}
}  // namespace

bool writeStaticVtk(const std::string& prefix, const core::Model& model, const analysis::StaticRun& run) {
  return reported(prefix + ".pvd", [&] {
    core::Trajectory traj;
    for (const auto& st : run.steps) {
      // The series' time: the DEL* load factor, 0 at load step 0; ramp steps of the initial loads
      // before it at their fraction minus 1 (-1..0), so the times increase.
      traj.time.push_back(st.loadStep >= 0 ? st.loadFactor : st.initialFactor - 1.0);
      traj.states.push_back(restState(model, st.x, st.e, st.sigma));
    }
    if (traj.time.empty()) throw std::runtime_error("no load step was reached: nothing to write");
    writeVtkSaid(prefix, model, traj);
  });
}

bool writeModesPage(const std::string& path, const core::Model& model, const std::string& modelFile,
                    const ModeSet& set) {
  return reported(path, [&] {
    io::AnimationOptions o;
    o.title = "Mode shapes of " + modelFile;
    io::writeHtmlPage(path, model, modeSequences(model, set), o);
    std::cout << "wrote " << path << "\n";
  });
}

bool writeModesVtk(const std::string& prefix, const core::Model& model, const ModeSet& set) {
  return reported(prefix + ".pvd", [&] {
    const NodalShapes n = nodalShapes(model, set);
    core::Trajectory traj;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.ne);
    for (Eigen::Index j = 0; j < n.shapes.cols(); ++j) {
      traj.time.push_back(static_cast<double>(j + 1));
      traj.states.push_back(restState(model, io::scaledShape(model, n.x, n.shapes.col(j)), zero, zero));
    }
    if (traj.time.empty()) throw std::runtime_error("no mode shapes to write");
    writeVtkSaid(prefix, model, traj);
  });
}

void writeShapeFigure(const std::string& path, const core::Model& model, const std::string& title,
                      const std::vector<NamedConfiguration>& configurations, const std::vector<ModeSet>& modeSets,
                      io::View view) {
  io::ShapeFigure fig;
  fig.title = title;
  fig.view = view;
  io::ShapePanel configs;
  configs.title = configurations.empty()       ? "initial configuration"
                  : configurations.size() == 1 ? configurations[0].label
                                               : "configurations";
  configs.layers.push_back({model.x0, "initial configuration", "", true});
  // A flexure's load steps deflect it by a few per cent of its size at most: drawn magnified, said.
  std::vector<Eigen::VectorXd> xs;
  for (const NamedConfiguration& c : configurations) xs.push_back(c.x);
  const double k = io::magnification(model, model.x0, xs);
  if (k > 1.0) configs.title += " (displacements x " + io::shortNumber(k, 3) + ")";
  for (size_t i = 0; i < configurations.size(); ++i) {
    // Legend entries for the first and the last only (the panel has room for three).
    const bool named = i == 0 || i + 1 == configurations.size();
    const Eigen::VectorXd x = configurations[i].x.size() == model.x0.size()
                                  ? model.x0 + k * (configurations[i].x - model.x0)
                                  : configurations[i].x;
    configs.layers.push_back({x, named ? configurations[i].label : "", sequenceColor(i, configurations.size()), false});
  }
  fig.panels.push_back(configs);

  core::GeometricTransferFunctions gtf(model);
  Eigen::MatrixXd shapes;
  for (const ModeSet& set : modeSets) {
    if (set.modes.cols() == 0) continue;
    gtf.setInputLoadFactor(set.inputLoadFactor);
    gtf.solvePositions(set.t, set.q);
    const Eigen::VectorXd x = gtf.x();
    gtf.firstOrder(&set.modes, shapes);
    for (Eigen::Index j = 0; j < set.modes.cols(); ++j) {
      io::ShapePanel p;
      const double f = j < set.omega.size() ? set.omega[j] / (2 * M_PI) : NAN;
      p.title = (set.title.empty() ? "" : set.title + ": ") + "mode " + std::to_string(j + 1) + ", " +
                io::shortNumber(f, 5) + " Hz";
      if (!std::isfinite(f)) p.title = set.title + ": mode " + std::to_string(j + 1);
      p.layers.push_back({x, "", "", true});
      p.layers.push_back({io::scaledShape(model, x, shapes.col(j)), "", "#D55E00", false});
      fig.panels.push_back(p);
    }
  }
  fig.notes.push_back(
      "mode shapes x + s F_q v drawn with the largest nodal displacement at 12% of the model size "
      "(rotations at most 0.3 rad); dashed grey: the configuration they belong to");
  const io::MechanismGeometry geometry(model);
  if (geometry.spatial() && view == io::View::Auto) {
    // Which view auto chose, panel by panel (io::panelView), so a reader knows what is seen.
    std::string views;
    for (const io::ShapePanel& p : fig.panels)
      views += std::string(views.empty() ? "" : ", ") + io::viewName(io::panelView(geometry, p, view));
    fig.notes.push_back("views, panel by panel: " + views +
                        " (auto: the one that sees most of the panel's model and motion; axes at its lower right; "
                        "--view sets one for all)");
  }
  io::writeShapesSvg(path, geometry, fig);
}

bool writeStaticFigure(const std::string& path, const core::Model& model, const std::string& modelFile,
                       const analysis::StaticRun& run, io::View view) {
  try {
    std::vector<NamedConfiguration> configs;
    for (const auto& st : run.steps) configs.push_back({loadLabel(st), st.x});
    std::vector<ModeSet> sets;
    if (!run.steps.empty() && run.steps.back().frequencies.modes.cols() > 0) {
      const auto& st = run.steps.back();
      // Static analyses run on the full model: eta = q.
      sets.push_back(
          {loadLabel(st), st.eta, st.frequencies.modes, st.frequencies.omega, model.settings.t0, st.loadFactor});
    }
    writeShapeFigure(path, model, "Static equilibria of " + modelFile, configs, sets, view);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << path << ": " << e.what() << "\n";
    return false;
  }
  std::cout << "wrote " << path << "\n";
  return true;
}

bool writeSweepFigure(const std::string& path, const core::Model& model, const std::string& modelFile,
                      const analysis::SweepResult& sweep, double t, io::View view) {
  try {
    std::vector<Eigen::VectorXd> qs;
    for (const auto& p : sweep.points) qs.push_back(p.q);
    const std::vector<Eigen::VectorXd> xs = positionsOf(model, qs, t);
    std::vector<NamedConfiguration> configs;
    for (size_t i = 0; i < xs.size(); ++i)
      configs.push_back({"value " + io::shortNumber(sweep.points[i].value, 6), xs[i]});
    std::vector<ModeSet> sets;
    std::vector<size_t> ends;
    if (!sweep.points.empty()) ends.push_back(0);
    if (sweep.points.size() > 1) ends.push_back(sweep.points.size() - 1);
    for (size_t i : ends) {
      const auto& p = sweep.points[i];
      sets.push_back({"value " + io::shortNumber(p.value, 6), p.q, p.modes, p.omega, t, 0.0});
    }
    writeShapeFigure(path, model, "Sweep of " + modelFile, configs, sets, view);
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << path << ": " << e.what() << "\n";
    return false;
  }
  std::cout << "wrote " << path << "\n";
  return true;
}

}  // namespace flexmb::cli
