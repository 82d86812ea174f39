#include "io/formats/OriginalResults.hpp"

#include <set>
#include <string>

#include "io/formats/ResultWriter.hpp"

namespace flexmb::io {

const core::Model& resultModel(const core::Model& model) { return model.unrefined ? *model.unrefined : model; }

core::Trajectory originalTrajectory(const core::Model& model, const core::Trajectory& traj) {
  if (!model.unrefined) return traj;
  const Eigen::Index nx = model.unrefined->nx, ne = model.unrefined->ne;
  core::Trajectory out = traj;
  for (core::StateOutputs& s : out.states) {
    for (Eigen::VectorXd* v : {&s.x, &s.xd, &s.xdd, &s.userForces})
      if (v->size() > nx) v->conservativeResize(nx);
    for (Eigen::VectorXd* v : {&s.e, &s.ed, &s.edd, &s.sig})
      if (v->size() > ne) v->conservativeResize(ne);
  }
  return out;
}

namespace {

// A SPACAR-ordered vector of the refined model as the original's: to model order, the leading
// entries, back to the original's SPACAR order.
struct Reorder {
  SpacarLayout from, to;
  Eigen::VectorXd x(const Eigen::VectorXd& v) const {
    if (!v.size()) return v;
    Eigen::VectorXd out(to.xOrder.size());
    for (std::size_t i = 0; i < to.xOrder.size(); ++i) out[static_cast<Eigen::Index>(i)] = v[from.xPos[to.xOrder[i]]];
    return out;
  }
  Eigen::VectorXd e(const Eigen::VectorXd& v) const {
    if (!v.size()) return v;
    Eigen::VectorXd out(to.eOrder.size());
    for (std::size_t i = 0; i < to.eOrder.size(); ++i) out[static_cast<Eigen::Index>(i)] = v[from.ePos[to.eOrder[i]]];
    return out;
  }
};

}  // namespace

SpacarResults originalSpacarResults(const core::Model& model, const SpacarResults& results) {
  if (!model.unrefined) return results;
  const Reorder r{spacarLayout(model), spacarLayout(*model.unrefined)};
  SpacarResults out;
  out.mode = results.mode;
  out.time = results.time;
  out.nsteps = results.nsteps, out.nfailed = results.nfailed, out.nfevals = results.nfevals;
  out.completed = results.completed;
  out.stopReason = results.stopReason;
  out.warning = results.warning;
  out.stateSpace = results.stateSpace;
  out.extraSbd = results.extraSbd;
  out.steps.reserve(results.steps.size());
  for (const SpacarStep& s : results.steps) {
    SpacarStep o;
    o.x = r.x(s.x), o.xd = r.x(s.xd), o.xdd = r.x(s.xdd), o.fxt = r.x(s.fxt);
    o.fx = r.x(s.fx), o.fxgrav = r.x(s.fxgrav);
    o.e = r.e(s.e), o.ed = r.e(s.ed), o.edd = r.e(s.edd), o.sig = r.e(s.sig);
    o.freq = s.freq;
    if (s.modex.size()) {
      o.modex.resize(static_cast<Eigen::Index>(r.to.xOrder.size()), s.modex.cols());
      for (Eigen::Index c = 0; c < s.modex.cols(); ++c) o.modex.col(c) = r.x(s.modex.col(c));
    }
    out.steps.push_back(std::move(o));
  }
  return out;
}

CsvTable originalColumns(const core::Model& model, CsvTable table) {
  if (!model.unrefined) return table;
  const core::Model& original = *model.unrefined;
  std::set<std::string> added;
  const std::vector<std::string> x = coordinateColumnNames(model), e = deformationColumnNames(model);
  added.insert(x.begin() + original.nx, x.end());
  added.insert(e.begin() + original.ne, e.end());
  for (std::size_t k = original.elements.size(); k < model.elements.size(); ++k)
    added.insert(model.elements[k].type->keyword + std::to_string(model.elements[k].label));
  // A column's quantity without the table's prefix ("F.", "x:", "stress_" ...).
  auto isAdded = [&](const std::string& name) {
    if (added.count(name)) return true;
    for (const char* prefix : {"F.", "M.", "R.", "x:", "xd:", "xdd:", "e:", "ed:", "edd:", "sig:", "stress_"}) {
      const std::string p(prefix);
      if (name.size() > p.size() && name.compare(0, p.size(), p) == 0 && added.count(name.substr(p.size())))
        return true;
    }
    return false;
  };
  std::vector<bool> keep(table.columns.size());
  CsvTable out;
  for (std::size_t c = 0; c < table.columns.size(); ++c)
    if ((keep[c] = !isAdded(table.columns[c]))) out.columns.push_back(table.columns[c]);
  out.rows.reserve(table.rows.size());
  for (const auto& row : table.rows) {
    std::vector<double> kept;
    kept.reserve(out.columns.size());
    for (std::size_t c = 0; c < row.size() && c < keep.size(); ++c)
      if (keep[c]) kept.push_back(row[c]);
    out.rows.push_back(std::move(kept));
  }
  return out;
}

}  // namespace flexmb::io
