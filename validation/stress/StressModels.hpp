#pragma once
// Model generators and helpers for the stress catalogue (validation/stress/README.md).
// Every generator returns .dat text in the SPACAR 2013+ dialect; the tests read it with
// io::readDatString, so a generated model goes through exactly the reader a user's file does.
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/dynamics/Inertia.hpp"
#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::stress {

// Full precision, for generated .dat text.
inline std::string fmt(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// 6 significant digits, for summary lines.
inline std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// ------------------------------------------------------------------------------------------------
// Straight guidance (datfiles/straight_guidance.dat, paper Section 4.1) with n PLBEAM per flexure.
//   Position nodes: left flexure 1 .. n+1 (x = 0), right flexure 1001 .. 1001+n (x = 0.2).
//   Orientation nodes: left 10001 .. 10001+n, right 20001 .. 20001+n.
//   Elements: left 1 .. n, right 1001 .. 1000+n, rigid body 5000 (top left -> top right).
//   DOF: left bending e2 e3 of every element except e3 of the top one; right e2 e3 of every element
//   but the top one; RLSE the 3 loop-closing bendings -> 2*2*n - 3 degrees of freedom.
// loadBlock: the dynamic-block lines of the load (XFT / XF / DELXF / ITERSTEP ...); "{TOP}" in it
// is replaced by the label of the loaded node (top of the left flexure).
// extraDynamic: further dynamic-block lines (STARTDE, TIMESTEP, ...).
struct GuidanceOptions {
  int elementsPerFlexure = 5;
  std::string loadBlock = "XFT {TOP} 1 \"t <= 0.1 ? 50*(1-cos(20*_pi*t)) : 0\"";
  std::string extraDynamic = "TIMESTEP 0.2 200\nERROR 1e-6 1e-3";
};

inline int guidanceTopNode(int n) { return n + 1; }

inline std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

inline std::string guidanceDat(const GuidanceOptions& o) {
  const int n = o.elementsPerFlexure;
  const double L = 0.2, h = L / n;
  std::ostringstream s;
  s << "% generated straight guidance, " << n << " PLBEAM per flexure\n";
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 10000 + k << " " << k + 1 << " " << 10001 + k << "\n";
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << 1000 + k << " " << 1000 + k << " " << 20000 + k << " " << 1001 + k << " " << 20001 + k << "\n";
  s << "PLBEAM 5000 " << n + 1 << " " << 10001 + n << " " << 1001 + n << " " << 20001 + n << "\n";
  for (int k = 1; k <= n + 1; ++k) {
    s << "X " << k << " 0.0 " << fmt(h * (k - 1)) << "\n";
    s << "X " << 1000 + k << " 0.2 " << fmt(h * (k - 1)) << "\n";
  }
  s << "FIX 1\nFIX 10001\nFIX 1001\nFIX 20001\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << (k == n ? " 2\n" : " 2 3\n");
  for (int k = 1; k < n; ++k) s << "DYNE " << 1000 + k << " 2 3\n";
  s << "RLSE " << n << " 3\nRLSE " << 1000 + n << " 2 3\nEND\nHALT\n";
  for (int k = 1; k <= n; ++k) {
    s << "EM " << k << " 0.228 1.9e-8\nEM " << 1000 + k << " 0.228 1.9e-8\n";
    s << "ESTIFF " << k << " 6.3e6 0.525\nESTIFF " << 1000 + k << " 6.3e6 0.525\n";
  }
  s << "EM 5000 6.84 5.13e-4\n";
  s << replaceAll(o.loadBlock, "{TOP}", std::to_string(n + 1)) << "\n";
  s << o.extraDynamic << "\nEND\nEND\n";
  return s.str();
}

// Eq. 24 with a given F_max: F_max/2 (1 - cos(20 pi t)) for t <= 0.1, 0 after.
inline std::string eq24Load(double fmax) {
  return "XFT {TOP} 1 \"t <= 0.1 ? " + fmt(fmax / 2) + "*(1-cos(20*_pi*t)) : 0\"";
}

// ------------------------------------------------------------------------------------------------
// Cantilever along +x of PLBEAMs clamped at node 1, each element (length, EI) with rho*A, rho*I;
// elongations fixed, bending DYNE. Position nodes 1 .. n+1, orientation nodes 101 .. 101+n.
struct Segment {
  double length, EI, rhoA = 1.0, rhoI = 1e-6;
};

inline std::string cantileverDat(const std::vector<Segment>& segs, const std::string& dynamicLines) {
  std::ostringstream s;
  const int n = static_cast<int>(segs.size());
  double x = 0.0;
  s << "X 1 0 0\n";
  for (int k = 1; k <= n; ++k) {
    s << "PLBEAM " << k << " " << k << " " << 100 + k << " " << k + 1 << " " << 101 + k << "\n";
    x += segs[k - 1].length;
    s << "X " << k + 1 << " " << fmt(x) << " 0\n";
  }
  s << "FIX 1\nFIX 101\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) {
    const auto& g = segs[k - 1];
    s << "EM " << k << " " << fmt(g.rhoA) << " " << fmt(g.rhoI) << "\n";
    s << "ESTIFF " << k << " 0 " << fmt(g.EI) << "\n";
  }
  s << dynamicLines << "\nEND\nEND\n";
  return s.str();
}

