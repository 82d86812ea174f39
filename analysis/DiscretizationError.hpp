#pragma once
// The discretization error of a result against the converged model (issue 50), estimated from the
// model and its refinements (`--refine`, core/model/Refinement.hpp): Richardson's extrapolation with
// the observed order. A quantity Q computed on meshes with r, r1 = a r and r2 = b r parts per beam
// behaves as Q_r = Q* + C r^-p in the asymptotic range; the differences between the meshes give p
// (checked against the element's order: away from it the mesh is not in the asymptotic range, and
// the estimate says so) and C, hence the error of each mesh. docs/theory/error-estimates.md
// "Discretization error" gives the derivation and its limits.
//
// The ladder (`climbMeshLadder`) runs an analysis on finer and finer meshes until the estimate of
// the finest meets a target, or on the user's mesh and two refinements for the estimate alone.
// What one level computes (the values compared: positions of the original nodes, frequencies) and
// how it is run are the caller's (analysis/AccuracyTarget.hpp); this file knows no analysis.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace flexmb::analysis {

// The order of convergence of the beams' results in the element length (PLBEAM, BEAM: the
// deformation modes of Eq. 3 are exact for end loads; the geometric nonlinearity and the
// distributed mass converge with h^2; issue 50's 10/20/40 elements per leaf: 8.5e-3, 2.2e-3, 7.1e-4).
constexpr double kBeamOrder = 2.0;
// Eigenfrequencies in an unstressed configuration converge as h^(2(k-1)) with the cubic bending
// shapes (k = 3) and a consistent mass: 4 (the cantilever's 4-8-16 elements: observed 4.1).
constexpr double kFrequencyOrder = 4.0;

// One mesh of the ladder: `refine` parts per flexible beam, what it computed and cost.
struct MeshLevel {
  int refine = 1;
  bool ok = false;
  std::string reason;      // why it has no result (ok = false)
  Eigen::VectorXd values;  // the compared quantities, the same length on every level
  double scale = 1.0;      // what a difference is relative to (the motion, a frequency: 1 for relative values)
  double seconds = 0.0;
  // The other errors of this level's result on the same scale (the integration error of a time run;
  // 0: none): a difference between meshes below a few times it does not resolve the discretization.
  double otherError = 0.0;
  double differenceToPrevious = std::numeric_limits<double>::quiet_NaN();  // max |Q - Q_prev| / scale
  Eigen::Index largestAt = -1;                                             // the value where that difference is largest
  // The leading values that are positions, stacked per time or load step (the caller names them);
  // the rest are other quantities (-1: none are positions).
  Eigen::Index positionValues = -1;
  std::string otherUnknown;  // why otherError is not known (empty: it is)
};

struct DiscretizationEstimate {
  bool estimated = false;
  double estimate = 0.0;  // of the result of level `of`, on its scale (kRichardsonSafety included)
  int of = 0;             // the level it is about (index into levels)
  int ofRefine = 1;
  double observedOrder = std::numeric_limits<double>::quiet_NaN();  // NaN: two levels only
  double order = kBeamOrder;                                        // the order the estimate used
  double elementOrder = kBeamOrder;  // what the element's theory says (kBeamOrder, kFrequencyOrder)
  bool asymptotic = false;           // the observed order is near the element's (within kOrderBand)
  bool resolved = true;              // the meshes differ by more than their other errors
  std::vector<MeshLevel> levels;
  std::string measure;  // "of the motion (0.0833 m)", "relative (frequencies)"
  std::string note;     // why it was not estimated, or what limits it
  std::string where;    // what the estimate is largest on ("node 45 z"; empty: not named)
};

// The estimate is the extrapolated error times this (Roache's grid convergence index takes 1.25 with
// three meshes): on the guidance, the elastica and the cantilever the bare extrapolation was 0.965 to
// 1.03 of the true error, so a bare estimate falls short of the truth as often as not.
constexpr double kRichardsonSafety = 1.25;

// An observed order between the element's / kOrderBand and the element's * kOrderBand is asymptotic.
constexpr double kOrderBand = 1.6;

// The order p with (r0^-p - r1^-p) / (r1^-p - r2^-p) = d01 / d12 (r0 < r1 < r2), by bisection on
// [0.05, 12]; NaN when no order there fits (the differences do not fall as a converging mesh's do) or one is zero.
double observedOrder(double r0, double r1, double r2, double d01, double d12);

// The estimate of level `of`'s error from the levels (ascending refinement, each ok with values of
// one length): the last three give the observed order; the estimate uses the smaller of it and
// the element's order (a faster observed order may be a cancellation), at least 0.5; two levels
// use the element's order. Differences are max-norm over the values, divided by the finer level's
// scale.
DiscretizationEstimate richardsonEstimate(std::vector<MeshLevel> levels, int of, const std::string& measure,
                                          double elementOrder = kBeamOrder);

// "D = 3.1e-03 of the motion (0.0833 m) at refine 4 (observed order 1.9 from refine 1, 2, 4 ...)".
std::string describeDiscretization(const DiscretizationEstimate& e);

// How to climb: refine `start`, then finer until the estimate of the finest is at most `target`
// (NaN: the estimate alone, on start, 2 start and 4 start, of the start level), never above
// `maxRefine` parts and never starting a level predicted to end after `maxSeconds` in all.
struct LadderOptions {
  int start = 1;
  double target = std::numeric_limits<double>::quiet_NaN();
  int maxRefine = 64;
  double maxSeconds = 300.0;
  double elementOrder = kBeamOrder;
  // Called before each level with its refinement and the reason ("the estimate of refine 2, 4.1e-3,
  // misses 7.5e-4: refine 6 predicted to meet it in 0.4 s").
  std::function<void(int refine, const std::string& why)> onLevel;
};

struct LadderResult {
  DiscretizationEstimate estimate;
  int chosen = 0;        // the level whose result is the answer (index into estimate.levels)
  bool met = false;      // target given and met
  std::string stopNote;  // why the ladder stopped short of the target (empty: met, or no target)
};

// Runs `run(refine)` on the ladder's levels (see LadderOptions) and estimates. With a target, the
// next refinement is the one the order predicts to meet it (at least 1.5x the last), and the
// chosen level is the finest that ran; without, the start level.
LadderResult climbMeshLadder(const std::function<MeshLevel(int refine)>& run, const LadderOptions& options);

}  // namespace flexmb::analysis
