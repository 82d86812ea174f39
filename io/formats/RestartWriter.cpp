#include "io/formats/RestartWriter.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>
#include "text/NumberText.hpp"

namespace flexmb::io {

namespace {

using core::Model;
using core::Role;

// Shortest text that reads back to the same double, independent of the locale.
std::string num(double v) {
  if (!std::isfinite(v)) throw std::invalid_argument("restart state: a value is not finite");
  if (v == 0.0) return "0";
  return text::shortest(v);
}

std::string quoted(const core::TimeFunctionPtr& f) {
  std::string s = "\"";  // appended piecewise: `"\"" + std::string` trips GCC 12's -Wrestrict (tools/README.md)
  s += f ? f->text() : std::string("0");
  s += '"';
  return s;
}

struct Writer {
  const Model& m;
  bool s95;
  std::string out;
  // An element the writer lists: the automatic L2MIN1 of an orientation node is not one.
  static bool listed(const core::ElementEntry& el) { return el.type != &core::normalisationType(); }

  void line(const std::string& s) { out += s + "\n"; }
  void comment(const std::string& s) { out += (s95 ? "* " : "# ") + s + "\n"; }
  int nodeLabel(int xi) const { return m.nodes[m.xOwnerNode[xi]].label; }
  int coordComp(int xi) const { return xi - m.nodes[m.xOwnerNode[xi]].firstCoord + 1; }
  int elemLabel(int di) const { return m.elements[m.eOwnerElement[di]].label; }
  int defComp(int di) const { return di - m.elements[m.eOwnerElement[di]].firstDef + 1; }
  std::string xId(int xi) const { return std::to_string(nodeLabel(xi)) + " " + std::to_string(coordComp(xi)); }
  std::string eId(int di) const { return std::to_string(elemLabel(di)) + " " + std::to_string(defComp(di)); }
};

}  // namespace

std::string restartUnsupportedReason(const Model& m) {
  // A spatial model's echo is written in SPACAR 2013+ form (X, XREF, STARTDE), which has no keyword
  // for the rate of a DYNX coordinate: refused before the run when the model has one.
  if (m.spatial)
    for (const auto& d : m.dofs)
      if (!d.isDeformation)
        return "the restart echo (--echo) of a spatial model is written in SPACAR 2013+ form, which has no "
               "keyword for the rate of a coordinate that is a degree of freedom (DYNX, or a BEAMW warping "
               "coordinate: " +
               m.coordName(d.index) + " of " + m.sourceFile + ")";
  return {};
}

namespace {

// A spatial model's coordinates: X where the run ended (positions, Euler parameters, warping), and
// XREF (flexmb extension) where the elements' undeformed reference configuration differs from it,
// so that the elements read back are the ones that ran: same reference lengths and triads.
void restartSpatialCoordinates(Writer& w, const Model& m, const core::StateOutputs& state) {
  const Eigen::VectorXd& ref = m.xRef.size() == m.nx ? m.xRef : m.x0;
  for (const auto& n : m.nodes) {
    std::string x = "X " + std::to_string(n.label), r = "XREF " + std::to_string(n.label);
    bool moved = false;
    for (int c = 0; c < n.dim(); ++c) {
      (x += ' ') += num(state.x[n.firstCoord + c]);
      (r += ' ') += num(ref[n.firstCoord + c]);
      moved = moved || state.x[n.firstCoord + c] != ref[n.firstCoord + c];
    }
    w.line(x);
    if (moved) w.line(r);
  }
}

// The elements, the coordinates where the run ended and the roles.
void restartTopology(Writer& w, const Model& m, const core::StateOutputs& state) {
  for (const auto& el : m.elements) {
    if (!Writer::listed(el)) continue;
    std::string s = el.type->keyword + " " + std::to_string(el.label);
    // Appended piecewise here and below: `" " + std::string` inside `+=` trips GCC 12's -Wrestrict
    // (a false positive in libstdc++'s inlined char_traits::copy, tools/README.md).
    for (int ni : el.nodes) (s += ' ') += std::to_string(m.nodes[ni].label);
    for (double v : el.vec) (s += ' ') += num(v);  // BEAM's y vector as given: the reference is XREF's
    w.line(s);
  }
  if (m.spatial) {
    restartSpatialCoordinates(w, m, state);
  } else {
    for (const auto& n : m.nodes) {
      const double* x = state.x.data() + n.firstCoord;
      if (n.kind == core::NodeKind::Position)
        w.line((w.s95 ? "XY " : "X ") + std::to_string(n.label) + " " + num(x[0]) + " " + num(x[1]));
      else
        w.line((w.s95 ? "BETA " : "X ") + std::to_string(n.label) + " " + num(x[0]));
    }
  }
  // Roles (q in the model's order: DYNX and DYNE as its dofs list them).
  auto roleLines = [&](const char* keyword, Role role) {
    for (const auto& n : m.nodes) {
      std::string comps;
      for (int c = 0; c < n.dim(); ++c)
        if (m.xRole[n.firstCoord + c] == role) (comps += ' ') += std::to_string(c + 1);
      if (!comps.empty()) w.line(std::string(keyword) + " " + std::to_string(n.label) + comps);
    }
  };
  roleLines("FIX", Role::Fixed);
  roleLines("INPUTX", Role::Input);
  for (const auto& d : m.dofs) w.line(d.isDeformation ? "DYNE " + w.eId(d.index) : "DYNX " + w.xId(d.index));
  for (const auto& [keyword, role] : {std::pair{"RLSE", Role::Calculable}, std::pair{"INPUTE", Role::Input}})
    for (const auto& el : m.elements) {
      std::string comps;
      for (int c = 0; c < el.type->numDeformations(); ++c)
        if (m.eRole[el.firstDef + c] == role) (comps += ' ') += std::to_string(c + 1);
      if (!comps.empty()) w.line(std::string(keyword) + " " + std::to_string(el.label) + comps);
    }
  if (!w.s95) {
    w.line("END");
    w.line("HALT");
  }
}

// Reference lengths (the undeformed geometry stays the original one), inertia, stiffness, damping.
void restartProperties(Writer& w, const Model& m) {
  if (!m.spatial)  // a spatial model's references come from XREF
    for (const auto& el : m.elements)
      if (el.impl && el.impl->referenceLength() > 0.0)
        w.line("LENGTH0 " + std::to_string(el.label) + " " + num(el.impl->referenceLength()));

  // Inertia, stiffness, damping.
  std::map<int, double> nodeMass;
  for (const auto& lm : m.lumpedMasses) nodeMass[m.xOwnerNode[lm.coord]] = lm.value;
  for (const auto& [ni, value] : nodeMass)
    w.line((w.s95 ? "MASS " : "XM ") + std::to_string(m.nodes[ni].label) + " " + num(value));
  for (const auto& el : m.elements) {
    if (!Writer::listed(el)) {  // an orientation node's rigid-body inertia: XM n Ixx Ixy Ixz Iyy Iyz Izz
      const auto& J = el.inertia;
      if (J.any())
        w.line("XM " + std::to_string(m.nodes[el.nodes[0]].label) + " " + num(J.jxx) + " " + num(J.jxy) + " " +
               num(J.jxz) + " " + num(J.jyy) + " " + num(J.jyz) + " " + num(J.jzz));
      continue;
    }
    if (m.spatial && el.inertia.any()) {  // EM in the element type's layout, as given
      std::string s = "EM " + std::to_string(el.label);
      for (double v : el.inertiaParams) (s += ' ') += num(v);
      w.line(s);
    } else if (el.inertia.any()) {
      if (w.s95) {
        if (el.inertia.rhoI != 0.0)
          throw std::invalid_argument("restart state: SPACAR95 EMASS has no rotary inertia per length");
        w.line("EMASS " + std::to_string(el.label) + " " + num(el.inertia.rhoA));
      } else {
        w.line("EM " + std::to_string(el.label) + " " + num(el.inertia.rhoA) + " " + num(el.inertia.rhoI));
      }
    }
    auto params = [&](const char* keyword, const std::vector<double>& p) {
      std::string s = std::string(keyword) + " " + std::to_string(el.label);
      for (double v : p) (s += ' ') += num(v);
      w.line(s);
    };
    if (el.hasStiffness) params("ESTIFF", el.stiffnessParams);
    if (el.hasDamping) params(w.s95 ? "EDAMPP" : "EDAMP", el.dampingParams);
  }
}

// Constant and time-dependent loads, gravity, prestress.
void restartLoads(Writer& w, const Model& m) {
  for (const auto& n : m.nodes) {
    bool any = false, anyDel = false;
    std::string f, d;
    for (int c = 0; c < n.dim(); ++c) {
      any = any || m.f0[n.firstCoord + c] != 0.0;
      anyDel = anyDel || (m.delf.size() && m.delf[n.firstCoord + c] != 0.0);
      (f += ' ') += num(m.f0[n.firstCoord + c]);
      if (m.delf.size()) (d += ' ') += num(m.delf[n.firstCoord + c]);
    }
    if (any) w.line((w.s95 ? "FORCE " : "XF ") + std::to_string(n.label) + f);
    if (anyDel) w.line("DELXF " + std::to_string(n.label) + d);
  }
  for (const auto& mo : m.moments) {  // spatial: global moments on orientation nodes
    const std::string node = std::to_string(m.nodes[mo.node].label);
    if (mo.value.squaredNorm() > 0.0)
      w.line("XF " + node + " " + num(mo.value[0]) + " " + num(mo.value[1]) + " " + num(mo.value[2]));
    if (mo.increment.squaredNorm() > 0.0)
      w.line("DELXF " + node + " " + num(mo.increment[0]) + " " + num(mo.increment[1]) + " " + num(mo.increment[2]));
  }
  if (m.hasGravity)
    w.line("GRAVITY " + num(m.gravity[0]) + " " + num(m.gravity[1]) + (m.spatial ? " " + num(m.gravity[2]) : ""));
  // ESIG e s1 ... sn: every deformation's value (n >= 3 numbers on elements with several, so that
  // reading it back never meets the two-value reading of flexmb's former ESIG e i s).
  if (m.sigma0.size() == m.ne)
    for (const auto& el : m.elements) {
      if (!Writer::listed(el)) continue;
      const int n = el.type->numDeformations();
      bool any = false;
      for (int c = 0; c < n; ++c) any = any || m.sigma0[el.firstDef + c] != 0.0;
      if (!any) continue;
      std::string s = "ESIG " + std::to_string(el.label);
      for (int c = 0; c < n; ++c) (s += ' ') += num(m.sigma0[el.firstDef + c]);
      w.line(s);
    }
  for (const auto& tl : m.timeForces) w.line("XFT " + w.xId(tl.index) + " " + quoted(tl.f));
  for (const auto& tl : m.timeStresses) w.line("ESIGT " + w.eId(tl.index) + " " + quoted(tl.f));
  for (const auto& tl : m.references) w.line("EREF " + w.eId(tl.index) + " " + quoted(tl.f));
}

// One prescribed input at time t: its functions (INPUTXT / INPUTET), else its value (a coordinate's
// is in XY/BETA in SPACAR95), rate and acceleration, and DELINPX.
void restartInput(Writer& w, const core::Rheonomic& r, double t, bool coordinate) {
  const std::string id = coordinate ? w.xId(r.index) : w.eId(r.index);
  if (r.fx) {
    w.line(std::string(coordinate ? "INPUTXT " : "INPUTET ") + id + " " + quoted(r.fx) + " " + quoted(r.fv) + " " +
           quoted(r.fa));
    return;
  }
  double x, v, a;
  r.evaluate(t, x, v, a);
  if (w.s95) {
    if (!coordinate) w.line("E " + id + " " + num(x));
    if (v != 0.0) w.line((coordinate ? "XD " : "ED ") + id + " " + num(v));
    if (a != 0.0) w.line((coordinate ? "XDD " : "EDD ") + id + " " + num(a));
  } else {
    w.line(std::string(coordinate ? "INPUTX " : "INPUTE ") + id + " " + num(x) + " " + num(v) + " " + num(a));
  }
  if (coordinate && r.delta != 0.0) w.line("DELINPX " + id + " " + num(r.delta));
}

void restartInputs(Writer& w, const Model& m, double t) {
  for (const auto& r : m.inputX) restartInput(w, r, t, true);
  for (const auto& r : m.inputE) restartInput(w, r, t, false);
}

// Rates (and, SPACAR95, accelerations) of DYNX coordinates, and the deformations where the run ended.
void restartRates(Writer& w, const Model& m, const core::StateOutputs& state) {
  // Rates (and, SPACAR95, accelerations) of DYNX coordinates.
  const bool accelerations = state.xdd.size() == m.nx && state.edd.size() == m.ne;
  for (const auto& d : m.dofs) {
    if (d.isDeformation) continue;
    const double v = state.xd[d.index];
    if (w.s95) {
      if (v != 0.0) w.line("XD " + w.xId(d.index) + " " + num(v));
      if (accelerations && state.xdd[d.index] != 0.0) w.line("XDD " + w.xId(d.index) + " " + num(state.xdd[d.index]));
    } else if (v != 0.0) {
      throw std::invalid_argument("restart state: SPACAR 2013+ has no keyword for the rate of a DYNX coordinate (" +
                                  m.coordName(d.index) + " moves); write the model in SPACAR95 form to restart it");
    }
  }
  // Deformations where the run ended (they place the element references together with LENGTH0).
  for (int di = 0; di < m.ne; ++di) {
    const Role role = m.eRole[di];
    if (role != Role::Dynamic && role != Role::Calculable) continue;
    // A spatial echo places its elements by XREF: released deformations follow from X.
    if (m.spatial && role != Role::Dynamic) continue;
    if (w.s95) {
      w.line("E " + w.eId(di) + " " + num(state.e[di]));
      if (role == Role::Dynamic) w.line("ED " + w.eId(di) + " " + num(state.ed[di]));
      if (role == Role::Dynamic && accelerations) w.line("EDD " + w.eId(di) + " " + num(state.edd[di]));
    } else {
      w.line("STARTDE " + w.eId(di) + " " + num(state.e[di]) +
             (role == Role::Dynamic ? " " + num(state.ed[di]) : std::string()));
    }
  }
}

// The time and the settings: the next period from t.
void restartSettings(Writer& w, const Model& m, double t) {
  const auto& set = m.settings;
  w.line("TIME " + num(t));
  const double period = set.tEnd - set.t0;
  if (w.s95)
    w.line("TIMESTEP " + std::to_string(set.outputIntervals) + " " + num(period));
  else
    w.line("TIMESTEP " + num(t + period) + " " + std::to_string(set.outputIntervals));
  if (w.s95) {
    if (set.relTol == set.absTol) w.line("EPSINT " + num(set.relTol));
    if (set.hmax > 0.0) w.line("HMAX " + num(set.hmax));
    if (set.kinematicTolGiven) w.line("EPSKIN " + num(set.kinematicTol));
    w.line("MAXITERAT " + std::to_string(set.maxIterations));
    w.line("END");
    w.line("EOF");
  } else {
    w.line("ERROR " + num(set.absTol) + " " + num(set.relTol));
    w.line("ITERSTEP " + std::to_string(set.maxIterations) + " " + std::to_string(set.loadSteps) + " " +
           num(set.kinematicTol) + " 1 1 " + std::to_string(set.initialLoadSteps));
    if (set.outputLevel || set.transferFunctionLevel)
      w.line("OUTLEVEL " + std::to_string(set.outputLevel) + " " + std::to_string(set.transferFunctionLevel));
    if (set.hmax > 0.0) w.comment("HMAX " + num(set.hmax) + " (SPACAR95 only: give it with --max-step)");
    w.line("END");
    w.line("END");
  }
}

}  // namespace

std::string restartText(const Model& m, double t, const core::StateOutputs& state) {
  if (const std::string why = restartUnsupportedReason(m); !why.empty()) throw std::invalid_argument(why);
  if (state.x.size() != m.nx || state.xd.size() != m.nx || state.e.size() != m.ne || state.ed.size() != m.ne)
    throw std::invalid_argument("restart state: the state does not match the model's sizes");
  if (!std::isfinite(t)) throw std::invalid_argument("restart state: the time is not finite");
  // A spatial model's echo is in SPACAR 2013+ form (X with Euler parameters, XREF, STARTDE).
  Writer w{m, m.dialect == core::Dialect::Spacar95 && !m.spatial, {}};
  w.comment("flexmb restart state of " + m.sourceFile + " at t = " + num(t));
  w.comment("(the configuration, deformations and input rates where the run ended; reading this file");
  w.comment("continues the run for one more period)");

  restartTopology(w, m, state);
  restartProperties(w, m);
  restartLoads(w, m);
  restartInputs(w, m, t);
  restartRates(w, m, state);
  restartSettings(w, m, t);
  return w.out;
}

void writeRestart(const std::string& path, const Model& model, double t, const core::StateOutputs& state) {
  const std::string text = restartText(model, t, state);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("cannot write '" + path + "': cannot open it for writing");
    f << text;
    f.flush();
    if (!f) throw std::runtime_error("cannot write '" + path + "': write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "': cannot rename the temporary file");
  }
}

}  // namespace flexmb::io
