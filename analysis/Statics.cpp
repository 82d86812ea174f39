#include "analysis/Statics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "analysis/Interrupt.hpp"
#include "analysis/StaticDesign.hpp"
#include "core/elements/EulerParameters.hpp"
#include "core/kinematics/ElementValidity.hpp"
#include "io/formats/OriginalResults.hpp"
#include "io/formats/ResultWriter.hpp"
#include "solvers/EigenSolver.hpp"
#include "solvers/KineticStability.hpp"

namespace flexmb::analysis {

namespace {
// Statics has no time: the kinematics' "failed at t = 0" is said without it.
std::string staticWording(std::string message) {
  const std::string timed = "kinematics failed at t = 0: ";
  for (auto at = message.find(timed); at != std::string::npos; at = message.find(timed))
    message.replace(at, timed.size(), "the kinematics failed: ");
  return message;
}

// The element whose end nodes turned most against each other since the initial configuration
// (planar: the difference of the angles; spatial: the angle of the relative rotation).
struct ElementBend {
  int element = -1;
  double angle = 0.0;
};
constexpr double kBendAdvice = 0.8;  // rad: beyond it, "refine the mesh" (beams follow about 1 rad)
ElementBend largestBend(const core::Model& model, const Eigen::VectorXd& x) {
  ElementBend worst;
  for (size_t ei = 0; ei < model.elements.size(); ++ei) {
    std::vector<const core::Node*> ends;
    for (int ni : model.elements[ei].nodes) {
      const core::Node& nd = model.nodes[static_cast<size_t>(ni)];
      if (nd.kind == core::NodeKind::Orientation || nd.kind == core::NodeKind::EulerParameters) ends.push_back(&nd);
    }
    if (ends.size() != 2) continue;
    double angle = 0.0;
    const int p = ends[0]->firstCoord, q = ends[1]->firstCoord;
    if (ends[0]->kind == core::NodeKind::Orientation) {
      angle = std::abs((x[q] - x[p]) - (model.x0[q] - model.x0[p]));
    } else {
      using core::euler::rotation;
      const Eigen::Matrix3d now = rotation(x.segment<4>(p)).transpose() * rotation(x.segment<4>(q));
      const Eigen::Matrix3d then = rotation(model.x0.segment<4>(p)).transpose() * rotation(model.x0.segment<4>(q));
      const double c = std::clamp(((then.transpose() * now).trace() - 1.0) / 2.0, -1.0, 1.0);
      angle = std::acos(c);
    }
    if (angle > worst.angle) worst = {static_cast<int>(ei), angle};
  }
  return worst;
}
// Force scale of the residual test: a stiffness times a small motion of the model.
double stiffnessForce(const core::Model& m, const Eigen::VectorXd& diagonalK) {
  return diagonalK.size() ? 1e-6 * std::max(m.lengthScale(), 1e-3) * diagonalK.cwiseAbs().maxCoeff() : 0.0;
}
double stiffnessForce(const core::Model& m, const Eigen::MatrixXd& K) {
  return stiffnessForce(m, Eigen::VectorXd(K.diagonal()));
}

solvers::StaticResult failed(const std::string& message) {
  solvers::StaticResult r;
  r.status = solvers::StaticStatus::Failed;
  r.message = message;
  return r;
}

// Planar models and models with a basis: the dense tangent Kbar + Gbar, loads evaluated where the
// kinematics were last (planar: the load path as before; gravity turns little).
solvers::StaticResult denseEquilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                       const solvers::NewtonOptions& options, double initialFactor) {
  Eigen::VectorXd f;
  core::LinearizedSystem sys;
  // Spatial models with a basis: configuration-dependent loads (gravity on distributed masses,
  // moments on Euler parameters) are evaluated where the generalised forces are.
  Eigen::VectorXd q;
  auto place = [&](const Eigen::VectorXd& e) {
    if (!lin.model().spatial) return;
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
  // Force scale: the generalised applied load, else a stiffness times a small motion of the model
  // (the diagonal of Kbar only: a whole projection costs O(nx m^2)).
  double scale = 0.0;
  try {
    place(eta);
    lin.appliedForces(t, loadFactor, f, initialFactor);
    if (lin.size() == 0) {  // nothing to solve: the kinematics alone place the model
      lin.atRest(t, eta, f, sys, false);
      solvers::StaticResult r;
      r.residual = 0.0;
      return r;
    }
    Eigen::VectorXd Q, diagonalK, Qf, Q0;
    lin.stiffnessDiagonal(t, eta, f, Q, diagonalK);
    lin.staticForces(t, eta, f, Qf);
    lin.staticForces(t, eta, Eigen::VectorXd::Zero(f.size()), Q0);
    scale = std::max(
        {(Qf - Q0).lpNorm<Eigen::Infinity>(), Q.lpNorm<Eigen::Infinity>(), stiffnessForce(lin.model(), diagonalK)});
  } catch (const std::exception& e) {
    return failed(e.what());
  }
  return solvers::solveEquilibrium(problem, eta, scale, options);
}

// Spatial full models: loads follow the configuration, the tangent is factorised sparse in the
// nodal saddle-point form (Linearization::staticTangent: no F_q, no dense projection).
class SparseStaticProblem final : public solvers::StaticProblem {
 public:
  SparseStaticProblem(core::Linearization& lin, double t, double loadFactor, double initialFactor)
      : lin_(lin), t_(t), s_(loadFactor), mu_(initialFactor) {}
  void residual(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) override { lin_.staticResidual(t_, eta, s_, mu_, Q); }
  solvers::TangentKind linearize(const Eigen::VectorXd& eta, Eigen::VectorXd& Q) override {
    return lin_.staticTangent(t_, eta, s_, mu_, Q) ? solvers::TangentKind::Unknown : solvers::TangentKind::Singular;
  }
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override { lin_.solveStaticTangent(b, x); }

 private:
  core::Linearization& lin_;
  const double t_, s_, mu_;
};

// stiffnessScale: stiffnessForce of Kbar near eta (< 0: computed here, one dense projection, and
// returned). The result's `stable` is left for the caller (the sparse factorisation does not know it).
solvers::StaticResult sparseEquilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                        const solvers::NewtonOptions& options, double initialFactor,
                                        double& stiffnessScale) {
  if (lin.size() == 0) return {};
  double scale = 0.0;
  try {
    Eigen::VectorXd Q, Qf, Q0, f;
    lin.staticResidual(t, eta, loadFactor, initialFactor, Q);
    lin.appliedForces(t, loadFactor, f, initialFactor);
    if (stiffnessScale < 0.0) {
      Eigen::VectorXd Qr, diagonalK;
      lin.stiffnessDiagonal(t, eta, f, Qr, diagonalK);
      stiffnessScale = stiffnessForce(lin.model(), diagonalK);
    }
    lin.staticForces(t, eta, f, Qf);
    lin.staticForces(t, eta, Eigen::VectorXd::Zero(f.size()), Q0);
    scale = std::max({(Qf - Q0).lpNorm<Eigen::Infinity>(), Q.lpNorm<Eigen::Infinity>(), stiffnessScale});
  } catch (const std::exception& e) {
    return failed(e.what());
  }
  SparseStaticProblem problem(lin, t, loadFactor, initialFactor);
  return solvers::solveEquilibrium(problem, eta, scale, options);
}

bool sparseNewton(const core::Linearization& lin) { return lin.model().spatial && !lin.basis(); }

}  // namespace

