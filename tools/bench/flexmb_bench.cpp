// flexmb_bench: benchmarks of the paper's two models (Boer et al. 2013, Section 4).
//   1. Work-precision diagrams: wall time against error for the full and the reduced models with the
//      ode45-equivalent integrator, and for SUNDIALS CVODE (solvers::Bdf: BDF, dense LU; the
//      difference-quotient Jacobian and the analytic one of analysis::StateJacobian, orders <= 5 and
//      <= 2) on the full models, all on the same right-hand side EquationsOfMotion::rhs.
//   2. Cost of one right-hand-side evaluation of the straight guidance against the number of
//      elements per flexure (5 ... 160), with the log-log slope.
//   3. CSV + SVG + a Markdown fragment bench.md for the report.
// Usage: flexmb_bench [--quick] [--out DIR]   (see tools/bench/README.md)
#include <unistd.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "analysis/AccuracyCheck.hpp"
#include "analysis/AnchoredDynamics.hpp"
#include "analysis/Reduction.hpp"
#include "analysis/ReductionError.hpp"
#include "analysis/Simulation.hpp"
#include "analysis/SparseIteration.hpp"
#include "analysis/StateJacobian.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/kinematics/GeometricTransferFunctions.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"
#include "io/pictures/SvgPlot.hpp"
#include "solvers/Bdf.hpp"
#include "solvers/GeneralizedAlpha.hpp"
#include "solvers/Ode45.hpp"

#ifndef FLEXMB_SOURCE_DIR
#define FLEXMB_SOURCE_DIR "."
#endif
#ifndef FLEXMB_BENCH_BUILD_TYPE
#define FLEXMB_BENCH_BUILD_TYPE "unknown"
#endif

namespace fs = std::filesystem;
using namespace flexmb;
using Clock = std::chrono::steady_clock;
using Eigen::VectorXd;

namespace {

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
std::string sci(double v, int digits = 2) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", digits, v);
  return buf;
}
std::string tolText(double v) {  // 1e-03 style, short
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0e", v);
  return buf;
}
std::string secText(double s) {
  if (!std::isfinite(s)) return "-";
  if (s >= 10) return fmt("%.1f", s);
  if (s >= 1) return fmt("%.2f", s);
  if (s >= 0.01) return fmt("%.3f", s);
  return fmt("%.4f", s);
}
std::string withThousands(long v) {
  std::string s = std::to_string(v), out;
  int n = 0;
  for (auto it = s.rbegin(); it != s.rend(); ++it) {
    if (n && n % 3 == 0 && *it != '-') out.push_back(',');
    out.push_back(*it);
    ++n;
  }
  return {out.rbegin(), out.rend()};
}
double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
std::string csvQuote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) {
    if (c == '"')
      o += "\"\"";
    else if (c == '\n')
      o += ' ';
    else
      o += c;
  }
  return o + "\"";
}
std::string mdEscape(std::string s) {
  for (size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
  for (auto& c : s)
    if (c == '\n') c = ' ';
  return s;
}

// ------------------------------------------------------------------------------------------------
// One integration run: statistics and the states at the output times (kept outside the timing).
struct Run {
  bool ok = true;
  std::string reason;                      // why it stopped (failed runs)
  long fevals = 0;                         // every right-hand-side evaluation (CVODE: including the DQ Jacobian ones)
  long jacFevals = 0;                      // CVODE: evaluations spent on difference-quotient Jacobians
  long nsteps = 0, nfailed = 0, njac = 0;  // njac: CVODE's Jacobian evaluations (analytic or DQ)
  double wall = 0.0;  // seconds, model set-up + integration (EquationsOfMotion construction included)
  std::vector<double> t;
  std::vector<VectorXd> y;
  // An observer that keeps every output state (room made for n of them first).
  std::function<bool(double, const VectorXd&)> recorder(std::size_t n) {
    t.reserve(n);
    y.reserve(n);
    return [this](double ti, const VectorXd& yi) {
      t.push_back(ti);
      y.push_back(yi);
      return true;
    };
  }
};

struct Problem {
  const core::Model* model;
  std::optional<Eigen::MatrixXd> basis;
  std::vector<double> tspan;
};

constexpr double kNoCap = 1e300;

Run runOde45(const Problem& p, double relTol, double absTol, double capSeconds) {
  Run r;
  const auto start = Clock::now();
  core::EquationsOfMotion eom(*p.model, p.basis);
  eom.kinematics().setRelativeTolerance(analysis::kinematicTolerance(p.model->settings, relTol));  // as simulate
  solvers::Ode45Options o;
  o.relTol = relTol;
  o.absTol = VectorXd::Constant(1, absTol);
  o.maxStep = p.model->settings.hmax;  // as analysis::simulate
  // Exactly analysis::simulate's right-hand side (plus the wall-time cap).
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    if ((eom.evaluations() & 255) == 255 && since(start) > capSeconds)
      throw solvers::RhsError("wall-time cap of " + fmt("%.0f", capSeconds) + " s reached");
    try {
      eom.rhs(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());
    }
  };
  const auto observer = r.recorder(p.tspan.size());
  const VectorXd y0 = eom.initialState();
  const solvers::OdeResult res = analysis::integrateOde45(eom, o, f, p.tspan, y0, observer);  // as simulate
  r.wall = since(start);
  r.fevals = res.stats.nfevals;
  r.nsteps = res.stats.nsteps;
  r.nfailed = res.stats.nfailed;
  if (res.status != solvers::OdeStatus::Success) {
    r.ok = false;
    r.reason = res.message.empty() ? "integrator stopped" : res.message;
  }
  return r;
}

// ---- SUNDIALS CVODE through solvers::Bdf, as `flexmb simulate --integrator bdf` runs it ---------------
// analytic: the Jacobian from the linearisation (analysis::StateJacobian, Eq. 15); otherwise CVODE's
// difference quotients (2m right-hand sides per Jacobian). maxOrder: the highest BDF order. Every
// evaluation starts the kinematics from the last accepted state (analysis::AnchoredDynamics; README
// "Warm start anchor"), part of the timed work.
Run runBdf(const Problem& p, double relTol, double absTol, double capSeconds, bool analytic, int maxOrder,
           bool alpha = false) {
  Run r;
  const auto start = Clock::now();
  core::Workspace workspace(*p.model);  // shared by eom and jacobian, as simulate does
  core::EquationsOfMotion eom(workspace, p.basis);
  eom.kinematics().setRelativeTolerance(analysis::kinematicTolerance(p.model->settings, relTol));
  std::optional<analysis::StateJacobian> jacobian;
  if (analytic) {
    jacobian.emplace(workspace, p.basis);
    jacobian->kinematics().setRelativeTolerance(analysis::kinematicTolerance(p.model->settings, relTol));
  }
  analysis::AnchoredDynamics dynamics(eom, analytic ? &*jacobian : nullptr);
  long calls = 0;
  auto f = [&](double t, const VectorXd& y, VectorXd& dy) {
    if ((++calls & 255) == 0 && since(start) > capSeconds)
      throw solvers::RhsAbort("wall-time cap of " + fmt("%.0f", capSeconds) + " s reached");
    try {
      dynamics.rhs(t, y, dy);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());  // a trial state: CVODE retries with a smaller step
    }
  };
  solvers::OdeJacobian J;
  if (analytic)
    J = [&](double t, const VectorXd& y, const VectorXd& fy, Eigen::Ref<Eigen::MatrixXd> out) {
      try {
        dynamics.jacobian(t, y, fy, out);
      } catch (const core::KinematicsError& e) {
        throw solvers::RhsError(e.what());
      }
    };
  auto accept = [&](double t, const VectorXd& y) {
    try {
      dynamics.accept(t, y);
    } catch (const core::KinematicsError& e) {
      throw solvers::RhsError(e.what());
    }
  };
  const auto observer = r.recorder(p.tspan.size());
  solvers::BdfOptions o;
  o.relTol = relTol;
  o.absTol = absTol;
  o.maxStep = p.model->settings.hmax;  // as analysis::simulate (0: 0.1 of the span)
  o.maxOrder = maxOrder;
  const VectorXd y0 = eom.initialState();
  solvers::OdeResult res;
  if (alpha) {  // generalized-alpha, as simulate --integrator galpha runs it
    solvers::GeneralizedAlphaOptions ao;
    ao.relTol = relTol;
    ao.absTol = absTol;
    ao.maxStep = o.maxStep;
    if (!p.basis) {
      analysis::SparseIteration system(
          workspace, f, accept, [&]() -> const VectorXd& { return dynamics.anchor(); },
          analysis::kinematicTolerance(p.model->settings, relTol));
      res = solvers::GeneralizedAlpha(ao).integrate(system, p.tspan, y0, observer);
    } else {
      solvers::FirstOrderAsSecondOrder system(f, J, eom.size(), accept);
      res = solvers::GeneralizedAlpha(ao).integrate(system, p.tspan, y0, observer);
    }
  } else {
    res = solvers::Bdf(o).integrate(f, J, p.tspan, y0, observer, accept);
  }
  r.wall = since(start);
  r.fevals = res.stats.nfevals;
  r.jacFevals = res.stats.njacfevals;
  r.njac = res.stats.njacevals;
  r.nsteps = res.stats.nsteps;
  r.nfailed = res.stats.nfailed;  // error-test plus corrector-convergence failures
  if (res.status != solvers::OdeStatus::Success) {
    r.ok = false;
    r.reason = res.message.empty() ? "integrator stopped" : res.message;
  }
  // Our own count (every call) must agree with the integrator's.
  if (calls != r.fevals && r.ok)
    std::fprintf(stderr, "warning: CVODE counted %ld evaluations, the right-hand side saw %ld\n", r.fevals, calls);
  return r;
}

