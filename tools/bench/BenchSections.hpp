#pragma once
// flexmb_bench's sections (tools/bench/README.md), one file each: the work-precision sweeps of the
// paper's two models (WorkPrecision.cpp), the elbow (ElbowBench.cpp), the right-hand side against
// the mesh (RhsScaling.cpp), the reduced operators (OperatorBench.cpp), the eigenanalysis
// (EigenBench.cpp), and the report: CSV and bench.md (BenchReport.cpp, BenchObservations.cpp).
#include <Eigen/Core>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "analysis/Simulation.hpp"

namespace flexmb::bench {

// The command line.
struct Options {
  bool quick = false;
  std::string out;
  std::string only;  // development: run only the sweeps whose "model method integrator" contains this
};

// The sweeps' settings (--quick: looser).
struct Settings {
  std::vector<double> tols;              // RelTol per decade
  double absFactor = 1e-3;               // AbsTol = RelTol * absFactor
  double skipAbove = 60.0;               // predicted seconds: skip this and tighter tolerances
  double hardCap = 90.0;                 // seconds: stop a running integration
  double stabilityCap = 90.0;            // seconds: the same for runs known to stall (quick: 5; settingsFor)
  double repeatBelow = 2.0;              // seconds: 3 runs (median) below, 1 above
  std::map<std::string, double> refTol;  // the references' RelTol (full model; CaseSpec::reference)
  std::vector<double> refinedTols;       // RelTol of the refined guidance's sweeps (two decades above its reference)
  std::vector<int> sizes;                // elements per flexure of the right-hand-side scaling
  int maxProjected = 160;                // the projected (dense) form up to this size
  double rhsBudget = 0.2;                // seconds of calls per timed size
};
Settings settingsFor(const Options& opt);

// ---- work-precision: the straight guidance, the manipulator and the guidance with 20 PLBEAMs per
// leaf (WorkPrecision.cpp)
struct CaseSpec {
  std::string key, title, file;
  int node = 0;        // response node
  bool xOnly = false;  // guidance: x of the rigid body's left node (6; 21 on the refined mesh); manipulator: the tip
  // The paper's models (their methods and observations as the paper's); false: the refined guidance
  // (ode45 stability-bound, the integrators and auto against MODAL-3; an observation of its own).
  bool paper = true;
  analysis::Integrator reference = analysis::Integrator::Ode45;  // the reference run's integrator
};

// One point of a sweep.
struct Point {
  std::string model, method, integrator;
  double relTol = 0, absTol = 0;
  // "ok" (completed and converged by the a-posteriori accuracy check of analysis/AccuracyCheck.hpp,
  // as simulate runs it), "not converged" (completed, but the check flags it; its error is still
  // measured and plotted), "failed", "skipped".
  std::string status;
  std::string note;  // failure reason or prediction
  bool completed() const { return status == "ok" || status == "not converged"; }
  double estimate = NAN;   // the accuracy check's estimate of the error (of the model size)
  double reduction = NAN;  // reduced runs: the reduction error estimate (of the motion)
  long fevals = 0, jacFevals = 0, nsteps = 0, nfailed = 0, njac = 0;
  double wall = NAN, error = NAN;
  int runs = 0;
  bool capped = false;  // stopped at its wall-time cap (status "failed"; the note says where)
};

// The integrators beside ode45 on the full models: CVODE's BDF with its difference-quotient
// Jacobian (orders 1-5; the bench's own run, BenchRuns.hpp), simulate's bdf with orders 1-5 and
// with its default orders 1-2 (the analytic Jacobian), and simulate's galpha.
struct CvodeVariant {
  const char* name;
  analysis::Integrator integrator;
  int bdfOrder;                      // BDF's highest order (0: not BDF)
  bool differenceQuotients = false;  // CVODE's difference-quotient Jacobian: not simulate's recipe
};
inline constexpr CvodeVariant kCvode[] = {{"CVODE-BDF DQ J", analysis::Integrator::Bdf, 5, true},
                                          {"CVODE-BDF analytic J", analysis::Integrator::Bdf, 5},
                                          {"CVODE-BDF2 analytic J", analysis::Integrator::Bdf, 2},
                                          {"generalized-alpha", analysis::Integrator::GeneralizedAlpha, 0}};

struct WorkPrecisionResults {
  std::vector<CaseSpec> cases;
  std::vector<Point> points;
  std::map<std::string, std::string> refNotes, basisNotes, svgFiles;
  std::vector<std::string> skipped;  // points predicted or measured to exceed the time limit
};
// The sweeps of both models with their SVGs; false when a reference run failed (said on stderr).
bool workPrecision(const Options& opt, const Settings& set, WorkPrecisionResults& out);

// ---- the elbow of Simo & Vu-Quoc: stiff spatial dynamics (ElbowBench.cpp)
struct ElbowPoint {
  std::string file, integrator;
  double relTol = 0, wall = NAN, error = NAN;
  long fevals = 0, njac = 0, nsteps = 0;
  std::string note;
};
struct ElbowResults {
  std::vector<ElbowPoint> points;  // empty: not run (--only)
  std::string cost;                // the iteration matrix's cost in right-hand sides
};
ElbowResults elbowFigures(const Options& opt, const Settings& set);

// ---- one right-hand side against the mesh (RhsScaling.cpp)
struct ScalingRow {
  int n = 0, dof = 0, nx = 0, calls = 0;
  double median = NAN, setup = NAN;  // the automatic form (the sparse saddle point for these models)
  double projected = NAN;            // the projected form (dense F_q^T M F_q), small sizes only
};
struct RhsScalingResults {
  std::vector<ScalingRow> rows;
  double checkDiff = NAN;  // the generated n = 5 model against datfiles/straight_guidance.dat
  double slopeAll = NAN, slopeAllDof = NAN, slopeLast = NAN, slopeLastDof = NAN;
  size_t lastFrom = 0;  // the first of the last three sizes
};
RhsScalingResults rhsScaling(const Options& opt, const Settings& set);
// The straight guidance with n PLBEAMs per flexure, as datfiles/straight_guidance.dat for n = 5.
std::string guidanceDat(int n);

// ---- the reduced operators (OperatorBench.cpp) and the eigenanalysis (EigenBench.cpp)
std::string operatorFigures(bool quick);  // printed; returns bench.md's section
void eigenFigures();

// ---- the report (BenchReport.cpp, BenchObservations.cpp)
struct Report {
  Options opt;
  Settings set;
  WorkPrecisionResults wp;
  ElbowResults elbow;
  RhsScalingResults rhs;
  std::string operatorMd;
  std::string loadBefore;  // the load average before the benchmark
  double totalSeconds = NAN;
};
std::string loadAverage();
void writeCsv(const std::string& dir, const std::vector<Point>& points, const std::vector<ScalingRow>& rows);
void writeMarkdown(const Report& r);  // bench.md
// The observations generated from the measurements (bench.md's list).
std::string observations(const WorkPrecisionResults& wp, const RhsScalingResults& rhs);

}  // namespace flexmb::bench
