#include "analysis/Modes.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "solvers/EigenSolver.hpp"
#include "solvers/ReductionBasis.hpp"

namespace flexmb::analysis {

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

Frequencies naturalFrequencies(const core::LinearizedSystem& sys, int nev, bool lowestShift) {
  solvers::EigenOptions o;
  o.nev = std::min<int>(nev, static_cast<int>(sys.M.rows()));
  o.lowestShift = lowestShift;
  const solvers::EigenResult r = o.nev >= sys.M.rows() ? solvers::solveDense(sys.K + sys.G, sys.M, o)
                                                       : solvers::solveLowest(sys.K + sys.G, sys.M, o);
  Frequencies out = fromResult(r);
  out.modes = r.vectors;
  return out;
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
  for (size_t i = 0; i < p.free.size(); ++i)
    out.nodalModes.row(p.free[i]) = r.vectors.row(static_cast<Eigen::Index>(i));
  return r;
}
}  // namespace

Frequencies naturalFrequencies(const core::Linearization& lin, const core::LinearizedSystem& sys, int nev,
                               EigenPath path) {
  const int m = lin.size();
  nev = std::min(nev, m);
  if (path == EigenPath::Auto) path = m >= kSparseEigenFrom ? EigenPath::Sparse : EigenPath::Dense;
  if (path == EigenPath::Sparse && !lin.basis() && nev < m) {
    Frequencies out;
    const solvers::EigenResult r = sparseSolve(lin, nev, out);
    if (r.status == solvers::EigenStatus::Converged) return out;
  }
  Frequencies out = naturalFrequencies(sys, nev, lin.model().spatial);
  out.nodalModes = lin.transfer() * out.modes;
  return out;
}

Frequencies sparseFrequencies(const core::Linearization& lin, int nev) {
  Frequencies out;
  const solvers::EigenResult r = sparseSolve(lin, nev, out);
  if (r.status != solvers::EigenStatus::Converged) throw std::runtime_error("sparse eigenanalysis: " + r.message);
  return out;
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

Frequencies subproblemModes(const solvers::Partition& p, const core::LinearizedSystem& sys, int nev) {
  const Eigen::MatrixXd Ks = solvers::restrictToSmall(p, sys.K + sys.G), Ms = solvers::restrictToSmall(p, sys.M);
  if (nev > Ks.rows())
    throw std::invalid_argument("asked for " + std::to_string(nev) + " modes, the q_s subproblem has " +
                                std::to_string(Ks.rows()));
  solvers::EigenOptions eo;
  eo.nev = nev;
  const solvers::EigenResult r = nev >= Ks.rows() ? solvers::solveDense(Ks, Ms, eo) : solvers::solveLowest(Ks, Ms, eo);
  if (r.status != solvers::EigenStatus::Converged) throw std::runtime_error("q_s eigenproblem: " + r.message);
  Frequencies out;
  out.lambda = r.lambda;
  out.omega = r.omega;
  out.method = r.method;
  out.modes.setZero(p.size(), r.vectors.cols());
  for (int i = 0; i < p.nSmall(); ++i) out.modes.row(p.small[i]) = r.vectors.row(i);
  return out;
}

InitialModes initialModes(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis, int nev,
                          const ReferencePoint* reference) {
  InitialModes out;
  core::Linearization lin(model, basis);
  lin.initialRest(out.system, out.eta);
  lin.dofs(out.eta, out.q);
  out.x = lin.kinematics().x();
  out.frequencies = naturalFrequencies(lin, out.system, std::min<int>(nev, lin.size()));
  if (reference)
    out.participation = modalParticipation(model, out.x, lin.transfer(), out.system.M, out.frequencies.modes,
                                           referencePosition(model, out.x, *reference));
  return out;
}

HighestMode highestMode(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis, int maxDofs) {
  HighestMode h;
  core::Linearization lin(model, basis);
  if (lin.size() == 0 || lin.size() > maxDofs) return h;
  core::LinearizedSystem sys;
  Eigen::VectorXd eta;
  lin.initialRest(sys, eta);
  const Eigen::MatrixXd K = 0.5 * ((sys.K + sys.G) + (sys.K + sys.G).transpose());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, sys.M);
  if (es.info() != Eigen::Success) return h;
  const Eigen::VectorXd lambda = es.eigenvalues();
  h.found = true;
  h.omegaMax = std::sqrt(std::max(0.0, lambda.maxCoeff()));
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    if (lambda[i] > 1e-9 * lambda.maxCoeff()) {
      h.omegaMin = std::sqrt(lambda[i]);
      break;
    }
  h.modeQ = es.eigenvectors().col(lambda.size() - 1);
  if (basis) h.modeQ = *basis * h.modeQ;
  return h;
}

double highestFrequencyAtRest(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis, int maxDofs) {
  core::Linearization lin(model, basis);
  if (lin.size() == 0 || lin.size() > maxDofs) return 0.0;
  core::LinearizedSystem sys;
  Eigen::VectorXd eta;
  lin.initialRest(sys, eta);
  const Eigen::MatrixXd K = 0.5 * ((sys.K + sys.G) + (sys.K + sys.G).transpose());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, sys.M, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return 0.0;
  return std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff()));
}

io::CsvTable modesTable(const Frequencies& fr) {
  io::CsvTable t;
  t.columns = {"mode", "f_Hz", "omega_rad_s"};
  for (Eigen::Index i = 0; i < fr.omega.size(); ++i)
    t.rows.push_back({static_cast<double>(i + 1), fr.omega[i] / (2 * M_PI), fr.omega[i]});
  return t;
}

}  // namespace flexmb::analysis