// ------------------------------------------------------------------------------------------------
// Response quantities at the output times (computed after the timing).
struct CaseSpec {
  std::string key, title, file;
  int node = 0;        // response node
  bool xOnly = false;  // guidance: x of node 6; manipulator: the tip position
};

std::vector<Eigen::Vector2d> responses(const Problem& p, const Run& r, int nodeLabel) {
  core::EquationsOfMotion probe(*p.model, p.basis);
  const int first = p.model->nodes[p.model->nodeByLabel.at(nodeLabel)].firstCoord;
  core::StateOutputs out;
  std::vector<Eigen::Vector2d> res;
  res.reserve(r.t.size());
  for (size_t i = 0; i < r.t.size(); ++i) {
    probe.outputs(r.t[i], r.y[i], out);
    res.emplace_back(out.x[first], out.x[first + 1]);
  }
  return res;
}

// The accuracy check simulate runs (analysis/AccuracyCheck.hpp) on a completed run: its windows
// from the stored states, run again at a 100x tighter tolerance with the same integrator (CVODE:
// simulate's, the analytic Jacobian at the variant's highest order). Outside the timing.
core::AccuracyEstimate accuracyOf(const Problem& p, const Run& r, double relTol, double absTol, int bdfOrder,
                                  bool alpha = false) {
  const core::Model& m = *p.model;
  analysis::AccuracyWindowRecorder rec(p.tspan.front(), p.tspan.back());
  core::EquationsOfMotion probe(m, p.basis);
  core::StateOutputs out;
  for (size_t i = 0; i < r.t.size(); ++i) {
    probe.outputs(r.t[i], r.y[i], out);
    rec.observe(r.t[i], r.y[i], out.x);
  }
  analysis::SimulationOptions o;
  o.basis = p.basis;
  o.relTol = relTol;
  o.absTol = absTol;
  if (alpha) {
    o.integrator = analysis::Integrator::GeneralizedAlpha;
  } else if (bdfOrder > 0) {
    o.integrator = analysis::Integrator::Bdf;
    o.bdfMaxOrder = bdfOrder;
  }
  return analysis::checkAccuracy(m, o, p.tspan.front(), p.tspan.back(), rec.complete());
}

// A reduced run's reduction error estimate (analysis/ReductionError.hpp), as simulate prints it:
// from the run's output states. Outside the timing.
core::ReductionEstimate reductionOf(const Problem& p, const Run& r) {
  core::Trajectory traj;
  core::EquationsOfMotion probe(*p.model, p.basis);
  for (size_t i = 0; i < r.t.size(); ++i) {
    core::StateOutputs out;
    probe.outputs(r.t[i], r.y[i], out);
    traj.time.push_back(r.t[i]);
    traj.states.push_back(std::move(out));
  }
  return analysis::estimateReductionError(*p.model, *p.basis, traj);
}

struct Reference {
  std::vector<Eigen::Vector2d> r;
  double scale = 1.0;  // max deflection (guidance) or reach (manipulator)
  std::string scaleText;
};

// NaN when the run did not reach every output time.
double errorAgainst(const std::vector<Eigen::Vector2d>& a, const Reference& ref, bool xOnly) {
  if (a.size() != ref.r.size()) return NAN;
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, xOnly ? std::abs(a[i].x() - ref.r[i].x()) : (a[i] - ref.r[i]).norm());
  return worst / ref.scale;
}

// ------------------------------------------------------------------------------------------------
struct Point {
  std::string model, method, integrator;
  double relTol = 0, absTol = 0;
  // "ok" (completed and converged by the a-posteriori accuracy check of analysis/AccuracyCheck.hpp,
  // as simulate runs it), "not converged" (completed, but the check flags it; its error is still
  // measured and plotted), "failed", "skipped".
  std::string status;
  std::string note;  // failure reason or prediction
  bool completed() const { return status == "ok" || status == "not converged"; }
  double estimate = NAN;   // the accuracy check's estimate of the error (of the model size)
  double reduction = NAN;  // reduced runs: the reduction error estimate (of the motion)
  long fevals = 0, jacFevals = 0, nsteps = 0, nfailed = 0, njac = 0;
  double wall = NAN, error = NAN;
  int runs = 0;
};

struct Method {
  std::string label;       // "full", "MODAL-3", ...
  std::string integrator;  // "ode45" or one of the CVODE variants (kCvode)
  std::optional<Eigen::MatrixXd> basis;
  std::string basisNote;  // size and build time
  int bdfOrder = 0;       // CVODE: the highest BDF order (0: ode45)
  bool analytic = false;  // CVODE: the analytic Jacobian (else difference quotients)
  bool alpha = false;     // generalized-alpha instead of CVODE
};

// The CVODE variants on the full models: CVODE's defaults with its difference-quotient Jacobian, the
// same with the analytic Jacobian, and `simulate --integrator bdf` (analytic, orders <= 2).
// Last, flexmb's generalized-alpha (simulate --integrator galpha; its accuracy check runs BDF2).
struct CvodeVariant {
  const char* name;
  int order;
  bool analytic;
  bool alpha = false;
};
constexpr CvodeVariant kCvode[] = {{"CVODE-BDF DQ J", 5, false},
                                   {"CVODE-BDF analytic J", 5, true},
                                   {"CVODE-BDF2 analytic J", 2, true},
                                   {"generalized-alpha", 2, true, true}};

struct Options {
  bool quick = false;
  std::string out;
  std::string only;  // development: run only the sweeps whose "model method integrator" contains this
};

std::string machineLine(const std::string& key) {
  std::ifstream in(key == "cpu" ? "/proc/cpuinfo" : "/proc/meminfo");
  std::string line;
  const std::string want = key == "cpu" ? "model name" : "MemTotal";
  while (std::getline(in, line))
    if (line.rfind(want, 0) == 0) {
      auto pos = line.find(':');
      std::string v = pos == std::string::npos ? line : line.substr(pos + 1);
      v.erase(0, v.find_first_not_of(" \t"));
      return v;
    }
  return "unknown";
}
std::string memoryText() {
  const std::string m = machineLine("mem");  // "24684092 kB"
  const double kb = std::atof(m.c_str());
  return kb > 0 ? fmt("%.1f", kb / 1048576.0) + " GiB" : m;
}
std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  return fmt("%.2f", a) + " " + fmt("%.2f", b) + " " + fmt("%.2f", c);
}
std::string compilerText() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("g++ ") + __VERSION__;
#else
  return "unknown";
#endif
}

// ------------------------------------------------------------------------------------------------
// Straight guidance with n PLBEAMs per flexure, as datfiles/straight_guidance.dat for n = 5.
//   position nodes: left 1 ... n+1 (x = 0), right 1001 ... 1001+n (x = 0.2)
//   orientation nodes: left 2001 ... 2001+n, right 3001 ... 3001+n
//   elements: left 1 ... n, right 1001 ... 1000+n, rigid body 9001 (top nodes of both flexures)
//   DYNE e2 e3 on every flexure element except: left top element e3 RLSE, right top element e2 e3 RLSE.
std::string guidanceDat(int n) {
  std::ostringstream s;
  s.precision(17);
  s << "% straight guidance, " << n << " PLBEAM elements per flexure (generated by flexmb_bench)\n";
  auto pos = [](int side, int k) { return side == 0 ? k : 1000 + k; };
  auto ori = [](int side, int k) { return side == 0 ? 2000 + k : 3000 + k; };
  auto el = [](int side, int k) { return side == 0 ? k : 1000 + k; };
  for (int side = 0; side < 2; ++side)
    for (int k = 1; k <= n; ++k)
      s << "PLBEAM " << el(side, k) << ' ' << pos(side, k) << ' ' << ori(side, k) << ' ' << pos(side, k + 1) << ' '
        << ori(side, k + 1) << '\n';
  s << "PLBEAM 9001 " << pos(0, n + 1) << ' ' << ori(0, n + 1) << ' ' << pos(1, n + 1) << ' ' << ori(1, n + 1) << '\n';
  for (int side = 0; side < 2; ++side)
    for (int k = 1; k <= n + 1; ++k)
      s << "X " << pos(side, k) << ' ' << (side == 0 ? 0.0 : 0.2) << ' ' << 0.2 * (k - 1) / n << '\n';
  s << "FIX " << pos(0, 1) << "\nFIX " << ori(0, 1) << "\nFIX " << pos(1, 1) << "\nFIX " << ori(1, 1) << '\n';
  for (int k = 1; k < n; ++k) s << "DYNE " << el(0, k) << " 2 3\n";
  s << "DYNE " << el(0, n) << " 2\n";
  for (int k = 1; k < n; ++k) s << "DYNE " << el(1, k) << " 2 3\n";
  s << "RLSE " << el(0, n) << " 3\nRLSE " << el(1, n) << " 2 3\nEND\nHALT\n";
  for (int side = 0; side < 2; ++side)
    for (int k = 1; k <= n; ++k) s << "EM " << el(side, k) << " 0.228 1.9e-8\n";
  s << "EM 9001 6.84 5.13e-4\n";
  for (int side = 0; side < 2; ++side)
    for (int k = 1; k <= n; ++k) s << "ESTIFF " << el(side, k) << " 6.3e6 0.525\n";
  s << "XFT " << pos(0, n + 1) << " 1 \"t <= 0.1 ? 50*(1-cos(20*_pi*t)) : 0\"\n";
  s << "TIMESTEP 0.2 200\nERROR 1e-6 1e-3\nEND\nEND\n";
  return s.str();
}

