// flexmb_bench's report: the machine, workprecision.csv, rhs_scaling.csv and bench.md (a Markdown
// fragment for the validation report; its links are relative to its own directory).
#include <unistd.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "solvers/Bdf.hpp"
#include "tools/bench/BenchSections.hpp"
#include "tools/bench/BenchSupport.hpp"

#ifndef FLEXMB_BENCH_BUILD_TYPE
#define FLEXMB_BENCH_BUILD_TYPE "unknown"
#endif

namespace flexmb::bench {

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  return fmt("%.2f", a) + " " + fmt("%.2f", b) + " " + fmt("%.2f", c);
}

namespace {

// ---- the machine
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
std::string compilerText() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("g++ ") + __VERSION__;
#else
  return "unknown";
#endif
}
std::string buildText() {
#ifdef NDEBUG
  return FLEXMB_BENCH_BUILD_TYPE " (NDEBUG)";
#else
  return FLEXMB_BENCH_BUILD_TYPE;
#endif
}

// ---- bench.md
std::string entry(const std::map<std::string, std::string>& m, const std::string& key) {
  const auto it = m.find(key);
  return it == m.end() ? std::string() : it->second;
}

void writeHeader(std::ostream& md, const Report& r) {
  std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  const bool quick = r.opt.quick;
  md << "## Benchmarks" << (quick ? " (quick mode)" : "") << "\n\n";
  md << "Produced by `flexmb_bench" << (quick ? " --quick" : "") << "` on " << date << " in " << secText(r.totalSeconds)
     << " s (tools/bench/README.md). Links are relative to this file's directory.\n\n";
  md << "**Machine.** " << sysconf(_SC_NPROCESSORS_ONLN) << " cores (`nproc`), CPU " << machineLine("cpu")
     << ", memory " << memoryText() << "; compiler " << compilerText() << ", build type " << buildText() << "; Eigen "
     << EIGEN_WORLD_VERSION << '.' << EIGEN_MAJOR_VERSION << '.' << EIGEN_MINOR_VERSION << ", "
     << solvers::Bdf::library() << ". Load average before/after: " << r.loadBefore << " / " << loadAverage()
     << " (the machine may be shared; single-threaded runs).\n\n";
}