solvers::StaticResult equilibrium(core::Linearization& lin, double t, double loadFactor, Eigen::VectorXd& eta,
                                  const solvers::NewtonOptions& options, double initialFactor) {
  lin.kinematics().setInputLoadFactor(loadFactor, initialFactor);
  if (!sparseNewton(lin)) return denseEquilibrium(lin, t, loadFactor, eta, options, initialFactor);
  double stiffnessScale = -1.0;
  solvers::StaticResult r = sparseEquilibrium(lin, t, loadFactor, eta, options, initialFactor, stiffnessScale);
  if (r.status == solvers::StaticStatus::Converged && lin.size() > 0) {
    try {  // stability: the dense tangent at the solution
      Eigen::VectorXd Q, f;
      Eigen::MatrixXd T;
      lin.staticResidual(t, eta, loadFactor, initialFactor, Q);
      lin.appliedForces(t, loadFactor, f, initialFactor);
      lin.tangent(t, eta, f, Q, T);
      r.stable = solvers::isPositiveDefinite(T);
    } catch (const std::exception& e) {
      return failed(e.what());
    }
  }
  return r;
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
  initial =
      initial || (model.hasGravity && (model.gravity[0] != 0.0 || model.gravity[1] != 0.0 || model.gravity[2] != 0.0));
  std::vector<LoadPoint> points;
  if (!increments && initial && ninit == 0) {  // the initial loads are the increments
    for (int k = 0; k <= nsteps; ++k) points.push_back({static_cast<double>(k) / nsteps, 0.0, k});
    return points;
  }
  if (initial)
    for (int k = 1; k < ninit; ++k) points.push_back({static_cast<double>(k) / ninit, 0.0, -1});
  points.push_back({1.0, 0.0, 0});
  for (int i = 1; i <= nsteps; ++i) points.push_back({1.0, static_cast<double>(i) / nsteps, i});
  return points;
}

