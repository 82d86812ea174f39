#include "core/linearization/ModelDiagnostics.hpp"

#include <cmath>
#include <sstream>

#include "core/kinematics/ElementValidity.hpp"
#include "core/linearization/Linearization.hpp"

namespace flexmb::core {

namespace {
std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
bool overflows(double v) { return !std::isnan(v) && !(std::abs(v) <= kOverflowLimit); }
}  // namespace

ModelDiagnosis diagnoseModel(const Model& model) {
  ModelDiagnosis d;
  auto check = [&](double v, const std::string& what) {
    if (overflows(v)) d.overflow.push_back(what + ": " + number(v));
  };
  for (const auto& n : model.nodes)
    for (int c = 0; c < n.dim(); ++c)
      check(model.x0[n.firstCoord + c],
            std::string(n.kind == NodeKind::Orientation ? "BETA" : "X") + " of node " + std::to_string(n.label));
  for (const auto& E : model.elements) {
    const std::string el = " of element " + std::to_string(E.label);
    check(E.inertia.rhoA, "mass per length (EM)" + el);
    check(E.inertia.rhoI, "rotary inertia (EM)" + el);
    check(E.inertia.jw, "warping inertia (EM)" + el);
    if (E.hasStiffness)
      for (Eigen::Index i = 0; i < E.S.size(); ++i) check(E.S.data()[i], "stiffness (ESTIFF)" + el);
    if (E.hasDamping)
      for (Eigen::Index i = 0; i < E.Sd.size(); ++i) check(E.Sd.data()[i], "damping (EDAMP)" + el);
  }
  for (const auto& m : model.lumpedMasses) check(m.value, "lumped mass (XM) on " + model.coordName(m.coord));
  for (int i = 0; i < model.nx; ++i) {
    if (model.f0.size() == model.nx) check(model.f0[i], "force (XF) on " + model.coordName(i));
    if (model.delf.size() == model.nx) check(model.delf[i], "force increment (DELXF) on " + model.coordName(i));
  }
  check(model.gravity[0], "GRAVITY x");
  check(model.gravity[1], "GRAVITY y");
  for (int k = 0; k < model.ne; ++k) {
    if (model.sigma0.size() == model.ne) check(model.sigma0[k], "stress (ESIG) of " + model.deformationName(k));
    if (model.e0.size() == model.ne) check(model.e0[k], "initial value (E) of " + model.deformationName(k));
    if (model.ed0.size() == model.ne) check(model.ed0[k], "initial rate (ED) of " + model.deformationName(k));
  }
  for (const auto& r : model.inputX) {
    check(r.x0, "input value (INPUTX) of " + model.coordName(r.index));
    check(r.v, "input rate (INPUTX) of " + model.coordName(r.index));
    check(r.a, "input acceleration (INPUTX) of " + model.coordName(r.index));
  }
  for (const auto& r : model.inputE) {
    check(r.x0, "input value (INPUTE) of " + model.deformationName(r.index));
    check(r.v, "input rate (INPUTE) of " + model.deformationName(r.index));
    check(r.a, "input acceleration (INPUTE) of " + model.deformationName(r.index));
  }
  // A warping coordinate that is a degree of freedom gets its stiffness from the BEAMWs with ESTIFF
  // that use its node (S78 > 0 whenever GIt or ECw is); without one it is a mechanism.
  std::vector<char> stiffWarping(model.nx, 0);
  for (const auto& el : model.elements) {
    bool stiff = false;
    for (int k : el.type->alwaysReleased) stiff |= el.hasStiffness && el.S(k, k) != 0.0;
    if (stiff)
      for (int ni : el.nodes)
        if (model.nodes[ni].kind == NodeKind::Warping) stiffWarping[model.nodes[ni].firstCoord] = 1;
  }
  for (const auto& dof : model.dofs) {
    if (!dof.isDeformation) {
      if (model.nodes[model.xOwnerNode[dof.index]].kind == NodeKind::Warping && !stiffWarping[dof.index])
        d.mechanismDeformations.push_back(model.coordName(dof.index) +
                                          " (warping node of BEAMWs without ESTIFF: FIX it to restrain warping)");
      continue;
    }
    const ElementEntry& E = model.elements[model.eOwnerElement[dof.index]];
    const int local = dof.index - E.firstDef;
    const bool stiff = E.hasStiffness && local < E.S.rows() && E.S(local, local) != 0.0;
    if (!stiff)
      d.mechanismDeformations.push_back(model.deformationName(dof.index) + " (" + E.type->keyword + ", no " +
                                        (E.hasStiffness ? "stiffness for it in ESTIFF" : "ESTIFF") + ")");
  }
  return d;
}

std::vector<std::string> masslessDegreesOfFreedom(const Model& model) {
  std::vector<std::string> names;
  if (model.numDofs() == 0) return names;
  Linearization lin(model);
  Eigen::VectorXd q0;
  LinearizedSystem sys;
  lin.initialRest(sys, q0);
  const Eigen::VectorXd m = sys.M.diagonal();
  const double scale = m.cwiseAbs().maxCoeff();
  for (int i = 0; i < model.numDofs(); ++i) {
    const auto& dof = model.dofs[i];
    // A warping coordinate's mass (Jw l0/2, lumped, in its own units: kg m^4 for w in rad/m) is
    // many decades below the others' (SPACAR Light's steel strip: 1e-15 against 0.1 kg); it is
    // exactly zero only without Jw.
    if (!dof.isDeformation && model.nodes[model.xOwnerNode[dof.index]].kind == NodeKind::Warping) {
      if (m[i] > 0.0) continue;
    } else if (m[i] > 1e-13 * scale && scale > 0) {
      continue;
    }
    names.push_back(dof.isDeformation ? model.deformationName(dof.index) : model.coordName(dof.index));
  }
  return names;
}

std::string initialAssemblyProblem(const Model& model) {
  GeometricTransferFunctions gtf(model);
  gtf.solvePositions(model.settings.t0, gtf.initialDofs());
  const auto bad = firstInvalidElement(model, gtf.x());
  if (!bad) return "";
  // Only a problem of the start when the file's own coordinates are valid.
  if (firstInvalidElement(model, model.x0)) return "";
  return "the initial configuration landed on another assembly branch: solving the kinematics from the "
         "file's nodal coordinates (X, BETA) with the initial degrees of freedom (E, STARTDE, INPUTX) gave " +
         bad->message +
         ". Give nodal coordinates close to the initial configuration (X and BETA consistent with the "
         "initial E), or start from a configuration nearer to the file's";
}

}  // namespace flexmb::core