void writeSetup(std::ostream& md, const Report& r) {
  const Settings& set = r.set;
  md << "**Set-up.** Tolerances RelTol " << tolText(set.tols.front()) << " ... " << tolText(set.tols.back())
     << " per decade, AbsTol = RelTol x 1e-3 (scalar), for every method. Every run is `simulate`'s own "
        "(analysis::simulate with the options the command line gives it) but CVODE's difference-quotient variant. "
        "Wall time = in-process time of model set-up plus integration (the bench calls analysis::simulate; the "
        "command `flexmb simulate` also reads the file, runs its accuracy check and writes its files: "
        "tools/bench/README.md compares the two on the 20-element guidance), without the output quantities "
        "(a second, untimed run keeps "
        "the states at the model's output times; the difference-quotient variant stores them as it goes and "
        "evaluates them afterwards); median of 3 runs when a run takes < "
     << set.repeatBelow
     << " s, else 1 run. A point predicted (from the growth of the evaluation count, at least "
        "10^(1/5) per decade) to take more than "
     << fmt("%.0f", set.skipAbove) << " s is skipped with the tighter ones; a run is stopped at "
     << fmt("%.0f", set.hardCap)
     << " s (every run on the 20-element guidance, where ode45 is bound by stability and BDF2 stalls at tight "
        "tolerances, at "
     << fmt("%.0f", set.stabilityCap)
     << " s). Error = max over the output times of |response - reference| divided by the max reference deflection of x "
        "(node 6, relative to its initial value) for the straight guidance (node 21, the same point, on the guidance "
        "with 20 PLBEAMs per leaf, datfiles/tests/straight_guidance_20.dat), and the tip position distance (node 9) "
        "divided by the reach for the manipulator, both from `simulate`'s output quantities (solved to its kinematic "
        "tolerance, min(1e-10, 1e-5 RelTol) of the model size). Reduced models are measured against the full model's "
        "reference, so their curves level off at their reduction error.\n\n";
  md << "- ode45: flexmb's ode45-equivalent (Dormand-Prince 5(4), MATLAB's step control), same counting rule as "
        "MATLAB.\n";
  md << "- Status **ok**: the run completed and `simulate`'s a-posteriori accuracy check (analysis/AccuracyCheck.hpp: "
        "three windows of the run, a tenth of the span, integrated again at a 10x tighter tolerance; their largest "
        "difference per second times the span, in positions relative to the model size) finds it converged, i.e. "
        "the estimate is at most 10 RelTol. **not converged**: completed, but the estimate is larger; such runs are "
        "plotted with their measured error. The column *accuracy check* is that estimate (the *error* column is the "
        "error measured against the reference, on its own scale). The column *reduction estimate* is what every "
        "reduced run of `simulate` prints beside it: its reduction error estimate (analysis/ReductionError.hpp; "
        "every position, of the motion: a measure of its own, comparable with the validation report's true errors, "
        "not with the *error* column's single response).\n";
  md << "- CVODE: " << solvers::Bdf::library()
     << " through solvers::Bdf: BDF, Newton with the dense direct linear solver, on the same right-hand side, in "
        "three variants: **CVODE-BDF DQ J** (orders 1-5, CVODE's difference-quotient Jacobian: the bench's own run, "
        "as `simulate` has no such setting), **CVODE-BDF analytic J** (`simulate --integrator bdf --bdf-order 5`: "
        "the Jacobian [[0, I], [-M^-1 (K+N+G), -M^-1 (C+D)]] from the linearisation of Eq. 15, "
        "analysis::StateJacobian) and **CVODE-BDF2 analytic J** (`simulate --integrator bdf`, orders 1-2, A-stable). "
        "Counts: fevals includes the difference-quotient evaluations; (J n: m) gives the Jacobian evaluations n and "
        "the right-hand sides m spent on them; failed steps are error-test plus corrector-convergence failures. Every "
        "evaluation starts the kinematic Newton solve from the configuration of the last accepted step "
        "(tools/bench/README.md: without this anchor CVODE's trial states spoil the warm start). Note CVODE's error "
        "test uses a weighted RMS norm, ode45 a max norm.\n";
  analysis::SimulationOptions galpha;
  galpha.integrator = analysis::Integrator::GeneralizedAlpha;
  md << "- generalized-alpha: `simulate --integrator galpha`, " << analysis::integratorDescription(galpha) << ".\n";
  for (const CaseSpec& cs : r.wp.cases) {
    md << "- Reference " << cs.key << ": " << entry(r.wp.refNotes, cs.key) << ".\n";
    md << "- Bases " << cs.key << ": " << entry(r.wp.basisNotes, cs.key) << ".\n";
  }
  // How far the references resolve: the error of the tightest full ode45 point against them.
  std::string res, refined;
  for (const CaseSpec& cs : r.wp.cases) {
    if (!cs.paper) {  // the refined guidance: its reference is generalized-alpha, two decades below the sweep
      const Point* tight = nullptr;
      for (const Point& p : r.wp.points)
        if (p.model == cs.key && p.method == "full" && p.integrator == "generalized-alpha" && p.completed() &&
            (!tight || p.relTol < tight->relTol))
          tight = &p;
      refined +=
          " On the guidance with 20 PLBEAMs per leaf ode45 at a tight tolerance costs minutes (RelTol 1e-9: "
          "237 s, 1.1 million steps, tools/bench/README.md) and at any tolerance its step is bound by "
          "stability, so the reference there is generalized-alpha (`simulate --integrator galpha`, whose RelTol "
          "is its global error: local tolerance 5 RelTol^1.5, issue 48) at RelTol " +
          tolText(r.set.refTol.at(cs.key)) + ", two decades below the tightest swept point" +
          (tight ? " (generalized-alpha at RelTol " + tolText(tight->relTol) + " differs from it by " +
                       sci(tight->error, 1) + ")"
                 : std::string()) +
          ".";
      continue;
    }
    const Point* tight = nullptr;
    for (const Point& p : r.wp.points)
      if (p.model == cs.key && p.method == "full" && p.integrator == "ode45" && p.status == "ok" &&
          (!tight || p.relTol < tight->relTol))
        tight = &p;
    if (tight)
      res += (res.empty() ? "" : ", ") + cs.key + " " + sci(tight->error, 1) + " at RelTol " + tolText(tight->relTol);
  }
  md << "- Reference choice: "
     << (r.opt.quick
             ? "quick mode uses RelTol 1e-7 for both of the paper's references (two decades below the tightest swept "
               "tolerance). "
             : "RelTol 1e-10 for both of the paper's models (costs above; the manipulator's is the largest item of the "
               "budget; "
               "the guidance at 1e-11 was measured separately at 1.1M evaluations, ~48 s, and not used: it would "
               "change no conclusion). ")
     << (res.empty() ? ""
                     : "The full model's own errors level off near the references' resolution (" + res +
                           "); smaller differences are not resolved.")
     << refined << "\n\n";
}

