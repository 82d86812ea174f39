// Linear analyses: modes (initial configuration), static (mode 10), sweep (Fig. 5 style).
#include <algorithm>
#include <array>
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <memory>
#include <set>
#include <sstream>
#include <utility>

#include "analysis/ModelCheck.hpp"
#include "analysis/Modes.hpp"
#include "analysis/ModesJob.hpp"
#include "analysis/Participation.hpp"
#include "analysis/SpacarOutput.hpp"
#include "analysis/StaticDesign.hpp"
#include "analysis/StaticJob.hpp"
#include "analysis/Statics.hpp"
#include "analysis/SweepJob.hpp"
#include "io/formats/BasisFile.hpp"
#include "io/formats/OriginalResults.hpp"
#include "io/formats/OutputFile.hpp"
#include "io/formats/ResultWriter.hpp"
#include "io/formats/SpacarResults.hpp"
#include "io/formats/TextOutput.hpp"
#include "io/pictures/DesignPlots.hpp"
#include "io/pictures/SvgPlot.hpp"
#include "io/templates/StudySummary.hpp"
#include "text/NumberText.hpp"
#include "tools/cli/Commands.hpp"
#include "tools/cli/Progress.hpp"
#include "tools/cli/Visuals.hpp"

namespace po = boost::program_options;

