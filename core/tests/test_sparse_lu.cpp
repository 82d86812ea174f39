// core::SparseLU against a dense LU (Eigen) and against KLU's own klu_solve on the same matrix:
// random nonsymmetric matrices with block triangular (BTF) structure and without, saddle-point
// matrices with a zero (2,2) block, one to many right-hand sides, refactorisation with new values
// on the same pattern, the fresh-pivoting fallback, singular matrices and transposed solves.
// SparseLU refactorises with the old pivots by its own code (not klu_refactor): many
// refactorisations are checked against the dense LU and against klu_refactor + klu_solve.
#include <gtest/gtest.h>
#include <klu.h>

#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "core/kinematics/SparseLU.hpp"
#include "core/tests/ShortRun.hpp"

using Eigen::MatrixXd;
using flexmb::core::SparseLU;

namespace {

double uniform(std::mt19937& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
int uniformInt(std::mt19937& rng, int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }

// Compressed-column matrix built from (row, col) -> value.
struct Csc {
  int n = 0;
  std::vector<int> colPtr, rowIdx;
  std::vector<double> values;

  Csc(int size, const std::map<std::pair<int, int>, double>& entries) : n(size), colPtr(size + 1, 0) {
    for (const auto& [rc, v] : entries) ++colPtr[rc.second + 1];
    std::partial_sum(colPtr.begin(), colPtr.end(), colPtr.begin());
    std::vector<int> next(colPtr.begin(), colPtr.end() - 1);
    rowIdx.resize(entries.size());
    values.resize(entries.size());
    for (const auto& [rc, v] : entries) {  // by row, then column: each column's rows ascending
      const int p = next[rc.second]++;
      rowIdx[p] = rc.first;
      values[p] = v;
    }
  }
  MatrixXd dense() const {
    MatrixXd a = MatrixXd::Zero(n, n);
    for (int c = 0; c < n; ++c)
      for (int p = colPtr[c]; p < colPtr[c + 1]; ++p) a(rowIdx[p], c) = values[p];
    return a;
  }
};

using Entries = std::map<std::pair<int, int>, double>;

int size(const Entries& e) {
  int n = 0;
  for (const auto& [rc, v] : e) n = std::max({n, rc.first + 1, rc.second + 1});
  return n;
}

// Rows and columns shuffled by the same permutation.
Entries permuted(const Entries& e, int n, std::mt19937& rng) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  Entries out;
  for (const auto& [rc, v] : e) out[{order[rc.first], order[rc.second]}] = v;
  return out;
}

double sign(std::mt19937& rng) { return uniformInt(rng, 0, 1) ? 1.0 : -1.0; }

// A strongly connected block of size nk at offset k1, diagonally dominant by columns: strong
// entries (2 to 3) on the diagonal, or for some pairs of rows crosswise with tiny diagonal entries
// (there KLU pivots off the diagonal), weak ones on a cycle through all rows and elsewhere. A pair
// has no weak entries but the cycle's: fill-in would raise its tiny diagonal just past KLU's pivot
// threshold (1e-3 of the column), and KLU would pivot there. Dominance keeps KLU's pivot growth
// small, so residuals can be held to round-off.
void addIrreducibleBlock(Entries& e, int k1, int nk, double density, std::mt19937& rng) {
  std::vector<char> paired(nk, 0);
  for (int i = 0; i < nk; ++i) e[{k1 + i, k1 + i}] = uniform(rng, 2.0, 3.0) * sign(rng);
  for (int i = 0; i + 1 < nk; i += 2) {
    if (uniformInt(rng, 0, 3) != 0) continue;
    paired[i] = paired[i + 1] = 1;
    e[{k1 + i, k1 + i}] = e[{k1 + i + 1, k1 + i + 1}] = 1e-9;
    e[{k1 + i, k1 + i + 1}] = uniform(rng, 2.0, 3.0) * sign(rng);
    e[{k1 + i + 1, k1 + i}] = uniform(rng, 2.0, 3.0) * sign(rng);
  }
  auto weak = [&](int i, int j) { e.try_emplace({k1 + i, k1 + j}, uniform(rng, 0.05, 0.15) * sign(rng)); };
  for (int i = 0; i < nk; ++i) {
    if (nk > 1) weak(i, (i + 1) % nk);
    for (int j = 0; j < nk; ++j)
      if (!paired[i] && !paired[j] && uniform(rng, 0, 1) < density) weak(i, j);
  }
}

// Block upper triangular, then rows and columns shuffled alike (KLU finds the blocks; the same
// shuffle keeps its matching on the strong entries): diagonal blocks of 1 to maxBlock rows; each
// block coupled to the next one by a dense block (as in a kinematic chain: F by columns), and
// scattered entries further up (F by rows).
Entries blockTriangular(int n, int maxBlock, std::mt19937& rng) {
  Entries e;
  std::vector<int> starts;
  for (int k = 0; k < n;) {
    const int nk = std::min(n - k, uniformInt(rng, 1, maxBlock));
    starts.push_back(k);
    addIrreducibleBlock(e, k, nk, 0.3, rng);
    k += nk;
  }
  starts.push_back(n);
  for (size_t b = 0; b + 2 < starts.size(); ++b) {
    const bool coupled = uniformInt(rng, 0, 2) != 0;
    for (int i = starts[b]; i < starts[b + 1]; ++i) {
      if (coupled)
        for (int j = starts[b + 1]; j < std::min(starts[b + 2], starts[b + 1] + 3); ++j)
          e[{i, j}] = uniform(rng, 0.01, 0.05) * sign(rng);
      const int j = uniformInt(rng, starts[b + 1], n - 1);
      if (uniformInt(rng, 0, 1)) e[{i, j}] = uniform(rng, 0.01, 0.05) * sign(rng);
    }
  }
  return permuted(e, n, rng);
}

// One strongly connected sparse matrix (a single block for KLU), shuffled.
Entries irreducible(int n, std::mt19937& rng) {
  Entries e;
  addIrreducibleBlock(e, 0, n, std::min(0.3, 3.0 / n), rng);
  return permuted(e, n, rng);
}

// [H C^T; C 0] (n = nh + m): H symmetric, diagonally dominant, sparse; C of full row rank with
// its largest entry of row r in column r and smaller ones in columns m and up, so that KLU pairs
// each multiplier with its column through that entry. Zero (2,2) block: every pivot of the
// multipliers is off the diagonal.
Entries saddlePoint(int nh, int m, std::mt19937& rng) {
  Entries e;
  for (int i = 0; i < nh; ++i) {
    e[{i, i}] = uniform(rng, 2.0, 4.0);
    for (int k = 0; k < 2; ++k) {
      const int j = uniformInt(rng, 0, nh - 1);
      if (j != i) e[{i, j}] = e[{j, i}] = uniform(rng, -0.25, 0.25);
    }
  }
  for (int r = 0; r < m; ++r) {
    auto put = [&](int j, double v) { e[{nh + r, j}] = e[{j, nh + r}] = v; };
    put(r, uniform(rng, 1.0, 2.0) * sign(rng));
    if (nh > m)
      for (int k = 0; k < 2; ++k) put(uniformInt(rng, m, nh - 1), uniform(rng, -0.5, 0.5));
  }
  return e;
}

// KLU's own factorisation and solve of the same matrix, as the reference the new solve replaces.
class Klu {
 public:
  Klu(const Csc& a, bool scaling) {
    klu_defaults(&common_);
    if (!scaling) common_.scale = -1;
    symbolic_ = klu_analyze(a.n, const_cast<int*>(a.colPtr.data()), const_cast<int*>(a.rowIdx.data()), &common_);
    numeric_ = klu_factor(const_cast<int*>(a.colPtr.data()), const_cast<int*>(a.rowIdx.data()),
                          const_cast<double*>(a.values.data()), symbolic_, &common_);
  }
  ~Klu() {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
  }
  // Rows whose pivot is off the diagonal (row and column permutations differ there).
  int offDiagonalPivots() const {
    int c = 0;
    for (int k = 0; k < symbolic_->n; ++k) c += numeric_->Pnum[k] != symbolic_->Q[k];
    return c;
  }
  int blocks() const { return symbolic_->nblocks; }
  int largestBlock() const { return symbolic_->maxblock; }
  // klu_refactor with new values of the same pattern (the pivots of the first factorisation).
  bool refactor(const Csc& a) {
    return klu_refactor(const_cast<int*>(a.colPtr.data()), const_cast<int*>(a.rowIdx.data()),
                        const_cast<double*>(a.values.data()), symbolic_, numeric_, &common_);
  }
  MatrixXd solve(MatrixXd b) {
    klu_solve(symbolic_, numeric_, static_cast<int>(b.rows()), static_cast<int>(b.cols()), b.data(), &common_);
    return b;
  }