StaticRun staticAnalysis(const core::Model& model, int nev, int loadSteps, const std::function<void(int, int)>& onStep,
                         int buckling) {
  StaticOptions o;
  o.nev = nev;
  o.loadSteps = loadSteps;
  o.onStep = onStep;
  o.buckling = buckling;
  return staticAnalysis(model, o);
}

// Why a load step stops where halving no longer finds an equilibrium (Newton's message in statics'
// words), with the mesh to refine where an element bent through about a radian.
std::string noEquilibriumBeyond(const core::Model& model, const LoadPoint& lr, int i, int n, const std::string& newton,
                                const Eigen::VectorXd& lastEquilibrium) {
  std::ostringstream msg;
  msg << "no equilibrium beyond load factor " << lr.increment;
  if (lr.initial != 1.0) msg << " (initial loads " << lr.initial << ")";
  std::string why = staticWording(newton);
  // An element bent through about a radian is past what one beam element follows: the mesh,
  // not the load steps, is what to refine.
  const ElementBend bend = largestBend(model, lastEquilibrium);
  if (bend.angle > kBendAdvice) {
    const std::string limitAdvice = "; a limit point is near: use smaller load steps";
    if (const auto pos = why.find(limitAdvice); pos != std::string::npos) why.erase(pos, limitAdvice.size());
  }
  msg << " (step " << i << " of " << n << "): " << why;
  if (bend.angle > kBendAdvice)
    msg << "; " << model.elements[bend.element].type->keyword << " " << model.elements[bend.element].label
        << " bends through " << std::round(bend.angle * 100) / 100
        << " rad between its end nodes at the last equilibrium, more than one beam element follows (about 1 "
           "rad): refine the mesh (more elements along it), not the load steps";
  return msg.str();
}

