#include "tools/analysis/Statics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <sstream>

#include "core/ElementValidity.hpp"
#include "solvers/EigenSolver.hpp"

namespace flexmb::analysis {

solvers::StaticResult equilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                  const solvers::NewtonOptions& options, double initialFactor) {
  lin.kinematics().setInputLoadFactor(loadFactor, initialFactor);
  Eigen::VectorXd f;
  core::LinearizedSystem sys;
  // Loads that depend on the configuration (gravity on distributed masses, spatial moments on
  // Euler parameters) are evaluated where the generalised forces are: place the model first.
  Eigen::VectorXd q;
  auto place = [&](const Eigen::VectorXd& e) {
    if (!lin.model().spatial) return;  // planar: the load path as before (gravity turns little)
    lin.dofs(e, q);
    lin.kinematics().solvePositions(t, q);
  };
  auto problem = [&](const Eigen::VectorXd& e, Eigen::VectorXd& Q, Eigen::MatrixXd* T) {
    place(e);
    lin.appliedForces(t, loadFactor, f, initialFactor);
    if (T) {
      lin.tangent(t, e, f, Q, *T);
    } else {
      lin.staticForces(t, e, f, Q);
    }
  };
  // Force scale: the generalised applied load, else a stiffness times a small motion of the model.
  double scale = 0.0;
  try {
    place(eta);
    lin.appliedForces(t, loadFactor, f, initialFactor);
    lin.atRest(t, eta, f, sys, false);
    if (lin.size() == 0) {  // nothing to solve: the kinematics alone place the model
      solvers::StaticResult r;
      r.residual = 0.0;
      return r;
    }
    Eigen::VectorXd Qf, Q0;
    lin.staticForces(t, eta, f, Qf);
    lin.staticForces(t, eta, Eigen::VectorXd::Zero(f.size()), Q0);
    double L = 0.0;
    for (int i = 0; i < lin.model().nx; ++i)
      if (lin.model().nodes[lin.model().xOwnerNode[i]].kind == core::NodeKind::Position || lin.model().nodes[lin.model().xOwnerNode[i]].kind == core::NodeKind::SpatialPosition)
        L = std::max(L, std::abs(lin.model().x0[i]));
    scale = std::max({(Qf - Q0).lpNorm<Eigen::Infinity>(), sys.Q.lpNorm<Eigen::Infinity>(),
                      1e-6 * std::max(L, 1e-3) * sys.K.diagonal().cwiseAbs().maxCoeff()});
  } catch (const std::exception& e) {
    solvers::StaticResult r;
    r.status = solvers::StaticStatus::Failed;
    r.message = e.what();
    return r;
  }
  return solvers::solveEquilibrium(problem, eta, scale, options);
}

namespace {
Frequencies fromResult(const solvers::EigenResult& r) {
  Frequencies out;
  out.lambda = r.lambda;
  out.omega.resize(r.lambda.size());
  for (Eigen::Index i = 0; i < r.lambda.size(); ++i)
    out.omega[i] = r.lambda[i] >= 0 ? std::sqrt(r.lambda[i]) : -std::sqrt(-r.lambda[i]);
  out.method = r.method;
  return out;
}

}  // namespace

Frequencies naturalFrequencies(const core::LinearizedSystem& sys, int nev) {
  solvers::EigenOptions o;
  o.nev = std::min<int>(nev, static_cast<int>(sys.M.rows()));
  const solvers::EigenResult r = o.nev >= sys.M.rows() ? solvers::solveDense(sys.K + sys.G, sys.M, o)
                                                       : solvers::solveLowest(sys.K + sys.G, sys.M, o);
  Frequencies out = fromResult(r);
  out.modes = r.vectors;
  return out;
}

EigenPath eigenPathFromEnvironment() {
  const char* v = std::getenv("FLEXMB_EIGEN");
  if (!v) return EigenPath::Auto;
  const std::string s(v);
  if (s == "dense") return EigenPath::Dense;
  if (s == "sparse") return EigenPath::Sparse;
  return EigenPath::Auto;
}

namespace {
// ARPACK on the constrained nodal pencil; eigenvectors back in q (P dx) and x (scattered dx).
solvers::EigenResult sparseSolve(const core::Linearization& lin, int nev, Frequencies& out) {
  core::ConstrainedPencil p;
  lin.constrainedPencil(p);
  solvers::ConstrainedShiftInvert op(p.K, p.M, p.C);
  solvers::EigenOptions o;
  o.nev = nev;
  o.lowestShift = true;
  const solvers::EigenResult r = solvers::solveArpack(op, o);
  out = fromResult(r);
  out.method = "sparse-constrained";
  out.modes = p.P * r.vectors;
  out.nodalModes.setZero(lin.model().nx, r.vectors.cols());
  for (size_t i = 0; i < p.free.size(); ++i) out.nodalModes.row(p.free[i]) = r.vectors.row(static_cast<Eigen::Index>(i));
  return r;
}
}  // namespace