struct ScalingRow {
  int n = 0, dof = 0, nx = 0, calls = 0;
  double median = NAN, setup = NAN;  // the automatic form (the sparse saddle point for these models)
  double projected = NAN;            // the projected form (dense F_q^T M F_q), small sizes only
};

// Median wall time of one rhs call at t = 0.05 s (load on), the initial configuration and a small
// velocity (etad = 1e-3 in every component), over enough calls for about `budget` seconds.
ScalingRow timeRhs(const core::Model& model, int n, double budget,
                   core::DynamicsForm form = core::DynamicsForm::Automatic) {
  ScalingRow row;
  row.n = n;
  row.dof = model.numDofs();
  row.nx = model.nx;
  const auto s0 = Clock::now();
  core::EquationsOfMotion eom(model, std::nullopt, form);
  row.setup = since(s0);
  VectorXd y = eom.initialState(), dy(y.size());
  y.tail(eom.size()).setConstant(1e-3);
  const double t = 0.05;
  const auto w0 = Clock::now();
  for (int i = 0; i < 3; ++i) eom.rhs(t, y, dy);
  const double est = since(w0) / 3;
  row.calls = static_cast<int>(std::clamp(budget / std::max(est, 1e-9), 7.0, 200000.0));
  std::vector<double> times(row.calls);
  for (int i = 0; i < row.calls; ++i) {
    const auto c0 = Clock::now();
    eom.rhs(t, y, dy);
    times[i] = since(c0);
  }
  row.median = median(times);
  return row;
}

double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t k = x.size();
  if (k < 2) return NAN;
  double mx = 0, my = 0;
  for (size_t i = 0; i < k; ++i) mx += std::log(x[i]), my += std::log(y[i]);
  mx /= k, my /= k;
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < k; ++i) {
    const double dx = std::log(x[i]) - mx;
    sxy += dx * (std::log(y[i]) - my);
    sxx += dx * dx;
  }
  return sxy / sxx;
}

}  // namespace
namespace flexmb::bench {
void eigenFigures();
std::string operatorFigures(bool quick, const std::function<std::string(int)>& guidanceDat);
}  // namespace flexmb::bench
namespace {

void usage() {
  std::cout << "usage: flexmb_bench [--quick] [--out DIR]\n"
               "  --quick    RelTol 1e-2..1e-5, cheaper references, element counts 5..40\n"
               "  --out DIR  output directory (default " FLEXMB_SOURCE_DIR "/validation/report/bench)\n";
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  opt.out = std::string(FLEXMB_SOURCE_DIR) + "/validation/report/bench";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick")
      opt.quick = true;
    else if (a == "--out" && i + 1 < argc)
      opt.out = argv[++i];
    else if (a == "--only" && i + 1 < argc)
      opt.only = argv[++i];
    else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else {
      usage();
      return 2;
    }
  }
  try {
    fs::create_directories(opt.out);
  } catch (const std::exception& e) {
    std::cerr << "flexmb_bench: cannot create " << opt.out << ": " << e.what() << "\n";
    return 1;
  }
  if (opt.only.empty() || opt.only == "eigen") flexmb::bench::eigenFigures();
  if (opt.only == "eigen") return 0;
  std::string operatorMd;
  if (opt.only.empty() || opt.only == "operators") operatorMd = flexmb::bench::operatorFigures(opt.quick, guidanceDat);
  if (opt.only == "operators") {
    std::printf("%s", operatorMd.c_str());
    return 0;
  }
  const auto benchStart = Clock::now();
  const std::string loadBefore = loadAverage();
  std::setvbuf(stdout, nullptr, _IOLBF, 0);

