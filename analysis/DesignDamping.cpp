#include "analysis/DesignDamping.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "text/NumberText.hpp"

namespace flexmb::analysis {

std::string dampingRefusal(const DampingOptions& o) {
  for (double z : o.ratios)
    if (!std::isfinite(z) || z < 0.0)
      return "the modal damping ratio must be finite and at least 0, not " + text::shortest(z);
  if (!std::isfinite(o.alpha) || o.alpha < 0.0)
    return "Rayleigh's alpha must be finite and at least 0, not " + text::shortest(o.alpha);
  if (!std::isfinite(o.beta) || o.beta < 0.0)
    return "Rayleigh's beta must be finite and at least 0, not " + text::shortest(o.beta);
  return "";
}

std::string timeRunDampingRefusal(const DampingOptions& o) {
  if (!o.ratios.empty())
    return "a modal damping ratio has no form in a nonlinear time run (the modes change with the configuration); "
           "give Rayleigh's beta alone (alpha 0), which damps mode i by the ratio beta omega_i / 2 (beta = 2 zeta / "
           "omega_1 gives the first mode zeta and the higher ones more), or EDAMP; the modal ratio applies to the "
           "linear analyses (transfer, modes)";
  if (o.alpha != 0.0)
    return "Rayleigh's alpha M (mass-proportional damping) is not in the nonlinear equations of motion: a time run "
           "takes beta K alone (alpha 0; beta K is EDAMP = beta * ESTIFF); alpha applies to the linear analyses "
           "(transfer, modes)";
  return "";
}

void addStiffnessProportionalDamping(core::Model& model, double beta) {
  if (beta == 0.0) return;
  for (core::ElementEntry& e : model.elements) {
    if (!e.hasStiffness) continue;
    e.Sd = e.hasDamping ? core::DefMat(e.Sd + beta * e.S) : core::DefMat(beta * e.S);
    e.hasDamping = true;
  }
}

std::string dampingText(const DampingOptions& o) {
  std::ostringstream s;
  if (!o.ratios.empty()) {
    s << "modal damping ratio ";
    for (std::size_t i = 0; i < o.ratios.size(); ++i) s << (i ? "," : "") << text::shortest(o.ratios[i]);
    if (o.ratios.size() > 1) s << " (modes 1, 2, ...; the last for the higher modes)";
  }
  if (o.alpha != 0.0 || o.beta != 0.0) {
    if (!o.ratios.empty()) s << "; ";
    s << "Rayleigh alpha " << text::shortest(o.alpha) << " 1/s, beta " << text::shortest(o.beta) << " s";
  }
  return o.any() ? s.str() : "none added";
}

Eigen::MatrixXd modalDamping(const Eigen::MatrixXd& M, const Eigen::MatrixXd& Kt, const std::vector<double>& ratios) {
  const Eigen::Index m = M.rows();
  if (m == 0 || ratios.empty()) return Eigen::MatrixXd::Zero(m, m);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (Kt + Kt.transpose()),
                                                                     0.5 * (M + M.transpose()));
  if (es.info() != Eigen::Success)
    throw std::runtime_error("modal damping: the eigenproblem (K, M) of the degrees of freedom failed");
  const Eigen::MatrixXd& Phi = es.eigenvectors();  // M-orthonormal, ascending
  Eigen::VectorXd c(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const double lambda = es.eigenvalues()[i];
    const double zeta = ratios[std::min<std::size_t>(static_cast<std::size_t>(i), ratios.size() - 1)];
    c[i] = lambda > 0.0 ? 2.0 * zeta * std::sqrt(lambda) : 0.0;
  }
  const Eigen::MatrixXd MPhi = M * Phi;
  Eigen::MatrixXd C = MPhi * c.asDiagonal() * MPhi.transpose();
  return 0.5 * (C + C.transpose());
}

Eigen::MatrixXd designDamping(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K0, const Eigen::MatrixXd& Kt,
                              const DampingOptions& o) {
  Eigen::MatrixXd C = modalDamping(M, Kt, o.ratios);
  if (o.alpha != 0.0) C += o.alpha * M;
  if (o.beta != 0.0) C += o.beta * K0;
  return C;
}

Eigen::VectorXd modalDampingRatios(const Eigen::MatrixXd& modes, const Eigen::VectorXd& omega, const Eigen::MatrixXd& M,
                                   const Eigen::MatrixXd& C) {
  Eigen::VectorXd zeta(modes.cols());
  for (Eigen::Index i = 0; i < modes.cols(); ++i) {
    const Eigen::VectorXd phi = modes.col(i);
    zeta[i] = omega[i] > 0.0 ? phi.dot(C * phi) / (2.0 * omega[i] * phi.dot(M * phi))
                             : std::numeric_limits<double>::quiet_NaN();
  }
  return zeta;
}

}  // namespace flexmb::analysis
