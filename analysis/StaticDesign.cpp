#include "analysis/StaticDesign.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "analysis/TrajectoryModes.hpp"
#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/ResultQuantities.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/OriginalResults.hpp"
#include "io/formats/ResultWriter.hpp"

namespace flexmb::analysis {

namespace {

using Section = core::ElementAppearance::Section;

// St Venant torsion constant of an h x b rectangle (h <= b): the series SPACAR Light uses.
double torsionConstant(double h, double b) {
  const double a = h / 2, c = b / 2;
  double sum5 = 0.0;
  for (int n = 1; n <= 201; n += 2) {
    const double term = std::tanh(n * M_PI * c / (2 * a)) / std::pow(n, 5);
    sum5 += term;
    if (n >= 3 && term < 1e-12 * sum5) break;
  }
  return std::pow(2 * a, 3) * (2 * c) / 3 * (1 - 192 / std::pow(M_PI, 5) * (a / c) * sum5);
}

// |shear| of St Venant torsion at u in [-1/2, 1/2] along a side of an h x b rectangle (h <= b), per
// unit G theta: the long side (length b) Gtheta h [1 - 8/pi^2 sum cosh(n pi x/h)/(n^2 cosh(n pi b/2h))],
// the short side (length h) Gtheta 8 h/pi^2 |sum (-1)^((n-1)/2) tanh(n pi b/2h) cos(n pi x/h)/n^2|.
double torsionShearPerTwist(double h, double b, bool longSide, double u) {
  double acc = 0.0;
  for (int n = 1; n <= 401; n += 2) {
    double term;
    if (longSide) {
      const double x = std::abs(u * b);  // cosh(n pi x/h)/cosh(n pi b/2h) without overflow
      term = std::exp(n * M_PI * (x - b / 2) / h) * (1 + std::exp(-2 * n * M_PI * x / h)) /
             (1 + std::exp(-n * M_PI * b / h)) / (n * n);
    } else {
      const double x = u * h;
      term =
          (((n - 1) / 2) % 2 ? -1.0 : 1.0) * std::tanh(n * M_PI * b / (2 * h)) * std::cos(n * M_PI * x / h) / (n * n);
    }
    acc += term;
    if (std::abs(term) < 1e-14 * std::max(std::abs(acc), 1e-300)) break;
  }
  return longSide ? h * (1 - 8 / (M_PI * M_PI) * acc) : 8 * h / (M_PI * M_PI) * std::abs(acc);
}

double rectangleVonMises(double w, double t, const SectionLoads& L) {
  const double A = w * t, Iy = w * t * t * t / 12, Iz = t * w * w * w / 12, Cw = w * w * w * t * t * t / 144;
  const double h = std::min(w, t), b = std::max(w, t);
  const double twist = L.T != 0.0 ? std::abs(L.T) / torsionConstant(h, b) : 0.0;  // G theta
  constexpr int kPoints = 101;
  double vm = 0.0;
  for (int side = 0; side < 2; ++side) {  // 0: the sides z = +-t/2 (u along y); 1: y = +-w/2 (u along z)
    const bool longSide = side == 0 ? w >= t : w < t;
    for (int k = 0; k < kPoints; ++k) {
      const double u = -0.5 + static_cast<double>(k) / (kPoints - 1);
      const double y = side == 0 ? u * w : w / 2, z = side == 0 ? t / 2 : u * t;
      const double tau = twist > 0.0 ? twist * torsionShearPerTwist(h, b, longSide, u) : 0.0;
      for (double sy : {-1.0, 1.0})
        for (double sz : {-1.0, 1.0}) {
          double s = L.N / A + L.My * sz * z / Iy - L.Mz * sy * y / Iz;
          // The bimoment's B y z / Cw with the sign that makes |s| largest (a bound; exact without it).
          s = (s < 0 ? -1.0 : 1.0) * (std::abs(s) + std::abs(L.B * y * z) / Cw);
          vm = std::max(vm, std::sqrt(s * s + 3 * tau * tau));
        }
    }
  }
  return vm;
}

// The section forces at the two ends of an element from its generalised stresses g and deformations
// e (l0 times the moments' generalised stresses); empty for an element that is not a beam or truss.
std::vector<SectionLoads> endLoads(const core::Model& model, const core::ElementEntry& el, const Eigen::VectorXd& g,
                                   const Eigen::VectorXd& e) {
  const int nd = el.type->numDeformations();
  const double l0 = elementLength(model, el);
  using K = core::DeformationKind;
  if (nd == 1 && el.type->deformationKind(0) == K::Elongation) return {{g[0]}};
  if (nd == 3 && el.type->deformationKind(1) == K::Bending) {
    // Planar: the in-plane moment bends across the thickness (about the local y axis).
    return {{g[0], 0.0, l0 * g[1]}, {g[0], 0.0, l0 * g[2]}};
  }
  if (nd == 6 && el.type->deformationKind(1) == K::Torsion)
    return {{g[0], l0 * g[1], l0 * g[2], l0 * g[4]}, {g[0], l0 * g[1], l0 * g[3], l0 * g[5]}};
  if (nd == 8 && el.type->deformationKind(1) == K::Torsion) {
    const double T = l0 * (g[1] - g[6] - g[7]);
    const double ecw = el.stiffnessParams.size() >= 7 ? el.stiffnessParams[6] : 0.0;
    const double l3 = l0 * l0 * l0;
    return {{g[0], T, l0 * g[2], l0 * g[4], ecw * (4 * e[6] + 2 * e[7]) / l3},
            {g[0], T, l0 * g[3], l0 * g[5], ecw * (2 * e[6] + 4 * e[7]) / l3}};
  }
  return {};
}

bool hasElasticDeformation(const core::Model& m, const core::ElementEntry& el) {
  for (int k = 0; k < el.type->numDeformations(); ++k) {
    const core::Role r = m.eRole[el.firstDef + k];
    if (r == core::Role::Dynamic || r == core::Role::Calculable) return true;
  }
  return false;
}

bool isOrientation(core::NodeKind k) {
  return k == core::NodeKind::Orientation || k == core::NodeKind::EulerParameters;
}

// The orientation node a position node shares a beam end with (the slot after it), or the position
// node of an orientation node (the slot before it); -1 when no element pairs them.
int partnerNode(const core::Model& m, int node) {
  const bool orientation = isOrientation(m.nodes[node].kind);
  for (const auto& el : m.elements)
    for (size_t s = 0; s < el.nodes.size(); ++s) {
      if (el.nodes[s] != node) continue;
      if (!orientation && s + 1 < el.nodes.size() && isOrientation(m.nodes[el.nodes[s + 1]].kind))
        return el.nodes[s + 1];
      if (orientation && s > 0 && core::isTranslational(m.nodes[el.nodes[s - 1]].kind)) return el.nodes[s - 1];
    }
  return -1;
}

// B (4 x 3): the generalised force on the Euler parameters lambda of a global moment M is B M.
Eigen::Matrix<double, 4, 3> momentToEuler(const Eigen::Vector4d& lambda) {
  Eigen::Matrix<double, 4, 3> B;
  for (int k = 0; k < 3; ++k) B.col(k) = core::momentMatrix(Eigen::Vector3d::Unit(k)) * lambda;
  return B;
}

const char* kXyz[] = {"x", "y", "z"};

}  // namespace

double sectionVonMises(const core::ElementAppearance& s, const SectionLoads& L) {
  if (s.section == Section::Rectangle && s.width > 0.0 && s.thickness > 0.0)
    return rectangleVonMises(s.width, s.thickness, L);
  if (s.section == Section::Circle && s.width > 0.0) {
    const double r = s.width / 2, A = M_PI * r * r, I = M_PI * std::pow(s.width, 4) / 64, Ip = 2 * I;
    const double sigma = std::abs(L.N) / A + std::hypot(L.My, L.Mz) * r / I, tau = std::abs(L.T) * r / Ip;
    return std::sqrt(sigma * sigma + 3 * tau * tau);
  }
  return 0.0;
}

std::vector<int> stressedElements(const core::Model& m) {
  std::vector<int> out;
  for (size_t i = 0; i < m.elements.size(); ++i) {
    const auto& el = m.elements[i];
    const auto look = m.appearance.find(el.label);
    if (look == m.appearance.end() || look->second.section == Section::Unknown || el.type->internal) continue;
    if (!hasElasticDeformation(m, el)) continue;
    if (endLoads(m, el, Eigen::VectorXd::Zero(el.type->numDeformations()),
                 Eigen::VectorXd::Zero(el.type->numDeformations()))
            .empty())
      continue;
    out.push_back(static_cast<int>(i));
  }
  return out;
}

std::vector<ElementStress> elementStresses(const core::Model& m, const StaticStep& step) {
  std::vector<ElementStress> out;
  for (int i : stressedElements(m)) {
    const auto& el = m.elements[i];
    const int nd = el.type->numDeformations();
    Eigen::VectorXd g = Eigen::VectorXd::Zero(nd), e = Eigen::VectorXd::Zero(nd);
    if (step.sigma.size() >= el.firstDef + nd) g = step.sigma.segment(el.firstDef, nd);
    if (step.e.size() >= el.firstDef + nd) e = step.e.segment(el.firstDef, nd);
    double vm = 0.0;
    for (const SectionLoads& L : endLoads(m, el, g, e))
      vm = std::max(vm, sectionVonMises(m.appearance.at(el.label), L));
    out.push_back({i, vm});
  }
  return out;
}

ElementStress largestStress(const core::Model& m, const StaticStep& step) {
  ElementStress top;
  for (const auto& s : elementStresses(m, step))
    if (top.element < 0 || s.vonMises > top.vonMises) top = s;
  return top;
}

std::vector<int> supportedNodes(const core::Model& m) {
  std::vector<int> out;
  for (size_t n = 0; n < m.nodes.size(); ++n) {
    const core::Node& nd = m.nodes[n];
    for (int c = 0; c < nd.dim(); ++c) {
      const core::Role r = m.xRole[nd.firstCoord + c];
      if (r == core::Role::Fixed || r == core::Role::Input) {
        out.push_back(static_cast<int>(n));
        break;
      }
    }
  }
  return out;
}

std::vector<std::pair<std::string, double>> supportReactions(const core::Model& m, const StaticStep& step,
                                                             const Eigen::VectorXd& extraLoads) {
  std::vector<std::pair<std::string, double>> out;
  const std::vector<int> nodes = supportedNodes(m);
  if (nodes.empty()) return out;
  Eigen::VectorXd reaction = Eigen::VectorXd::Zero(m.nx);
  if (step.x.size() == m.nx) {
    core::ResultQuantities rq(m);
    core::StateOutputs s;
    s.x = step.x, s.e = step.e, s.sig = step.sigma;
    s.xd = s.xdd = Eigen::VectorXd::Zero(m.nx);
    s.ed = s.edd = Eigen::VectorXd::Zero(m.ne);
    const double t = m.settings.t0;
    rq.setState(t, dofsOf(m, s, 0), step.loadFactor, step.initialFactor, &s.x);
    Eigen::VectorXd sig, fxt;
    core::ResultQuantities::AppliedForces applied;
    rq.forces(t, step.loadFactor, s, extraLoads, sig, fxt, step.initialFactor, &applied);
    reaction = fxt - applied.loads - applied.gravity;
  }
  for (int n : nodes) {
    const core::Node& nd = m.nodes[n];
    const std::string label = "node" + std::to_string(nd.label) + ".";
    const Eigen::VectorXd r = reaction.segment(nd.firstCoord, nd.dim());
    switch (nd.kind) {
      case core::NodeKind::Position:
      case core::NodeKind::SpatialPosition:
        for (int c = 0; c < nd.dim(); ++c) out.emplace_back("R.F." + label + kXyz[c], r[c]);
        break;
      case core::NodeKind::Orientation:
        out.emplace_back("R.M." + label + "angle", r[0]);
        break;
      case core::NodeKind::EulerParameters: {
        // The global moment whose generalised force B M is the reaction on the Euler parameters.
        const Eigen::Vector4d lambda =
            step.x.size() == m.nx ? Eigen::Vector4d(step.x.segment<4>(nd.firstCoord)) : Eigen::Vector4d(1, 0, 0, 0);
        const Eigen::Matrix<double, 4, 3> B = momentToEuler(lambda);
        const Eigen::Vector3d M = (B.transpose() * B).ldlt().solve(B.transpose() * Eigen::Vector4d(r));
        for (int c = 0; c < 3; ++c) out.emplace_back("R.M." + label + kXyz[c], M[c]);
        break;
      }
      case core::NodeKind::Warping:
        out.emplace_back("R.B." + label + "warping", r[0]);
        break;
    }
  }
  return out;
}

std::string checkComplianceNodes(const core::Model& m, const std::vector<int>& labels) {
  for (int label : labels)
    if (!m.nodeByLabel.count(label))
      return "a compliance is asked for node " + std::to_string(label) + ", which the model does not have";
  return "";
}

std::vector<NodeCompliance> nodeCompliances(const core::Model& m, const StaticStep& step,
                                            const std::vector<int>& labels) {
  std::vector<NodeCompliance> out;
  if (labels.empty()) return out;
  core::Linearization lin(m);
  core::EquilibriumPoint at;
  at.t = m.settings.t0;
  at.loadFactor = step.loadFactor, at.initialFactor = step.initialFactor;
  at.eta = step.eta;
  at.x = &step.x;
  core::LinearizedSystem sys;
  core::linearizeAt(lin, at, sys, false);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(sys.K + sys.G);
  const bool regular = lu.rank() == sys.K.rows();
  for (int label : labels) {
    NodeCompliance nc;
    nc.label = label;
    const int node = m.nodeByLabel.at(label), partner = partnerNode(m, node);
    const bool orientation = isOrientation(m.nodes[node].kind);
    nc.position = orientation ? partner : node;
    nc.orientation = orientation ? node : partner;
    if (m.nodes[node].kind == core::NodeKind::Warping) nc.position = nc.orientation = -1;
    // A: the rows of F_q of the node's coordinates; T: their displacement per generalised load.
    std::vector<int> rows;
    std::vector<Eigen::MatrixXd> blocks;
    if (nc.position >= 0) {
      const core::Node& p = m.nodes[nc.position];
      for (int c = 0; c < p.dim(); ++c) rows.push_back(p.firstCoord + c), nc.names.push_back(kXyz[c]);
      blocks.push_back(Eigen::MatrixXd::Identity(p.dim(), p.dim()));
    }
    if (nc.orientation >= 0) {
      const core::Node& o = m.nodes[nc.orientation];
      for (int c = 0; c < o.dim(); ++c) rows.push_back(o.firstCoord + c);
      if (o.kind == core::NodeKind::Orientation) {
        nc.names.push_back("angle");
        blocks.push_back(Eigen::MatrixXd::Identity(1, 1));
      } else {
        for (const char* r : {"rx", "ry", "rz"}) nc.names.push_back(r);
        blocks.push_back(momentToEuler(step.x.segment<4>(o.firstCoord)));
      }
    }
    if (m.nodes[node].kind == core::NodeKind::Warping) {
      rows.push_back(m.nodes[node].firstCoord), nc.names.push_back("warping");
      blocks.push_back(Eigen::MatrixXd::Identity(1, 1));
    }
    if (regular && sys.K.rows() > 0) {
      Eigen::MatrixXd A(static_cast<Eigen::Index>(rows.size()), sys.K.rows());
      for (size_t r = 0; r < rows.size(); ++r) A.row(static_cast<Eigen::Index>(r)) = lin.transfer().row(rows[r]);
      Eigen::MatrixXd T = Eigen::MatrixXd::Zero(A.rows(), static_cast<Eigen::Index>(nc.names.size()));
      Eigen::Index r0 = 0, c0 = 0;
      for (const auto& b : blocks) T.block(r0, c0, b.rows(), b.cols()) = b, r0 += b.rows(), c0 += b.cols();
      nc.C = T.transpose() * A * lu.solve(A.transpose()) * T;
    } else if (sys.K.rows() == 0) {
      nc.C =
          Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nc.names.size()), static_cast<Eigen::Index>(nc.names.size()));
    }
    out.push_back(std::move(nc));
  }
  return out;
}

