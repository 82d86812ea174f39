#include "core/kinematics/SparseLU.hpp"

#include <klu.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace flexmb::core {

namespace {

// Diagonal blocks up to this size are kept dense and solved by unrolled code: the BTF
// blocks of a kinematic Jacobian are a few coordinates each (3 for a planar beam's end node, 7 for
// a spatial one with its Euler parameters), where per-row loop overhead costs more than the flops.
constexpr int kDenseBlock = 8;
constexpr double kZero = 0.0;

// Two right-hand sides side by side (one SSE2 register): a pair shares each factor entry's index
// and value load. Lane = double solves one column, Pair two.
using Pair = double __attribute__((vector_size(16)));

template <class Lane>
Lane gather(const double* b, int n, int i) {
  if constexpr (sizeof(Lane) == sizeof(double))
    return b[i];
  else
    return Lane{b[i], b[n + i]};
}
template <class Lane>
void scatter(double* b, int n, int i, Lane v) {
  if constexpr (sizeof(Lane) == sizeof(double)) {
    b[i] = v;
  } else {
    b[i] = v[0];
    b[n + i] = v[1];
  }
}

enum class Part { Off, L, U };

// KLU keeps each block's columns of L and U in LUbx[block] as Llen[k] row indices (local to the
// block, padded to whole doubles) followed by as many values, starting Lip[k] doubles in (klu.h's
// numeric object; the layout klu_extract decodes).
void columnOf(const void* lu, const int* ip, const int* len, int k, const int*& rows, const double*& values,
              int& count) {
  const double* start = static_cast<const double*>(lu) + ip[k];
  count = len[k];
  rows = reinterpret_cast<const int*>(start);
  values = start + (count * sizeof(int) + sizeof(double) - 1) / sizeof(double);
}

// Calls visit(part, row, col, value) for every entry of the factors off their diagonals, in
// pivot order (the unit diagonal of L and the diagonal of U, Udiag, are not visited).
template <class Visit>
void forEachEntry(const klu_symbolic& s, const klu_numeric& f, Visit&& visit) {
  const double* off = static_cast<const double*>(f.Offx);
  for (int block = 0; block < s.nblocks; ++block) {
    const int k1 = s.R[block], k2 = s.R[block + 1];
    for (int k = k1; k < k2; ++k) {
      for (int p = f.Offp[k]; p < f.Offp[k + 1]; ++p) visit(Part::Off, f.Offi[p], k, off + p);
      if (k2 - k1 == 1) continue;  // a singleton's L and U hold no entries
      const int* rows;
      const double* values;
      int count;
      columnOf(f.LUbx[block], f.Lip + k1, f.Llen + k1, k - k1, rows, values, count);
      for (int p = 0; p < count; ++p) visit(Part::L, k1 + rows[p], k, values + p);
      columnOf(f.LUbx[block], f.Uip + k1, f.Ulen + k1, k - k1, rows, values, count);
      for (int p = 0; p < count; ++p) visit(Part::U, k1 + rows[p], k, values + p);
    }
  }
}

// LU without pivoting (the rows and columns already in KLU's pivot order) of a dense NK x NK block
// in place, row-major: L below the diagonal (unit diagonal not stored), U on and above, u_kk also
// to ud. Right-looking, unrolled; the same operations as KLU's left-looking column loop for the
// entries of its patterns, summed in another order (round-off), exact zeros elsewhere. False on a
// zero or non-finite pivot; umin, umax take in the pivots' magnitudes.
template <int NK>
bool denseLU(double* a, double* ud, double& umin, double& umax) {
  bool regular = true;
#pragma GCC unroll 8
  for (int k = 0; k < NK; ++k) {
    const double ukk = a[k * NK + k];
    ud[k] = ukk;
    const double m = std::fabs(ukk);
    regular &= m > 0.0 && m <= std::numeric_limits<double>::max();
    umin = std::min(umin, m);
    umax = std::max(umax, m);
#pragma GCC unroll 8
    for (int i = k + 1; i < NK; ++i) {
      const double lik = a[i * NK + k] /= ukk;
#pragma GCC unroll 8
      for (int j = k + 1; j < NK; ++j) a[i * NK + j] -= lik * a[k * NK + j];
    }
  }
  return regular;
}

using DenseLUFn = bool (*)(double*, double*, double&, double&);
DenseLUFn denseLU(int nk) {
  static constexpr DenseLUFn kBySize[kDenseBlock + 1] = {nullptr,    denseLU<1>, denseLU<2>, denseLU<3>, denseLU<4>,
                                                         denseLU<5>, denseLU<6>, denseLU<7>, denseLU<8>};
  return kBySize[nk];
}

}  // namespace