  // ---------------------------------------------------------------- settings
  std::vector<double> tols = opt.quick ? std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5}
                                       : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  const double absFactor = 1e-3;                     // AbsTol = RelTol * 1e-3
  const double skipAbove = opt.quick ? 20.0 : 60.0;  // predicted seconds: skip this and tighter tolerances
  const double hardCap = opt.quick ? 30.0 : 90.0;    // seconds: abort a sweep run
  const int repeatBelow = 2;                         // seconds: 3 runs (median) below, 1 above
  // Reference tolerances (full model, ode45): 1e-10 for both (measured: guidance 331k evaluations,
  // ~13 s; manipulator 6.1M, ~185 s; the guidance at 1e-11 would need 1.1M, ~48 s). Quick: 1e-7,
  // two decades below the tightest swept tolerance.
  const std::map<std::string, double> refTol =
      opt.quick ? std::map<std::string, double>{{"straight_guidance", 1e-7}, {"manipulator", 1e-7}}
                : std::map<std::string, double>{{"straight_guidance", 1e-10}, {"manipulator", 1e-10}};
  // The sparse saddle-point form is O(n): every size; the projected form (dense, O(n^3)) up to
  // maxProjected elements per flexure.
  const std::vector<int> sizes = {5, 10, 20, 40, 80, 160, 320, 640};
  const int maxProjected = opt.quick ? 80 : 160;
  const double rhsBudget = opt.quick ? 0.05 : 0.2;

  const std::string src = FLEXMB_SOURCE_DIR;
  std::vector<CaseSpec> cases = {
      {"straight_guidance", "straight guidance (0.2 s)", src + "/datfiles/straight_guidance.dat", 6, true},
      {"manipulator", "two-link manipulator (0.7 s)", src + "/datfiles/manipulator.dat", 9, false}};

  std::vector<Point> points;
  std::map<std::string, std::string> refNotes, basisNotes;
  std::map<std::string, std::string> svgFiles;
  std::vector<std::string> skippedList;

  for (const CaseSpec& cs : cases) {
    if (opt.only == "rhs") break;  // development: the rhs scaling only
    const core::Model model = io::readDatFile(cs.file);
    Problem full{&model, std::nullopt, {}};
    const auto& s = model.settings;
    for (int i = 0; i <= s.outputIntervals; ++i) full.tspan.push_back(s.t0 + (s.tEnd - s.t0) * i / s.outputIntervals);

    // ---- reference
    const double rt = refTol.at(cs.key);
    std::printf("[%s] reference: full model, ode45, RelTol %s AbsTol %s ...\n", cs.key.c_str(), tolText(rt).c_str(),
                tolText(rt * absFactor).c_str());
    const Run refRun = runOde45(full, rt, rt * absFactor, kNoCap);
    if (!refRun.ok) {
      std::fprintf(stderr, "flexmb_bench: the reference run of %s failed: %s\n", cs.key.c_str(), refRun.reason.c_str());
      return 1;
    }
    Reference ref;
    ref.r = responses(full, refRun, cs.node);
    if (cs.xOnly) {
      double d = 0;
      for (const auto& p : ref.r) d = std::max(d, std::abs(p.x() - ref.r.front().x()));
      ref.scale = d;
      ref.scaleText = "max |x(node " + std::to_string(cs.node) + ") - x0| = " + fmt("%.5f", d) + " m";
    } else {
      // Reach: base to elbow plus elbow to tip in the initial configuration.
      auto at = [&](int label) {
        const int f = model.nodes[model.nodeByLabel.at(label)].firstCoord;
        return Eigen::Vector2d(model.x0[f], model.x0[f + 1]);
      };
      ref.scale = (at(5) - at(1)).norm() + (at(9) - at(5)).norm();
      ref.scaleText = "reach |node 5 - node 1| + |node 9 - node 5| = " + fmt("%.4f", ref.scale) + " m";
    }
    std::printf("[%s] reference: %ld fevals, %s s; %s\n", cs.key.c_str(), refRun.fevals, secText(refRun.wall).c_str(),
                ref.scaleText.c_str());
    refNotes[cs.key] = "full model, ode45-equivalent, RelTol " + tolText(rt) + ", AbsTol " + tolText(rt * absFactor) +
                       " (" + withThousands(refRun.fevals) + " fevals, " + secText(refRun.wall) +
                       " s); error scale: " + ref.scaleText;

    // ---- methods
    std::vector<Method> methods;
    methods.push_back({"full", "ode45", std::nullopt, ""});
    auto addBasis = [&](const std::string& label, analysis::ReductionOptions ro) {
      const auto b0 = Clock::now();
      const analysis::ReductionResult rr = analysis::buildBasis(model, ro);
      const double bt = since(b0);
      const int nl = static_cast<int>(rr.large.size());
      std::string lab = label;
      if (ro.method == "svd-modal") {  // the label's mode count is the number the 1% criterion keeps
        const int kept = static_cast<int>(rr.V.cols()) - nl;
        lab = "SVDm-" + std::to_string(kept) + "-a" + fmt("%g", ro.weight);
      }
      methods.push_back({lab, "ode45", rr.V, ""});
      basisNotes[cs.key] += (basisNotes[cs.key].empty() ? "" : "; ") + lab + ": " + std::to_string(rr.V.cols()) +
                            " columns, built in " + secText(bt) + " s";
    };
    if (cs.key == "straight_guidance") {
      for (int r : {3, 5}) {
        analysis::ReductionOptions ro;
        ro.method = "modal";
        ro.modes = r;
        addBasis("MODAL-" + std::to_string(r), ro);
      }
      for (double a : {0.0, 1.0}) {
        analysis::ReductionOptions ro;
        ro.method = "svd-modal";
        ro.modes = 3;
        ro.configs = 10;
        ro.weight = a;
        ro.threshold = 0.01;
        ro.node = 6;
        ro.component = 1;
        ro.from = -0.0833;
        ro.to = 0.0833;
        addBasis("SVDm", ro);
      }
    } else {
      analysis::ReductionOptions ro;
      ro.method = "modal";
      ro.modes = 2;
      addBasis("MODAL-2", ro);
    }
    for (const CvodeVariant& v : kCvode)
      methods.push_back({"full", v.name, std::nullopt, "", v.order, v.analytic, v.alpha});

    // ---- sweeps
    for (const Method& m : methods) {
      if (!opt.only.empty() && (cs.key + " " + m.label + " " + m.integrator).find(opt.only) == std::string::npos)
        continue;
      const Problem prob{&model, m.basis, full.tspan};
      const bool cv = m.bdfOrder > 0;
      double lastWall = NAN, lastFe = NAN, prevFe = NAN;
      bool stop = false;
      double predicted = NAN;
      for (double tol : tols) {
        Point pt;
        pt.model = cs.key;
        pt.method = m.label;
        pt.integrator = m.integrator;
        pt.relTol = tol;
        pt.absTol = tol * absFactor;
        // Prediction from the growth of the evaluation count (at least 10^(1/5) per decade).
        if (!stop && std::isfinite(lastWall)) {
          double ratio = std::isfinite(prevFe) && prevFe > 0 ? lastFe / prevFe : 1.0;
          ratio = std::max(ratio, std::pow(10.0, 0.2));
          predicted = lastWall * ratio;
          if (predicted > skipAbove) stop = true;
        } else if (stop) {
          predicted *= std::pow(10.0, 0.2);
        }
        const std::string tag = "[" + cs.key + "] " + m.label + " / " + m.integrator + " RelTol " + tolText(tol);
        if (stop) {
          pt.status = "skipped";
          pt.note = "predicted > " + fmt("%.0f", predicted) + " s";
          std::printf("%s: skipped (predicted %.0f s > %.0f s)\n", tag.c_str(), predicted, skipAbove);
          skippedList.push_back(cs.key + " " + m.label + " (" + m.integrator + ") RelTol " + tolText(tol) + ": " +
                                pt.note);
          points.push_back(pt);
          continue;
        }
        auto once = [&]() {
          try {
            return cv ? runBdf(prob, tol, tol * absFactor, hardCap, m.analytic, m.bdfOrder, m.alpha)
                      : runOde45(prob, tol, tol * absFactor, hardCap);
          } catch (const std::exception& e) {  // set-up or initial kinematics: a failed run, not a crash
            Run bad;
            bad.ok = false;
            bad.reason = e.what();
            return bad;
          }
        };
        Run r = once();
        std::vector<double> walls{r.wall};
        if (r.ok && r.wall < repeatBelow) {
          for (int k = 0; k < 2; ++k) walls.push_back(once().wall);
        }
        pt.runs = static_cast<int>(walls.size());
        pt.wall = median(walls);
        pt.fevals = r.fevals;
        pt.jacFevals = r.jacFevals;
        pt.njac = r.njac;
        pt.nsteps = r.nsteps;
        pt.nfailed = r.nfailed;
        if (r.ok) {
          try {
            pt.error = errorAgainst(responses(prob, r, cs.node), ref, cs.xOnly);
            pt.status = std::isfinite(pt.error) ? "ok" : "failed";
            if (!std::isfinite(pt.error)) pt.note = "non-finite response";
          } catch (const std::exception& e) {
            pt.status = "failed";
            pt.note = std::string("response evaluation: ") + e.what();
          }
          if (pt.status != "failed" && prob.basis) {
            try {
              const core::ReductionEstimate re = reductionOf(prob, r);
              if (re.estimated) pt.reduction = re.estimate;
            } catch (const std::exception&) {  // the column stays empty
            }
          }
          if (pt.status == "ok") {  // "ok" means converged, as simulate's accuracy check says it
            try {
              const core::AccuracyEstimate acc = accuracyOf(prob, r, tol, tol * absFactor, m.bdfOrder, m.alpha);
              pt.estimate = acc.checked ? acc.estimate : NAN;
              if (!acc.converged()) {
                pt.status = "not converged";
                pt.note = "accuracy check: estimated error " + sci(acc.estimate, 1) + " > " + sci(acc.limit, 1) +
                          " (10 RelTol)";
              } else if (!acc.checked) {
                pt.note = "accuracy check not run: " + acc.note;
              }
            } catch (const std::exception& e) {
              pt.note = std::string("accuracy check not run: ") + e.what();
            }
          }
        } else {
          pt.status = "failed";
          pt.note = r.reason;
        }
        if (pt.completed()) {
          std::printf("%s: %ld fevals%s, %s s (%s), error %s, accuracy check %s, reduction estimate %s%s\n",
                      tag.c_str(), pt.fevals,
                      cv ? (" (" + std::to_string(pt.njac) + " Jacobians, " + std::to_string(pt.jacFevals) +
                            " evaluations in them)")
                               .c_str()
                         : "",
                      secText(pt.wall).c_str(), pt.runs > 1 ? "median of 3" : "1 run", sci(pt.error).c_str(),
                      std::isfinite(pt.estimate) ? sci(pt.estimate, 1).c_str() : "-",
                      std::isfinite(pt.reduction) ? sci(pt.reduction, 1).c_str() : "-",
                      pt.status == "ok" ? "" : " (NOT CONVERGED)");
          prevFe = lastFe;
          lastFe = static_cast<double>(pt.fevals);
          lastWall = pt.wall;
        } else {
          std::printf("%s: FAILED after %s s, %ld fevals: %s\n", tag.c_str(), secText(pt.wall).c_str(), pt.fevals,
                      pt.note.c_str());
          if (pt.wall > skipAbove) {  // hit the cap: tighter tolerances only cost more
            stop = true;
            predicted = pt.wall;
          }
        }
        points.push_back(pt);
      }
    }

    // ---- work-precision diagrams (wall time and evaluations)
    for (int kind = 0; kind < 2; ++kind) {
      io::Plot plot;
      plot.title = "Work-precision: " + cs.title;
      plot.x = {"error: max over output times of |response - reference| / " +
                    std::string(cs.xOnly ? "max deflection" : "reach"),
                true, std::nullopt, std::nullopt};
      plot.y = {kind == 0 ? "wall time [s] (median)" : "right-hand-side evaluations", true, std::nullopt, std::nullopt};
      plot.notes.push_back("RelTol " + tolText(tols.front()) + " ... " + tolText(tols.back()) +
                           " (AbsTol = 1e-3 RelTol); reference: full model, ode45, RelTol " + tolText(rt));
      plot.notes.push_back(cs.xOnly ? "response: x of node 6 (rigid body)" : "response: tip position (node 9)");
      std::map<std::string, size_t> seriesOf;
      for (const Point& pt : points) {
        if (pt.model != cs.key) continue;
        const std::string label = pt.method + " (" + pt.integrator + ")";
        if (!seriesOf.count(label)) {
          seriesOf[label] = plot.series.size();
          io::Series se;
          se.label = label;
          se.markers = true;
          se.dashed = pt.integrator != "ode45";
          plot.series.push_back(se);
        }
        if (!pt.completed()) continue;  // a run the accuracy check flags is still a measured point
        auto& se = plot.series[seriesOf[label]];
        se.x.push_back(pt.error);
        se.y.push_back(kind == 0 ? pt.wall : static_cast<double>(pt.fevals));
      }
      const std::string name = (kind == 0 ? "wp_" : "wp_fevals_") + cs.key + ".svg";
      io::writeSvg(opt.out + "/" + name, plot);
      svgFiles[cs.key + (kind == 0 ? "" : "_fevals")] = name;
    }
  }

  // ---------------------------------------------------------------- the elbow (stiff spatial dynamics)
  // Simo & Vu-Quoc's right-angle cantilever (datfiles/spatial/elbow.dat, 2 x 10 BEAMs; elbow_fine.dat,
  // 2 x 20): the out-of-plane displacement of the elbow and the tip against the stored converged
  // reference (datfiles/spatial/elbow_reference.csv), per integrator and tolerance.
  struct ElbowPoint {
    std::string file, integrator;
    double relTol = 0, wall = NAN, error = NAN;
    long fevals = 0, njac = 0, nsteps = 0;
    std::string note;
  };
  std::vector<ElbowPoint> elbow;
  std::string elbowCost;  // the iteration matrix's cost in right-hand sides
  if (opt.only.empty() || opt.only.find("elbow") != std::string::npos) {
    std::vector<std::array<double, 3>> refRows;  // t, elbow z, tip z
    {
      std::ifstream in(src + "/datfiles/spatial/elbow_reference.csv");
      std::string line;
      while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line[0] == 't') continue;
        std::array<double, 3> r{};
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &r[0], &r[1], &r[2]) == 3) refRows.push_back(r);
      }
    }
    double lo = 1e300, hi = -1e300;
    for (const auto& r : refRows) lo = std::min(lo, r[2]), hi = std::max(hi, r[2]);
    const double range = hi - lo;
    struct ElbowRun {
      const char* file;
      int elbowNode, tipNode;
      analysis::Integrator integrator;
      std::vector<double> tols;
    };
    std::vector<ElbowRun> plan = {
        {"elbow.dat", 21, 41, analysis::Integrator::GeneralizedAlpha, {1e-2, 1e-3, 1e-4, 1e-5}},
        {"elbow.dat", 21, 41, analysis::Integrator::Bdf, {1e-2, 1e-3}},
        {"elbow.dat", 21, 41, analysis::Integrator::Ode45, {1e-3}},
        {"elbow.dat", 21, 41, analysis::Integrator::Auto, {1e-3}},
        {"elbow_fine.dat", 41, 81, analysis::Integrator::GeneralizedAlpha, {1e-3}},
        {"elbow_fine.dat", 41, 81, analysis::Integrator::Auto, {1e-3}}};
    if (!opt.quick) plan[1].tols.push_back(1e-4);
    for (const ElbowRun& er : plan) {
      const core::Model model = io::readDatFile(src + "/datfiles/spatial/" + er.file);
      const int ze = model.nodes[model.nodeByLabel.at(er.elbowNode)].firstCoord + 2;
      const int zt = model.nodes[model.nodeByLabel.at(er.tipNode)].firstCoord + 2;
      for (double tol : er.tols) {
        ElbowPoint pt;
        pt.file = er.file;
        pt.integrator = analysis::integratorName(er.integrator);
        pt.relTol = tol;
        analysis::SimulationOptions so;
        so.integrator = er.integrator;
        so.relTol = tol;
        so.absTol = 1e-3 * tol;
        std::atomic<bool> stopFlag{false};
        so.interrupt = &stopFlag;
        std::thread watchdog;  // the cap: ode45 on the elbow takes minutes at tight tolerances
        bool done = false;
        std::mutex mu;
        std::condition_variable cv;
        watchdog = std::thread([&] {
          std::unique_lock<std::mutex> lock(mu);
          if (!cv.wait_for(lock, std::chrono::duration<double>(hardCap), [&] { return done; })) stopFlag = true;
        });
        const auto t0 = Clock::now();
        core::Trajectory run;
        try {
          run = analysis::simulate(model, so);
        } catch (const std::exception& e) {
          run.completed = false;
          run.stopReason = e.what();
        }
        pt.wall = since(t0);
        {
          std::lock_guard<std::mutex> lock(mu);
          done = true;
        }
        cv.notify_all();
        watchdog.join();
        pt.fevals = run.nfevals;
        pt.njac = run.njacevals;
        pt.nsteps = run.nsteps;
        if (run.completed && run.time.size() == refRows.size() && range > 0) {
          double worst = 0.0;
          for (size_t i = 0; i < refRows.size(); ++i)
            worst = std::max(
                {worst, std::abs(run.states[i].x[ze] - refRows[i][1]), std::abs(run.states[i].x[zt] - refRows[i][2])});
          pt.error = worst / range;
        } else {
          pt.note = stopFlag ? "stopped at the " + fmt("%.0f", hardCap) + " s cap" : run.stopReason;
        }
        std::printf("[elbow] %s %s RelTol %s: %s s, %ld steps, %ld fevals, %ld Jacobians, error %s%s\n", er.file,
                    pt.integrator.c_str(), tolText(tol).c_str(), secText(pt.wall).c_str(), pt.nsteps, pt.fevals,
                    pt.njac, std::isfinite(pt.error) ? sci(pt.error).c_str() : "-",
                    pt.note.empty() ? "" : (" (" + pt.note + ")").c_str());
        std::fflush(stdout);
        elbow.push_back(pt);
      }
    }
    // The iteration matrix's cost in right-hand sides (a state of the run at t = 1.5 s: bent and moving).
    for (const char* file : {"elbow.dat", "elbow_fine.dat"}) {
      const core::Model model = io::readDatFile(src + "/datfiles/spatial/" + file);
      core::Workspace ws(model);
      core::EquationsOfMotion eom(ws);
      core::Linearization lin(ws);
      analysis::StateJacobian dense(ws, std::nullopt);
      const int m = eom.size();
      VectorXd y = eom.initialState(), dy(2 * m);
      y.head(m).setConstant(2e-3);
      y.tail(m).setConstant(1e-2);
      Eigen::MatrixXd J(2 * m, 2 * m);
      auto perCall = [](int n, auto&& fn) {
        fn();
        const auto t0 = Clock::now();
        for (int i = 0; i < n; ++i) fn();
        return since(t0) / n;
      };
      const double rhs = perCall(200, [&] { eom.rhs(1.5, y, dy); });
      const VectorXd q = y.head(m);
      const double iteration = perCall(50, [&] {
        lin.iterationMatrix(1.5, q);
        lin.factorizeIteration(0.01, 0.1);
      });
      const double eq15 = perCall(3, [&] { dense.evaluate(1.5, y, dy, J); });
      std::printf(
          "[elbow] %s: one right-hand side %s us; the sparse iteration matrix (evaluated and factorised) %s "
          "us = %.1f right-hand sides; the dense Jacobian of Eq. 15 %s us = %.0f right-hand sides\n",
          file, fmt("%.1f", rhs * 1e6).c_str(), fmt("%.1f", iteration * 1e6).c_str(), iteration / rhs,
          fmt("%.0f", eq15 * 1e6).c_str(), eq15 / rhs);
      elbowCost += std::string(elbowCost.empty() ? "" : "; ") + file + ": one right-hand side " +
                   fmt("%.1f", rhs * 1e6) + " us, the sparse iteration matrix " + fmt("%.1f", iteration / rhs) +
                   " right-hand sides, the dense Jacobian of Eq. 15 " + fmt("%.0f", eq15 / rhs);
    }
    io::Plot plot;
    plot.title = "Work-precision: elbow (Simo & Vu-Quoc), 2 x 10 BEAMs, 30 s";
    plot.x = {"error: max over output times of |z - reference| (elbow and tip) / tip range", true, std::nullopt,
              std::nullopt};
    plot.y = {"wall time [s]", true, std::nullopt, std::nullopt};
    plot.notes.push_back("reference: datfiles/spatial/elbow_reference.csv (generalized-alpha, RelTol 1e-7)");
    for (const char* integ : {"galpha", "bdf", "ode45", "auto"}) {
      io::Series se;
      se.label = integ;
      se.markers = true;
      for (const ElbowPoint& p : elbow)
        if (p.file == "elbow.dat" && p.integrator == integ && std::isfinite(p.error))
          se.x.push_back(p.error), se.y.push_back(p.wall);
      if (!se.x.empty()) plot.series.push_back(se);
    }
    io::writeSvg(opt.out + "/wp_elbow.svg", plot);
  }

  // ---------------------------------------------------------------- RHS cost scaling
  std::vector<ScalingRow> rows;
  double checkDiff = NAN;
  {
    // n = 5 generated against the shipped file: same equations (up to numbering).
    const core::Model a = io::readDatFile(src + "/datfiles/straight_guidance.dat");
    const core::Model b = io::readDatString(guidanceDat(5), "straight_guidance_n5.dat");
    core::EquationsOfMotion ea(a), eb(b);
    VectorXd ya = ea.initialState(), yb = eb.initialState();
    if (ya.size() == yb.size()) {
      ya.tail(ea.size()).setConstant(1e-3);
      yb.tail(eb.size()).setConstant(1e-3);
      VectorXd da(ya.size()), db(yb.size());
      ea.rhs(0.05, ya, da);
      eb.rhs(0.05, yb, db);
      checkDiff = (da - db).norm() / da.norm();
    }
    std::printf(
        "[rhs scaling] generated n = 5 model against datfiles/straight_guidance.dat: relative rhs difference %s\n",
        std::isfinite(checkDiff) ? sci(checkDiff).c_str() : "(DOF counts differ)");
  }
  for (int n : sizes) {
    const core::Model m = io::readDatString(guidanceDat(n), "straight_guidance_n" + std::to_string(n) + ".dat");
    ScalingRow row = timeRhs(m, n, rhsBudget);
    if (n <= maxProjected) row.projected = timeRhs(m, n, rhsBudget, core::DynamicsForm::Projected).median;
    std::printf(
        "[rhs scaling] n = %d elements per flexure: %d DOF, median %s us over %d calls (projected form: %s us)\n", n,
        row.dof, fmt("%.2f", row.median * 1e6).c_str(), row.calls,
        std::isfinite(row.projected) ? fmt("%.2f", row.projected * 1e6).c_str() : "not timed");
    rows.push_back(row);
  }
  std::vector<double> xs, xd, ys;
  for (const auto& r : rows) xs.push_back(r.n), xd.push_back(r.dof), ys.push_back(r.median);
  const double slopeAll = slope(xs, ys), slopeAllDof = slope(xd, ys);
  const size_t k3 = xs.size() >= 3 ? xs.size() - 3 : 0;
  const double slopeLast = slope({xs.begin() + k3, xs.end()}, {ys.begin() + k3, ys.end()});
  const double slopeLastDof = slope({xd.begin() + k3, xd.end()}, {ys.begin() + k3, ys.end()});
  std::printf("[rhs scaling] log-log slope against elements per flexure: %.2f (all sizes), %.2f (last three)\n",
              slopeAll, slopeLast);
  {
    io::Plot plot;
    plot.title = "Right-hand-side cost: straight guidance, n elements per flexure";
    plot.x = {"elements per flexure n (DOF = 4n - 3)", true, std::nullopt, std::nullopt};
    plot.y = {"wall time of one rhs evaluation [s] (median)", true, std::nullopt, std::nullopt};
    plot.notes.push_back("log-log slope " + fmt("%.2f", slopeAll) + " (least squares, all sizes), " +
                         fmt("%.2f", slopeLast) + " (last three sizes)");
    io::Series se;
    se.label = "saddle point (automatic)";
    se.markers = true;
    se.x = xs;
    se.y = ys;
    plot.series.push_back(se);
    io::Series sp;
    sp.label = "projected (dense F_q^T M F_q)";
    sp.markers = true;
    for (const auto& r : rows)
      if (std::isfinite(r.projected)) sp.x.push_back(r.n), sp.y.push_back(r.projected);
    plot.series.push_back(sp);
    // Reference slopes 1, 2, 3 through the largest size.
    for (double p : {1.0, 2.0, 3.0}) {
      io::Series r;
      r.label = "slope " + fmt("%g", p);
      r.dashed = true;
      r.x = {xs.front(), xs.back()};
      r.y = {ys.back() * std::pow(xs.front() / xs.back(), p), ys.back()};
      plot.series.push_back(r);
    }
    io::writeSvg(opt.out + "/rhs_scaling.svg", plot);
  }

  // ---------------------------------------------------------------- CSV
  {
    std::ofstream f(opt.out + "/workprecision.csv");
    f << "model,method,integrator,reltol,abstol,status,fevals,jacobian_fevals,jacobians,steps,failed_steps,wall_s,runs,"
         "error,accuracy_estimate,"
         "note\n";
    for (const Point& p : points) {
      f << p.model << ',' << p.method << ',' << p.integrator << ',' << sci(p.relTol, 1) << ',' << sci(p.absTol, 1)
        << ',' << p.status << ',' << (p.status == "skipped" ? "" : std::to_string(p.fevals)) << ','
        << (p.status == "skipped" || p.integrator == "ode45" ? "" : std::to_string(p.jacFevals)) << ','
        << (p.status == "skipped" || p.integrator == "ode45" ? "" : std::to_string(p.njac)) << ','
        << (p.status == "skipped" ? "" : std::to_string(p.nsteps)) << ','
        << (p.status == "skipped" ? "" : std::to_string(p.nfailed)) << ','
        << (std::isfinite(p.wall) ? fmt("%.6g", p.wall) : "") << ',' << (p.runs ? std::to_string(p.runs) : "") << ','
        << (std::isfinite(p.error) ? sci(p.error, 4) : "") << ','
        << (std::isfinite(p.estimate) ? sci(p.estimate, 2) : "") << ',' << csvQuote(p.note) << '\n';
    }
    std::ofstream g(opt.out + "/rhs_scaling.csv");
    g << "elements_per_flexure,dof,nodal_coordinates,calls,median_rhs_s,eom_setup_s,median_rhs_projected_s\n";
    for (const auto& r : rows)
      g << r.n << ',' << r.dof << ',' << r.nx << ',' << r.calls << ',' << fmt("%.6e", r.median) << ','
        << fmt("%.6e", r.setup) << ',' << (std::isfinite(r.projected) ? fmt("%.6e", r.projected) : std::string())
        << '\n';
  }

  // ---------------------------------------------------------------- bench.md
  const double totalTime = since(benchStart);
  std::ofstream md(opt.out + "/bench.md");
  std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  md << "## Benchmarks" << (opt.quick ? " (quick mode)" : "") << "\n\n";
  md << "Produced by `flexmb_bench" << (opt.quick ? " --quick" : "") << "` on " << date << " in " << secText(totalTime)
     << " s (tools/bench/README.md). Links are relative to this file's directory.\n\n";
  md << "**Machine.** " << sysconf(_SC_NPROCESSORS_ONLN) << " cores (`nproc`), CPU " << machineLine("cpu")
     << ", memory " << memoryText() << "; compiler " << compilerText() << ", build type " << FLEXMB_BENCH_BUILD_TYPE
