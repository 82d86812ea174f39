#include "core/SparseLU.hpp"

#include <klu.h>

#include <stdexcept>

namespace flexmb::core {

struct SparseLU::Impl {
  klu_common common{};
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
  const int* colPtr = nullptr;
  const int* rowIdx = nullptr;
  ~Impl() {
    if (numeric) klu_free_numeric(&numeric, &common);
    if (symbolic) klu_free_symbolic(&symbolic, &common);
  }
};

SparseLU::SparseLU() : impl_(std::make_unique<Impl>()) { klu_defaults(&impl_->common); }
SparseLU::~SparseLU() = default;

// scale = -1: no scale factors and no per-call pattern check (klu_scale's scan of every entry,
// which the fixed pattern does not need).
void SparseLU::disableScaling() { impl_->common.scale = -1; }

void SparseLU::analyze(int n, const int* colPtr, const int* rowIdx) {
  auto& m = *impl_;
  if (m.numeric) klu_free_numeric(&m.numeric, &m.common);
  if (m.symbolic) klu_free_symbolic(&m.symbolic, &m.common);
  n_ = n;
  m.colPtr = colPtr;
  m.rowIdx = rowIdx;
  if (n == 0) return;
  m.symbolic = klu_analyze(n, const_cast<int*>(colPtr), const_cast<int*>(rowIdx), &m.common);
  if (!m.symbolic) throw std::runtime_error("KLU could not analyse the kinematic Jacobian pattern");
}

bool SparseLU::factorize(const double* ax) {
  auto& m = *impl_;
  if (n_ == 0) return true;
  int* ap = const_cast<int*>(m.colPtr);
  int* ai = const_cast<int*>(m.rowIdx);
  double* x = const_cast<double*>(ax);
  if (m.numeric) {
    // Reuse the pivot order; accept unless the pivots degraded (cheap diagonal estimate of U),
    // then pivot afresh below.
    if (klu_refactor(ap, ai, x, m.symbolic, m.numeric, &m.common) &&
        klu_rcond(m.symbolic, m.numeric, &m.common) && m.common.rcond > 1e-10)
      return true;
    klu_free_numeric(&m.numeric, &m.common);
  }
  m.numeric = klu_factor(ap, ai, x, m.symbolic, &m.common);
  if (!m.numeric) return false;
  klu_rcond(m.symbolic, m.numeric, &m.common);
  return m.common.status == KLU_OK && m.common.rcond > 1e-14;
}

void SparseLU::solve(double* b, int nrhs) const {
  if (n_ == 0 || nrhs == 0) return;
  klu_solve(impl_->symbolic, impl_->numeric, n_, nrhs, b, &impl_->common);
}

void SparseLU::solveTransposed(double* b, int nrhs) const {
  if (n_ == 0 || nrhs == 0) return;
  klu_tsolve(impl_->symbolic, impl_->numeric, n_, nrhs, b, &impl_->common);
}

double SparseLU::reciprocalCondition() const { return impl_->common.rcond; }

long SparseLU::factorNonzeros() const { return impl_->numeric ? impl_->numeric->lnz + impl_->numeric->unz : 0; }

}  // namespace flexmb::core