// The factors of the last factorisation rearranged for the solve. Blocks are visited last to
// first; each row of a block starts from b_P(i) less F(i,:) x, F the off-diagonal blocks, whose x
// is final, then the block's own LU is solved. Two forms:
// - small blocks (up to kDenseBlock rows) keep their LU dense (row-major, L below the diagonal,
//   U on and above) and are solved in registers by unrolled code; their F is dense by columns
//   (the distinct columns its rows use, one unrolled update each) or, where that would be mostly
//   zeros, by rows as below;
// - larger blocks are solved by rows as dot products (loads only; KLU's column sweeps store into
//   x per entry): forward rows x_i = b_P(i) - F(i,:) x - L(i,:) x first to last (the last also
//   divided by U(i,i)), then backward rows up, x_i = (x_i - U(i,:) x) / U(i,i).
// KLU's factorisation fills the plan once (build copies each value from its address in KLU's
// numeric object). Refactorisations with the same pivot order are the plan's own (refactor), over
// index maps made at build time, writing each factor value straight to its place in the plan:
// large blocks by KLU's left-looking algorithm (klu_refactor's loops, same operations in the same
// order), small blocks by a dense unrolled LU in place in their dense form (same pivots, sums in
// another order). KLU's numeric object is then stale; writeBack restores it where KLU itself must
// solve (A^T).
class SolvePlan {
 public:
  void build(const klu_symbolic& s, const klu_numeric& f, const int* ap, const int* ai);
  // build's second half: klu_refactor's traversal mapped onto the solve layout (val_).
  void buildRefactorMaps(const klu_symbolic& s, const klu_numeric& f, const int* ap, const int* ai);
  // Factor values for new matrix values ax (same pattern) in the pivot order of the last build.
  // Returns min |u_kk| / max |u_kk| (KLU's klu_rcond), 0 for a zero or non-finite pivot.
  double refactor(const double* ax);
  // Copies the plan's factor values back into KLU's numeric object f (the one of the last build).
  void writeBack(klu_numeric& f) const;
  // A X = B in place, nrhs columns of leading dimension n.
  void solve(double* b, int nrhs) const;

 private:
  struct Block {
    int first, size;
    bool small;  // dense LU, solved by unrolled code; else by rows
    int rows;    // first row entry (col_, val_) of its rows
    int lu;      // small: offset of its dense LU in val_ (F by columns just before)
    int cols;    // small, F by columns: its first column in offCol_
    int count;   // small, F by columns: number of columns; -1: F by rows
  };
  // Solves consecutive small blocks of one size.
  template <class Lane>
  using SmallSolve = void (*)(const SolvePlan&, const Block* begin, const Block* end, const double* b, Lane* x);
  // Consecutive blocks in visiting order solved alike: small ones of one size, or one large.
  struct Run {
    int begin, end;  // in blocks_
    SmallSolve<double> one;
    SmallSolve<Pair> two;
  };

  template <class Lane>
  void solveLanes(double* b, Lane* x) const;
  template <class Lane>
  void forwardRows(const Block& blk, const double* b, Lane* x) const;
  template <class Lane>
  void backwardRows(const Block& blk, Lane* x) const;
  template <int NK, class Lane>
  static void smallBlocks(const SolvePlan& plan, const Block* begin, const Block* end, const double* b, Lane* x);
  template <class Lane>
  static SmallSolve<Lane> smallSolve(int nk);