StaticRun staticAnalysis(const core::Model& model, const StaticOptions& options) {
  const int nev = options.nev, loadSteps = options.loadSteps, buckling = options.buckling;
  const auto& onStep = options.onStep;
  StaticRun run;
  core::Linearization lin(model);
  // The kinematic residual must stay far below the equilibrium Newton's tolerance (relative 1e-10),
  // else it is noise in Q that stalls the iteration: SPACAR Light writes ITERSTEP's tolerance as
  // 5e-7, which flexmb reads as the kinematic tolerance; statics tightens it (as simulate does).
  lin.kinematics().setRelativeTolerance(std::min(model.settings.kinematicTol, 1e-12));
  const std::vector<LoadPoint> schedule = loadSchedule(model, loadSteps);
  const int n = static_cast<int>(schedule.size());
  run.loadSteps = schedule.back().loadStep;
  Eigen::VectorXd eta = lin.kinematics().initialDofs();
  const double t = model.settings.t0;
  // Every path starts unloaded (mu = s = 0): initial loads applied "at once" are reached within
  // the first step, sub-stepped like any other when Newton needs it.
  LoadPoint reachedPoint{0.0, 0.0};
  // Spatial full models: Newton accepts steps by the correction test and factorises the tangent
  // sparse; its residual scale takes Kbar's diagonal from the last equilibrium (the start).
  const bool sparse = sparseNewton(lin);
  solvers::NewtonOptions newton;
  newton.correctionMonotonicity = model.spatial;
  double stiffnessScale = -1.0;
  bool lastStable = true;  // the last accepted equilibrium (dense path: Newton reports it)
  const bool loadControl =
      std::none_of(model.inputX.begin(), model.inputX.end(), [](const core::Rheonomic& r) { return r.delta != 0.0; });
  const double minStep = std::ldexp(1.0, -6);
  Eigen::VectorXd lastEquilibrium = model.x0;  // the configuration of the last converged (sub-)step
  auto interrupted = [&](int step) {
    if (!stopRequested(options.interrupt)) return false;
    run.completed = false;
    run.interrupted = true;
    run.stopReason = interruptCause(options.interruptSignal) + " before load step " + std::to_string(step) + " of " +
                     std::to_string(n) + "; the " + std::to_string(run.steps.size()) + " load steps before it are kept";
    return true;
  };
  for (int i = 1; i <= n; ++i) {
    if (onStep) onStep(i - 1, n);
    if (interrupted(i)) return run;
    const LoadPoint from = reachedPoint, to = schedule[i - 1];
    // Sub-steps in the fraction p of this step: halve it when Newton fails, down to 2^-6.
    double reached = 0.0, ds = 1.0;
    int iterations = 0;
    solvers::StaticResult res;
    auto at = [&](double p) {
      return LoadPoint{from.initial + p * (to.initial - from.initial),
                       from.increment + p * (to.increment - from.increment)};
    };
    while (reached < 1.0 - 1e-12) {
      if (interrupted(i)) return run;  // a load step cut into many sub-steps can take long
      Eigen::VectorXd trial = eta;
      const double p = std::min(1.0, reached + ds);
      const LoadPoint lp = at(p);
      // A failed attempt may leave the kinematic warm start far away (another assembly branch of
      // a closed loop): the next attempt starts from the last equilibrium's configuration.
      const Eigen::VectorXd xGood = lin.kinematics().x();
      lin.kinematics().setInputLoadFactor(lp.increment, lp.initial);
      res = sparse ? sparseEquilibrium(lin, t, lp.increment, trial, newton, lp.initial, stiffnessScale)
                   : denseEquilibrium(lin, t, lp.increment, trial, newton, lp.initial);
      iterations += res.iterations;
      // (Spatial models only: planar load paths, e.g. onto a post-buckled branch, stay as they were.)
      if (res.status != solvers::StaticStatus::Converged && model.spatial) lin.kinematics().setConfiguration(xGood);
      if (res.status == solvers::StaticStatus::Converged) {
        // Under load control, from a stable equilibrium onto an unstable one: the step jumped
        // across a limit or bifurcation point onto another branch (an imperfect column's
        // complementary branch). Smaller steps follow the stable path where there is one; where
        // halving no longer helps the unstable equilibrium is kept (and reported as such). Under
        // prescribed motion (DELINPX) the motion parametrises the path: an unstable equilibrium
        // there (a dead point approached) is part of it.
        if (!sparse && loadControl && lastStable && !res.stable && ds >= 2 * minStep) {
          lin.kinematics().setConfiguration(xGood);
          ds *= 0.5;
          continue;
        }
        if (!sparse) lastStable = res.stable;
        eta = trial;
        reached = p;
        lastEquilibrium = lin.kinematics().x();
        ds = std::min(2 * ds, 1.0 - reached);
        continue;
      }
      ds *= 0.5;
      if (ds < minStep) {
        run.completed = false;
        run.stopReason = noEquilibriumBeyond(model, at(reached), i, n, res.message, lastEquilibrium);
        return run;
      }
    }
    reachedPoint = to;
    const double reachedS = to.increment, reachedMu = to.initial;
    try {
      StaticStep st;
      st.loadFactor = reachedS;
      st.initialFactor = reachedMu;
      st.loadStep = to.loadStep;
      st.eta = eta;
      st.newton = res;
      st.iterations = iterations;
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
      if (sparse) {
        st.newton.stable = solvers::isPositiveDefinite(sys.K + sys.G);
        stiffnessScale = stiffnessForce(model, sys.K);  // for the next step, which starts here
      }
      // Dead moments make the load circulatory (Gskew): the kinetic criterion decides (KineticStability.hpp).
      if (sys.Gskew.size() && !sys.Gskew.isZero(0.0) && sys.M.rows() > 0) {
        st.kinetic = solvers::kineticStability(sys.K + sys.G + sys.Gskew, sys.M);
        if (st.kinetic->verdict != solvers::KineticVerdict::Undecided) st.newton.stable = st.kinetic->stable();
      }
      st.e = lin.kinematics().e();
      st.sigma = sys.sigma;
      if (nev > 0 && sys.M.rows() > 0) st.frequencies = naturalFrequencies(lin, sys, nev, options.eigenPath);
      if (buckling > 0) st.buckling = bucklingFactors(sys, buckling);
      st.system = std::move(sys);  // seven m x m matrices: moved, not copied
      run.steps.push_back(std::move(st));
    } catch (const std::exception& e) {
      run.completed = false;
      run.stopReason = "at load factor " + std::to_string(reachedS) + ": " + staticWording(e.what());
      return run;
    }
  }
  return run;
}