 private:
  klu_common common_{};
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
};

double relative(const MatrixXd& a, const MatrixXd& ref) {
  return (a - ref).cwiseAbs().maxCoeff() / std::max(ref.cwiseAbs().maxCoeff(), 1e-300);
}

// What the matrices of a test exercised in KLU's factorisation.
struct Coverage {
  int offDiagonalPivots = 0, mostBlocks = 0, largestBlock = 0;
};

// Solves A X = B and A^T X = B for each count of random right-hand sides and compares with the
// dense LU and with klu_solve; lu must hold the factorisation of a.
Coverage expectSolves(SparseLU& lu, const Csc& a, const std::vector<int>& counts, bool scaling, std::mt19937& rng,
                      const char* what) {
  const MatrixXd dense = a.dense();
  const Eigen::PartialPivLU<MatrixXd> ref(dense);
  Klu klu(a, scaling);
  for (const int nrhs : counts) {
    SCOPED_TRACE(::testing::Message() << what << ", n = " << a.n << ", nrhs = " << nrhs
                                      << (scaling ? ", KLU scaling" : ", no scaling"));
    MatrixXd b(a.n, nrhs);
    for (int i = 0; i < b.size(); ++i) b.data()[i] = uniform(rng, -1, 1);

    MatrixXd x = b;
    lu.solve(x.data(), nrhs);
    EXPECT_LT((dense * x - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(relative(x, ref.solve(b)), 1e-10);
    EXPECT_LT(relative(x, klu.solve(b)), 1e-12);

    MatrixXd y = b;
    lu.solveTransposed(y.data(), nrhs);
    EXPECT_LT((dense.transpose() * y - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(relative(y, ref.transpose().solve(b)), 1e-10);
  }
  return {klu.offDiagonalPivots(), klu.blocks(), klu.largestBlock()};
}

Coverage checkFreshFactorisations(const std::vector<Entries>& matrices, const char* what, std::mt19937& rng) {
  Coverage all;
  for (const Entries& e : matrices) {
    const Csc a(size(e), e);
    for (const bool scaling : {true, false}) {
      SparseLU lu;
      if (!scaling) lu.disableScaling();
      lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
      EXPECT_TRUE(lu.factorize(a.values.data())) << what << ", n = " << a.n;
      const Coverage c = expectSolves(lu, a, {1, 2, 3, 5}, scaling, rng, what);
      all.offDiagonalPivots += c.offDiagonalPivots;
      all.mostBlocks = std::max(all.mostBlocks, c.mostBlocks);
      all.largestBlock = std::max(all.largestBlock, c.largestBlock);
    }
  }
  return all;
}

}  // namespace

// The three tests below are slow by design (dense reference LUs up to n = 2000; 30-60 s each under
// the sanitizers): their short runs stop at n = 500, which still has every block kind.
TEST(SparseLU, SolvesBlockTriangularMatricesLikeDenseLUAndKlu) {
  std::mt19937 rng(11);
  std::vector<Entries> matrices;
  for (const int n : {1, 2, 3, 7, 8, 9, 30, 31, 100, 500, 2000}) {
    if (n > 500 && flexmb::test::shortRun()) break;
    matrices.push_back(blockTriangular(n, 4, rng));   // small blocks only (dense LU)
    matrices.push_back(blockTriangular(n, 12, rng));  // small and large blocks
  }
  const Coverage c = checkFreshFactorisations(matrices, "block triangular", rng);
  EXPECT_GT(c.offDiagonalPivots, 0);
  EXPECT_GT(c.mostBlocks, 100);
  EXPECT_GT(c.largestBlock, 8);  // also blocks solved by rows, not as dense LU
}

TEST(SparseLU, SolvesIrreducibleMatricesLikeDenseLUAndKlu) {
  std::mt19937 rng(12);
  std::vector<Entries> matrices;
  for (const int n : {1, 2, 5, 8, 9, 40, 300, 2000})
    if (n <= 500 || !flexmb::test::shortRun()) matrices.push_back(irreducible(n, rng));
  const Coverage c = checkFreshFactorisations(matrices, "irreducible", rng);
  EXPECT_GT(c.offDiagonalPivots, 0);
  EXPECT_EQ(c.mostBlocks, 1);
}

TEST(SparseLU, SolvesSaddlePointMatricesLikeDenseLUAndKlu) {
  std::mt19937 rng(13);
  std::vector<Entries> matrices;
  for (const auto& [nh, m] :
       std::vector<std::pair<int, int>>{{1, 1}, {2, 1}, {4, 3}, {6, 2}, {30, 13}, {300, 100}, {1500, 500}})
    if (nh + m <= 500 || !flexmb::test::shortRun()) matrices.push_back(saddlePoint(nh, m, rng));
  const Coverage c = checkFreshFactorisations(matrices, "saddle point", rng);
  EXPECT_GT(c.offDiagonalPivots, 0);
}

TEST(SparseLU, ManyRightHandSides) {
  std::mt19937 rng(14);
  const Csc a(60, blockTriangular(60, 12, rng));
  SparseLU lu;
  lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
  ASSERT_TRUE(lu.factorize(a.values.data()));
  expectSolves(lu, a, {4, 7, 20}, true, rng, "block triangular");
}

TEST(SparseLU, RefactorisationWithNewValuesSolvesTheNewMatrix) {
  std::mt19937 rng(15);
  for (const Entries& e : {blockTriangular(40, 10, rng), saddlePoint(50, 20, rng), irreducible(25, rng)}) {
    Csc a(size(e), e);
    const std::vector<double> first = a.values;
    SparseLU lu;
    lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
    ASSERT_TRUE(lu.factorize(a.values.data()));
    for (int step = 0; step < 4; ++step) {
      // Same pattern, values moved by up to 20% (the pivot order stays acceptable).
      for (size_t p = 0; p < a.values.size(); ++p) a.values[p] = first[p] * (1.0 + uniform(rng, -0.2, 0.2));
      ASSERT_TRUE(lu.factorize(a.values.data()));
      expectSolves(lu, a, {1, 2, 3}, true, rng, "refactorised");
    }
  }
}

// Normwise backward error of X for A X = B: ||A X - B|| / (||A|| ||X|| + ||B||), infinity norms.
double backwardError(const MatrixXd& a, const MatrixXd& x, const MatrixXd& b) {
  const double na = a.cwiseAbs().rowwise().sum().maxCoeff();
  const double nx = x.cwiseAbs().maxCoeff();
  return (a * x - b).cwiseAbs().maxCoeff() / (na * nx + b.cwiseAbs().maxCoeff());
}

// Factorise once, then refactorise with new values (same pattern, moved by up to 30%) many
// times: every solve against the dense LU (backward error ~1e-16) and against the old path,
// klu_refactor + klu_solve in the first pivot order, to round-off; transposed solves too.
// No fresh pivoting may happen (else the own refactorisation would not be what is tested).
void expectRefactorisations(const Entries& e, bool scaling, int steps, std::mt19937& rng, const char* what) {
  Csc a(size(e), e);
  const std::vector<double> first = a.values;
  SparseLU lu;
  if (!scaling) lu.disableScaling();
  lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
  ASSERT_TRUE(lu.factorize(a.values.data()));
  Klu old(a, scaling);
  for (int step = 0; step < steps; ++step) {
    SCOPED_TRACE(::testing::Message() << what << ", n = " << a.n << ", step " << step
                                      << (scaling ? ", KLU scaling" : ", no scaling"));
    for (size_t p = 0; p < a.values.size(); ++p) a.values[p] = first[p] * (1.0 + uniform(rng, -0.3, 0.3));
    ASSERT_TRUE(lu.factorize(a.values.data()));
    ASSERT_TRUE(old.refactor(a));
    const MatrixXd dense = a.dense();
    const int nrhs = 1 + step % 3;
    MatrixXd b(a.n, nrhs);
    for (int i = 0; i < b.size(); ++i) b.data()[i] = uniform(rng, -1, 1);
    MatrixXd x = b;
    lu.solve(x.data(), nrhs);
    EXPECT_LT(backwardError(dense, x, b), 1e-14);
    EXPECT_LT(relative(x, Eigen::PartialPivLU<MatrixXd>(dense).solve(b)), 1e-10);
    EXPECT_LT(relative(x, old.solve(b)), 1e-13);
    if (step % 5 == 0) {  // A^T through KLU's numeric object, brought up to date from the plan
      MatrixXd y = b;
      lu.solveTransposed(y.data(), nrhs);
      EXPECT_LT(backwardError(dense.transpose(), y, b), 1e-14);
    }
  }
  EXPECT_EQ(lu.pivotings(), 1);
  EXPECT_GT(lu.reciprocalCondition(), 1e-10);
}

TEST(SparseLU, OwnRefactorisationAgreesWithDenseLUAndKluRefactor) {
  std::mt19937 rng(19);
  for (const bool scaling : {false, true}) {
    // Kinematic-Jacobian-like: many blocks of 1 to 7 rows (dense LU in the plan), coupled
    // upwards; then larger blocks (solved by rows) as well.
    for (const int n : {1, 5, 30, 31, 120}) {
      expectRefactorisations(blockTriangular(n, 3, rng), scaling, 40, rng, "block triangular, blocks <= 3");
      expectRefactorisations(blockTriangular(n, 7, rng), scaling, 40, rng, "block triangular, blocks <= 7");
      expectRefactorisations(blockTriangular(n, 14, rng), scaling, 40, rng, "block triangular, blocks <= 14");
    }
    for (const int n : {2, 9, 40, 300}) expectRefactorisations(irreducible(n, rng), scaling, 20, rng, "irreducible");
    for (const auto& [nh, m] : std::vector<std::pair<int, int>>{{2, 1}, {6, 2}, {30, 13}, {200, 70}})
      expectRefactorisations(saddlePoint(nh, m, rng), scaling, 20, rng, "saddle point");
  }
}

TEST(SparseLU, SingularRefactorisationOfALargerMatrix) {
  // A block of a block triangular matrix made singular by new values (a column of zeros): false,
  // and the next regular values are factorised and solved again.
  std::mt19937 rng(20);
  for (const bool scaling : {false, true}) {
    Csc a(60, blockTriangular(60, 7, rng));
    const std::vector<double> regular = a.values;
    SparseLU lu;
    if (!scaling) lu.disableScaling();
    lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
    ASSERT_TRUE(lu.factorize(a.values.data()));
    for (int p = a.colPtr[17]; p < a.colPtr[18]; ++p) a.values[p] = 0.0;
    EXPECT_FALSE(lu.factorize(a.values.data()));
    a.values = regular;
    ASSERT_TRUE(lu.factorize(a.values.data()));
    expectSolves(lu, a, {1, 2}, scaling, rng, "regular again");
  }
}

TEST(SparseLU, PivotsAfreshWhenTheOldPivotsDegrade) {
  // [[10, 1], [1, 10]] pivots on the diagonal; with A(0,0) = 1e-20 that pivot order gives
  // U(1,1) = 10 - 1e20 (the 10 is lost), so the refactorisation must be rejected and redone.
  std::mt19937 rng(16);
  Csc a(2, Entries{{{0, 0}, 10.0}, {{0, 1}, 1.0}, {{1, 0}, 1.0}, {{1, 1}, 10.0}});
  for (const bool scaling : {true, false}) {
    SparseLU lu;
    if (!scaling) lu.disableScaling();
    lu.analyze(2, a.colPtr.data(), a.rowIdx.data());
    a.values = {10.0, 1.0, 1.0, 10.0};
    ASSERT_TRUE(lu.factorize(a.values.data()));
    a.values = {1e-20, 1.0, 1.0, 10.0};
    EXPECT_EQ(lu.pivotings(), 1);
    ASSERT_TRUE(lu.factorize(a.values.data()));
    EXPECT_EQ(lu.pivotings(), 2);  // the old pivots were rejected
    EXPECT_GT(lu.reciprocalCondition(), 1e-10);
    expectSolves(lu, a, {1, 2}, scaling, rng, "after the fallback");
  }
  // The same 2 x 2 block inside a larger matrix with block structure (coupled to it both ways,
  // so that it becomes a block of its own in the middle of the order).
  Entries e = blockTriangular(40, 6, rng);
  e[{40, 40}] = 10.0, e[{40, 41}] = 1.0, e[{41, 40}] = 1.0, e[{41, 41}] = 10.0;
  e[{40, 3}] = 0.05, e[{7, 41}] = 0.05;
  Csc b(42, e);
  const int p00 = b.colPtr[40];  // A(40,40): the first entry of column 40
  SparseLU lu;
  lu.analyze(b.n, b.colPtr.data(), b.rowIdx.data());
  ASSERT_TRUE(lu.factorize(b.values.data()));
  b.values[p00] = 1e-20;
  ASSERT_TRUE(lu.factorize(b.values.data()));
  EXPECT_EQ(lu.pivotings(), 2);
  EXPECT_GT(lu.reciprocalCondition(), 1e-10);
  // Refactorised with these new pivots many times over (the plan's maps follow the new order).
  const std::vector<double> pivoted = b.values;
  for (int step = 0; step < 10; ++step) {
    for (size_t p = 0; p < b.values.size(); ++p) b.values[p] = pivoted[p] * (1.0 + uniform(rng, -0.2, 0.2));
    ASSERT_TRUE(lu.factorize(b.values.data()));
  }
  EXPECT_EQ(lu.pivotings(), 2);
  expectSolves(lu, b, {3}, true, rng, "the 2 x 2 block in a larger matrix");
}

TEST(SparseLU, ReportsSingularMatrices) {
  // Structurally singular: an empty column.
  {
    const Csc a(3, Entries{{{0, 0}, 1.0}, {{1, 0}, 2.0}, {{1, 1}, 1.0}, {{2, 1}, 1.0}});
    SparseLU lu;
    lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
    EXPECT_FALSE(lu.factorize(a.values.data()));
    std::vector<double> b = {1.0, 2.0, 3.0};
    lu.solve(b.data(), 1);  // no factorisation: leaves b alone
    EXPECT_EQ(b, (std::vector<double>{1.0, 2.0, 3.0}));
  }
  // Numerically singular (two equal rows), fresh and as a refactorisation of a regular matrix.
  {
    std::mt19937 rng(17);
    Csc a(3, Entries{{{0, 0}, 1.0},
                     {{0, 1}, 2.0},
                     {{0, 2}, 3.0},
                     {{1, 0}, 1.0},
                     {{1, 1}, 2.0},
                     {{1, 2}, 3.0},
                     {{2, 0}, 4.0},
                     {{2, 1}, 5.0},
                     {{2, 2}, 7.0}});
    SparseLU lu;
    lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
    EXPECT_FALSE(lu.factorize(a.values.data()));
    const std::vector<double> singular = a.values;
    a.values[a.colPtr[1] + 1] = 2.5;  // A(1,1): the rows differ
    ASSERT_TRUE(lu.factorize(a.values.data()));
    expectSolves(lu, a, {2}, true, rng, "regular 3 x 3");
    EXPECT_FALSE(lu.factorize(singular.data()));
  }
}

TEST(SparseLU, EmptySystemAndNoRightHandSides) {
  SparseLU empty;
  empty.analyze(0, nullptr, nullptr);
  EXPECT_TRUE(empty.factorize(nullptr));
  empty.solve(nullptr, 3);
  empty.solveTransposed(nullptr, 1);
  EXPECT_EQ(empty.factorNonzeros(), 0);

  std::mt19937 rng(18);
  const Csc a(10, blockTriangular(10, 3, rng));
  SparseLU lu;
  lu.analyze(a.n, a.colPtr.data(), a.rowIdx.data());
  ASSERT_TRUE(lu.factorize(a.values.data()));
  std::vector<double> b(10, 1.0);
  lu.solve(b.data(), 0);
  EXPECT_EQ(b, std::vector<double>(10, 1.0));
}