  int n_ = 0;
  std::vector<Block> blocks_;       // in visiting order
  std::vector<Run> runs_;           // in visiting order
  std::vector<int> forwardEnd_;     // per row: end of its forward row entries
  std::vector<int> backwardEnd_;    // per row of a large block: end of its backward row entries
  std::vector<int> col_;            // per row entry: column (pivot order)
  std::vector<int> offCol_;         // columns of the F blocks kept by columns
  std::vector<double> val_;         // row entries, then the small blocks' F by columns and LU
  std::vector<const double*> src_;  // per value: its address in KLU's numeric object
  const int* pnum_ = nullptr;       // pivot row permutation
  const int* q_ = nullptr;          // column permutation
  const double* udiag_ = nullptr;   // diagonal of U (ud_)
  const double* rs_ = nullptr;      // row scale factors in pivot order (rsPivot_), or null
  std::vector<double> ud_;          // diagonal of U
  std::vector<double> rsPivot_;     // row scale factors in pivot order (KLU's scaling only)

  // Refactorisation maps (pivot order k; rows local to the block in X):
  int nnz_ = 0;
  const int* ai_ = nullptr;           // the caller's row indices (for the scale factors)
  std::vector<double> rsRow_;         // scale factors by original row
  std::vector<int> offSrc_, offDst_;  // entries copied: index in ax -> index in val_ (those of the
                                      // off-diagonal blocks and of the small blocks' dense LU)
  using DenseLU = bool (*)(double* a, double* ud, double& umin, double& umax);
  struct Dense {
    int lu, first, size;  // its dense LU in val_, its first pivot, its size
    DenseLU factor;
  };
  std::vector<Dense> dense_;               // small blocks: factorised densely in place
  std::vector<int> largeFirst_;            // large blocks (sparse, left-looking): first pivot, then the
                                           // next block's (pairs)
  std::vector<int> aBegin_, aSrc_, aRow_;  // per column k: entries of the diagonal block in ax
  std::vector<int> uBegin_, uRow_, uDst_;  // per column k: U(:,k) off the diagonal, KLU's order
  std::vector<int> lBegin_, lRow_, lDst_;  // per column k: L(:,k) below the diagonal
  std::vector<double> lx_;                 // L(:,k)'s values also by columns (the update's operand)
  mutable std::vector<double> work_;       // dense column of a block, zero between uses
  mutable std::vector<double> x1_;         // workspace, one column
  mutable std::vector<Pair> x2_;           // workspace, two columns
};