// ------------------------------------------------------------------------------------------------
// Column along +y of n PLBEAMs, clamped at the bottom (node 1 / 101), free at the top (n+1).
inline std::string columnDat(int n, double L, double EI, const std::string& dynamicLines) {
  std::ostringstream s;
  for (int k = 1; k <= n; ++k) {
    s << "PLBEAM " << k << " " << k << " " << 100 + k << " " << k + 1 << " " << 101 + k << "\n";
  }
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " 0 " << fmt(L * (k - 1) / n) << "\n";
  s << "FIX 1\nFIX 101\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " 1.0 1e-6\nESTIFF " << k << " 0 " << fmt(EI) << "\n";
  s << dynamicLines << "\nEND\nEND\n";
  return s.str();
}

// ------------------------------------------------------------------------------------------------
// Two-link arm of rigid PLBEAMs (lengths L1, L2) from the origin along the angles phi1 (link 1,
// absolute) and phi1 + phi2 (link 2). Position nodes 1 (base), 2 (elbow), 3 (tip); orientation
// nodes 100 (ground), 101/102 link 1, 201/202 link 2. PLHINGE 1 (100 -> 101), 2 (102 -> 201).
// tipInput: the tip position is an input (INPUTX 3 1 2) and the hinges are released (DOF 0);
// otherwise the hinges are the DOFs (DYNE).
inline std::string twoLinkDat(double L1, double L2, double phi1, double phi2, bool tipInput,
                              const std::string& dynamicLines) {
  const double ex = L1 * std::cos(phi1), ey = L1 * std::sin(phi1);
  const double a2 = phi1 + phi2;
  const double tx = ex + L2 * std::cos(a2), ty = ey + L2 * std::sin(a2);
  std::ostringstream s;
  s << "PLHINGE 1 100 101\nPLHINGE 2 102 201\n"
    << "PLBEAM 11 1 101 2 102\nPLBEAM 21 2 201 3 202\n"
    << "X 1 0 0\nX 2 " << fmt(ex) << " " << fmt(ey) << "\nX 3 " << fmt(tx) << " " << fmt(ty) << "\n"
    << "BETA 101 " << fmt(phi1) << "\nBETA 102 " << fmt(phi1) << "\nBETA 201 " << fmt(a2) << "\nBETA 202 " << fmt(a2)
    << "\n"
    << "FIX 1\nFIX 100\n";
  if (tipInput)
    s << "INPUTX 3 1 2\nRLSE 1 1\nRLSE 2 1\n";
  else
    s << "DYNE 1 1\nDYNE 2 1\n";
  s << "END\nHALT\nEM 11 1.0 1e-4\nEM 21 1.0 1e-4\nXM 3 0.5\n" << dynamicLines << "\nEND\nEND\n";
  return s.str();
}

