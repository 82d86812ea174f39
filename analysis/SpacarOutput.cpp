#include "analysis/SpacarOutput.hpp"

#include <cmath>

#include "analysis/Perturbation.hpp"
#include "core/dynamics/ResultQuantities.hpp"
#include "core/kinematics/KinematicCheck.hpp"

namespace flexmb::analysis {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

std::vector<core::FreeCoordinate> dynamicColumns(const core::Model& model) {
  std::vector<core::FreeCoordinate> cols;
  for (const auto& d : model.dofs) cols.push_back({d.isDeformation, d.index});
  return cols;
}

// The state part of a step, in SPACAR's order, with sig~ and fxt (and dx, de, bigd when asked).
io::SpacarStep stateStep(const core::Model& model, const io::SpacarLayout& L, core::ResultQuantities& rq, double t,
                         double loadFactor, const core::StateOutputs& s, const SpacarOutputOptions& o,
                         double initialFactor = 1.0) {
  io::SpacarStep st;
  rq.setState(t, dofsOf(model, s, 0), loadFactor, initialFactor, &s.x);  // from the state's own configuration
  Eigen::VectorXd sig, fxt;
  core::ResultQuantities::AppliedForces applied;
  rq.forces(t, loadFactor, s, Eigen::VectorXd(), sig, fxt, initialFactor, &applied);
  st.x = L.sortX(s.x), st.xd = L.sortX(s.xd), st.xdd = L.sortX(s.xdd), st.fxt = L.sortX(fxt);
  st.fx = L.sortX(applied.loads), st.fxgrav = L.sortX(applied.gravity);
  st.e = L.sortE(s.e), st.ed = L.sortE(s.ed), st.edd = L.sortE(s.edd), st.sig = L.sortE(sig);
  Eigen::MatrixXd D;
  if (o.transferFunctions) {
    Eigen::MatrixXd dx;
    rq.transfer(L.dofColumns, dx);
    st.dx.resize(model.nx, dx.cols());
    for (int i = 0; i < model.nx; ++i) st.dx.row(i) = dx.row(L.xOrder[i]);
    // SPACAR's de: the deformations' first-order transfer functions de/d(degrees of freedom) = D dx.
    rq.jacobian(D);
    const Eigen::MatrixXd de = D * dx;
    st.de.resize(model.ne, de.cols());
    for (int i = 0; i < model.ne; ++i) st.de.row(i) = de.row(L.eOrder[i]);
  }
  if (o.jacobian) {
    if (!D.size()) rq.jacobian(D);
    st.bigd.resize(model.ne, model.nx);
    for (int i = 0; i < model.ne; ++i)
      for (int j = 0; j < model.nx; ++j) st.bigd(i, j) = D(L.eOrder[i], L.xOrder[j]);
  }
  return st;
}

void setMatrices(io::SpacarStep& st, const core::LinearizedSystem& sys) {
  st.M0 = sys.M, st.K0 = sys.K, st.G0 = sys.G;
  const Eigen::Index m = sys.M.rows();
  st.D0 = sys.D.size() ? sys.D : Eigen::MatrixXd::Zero(m, m);
  st.C0 = sys.C.size() ? sys.C : Eigen::MatrixXd::Zero(m, m);
  st.N0 = sys.N.size() ? sys.N : Eigen::MatrixXd::Zero(m, m);
}

}  // namespace