void SolvePlan::build(const klu_symbolic& s, const klu_numeric& f, const int* ap, const int* ai) {
  const int n = n_ = s.n;
  pnum_ = f.Pnum;
  q_ = s.Q;
  const double* kluUdiag = static_cast<const double*>(f.Udiag);
  ud_.assign(kluUdiag, kluUdiag + n);
  udiag_ = ud_.data();
  if (f.Rs) {
    rsPivot_.assign(f.Rs, f.Rs + n);
    rs_ = rsPivot_.data();
  } else {
    rsPivot_.clear();
    rs_ = nullptr;
  }
  x1_.assign(n, 0.0);
  x2_.assign(n, Pair{0.0, 0.0});

  // Blocks in visiting order, each row's block, and per block its F entries and distinct F
  // columns (the visit is by ascending column).
  blocks_.clear();
  std::vector<int> blockOf(n);
  for (int block = s.nblocks - 1; block >= 0; --block) {
    const int k1 = s.R[block], nk = s.R[block + 1] - k1;
    for (int k = k1; k < k1 + nk; ++k) blockOf[k] = static_cast<int>(blocks_.size());
    blocks_.push_back({k1, nk, nk <= kDenseBlock, 0, 0, 0, 0});
  }
  const int nb = static_cast<int>(blocks_.size());
  std::vector<int> offEntries(nb, 0), lastCol(nb, -1);
  forEachEntry(s, f, [&](Part part, int row, int c, const double*) {
    if (part != Part::Off) return;
    const int b = blockOf[row];
    ++offEntries[b];
    if (lastCol[b] != c) lastCol[b] = c, ++blocks_[b].count;
  });
  for (int b = 0; b < nb; ++b) {
    Block& blk = blocks_[b];
    const bool byColumns = blk.small && blk.count * blk.size <= 2 * offEntries[b] + blk.size;
    if (!byColumns) blk.count = -1;
  }
  runs_.clear();
  for (int b = 0; b < nb; ++b) {
    const Block& blk = blocks_[b];
    if (blk.small && !runs_.empty() && runs_.back().one && blocks_[runs_.back().begin].size == blk.size)
      ++runs_.back().end;
    else if (blk.small)
      runs_.push_back({b, b + 1, smallSolve<double>(blk.size), smallSolve<Pair>(blk.size)});
    else
      runs_.push_back({b, b + 1, nullptr, nullptr});
  }
  // Entries by rows (F by rows; L and U of large blocks): count per forward and backward row.
  auto inRows = [&](Part part, int row) {
    const Block& b = blocks_[blockOf[row]];
    return part == Part::Off ? b.count < 0 : !b.small;
  };
  std::vector<int> forward(n, 0), backward(n, 0);
  forEachEntry(s, f, [&](Part part, int row, int, const double*) {
    if (inRows(part, row)) ++(part == Part::U ? backward : forward)[row];
  });

  // Each row's first entry in visiting order, then the small blocks' values.
  forwardEnd_.assign(n, 0);
  backwardEnd_.assign(n, 0);
  int next = 0;
  auto place = [&](std::vector<int>& count, std::vector<int>& end, int i) {
    const int c = count[i];
    count[i] = next;
    end[i] = next += c;
  };
  for (Block& b : blocks_) {
    b.rows = next;
    for (int i = b.first; i < b.first + b.size; ++i) place(forward, forwardEnd_, i);
    if (!b.small)
      for (int i = b.first + b.size - 2; i >= b.first; --i) place(backward, backwardEnd_, i);
  }
  col_.resize(next);
  int cols = 0;
  for (Block& b : blocks_) {
    if (!b.small) continue;
    if (b.count > 0) {
      b.cols = cols;
      cols += b.count;
      next += b.count * b.size;
    }
    b.lu = next;
    next += b.size * b.size;
  }
  offCol_.resize(cols);
  val_.resize(next);
  src_.assign(next, &kZero);  // the structural zeros of dense parts stay 0

  std::vector<int> column(nb, -1);  // per F by columns: index of the column being filled
  lastCol.assign(nb, -1);
  forEachEntry(s, f, [&](Part part, int row, int c, const double* v) {
    const int bi = blockOf[row];
    const Block& b = blocks_[bi];
    if (inRows(part, row)) {
      const int p = (part == Part::U ? backward : forward)[row]++;
      col_[p] = c;
      src_[p] = v;
    } else if (part == Part::Off) {
      if (lastCol[bi] != c) lastCol[bi] = c, offCol_[b.cols + ++column[bi]] = c;
      src_[b.lu - (b.count - column[bi]) * b.size + (row - b.first)] = v;
    } else {
      src_[b.lu + (row - b.first) * b.size + (c - b.first)] = v;
    }
  });
  for (const Block& b : blocks_)
    if (b.small)
      for (int k = 0; k < b.size; ++k) src_[b.lu + k * (b.size + 1)] = kluUdiag + b.first + k;
  for (size_t p = 0; p < val_.size(); ++p) val_[p] = *src_[p];

  buildRefactorMaps(s, f, ap, ai);
}