// ------------------------------------------------------------------------------------------------
// Four-bar: crank A->B (L1, from A = (0,0) at angle theta0), coupler B->C (L2), rocker D->C (L3),
// D = (L4, 0); open (upper) assembly. Same numbering as datfiles/tests/fourbar.dat.
// crankRole: the kinematic lines giving the crank its role, e.g. "INPUTE 4 1" (rheonomic hinge) or
// "INPUTX 11 1\nRLSE 4 1" (crank orientation node prescribed, for static DELINPX stepping).
struct FourBar {
  double L1, L2, L3, L4, theta0;
  // Crank angle range for which the linkage can be assembled (Non-Grashof: |BD| <= L2 + L3).
  double deadPointAngle() const {
    // |BD|^2 = L1^2 + L4^2 - 2 L1 L4 cos(theta) = (L2 + L3)^2
    const double c = (L1 * L1 + L4 * L4 - (L2 + L3) * (L2 + L3)) / (2 * L1 * L4);
    return std::acos(c);
  }
};

inline std::string fourBarDat(const FourBar& g, const std::string& crankRole, const std::string& dynamicLines) {
  const double bx = g.L1 * std::cos(g.theta0), by = g.L1 * std::sin(g.theta0);
  const double dx = g.L4, dy = 0.0;
  // C: intersection of circle(B, L2) and circle(D, L3), upper solution.
  const double ux = dx - bx, uy = dy - by, d = std::hypot(ux, uy);
  const double a = (g.L2 * g.L2 - g.L3 * g.L3 + d * d) / (2 * d);
  const double hh = std::sqrt(std::max(0.0, g.L2 * g.L2 - a * a));
  const double px = bx + a * ux / d, py = by + a * uy / d;
  // The two solutions p +- h * perp(u); pick the one with larger y.
  double cx = px - hh * uy / d, cy = py + hh * ux / d;
  const double cx2 = px + hh * uy / d, cy2 = py - hh * ux / d;
  if (cy2 > cy) cx = cx2, cy = cy2;
  const double coupler = std::atan2(cy - by, cx - bx), rocker = std::atan2(cy - dy, cx - dx);
  std::ostringstream s;
  s << "PLBEAM 1 1 11 2 12\nPLBEAM 2 2 21 3 22\nPLBEAM 3 4 31 3 32\n"
    << "PLHINGE 4 10 11\nPLHINGE 5 12 21\nPLHINGE 6 22 32\nPLHINGE 7 10 31\n"
    << "X 1 0 0\nX 2 " << fmt(bx) << " " << fmt(by) << "\nX 3 " << fmt(cx) << " " << fmt(cy) << "\nX 4 " << fmt(dx)
    << " 0\n"
    << "BETA 10 0\nBETA 11 " << fmt(g.theta0) << "\nBETA 12 " << fmt(g.theta0) << "\nBETA 21 " << fmt(coupler)
    << "\nBETA 22 " << fmt(coupler) << "\nBETA 31 " << fmt(rocker) << "\nBETA 32 " << fmt(rocker) << "\n"
    << "FIX 1\nFIX 4\nFIX 10\n"
    << crankRole << "\nRLSE 5 1\nRLSE 6 1\nRLSE 7 1\nEND\nHALT\n"
    << "EM 1 1.0 1e-6\nEM 2 1.0 1e-6\nEM 3 1.0 1e-6\n"
    << dynamicLines << "\nEND\nEND\n";
  return s.str();
}

// ------------------------------------------------------------------------------------------------
// Helpers.

inline int coordIndex(const core::Model& m, int nodeLabel, int component /*1-based*/) {
  return m.nodes[m.nodeByLabel.at(nodeLabel)].firstCoord + component - 1;
}

inline int defIndex(const core::Model& m, int elementLabel, int component /*1-based*/) {
  return m.elements[m.elementByLabel.at(elementLabel)].firstDef + component - 1;
}

// Every number of every stored state finite.
inline bool allFinite(const core::Trajectory& tr) {
  for (double t : tr.time)
    if (!std::isfinite(t)) return false;
  for (const auto& s : tr.states)
    if (!s.x.allFinite() || !s.xd.allFinite() || !s.xdd.allFinite() || !s.e.allFinite() || !s.ed.allFinite() ||
        !s.edd.allFinite() || !s.sig.allFinite())
      return false;
  return true;
}

