// Stiff spatial dynamics: the right-angle cantilever of Simo & Vu-Quoc (datfiles/spatial/elbow.dat,
// 2 x 10 BEAMs; elbow_fine.dat, 2 x 20). The out-of-plane displacement of the elbow and the tip
// against the stored converged reference (datfiles/spatial/elbow_reference.csv) per integrator and
// tolerance, each run simulate's recipe with the wall-time cap (BenchRuns.hpp); and the cost of
// generalized-alpha's iteration matrix against a right-hand side and Eq. 15's dense Jacobian.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/Simulation.hpp"
#include "analysis/StateJacobian.hpp"
#include "core/dynamics/EquationsOfMotion.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"
#include "io/pictures/SvgPlot.hpp"
#include "tools/bench/BenchRuns.hpp"
#include "tools/bench/BenchSections.hpp"
#include "tools/bench/BenchSupport.hpp"

namespace flexmb::bench {

namespace {

std::string spatial(const std::string& file) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/" + file; }

// The reference's rows: t, elbow z, tip z.
std::vector<std::array<double, 3>> elbowReference() {
  std::vector<std::array<double, 3>> rows;
  std::ifstream in(spatial("elbow_reference.csv"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 't') continue;
    std::array<double, 3> r{};
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &r[0], &r[1], &r[2]) == 3) rows.push_back(r);
  }
  return rows;
}

struct ElbowRun {
  const char* file;
  int elbowNode, tipNode;
  analysis::Integrator integrator;
  std::vector<double> tols;
  bool stabilityBound = false;  // ode45 here: capped at Settings::stabilityCap (the row still shows it stuck)
};

std::vector<ElbowPoint> elbowRuns(const Options& opt, const Settings& set) {
  const std::vector<std::array<double, 3>> ref = elbowReference();
  double lo = 1e300, hi = -1e300;
  for (const auto& r : ref) lo = std::min(lo, r[2]), hi = std::max(hi, r[2]);
  const double range = hi - lo;
  // Quick mode leaves out galpha at 1e-5 and BDF at 1e-3 (14 s and 13 s; the curves' shape shows
  // without them); the full mode adds BDF at 1e-4.
  std::vector<ElbowRun> plan = {{"elbow.dat", 21, 41, analysis::Integrator::GeneralizedAlpha, {1e-2, 1e-3, 1e-4}},
                                {"elbow.dat", 21, 41, analysis::Integrator::Bdf, {1e-2}},
                                {"elbow.dat", 21, 41, analysis::Integrator::Ode45, {1e-3}, true},
                                {"elbow.dat", 21, 41, analysis::Integrator::Auto, {1e-3}},
                                {"elbow_fine.dat", 41, 81, analysis::Integrator::GeneralizedAlpha, {1e-3}},
                                {"elbow_fine.dat", 41, 81, analysis::Integrator::Auto, {1e-3}}};
  if (!opt.quick) {
    plan[0].tols.push_back(1e-5);
    plan[1].tols.insert(plan[1].tols.end(), {1e-3, 1e-4});
  }
  std::vector<ElbowPoint> points;
  for (const ElbowRun& er : plan) {
    const core::Model model = io::readDatFile(spatial(er.file));
    const int ze = model.nodes[model.nodeByLabel.at(er.elbowNode)].firstCoord + 2;
    const int zt = model.nodes[model.nodeByLabel.at(er.tipNode)].firstCoord + 2;
    for (double tol : er.tols) {
      ElbowPoint pt;
      pt.file = er.file;
      pt.integrator = analysis::integratorName(er.integrator);
      pt.relTol = tol;
      // The cap: ode45 on the elbow takes minutes at any tolerance (bound by stability: in quick mode
      // the short Settings::stabilityCap), BDF at tight ones.
      const CappedRun r = runCapped(model, recipeOptions(model, er.integrator, tol, 1e-3 * tol),
                                    er.stabilityBound ? set.stabilityCap : set.hardCap);
      const core::Trajectory& run = r.trajectory;
      pt.wall = r.wall;
      pt.fevals = run.nfevals;
      pt.njac = run.njacevals;
      pt.nsteps = run.nsteps;
      if (r.completed() && run.time.size() == ref.size() && range > 0) {
        double worst = 0.0;
        for (size_t i = 0; i < ref.size(); ++i)
          worst =
              std::max({worst, std::abs(run.states[i].x[ze] - ref[i][1]), std::abs(run.states[i].x[zt] - ref[i][2])});
        pt.error = worst / range;
      } else {
        pt.note = r.completed() ? "the output times differ from the reference's" : r.reason;
      }
      std::printf("[elbow] %s %s RelTol %s: %s s, %ld steps, %ld fevals, %ld Jacobians, error %s%s\n", er.file,
                  pt.integrator.c_str(), tolText(tol).c_str(), secText(pt.wall).c_str(), pt.nsteps, pt.fevals, pt.njac,
                  std::isfinite(pt.error) ? sci(pt.error).c_str() : "-",
                  pt.note.empty() ? "" : (" (" + pt.note + ")").c_str());
      std::fflush(stdout);
      points.push_back(pt);
    }
  }
  return points;
}

// The iteration matrix's cost in right-hand sides (a state of the run at t = 1.5 s: bent and moving).
std::string iterationCost() {
  std::string cost;
  for (const char* file : {"elbow.dat", "elbow_fine.dat"}) {
    const core::Model model = io::readDatFile(spatial(file));
    core::Workspace ws(model);
    core::EquationsOfMotion eom(ws);
    core::Linearization lin(ws);
    analysis::StateJacobian dense(ws, std::nullopt);
    const int m = eom.size();
    Eigen::VectorXd y = eom.initialState(), dy(2 * m);
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
    const Eigen::VectorXd q = y.head(m);
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
    cost += std::string(cost.empty() ? "" : "; ") + file + ": one right-hand side " + fmt("%.1f", rhs * 1e6) +
            " us, the sparse iteration matrix " + fmt("%.1f", iteration / rhs) +
            " right-hand sides, the dense Jacobian of Eq. 15 " + fmt("%.0f", eq15 / rhs);
  }
  return cost;
}

void plotElbow(const std::vector<ElbowPoint>& points, const std::string& dir) {
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
    for (const ElbowPoint& p : points)
      if (p.file == "elbow.dat" && p.integrator == integ && std::isfinite(p.error))
        se.x.push_back(p.error), se.y.push_back(p.wall);
    if (!se.x.empty()) plot.series.push_back(se);
  }
  io::writeSvg(dir + "/wp_elbow.svg", plot);
}

}  // namespace

ElbowResults elbowFigures(const Options& opt, const Settings& set) {
  ElbowResults r;
  if (!opt.only.empty() && opt.only.find("elbow") == std::string::npos) return r;
  r.points = elbowRuns(opt, set);
  r.cost = iterationCost();
  plotElbow(r.points, opt.out);
  return r;
}

}  // namespace flexmb::bench