void SolvePlan::buildRefactorMaps(const klu_symbolic& s, const klu_numeric& f, const int* ap, const int* ai) {
  const int n = n_, nb = static_cast<int>(blocks_.size());
  // Refactorisation maps: klu_refactor's traversal (blocks first to last, columns in pivot order,
  // each column's entries of A in stored order), each factor value's address in KLU's numeric
  // object translated to its place in val_.
  std::unordered_map<const double*, int> placeOf;
  for (size_t p = 0; p < src_.size(); ++p)
    if (src_[p] != &kZero) placeOf[src_[p]] = static_cast<int>(p);
  auto placeIn = [&](const double* v) {
    const auto it = placeOf.find(v);
    if (it == placeOf.end()) throw std::logic_error("SparseLU: a factor value without a place in the solve layout");
    return it->second;
  };
  nnz_ = ap[n];
  ai_ = ai;
  rsRow_.assign(f.Rs ? n : 0, 0.0);
  offSrc_.clear();
  offDst_.clear();
  dense_.clear();
  largeFirst_.clear();
  aSrc_.clear();
  aRow_.clear();
  uRow_.clear();
  uDst_.clear();
  lRow_.clear();
  lDst_.clear();
  aBegin_.assign(n + 1, 0);
  uBegin_.assign(n + 1, 0);
  lBegin_.assign(n + 1, 0);
  work_.assign(s.maxblock, 0.0);
  lx_.clear();
  const double* offx = static_cast<const double*>(f.Offx);
  int poff = 0;
  for (int block = 0; block < s.nblocks; ++block) {
    const int k1 = s.R[block], k2 = s.R[block + 1], nk = k2 - k1;
    const Block& blk = blocks_[nb - 1 - block];  // blocks_ is in visiting order, last to first
    if (blk.small) {
      dense_.push_back({blk.lu, k1, nk, denseLU(nk)});
    } else {
      largeFirst_.push_back(k1);
      largeFirst_.push_back(k2);
    }
    for (int k = k1; k < k2; ++k) {
      const int oldcol = s.Q[k];
      for (int p = ap[oldcol]; p < ap[oldcol + 1]; ++p) {
        const int newrow = f.Pinv[ai[p]] - k1;
        if (newrow < 0) {
          if (poff >= f.nzoff || f.Offi[poff] != newrow + k1)
            throw std::logic_error("SparseLU: KLU's off-diagonal entries not in klu_refactor's order");
          offSrc_.push_back(p);
          offDst_.push_back(placeIn(offx + poff++));
        } else if (blk.small) {
          offSrc_.push_back(p);
          offDst_.push_back(blk.lu + newrow * nk + (k - k1));
        } else {
          aSrc_.push_back(p);
          aRow_.push_back(newrow);
        }
      }
      aBegin_[k + 1] = static_cast<int>(aSrc_.size());
      if (!blk.small) {
        const int* rows;
        const double* values;
        int count;
        columnOf(f.LUbx[block], f.Uip + k1, f.Ulen + k1, k - k1, rows, values, count);
        for (int p = 0; p < count; ++p) uRow_.push_back(rows[p]), uDst_.push_back(placeIn(values + p));
        columnOf(f.LUbx[block], f.Lip + k1, f.Llen + k1, k - k1, rows, values, count);
        for (int p = 0; p < count; ++p) lRow_.push_back(rows[p]), lDst_.push_back(placeIn(values + p));
      }
      uBegin_[k + 1] = static_cast<int>(uRow_.size());
      lBegin_[k + 1] = static_cast<int>(lRow_.size());
    }
  }
  lx_.resize(lRow_.size());
  for (size_t p = 0; p < lx_.size(); ++p) lx_[p] = val_[lDst_[p]];
}

