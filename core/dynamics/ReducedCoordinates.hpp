#pragma once
// The coordinates an analysis integrates or linearises: q = V eta (paper Eq. 17) for a reduced
// model, q = eta for the full one (no basis). Shared by the equations of motion and the
// linearisation so both map eta the same way.
#include <Eigen/Core>
#include <Eigen/QR>
#include <optional>

namespace flexmb::core {

class ReducedCoordinates {
 public:
  ReducedCoordinates(int nq, std::optional<Eigen::MatrixXd> basis)
      : basis_(std::move(basis)), m_(basis_ ? static_cast<int>(basis_->cols()) : nq) {
    if (basis_) qr_.compute(*basis_);  // once: fromFull is called per output time
  }
  int size() const { return m_; }  // dimension of eta
  const Eigen::MatrixXd* basis() const { return basis_ ? &*basis_ : nullptr; }
  // q = V eta (or eta); eta may be a block of a state vector (no temporary on the hot path).
  template <class Derived>
  void toFull(const Eigen::MatrixBase<Derived>& eta, Eigen::VectorXd& q) const {
    if (basis_)
      q.noalias() = *basis_ * eta;
    else
      q = eta;
  }
  // eta from q by least squares onto V (exact when q lies in its span); q itself without a basis.
  Eigen::VectorXd fromFull(const Eigen::VectorXd& q) const { return basis_ ? Eigen::VectorXd(qr_.solve(q)) : q; }

 private:
  std::optional<Eigen::MatrixXd> basis_;
  int m_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

}  // namespace flexmb::core
