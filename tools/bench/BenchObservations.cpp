// bench.md's observations, generated from the measurements: the reduced models against the full
// one per model, each implicit integrator against ode45 (the paper's models), the integrators on the
// guidance with 20 PLBEAMs per leaf, and the right-hand side's growth.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tools/bench/BenchSections.hpp"
#include "tools/bench/BenchSupport.hpp"

namespace flexmb::bench {

namespace {

// The converged point of a method at a tolerance.
const Point* find(const std::vector<Point>& points, const std::string& model, const std::string& method,
                  const std::string& integ, double tol) {
  for (const Point& p : points)
    if (p.model == model && p.method == method && p.integrator == integ && p.relTol == tol && p.status == "ok")
      return &p;
  return nullptr;
}

// The cheapest converged point of a method with error <= eps.
const Point* cheapest(const std::vector<Point>& points, const std::string& model, const std::string& method,
                      const std::string& integ, double eps) {
  const Point* best = nullptr;
  for (const Point& p : points)
    if (p.model == model && p.method == method && p.integrator == integ && p.status == "ok" && p.error <= eps &&
        (!best || p.wall < best->wall))
      best = &p;
  return best;
}

std::string shortTitle(const CaseSpec& cs) { return cs.title.substr(0, cs.title.find(" (")); }

// Below which error the best reduced model stops being the cheapest way there.
void crossover(std::ostream& o, const std::vector<Point>& points, const CaseSpec& cs, const std::string& best,
               double bestFloor) {
  const Point* rp = cheapest(points, cs.key, best, "ode45", 1.5 * bestFloor);
  const Point* fp = cheapest(points, cs.key, "full", "ode45", 1.5 * bestFloor);
  const Point* cp = nullptr;  // the cheapest implicit variant there
  for (const CvodeVariant& v : kCvode)
    if (const Point* c = cheapest(points, cs.key, "full", v.name, 1.5 * bestFloor); c && (!cp || c->wall < cp->wall))
      cp = c;
  o << "; for any error above " << sci(bestFloor, 1) << " " << best << " (" << secText(rp->wall) << " s) is ";
  if (fp)
    o << fmt("%.0f", fp->wall / rp->wall) << "x faster than the full model with ode45";
  else
    o << "the only method within the sweep's budget";
  if (cp)
    o << " and "
      << (cp->wall >= rp->wall ? fmt("%.0f", cp->wall / rp->wall) + "x faster than"
                               : fmt("%.1f", rp->wall / cp->wall) + "x slower than")
      << " the full model with the cheapest CVODE variant there (" << cp->integrator << ", " << secText(cp->wall)
      << " s)";
  o << ", and only below that error does the full model win.";
}

// The reduced models against the full one at ode45's default RelTol 1e-3.
std::string caseObservation(const std::vector<Point>& points, const CaseSpec& cs) {
  const Point* fd = find(points, cs.key, "full", "ode45", 1e-3);
  if (!fd) return "";
  std::vector<std::string> reduced;
  for (const Point& p : points)
    if (p.model == cs.key && p.method != "full" && std::find(reduced.begin(), reduced.end(), p.method) == reduced.end())
      reduced.push_back(p.method);
  // Evaluation range of full ode45 (stability-bounded steps show as a flat count).
  long feMin = 0, feMax = 0;
  double tolLo = 0, tolHi = 0;
  for (const Point& p : points)
    if (p.model == cs.key && p.method == "full" && p.integrator == "ode45" && p.status == "ok") {
      if (!feMin || p.fevals < feMin) feMin = p.fevals;
      if (p.fevals > feMax) feMax = p.fevals;
      tolHi = std::max(tolHi, p.relTol);
      tolLo = tolLo ? std::min(tolLo, p.relTol) : p.relTol;
    }
  double sMin = INFINITY, sMax = 0, eMin = INFINITY, eMax = 0, bestFloor = INFINITY;
  std::string nMin, nMax, best;
  for (const std::string& rm : reduced) {
    double floorErr = INFINITY;
    for (const Point& p : points)
      if (p.model == cs.key && p.method == rm && p.status == "ok") floorErr = std::min(floorErr, p.error);
    if (floorErr < bestFloor) bestFloor = floorErr, best = rm;
    if (const Point* rp = find(points, cs.key, rm, "ode45", 1e-3)) {
      sMin = std::min(sMin, fd->wall / rp->wall), sMax = std::max(sMax, fd->wall / rp->wall);
      if (rp->error < eMin) eMin = rp->error, nMin = rm;
      if (rp->error > eMax) eMax = rp->error, nMax = rm;
    }
  }
  const bool one = reduced.size() == 1;
  std::ostringstream o;
  o << "- **" << cs.title << ".** At ode45's default RelTol 1e-3 ";
  if (one)
    o << reduced[0] << " runs " << fmt("%.0f", sMin) << "x faster";
  else
    o << "the reduced models run " << fmt("%.0f", sMin) << "-" << fmt("%.0f", sMax) << "x faster";
  o << " than the full model (" << secText(fd->wall) << " s; "
    << (feMax < 3 * feMin ? "its ode45 step is bounded by stability, not accuracy: " : "") << withThousands(feMin)
    << "-" << withThousands(feMax) << " evaluations from RelTol " << tolText(tolHi) << " to " << tolText(tolLo)
    << ") but level" << (one ? "s" : "") << " off at " << (one ? "its" : "their") << " reduction error";
  if (one)
    o << " of " << sci(eMin, 1);
  else
    o << ", from " << sci(eMax, 1) << " (" << nMax << ") down to " << sci(eMin, 1) << " (" << nMin << ")";
  if (std::isfinite(bestFloor)) crossover(o, points, cs, best, bestFloor);
  o << "\n";
  return o.str();
}

// The variant's time against the reduced models' (ratio range lo ... hi of its time / reduced time).
std::string reducedComparison(double lo, double hi) {
  if (!std::isfinite(lo)) return "";
  const std::string tail = " the reduced models (ode45) at the same tolerance";
  if (lo > 1) return ", and it remains " + fmt("%.0f", lo) + "-" + fmt("%.0f", hi) + "x slower than" + tail;
  if (hi < 1) return ", and it is " + fmt("%.1f", 1 / hi) + "-" + fmt("%.1f", 1 / lo) + "x faster than" + tail;
  return ", and it takes " + fmt("%.2f", lo) + "-" + fmt("%.1f", hi) + " times the time of" + tail;
}

// An implicit variant against ode45 on the full models at RelTol 1e-3.
std::string variantObservation(const WorkPrecisionResults& wp, const CvodeVariant& v) {
  const std::vector<Point>& points = wp.points;
  std::string fe, sp, acc, failedAt, steps, perStep, jac;
  bool moreSteps = true, fewerSteps = true;
  double slowMin = INFINITY, slowMax = 0;  // its time / reduced-model time at RelTol 1e-3
  for (const CaseSpec& cs : wp.cases) {
    if (!cs.paper) continue;
    const Point* fd = find(points, cs.key, "full", "ode45", 1e-3);
    const Point* cd = find(points, cs.key, "full", v.name, 1e-3);
    if (!fd || !cd) continue;
    for (const Point& p : points)
      if (p.model == cs.key && p.method != "full" && p.relTol == 1e-3 && p.status == "ok") {
        slowMin = std::min(slowMin, cd->wall / p.wall);
        slowMax = std::max(slowMax, cd->wall / p.wall);
      }
    const auto join = [](const std::string& s, const char* sep) { return s.empty() ? s : s + sep; };
    fe = join(fe, " / ") + fmt("%.1f", double(fd->fevals) / cd->fevals) + "x";
    sp = join(sp, " / ") + (cd->wall <= fd->wall ? fmt("%.1f", fd->wall / cd->wall) + "x faster"
                                                 : fmt("%.1f", cd->wall / fd->wall) + "x slower");
    acc = join(acc, ", ") + shortTitle(cs) + " " + sci(cd->error, 1) + " against " + sci(fd->error, 1);
    moreSteps = moreSteps && cd->nsteps >= 0.9 * fd->nsteps;
    fewerSteps = fewerSteps && cd->nsteps < 0.9 * fd->nsteps;
    steps = join(steps, " / ") + withThousands(cd->nsteps) + " against " + withThousands(fd->nsteps);
    perStep = join(perStep, " / ") + fmt("%.1f", double(cd->fevals) / cd->nsteps) + " against " +
              fmt("%.1f", double(fd->fevals) / fd->nsteps);
    jac = join(jac, " / ") + withThousands(cd->njac) + " Jacobians" +
          (cd->jacFevals > 0 ? " taking " + withThousands(cd->jacFevals) + " of the evaluations" : std::string());
  }
  if (fe.empty()) return "";
  for (const Point& p : points)
    if (p.integrator == v.name && p.status == "failed" &&
        std::any_of(wp.cases.begin(), wp.cases.end(), [&](const CaseSpec& c) { return c.paper && c.key == p.model; }))
      failedAt += (failedAt.empty() ? "" : ", ") + p.model + " RelTol " + tolText(p.relTol);
  std::string names;
  for (const CaseSpec& cs : wp.cases)
    if (cs.paper) names += (names.empty() ? "" : " / ") + shortTitle(cs);
  std::ostringstream o;
  o << "- **" << v.name << "** (" << names << ", RelTol 1e-3) needs " << fe
    << " fewer evaluations than ode45 on the full model (" << jac << ") and is " << sp
    << (moreSteps    ? ": it takes as many steps or more ("
        : fewerSteps ? ": it takes fewer steps ("
                     : ": it takes (")
    << steps << " steps) with fewer evaluations per step (" << perStep << "); its error at equal tolerance is " << acc
    << (failedAt.empty() ? "" : "; it stopped at " + failedAt + " (see the table)")
    << reducedComparison(slowMin, slowMax) << ".\n";
  return o.str();
}

// The refined guidance: where full ode45 stopped (or what it cost), each method at RelTol 1e-3, and
// per error level the cheapest run of each method that reaches it.
std::string refinedObservation(const std::vector<Point>& points, const CaseSpec& cs) {
  std::vector<std::string> series;  // "method (integrator)" in the order of the sweeps
  for (const Point& p : points) {
    const std::string label = p.method == "full" ? p.integrator : p.method + " (" + p.integrator + ")";
    if (p.model == cs.key && std::find(series.begin(), series.end(), label) == series.end()) series.push_back(label);
  }
  auto labelOf = [](const Point& p) {
    return p.method == "full" ? p.integrator : p.method + " (" + p.integrator + ")";
  };
  std::ostringstream o;
  o << "- **" << shortTitle(cs) << ".** ";
  for (const Point& p : points)
    if (p.model == cs.key && p.method == "full" && p.integrator == "ode45") {
      o << "The full model with ode45 at RelTol " << tolText(p.relTol) << ": ";
      if (p.completed())
        o << secText(p.wall) << " s, " << withThousands(p.fevals) << " evaluations (its step is bound by stability), "
          << "error " << sci(p.error, 1) << ". ";
      else
        o << p.note << ". ";
      break;
    }
  std::string at3;
  for (const Point& p : points)
    if (p.model == cs.key && p.relTol == 1e-3 && p.completed() && !(p.method == "full" && p.integrator == "ode45"))
      at3 += (at3.empty() ? "" : ", ") + labelOf(p) + " " + secText(p.wall) + " s (error " + sci(p.error, 1) + ")";
  if (!at3.empty()) o << "At RelTol 1e-3: " << at3 << ".";
  const Point* g3 = find(points, cs.key, "full", "generalized-alpha", 1e-3);
  const Point* a3 = find(points, cs.key, "full", "auto", 1e-3);
  if (g3 && a3 && g3->fevals == a3->fevals) o << " auto ran generalized-alpha from the start (the same evaluations).";
  for (const Point& p : points)  // the other runs that stopped (BDF2 at tight tolerances)
    if (p.model == cs.key && p.status == "failed" && !(p.method == "full" && p.integrator == "ode45"))
      o << " " << labelOf(p) << " at RelTol " << tolText(p.relTol) << ": " << p.note << ".";
  for (double level : {1e-3, 1e-4, 1e-5}) {
    std::vector<const Point*> best;  // the cheapest completed run of each series within the level
    for (const std::string& label : series) {
      const Point* b = nullptr;
      for (const Point& p : points)
        if (p.model == cs.key && labelOf(p) == label && p.completed() && p.error <= level && (!b || p.wall < b->wall))
          b = &p;
      if (b) best.push_back(b);
    }
    if (best.empty()) continue;
    std::sort(best.begin(), best.end(), [](const Point* a, const Point* b) { return a->wall < b->wall; });
    o << " Error <= " << tolText(level) << ": ";
    for (size_t i = 0; i < best.size(); ++i) {
      const Point& p = *best[i];
      o << (i ? ", " : "") << labelOf(p) << " " << secText(p.wall) << " s (RelTol " << tolText(p.relTol)
        << (i ? ", " + fmt("%.1f", p.wall / best[0]->wall) + "x" : std::string()) << ")";
    }
    o << ".";
  }
  for (const Point& p : points)  // the reduced model's floor
    if (p.model == cs.key && p.method != "full") {
      double floorErr = INFINITY, fastest = INFINITY;
      for (const Point& q : points)
        if (q.model == cs.key && q.method == p.method && q.completed())
          floorErr = std::min(floorErr, q.error), fastest = std::min(fastest, q.wall);
      if (std::isfinite(floorErr))
        o << " " << p.method << " levels off at its reduction error " << sci(floorErr, 1) << " (" << secText(fastest)
          << " s and up).";
      break;
    }
  o << "\n";
  return o.str();
}

}  // namespace

std::string observations(const WorkPrecisionResults& wp, const RhsScalingResults& rhs) {
  std::ostringstream md;
  for (const CaseSpec& cs : wp.cases)
    md << (cs.paper ? caseObservation(wp.points, cs) : refinedObservation(wp.points, cs));
  for (const CvodeVariant& v : kCvode) md << variantObservation(wp, v);
  const ScalingRow& first = rhs.rows.front();
  md << "- One rhs evaluation of the full model (sparse nodal saddle-point form, "
        "core/dynamics/SaddlePointAccelerations) grows with a log-log slope of "
     << fmt("%.2f", rhs.slopeAll) << " in the number of elements per flexure (" << fmt("%.2f", rhs.slopeLast)
     << " over the last three sizes) and costs " << fmt("%.2f", first.median * 1e6) << " us at " << first.dof
     << " DOF; the projected form (dense F_q^T M F_q and its Cholesky, O(nx m^2 + m^3)) costs "
     << (std::isfinite(first.projected) ? fmt("%.2f", first.projected * 1e6) : "-") << " us at " << first.dof
     << " DOF and grows with slope ~2.4-3.\n";
  return md.str();
}

}  // namespace flexmb::bench