Frequencies naturalFrequencies(const core::Linearization& lin, const core::LinearizedSystem& sys, int nev,
                               EigenPath path) {
  const int m = lin.size();
  nev = std::min(nev, m);
  if (path == EigenPath::Auto) path = eigenPathFromEnvironment();
  if (path == EigenPath::Auto) path = m >= kSparseEigenFrom ? EigenPath::Sparse : EigenPath::Dense;
  if (path == EigenPath::Sparse && !lin.basis() && nev < m) {
    Frequencies out;
    const solvers::EigenResult r = sparseSolve(lin, nev, out);
    if (r.status == solvers::EigenStatus::Converged) return out;
  }
  Frequencies out = naturalFrequencies(sys, nev);
  out.nodalModes = lin.transfer() * out.modes;
  return out;
}

Frequencies sparseFrequencies(const core::Linearization& lin, int nev) {
  Frequencies out;
  const solvers::EigenResult r = sparseSolve(lin, nev, out);
  if (r.status != solvers::EigenStatus::Converged)
    throw std::runtime_error("sparse eigenanalysis: " + r.message);
  return out;
}

std::vector<LoadPoint> loadSchedule(const core::Model& model, int loadSteps) {
  const int nsteps = loadSteps > 0 ? loadSteps : std::max(1, model.settings.loadSteps);
  const int ninit = std::max(0, model.settings.initialLoadSteps);
  bool increments = model.delf.size() && !model.delf.isZero(0.0);
  for (const auto& r : model.inputX) increments = increments || r.delta != 0.0;
  for (const auto& mo : model.moments) increments = increments || !mo.increment.isZero(0.0);  // spatial DELXF
  bool initial = model.f0.size() && !model.f0.isZero(0.0);
  for (const auto& r : model.inputX) initial = initial || (!r.fx && r.x0 != r.base);
  for (const auto& r : model.inputE) initial = initial || (!r.fx && r.x0 != 0.0);
  for (const auto& mo : model.moments) initial = initial || !mo.value.isZero(0.0);  // spatial XF moments
  std::vector<LoadPoint> points;
  if (!increments) {
    const int n = !initial ? 1 : ninit > 0 ? ninit : nsteps;
    for (int k = 1; k <= n; ++k) points.push_back({static_cast<double>(k) / n, 0.0});
    return points;
  }
  if (initial)
    for (int k = 1; k <= ninit; ++k) points.push_back({static_cast<double>(k) / ninit, 0.0});
  for (int i = 1; i <= nsteps; ++i) points.push_back({1.0, static_cast<double>(i) / nsteps});
  return points;
}

Eigen::VectorXd bucklingFactors(const core::LinearizedSystem& sys, int count) {
  // K0 = L L^T; mu = 1/nu for the eigenvalues nu > 0 of -L^-1 G0 L^-T (symmetric).
  const Eigen::Index m = sys.K.rows();
  if (m == 0 || count <= 0) return {};
  Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (sys.K + sys.K.transpose()));
  if (llt.info() != Eigen::Success) return {};
  Eigen::MatrixXd A = -0.5 * (sys.G + sys.G.transpose());
  A = llt.matrixL().solve(A);
  A = llt.matrixL().solve(A.transpose().eval()).transpose().eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (A + A.transpose()), Eigen::EigenvaluesOnly);
  std::vector<double> mu;
  const double top = es.eigenvalues().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < m; ++i)
    if (es.eigenvalues()[i] > 1e-12 * top) mu.push_back(1.0 / es.eigenvalues()[i]);
  std::sort(mu.begin(), mu.end());
  if (static_cast<int>(mu.size()) > count) mu.resize(count);
  return Eigen::Map<Eigen::VectorXd>(mu.data(), static_cast<Eigen::Index>(mu.size()));
}