void writeCaseTables(std::ostream& md, const WorkPrecisionResults& wp) {
  for (const CaseSpec& cs : wp.cases) {
    const std::string fevalsSvg = entry(wp.svgFiles, cs.key + "_fevals");
    md << "### " << cs.title << "\n\n";
    md << "![work-precision " << cs.key << "](" << entry(wp.svgFiles, cs.key) << ")\n\n";
    md << "Evaluation counts instead of time: [" << fevalsSvg << "](" << fevalsSvg << ")\n\n";
    md << "| method | integrator | RelTol | status | fevals | steps (failed) | wall time [s] | runs | us/feval | error "
          "| accuracy check | reduction estimate |\n";
    md << "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Point& p : wp.points) {
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
}

void writeElbow(std::ostream& md, const ElbowResults& elbow, const Settings& set, bool quick) {
  if (elbow.points.empty()) return;
  md << "### Stiff spatial dynamics: the elbow of Simo & Vu-Quoc\n\n"
     << "datfiles/spatial/elbow.dat (2 x 10 BEAMs, 120 DOF) and elbow_fine.dat (2 x 20, 240 DOF), 30 s, output "
        "every 0.1 s, AbsTol = 1e-3 RelTol, each run `simulate`'s own (its states kept). Error: the largest "
        "deviation of the elbow's and the tip's out-of-plane displacement from "
        "datfiles/spatial/elbow_reference.csv, relative to the tip's range. Runs are capped at "
     << fmt("%.0f", set.hardCap) << " s, ode45 (bound by stability here) at " << fmt("%.0f", set.stabilityCap) << " s."
     << (quick ? " Quick mode leaves out galpha at RelTol 1e-5 and BDF at 1e-3 and 1e-4 (the full mode runs them)."
               : "")
     << "\n\n"
     << "| model | integrator | RelTol | wall [s] | steps | fevals | Jacobians | error "
        "|\n|---|---|---|---|---|---|---|---|\n";
  for (const ElbowPoint& p : elbow.points)
    md << "| " << p.file << " | " << p.integrator << " | " << tolText(p.relTol) << " | " << secText(p.wall) << " | "
       << p.nsteps << " | " << p.fevals << " | " << p.njac << " | " << (std::isfinite(p.error) ? sci(p.error) : p.note)
       << " |\n";
  md << "\nCost of one iteration matrix (at a bent, moving state): " << elbow.cost << ".\n\n";
  md << "![work-precision elbow](wp_elbow.svg)\n\n";
}

void writeScaling(std::ostream& md, const RhsScalingResults& rhs) {
  md << "### Right-hand-side cost against model size\n\n";
  md << "Straight guidance with n PLBEAM elements per flexure (geometry, material, load and DYNE/RLSE pattern of "
        "datfiles/straight_guidance.dat), one rhs evaluation at t = 0.05 s in the initial configuration with "
        "etad = 1e-3 in every component; median over the calls shown. The generated n = 5 model agrees with "
        "datfiles/straight_guidance.dat to a relative rhs difference of "
     << (std::isfinite(rhs.checkDiff) ? sci(rhs.checkDiff) : std::string("(DOF counts differ)")) << ".\n\n";
  md << "![rhs scaling](rhs_scaling.svg)\n\n";
  md << "| n per flexure | DOF | nodal coordinates | calls | median rhs time [us] | EquationsOfMotion set-up [ms] | "
        "projected form [us] |\n";
  md << "|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rhs.rows)
    md << "| " << r.n << " | " << r.dof << " | " << r.nx << " | " << r.calls << " | " << fmt("%.2f", r.median * 1e6)
       << " | " << fmt("%.2f", r.setup * 1e3) << " | "
       << (std::isfinite(r.projected) ? fmt("%.2f", r.projected * 1e6) : "-") << " |\n";
  md << "\n| log-log slope of rhs time | against n | against DOF |\n|---|---:|---:|\n";
  md << "| least squares, all sizes | " << fmt("%.2f", rhs.slopeAll) << " | " << fmt("%.2f", rhs.slopeAllDof) << " |\n";
  md << "| last three sizes (n = " << rhs.rows[rhs.lastFrom].n << " ... " << rhs.rows.back().n << ") | "
     << fmt("%.2f", rhs.slopeLast) << " | " << fmt("%.2f", rhs.slopeLastDof) << " |\n\n";
}

}  // namespace