io::SpacarResults spacarFromTrajectory(const core::Model& model, const core::Trajectory& traj,
                                       const TrajectoryModes* modes, int mode, const SpacarOutputOptions& o) {
  io::SpacarResults r;
  r.mode = mode;
  r.nsteps = traj.nsteps, r.nfailed = traj.nfailed, r.nfevals = traj.nfevals;
  r.completed = traj.completed, r.stopReason = traj.stopReason;
  const io::SpacarLayout L = io::spacarLayout(model);
  core::ResultQuantities rq(model);
  // Modes 3 and 4 store the steps the linearisation reached.
  const std::size_t n = modes ? std::min(traj.time.size(), modes->time.size()) : traj.time.size();
  for (std::size_t k = 0; k < n; ++k) {
    io::SpacarStep st = stateStep(model, L, rq, traj.time[k], 0.0, traj.states[k], o);
    if (modes) {
      if (k < modes->matrices.size()) setMatrices(st, modes->matrices[k]);
      st.freq = modes->omega[k] / kTwoPi;
    }
    r.time.push_back(traj.time[k]);
    r.steps.push_back(std::move(st));
  }
  if (modes && !modes->completed && r.completed) r.completed = false, r.stopReason = modes->stopReason;
  return r;
}

io::SpacarResults spacarFromStatics(const core::Model& model, const StaticRun& run, const SpacarOutputOptions& o) {
  io::SpacarResults r;
  r.mode = 10;
  r.completed = run.completed, r.stopReason = run.stopReason;
  const io::SpacarLayout L = io::spacarLayout(model);
  core::ResultQuantities rq(model);
  for (const StaticStep& s : run.steps) {
    if (s.loadStep < 0) continue;  // a ramp step of the initial loads: not a SPACAR load step
    core::StateOutputs out;
    out.x = s.x, out.e = s.e, out.sig = s.sigma;
    out.xd = out.xdd = Eigen::VectorXd::Zero(model.nx);
    out.ed = out.edd = Eigen::VectorXd::Zero(model.ne);
    io::SpacarStep st = stateStep(model, L, rq, model.settings.t0, s.loadFactor, out, o, s.initialFactor);
    if (o.matrices) setMatrices(st, s.system);
    st.freq = s.frequencies.omega / kTwoPi;
    r.time.push_back(run.loadSteps > 0 ? static_cast<double>(s.loadStep) / run.loadSteps : 0.0);
    r.steps.push_back(std::move(st));
  }
  return r;
}

io::SpacarResults spacarFromStaticPerturbation(const core::Model& model, const StaticRun& run,
                                               const SpacarOutputOptions& o) {
  io::SpacarResults r = spacarFromStatics(model, run, o);
  r.mode = 3;
  std::size_t k = 0;
  for (const StaticStep& s : run.steps) {
    if (s.loadStep < 0) continue;
    const KinematicDofMatrices km = kinematicDofMatrices(model, s);
    r.steps[k].M0all = km.M0;
    r.steps[k].K0B = km.K0B;
    ++k;
  }
  return r;
}

io::SpacarResults spacarFromTransfer(const core::Model& model, const TransferRun& run, const SpacarOutputOptions& o) {
  io::SpacarResults r = spacarFromStatics(model, run.statics, o);
  r.mode = 9;
  if (!run.completed) {
    r.completed = false;
    r.stopReason = run.stopReason;
    return r;
  }
  io::SpacarStateSpace ss;
  ss.A = run.model.A, ss.B = run.model.B, ss.C = run.model.C, ss.D = run.model.D;
  ss.inputNames = run.model.inputNames, ss.outputNames = run.model.outputNames;
  r.stateSpace = std::move(ss);
  return r;
}

io::SpacarResults spacarFromModes(const core::Model& model, double t, const Eigen::VectorXd& eta,
                                  const core::LinearizedSystem& sys, const Eigen::VectorXd& omega,
                                  const Eigen::MatrixXd& modes, const std::optional<Eigen::MatrixXd>& basis) {
  io::SpacarResults r;
  r.mode = 2;
  const io::SpacarLayout L = io::spacarLayout(model);
  core::Workspace workspace(model);  // one for both (each keeps its own warm start)
  core::ResultQuantities rq(workspace);
  const Eigen::VectorXd q = basis ? Eigen::VectorXd(*basis * eta) : eta;
  rq.setState(t, q);
  core::GeometricTransferFunctions probe(workspace.kinematics());
  probe.solvePositions(t, q);
  core::StateOutputs s;
  s.x = probe.x(), s.e = probe.e(), s.sig = sys.sigma;
  s.xd = s.xdd = Eigen::VectorXd::Zero(model.nx);
  s.ed = s.edd = Eigen::VectorXd::Zero(model.ne);
  io::SpacarStep st = stateStep(model, L, rq, t, 0.0, s, {});
  setMatrices(st, sys);
  st.freq = omega / kTwoPi;
  st.modeq = basis ? Eigen::MatrixXd(*basis * modes) : modes;
  Eigen::MatrixXd Fq;
  rq.transfer(dynamicColumns(model), Fq);
  const Eigen::MatrixXd xm = Fq * st.modeq;
  st.modex.resize(model.nx, xm.cols());
  for (int i = 0; i < model.nx; ++i) st.modex.row(i) = xm.row(L.xOrder[i]);
  r.time.push_back(t);
  r.steps.push_back(std::move(st));
  return r;
}