io::CsvTable stressTable(const core::Model& m, const StaticRun& run) {
  io::CsvTable t;
  t.columns = {"load_step", "initial_factor", "load_factor"};
  for (int i : stressedElements(m))
    t.columns.push_back("stress_" + m.elements[i].type->keyword + std::to_string(m.elements[i].label));
  for (const auto& st : run.steps) {
    std::vector<double> row{static_cast<double>(st.loadStep), st.initialFactor, st.loadFactor};
    for (const auto& s : elementStresses(m, st)) row.push_back(s.vonMises);
    t.rows.push_back(std::move(row));
  }
  return io::originalColumns(m, std::move(t));  // a refined model's: the original elements
}

StaticCompliances runCompliances(const core::Model& m, const StaticRun& run, const std::vector<int>& labels) {
  StaticCompliances out;
  if (labels.empty()) return out;
  for (const auto& st : run.steps) out.push_back(nodeCompliances(m, st, labels));
  return out;
}

io::CsvTable complianceTable(const StaticRun& run, const StaticCompliances& compliances) {
  io::CsvTable t;
  t.columns = {"load_step", "initial_factor", "load_factor", "node", "row"};
  std::vector<std::string> all;
  for (const char* c : {"x", "y", "z", "angle", "rx", "ry", "rz", "warping"}) all.emplace_back(c);
  for (const auto& c : all) t.columns.push_back(c);
  const double empty = std::numeric_limits<double>::quiet_NaN();
  for (size_t k = 0; k < run.steps.size() && k < compliances.size(); ++k) {
    const StaticStep& st = run.steps[k];
    for (const auto& nc : compliances[k])
      for (size_t r = 0; r < nc.names.size(); ++r) {
        std::vector<double> row{static_cast<double>(st.loadStep), st.initialFactor, st.loadFactor,
                                static_cast<double>(nc.label), static_cast<double>(r + 1)};
        row.resize(t.columns.size(), empty);
        for (size_t c = 0; c < nc.names.size(); ++c) {
          const auto at = std::find(all.begin(), all.end(), nc.names[c]) - all.begin();
          row[5 + static_cast<size_t>(at)] =
              nc.C.size() ? nc.C(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) : empty;
        }
        t.rows.push_back(std::move(row));
      }
  }
  return t;
}