std::string stabilityVerdict(const StaticStep& step) {
  if (step.kinetic && step.kinetic->verdict != solvers::KineticVerdict::Undecided)
    return step.kinetic->stable() ? "stable" : step.kinetic->describe() + " under the dead moments";
  const std::string energy = step.newton.stable ? "stable" : "K0 + G0 not positive definite";
  if (!step.kinetic) return energy;
  return energy + " (energy criterion: the kinetic test for the dead moments could not be made, " +
         step.kinetic->message + ")";
}

double elementLength(const core::Model& m, const core::ElementEntry& el) {
  if (el.impl && el.impl->referenceLength() > 0.0) return el.impl->referenceLength();
  int first = -1, last = -1;
  for (int n : el.nodes)
    if (core::isTranslational(m.nodes[n].kind)) (first < 0 ? first : last) = n;
  if (first < 0 || last < 0) return 0.0;
  const auto& a = m.nodes[first];
  const auto& b = m.nodes[last];
  return (m.x0.segment(b.firstCoord, b.dim()) - m.x0.segment(a.firstCoord, a.dim())).norm();
}

namespace {

// The column of a deformation's generalised stress and its scale to a force or moment: beams measure
// bending and torsion as l0 times an angle (Eq. 3b/3c; core/elements/SpatialBeam.hpp), so their
// generalised stresses are moments over l0. "" for the other kinds.
const char* sectionForceColumn(core::DeformationKind kind) {
  switch (kind) {
    case core::DeformationKind::Elongation:
      return "max_axial_force";
    case core::DeformationKind::Torsion:
      return "max_torsion_moment";
    case core::DeformationKind::BendingY:
      return "max_bending_moment_y";
    case core::DeformationKind::BendingZ:
      return "max_bending_moment_z";
    case core::DeformationKind::Bending:
      return "max_bending_moment";
    case core::DeformationKind::Rotation:
    case core::DeformationKind::Warping:
    case core::DeformationKind::Other:
      break;
  }
  return "";
}
}  // namespace

std::vector<SectionForceMaximum> sectionForceMaxima(const core::Model& m, const Eigen::VectorXd& sigma) {
  std::map<std::string, SectionForceMaximum> maxima;
  for (size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = m.elements[e];
    const int nd = el.type->numDeformations();
    bool elastic = false;
    for (int k = 0; k < nd; ++k) {
      const core::Role r = m.eRole[el.firstDef + k];
      elastic = elastic || r == core::Role::Dynamic || r == core::Role::Calculable;
    }
    if (!elastic || el.type->internal) continue;
    const double l0 = elementLength(m, el);
    for (int k = 0; k < nd; ++k) {
      const core::DeformationKind kind = el.type->deformationKind(k);
      const std::string column = sectionForceColumn(kind);
      if (column.empty()) continue;
      SectionForceMaximum& v = maxima.emplace(column, SectionForceMaximum{column}).first->second;
      if (el.firstDef + k >= sigma.size()) continue;
      const double f = std::abs(sigma[el.firstDef + k]) * (kind == core::DeformationKind::Elongation ? 1.0 : l0);
      if (f > v.value) v.value = f, v.element = static_cast<int>(e);
    }
  }
  std::vector<SectionForceMaximum> out;
  for (const char* c :
       {"max_axial_force", "max_bending_moment", "max_bending_moment_y", "max_bending_moment_z", "max_torsion_moment"})
    if (auto it = maxima.find(c); it != maxima.end()) out.push_back(it->second);
  return out;
}

