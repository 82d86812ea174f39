#include "analysis/Participation.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/dynamics/Inertia.hpp"
#include "core/elements/EulerParameters.hpp"

namespace flexmb::analysis {

namespace {
constexpr double kNoParticipation = std::numeric_limits<double>::quiet_NaN();

Eigen::Vector3d participationNodePosition(const core::Node& n, const Eigen::VectorXd& x) {
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  for (int k = 0; k < n.dim(); ++k) X[k] = x[n.firstCoord + k];
  return X;
}
}  // namespace

Eigen::MatrixXd rigidBodyMotions(const core::Model& model, const Eigen::VectorXd& x, const Eigen::Vector3d& p) {
  const bool spatial = model.spatial;
  const int nd = spatial ? 6 : 3;
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(model.nx, nd);
  for (const core::Node& n : model.nodes) {
    const int c = n.firstCoord;
    switch (n.kind) {
      case core::NodeKind::Position: {  // x, y; rotation about z through p: (-(Y - py), X - px)
        const Eigen::Vector3d s = participationNodePosition(n, x) - p;
        R(c, 0) = 1.0, R(c + 1, 1) = 1.0;
        R(c, nd - 1) = -s[1], R(c + 1, nd - 1) = s[0];
        break;
      }
      case core::NodeKind::Orientation:
        R(c, nd - 1) = 1.0;
        break;
      case core::NodeKind::SpatialPosition: {
        const Eigen::Vector3d s = participationNodePosition(n, x) - p;
        for (int k = 0; k < 3; ++k) {
          R(c + k, k) = 1.0;
          R.block<3, 1>(c, 3 + k) = Eigen::Vector3d::Unit(k).cross(s);
        }
        break;
      }
      case core::NodeKind::EulerParameters: {  // lambdad = 1/2 E^T a / |lambda|^2 gives 2 E lambdad = a
        const Eigen::Vector4d l = x.segment<4>(c);
        const core::euler::Mat34 E = core::euler::globalRateMatrix(l);
        const double n2 = l.squaredNorm();
        for (int k = 0; k < 3; ++k) R.block<4, 1>(c, 3 + k) = 0.5 * E.row(k).transpose() / n2;
        break;
      }
      case core::NodeKind::Warping:
        break;
    }
  }
  return R;
}

Eigen::Vector3d referencePosition(const core::Model& model, const Eigen::VectorXd& x, const ReferencePoint& ref) {
  if (ref.node == 0) return model.spatial ? ref.point : Eigen::Vector3d(ref.point[0], ref.point[1], 0.0);
  const auto it = model.nodeByLabel.find(ref.node);
  if (it == model.nodeByLabel.end() || !core::isTranslational(model.nodes[it->second].kind))
    throw std::invalid_argument("the reference node " + std::to_string(ref.node) +
                                " is no position node of the model (rotations are about a point: a position node "
                                "or coordinates)");
  return participationNodePosition(model.nodes[it->second], x);
}

double ModalParticipation::mass() const { return rigidBody.size() ? rigidBody(0, 0) : kNoParticipation; }

Eigen::Vector3d ModalParticipation::centreOfMass() const {
  const double m = mass();
  if (!(m > 0.0)) return Eigen::Vector3d::Constant(kNoParticipation);
  const Eigen::Index r = rigidBody.rows() - 1;  // rz
  Eigen::Vector3d s(rigidBody(1, r) / m, -rigidBody(0, r) / m, 0.0);
  if (rigidBody.rows() == 6) s[2] = rigidBody(0, 4) / m;
  return reference + s;
}

ModalParticipation modalParticipation(const core::Model& model, const Eigen::VectorXd& x,
                                      const Eigen::MatrixXd& transfer, const Eigen::MatrixXd& mass,
                                      const Eigen::MatrixXd& modes, const Eigen::Vector3d& reference) {
  ModalParticipation out;
  out.directions = model.spatial ? std::vector<std::string>{"x", "y", "z", "rx", "ry", "rz"}
                                 : std::vector<std::string>{"x", "y", "rz"};
  out.reference = reference;
  const Eigen::MatrixXd R = rigidBodyMotions(model, x, reference);
  core::Inertia inertia(model);
  inertia.update(x);
  Eigen::MatrixXd MR;
  inertia.multiply(R, MR);
  out.rigidBody = R.transpose() * MR;
  out.rigidBody = (0.5 * (out.rigidBody + out.rigidBody.transpose())).eval();
  const Eigen::MatrixXd b = transfer.transpose() * MR;  // m x nd: the loads of unit support accelerations
  const Eigen::MatrixXd L = modes.transpose() * b;      // k x nd
  const Eigen::Index k = modes.cols(), nd = R.cols();
  out.factors.resize(k, nd);
  out.effective.resize(k, nd);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double mu = modes.col(i).dot(mass * modes.col(i));
    out.factors.row(i) = L.row(i) / mu;
    out.effective.row(i) = L.row(i).array().square() / mu;
  }
  out.total = Eigen::VectorXd::Constant(nd, kNoParticipation);
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (mass + mass.transpose()));
  if (mass.rows() > 0 && llt.info() == Eigen::Success)
    for (Eigen::Index d = 0; d < nd; ++d) out.total[d] = b.col(d).dot(llt.solve(b.col(d)));
  return out;
}

io::CsvTable participationTable(const Eigen::VectorXd& omega, const ModalParticipation& p,
                                const Eigen::VectorXd* zeta) {
  io::CsvTable t;
  t.columns = {"mode", "f_Hz"};
  if (zeta) t.columns.push_back("zeta");
  for (const auto& d : p.directions) t.columns.push_back("gamma_" + d);
  for (const auto& d : p.directions) t.columns.push_back("meff_" + d);
  for (const auto& d : p.directions) t.columns.push_back("meff_" + d + "_pct");
  for (const auto& d : p.directions) t.columns.push_back("meff_" + d + "_cum_pct");
  const Eigen::Index nd = static_cast<Eigen::Index>(p.directions.size());
  Eigen::VectorXd cum = Eigen::VectorXd::Zero(nd);
  for (Eigen::Index i = 0; i < p.effective.rows(); ++i) {
    std::vector<double> row = {static_cast<double>(i + 1), omega[i] / (2 * M_PI)};
    if (zeta) row.push_back((*zeta)[i]);
    for (Eigen::Index d = 0; d < nd; ++d) row.push_back(p.factors(i, d));
    for (Eigen::Index d = 0; d < nd; ++d) row.push_back(p.effective(i, d));
    cum += p.effective.row(i).transpose();
    // m_d of a direction the degrees of freedom cannot move in is round-off: no percentages.
    const auto pct = [&](double v, Eigen::Index d) {
      return p.total[d] > 1e-10 * std::abs(p.rigidBody(d, d)) && p.total[d] > 0.0 ? 100.0 * v / p.total[d]
                                                                                  : kNoParticipation;
    };
    for (Eigen::Index d = 0; d < nd; ++d) row.push_back(pct(p.effective(i, d), d));
    for (Eigen::Index d = 0; d < nd; ++d) row.push_back(pct(cum[d], d));
    t.rows.push_back(std::move(row));
  }
  return t;
}

}  // namespace flexmb::analysis