StaticRun staticAnalysis(const core::Model& model, int nev, int loadSteps, const std::function<void(int, int)>& onStep,
                         int buckling) {
  StaticRun run;
  core::Linearization lin(model);
  // The kinematic residual must stay far below the equilibrium Newton's tolerance (relative 1e-10),
  // else it is noise in Q that stalls the iteration: SPACAR Light writes ITERSTEP's tolerance as
  // 5e-7, which flexmb reads as the kinematic tolerance; statics tightens it (as simulate does).
  lin.kinematics().setRelativeTolerance(std::min(model.settings.kinematicTol, 1e-12));
  const std::vector<LoadPoint> schedule = loadSchedule(model, loadSteps);
  const int n = static_cast<int>(schedule.size());
  Eigen::VectorXd eta = lin.kinematics().initialDofs();
  const double t = model.settings.t0;
  // Every path starts unloaded (mu = s = 0): initial loads applied "at once" are reached within
  // the first step, sub-stepped like any other when Newton needs it.
  LoadPoint reachedPoint{0.0, 0.0};
  for (int i = 1; i <= n; ++i) {
    if (onStep) onStep(i - 1, n);
    const LoadPoint from = reachedPoint, to = schedule[i - 1];
    // Sub-steps in the fraction p of this step: halve it when Newton fails, down to 2^-6.
    double reached = 0.0, ds = 1.0;
    solvers::StaticResult res;
    auto at = [&](double p) {
      return LoadPoint{from.initial + p * (to.initial - from.initial),
                       from.increment + p * (to.increment - from.increment)};
    };
    while (reached < 1.0 - 1e-12) {
      Eigen::VectorXd trial = eta;
      const double p = std::min(1.0, reached + ds);
      const LoadPoint lp = at(p);
      // A failed attempt may leave the kinematic warm start far away (another assembly branch of
      // a closed loop): the next attempt starts from the last equilibrium's configuration.
      const Eigen::VectorXd xGood = lin.kinematics().x();
      solvers::NewtonOptions newton;
      newton.energyFallback = model.spatial;
      res = equilibrium(lin, t, lp.increment, trial, newton, lp.initial);
      // (Spatial models only: planar load paths, e.g. onto a post-buckled branch, stay as they were.)
      if (res.status != solvers::StaticStatus::Converged && model.spatial) lin.kinematics().setConfiguration(xGood);
      if (res.status == solvers::StaticStatus::Converged) {
        eta = trial;
        reached = p;
        ds = std::min(2 * ds, 1.0 - reached);
        continue;
      }
      ds *= 0.5;
      if (ds < std::ldexp(1.0, -6)) {
        const LoadPoint lr = at(reached);
        std::ostringstream msg;
        msg << "no equilibrium beyond load factor " << lr.increment;
        if (lr.initial != 1.0) msg << " (initial loads " << lr.initial << ")";
        msg << " (step " << i << " of " << n << "): " << res.message;
        run.completed = false;
        run.stopReason = msg.str();
        return run;
      }
    }
    reachedPoint = to;
    const double reachedS = to.increment, reachedMu = to.initial;
    try {
    StaticStep st;
    st.loadFactor = reachedS;
    st.initialFactor = reachedMu;
    st.eta = eta;
    st.newton = res;
    Eigen::VectorXd f;
    core::LinearizedSystem sys;
    lin.kinematics().setInputLoadFactor(reachedS, reachedMu);
    if (model.spatial) {
      Eigen::VectorXd q;
      lin.dofs(eta, q);
      lin.kinematics().solvePositions(t, q);  // configuration-dependent loads at the equilibrium
    }
    lin.appliedForces(t, reachedS, f, reachedMu);
    lin.atRest(t, eta, f, sys, true);
    st.x = lin.kinematics().x();
    // A converged equilibrium can still be spurious: load control may jump into a fold where a
    // beam node turned past 90 degrees against its chord, which Eq. 3b/3c (l0 sin theta) see as
    // nearly unbent. Stop there and keep the steps before it.
    if (const auto bad = core::firstInvalidElement(model, st.x)) {
      std::ostringstream msg;
      msg << "load factor " << reachedS << " (step " << i << " of " << n << "): " << bad->message
          << "; refine the mesh or use more load steps";
      run.completed = false;
      run.stopReason = msg.str();
      return run;
    }
    st.e = lin.kinematics().e();
    st.sigma = sys.sigma;
    st.system = sys;
    if (nev > 0 && sys.M.rows() > 0) st.frequencies = naturalFrequencies(lin, sys, nev);
    if (buckling > 0) st.buckling = bucklingFactors(sys, buckling);
    run.steps.push_back(std::move(st));
    } catch (const std::exception& e) {
      run.completed = false;
      run.stopReason = "at load factor " + std::to_string(reachedS) + ": " + e.what();
      return run;
    }
  }
  return run;
}

}  // namespace flexmb::analysis
