// Sparse eigenanalysis (paper Eq. 21 on the constrained nodal pencil, ARPACK shift-invert on
// [K - sigma M, C^T; C, 0]) against the dense oracle (Kbar + Gbar, Mbar in the independent
// coordinates): eigenvalues, eigenvector residuals in q, mass normalisation, modes in x = F_q v.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <string>

#include "analysis/Statics.hpp"
#include "core/linearization/Linearization.hpp"
#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

// Planar chain of n PLBEAMs along +x, clamped at node 1, bending and elongation dynamic, a tip load
// that bends it (geometric stiffness) and gravity.
std::string chain(int n, double fy) {
  std::ostringstream s;
  s.precision(17);
  for (int k = 1; k <= n; ++k)
    s << "PLBEAM " << k << " " << k << " " << 1000 + k << " " << k + 1 << " " << 1001 + k << "\n";
  for (int k = 1; k <= n + 1; ++k) s << "X " << k << " " << 1.0 * (k - 1) / n << " 0\n";
  s << "FIX 1\nFIX 1001\n";
  for (int k = 1; k <= n; ++k) s << "DYNE " << k << " 1 2 3\n";
  s << "END\nHALT\n";
  for (int k = 1; k <= n; ++k) s << "EM " << k << " 0.5\nESTIFF " << k << " 1e5 2.0\n";
  if (fy != 0) s << "DELXF " << n + 1 << " 0 " << fy << "\n";
  s << "ITERSTEP 50 1\nEND\nEND\n";
  return s.str();
}

struct Compared {
  double maxRelLambda = 0.0, maxResidual = 0.0, maxNorm = 0.0, maxNodal = 0.0;
};

// Both paths on the same linearisation; returns the worst differences.
Compared compare(const core::Model& m, int nev, const Eigen::VectorXd* extraLoad, const std::string& what) {
  core::Linearization lin(m);
  const double t = m.settings.t0;
  Eigen::VectorXd eta = lin.kinematics().initialDofs(), f;
  lin.kinematics().solvePositions(t, eta);
  lin.appliedForces(t, 1.0, f);
  if (extraLoad) f += *extraLoad;
  core::LinearizedSystem sys;
  lin.atRest(t, eta, f, sys, true);
  nev = std::min(nev, lin.size() - 1);
  const analysis::Frequencies d = analysis::naturalFrequencies(lin, sys, nev, analysis::EigenPath::Dense);
  const analysis::Frequencies s = analysis::naturalFrequencies(lin, sys, nev, analysis::EigenPath::Sparse);
  EXPECT_EQ(s.method, "sparse-constrained") << what << ": the sparse path ran (no fallback)";
  EXPECT_EQ(s.lambda.size(), d.lambda.size()) << what;
  Compared c;
  if (s.lambda.size() != d.lambda.size()) return c;
  const Eigen::MatrixXd A = sys.K + sys.G;
  const double top = d.lambda.cwiseAbs().maxCoeff();
  double rawRel = 0.0;
  for (Eigen::Index i = 0; i < d.lambda.size(); ++i) {
    const double ref = std::max(std::abs(d.lambda[i]), 1e-8 * top);  // rigid modes: against the spectrum
    // The dense oracle's eigenvalue refined by the Rayleigh quotient of its own eigenvector (error
    // quadratic in the vector's): the dense QR-type solver's absolute error eps*||A|| is large
    // against the lowest eigenvalue of a stiff pencil (axial against bending stiffness).
    const Eigen::VectorXd u = d.modes.col(i);
    const double rq = u.dot(A * u) / u.dot(sys.M * u);
    rawRel = std::max(rawRel, std::abs(s.lambda[i] - d.lambda[i]) / ref);
    c.maxRelLambda = std::max(c.maxRelLambda, std::abs(s.lambda[i] - rq) / ref);
    // The sparse mode in q solves the dense pencil (the oracle) and is mass normalised.
    const Eigen::VectorXd v = s.modes.col(i);
    const Eigen::VectorXd Av = A * v, Mv = sys.M * v;
    const double res = (Av - s.lambda[i] * Mv).norm() /
                       std::max(Av.norm(), std::abs(s.lambda[i]) * Mv.norm() + 1e-8 * top * Mv.norm());
    c.maxResidual = std::max(c.maxResidual, res);
    c.maxNorm = std::max(c.maxNorm, std::abs(v.dot(Mv) - 1.0));
    // ... and its nodal shape is F_q v.
    const Eigen::VectorXd x = lin.transfer() * v;
    c.maxNodal = std::max(c.maxNodal, (s.nodalModes.col(i) - x).norm() / std::max(x.norm(), 1e-300));
  }
  std::printf("  %-34s m = %4d  max rel dlambda %.2e (raw dense %.2e)  residual %.2e  |v'Mv-1| %.2e  nodal %.2e\n",
              what.c_str(), lin.size(), c.maxRelLambda, rawRel, c.maxResidual, c.maxNorm, c.maxNodal);
  return c;
}
}  // namespace

TEST(SparseEigen, AgreesWithDenseOnPlanarModels) {
  for (const std::string file : {"cantilever.dat", "portal.dat", "straight_guidance.dat", "manipulator.dat",
                                 "slider_crank_s95.dat", "tests/fourbar.dat"}) {
    core::Model m = io::readDatFile(dat(file));
    m.settings.kinematicTol = 1e-15;
    if (m.numDofs() < 2) continue;
    // Extra dead loads on every coordinate: reaction stresses and a geometric stiffness everywhere.
    Eigen::VectorXd extra = 1e-3 * Eigen::VectorXd::LinSpaced(m.nx, -3.0, 5.0);
    const Compared c = compare(m, 6, &extra, file);
    EXPECT_LT(c.maxRelLambda, 1e-9) << file;
    EXPECT_LT(c.maxResidual, 1e-8) << file;
    EXPECT_LT(c.maxNorm, 1e-8) << file;
    EXPECT_LT(c.maxNodal, 1e-7) << file;
  }
}

TEST(SparseEigen, AgreesWithDenseOnALoadedChain) {
  const core::Model m = io::readDatString(chain(60, -0.5), "chain.dat");
  const Compared c = compare(m, 10, nullptr, "chain of 60 PLBEAMs, tip load");
  // The dense oracle's Kbar is exact here (all deformations are DYNE: E_q's rows are unit rows,
  // Linearization takes Kbar = S through them), so this is the nodal sparse path's own round-off:
  // of the order of eps times the axial-to-bending stiffness ratio 5e4 times the number of elements (1.8e-9; against
  // the nodal projection F^T K_x F, which shares that round-off, it was 1.8e-10).
  EXPECT_LT(c.maxRelLambda, 5e-9);
  EXPECT_LT(c.maxResidual, 1e-8);
  EXPECT_LT(c.maxNorm, 1e-8);
  EXPECT_LT(c.maxNodal, 1e-7);
}

TEST(SparseEigen, AgreesWithDenseOnTheSpatialPivot) {
  core::Model m = io::readDatFile(dat("spatial/cross_spring_pivot_coarse.dat"));
  const Compared c = compare(m, 6, nullptr, "cross-spring pivot (coarse)");
  // Spatial leaves: axial over bending stiffness ~1e6, so both pencils carry rounding of that size
  // relative to the lowest eigenvalue; the agreement asked for is still 1e-9.
  EXPECT_LT(c.maxRelLambda, 1e-9);
  EXPECT_LT(c.maxResidual, 1e-8);
  EXPECT_LT(c.maxNorm, 1e-8);
  EXPECT_LT(c.maxNodal, 1e-6);
}