#ifdef NDEBUG
     << " (NDEBUG)"
#endif
     << "; Eigen " << EIGEN_WORLD_VERSION << '.' << EIGEN_MAJOR_VERSION << '.' << EIGEN_MINOR_VERSION << ", "
     << solvers::Bdf::library() << ". Load average before/after: " << loadBefore << " / " << loadAverage()
     << " (the machine may be shared; single-threaded runs).\n\n";
  md << "**Set-up.** Tolerances RelTol " << tolText(tols.front()) << " ... " << tolText(tols.back())
     << " per decade, AbsTol = RelTol x 1e-3 (scalar), for every method. Wall time = model set-up "
        "(EquationsOfMotion) plus integration with the states stored at the model's output times (output "
        "quantities are evaluated afterwards, untimed); median of 3 runs when a run takes < "
     << repeatBelow
     << " s, else 1 run. A point predicted (from the growth of the evaluation count, at least "
        "10^(1/5) per decade) to take more than "
     << fmt("%.0f", skipAbove) << " s is skipped with the tighter ones; a run is stopped at " << fmt("%.0f", hardCap)
     << " s. Error = max over the output times of |response - reference| divided by the max reference deflection of x "
        "(node 6, relative to its initial value) for the straight guidance, and the tip position distance (node 9) "
        "divided by the reach for the manipulator. Reduced models are measured against the full model's "
        "reference, so their curves level off at their reduction error.\n\n";
  md << "- ode45: flexmb's ode45-equivalent (Dormand-Prince 5(4), MATLAB's step control), same counting rule as "
        "MATLAB.\n";
  md << "- Status **ok**: the run completed and `simulate`'s a-posteriori accuracy check (analysis/AccuracyCheck.hpp: "
        "three windows of the run, a tenth of the span, integrated again at a 100x tighter tolerance; their largest "
        "difference per second times the span, in positions relative to the model size) finds it converged, i.e. "
        "the estimate is at most 10 RelTol. **not converged**: completed, but the estimate is larger; such runs are "
        "plotted with their measured error. The column *accuracy check* is that estimate (the *error* column is the "
        "error measured against the reference, on its own scale). The column *reduction estimate* is what every "
        "reduced run of `simulate` prints beside it: its reduction error estimate (analysis/ReductionError.hpp; "
        "every position, of the motion: a measure of its own, comparable with the validation report's true errors, "
        "not with the *error* column's single response).\n";
  md << "- CVODE: " << solvers::Bdf::library()
     << " through solvers::Bdf (as `flexmb simulate --integrator bdf`): BDF, Newton with the dense direct linear "
        "solver, "
        "on the same right-hand side, in three variants: **CVODE-BDF DQ J** (orders 1-5, CVODE's difference-quotient "
        "Jacobian), **CVODE-BDF analytic J** (orders 1-5, the Jacobian [[0, I], [-M^-1 (K+N+G), -M^-1 (C+D)]] from the "
        "linearisation of Eq. 15, analysis::StateJacobian) and **CVODE-BDF2 analytic J** (the same with orders 1-2, "
        "A-stable: simulate's default). Counts: fevals includes the difference-quotient evaluations; (J n: m) gives "
        "the "
        "Jacobian evaluations n and the right-hand sides m spent on them; failed steps are error-test plus "
        "corrector-convergence failures. Every evaluation starts the kinematic Newton solve from the configuration of "
        "the "
        "last accepted step (tools/bench/README.md: without this anchor CVODE's trial states spoil the warm start). "
        "Note CVODE's error test uses a weighted RMS norm, ode45 a max norm.\n";
  for (const CaseSpec& cs : cases) {
    md << "- Reference " << cs.key << ": " << refNotes[cs.key] << ".\n";
    md << "- Bases " << cs.key << ": " << basisNotes[cs.key] << ".\n";
  }
  {
    // How far the references resolve: the error of the tightest full ode45 point against them.
    std::string res;
    for (const CaseSpec& cs : cases) {
      const Point* tight = nullptr;
      for (const Point& p : points)
        if (p.model == cs.key && p.method == "full" && p.integrator == "ode45" && p.status == "ok" &&
            (!tight || p.relTol < tight->relTol))
          tight = &p;
      if (tight)
        res += (res.empty() ? "" : ", ") + cs.key + " " + sci(tight->error, 1) + " at RelTol " + tolText(tight->relTol);
    }
    md << "- Reference choice: "
       << (opt.quick
               ? "quick mode uses RelTol 1e-7 for both references (two decades below the tightest swept tolerance). "
               : "RelTol 1e-10 for both models (costs above; the manipulator's is the largest item of the budget; "
                 "the guidance at 1e-11 was measured separately at 1.1M evaluations, ~48 s, and not used: it would "
                 "change no conclusion). ")
       << "The full model's own errors level off near the references' resolution (" << res
       << "); smaller differences are not resolved.\n";
  }
  md << "\n";
  for (const CaseSpec& cs : cases) {
    md << "### " << cs.title << "\n\n";
    md << "![work-precision " << cs.key << "](" << svgFiles[cs.key] << ")\n\n";
    md << "Evaluation counts instead of time: [" << svgFiles[cs.key + "_fevals"] << "](" << svgFiles[cs.key + "_fevals"]
       << ")\n\n";
    md << "| method | integrator | RelTol | status | fevals | steps (failed) | wall time [s] | runs | us/feval | error "
          "| accuracy check | reduction estimate |\n";
    md << "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Point& p : points) {
      if (p.model != cs.key) continue;
      md << "| " << p.method << " | " << p.integrator << " | " << tolText(p.relTol) << " | ";
      if (p.status == "ok")
        md << "ok";
      else
        md << p.status << ": " << mdEscape(p.note.size() > 170 ? p.note.substr(0, 167) + "..." : p.note);
      md << " | ";
      if (p.status == "skipped") {
        md << "- | - | - | - | - | - | - | - |\n";
        continue;
      }
      md << withThousands(p.fevals);
      if (p.integrator != "ode45") md << " (J " << withThousands(p.njac) << ": " << withThousands(p.jacFevals) << ")";
      md << " | " << withThousands(p.nsteps) << " (" << withThousands(p.nfailed) << ") | " << secText(p.wall) << " | "
         << p.runs << " | " << (p.fevals > 0 ? fmt("%.1f", p.wall / p.fevals * 1e6) : std::string("-")) << " | "
         << (p.completed() ? sci(p.error) : std::string("-")) << " | "
         << (std::isfinite(p.estimate) ? sci(p.estimate, 1) : std::string("-")) << " | "
         << (std::isfinite(p.reduction) ? sci(p.reduction, 1) : std::string("-")) << " |\n";
    }
    md << "\n";
  }
  if (!elbow.empty()) {
    md << "### Stiff spatial dynamics: the elbow of Simo & Vu-Quoc\n\n"
       << "datfiles/spatial/elbow.dat (2 x 10 BEAMs, 120 DOF) and elbow_fine.dat (2 x 20, 240 DOF), 30 s, output "
          "every 0.1 s, AbsTol = 1e-3 RelTol. Error: the largest deviation of the elbow's and the tip's "
          "out-of-plane displacement from datfiles/spatial/elbow_reference.csv, relative to the tip's range. ode45 "
          "and BDF runs are capped at "
       << fmt("%.0f", hardCap) << " s.\n\n"
       << "| model | integrator | RelTol | wall [s] | steps | fevals | Jacobians | error "
          "|\n|---|---|---|---|---|---|---|---|\n";
    for (const ElbowPoint& p : elbow)
      md << "| " << p.file << " | " << p.integrator << " | " << tolText(p.relTol) << " | " << secText(p.wall) << " | "
         << p.nsteps << " | " << p.fevals << " | " << p.njac << " | "
         << (std::isfinite(p.error) ? sci(p.error) : p.note) << " |\n";
    md << "\nCost of one iteration matrix (at a bent, moving state): " << elbowCost << ".\n\n";
    md << "![work-precision elbow](wp_elbow.svg)\n\n";
  }
  md << "### Right-hand-side cost against model size\n\n";
  md << "Straight guidance with n PLBEAM elements per flexure (geometry, material, load and DYNE/RLSE pattern of "
        "datfiles/straight_guidance.dat), one rhs evaluation at t = 0.05 s in the initial configuration with "
        "etad = 1e-3 in every component; median over the calls shown. The generated n = 5 model agrees with "
        "datfiles/straight_guidance.dat to a relative rhs difference of "
     << (std::isfinite(checkDiff) ? sci(checkDiff) : std::string("(DOF counts differ)")) << ".\n\n";
  md << "![rhs scaling](rhs_scaling.svg)\n\n";
  md << "| n per flexure | DOF | nodal coordinates | calls | median rhs time [us] | EquationsOfMotion set-up [ms] | "
        "projected form [us] |\n";
  md << "|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows)
    md << "| " << r.n << " | " << r.dof << " | " << r.nx << " | " << r.calls << " | " << fmt("%.2f", r.median * 1e6)
       << " | " << fmt("%.2f", r.setup * 1e3) << " | "
       << (std::isfinite(r.projected) ? fmt("%.2f", r.projected * 1e6) : "-") << " |\n";
  md << "\n| log-log slope of rhs time | against n | against DOF |\n|---|---:|---:|\n";
  md << "| least squares, all sizes | " << fmt("%.2f", slopeAll) << " | " << fmt("%.2f", slopeAllDof) << " |\n";
  md << "| last three sizes (n = " << rows[k3].n << " ... " << rows.back().n << ") | " << fmt("%.2f", slopeLast)
     << " | " << fmt("%.2f", slopeLastDof) << " |\n\n";

  // ---- observations (generated from the measurements)
  md << "### Observations\n\n";
  auto find = [&](const std::string& model, const std::string& method, const std::string& integ,
                  double tol) -> const Point* {
    for (const Point& p : points)
      if (p.model == model && p.method == method && p.integrator == integ && p.relTol == tol && p.status == "ok")
        return &p;
    return nullptr;
  };
  // The cheapest ok point of a method with error <= eps.
  auto cheapest = [&](const std::string& model, const std::string& method, const std::string& integ,
                      double eps) -> const Point* {
    const Point* best = nullptr;
    for (const Point& p : points)
      if (p.model == model && p.method == method && p.integrator == integ && p.status == "ok" && p.error <= eps &&
          (!best || p.wall < best->wall))
        best = &p;
    return best;
  };
  for (const CaseSpec& cs : cases) {
    const Point* fd = find(cs.key, "full", "ode45", 1e-3);
    if (!fd) continue;
    std::vector<std::string> reduced;
    for (const Point& p : points)
      if (p.model == cs.key && p.method != "full" &&
          std::find(reduced.begin(), reduced.end(), p.method) == reduced.end())
        reduced.push_back(p.method);
    // Evaluation range of full ode45 (stability-bounded steps show as a flat count).
    long feMin = 0, feMax = 0;
    double tolLo = 0, tolHi = 0;
    for (const Point& p : points)
      if (p.model == cs.key && p.method == "full" && p.integrator == "ode45" && p.status == "ok") {
        if (!feMin || p.fevals < feMin) feMin = p.fevals;
        if (p.fevals > feMax) feMax = p.fevals;
        tolHi = std::max(tolHi, p.relTol);
        tolLo = tolLo ? std::min(tolLo, p.relTol) : p.relTol;
      }
    double sMin = INFINITY, sMax = 0, eMin = INFINITY, eMax = 0, bestFloor = INFINITY;
    std::string nMin, nMax, best;
    for (const std::string& rm : reduced) {
      double floorErr = INFINITY;
      for (const Point& p : points)
        if (p.model == cs.key && p.method == rm && p.status == "ok") floorErr = std::min(floorErr, p.error);
      if (floorErr < bestFloor) bestFloor = floorErr, best = rm;
      if (const Point* rp = find(cs.key, rm, "ode45", 1e-3)) {
        sMin = std::min(sMin, fd->wall / rp->wall), sMax = std::max(sMax, fd->wall / rp->wall);
        if (rp->error < eMin) eMin = rp->error, nMin = rm;
        if (rp->error > eMax) eMax = rp->error, nMax = rm;
      }
    }
    std::ostringstream o;
    o << "- **" << cs.title << ".** At ode45's default RelTol 1e-3 ";
    if (reduced.size() == 1)
      o << reduced[0] << " runs " << fmt("%.0f", sMin) << "x faster";
    else
      o << "the reduced models run " << fmt("%.0f", sMin) << "-" << fmt("%.0f", sMax) << "x faster";
    o << " than the full model (" << secText(fd->wall) << " s; "
      << (feMax < 3 * feMin ? "its ode45 step is bounded by stability, not accuracy: " : "") << withThousands(feMin)
      << "-" << withThousands(feMax) << " evaluations from RelTol " << tolText(tolHi) << " to " << tolText(tolLo)
      << ") but level" << (reduced.size() == 1 ? "s" : "") << " off at " << (reduced.size() == 1 ? "its" : "their")
      << " reduction error";
    if (reduced.size() == 1)
      o << " of " << sci(eMin, 1);
    else
      o << ", from " << sci(eMax, 1) << " (" << nMax << ") down to " << sci(eMin, 1) << " (" << nMin << ")";
    if (std::isfinite(bestFloor)) {
      const Point* rp = cheapest(cs.key, best, "ode45", 1.5 * bestFloor);
      const Point* fp = cheapest(cs.key, "full", "ode45", 1.5 * bestFloor);
      const Point* cp = nullptr;  // the cheapest CVODE variant there
      for (const CvodeVariant& v : kCvode)
        if (const Point* c = cheapest(cs.key, "full", v.name, 1.5 * bestFloor); c && (!cp || c->wall < cp->wall))
          cp = c;
      o << "; for any error above " << sci(bestFloor, 1) << " " << best << " (" << secText(rp->wall) << " s) is ";
      if (fp)
        o << fmt("%.0f", fp->wall / rp->wall) << "x faster than the full model with ode45";
      else
        o << "the only method within the sweep's budget";
      if (cp)
        o << " and "
          << (cp->wall >= rp->wall ? fmt("%.0f", cp->wall / rp->wall) + "x faster than"
                                   : fmt("%.1f", rp->wall / cp->wall) + "x slower than")
          << " the full model with the cheapest CVODE variant there (" << cp->integrator << ", " << secText(cp->wall)
          << " s)";
      o << ", and only below that error does the full model win.";
    }
    md << o.str() << "\n";
  }
  // Each CVODE variant against ode45 on the full models at RelTol 1e-3, and its time against the
  // reduced models' (ratio range lo ... hi of CVODE time / reduced time).
  auto reducedComparison = [](double lo, double hi) -> std::string {
    if (!std::isfinite(lo)) return "";
    const std::string tail = " the reduced models (ode45) at the same tolerance";
    if (lo > 1) return ", and it remains " + fmt("%.0f", lo) + "-" + fmt("%.0f", hi) + "x slower than" + tail;
    if (hi < 1) return ", and it is " + fmt("%.1f", 1 / hi) + "-" + fmt("%.1f", 1 / lo) + "x faster than" + tail;
    return ", and it takes " + fmt("%.2f", lo) + "-" + fmt("%.1f", hi) + " times the time of" + tail;
  };
  for (const CvodeVariant& v : kCvode) {
    std::string fe, sp, acc, failedAt, steps, perStep, jac;
    bool moreSteps = true, fewerSteps = true;
    double slowMin = INFINITY, slowMax = 0;  // CVODE time / reduced-model time at RelTol 1e-3
    for (const CaseSpec& cs : cases) {
      const Point* fd = find(cs.key, "full", "ode45", 1e-3);
      const Point* cd = find(cs.key, "full", v.name, 1e-3);
      if (!fd || !cd) continue;
      for (const Point& p : points)
        if (p.model == cs.key && p.method != "full" && p.relTol == 1e-3 && p.status == "ok") {
          slowMin = std::min(slowMin, cd->wall / p.wall);
          slowMax = std::max(slowMax, cd->wall / p.wall);
        }
      const std::string name = cs.title.substr(0, cs.title.find(" ("));
      fe += (fe.empty() ? "" : " / ") + fmt("%.1f", double(fd->fevals) / cd->fevals) + "x";
      sp += (sp.empty() ? "" : " / ") + (cd->wall <= fd->wall ? fmt("%.1f", fd->wall / cd->wall) + "x faster"
                                                              : fmt("%.1f", cd->wall / fd->wall) + "x slower");
      acc += (acc.empty() ? "" : ", ") + name + " " + sci(cd->error, 1) + " against " + sci(fd->error, 1);
      moreSteps = moreSteps && cd->nsteps >= 0.9 * fd->nsteps;
      fewerSteps = fewerSteps && cd->nsteps < 0.9 * fd->nsteps;
      steps += (steps.empty() ? "" : " / ") + withThousands(cd->nsteps) + " against " + withThousands(fd->nsteps);
      perStep += (perStep.empty() ? "" : " / ") + fmt("%.1f", double(cd->fevals) / cd->nsteps) + " against " +
                 fmt("%.1f", double(fd->fevals) / fd->nsteps);
      jac += (jac.empty() ? "" : " / ") + withThousands(cd->njac) + " Jacobians" +
             (cd->jacFevals > 0 ? " taking " + withThousands(cd->jacFevals) + " of the evaluations" : std::string());
    }
    for (const Point& p : points)
      if (p.integrator == v.name && p.status == "failed")
        failedAt += (failedAt.empty() ? "" : ", ") + p.model + " RelTol " + tolText(p.relTol);
    std::string names;
    for (const CaseSpec& cs : cases) names += (names.empty() ? "" : " / ") + cs.title.substr(0, cs.title.find(" ("));
    if (fe.empty()) continue;
    md << "- **" << v.name << "** (" << names << ", RelTol 1e-3) needs " << fe
       << " fewer evaluations than ode45 on the full "
       << "model (" << jac << ") and is " << sp
       << (moreSteps    ? ": it takes as many steps or more ("
           : fewerSteps ? ": it takes fewer steps ("
                        : ": it takes (")
       << steps << " steps) with fewer evaluations per step (" << perStep << "); its error at equal tolerance is "
       << acc << (failedAt.empty() ? "" : "; it stopped at " + failedAt + " (see the table)")
       << reducedComparison(slowMin, slowMax) << ".\n";
  }
  md << "- One rhs evaluation of the full model (sparse nodal saddle-point form, "
        "core/dynamics/SaddlePointAccelerations) grows "
     << "with a log-log slope of " << fmt("%.2f", slopeAll) << " in the number of elements per flexure ("
     << fmt("%.2f", slopeLast) << " over the last three sizes) and costs " << fmt("%.2f", rows.front().median * 1e6)
     << " us at " << rows.front().dof
     << " DOF; the projected form (dense F_q^T M F_q and its Cholesky, O(nx m^2 + m^3)) "
     << "costs " << (std::isfinite(rows.front().projected) ? fmt("%.2f", rows.front().projected * 1e6) : "-")
     << " us at " << rows.front().dof << " DOF and grows with slope ~2.4-3.\n";
  if (!skippedList.empty()) {
    md << "\n**Skipped points** (predicted or measured to exceed the time limit):\n\n";
    for (const auto& s : skippedList) md << "- " << s << "\n";
  }
  md << "\n" << operatorMd;
  md << "\nData: [workprecision.csv](workprecision.csv), [rhs_scaling.csv](rhs_scaling.csv).\n";
  md.close();
  std::printf("flexmb_bench: done in %s s; wrote %s/bench.md, workprecision.csv, rhs_scaling.csv and the SVGs\n",
              secText(totalTime).c_str(), opt.out.c_str());
  return 0;
}
