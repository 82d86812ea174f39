// Eigenanalysis figures (issue 13 item 2, issue 11 item 6): printed, never pass/fail.
//  - the spatial cross-spring pivot's static run (load steps with frequencies in each);
//  - the 10 lowest modes of a 1,000-element planar chain (sparse constrained pencil);
//  - 10 configurations of a ~1,000-DOF chain, 10 modes each;
//  - sparse against dense eigenvalues.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/Statics.hpp"
#include "analysis/Transfer.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"
#include "tools/bench/BenchSupport.hpp"

namespace flexmb::bench {

namespace {
// Planar chain of n PLBEAMs (1 m, clamped at node 1), all deformations dynamic: 3n DOF.
std::string chain(int n) {
  std::ostringstream s;
  s.precision(17);
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 100000 + k << " " << k + 1 << " " << 100001 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << 1.0 * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 100001\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 1 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " 0.5\nESTIFF " << k << " 1e5 2.0\n";
  s << "END\nEND\n";
  return s.str();
}

double relDiff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < std::min(a.size(), b.size()); ++i)
    m = std::max(m, std::abs(a[i] - b[i]) / std::max(std::abs(b[i]), 1e-300));
  return m;
}

// max_i |lambda_i - rho(v_i)| / |lambda_i|, rho the Rayleigh quotient in the dense pencil (A, M).
double rayleighGap(const Eigen::MatrixXd& A, const Eigen::MatrixXd& M, const analysis::Frequencies& f) {
  double g = 0.0;
  for (Eigen::Index i = 0; i < f.lambda.size(); ++i) {
    const Eigen::VectorXd v = f.modes.col(i);
    const double rho = v.dot(A * v) / v.dot(M * v);
    g = std::max(g, std::abs(f.lambda[i] - rho) / std::abs(f.lambda[i]));
  }
  return g;
}