// First non-finite entry of a trajectory, described ("" if none).
inline std::string firstNonFinite(const core::Trajectory& tr) {
  auto check = [](const Eigen::VectorXd& v, const char* name, size_t k, double t) -> std::string {
    for (Eigen::Index i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        return std::string(name) + "[" + std::to_string(i) + "] = " + fmt(v[i]) + " at output " + std::to_string(k) +
               " (t = " + fmt(t) + ")";
    return "";
  };
  for (size_t k = 0; k < tr.states.size(); ++k) {
    const auto& s = tr.states[k];
    const double t = k < tr.time.size() ? tr.time[k] : std::numeric_limits<double>::quiet_NaN();
    for (auto r : {check(s.x, "x", k, t), check(s.xd, "xd", k, t), check(s.xdd, "xdd", k, t), check(s.e, "e", k, t),
                   check(s.ed, "ed", k, t), check(s.edd, "edd", k, t), check(s.sig, "sig", k, t)})
      if (!r.empty()) return r;
  }
  return "";
}

// Total mechanical energy: kinetic 0.5 xd^T M(x) xd + elastic 0.5 e^T S e over the active (dynamic
// and released) deformations of elements with stiffness. inertia is updated to x.
inline double elasticEnergy(const core::Model& m, const Eigen::VectorXd& e) {
  double U = 0.0;
  for (const auto& E : m.elements) {
    if (!E.hasStiffness) continue;
    const int nd = static_cast<int>(E.S.rows());
    for (int i = 0; i < nd; ++i) {
      const core::Role ri = m.eRole[E.firstDef + i];
      if (ri != core::Role::Dynamic && ri != core::Role::Calculable) continue;
      for (int j = 0; j < nd; ++j) {
        const core::Role rj = m.eRole[E.firstDef + j];
        if (rj != core::Role::Dynamic && rj != core::Role::Calculable) continue;
        U += 0.5 * e[E.firstDef + i] * E.S(i, j) * e[E.firstDef + j];
      }
    }
  }
  return U;
}

inline double totalEnergy(const core::Model& m, core::Inertia& inertia, const core::StateOutputs& s) {
  inertia.update(s.x);
  return inertia.kineticEnergy(s.xd) + elasticEnergy(m, s.e);
}

inline bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// The first time named in a stop reason "... at t = 0.0937 ..." (NaN when none).
inline double stopTime(const std::string& reason) {
  const auto p = reason.find("t = ");
  if (p == std::string::npos) return std::nan("");
  return std::atof(reason.c_str() + p + 4);
}

// Wall-clock seconds since construction.
struct Stopwatch {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};

inline bool slowEnabled() {
  const char* v = std::getenv("FLEXMB_SLOW_STRESS");
  return v && std::string(v) == "1";
}

// One summary line per case on stdout, and appended to $FLEXMB_STRESS_CSV when set
// (columns: case,outcome,key_figure,seconds; a header is written when the file is new or empty).
inline std::string csvQuote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += (c == '\n' ? ' ' : c);
  }
  return out + "\"";
}

inline void summary(const std::string& name, const std::string& outcome, const std::string& figure, double seconds) {
  std::printf("[stress] %-34s | %-10s | %s | %.2f s\n", name.c_str(), outcome.c_str(), figure.c_str(), seconds);
  std::fflush(stdout);
  if (const char* path = std::getenv("FLEXMB_STRESS_CSV"); path && *path) {
    bool empty = true;
    {
      std::ifstream in(path);
      empty = !in.good() || in.peek() == std::ifstream::traits_type::eof();
    }
    std::ofstream out(path, std::ios::app);
    if (empty) out << "case,outcome,key_figure,seconds\n";
    out << csvQuote(name) << "," << csvQuote(outcome) << "," << csvQuote(figure) << "," << fmt(seconds) << "\n";
  }
}

}  // namespace flexmb::stress