io::SpacarResults spacarKinematic(const core::Model& model) {
  io::SpacarResults r;
  r.mode = 0;
  const io::SpacarLayout L = io::spacarLayout(model);
  // An over- or under-determined model has no transfer functions, but SPACAR's mode 0 still
  // stores the topology and D = de/dx of the initial configuration: SPACAR Light finds the
  // overconstraints of its models from them (the singular vectors of D's calculable block).
  const core::KinematicReport check = core::checkKinematics(model);
  if (!check.wellPosed()) {
    r.warning = "the kinematic equations are not uniquely solvable (" + std::to_string(check.xCalculable) +
                " calculable coordinates, rank " + std::to_string(check.rank) +
                "): stored the initial configuration and D = de/dx only (no dx); `flexmb check` names the "
                "over- and under-determined coordinates";
    const double t = model.settings.t0;
    Eigen::VectorXd x = model.x0;
    for (const auto& in : model.inputX) {
      double v, vd, vdd;
      in.evaluate(t, v, vd, vdd);
      x[in.index] = v;
    }
    io::SpacarStep st;
    Eigen::VectorXd e = Eigen::VectorXd::Zero(model.ne);
    st.bigd = Eigen::MatrixXd::Zero(model.ne, model.nx);
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(model.ne, model.nx);
    for (const auto& el : model.elements) {
      core::ElemVec xe;
      el.gather(x, xe);
      core::DefVec ee;
      core::DefJac De;
      el.impl->deformations(xe, ee);
      el.impl->jacobian(xe, De);
      for (int i = 0; i < ee.size(); ++i) e[el.firstDef + i] = ee[i];
      for (int i = 0; i < De.rows(); ++i)
        for (int j = 0; j < De.cols(); ++j) D(el.firstDef + i, el.coords[j]) += De(i, j);
    }
    for (int i = 0; i < model.ne; ++i)
      for (int j = 0; j < model.nx; ++j) st.bigd(i, j) = D(L.eOrder[i], L.xOrder[j]);
    st.x = L.sortX(x), st.e = L.sortE(e);
    st.xd = st.xdd = st.fxt = st.fx = st.fxgrav = Eigen::VectorXd::Zero(model.nx);
    st.ed = st.edd = st.sig = Eigen::VectorXd::Zero(model.ne);
    r.time.push_back(t);
    r.steps.push_back(std::move(st));
    return r;
  }
  core::Workspace workspace(model);  // one for both (each keeps its own warm start)
  core::ResultQuantities rq(workspace);
  core::GeometricTransferFunctions probe(workspace.kinematics());
  const double t = model.settings.t0;
  const Eigen::VectorXd q = probe.initialDofs();
  probe.solvePositions(t, q);
  core::StateOutputs s;
  s.x = probe.x(), s.e = probe.e();
  s.xd = s.xdd = Eigen::VectorXd::Zero(model.nx);
  s.ed = s.edd = s.sig = Eigen::VectorXd::Zero(model.ne);
  r.time.push_back(t);
  r.steps.push_back(stateStep(model, L, rq, t, 0.0, s, {true, true}));
  return r;
}

}  // namespace flexmb::analysis