std::vector<std::pair<std::string, double>> appliedNodalLoads(const core::Model& model, const StaticStep& step) {
  std::vector<std::pair<std::string, double>> loads;
  Eigen::VectorXd timed = Eigen::VectorXd::Zero(model.nx);
  for (const auto& tf : model.timeForces) timed[tf.index] += tf.f->value(model.settings.t0);
  const auto names = io::coordinateColumnNames(model);
  for (int i = 0; i < model.nx; ++i) {
    const double f0 = model.f0.size() == model.nx ? model.f0[i] : 0.0,
                 df = model.delf.size() == model.nx ? model.delf[i] : 0.0;
    const bool xft = std::any_of(model.timeForces.begin(), model.timeForces.end(),
                                 [&](const core::TimeLoad& tf) { return tf.index == i; });
    if (f0 == 0.0 && df == 0.0 && !xft) continue;
    const bool moment = model.nodes[model.xOwnerNode[i]].kind == core::NodeKind::Orientation;
    loads.emplace_back((moment ? "M." : "F.") + names[i], step.initialFactor * f0 + step.loadFactor * df + timed[i]);
  }
  for (const auto& mo : model.moments) {
    if (mo.value.isZero(0.0) && mo.increment.isZero(0.0)) continue;
    const Eigen::Vector3d M = step.initialFactor * mo.value + step.loadFactor * mo.increment;
    for (int c = 0; c < 3; ++c)
      loads.emplace_back("M.node" + std::to_string(model.nodes[mo.node].label) + "." + "xyz"[c], M[c]);
  }
  return loads;
}

io::CsvTable staticTable(const core::Model& model, const StaticRun& run, int buckling) {
  Eigen::Index nev = 0;
  for (const auto& st : run.steps) nev = std::max(nev, st.frequencies.omega.size());
  io::CsvTable t;
  t.columns = {"load_step", "initial_factor", "load_factor"};
  for (const auto& name : io::coordinateColumnNames(model)) t.columns.push_back(name);
  for (Eigen::Index i = 0; i < nev; ++i) t.columns.push_back(io::numberedColumn("f", i + 1, "_Hz"));
  for (int i = 0; i < buckling; ++i) t.columns.push_back(io::numberedColumn("buckling", i + 1, ""));
  // The section forces and the loads: the same columns at every step (the model's kinds and loads).
  const StaticStep none;
  for (const auto& f : sectionForceMaxima(model, Eigen::VectorXd())) t.columns.push_back(f.name);
  for (const auto& l : appliedNodalLoads(model, none)) t.columns.push_back(l.first);
  // The largest von Mises stress and its element (StaticDesign.hpp), then the support reactions.
  const bool stresses = !stressedElements(model).empty();
  if (stresses) t.columns.insert(t.columns.end(), {"max_stress", "max_stress_element"});
  for (const auto& r : supportReactions(model, none)) t.columns.push_back(r.first);
  const double empty = std::numeric_limits<double>::quiet_NaN();
  for (const auto& st : run.steps) {
    std::vector<double> row{static_cast<double>(st.loadStep), st.initialFactor, st.loadFactor};
    for (int i = 0; i < model.nx; ++i) row.push_back(st.x[i]);
    for (Eigen::Index i = 0; i < nev; ++i)
      row.push_back(i < st.frequencies.omega.size() ? st.frequencies.omega[i] / (2 * M_PI) : empty);
    for (int i = 0; i < buckling; ++i) row.push_back(i < st.buckling.size() ? st.buckling[i] : empty);
    for (const auto& f : sectionForceMaxima(model, st.sigma)) row.push_back(f.value);
    for (const auto& l : appliedNodalLoads(model, st)) row.push_back(l.second);
    if (stresses) {
      const ElementStress top = largestStress(model, st);
      row.push_back(top.vonMises);
      row.push_back(top.element >= 0 ? model.elements[top.element].label : empty);
    }
    for (const auto& r : supportReactions(model, st)) row.push_back(r.second);
    t.rows.push_back(std::move(row));
  }
  return io::originalColumns(model, std::move(t));  // a refined model's: at the original nodes
}

}  // namespace flexmb::analysis