std::vector<io::SpacarVariable> spacarDesignVariables(const core::Model& m, const StaticRun& run,
                                                      const StaticCompliances& compliances) {
  std::vector<const StaticStep*> steps;
  std::vector<const std::vector<NodeCompliance>*> stepCompliances;
  for (size_t k = 0; k < run.steps.size(); ++k)
    if (run.steps[k].loadStep >= 0) {
      steps.push_back(&run.steps[k]);
      stepCompliances.push_back(k < compliances.size() ? &compliances[k] : nullptr);
    }
  const std::size_t tdef = steps.size();
  int maxElement = 0, maxNode = 0;
  for (const auto& el : m.elements)
    if (!el.type->internal) maxElement = std::max(maxElement, el.label);
  for (const auto& nd : m.nodes) maxNode = std::max(maxNode, nd.label);
  const std::size_t nf = m.spatial ? 3 : 2, nm = m.spatial ? 3 : 1;
  io::SpacarVariable stressmax{"stressmax", {1, tdef}, std::vector<double>(tdef, 0.0), {}, false};
  io::SpacarVariable stressel{"stressel", {static_cast<std::size_t>(maxElement), tdef}, {}, {}, false};
  stressel.data.assign(static_cast<std::size_t>(maxElement) * tdef, 0.0);
  io::SpacarVariable freac{"Freac", {nf, tdef, static_cast<std::size_t>(maxNode)}, {}, {}, false};
  io::SpacarVariable mreac{"Mreac", {nm, tdef, static_cast<std::size_t>(maxNode)}, {}, {}, false};
  freac.data.assign(nf * tdef * static_cast<std::size_t>(maxNode), 0.0);
  mreac.data.assign(nm * tdef * static_cast<std::size_t>(maxNode), 0.0);
  std::map<int, io::SpacarVariable> cm;
  for (std::size_t k = 0; k < tdef; ++k) {
    const StaticStep& st = *steps[k];
    for (const auto& s : elementStresses(m, st)) {
      const auto label = static_cast<std::size_t>(m.elements[s.element].label);
      stressel.data[k * static_cast<std::size_t>(maxElement) + label - 1] = s.vonMises;
      stressmax.data[k] = std::max(stressmax.data[k], s.vonMises);
    }
    for (const auto& [name, value] : supportReactions(m, st)) {
      // "R.F.node<label>.<c>"
      const bool force = name[2] == 'F';
      if (!force && name[2] != 'M') continue;
      const auto dot = name.rfind('.');
      const std::size_t label = std::stoul(name.substr(8, dot - 8));
      const std::string c = name.substr(dot + 1);
      const std::size_t comp = c == "y" ? 1 : c == "z" ? 2 : 0;
      io::SpacarVariable& v = force ? freac : mreac;
      const std::size_t n = force ? nf : nm;
      v.data[(label - 1) * n * tdef + k * n + comp] = value;
    }
    for (const auto& nc : stepCompliances[k] ? *stepCompliances[k] : std::vector<NodeCompliance>()) {
      const std::size_t n = nc.names.size();
      auto [it, added] = cm.try_emplace(nc.label);
      if (added) it->second = {"CMglob_node" + std::to_string(nc.label), {n, n, tdef}, {}, {}, false};
      it->second.data.resize(n * n * tdef, std::numeric_limits<double>::quiet_NaN());
      for (std::size_t c = 0; c < n && nc.C.size(); ++c)
        for (std::size_t r = 0; r < n; ++r)
          it->second.data[k * n * n + c * n + r] = nc.C(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c));
    }
  }
  std::vector<io::SpacarVariable> out;
  if (maxElement > 0 && !stressedElements(m).empty()) out.push_back(stressmax), out.push_back(stressel);
  if (!supportedNodes(m).empty()) out.push_back(freac), out.push_back(mreac);
  for (auto& [label, v] : cm) out.push_back(std::move(v));
  return out;
}

}  // namespace flexmb::analysis