// Small blocks: A's entries copied into their zeroed dense LU, then denseLU in place. Large blocks:
// klu_refactor's numeric loop (SuiteSparse 5.12, KLU/Source/klu_refactor.c), with KLU's numeric
// object replaced by the plan's places: per block, per column k, scatter the block's part of
// A(P, Q(k)) into the dense X, for each j of U(:,k) in KLU's (topological) order take u_jk = X_j
// and subtract L(:,j) u_jk, then u_kk = X_k and L(:,k) = X(L's rows) / u_kk. Off-diagonal block
// entries are A's, permuted. With KLU's scaling (scale = 2, the default) every entry of A is
// divided by the largest magnitude of its row first, as klu_scale does.
double SolvePlan::refactor(const double* ax) {
  if (!rsRow_.empty()) {
    double* rs = rsRow_.data();
    std::fill(rsRow_.begin(), rsRow_.end(), 0.0);
    for (int p = 0; p < nnz_; ++p) rs[ai_[p]] = std::max(rs[ai_[p]], std::fabs(ax[p]));
    for (int i = 0; i < n_; ++i)
      if (rs[i] == 0.0) rs[i] = 1.0;
    for (int k = 0; k < n_; ++k) rsPivot_[k] = rs[pnum_[k]];
  }
  const double* rs = rsRow_.empty() ? nullptr : rsRow_.data();
  double* v = val_.data();
  double* ud = ud_.data();
  for (const Dense& d : dense_)  // the dense LUs' structural zeros (the copies below fill the rest)
    std::fill(v + d.lu, v + d.lu + d.size * d.size, 0.0);
  const int* src = offSrc_.data();
  const int* dst = offDst_.data();
  const int nOff = static_cast<int>(offSrc_.size());
  if (!rs)
    for (int e = 0; e < nOff; ++e) v[dst[e]] = ax[src[e]];
  else
    for (int e = 0; e < nOff; ++e) v[dst[e]] = ax[src[e]] / rs[ai_[src[e]]];

  const int *aBegin = aBegin_.data(), *aSrc = aSrc_.data(), *aRow = aRow_.data();
  const int *uBegin = uBegin_.data(), *uRow = uRow_.data(), *uDst = uDst_.data();
  const int *lBegin = lBegin_.data(), *lRow = lRow_.data(), *lDst = lDst_.data();
  double* lx = lx_.data();
  double* x = work_.data();
  double umin = std::numeric_limits<double>::infinity(), umax = 0.0;
  bool regular = true;
  for (const Dense& d : dense_) regular &= d.factor(v + d.lu, ud + d.first, umin, umax);
  for (size_t b = 0; b < largeFirst_.size(); b += 2) {
    const int k1 = largeFirst_[b], k2 = largeFirst_[b + 1];
    for (int k = k1; k < k2; ++k) {
      if (!rs)
        for (int p = aBegin[k]; p < aBegin[k + 1]; ++p) x[aRow[p]] = ax[aSrc[p]];
      else
        for (int p = aBegin[k]; p < aBegin[k + 1]; ++p) x[aRow[p]] = ax[aSrc[p]] / rs[ai_[aSrc[p]]];
      for (int up = uBegin[k]; up < uBegin[k + 1]; ++up) {
        const int j = uRow[up];
        const double ujk = x[j];
        x[j] = 0.0;
        v[uDst[up]] = ujk;
        for (int p = lBegin[k1 + j]; p < lBegin[k1 + j + 1]; ++p) x[lRow[p]] -= lx[p] * ujk;
      }
      const double ukk = x[k - k1];
      x[k - k1] = 0.0;
      ud[k] = ukk;
      const double a = std::fabs(ukk);
      if (!(a > 0.0 && a <= std::numeric_limits<double>::max())) regular = false;  // zero, NaN, Inf
      umin = std::min(umin, a);
      umax = std::max(umax, a);
      for (int p = lBegin[k]; p < lBegin[k + 1]; ++p) {
        const int i = lRow[p];
        v[lDst[p]] = lx[p] = x[i] / ukk;
        x[i] = 0.0;
      }
    }
  }
  if (!regular || n_ == 0) return 0.0;
  const double rcond = umin / umax;
  return std::isfinite(rcond) ? rcond : 0.0;
}

void SolvePlan::writeBack(klu_numeric& f) const {
  for (size_t p = 0; p < val_.size(); ++p)
    if (src_[p] != &kZero) *const_cast<double*>(src_[p]) = val_[p];
  std::copy(ud_.begin(), ud_.end(), static_cast<double*>(f.Udiag));
  if (f.Rs && rs_) std::copy(rsPivot_.begin(), rsPivot_.end(), f.Rs);
}

// Forward rows: x_i = b_P(i) - F(i,:) x (- L(i,:) x in a large block).
template <class Lane>
void SolvePlan::forwardRows(const Block& blk, const double* b, Lane* x) const {
  const int* c = col_.data();
  const double* v = val_.data();
  int p = blk.rows;
  for (int i = blk.first; i < blk.first + blk.size; ++i) {
    Lane t = gather<Lane>(b, n_, pnum_[i]);
    for (const int e = forwardEnd_[i]; p < e; ++p) t -= v[p] * x[c[p]];
    x[i] = t;
  }
}

