#include "core/kinematics/KinematicCheck.hpp"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace flexmb::core {

namespace {
// Indices whose weight in the given orthonormal vectors is significant, largest first.
std::vector<int> involved(const Eigen::MatrixXd& basis) {
  std::vector<std::pair<double, int>> w;
  for (int i = 0; i < basis.rows(); ++i) {
    const double v = basis.row(i).norm();
    if (v > 1e-6) w.emplace_back(v, i);
  }
  std::sort(w.begin(), w.end(), [](auto& a, auto& b) { return a.first > b.first; });
  std::vector<int> out;
  for (auto& p : w) out.push_back(p.second);
  return out;
}
}  // namespace

KinematicReport checkKinematics(const Model& model) {
  KinematicReport r;
  for (const auto& n : model.nodes)
    (isTranslational(n.kind) ? r.positionNodes : n.kind == NodeKind::Warping ? r.warpingNodes : r.orientationNodes)++;
  for (const auto& el : model.elements) (el.type->internal ? r.normalisations : r.elements)++;
  r.nx = model.nx;
  r.ne = model.ne;
  std::vector<int> col(model.nx, -1), row(model.ne, -1), cols, rows;
  for (int i = 0; i < model.nx; ++i) {
    switch (model.xRole[i]) {
      case Role::Fixed:
        r.xFixed++;
        break;
      case Role::Input:
        r.xInput++;
        break;
      case Role::Dynamic:
        r.xDynamic++;
        break;
      case Role::Calculable:
        r.xCalculable++;
        col[i] = static_cast<int>(cols.size());
        cols.push_back(i);
        break;
    }
  }
  for (int k = 0; k < model.ne; ++k) {
    switch (model.eRole[k]) {
      case Role::Fixed:
        r.eFixed++;
        break;
      case Role::Input:
        r.eInput++;
        break;
      case Role::Dynamic:
        r.eDynamic++;
        break;
      case Role::Calculable:
        r.eReleased++;
        break;
    }
    if (model.eRole[k] != Role::Calculable) {
      row[k] = static_cast<int>(rows.size());
      rows.push_back(k);
    }
  }
  r.dof = model.numDofs();

  // Dense Jacobian of the constrained deformations w.r.t. the calculable coordinates at x0.
  const int m = static_cast<int>(rows.size()), n = static_cast<int>(cols.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, n);
  ElemVec xe;
  DefJac De;
  for (const auto& E : model.elements) {
    E.gather(model.x0, xe);
    E.impl->jacobian(xe, De);
    for (int i = 0; i < De.rows(); ++i) {
      if (row[E.firstDef + i] < 0) continue;
      for (int j = 0; j < De.cols(); ++j)
        if (col[E.coords[j]] >= 0) J(row[E.firstDef + i], col[E.coords[j]]) = De(i, j);
    }
  }
  if (m == 0 || n == 0) {
    r.rank = 0;
    for (int c : cols) r.underdetermined.push_back(model.coordName(c));
    for (int k : rows) r.overdetermined.push_back(model.deformationName(k));
    return r;
  }
  Eigen::BDCSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  const double tol = std::max(m, n) * 1e-10 * (s.size() ? s[0] : 1.0);
  r.rank = 0;
  for (int i = 0; i < s.size(); ++i) r.rank += s[i] > tol;
  if (r.rank < n) {
    const Eigen::MatrixXd nullSpace = svd.matrixV().rightCols(n - r.rank);
    for (int i : involved(nullSpace)) r.underdetermined.push_back(model.coordName(cols[i]));
  }
  if (r.rank < m) {
    const Eigen::MatrixXd leftNull = svd.matrixU().rightCols(m - r.rank);
    for (int i : involved(leftNull)) r.overdetermined.push_back(model.deformationName(rows[i]));
  }
  return r;
}

std::string formatReport(const KinematicReport& r) {
  std::ostringstream o;
  o << "nodes: " << r.positionNodes << " position, " << r.orientationNodes << " orientation";
  if (r.warpingNodes > 0) o << ", " << r.warpingNodes << " warping";
  o << "; elements: " << r.elements;
  // The file's elements, as `show` counts them; the constraints flexmb adds are said apart.
  if (r.normalisations > 0)
    o << " (and " << r.normalisations << " normalisation constraints of the Euler parameters that flexmb adds)";
  o << "\n";
  o << "nodal coordinates: " << r.nx << " (fixed " << r.xFixed << ", input " << r.xInput << ", dynamic " << r.xDynamic
    << ", calculable " << r.xCalculable << ")\n";
  o << "deformations:      " << r.ne << " (fixed " << r.eFixed << ", input " << r.eInput << ", dynamic " << r.eDynamic
    << ", released " << r.eReleased << ")\n";
  o << "kinematic equations: " << (r.eFixed + r.eInput + r.eDynamic) << " for " << r.xCalculable
    << " calculable coordinates, rank " << r.rank << "\n";
  o << "degrees of freedom: " << r.dof << "\n";
  if (r.wellPosed()) {
    o << "kinematics: well posed\n";
    return o.str();
  }
  auto list = [&o](const std::vector<std::string>& v) {
    const size_t shown = std::min<size_t>(v.size(), 12);
    for (size_t i = 0; i < shown; ++i) o << "  " << v[i] << "\n";
    if (v.size() > shown) o << "  ... and " << v.size() - shown << " more\n";
  };
  // How many to change: one per missing or redundant equation (a closed loop of beams needs six
  // releases in space, three in the plane), so the advice counts them.
  auto howMany = [](int n, const char* one, const char* several) {
    return n == 1 ? std::string(one) : std::to_string(n) + " " + several;
  };
  if (!r.underdetermined.empty()) {
    const int free = r.xCalculable - r.rank;
    o << "UNDER-DETERMINED: " << free
      << " free motion(s) that no kinematic equation fixes; involved coordinates (most first):\n";
    list(r.underdetermined);
    o << "  fix: FIX or DYNX " << howMany(free, "one of these coordinates", "of these coordinates") << ", or make "
      << howMany(free, "a released deformation", "released deformations") << " DYNE/fixed\n";
  }
  if (!r.overdetermined.empty()) {
    const int redundant = r.eFixed + r.eInput + r.eDynamic - r.rank;
    o << "OVER-DETERMINED: " << redundant << " redundant kinematic equation(s); dependent deformations (most first):\n";
    list(r.overdetermined);
    o << "  fix: release (RLSE) " << howMany(redundant, "one of these deformations", "of these deformations")
      << " (one per redundant equation, chosen so that the rank check passes)\n";
  }
  return o.str();
}

}  // namespace flexmb::core
