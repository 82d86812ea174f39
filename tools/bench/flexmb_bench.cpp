// flexmb_bench: benchmarks of the paper's two models (Boer et al. 2013, Section 4) and beyond
// (tools/bench/README.md). The sections, one file each (BenchSections.hpp): the eigenanalysis, the
// reduced operators, the work-precision sweeps of the straight guidance and the manipulator (ode45
// on the full and reduced models, CVODE's BDF and generalized-alpha on the full ones), the elbow
// (stiff spatial dynamics), one right-hand side against the mesh; then CSV, SVG and bench.md. Every
// run that stands for `flexmb simulate` is simulate's own recipe (BenchRuns.hpp).
// Usage: flexmb_bench [--quick] [--out DIR] [--only TEXT]
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "tools/bench/BenchSections.hpp"
#include "tools/bench/BenchSupport.hpp"

#ifndef FLEXMB_SOURCE_DIR
#define FLEXMB_SOURCE_DIR "."
#endif

namespace flexmb::bench {

Settings settingsFor(const Options& opt) {
  Settings s;
  s.tols = opt.quick ? std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5}
                     : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  s.absFactor = 1e-3;
  s.skipAbove = opt.quick ? 20.0 : 60.0;
  s.hardCap = opt.quick ? 30.0 : 90.0;
  // Runs known to stall (ode45, bound by stability, on the elbow and on the refined guidance; BDF2 at
  // RelTol 1e-5 on the refined guidance, which did not pass t = 0.001 in 30 s): in quick mode a short
  // cap still shows that they are stuck (the row says where they stopped).
  s.stabilityCap = opt.quick ? 5.0 : s.hardCap;
  // Median of 3 below this (the timer's resolution and a run's warm-up matter for short runs); quick:
  // runs of 0.5-2 s (the manipulator's full ode45 and CVODE orders 1-5) are timed once, which saved
  // ~30 s of the quick run.
  s.repeatBelow = opt.quick ? 0.5 : 2.0;
  // Reference tolerances (full model, ode45): 1e-10 for both (measured: guidance 331k evaluations,
  // ~13 s; manipulator 6.1M, ~185 s; the guidance at 1e-11 would need 1.1M, ~48 s). Quick: 1e-7,
  // two decades below the tightest swept tolerance.
  const double ref = opt.quick ? 1e-7 : 1e-10;
  s.refTol = {{"straight_guidance", ref}, {"manipulator", ref}};
  // The guidance with 20 PLBEAMs per leaf: ode45 at a tight tolerance costs minutes there (1e-9: 237 s),
  // so its reference is generalized-alpha, whose RelTol is its global error (issue 48), two decades
  // below the tightest swept point (quick 1e-7, full 1e-8).
  s.refTol["straight_guidance_20"] = opt.quick ? 1e-7 : 1e-8;
  s.refinedTols =
      opt.quick ? std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5} : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6};
  // The sparse saddle-point form is O(n): every size; the projected form (dense, O(n^3)) up to
  // maxProjected elements per flexure.
  s.sizes = {5, 10, 20, 40, 80, 160, 320, 640};
  s.maxProjected = opt.quick ? 80 : 160;
  s.rhsBudget = opt.quick ? 0.05 : 0.2;
  return s;
}

namespace {

void usage() {
  std::cout << "usage: flexmb_bench [--quick] [--out DIR] [--only TEXT]\n"
               "  --quick      RelTol 1e-2..1e-5, cheaper references, element counts 5..40\n"
               "  --out DIR    output directory (default " FLEXMB_SOURCE_DIR
               "/validation/report/bench)\n"
               "  --only TEXT  development: only the sweeps whose \"model method integrator\" contains TEXT\n"
               "               (rhs: the scaling only; elbow; operators, eigen: that section only, printed)\n";
}

// The arguments into opt: -1 to go on, else the exit code.
int parseArguments(int argc, char** argv, Options& opt) {
  opt.out = std::string(FLEXMB_SOURCE_DIR) + "/validation/report/bench";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      opt.quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      opt.out = argv[++i];
    } else if (a == "--only" && i + 1 < argc) {
      opt.only = argv[++i];
    } else {
      usage();
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  try {
    std::filesystem::create_directories(opt.out);
  } catch (const std::exception& e) {
    std::cerr << "flexmb_bench: cannot create " << opt.out << ": " << e.what() << "\n";
    return 1;
  }
  return -1;
}

}  // namespace
}  // namespace flexmb::bench

int main(int argc, char** argv) {
  using namespace flexmb::bench;
  Report r;
  if (const int code = parseArguments(argc, argv, r.opt); code >= 0) return code;
  const Options& opt = r.opt;
  if (opt.only.empty() || opt.only == "eigen") eigenFigures();
  if (opt.only == "eigen") return 0;
  if (opt.only.empty() || opt.only == "operators") r.operatorMd = operatorFigures(opt.quick);
  if (opt.only == "operators") {
    std::printf("%s", r.operatorMd.c_str());
    return 0;
  }
  const auto start = Clock::now();
  r.loadBefore = loadAverage();
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  r.set = settingsFor(opt);
  if (!workPrecision(opt, r.set, r.wp)) return 1;
  r.elbow = elbowFigures(opt, r.set);
  r.rhs = rhsScaling(opt, r.set);
  writeCsv(opt.out, r.wp.points, r.rhs.rows);
  r.totalSeconds = since(start);
  writeMarkdown(r);
  std::printf("flexmb_bench: done in %s s; wrote %s/bench.md, workprecision.csv, rhs_scaling.csv and the SVGs\n",
              secText(r.totalSeconds).c_str(), opt.out.c_str());
  return 0;
}