// The rest of a large block after its forward rows: backward rows up from the last.
template <class Lane>
void SolvePlan::backwardRows(const Block& blk, Lane* x) const {
  const int* c = col_.data();
  const double* v = val_.data();
  const int last = blk.first + blk.size - 1;
  x[last] /= udiag_[last];
  int p = forwardEnd_[last];
  for (int i = last - 1; i >= blk.first; --i) {
    Lane t = x[i];
    for (const int e = backwardEnd_[i]; p < e; ++p) t -= v[p] * x[c[p]];
    x[i] = t / udiag_[i];
  }
}

// Small blocks of size NK, each in registers: b_P less F x (by columns or by rows), then its LU
// unrolled.
template <int NK, class Lane>
void SolvePlan::smallBlocks(const SolvePlan& plan, const Block* blk, const Block* end, const double* b, Lane* x) {
  const double* v = plan.val_.data();
  for (; blk < end; ++blk) {
    const int* pnum = plan.pnum_ + blk->first;
    Lane t[NK];
#pragma GCC unroll 8
    for (int i = 0; i < NK; ++i) t[i] = gather<Lane>(b, plan.n_, pnum[i]);
    if (blk->count >= 0) {
      const double* f = v + blk->lu - blk->count * NK;
      for (const int *c = plan.offCol_.data() + blk->cols, *e = c + blk->count; c < e; ++c, f += NK) {
        const Lane xc = x[*c];
#pragma GCC unroll 8
        for (int i = 0; i < NK; ++i) t[i] -= f[i] * xc;
      }
    } else {
      const int* c = plan.col_.data();
      const int* rowEnd = plan.forwardEnd_.data() + blk->first;
      int p = blk->rows;
#pragma GCC unroll 8
      for (int i = 0; i < NK; ++i)
        for (const int e = rowEnd[i]; p < e; ++p) t[i] -= v[p] * x[c[p]];
    }
    const double* a = v + blk->lu;
#pragma GCC unroll 8
    for (int i = 1; i < NK; ++i)
#pragma GCC unroll 8
      for (int j = 0; j < i; ++j) t[i] -= a[i * NK + j] * t[j];
#pragma GCC unroll 8
    for (int i = NK - 1; i >= 0; --i) {
#pragma GCC unroll 8
      for (int j = i + 1; j < NK; ++j) t[i] -= a[i * NK + j] * t[j];
      t[i] /= a[i * NK + i];
    }
#pragma GCC unroll 8
    for (int i = 0; i < NK; ++i) x[blk->first + i] = t[i];
  }
}

template <class Lane>
SolvePlan::SmallSolve<Lane> SolvePlan::smallSolve(int nk) {
  static constexpr SmallSolve<Lane> kBySize[kDenseBlock + 1] = {nullptr,
                                                                smallBlocks<1, Lane>,
                                                                smallBlocks<2, Lane>,
                                                                smallBlocks<3, Lane>,
                                                                smallBlocks<4, Lane>,
                                                                smallBlocks<5, Lane>,
                                                                smallBlocks<6, Lane>,
                                                                smallBlocks<7, Lane>,
                                                                smallBlocks<8, Lane>};
  return kBySize[nk];
}

// One or two right-hand sides (columns of b, leading dimension n_).
template <class Lane>
void SolvePlan::solveLanes(double* b, Lane* x) const {
  for (const Run& run : runs_) {
    const Block* blk = blocks_.data() + run.begin;
    if (!run.one) {
      forwardRows(*blk, b, x);
      backwardRows(*blk, x);
    } else if constexpr (sizeof(Lane) == sizeof(double)) {
      run.one(*this, blk, blocks_.data() + run.end, b, x);
    } else {
      run.two(*this, blk, blocks_.data() + run.end, b, x);
    }
  }
  int k = 0;
  for (; k + 2 <= n_; k += 2) {
    scatter(b, n_, q_[k], x[k]);
    scatter(b, n_, q_[k + 1], x[k + 1]);
  }
  if (k < n_) scatter(b, n_, q_[k], x[k]);
}

