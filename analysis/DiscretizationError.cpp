#include "analysis/DiscretizationError.hpp"

#include <algorithm>
#include <cmath>

#include "text/NumberText.hpp"

namespace flexmb::analysis {

namespace {
// A difference between meshes below this many times their other errors (integration) does not
// resolve the discretization: two runs' integration errors differ by up to their sum.
constexpr double kResolvedFactor = 2.0;
// The slowest order an estimate assumes (an observed order below it, or differences that do not
// fall, are taken as it: error = 2.4 x the last difference at doubling).
constexpr double kSlowestOrder = 0.5;
// A refinement is chosen this much finer than the order predicts for the target (the prediction is
// an extrapolation).
constexpr double kRefineMargin = 1.15;
// The next level is at least this much finer than the last (smaller steps only add runs).
constexpr double kSmallestStep = 1.5;

double errorOfLevel(const std::vector<MeshLevel>& levels, int of, int pair, double p) {
  const double ra = levels[static_cast<size_t>(pair - 1)].refine, rb = levels[static_cast<size_t>(pair)].refine;
  const double d = levels[static_cast<size_t>(pair)].differenceToPrevious;
  const double c = d / (std::pow(ra, -p) - std::pow(rb, -p));
  return c * std::pow(static_cast<double>(levels[static_cast<size_t>(of)].refine), -p);
}

std::string refineList(const std::vector<MeshLevel>& levels, size_t from) {
  std::string s;
  for (size_t k = from; k < levels.size(); ++k) s += (k > from ? ", " : "") + std::to_string(levels[k].refine);
  return s;
}
}  // namespace

double observedOrder(double r0, double r1, double r2, double d01, double d12) {
  if (!(d01 > 0.0) || !(d12 > 0.0) || !(r0 < r1 && r1 < r2)) return std::nan("");
  auto ratio = [&](double p) { return (std::pow(r0, -p) - std::pow(r1, -p)) / (std::pow(r1, -p) - std::pow(r2, -p)); };
  const double want = d01 / d12;
  double lo = 0.05, hi = 12.0;  // the ratio grows with p
  if (ratio(lo) > want || ratio(hi) < want) return std::nan("");
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ratio(mid) < want ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

DiscretizationEstimate richardsonEstimate(std::vector<MeshLevel> levels, int of, const std::string& measure,
                                          double elementOrder) {
  DiscretizationEstimate e;
  e.elementOrder = elementOrder;
  e.measure = measure;
  e.of = of;
  const int n = static_cast<int>(levels.size());
  for (int k = 1; k < n; ++k) {
    MeshLevel& b = levels[static_cast<size_t>(k)];
    const MeshLevel& a = levels[static_cast<size_t>(k - 1)];
    if (!a.ok || !b.ok || a.values.size() != b.values.size() || b.values.size() == 0) continue;
    b.differenceToPrevious = (b.values - a.values).cwiseAbs().maxCoeff(&b.largestAt) / (b.scale > 0.0 ? b.scale : 1.0);
  }
  e.levels = levels;
  if (of < 0 || of >= n) return e.note = "no such level", e;
  e.ofRefine = levels[static_cast<size_t>(of)].refine;
  const int pair = std::max(of, 1);
  if (n < 2 || pair >= n || std::isnan(levels[static_cast<size_t>(pair)].differenceToPrevious)) {
    e.note = "needs two meshes that both computed a result";
    return e;
  }
  e.order = elementOrder;
  if (n >= 3 && !std::isnan(levels[static_cast<size_t>(n - 2)].differenceToPrevious)) {
    const MeshLevel &l0 = levels[static_cast<size_t>(n - 3)], &l1 = levels[static_cast<size_t>(n - 2)],
                    &l2 = levels[static_cast<size_t>(n - 1)];
    e.observedOrder = observedOrder(l0.refine, l1.refine, l2.refine, l1.differenceToPrevious, l2.differenceToPrevious);
    e.asymptotic = !std::isnan(e.observedOrder) && e.observedOrder >= elementOrder / kOrderBand &&
                   e.observedOrder <= elementOrder * kOrderBand;
    e.order = std::isnan(e.observedOrder) ? kSlowestOrder : std::clamp(e.observedOrder, kSlowestOrder, elementOrder);
  }
  const MeshLevel &a = levels[static_cast<size_t>(pair - 1)], &b = levels[static_cast<size_t>(pair)];
  e.resolved =
      b.differenceToPrevious > kResolvedFactor * std::max(a.otherError, b.otherError) || b.differenceToPrevious == 0.0;
  e.estimate = kRichardsonSafety * errorOfLevel(levels, of, pair, e.order);
  e.estimated = true;
  if (!e.resolved)
    e.note = "refine " + std::to_string(a.refine) + " and " + std::to_string(b.refine) + " differ by " +
             text::significant(b.differenceToPrevious, 2) + ", less than " + text::shortest(kResolvedFactor) +
             "x their integration error (" + text::significant(std::max(a.otherError, b.otherError), 2) +
             "): the discretization is not resolved; a tighter tolerance resolves it";
  else if (n < 3)
    e.note = "order not observed (two meshes): the element's order " + text::shortest(elementOrder) + " assumed";
  else if (std::isnan(e.observedOrder))
    e.note = "the differences between refine " + refineList(levels, static_cast<size_t>(n - 3)) +
             " do not fall as a converging mesh's do: the meshes are not in the asymptotic range (order " +
             text::shortest(kSlowestOrder) + " assumed)";
  else if (!e.asymptotic)
    e.note = "observed order " + text::significant(e.observedOrder, 2) + " is not near the element's " +
             text::shortest(elementOrder) + ": the meshes are not in the asymptotic range";
  return e;
}

std::string describeDiscretization(const DiscretizationEstimate& e) {
  if (!e.estimated) return "not estimated: " + e.note;
  std::string s = text::significant(e.estimate, 2) + " " + e.measure +
                  (e.where.empty() ? "" : ", largest at " + e.where) + " at refine " + std::to_string(e.ofRefine) +
                  " (Richardson from refine " + refineList(e.levels, 0) + ", differences";
  for (size_t k = 1; k < e.levels.size(); ++k)
    if (!std::isnan(e.levels[k].differenceToPrevious)) {
      s.push_back(' ');
      s.append(text::significant(e.levels[k].differenceToPrevious, 2));
    }
  if (!std::isnan(e.observedOrder)) {
    s.append("; observed order ").append(text::significant(e.observedOrder, 3));
    if (e.asymptotic) s.append(", near the element's ").append(text::shortest(e.elementOrder));
  }
  s.append("; order ").append(text::significant(e.order, 3)).append(" used)");
  if (!e.note.empty()) s.append(": ").append(e.note);
  return s;
}

namespace {
// The time of a run at `refine` from the last two levels' (seconds ~ refine^a, a in [1, 3]; 1.5
// from one level).
double predictSeconds(const std::vector<MeshLevel>& levels, int refine) {
  const MeshLevel& last = levels.back();
  double a = 1.5;
  if (levels.size() >= 2) {
    const MeshLevel& prev = levels[levels.size() - 2];
    if (prev.seconds > 0.0 && last.seconds > 0.0 && prev.refine != last.refine)
      a = std::clamp(std::log(last.seconds / prev.seconds) / std::log(double(last.refine) / prev.refine), 1.0, 3.0);
  }
  return last.seconds * std::pow(double(refine) / last.refine, a);
}

// The refinement the order predicts to meet the target from the finest level's estimate, and its
// time from the growth of the last two levels' (seconds ~ refine^a, a in [1, 3]).
struct NextLevel {
  int refine = 0;
  double seconds = 0.0;
};
NextLevel predictNext(const DiscretizationEstimate& e, double target) {
  const MeshLevel& last = e.levels.back();
  const double p = e.order;
  const double want = last.refine * std::pow(e.estimate / target, 1.0 / p) * kRefineMargin;
  NextLevel next;
  next.refine = static_cast<int>(std::ceil(std::max(want, kSmallestStep * last.refine)));
  next.seconds = predictSeconds(e.levels, next.refine);
  return next;
}
}  // namespace

LadderResult climbMeshLadder(const std::function<MeshLevel(int refine)>& run, const LadderOptions& options) {
  LadderResult out;
  std::vector<MeshLevel> levels;
  double spent = 0.0;
  auto runLevel = [&](int refine, const std::string& why) {
    if (options.onLevel) options.onLevel(refine, why);
    MeshLevel l = run(refine);
    l.refine = refine;
    spent += l.seconds;
    levels.push_back(std::move(l));
    return levels.back().ok;
  };
  const bool estimateOnly = std::isnan(options.target);
  if (!runLevel(options.start, "the model's mesh")) {
    out.estimate.levels = levels;
    out.estimate.note = "refine " + std::to_string(options.start) + ": " + levels.back().reason;
    return out;
  }
  if (estimateOnly) {
    for (int f : {2, 4}) {
      const int r = options.start * f;
      const double predicted = predictSeconds(levels, r);
      if (r > options.maxRefine) break;
      if (spent + predicted > options.maxSeconds) {
        out.stopNote = "refine " + std::to_string(r) + " is predicted to take " + text::significant(predicted, 2) +
                       " s, beyond the time allowed (" + text::shortest(options.maxSeconds) + " s in all)";
        break;
      }
      if (!runLevel(r, "for the estimate, predicted " + text::significant(predicted, 2) + " s")) break;
    }
    out.estimate = richardsonEstimate(levels, 0, "", options.elementOrder);
    if (levels.back().ok == false)
      out.estimate.note += "; refine " + std::to_string(levels.back().refine) + ": " + levels.back().reason;
    if (!out.stopNote.empty()) out.estimate.note += (out.estimate.note.empty() ? "" : "; ") + out.stopNote;
    return out;
  }
  int next = options.start * 2;
  std::string why = "a second mesh for the estimate";
  while (true) {
    if (next > options.maxRefine) {
      out.stopNote = "refine " + std::to_string(next) + " would be needed, above the largest allowed (" +
                     std::to_string(options.maxRefine) + ")";
      break;
    }
    if (!runLevel(next, why)) {
      out.stopNote = "refine " + std::to_string(next) + ": " + levels.back().reason;
      levels.pop_back();
      break;
    }
    out.estimate = richardsonEstimate(levels, static_cast<int>(levels.size()) - 1, "", options.elementOrder);
    // Met with the order observed (three meshes), or at once on a resolved pair whose estimate is far
    // below the target (a tenth: the order would have to be far off to miss).
    const bool observed = levels.size() >= 3;
    if (out.estimate.estimated && out.estimate.estimate <= options.target &&
        (observed || out.estimate.estimate <= 0.1 * options.target)) {
      out.met = true;
      break;
    }
    NextLevel n = predictNext(out.estimate, options.target);
    if (out.estimate.estimate <= options.target) n.refine = std::max(n.refine, levels.back().refine * 2);
    if (spent + n.seconds > options.maxSeconds) {
      out.stopNote = "refine " + std::to_string(n.refine) + " is predicted to take " + text::significant(n.seconds, 2) +
                     " s, beyond the time allowed (" + text::shortest(options.maxSeconds) + " s in all)";
      break;
    }
    why = "the estimate of refine " + std::to_string(levels.back().refine) + ", " +
          text::significant(out.estimate.estimate, 2) +
          (out.estimate.estimate <= options.target ? ", meets the target but the order is not yet observed"
                                                   : ", misses " + text::significant(options.target, 2)) +
          ": refine " + std::to_string(n.refine) + " predicted to meet it in " + text::significant(n.seconds, 2) + " s";
    next = n.refine;
  }
  if (levels.size() >= 2 && !out.met)
    out.estimate = richardsonEstimate(levels, static_cast<int>(levels.size()) - 1, "", options.elementOrder);
  else if (levels.size() < 2)
    out.estimate = richardsonEstimate(levels, 0, "", options.elementOrder);
  out.chosen = static_cast<int>(levels.size()) - 1;
  return out;
}

}  // namespace flexmb::analysis