namespace flexmb::cli {

namespace {

// What --view auto means for the shape figures (io::panelView).
constexpr const char* kShapeViewAuto =
    "each panel of a spatial model in the one of xy, xz, yz and iso that sees most of its model and of its motion "
    "(the largest product of the shares of the model's length and of its displacements seen), named in the "
    "figure's notes; xy for planar models";
void printFrequencies(std::ostream& o, const Eigen::VectorXd& omega) {
  o << "  mode   f [Hz]          omega [rad/s]\n";
  for (Eigen::Index i = 0; i < omega.size(); ++i) {
    o << "  " << std::setw(4) << i + 1 << "   " << std::setw(14) << std::setprecision(8) << omega[i] / (2 * M_PI)
      << "  " << std::setw(14) << omega[i];
    if (std::abs(omega[i]) < 1e-6 * std::max(1.0, omega.cwiseAbs().maxCoeff()))
      o << "   (rigid / mechanism mode)";
    else if (omega[i] < 0)
      o << "   (unstable: negative stiffness, reported as -sqrt|lambda|)";
    o << "\n";
  }
}

// The effective masses per direction as shares of what all the modes carry (analysis/Participation.hpp),
// their sums, and the model's mass and centre.
void printParticipation(std::ostream& o, const core::Model& model, const Eigen::VectorXd& omega,
                        const analysis::ModalParticipation& p) {
  const Eigen::Index nd = static_cast<Eigen::Index>(p.directions.size());
  const auto point = [&](const Eigen::Vector3d& v) {
    // Appended piece by piece: GCC 12's -Wrestrict misreads "(" + std::string here.
    std::string s(1, '(');
    s.append(text::shortest(v[0])).append(", ").append(text::shortest(v[1]));
    if (model.spatial) s.append(", ").append(text::shortest(v[2]));
    return s.append(")");
  };
  o << "effective masses, % of what all the modes carry per direction (rotations about " << point(p.reference)
    << "):\n  mode   f [Hz]        ";
  for (const auto& d : p.directions) o << std::setw(8) << d;
  o << "\n";
  const std::streamsize precision = o.precision(6);
  const auto pct = [&](double v, Eigen::Index d) {
    const bool known = p.total[d] > 1e-10 * std::abs(p.rigidBody(d, d)) && p.total[d] > 0.0;
    std::ostringstream c;
    if (known)
      c << std::fixed << std::setprecision(2) << 100.0 * v / p.total[d];
    else
      c << "-";
    return c.str();
  };
  for (Eigen::Index i = 0; i < p.effective.rows(); ++i) {
    o << "  " << std::setw(4) << i + 1 << "   " << std::setw(12) << omega[i] / (2 * M_PI) << "  ";
    for (Eigen::Index d = 0; d < nd; ++d) o << std::setw(8) << pct(p.effective(i, d), d);
    o << "\n";
  }
  o << "  sum of these " << std::setw(7) << p.effective.rows() << "  ";
  for (Eigen::Index d = 0; d < nd; ++d) o << std::setw(8) << pct(p.effective.col(d).sum(), d);
  o << "\n  all modes carry (mass; rotations: inertia):";
  for (Eigen::Index d = 0; d < nd; ++d) {  // NaN: M0 singular; round-off of a direction no mode moves: 0
    o << " " << p.directions[d] << " ";
    if (std::isnan(p.total[d]))
      o << "unknown (the mass matrix is singular)";
    else
      o << (pct(1.0, d) == "-" ? 0.0 : p.total[d]);
  }
  o << "\n  the whole model, supports included: mass " << p.mass() << ", centre of mass ";
  const Eigen::Vector3d c = p.centreOfMass();
  o << "(" << c[0] << ", " << c[1] << (model.spatial ? ", " : "");
  if (model.spatial) o << c[2];
  o << ")\n";
  o.precision(precision);
}

}  // namespace

int runModes(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  int nev = 6;
  std::string basisFile, out, svg, html, vtk;
  const std::string htmlHelp =
      std::string("also write a 3-D page that plays each mode shape (default <model>_modes.html)") + kHtmlUrlOptions;
  d.add_options()("nev", po::value(&nev)->notifier(atLeast("nev", 1)), "number of eigenfrequencies (default 6)")(
      "basis", po::value(&basisFile), "reduced model: q = V eta with V from this file")(
      "out", po::value(&out), "SPACAR result files <out>.sbd / .sbm (default: the model's name in the current folder)")(
      "svg", po::value(&svg), "also draw the mode shapes into this SVG file")(
      "html", po::value(&html)->implicit_value("<model>_modes.html"), htmlHelp.c_str())(
      "vtk", po::value(&vtk)->implicit_value("<model>_modes"),
      "also write the mode shapes as a ParaView series <prefix>.pvd (default <model>_modes)");
  std::string viewName, referenceText;
  int referenceNode = 0;
  d.add_options()("reference", po::value(&referenceText),
                  "the point X,Y[,Z] the effective masses' rotations are about (default: the origin)")(
      "reference-node", po::value(&referenceNode)->notifier(atLeast("reference-node", 1)),
      "rotations about this position node instead");
  analysis::DampingOptions damping;  // for the modes' damping ratios
  addDampingOptions(d, damping);
  AccuracyArgs accuracy;
  addAccuracyOptions(d, accuracy);
  addViewOption(d, viewName, kShapeViewAuto);
  if (auto rc = parseCommand(args, d, m,
                             "usage: flexmb modes model.dat [--nev N] [--basis V.csv] [--reference X,Y[,Z] | "
                             "--reference-node N] [--damping-ratio Z[,Z2...]] [--rayleigh ALPHA,BETA] [--out name] "
                             "[--svg file.svg] [--view xy|xz|yz|iso] "
                             "[--html [file.html]] [--vtk [prefix]]"))
    return *rc;
  analysis::ReferencePoint reference;
  try {
    if (!referenceText.empty()) {
      if (referenceNode) throw po::error("--reference and --reference-node name the same point: give one");
      const std::vector<double> v = numberList(referenceText, "reference");
      if (v.size() < 2 || v.size() > 3)
        throw po::error("--reference must be X,Y or X,Y,Z, not '" + referenceText + "'");
      for (std::size_t k = 0; k < v.size(); ++k) reference.point[static_cast<Eigen::Index>(k)] = v[k];
    }
  } catch (const po::error& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kUsageError;
  }
  reference.node = referenceNode;
  const std::string stem = std::filesystem::path(m.file).stem().string();
  if (html == "<model>_modes.html") html = stem + "_modes.html";
  if (vtk == "<model>_modes") vtk = stem + "_modes";
  analysis::ModesOptions mo;
  mo.nev = nev;
  mo.basis.file = basisFile;
  mo.reference = reference;
  mo.damping = damping;
  analysis::AccurateRun<analysis::ModesJob> accurate;  // --accuracy, --error-estimate
  const auto owned = commandJob(m, mo, accuracy, &analysis::modesToAccuracy, accurate,
                                basisFile.empty() ? "" : "run the full model (a basis belongs to one mesh)");
  if (!owned) return kUsageError;
  analysis::ModesJob& job = *owned;
  std::size_t said = showDiagnostics(job, m.quiet);
  if (!jobCanGoOn(job, accuracy.asked())) return exitCodeOf(job.status());
  const core::Model& model = job.model();
  const std::optional<Eigen::MatrixXd>& basis = job.basis();
  // One file set: <out>.sbd / .sbm, the --svg figure and the manifest <out>_run.txt.
  io::OutputSet files(io::OutputSet::resolvePrefix(out, m.file));
  if (!outputsWritable(files, {svg, html, vtk})) return kInputError;
  files.setting("command", "modes");
  recordModel(files, m, model);
  files.setting("nev", std::to_string(job.options().nev));
  if (!basisFile.empty()) files.setting("basis", basisFile);
  if (referenceNode)
    files.setting("reference node", std::to_string(referenceNode));
  else if (!referenceText.empty())
    files.setting("reference point", referenceText);
  if (accuracy.asked()) reportAccuracy(files, accurate.budget, accurate.diagnostics, m.quiet);
  job.run();
  said = showDiagnostics(job, m.quiet, said);
  if (job.status() != analysis::JobStatus::Completed) return kNumericalFailure;
  const analysis::InitialModes& im = job.result();
  const analysis::Frequencies& fr = im.frequencies;
  std::cout << "eigenfrequencies in the initial configuration (" << im.eta.size() << " degrees of freedom):\n";
  printFrequencies(std::cout, fr.omega);
  const Eigen::VectorXd& zeta = job.dampingRatios();
  if (zeta.size()) {
    std::cout << "damping ratio per mode (phi^T C phi / (2 omega mu); C: the model's EDAMP"
              << (damping.any() ? " + " + analysis::dampingText(damping) : std::string()) << "):\n";
    for (Eigen::Index i = 0; i < zeta.size(); ++i)
      std::cout << "  " << std::setw(4) << i + 1 << "   " << std::setprecision(6) << zeta[i] << "\n";
    if (damping.any()) files.setting("added damping", analysis::dampingText(damping));
  }
  if (!im.participation.empty()) {
    printParticipation(std::cout, model, fr.omega, im.participation);
    for (std::size_t k = 0; k < im.participation.directions.size(); ++k)
      files.setting("all modes carry " + im.participation.directions[k],
                    text::shortest(im.participation.total[static_cast<Eigen::Index>(k)]));
  }
  try {
    const io::SpacarResults sr =
        analysis::spacarFromModes(model, model.settings.t0, im.eta, im.system, fr.omega, fr.modes, basis);
    const std::string temp = files.temporaryPrefix();
    for (const auto& p : io::writeSpacarResults(temp, model, sr))
      files.adopt(p, files.prefix() + p.substr(temp.size()));
    // The frequencies' table every front end writes (analysis::modesTable).
    io::writeTextFile(files.temporaryFor("_modes.csv"), io::formatCsv(analysis::modesTable(fr)));
    if (!im.participation.empty())  // analysis::participationTable, as Python's write
      io::writeTextFile(
          files.temporaryFor("_participation.csv"),
          io::formatCsv(analysis::participationTable(fr.omega, im.participation, zeta.size() ? &zeta : nullptr)));
    for (const auto& p : files.renameFiles()) std::cout << "wrote " << p << "\n";
    sayRemovedStale(files.removedStale());
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  // The pictures, each on its own: a failed one leaves the SPACAR files and the other pictures.
  const ModeSet set{"", im.q, basis ? Eigen::MatrixXd(*basis * fr.modes) : fr.modes, fr.omega, model.settings.t0};
  bool complete = true;
  if (!svg.empty())
    complete &= tryProduct(files, "the figure " + svg, [&] {
      writeShapeFigure(svg, model, "Mode shapes of " + m.file, {}, {set}, viewNamed(viewName));
      std::cout << "wrote " << svg << "\n";
      files.record(svg);
    });
  if (!html.empty())
    complete &= tryProduct(files, "the page " + html, [&] {
      if (!writeModesPage(html, model, m.file, set)) throw ProductFailed("see above");
      files.record(html);
    });
  if (!vtk.empty())
    complete &= tryProduct(files, "the VTK series " + vtk, [&] {
      if (!writeModesVtk(vtk, model, set)) throw ProductFailed("see above");
      files.record(vtk + ".pvd");
      files.record(vtk + "_vtu");
    });
  try {
    std::cout << "wrote " << files.writeManifest("complete") << "\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  return complete ? kOk : kWriteFailed;
}

namespace {
// The nodes a static analysis is about: loaded (XF, DELXF, XFT, moments) and driven (INPUTX), in
// label order.
std::vector<int> loadedAndInputNodes(const core::Model& model) {
  std::set<int> nodes;
  auto add = [&](int xi) { nodes.insert(model.nodes[model.xOwnerNode[xi]].label); };
  for (int i = 0; i < model.nx; ++i)
    if ((model.f0.size() && model.f0[i] != 0.0) || (model.delf.size() && model.delf[i] != 0.0)) add(i);
  for (const auto& f : model.timeForces) add(f.index);
  for (const auto& mo : model.moments) nodes.insert(model.nodes[mo.node].label);
  for (const auto& in : model.inputX) add(in.index);
  return {nodes.begin(), nodes.end()};
}

// The displacements x - x0 of those nodes at the last load step (what a user looks for first:
// the tip deflection of a loaded cantilever), one line per node.
void printFinalDisplacements(std::ostream& o, const core::Model& model, const analysis::StaticRun& run) {
  if (run.steps.empty()) return;
  const std::vector<int> nodes = loadedAndInputNodes(model);
  if (nodes.empty()) return;
  const Eigen::VectorXd& x = run.steps.back().x;
  o << "displacements at the last load step (x - X) of the loaded and input nodes:\n";
  for (int label : nodes) {
    const core::Node& n = model.nodes[model.nodeByLabel.at(label)];
    o << "  node " << std::setw(4) << label << ":";
    static const char* position[] = {"dx", "dy", "dz"};
    static const char* euler[] = {"dlambda0", "dlambda1", "dlambda2", "dlambda3"};
    for (int c = 0; c < n.dim(); ++c) {
      const char* name = n.kind == core::NodeKind::Orientation       ? "rotation [rad]"
                         : n.kind == core::NodeKind::EulerParameters ? euler[c]
                                                                     : position[c];
      o << "  " << name << " = " << text::shortest(x[n.firstCoord + c] - model.x0[n.firstCoord + c]);
    }
    o << "\n";
  }
}
// The last load step's largest section forces (the CSV's max_* columns: where they are) and the
// nodal loads applied (its F.* / M.* columns).
void printForcesAndLoads(std::ostream& o, const core::Model& model, const analysis::StaticRun& run) {
  if (run.steps.empty()) return;
  const analysis::StaticStep& last = run.steps.back();
  const auto maxima = analysis::sectionForceMaxima(model, last.sigma);
  if (!maxima.empty()) o << "largest section forces at the last load step (over the elements that deform):\n";
  for (const auto& f : maxima) {
    o << "  " << f.name << " = " << io::shortNumber(f.value, 6) << " " << io::quantityUnit(f.name);
    if (f.element >= 0)
      o << " (" << model.elements[f.element].type->keyword << " " << model.elements[f.element].label << ")";
    o << "\n";
  }
  const auto loads = analysis::appliedNodalLoads(model, last);
  if (!loads.empty()) o << "nodal loads applied at the last load step (gravity apart):\n";
  for (const auto& [name, value] : loads) o << "  " << name << " = " << io::shortNumber(value, 6) << "\n";
}
// The last load step's largest von Mises stress, the support reactions with the sums of forces that
// check them against the loads, and the compliance of the named nodes (analysis/StaticDesign.hpp).
void printStressReactionsCompliance(std::ostream& o, const core::Model& model, const analysis::StaticRun& run,
                                    const analysis::StaticCompliances& compliances) {
  if (run.steps.empty()) return;
  const analysis::StaticStep& last = run.steps.back();
  const analysis::ElementStress top = analysis::largestStress(model, last);
  if (top.element >= 0)
    o << "largest von Mises stress at the last load step: " << io::shortNumber(top.vonMises, 6) << " Pa ("
      << model.elements[top.element].type->keyword << " " << model.elements[top.element].label
      << "; sections from VISUALIZATION's CROSSDIM)\n";
  const auto reactions = analysis::supportReactions(model, last);
  if (!reactions.empty()) o << "support reactions at the last load step (the supports' forces on the model):\n";
  for (const auto& [name, value] : reactions) o << "  " << name << " = " << io::shortNumber(value, 6) << "\n";
  if (compliances.empty() || compliances.back().empty()) return;
  o << "compliance at the last load step (displacement per unit load; m/N, rad/N, m/(N m), rad/(N m)):\n";
  for (const auto& nc : compliances.back()) {
    o << "  node " << nc.label << ":";
    for (const auto& n : nc.names) o << " " << std::setw(12) << n;
    o << "\n";
    if (!nc.C.size()) {
      o << "    none: K0 + G0 is singular\n";
      continue;
    }
    for (Eigen::Index r = 0; r < nc.C.rows(); ++r) {
      o << "  " << std::setw(8) << nc.names[static_cast<size_t>(r)] << ":";
      for (Eigen::Index c = 0; c < nc.C.cols(); ++c) o << " " << std::setw(12) << io::shortNumber(nc.C(r, c), 6);
      o << "\n";
    }
  }
}

// --compliance 3,5: node labels.
std::vector<int> nodeLabelList(const std::string& text) {
  std::vector<int> labels;
  if (text.empty()) return labels;
  for (double v : numberList(text, "compliance")) {
    if (v != std::floor(v) || v < 0 || v > 1e9) throw po::error("--compliance must be node labels, not '" + text + "'");
    labels.push_back(static_cast<int>(v));
  }
  return labels;
}

// SPACAR's <model>.sbd / .sbm beside the CSV, with SPACAR Light's stressmax, Freac, Mreac and the
// compliances in the .sbd (analysis::spacarDesignVariables); temporary names adopted by `files`.
void writeStaticSpacar(io::OutputSet& files, const std::string& base, const core::Model& model,
                       const analysis::StaticRun& run, const analysis::StaticCompliances& compliances, bool ltv,
                       bool matrices) {
  analysis::SpacarOutputOptions spo;
  // SPACAR's set unless --matrices none: SPACAR Light reads dx and bigd of the load steps in the .sbd
  // and m0, k0, g0, n0 of every step in the .sbm (spacarlight.m).
  spo.transferFunctions = spo.jacobian = spo.matrices = matrices;
  io::SpacarResults sr =
      ltv ? analysis::spacarFromStaticPerturbation(model, run, spo) : analysis::spacarFromStatics(model, run, spo);
  sr.extraSbd = analysis::spacarDesignVariables(model, run, compliances);
  const std::string tempBase = io::temporaryName(base);
  for (const auto& p : io::writeSpacarResults(tempBase, model, sr)) files.adopt(p, base + p.substr(tempBase.size()));
}

// Each load step: its factors, Newton iterations, frequencies and buckling load factors.
void printStaticSteps(std::ostream& screen, const analysis::StaticRun& run, int buckling) {
  for (const auto& st : run.steps) {
    if (st.loadStep >= 0)
      screen << "load step " << st.loadStep << " of " << run.loadSteps;
    else
      screen << "initial loads ramp";
    screen << " (initial loads x " << st.initialFactor << ", DEL* increments x " << st.loadFactor
           << "): " << st.iterations << " Newton iterations";
    if (!st.newton.stable)
      screen << " (UNSTABLE equilibrium" << (st.kinetic ? ": " + analysis::stabilityVerdict(st) : "") << ")";
    screen << "\n";
    if (st.frequencies.omega.size()) printFrequencies(screen, st.frequencies.omega);
    // The frequencies come from the symmetric part K0 + G0 (a semi-tangential moment's tangent); say
    // which criterion the flag used where the two can disagree.
    const bool negative = st.frequencies.omega.size() && st.frequencies.omega.minCoeff() < 0.0;
    if (st.kinetic && (negative || !st.newton.stable || st.kinetic->verdict == solvers::KineticVerdict::Undecided))
      screen << "  stability under the dead moments (kinetic: eigenvalues of K0 + G0 + Gskew, M0 nearest zero): "
             << st.kinetic->describe() << "; the frequencies above are those of K0 + G0 alone\n";
    if (buckling > 0) {
      screen << "  buckling load factors:";
      for (Eigen::Index i = 0; i < st.buckling.size(); ++i) screen << " " << st.buckling[i];
      if (st.buckling.size() == 0) screen << " none (K0 not positive definite or no compressive G0)";
      screen << "\n";
    }
  }
}

// The pictures of a static run asked for (--svg, --html, --vtk), each on its own (tryProduct): false
// when one failed.
bool writeStaticPictures(io::OutputSet& files, const std::string& svg, io::View view, const std::string& html,
                         const std::string& vtk, const core::Model& model, const std::string& modelFile,
                         const analysis::StaticRun& run) {
  bool complete = true;
  if (!svg.empty())
    complete &= tryProduct(files, "the figure " + svg, [&] {
      if (!writeStaticFigure(svg, model, modelFile, run, view)) throw ProductFailed("see above");
      files.record(svg);
    });
  if (!html.empty())
    complete &= tryProduct(files, "the page " + html, [&] {
      if (!writeStaticPage(html, model, modelFile, run)) throw ProductFailed("see above");
      files.record(html);
    });
  if (!vtk.empty())
    complete &= tryProduct(files, "the VTK series " + vtk, [&] {
      if (!writeStaticVtk(vtk, model, run)) throw ProductFailed("see above");
      files.record(vtk + ".pvd");
      files.record(vtk + "_vtu");
    });
  return complete;
}

// --plot COORDS of static and sweep: each coordinate a known one (a usage error listing the model's
// coordinates otherwise); a refined model's original ones, as its table has them.
bool plotCoordinatesKnown(const core::Model& model, const std::vector<std::string>& coordinates) {
  try {
    for (const auto& c : coordinates) io::coordinateIndex(io::resultModel(model), c);
  } catch (const std::invalid_argument& e) {
    std::cerr << "flexmb: --plot: " << e.what() << "\n";
    return false;
  }
  return true;
}

// <prefix>_force_deflection.svg: the panels of io::staticForceDeflectionPlots or
// io::sweepForceDeflectionPlots (made inside, so that a failure is this product's only).
bool writeForceDeflection(io::OutputSet& files, const std::function<std::vector<io::Plot>()>& panels) {
  const std::string path = files.prefix() + "_force_deflection.svg";
  return tryProduct(files, "the force-deflection plot " + path, [&] {
    io::writeSvgStack(path, panels());
    files.record(path);
    std::cout << "wrote " << path << "\n";
  });
}

// The CSV column of a sweep's prescribed coordinate ("node6.x"; "value", the sweep table's, for a
// spatial orientation node's rotation) and the x axis's words for it ("x(node 6, x) [m]").
std::pair<std::string, std::string> sweptColumn(const core::Model& model, const analysis::SweepOptions& o) {
  const auto at = model.nodeByLabel.find(o.node);
  if (at == model.nodeByLabel.end()) return {"value", "prescribed value"};  // the job has said why
  const core::Node& node = model.nodes[at->second];
  if (node.kind == core::NodeKind::EulerParameters)
    return {"value",
            "rotation of node " + std::to_string(o.node) + " about global " + "xyz"[o.component - 1] + " [rad]"};
  const int k = node.firstCoord + o.component - 1;
  const std::string name = io::coordinateColumnNames(model)[static_cast<std::size_t>(k)];
  const std::string unit = io::coordinateUnit(name);
  return {name, model.coordName(k) + (unit.empty() ? "" : " [" + unit + "]")};
}

// static --plot COORDS (empty: nothing to draw).
bool writeStaticForceDeflection(io::OutputSet& files, const core::Model& model, const analysis::StaticRun& run,
                                int buckling, const std::string& plot, const std::string& modelFile) {
  if (plot.empty() || run.steps.empty()) return true;
  return writeForceDeflection(files, [&] {
    return io::staticForceDeflectionPlots(model, analysis::staticTable(model, run, buckling), io::commaList(plot),
                                          modelFile + ": load against deflection over the load steps");
  });
}

constexpr const char* kPlotHelp =
    "COORDS: coordinates as the CSV names them, separated by commas (node6.x,node6.y): per coordinate the load "
    "along it (its F.* or M.* column; the load factor where none is applied there) against its deflection from the "
    "initial configuration over the load steps, a panel each in <prefix>_force_deflection.svg";

}  // namespace

// Why static's --format, --matrices and --ltv do not go together (empty: they do).
std::string staticFilesRefusal(const std::string& format, const std::string& matrices, bool ltv) {
  if (format != "csv" && format != "mat" && format != "both" && format != "none")
    return "--format must be csv, mat, both or none, not '" + format + "'";
  if (matrices != "all" && matrices != "none") return "--matrices must be all or none, not '" + matrices + "'";
  if (ltv && matrices == "none")
    return "--ltv writes the matrices of every load step: it cannot go with --matrices none";
  if (ltv && (format == "csv" || format == "none"))
    return "--ltv writes SPACAR's .ltv beside the .sbd: it needs --format mat or both";
  return "";
}

// The static run's manifest settings: the command, the model, the settled options and the files asked.
void describeStatic(io::OutputSet& files, const ModelOptions& m, const analysis::StaticJob& job,
                    const std::array<std::string, 3>& formatMatricesCompliance) {
  const auto& [format, matrices, compliance] = formatMatricesCompliance;
  files.setting("command", "static");
  recordModel(files, m, job.model());
  files.setting("load steps", std::to_string(job.options().loadSteps));
  files.setting("nev", std::to_string(job.options().nev));
  files.setting("format", format);
  files.setting("matrices", matrices);
  if (job.options().buckling > 0) files.setting("buckling load factors", std::to_string(job.options().buckling));
  if (!compliance.empty()) files.setting("compliance nodes", compliance);
}

int runStatic(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  int nev = 6, steps = 0, buckling = 0;
  bool ltv = false;
  std::string out, svg, html, vtk, format = "both", matrices = "all", compliance, plot;
  analysis::StaticOptions so;
  const std::string htmlHelp = std::string(
                                   "also write a 3-D page that plays the load steps and the last one's mode "
                                   "shapes (default: beside the CSV)") +
                               kHtmlUrlOptions;
  d.add_options()("nev", po::value(&nev)->notifier(atLeast("nev", 0)), "eigenfrequencies per equilibrium (default 6)")(
      "matrices", po::value(&matrices),
      "with SPACAR's files: all (default, as SPACAR writes them and SPACAR Light reads them: M0 .. N0 of every load "
      "step in the .sbm, the transfer functions dx and D = de/dx of every step in the .sbd) or none (the states, "
      "stresses, forces and frequencies only: a large model's files shrink from tens of MB to a few)")(
      "format", po::value(&format),
      "csv (the load steps' table), mat (SPACAR's <model>.sbd / .sbm, which SPACAR's scripts read), both (default, "
      "as SPACAR writes its files) or none")(
      "ltv", po::bool_switch(&ltv),
      "SPACAR's mode 3 on a static file (`--mode 3`): also M0 and K0B = K0 + N0 + G0 over every kinematic degree "
      "of freedom, inputs included, per load step in <model>.ltv (mode 3 in the .sbd)")(
      "steps", po::value(&steps)->notifier(atLeast("steps", 1)), "load steps (default: ITERSTEP's second field)")(
      "compliance",
      po::value(&compliance)->notifier([&so](const std::string& v) { so.complianceNodes = nodeLabelList(v); }),
      "NODES: node labels separated by commas; the compliance matrix of each at every load step (K0 + G0 at the "
      "equilibrium; a position node with the orientation node of its beam end: planar 3 x 3, spatial 6 x 6) in "
      "<prefix>_compliance.csv, on screen (last load step) and in the .sbd (CMglob_node<N>)")(
      "buckling", po::value(&buckling)->implicit_value(3)->notifier(atLeast("buckling", 0)),
      "buckling load factors per equilibrium (SPACAR mode 8: (K0 + mu G0) v = 0; default 3 when given)")(
      "out", po::value(&out),
      "CSV with the equilibria: a file name, a prefix or a folder (default: <model>_static.csv); per load step the "
      "coordinates, frequencies, buckling factors, then the largest section forces max_*, the nodal loads F.*, M.*, "
      "the largest von Mises stress max_stress and its element, the support reactions R.*; beside it "
      "<prefix>_stress.csv (each element's von Mises stress) when VISUALIZATION gives sections")(
      "svg", po::value(&svg), "also draw the equilibria and the last one's mode shapes into this SVG file")(
      "plot", po::value(&plot), kPlotHelp)("html", po::value(&html)->implicit_value("<prefix>.html"), htmlHelp.c_str())(
      "vtk", po::value(&vtk)->implicit_value("<prefix>"),
      "also write the load steps as a ParaView series <prefix>.pvd (default: beside the CSV)");
  std::string viewName;
  addViewOption(d, viewName, kShapeViewAuto);
  AccuracyArgs accuracy;
  addAccuracyOptions(d, accuracy);
  if (auto rc = parseCommand(
          args, d, m,
          "usage: flexmb static model.dat [--nev N] [--steps n] [--buckling [N]] [--compliance NODES] [--ltv] "
          "[--matrices all|none] [--format "
          "csv|mat|both|none] [--out file.csv] [--svg file.svg] [--plot COORDS] [--view xy|xz|yz|iso] [--html "
          "[file.html]] [--vtk [prefix]]"))
    return *rc;
  if (const std::string why = staticFilesRefusal(format, matrices, ltv); !why.empty()) {
    std::cerr << "flexmb: " << why << "\n";
    return kUsageError;
  }
  const bool writeCsv = format == "csv" || format == "both", writeSpacar = format == "mat" || format == "both";
  so.nev = nev;
  so.loadSteps = steps;
  so.buckling = buckling;
  analysis::AccurateRun<analysis::StaticJob> accurate;  // --accuracy, --error-estimate
  const auto owned = commandJob(m, so, accuracy, &analysis::staticToAccuracy, accurate, "");
  if (!owned) return kUsageError;
  analysis::StaticJob& job = *owned;
  std::size_t said = showDiagnostics(job, m.quiet);
  if (!jobCanGoOn(job, accuracy.asked())) return exitCodeOf(job.status());
  const core::Model& model = job.model();
  if (!plotCoordinatesKnown(model, io::commaList(plot))) return kUsageError;
  if (ltv && model.unrefined) {  // the .ltv is over the degrees of freedom: the original layout has no place for it
    std::cerr << "flexmb: --ltv writes the refined model's matrices over its degrees of freedom: it needs "
                 "--refined-results with --refine\n";
    return kUsageError;
  }
  // Output: --out file.csv, a prefix, or a folder; checked before the analysis. One file set: the
  // CSV, SPACAR's <model>.sbd / .sbm beside it, the --svg figure, the manifest <prefix>_run.txt.
  std::string csvPath;
  if (out.size() > 4 && out.compare(out.size() - 4, 4, ".csv") == 0)
    csvPath = out;
  else
    csvPath = io::OutputSet::resolvePrefix(out, m.file, "_static") + ".csv";
  io::OutputSet files(csvPath.substr(0, csvPath.size() - 4));
  const std::string prefix = csvPath.substr(0, csvPath.size() - 4);
  if (html == "<prefix>.html") html = prefix + ".html";
  if (vtk == "<prefix>") vtk = prefix;
  if (!outputsWritable(files, {svg, html, vtk})) return kInputError;
  describeStatic(files, m, job, {format, matrices, compliance});
  if (accuracy.asked()) reportAccuracy(files, accurate.budget, accurate.diagnostics, m.quiet);

  installInterruptHandler();
  Progress progress("static", !m.quiet);
  job.run({[&](int i, int total) { progress.update(i, total, "load steps"); }, interruptFlag(), interruptSignal()});
  const analysis::StaticRun& run = job.result();
  progress.finish();
  try {
    // -q: the load steps are not listed (the final displacements and the files still are).
    std::ostringstream quietSteps;
    std::ostream& screen = m.quiet ? static_cast<std::ostream&>(quietSteps) : std::cout;
    printStaticSteps(screen, run, buckling);
    // The table every front end writes for a static run (analysis::staticTable).
    if (writeCsv) {
      io::writeTextFile(files.temporaryPath(csvPath), io::formatCsv(analysis::staticTable(model, run, buckling)));
      if (!analysis::stressedElements(model).empty())
        io::writeTextFile(files.temporaryPath(prefix + "_stress.csv"),
                          io::formatCsv(analysis::stressTable(model, run)));
      if (!job.compliances().empty())
        io::writeTextFile(files.temporaryPath(prefix + "_compliance.csv"),
                          io::formatCsv(analysis::complianceTable(run, job.compliances())));
    }
    printFinalDisplacements(std::cout, model, run);
    printForcesAndLoads(std::cout, model, run);
    printStressReactionsCompliance(std::cout, model, run, job.compliances());
    files.renameFiles();  // the load steps' CSV first: nothing after it can take it away
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  // SPACAR's <model>.sbd / .sbm beside the CSV (io/results.md; the steps reached), then the pictures:
  // each on its own (tryProduct).
  bool complete = !writeSpacar || tryProduct(files, "SPACAR's .sbd/.sbm", [&] {
    const auto base = (std::filesystem::path(csvPath).parent_path() / std::filesystem::path(m.file).stem()).string();
    writeStaticSpacar(files, base, model, run, job.compliances(), ltv, matrices == "all");
  });
  try {
    for (const auto& p : files.renameFiles()) std::cout << "wrote " << p << "\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    complete = false;
  }
  sayRemovedStale(files.removedStale());
  complete &= writeStaticPictures(files, svg, viewNamed(viewName), html, vtk, model, m.file, run);
  complete &= writeStaticForceDeflection(files, model, run, buckling, plot, m.file);
  try {
    files.writeManifest(run.completed ? "complete" : "stopped: " + run.stopReason);
    std::cout << "wrote " << files.manifestPath() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  showDiagnostics(job, m.quiet, said);  // a stop: why, and that the load steps before it are written
  if (job.status() != analysis::JobStatus::Completed) return exitCodeOf(job.status());
  return complete ? kOk : kWriteFailed;
}

// The sweep's largest von Mises stress and each support reaction's largest magnitude over its
// configurations, with where they occur (the CSV's max_stress and R.* columns; issue 53 item 1).
void printSweepStressAndReactions(std::ostream& o, const io::CsvTable& table) {
  const auto column = [&](const std::string& name) {
    const auto it = std::find(table.columns.begin(), table.columns.end(), name);
    return it == table.columns.end() ? -1 : static_cast<int>(it - table.columns.begin());
  };
  const int value = column("value"), stress = column("max_stress"), element = column("max_stress_element");
  const auto largest = [&](int c) {  // the row with the largest finite |value| in column c, or -1
    int best = -1;
    for (size_t r = 0; r < table.rows.size(); ++r)
      if (std::isfinite(table.rows[r][c]) && (best < 0 || std::abs(table.rows[r][c]) > std::abs(table.rows[best][c])))
        best = static_cast<int>(r);
    return best;
  };
  if (stress >= 0)
    if (const int r = largest(stress); r >= 0)
      o << "largest von Mises stress over the sweep: " << io::shortNumber(table.rows[r][stress], 6) << " Pa (element "
        << table.rows[r][element] << ", at value " << io::shortNumber(table.rows[r][value], 6)
        << "; sections from VISUALIZATION's CROSSDIM)\n";
  bool said = false;
  for (size_t c = 0; c < table.columns.size(); ++c) {
    if (table.columns[c].rfind("R.", 0) != 0) continue;
    const int r = largest(static_cast<int>(c));
    if (r < 0) continue;
    if (!said) o << "largest support reactions over the sweep (the supports' forces on the model):\n";
    said = true;
    o << "  " << table.columns[c] << " = " << io::shortNumber(table.rows[r][c], 6) << " at value "
      << io::shortNumber(table.rows[r][value], 6) << "\n";
  }
}

int runSweep(const std::vector<std::string>& args) {
  ModelOptions m;
  po::options_description d = commonModelOptions(m);
  analysis::SweepOptions o;
  std::string out, basisFile, svg;
  std::string plot;  // --plot alone: "prescribed"
  d.add_options()("node", po::value(&o.node)->required(), "node label of the prescribed coordinate (required)")(
      "comp", po::value(&o.component)->default_value(1)->notifier(atLeast("comp", 1)),
      "its component (1-based; a spatial orientation node: 1, 2, 3 = its rotation about global x, y, z in rad from "
      "its initial orientation)")(
      "from", po::value(&o.from)->required()->notifier(finite("from")),
      "first value (required): a position component's absolute coordinate (not a displacement from the node's "
      "initial position); an orientation node's rotation from its initial orientation")(
      "to", po::value(&o.to)->required()->notifier(finite("to")), "last value (required), as --from")(
      "steps", po::value(&o.steps)->default_value(10)->notifier(atLeast("steps", 1)),
      "number of equidistant configurations (the continuation sub-steps them as it needs)")(
      "nev", po::value(&o.nev)->default_value(4)->notifier(atLeast("nev", 1)), "eigenfrequencies per configuration")(
      "basis", po::value(&basisFile), "reduced model: q = V eta with V from this file")(
      "out", po::value(&out), "output prefix or folder (default: <model>_sweep): CSV and SVG")(
      "svg", po::value(&svg), "also draw the configurations and the first and last mode shapes into this SVG file")(
      "plot", po::value(&plot)->implicit_value("prescribed"),
      "[COORDS]: the load that holds the prescribed coordinate against the deflection of each of these coordinates "
      "(as the CSV names them, separated by commas; `prescribed`, the default: the prescribed one) from the initial "
      "configuration, a panel each in <prefix>_force_deflection.svg");
  std::string viewName;
  addViewOption(d, viewName, kShapeViewAuto);
  AccuracyArgs accuracy;
  addAccuracyOptions(d, accuracy);
  if (auto rc = parseCommand(args, d, m,
                             "usage: flexmb sweep model.dat --node N --comp i --from a --to b --steps n [--nev N] "
                             "[--svg file.svg] [--plot [COORDS]] [--view xy|xz|yz|iso]"))
    return *rc;
  analysis::AccurateRun<analysis::SweepJob> accurate;  // --accuracy, --error-estimate
  const auto owned = commandJob(m, o, accuracy, &analysis::sweepToAccuracy, accurate,
                                basisFile.empty() ? "" : "run the full model (a basis belongs to one mesh)",
                                analysis::BasisInput{basisFile, std::nullopt});
  if (!owned) return kUsageError;
  analysis::SweepJob& job = *owned;
  std::size_t said = showDiagnostics(job, m.quiet);
  if (!jobCanGoOn(job, accuracy.asked())) return exitCodeOf(job.status());
  const core::Model& model = job.model();
  const std::pair<std::string, std::string> sweptName = sweptColumn(model, o);
  std::vector<std::string> plotted = io::commaList(plot);
  for (auto& c : plotted)
    if (c == "prescribed") c = sweptName.first;
  std::vector<std::string> coordinates;  // "value", a rotation's column, is the sweep table's own
  std::copy_if(plotted.begin(), plotted.end(), std::back_inserter(coordinates), [](auto& c) { return c != "value"; });
  if (!plotCoordinatesKnown(model, coordinates)) return kUsageError;
  o.nev = job.options().nev;
  std::string suffix = "_sweep";
  if (!basisFile.empty()) suffix += "_" + std::filesystem::path(basisFile).stem().string();
  io::OutputSet files(io::OutputSet::resolvePrefix(out, m.file, suffix));
  if (!outputsWritable(files, {svg})) return kInputError;
  const std::string prefix = files.prefix();
  if (!svg.empty() && std::filesystem::absolute(svg) == std::filesystem::absolute(prefix + ".svg")) {
    std::cerr << "flexmb: --svg " << svg << " is the frequency plot's own file (" << prefix
              << ".svg): give the configuration figure another name\n";
    return kUsageError;
  }
  files.setting("command", "sweep");
  recordModel(files, m, model);
  files.setting("prescribed", "node " + std::to_string(o.node) + " component " + std::to_string(o.component));
  files.setting("range", text::shortest(o.from) + " to " + text::shortest(o.to) + " in " + std::to_string(o.steps) +
                             " configurations");
  files.setting("nev", std::to_string(o.nev));
  if (!basisFile.empty()) files.setting("basis", basisFile);
  if (accuracy.asked()) reportAccuracy(files, accurate.budget, accurate.diagnostics, m.quiet);

  installInterruptHandler();
  Progress progress("sweep", !m.quiet);
  job.run({[&](int i, int total) { progress.update(i, total, "configurations"); }, interruptFlag(), interruptSignal()});
  const analysis::SweepResult& r = job.result();
  if (job.status() == analysis::JobStatus::InputError) {
    progress.finish();
    showDiagnostics(job, m.quiet, said);
    return kInputError;
  }
  progress.finish();
  const io::CsvTable table = analysis::sweepTable(model, r);  // what every front end writes for a sweep
  try {
    std::cout << "  value          load           frequencies [Hz]\n";
    for (const auto& p : r.points) {
      std::cout << "  " << std::setw(12) << p.value << "  " << std::setw(12) << p.load << " ";
      for (int i = 0; i < o.nev && i < p.omegaSorted.size(); ++i)
        std::cout << "  " << std::setw(10) << p.omegaSorted[i] / (2 * M_PI);
      std::cout << "\n";
    }
    printSweepStressAndReactions(std::cout, table);
    io::writeTextFile(files.temporaryFor(".csv"), io::formatCsv(table));
    // A panel per group of modes (io::modeGroups): 5 Hz and 500 Hz never share a linear axis.
    if (!r.points.empty())
      io::writeSvgStack(files.temporaryFor(".svg"),
                        io::frequencyPanels(table, "value", "prescribed " + sweptName.second,
                                            "Eigenfrequencies against " + r.prescribed));
    files.renameFiles();
    std::cout << "wrote " << prefix << ".csv" << (r.points.empty() ? "" : " and " + prefix + ".svg") << " ("
              << r.points.size() << " of " << o.steps << " configurations)\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  bool complete = true;  // the picture on its own: a failure leaves the CSV and the manifest
  if (!plotted.empty() && !r.points.empty()) {
    const std::string unit = sweptName.first == "value"                   ? "N m"
                             : io::coordinateUnit(sweptName.first) == "m" ? "N"
                                                                          : "N m";
    complete &= writeForceDeflection(files, [&] {
      return io::sweepForceDeflectionPlots(model, table, plotted, "prescribed " + sweptName.second, unit,
                                           m.file + ": the load that holds " + r.prescribed);
    });
  }
  if (!svg.empty())
    complete = tryProduct(files, "the figure " + svg, [&] {
      if (!writeSweepFigure(svg, model, m.file, r, o.t, viewNamed(viewName))) throw ProductFailed("see above");
      files.record(svg);
    });
  try {
    std::cout << "wrote " << files.writeManifest(r.completed ? "complete" : "stopped: " + r.stopReason) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "flexmb: " << e.what() << "\n";
    return kWriteFailed;
  }
  showDiagnostics(job, m.quiet, said);  // a stop: why, and how many configurations before it are written
  if (job.status() != analysis::JobStatus::Completed) return exitCodeOf(job.status());
  return complete ? kOk : kWriteFailed;
}

}  // namespace flexmb::cli