void SolvePlan::solve(double* b, int nrhs) const {
  if (rs_)  // KLU's row scaling: A = R^-1 (L U + F) with R = diag(Rs) in pivot order
    for (int r = 0; r < nrhs; ++r)
      for (int k = 0; k < n_; ++k) b[static_cast<size_t>(r) * n_ + pnum_[k]] /= rs_[k];
  int r = 0;
  for (; r + 2 <= nrhs; r += 2) solveLanes(b + static_cast<size_t>(r) * n_, x2_.data());
  if (r < nrhs) solveLanes(b + static_cast<size_t>(r) * n_, x1_.data());
}

namespace {
// KLU's symbolic object, freed by the last SparseLU that uses it (shareAnalysis).
std::shared_ptr<klu_symbolic> ownSymbolic(klu_symbolic* s) {
  return std::shared_ptr<klu_symbolic>(s, [](klu_symbolic* p) {
    klu_common c;
    klu_defaults(&c);
    klu_free_symbolic(&p, &c);
  });
}
}  // namespace

struct SparseLU::Impl {
  klu_common common{};
  std::shared_ptr<klu_symbolic> symbolic;  // this object's analysis, or one shared with others
  klu_numeric* numeric = nullptr;
  const int* colPtr = nullptr;
  const int* rowIdx = nullptr;
  SolvePlan plan;
  bool kluStale = false;  // the plan's refactorisation is newer than KLU's numeric object
  ~Impl() {
    if (numeric) klu_free_numeric(&numeric, &common);
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
  m.symbolic.reset();
  n_ = n;
  m.colPtr = colPtr;
  m.rowIdx = rowIdx;
  if (n == 0) return;
  klu_symbolic* s = klu_analyze(n, const_cast<int*>(colPtr), const_cast<int*>(rowIdx), &m.common);
  if (!s) throw std::runtime_error("KLU could not analyse the kinematic Jacobian pattern");
  m.symbolic = ownSymbolic(s);
}

void SparseLU::shareAnalysis(const SparseLU& analysed) {
  auto& m = *impl_;
  if (m.numeric) klu_free_numeric(&m.numeric, &m.common);
  m.symbolic = analysed.impl_->symbolic;
  m.colPtr = analysed.impl_->colPtr;
  m.rowIdx = analysed.impl_->rowIdx;
  n_ = analysed.n_;
}

bool SparseLU::factorize(const double* ax) {
  auto& m = *impl_;
  if (n_ == 0) return true;
  int* ap = const_cast<int*>(m.colPtr);
  int* ai = const_cast<int*>(m.rowIdx);
  double* x = const_cast<double*>(ax);
  if (m.numeric) {
    // Reuse the pivot order (the plan's own refactorisation); accept unless the pivots degraded
    // (KLU's cheap diagonal estimate of U, min |u_kk| / max |u_kk|), then pivot afresh below.
    m.common.rcond = m.plan.refactor(ax);
    m.kluStale = true;
    if (m.common.rcond > 1e-10) return true;
    klu_free_numeric(&m.numeric, &m.common);
  }
  m.kluStale = false;
  m.numeric = klu_factor(ap, ai, x, m.symbolic.get(), &m.common);
  ++pivotings_;
  if (!m.numeric) return false;
  m.plan.build(*m.symbolic, *m.numeric, m.colPtr, m.rowIdx);
  klu_rcond(m.symbolic.get(), m.numeric, &m.common);
  return m.common.status == KLU_OK && m.common.rcond > 1e-14;
}

void SparseLU::solve(double* b, int nrhs) const {
  if (n_ == 0 || nrhs == 0 || !impl_->numeric) return;
  impl_->plan.solve(b, nrhs);
}

void SparseLU::solveTransposed(double* b, int nrhs) const {
  if (n_ == 0 || nrhs == 0 || !impl_->numeric) return;
  if (impl_->kluStale) {  // KLU solves A^T on its own numeric object: bring it up to date
    impl_->plan.writeBack(*impl_->numeric);
    impl_->kluStale = false;
  }
  klu_tsolve(impl_->symbolic.get(), impl_->numeric, n_, nrhs, b, &impl_->common);
}

double SparseLU::reciprocalCondition() const { return impl_->common.rcond; }

long SparseLU::factorNonzeros() const { return impl_->numeric ? impl_->numeric->lnz + impl_->numeric->unz : 0; }

}  // namespace flexmb::core