double median3(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

void eigenFigures() {
  std::printf("\n== eigenanalysis (sparse constrained pencil against the dense independent-coordinate one)\n");
  // 1. The pivot's static run (10 load steps, 6 frequencies in each; issue 11 item 6), each eigen
  //    path: wall and CPU time, Newton iterations per load step (all attempts counted).
  if (!std::getenv("FLEXMB_BENCH_SKIP_PIVOT")) {
    const core::Model m = io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot.dat");
    constexpr int kSteps = 10;
    for (const char* path : {"dense", "sparse"}) {
      analysis::StaticOptions so;
      so.nev = 6;
      so.loadSteps = kSteps;
      so.eigenPath = path[0] == 'd' ? analysis::EigenPath::Dense : analysis::EigenPath::Sparse;
      std::vector<double> w, cpu;
      analysis::StaticRun run;
      for (int rep = 0; rep < 3; ++rep) {
        const auto t0 = Clock::now();
        const std::clock_t c0 = std::clock();
        run = analysis::staticAnalysis(m, so);
        w.push_back(since(t0));
        cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
      }
      std::string iterations;
      int total = 0;
      for (const auto& st : run.steps) {
        (iterations += ' ') += std::to_string(st.iterations);
        total += st.iterations;
      }
      std::printf(
          "  cross-spring pivot 2 x 20 BEAM (%d DOF), static, %zu load steps with 6 frequencies each, "
          "%s eigen path: %.3f s wall, %.3f s CPU (medians of 3); Newton iterations per step%s (%d in all); "
          "f1 %.6f Hz at the last step%s\n",
          m.numDofs(), run.steps.size(), path, median3(w), median3(cpu), iterations.c_str(), total,
          run.steps.empty() ? 0.0 : run.steps.back().frequencies.omega[0] / (2 * M_PI),
          run.completed ? "" : " [did not complete]");
    }
  }
  // 2. The 10 lowest modes of a 1,000-element chain (sparse), and the dense path on 100 elements.
  for (int n : {100, 1000}) {
    const core::Model m = io::readDatString(chain(n), "chain.dat");
    core::Linearization lin(m);
    Eigen::VectorXd eta = Eigen::VectorXd::Zero(lin.size()), f = Eigen::VectorXd::Zero(m.nx);
    std::vector<double> w;
    analysis::Frequencies fs;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = Clock::now();
      lin.nodalAtRest(0.0, eta, f, true);
      fs = analysis::sparseFrequencies(lin, 10);
      w.push_back(since(t0));
    }
    std::printf(
        "  planar chain of %d PLBEAMs (%d DOF), 10 lowest modes, sparse: %.4f s (linearisation + "
        "ARPACK; median of 3); f1 = %.6g Hz\n",
        n, lin.size(), median3(w), fs.omega[0] / (2 * M_PI));
    if (n <= 100) {
      const auto t0 = Clock::now();
      core::LinearizedSystem sys;
      lin.atRest(0.0, eta, f, sys, true);
      const analysis::Frequencies fd = analysis::naturalFrequencies(lin, sys, 10, analysis::EigenPath::Dense);
      std::printf(
          "  planar chain of %d PLBEAMs (%d DOF), 10 lowest modes, dense: %.4f s; sparse vs dense "
          "max rel |dlambda| %.2e\n",
          n, lin.size(), since(t0), relDiff(fs.lambda, fd.lambda));
    }
  }
  // 3. Ten configurations of a ~1,000-DOF chain (its bending deformations scaled up: the chain
  //    curls), kinematics + linearisation + 10 modes in each; no equilibrium solve.
  {
    const core::Model m = io::readDatString(chain(333), "chain.dat");
    core::Linearization lin(m);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(m.nx), eta = Eigen::VectorXd::Zero(lin.size());
    auto config = [&](int c) {
      for (int k = 0; k < lin.size(); ++k) eta[k] = (k % 3 == 0) ? 0.0 : 3e-4 * c / 333.0 * ((k % 3 == 1) ? 1.0 : 0.0);
    };
    {
      // Straight: against Euler-Bernoulli (beta_i L)^4 EI / (rhoA L^4), discretisation error ~h^4.
      const double bl[3] = {1.875104068711961, 4.694091132974175, 7.854757438237613};
      core::LinearizedSystem sys0;
      lin.atRest(0.0, eta, f, sys0, true);
      const analysis::Frequencies d0 = analysis::naturalFrequencies(lin, sys0, 10, analysis::EigenPath::Dense);
      const analysis::Frequencies s0 = analysis::naturalFrequencies(lin, sys0, 10, analysis::EigenPath::Sparse);
      double es = 0.0, ed = 0.0;
      for (int i = 0; i < 3; ++i) {
        const double exact = std::pow(bl[i], 4) * 2.0 / 0.5;
        es = std::max(es, std::abs(s0.lambda[i] - exact) / exact);
        ed = std::max(ed, std::abs(d0.lambda[i] - exact) / exact);
      }
      std::printf(
          "  straight chain of 333 PLBEAMs: lowest 3 eigenvalues against Euler-Bernoulli, max rel error: "
          "sparse (%s) %.2e, dense %.2e; sparse vs dense %.2e\n",
          s0.method.c_str(), es, ed, relDiff(s0.lambda, d0.lambda));
    }
    auto t0 = Clock::now();
    Eigen::VectorXd last;
    for (int c = 0; c < 10; ++c) {
      config(c);
      lin.nodalAtRest(0.0, eta, f, true);
      last = analysis::sparseFrequencies(lin, 10).lambda;
    }
    const double ws = since(t0);
    t0 = Clock::now();
    core::LinearizedSystem sys;
    config(9);
    lin.atRest(0.0, eta, f, sys, true);
    const analysis::Frequencies fd = analysis::naturalFrequencies(lin, sys, 10, analysis::EigenPath::Dense);
    const double wd = since(t0);
    lin.nodalAtRest(0.0, eta, f, true);
    const analysis::Frequencies fsl = analysis::sparseFrequencies(lin, 10);
    const Eigen::MatrixXd A = sys.K + sys.G;
    std::printf(
        "  10 configurations of a chain of 333 PLBEAMs (%d DOF), 10 modes each, sparse: %.3f s in all; "
        "dense path, one configuration: %.3f s; last configuration sparse vs dense max rel |dlambda| %.2e; "
        "|lambda - Rayleigh quotient of its own vector| / lambda in the dense pencil: sparse %.2e, dense %.2e\n",
        lin.size(), ws, wd, relDiff(last, fd.lambda), rayleighGap(A, sys.M, fsl), rayleighGap(A, sys.M, fd));
  }
  // 4. Agreement on the pivot's last equilibrium is in (1) implicitly; the coarse pivot and the planar
  //    models are compared in tools/tests/test_sparse_eigen.cpp.
  // 5. Mode 9 (issue 21): the state-space model of a 999-DOF chain between a tip force and the tip
  //    displacement, static solution (load steps 0 and 1) included; median of 3.
  {
    const int n = 333;
    std::string text = chain(n);
    text.resize(text.size() - std::string("END\nEND\n").size());
    const std::string tip = std::to_string(n + 1);
    text += "ITERSTEP 10 1\nEND\nHALT\nINPUTF 1 " + tip + " 2\nOUTX 1 " + tip + " 2\nEND\nEND\n";
    const core::Model m = io::readDatString(text, "chain_transfer.dat");
    std::vector<double> walls;
    analysis::TransferRun run;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = Clock::now();
      run = analysis::transferAnalysis(m);
      walls.push_back(since(t0));
    }
    std::sort(walls.begin(), walls.end());
    // Static gain against the cantilever's tip compliance L^3 / (3 EI) (shear-free, small load).
    double gain = NAN;
    if (run.completed) {
      const Eigen::Index nq = run.model.A.rows() / 2;
      const Eigen::MatrixXd x1 = run.model.A.bottomLeftCorner(nq, nq).partialPivLu().solve(run.model.B.bottomRows(nq));
      gain = -(run.model.C.leftCols(nq) * x1)(0, 0);
    }
    std::printf(
        "  mode 9 on a chain of %d PLBEAMs (%d DOF, %d states): statics + state-space model %.3f s (median of 3)%s; "
        "static gain %.6e against L^3/(3 EI) = %.6e\n",
        n, m.numDofs(), static_cast<int>(run.model.A.rows()), walls[1],
        run.completed ? "" : (" (stopped: " + run.stopReason + ")").c_str(), gain, 1.0 / (3 * 2.0));
  }
}

}  // namespace flexmb::bench