void writeCsv(const std::string& dir, const std::vector<Point>& points, const std::vector<ScalingRow>& rows) {
  std::ofstream f(dir + "/workprecision.csv");
  f << "model,method,integrator,reltol,abstol,status,fevals,jacobian_fevals,jacobians,steps,failed_steps,wall_s,runs,"
       "error,accuracy_estimate,note\n";
  for (const Point& p : points) {
    const bool skipped = p.status == "skipped", ode45 = p.integrator == "ode45";
    f << p.model << ',' << p.method << ',' << p.integrator << ',' << sci(p.relTol, 1) << ',' << sci(p.absTol, 1) << ','
      << p.status << ',' << (skipped ? "" : std::to_string(p.fevals)) << ','
      << (skipped || ode45 ? "" : std::to_string(p.jacFevals)) << ','
      << (skipped || ode45 ? "" : std::to_string(p.njac)) << ',' << (skipped ? "" : std::to_string(p.nsteps)) << ','
      << (skipped ? "" : std::to_string(p.nfailed)) << ',' << (std::isfinite(p.wall) ? fmt("%.6g", p.wall) : "") << ','
      << (p.runs ? std::to_string(p.runs) : "") << ',' << (std::isfinite(p.error) ? sci(p.error, 4) : "") << ','
      << (std::isfinite(p.estimate) ? sci(p.estimate, 2) : "") << ',' << csvQuote(p.note) << '\n';
  }
  std::ofstream g(dir + "/rhs_scaling.csv");
  g << "elements_per_flexure,dof,nodal_coordinates,calls,median_rhs_s,eom_setup_s,median_rhs_projected_s\n";
  for (const auto& r : rows)
    g << r.n << ',' << r.dof << ',' << r.nx << ',' << r.calls << ',' << fmt("%.6e", r.median) << ','
      << fmt("%.6e", r.setup) << ',' << (std::isfinite(r.projected) ? fmt("%.6e", r.projected) : std::string()) << '\n';
}

void writeMarkdown(const Report& r) {
  std::ofstream md(r.opt.out + "/bench.md");
  writeHeader(md, r);
  writeSetup(md, r);
  writeCaseTables(md, r.wp);
  writeElbow(md, r.elbow, r.set, r.opt.quick);
  writeScaling(md, r.rhs);
  md << "### Observations\n\n" << observations(r.wp, r.rhs);
  if (!r.wp.skipped.empty()) {
    md << "\n**Skipped points** (predicted or measured to exceed the time limit):\n\n";
    for (const auto& s : r.wp.skipped) md << "- " << s << "\n";
  }
  md << "\n" << r.operatorMd;
  md << "\nData: [workprecision.csv](workprecision.csv), [rhs_scaling.csv](rhs_scaling.csv).\n";
}

}  // namespace flexmb::bench
