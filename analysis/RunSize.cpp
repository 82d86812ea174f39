#include "analysis/RunSize.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "analysis/Modes.hpp"

namespace flexmb::analysis {

namespace {
// Limits of what a run may keep in memory and the least number of steps it may need.
constexpr double kMaxSteps = 1e9;

double physicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * size : 8e9;
}

std::string bytes(double b) {
  std::ostringstream s;
  s.precision(3);
  if (b >= 1e9)
    s << b / 1e9 << " GB";
  else
    s << b / 1e6 << " MB";
  return s.str();
}

// The highest eigenfrequency at rest (analysis::highestMode) and the coordinates its mode lives in.
struct RunStiffness {
  double omegaMax = 0.0, omegaMin = 0.0;
  std::vector<std::string> where;
};
RunStiffness highestFrequency(const core::Model& model, const std::optional<Eigen::MatrixXd>& basis) {
  RunStiffness s;
  const analysis::HighestMode h = analysis::highestMode(model, basis);
  if (!h.found) return s;
  s.omegaMax = h.omegaMax;
  s.omegaMin = h.omegaMin;
  std::vector<std::pair<double, int>> w;
  for (Eigen::Index i = 0; i < h.modeQ.size(); ++i) w.emplace_back(std::abs(h.modeQ[i]), static_cast<int>(i));
  std::sort(w.rbegin(), w.rend());
  for (size_t i = 0; i < w.size() && i < 3 && w[i].first > 0.3 * w[0].first; ++i) {
    const auto& dof = model.dofs[w[i].second];
    s.where.push_back(dof.isDeformation ? model.deformationName(dof.index) : model.coordName(dof.index));
  }
  return s;
}

}  // namespace

RunSizeCheck checkRunSize(const core::Model& model, const SimulationOptions& opt) {
  RunSizeCheck c;
  const double t0 = model.settings.t0, t1 = opt.tEnd.value_or(model.settings.tEnd);
  std::ostringstream m;
  if (!(t1 > t0)) {
    m << "the end time " << t1 << " is not after the start time " << t0 << " (TIMESTEP's end time)";
    c.refusal = m.str();
    c.options = "t_end";
    return c;
  }
  const double span = t1 - t0;
  const double h = opt.maxStep.value_or(model.settings.hmax);
  if (h > 0 && span / h > kMaxSteps) {
    m << "a maximum step of " << h << " s over " << span << " s means at least " << span / h << " steps (the limit is "
      << kMaxSteps << "): raise the maximum step (HMAX)";
    c.refusal = m.str();
    c.options = "max_step";
    return c;
  }
  const long nOut = opt.intervals.value_or(model.settings.outputIntervals);
  if (nOut > 0) {
    const double values = 3.0 * model.nx + 4.0 * model.ne;
    const double memory = (nOut + 1.0) * (16.0 * values + 400.0);  // states, their copy for the .mat, overhead
    const double csv = (nOut + 1.0) * 24.0 * values;
    const double limit = 0.25 * physicalMemory();
    if (memory > limit) {
      m << nOut << " output intervals x " << values << " values would need about " << bytes(memory)
        << " of memory (the limit is a quarter of this machine's, " << bytes(limit) << ") and about " << bytes(csv)
        << " of CSV: lower the output intervals (TIMESTEP's second field)";
      c.refusal = m.str();
      c.options = "intervals";
      return c;
    }
  }
  // The explicit integrator's stability limit; an implicit integrator's step is not bounded by it.
  RunStiffness stiff;
  try {
    if (opt.integrator == Integrator::Ode45) stiff = highestFrequency(model, opt.basis);
  } catch (const std::exception&) {}
  if (stiff.omegaMax > 0) {
    const double steps = span * stiff.omegaMax / 3.3;
    // Warn when the stability limit, not the output or the accuracy, sets the step: many more steps
    // than output intervals.
    if (steps > 1e4 && steps > 20.0 * std::max(1L, nOut)) {
      std::ostringstream w;
      w << "the highest eigenfrequency, " << stiff.omegaMax / (2 * M_PI)
        << " Hz, limits the explicit integrator's step to about " << 3.3 / stiff.omegaMax << " s: at least " << steps
        << " steps for " << span << " s. It lives in ";
      for (size_t i = 0; i < stiff.where.size(); ++i) w << (i ? ", " : "") << stiff.where[i];
      w << ". A reduced model removes it (reduce, then simulate with that basis), the implicit integrators "
           "galpha and bdf step over it (auto starts galpha where it bounds ode45), or make those deformations rigid.";
      c.warning = w.str();
    }
    if (steps > kMaxSteps) {
      m << steps << " steps are more than the limit " << kMaxSteps
        << ": reduce the model, shorten the run or use the integrator galpha or bdf";
      c.refusal = m.str();
      c.options = "integrator,t_end";
    }
  }
  return c;
}

}  // namespace flexmb::analysis
