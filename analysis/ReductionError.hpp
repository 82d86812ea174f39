#pragma once
// The reduction error of a reduced run (issue 32), estimated from the run itself and the full
// model, without a full run. At output times, the full model's residual of Eq. 13 at the reduced
// state, Q(q, qd, qdd) with q = V eta (the generalised forces the reduced model leaves unbalanced;
// V^T Q = 0 by Eq. 19), loads two measures of the error, both mapped to the nodal positions
// (dx = F_q dq) and relative to the run's motion (the largest displacement of any position
// coordinate from its initial value; the model size where the motion is smaller than 1e-3 of it):
// - the error the full model linearised about the reduced trajectory carries along the run,
//   M e'' + (C + D) e' + (K + G + N) e = Q(t) from e = e' = 0 (every coordinate): the omitted
//   coordinates' response, dynamics included, and a poor basis' own motion going wrong (a phase
//   error of the kept modes). The estimate is twice it (calibrated in ReductionError.cpp against
//   full references: effectivity = estimate / true error, same measure).
// - the quasi-static deflection of the coordinates V does not hold exactly, (K + G + N) dq = Q (its
//   identity columns, the large-rotation coordinates of Eq. 20, held: dq = 0 there): the residual
//   flexibility of the modes the basis leaves out. Reported, and what predicts a larger basis'
//   estimate, but not counted: without inertia it reads far too high where the stiffness in motion
//   nearly vanishes.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "core/dynamics/Trajectory.hpp"
#include "core/model/Model.hpp"

namespace flexmb::analysis {

using ReductionErrorEstimate = core::ReductionEstimate;

// The largest displacement of any position coordinate from its initial value over the run.
double motionScale(const core::Model& model, const core::Trajectory& run);

// The scale every error estimate of a run is relative to: the motion, or the model size where the
// motion is below a thousandth of it; with its words ("of the motion (0.0833)"). No unit is named:
// a .dat file's length unit is the user's (the 45-degree bend's are inches).
struct ErrorScale {
  double value = 1.0;
  std::string text;
};
ErrorScale errorScaleOf(const core::Model& model, double motion);

// The estimate for a run of `model` with basis V (nq x m), from its stored output states
// (x, xd, xdd, e, ed, edd: q, qd, qdd are read there), at most `maxSamples` output times spread over
// the run (and always its last). Never throws for a numerical failure: estimated = false with the
// reason in note.
// What an estimate found at its samples, kept to predict the estimate of a larger basis without its
// run (predictReductionError).
struct ResidualDeflections {
  std::vector<int> free;                 // the q indices not held by the basis (rows of dq, T)
  std::vector<Eigen::VectorXd> dq;       // the deflection on them, per sample
  std::vector<Eigen::MatrixXd> T, Fpos;  // K + G + N on them; F_q's position rows on them
  double scale = 1.0;                    // the run's scale, times quasi-static / carried where that is above 1
};

// The output times (indices among n) the estimate samples: all when n <= maxSamples, else every
// stride-th (evenly in time: the carried error steps over them) and the last, at most maxSamples.
constexpr int kReductionSamples = 40;
std::vector<int> reductionSamples(int n, int maxSamples = kReductionSamples);

// The error carried along the run steps over at most transportSteps output times (each one
// linearisation: the estimate's main cost). Where decidedAbove is finite, a first pass over 16 of
// the samples may decide alone that the estimate is clearly above it (a candidate basis that fails
// its target anyway: its estimate is that pass's); an estimate not decided so is the same as
// without it.
constexpr int kTransportSteps = kReductionSamples;  // the same outputs: one linearisation each
ReductionErrorEstimate estimateReductionError(const core::Model& model, const Eigen::MatrixXd& V,
                                              const core::Trajectory& run, int maxSamples = kReductionSamples,
                                              ResidualDeflections* keep = nullptr, int transportSteps = kTransportSteps,
                                              double decidedAbove = std::numeric_limits<double>::infinity());

// The estimate a basis W (with the same held coordinates, e.g. more columns of the same kind)
// would give, predicted from the deflections of another basis' run: what of each deflection W does
// not take up statically (dq - W (W^T T W)^-1 W^T T dq on the free coordinates), doubled, relative
// to the same scale (which brings it to the carried error's level where the deflections read higher). It assumes the
// run with W moves as the run behind `found` did.
double predictReductionError(const ResidualDeflections& found, const Eigen::MatrixXd& W);

// The same measure between two runs of the model (a reduced run against a full reference on the
// same output times): the largest |x_a - x_b| over the positions and times, relative to b's motion
// (or model size). NaN when the output times differ.
double positionErrorAgainst(const core::Model& model, const core::Trajectory& a, const core::Trajectory& b);

// "reduction error estimate: 3.1e-04 of the motion (0.0833 m), ..." for the screen and the manifest.
std::string describeReductionError(const ReductionErrorEstimate& e);

}  // namespace flexmb::analysis
