// The Schur complement by an ordered Cholesky factorization (backends/linear/common), with a
// dense kernel written here that records which columns of its factor are read.
#include "cholesky_engine.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace hemivem::linear_detail {
namespace {

/// A dense Cholesky factorization in the order given, the ordering reversing the indices.
class DenseKernel final : public CholeskyKernel {
 public:
  FactorizationResult analyze(const SparseMatrix&) override { return FactorizationResult::good(); }
  FactorizationResult factorize(const SparseMatrix& A) override { return factor(A, &main_); }
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override {
    *X = main_.triangularView<Eigen::Lower>().solve(B);
    main_.triangularView<Eigen::Lower>().transpose().solveInPlace(*X);
    return FactorizationResult::good();
  }
  FactorizationResult order(const SparseMatrix& lower, std::vector<int>* perm) override {
    perm->resize(static_cast<std::size_t>(lower.rows()));
    for (std::size_t k = 0; k < perm->size(); ++k) (*perm)[k] = static_cast<int>(perm->size() - 1 - k);
    return FactorizationResult::good();
  }
  FactorizationResult analyze_ordered(const SparseMatrix& P) override {
    ++ordered_analyses;
    last_P_nonzeros = P.nonZeros();
    return FactorizationResult::good();
  }
  FactorizationResult factorize_ordered(const SparseMatrix& P) override {
    // P holds the lower triangle only.
    const Eigen::MatrixXd D(P);
    auto r = factor(SparseMatrix(Eigen::MatrixXd(D.selfadjointView<Eigen::Lower>()).sparseView()), &ordered_);
    rows_.assign(static_cast<std::size_t>(ordered_.cols()), {});
    values_.assign(static_cast<std::size_t>(ordered_.cols()), {});
    for (Eigen::Index j = 0; j < ordered_.cols(); ++j)
      for (Eigen::Index i = j; i < ordered_.rows(); ++i) {
        rows_[static_cast<std::size_t>(j)].push_back(static_cast<int>(i));
        values_[static_cast<std::size_t>(j)].push_back(ordered_(i, j));
      }
    return r;
  }
  FactorColumn column(int j) const override {
    highest_column = std::max(highest_column, j);
    const auto& rows = rows_[static_cast<std::size_t>(j)];
    return {rows.data(), values_[static_cast<std::size_t>(j)].data(), static_cast<int>(rows.size())};
  }

  int ordered_analyses = 0;
  Eigen::Index last_P_nonzeros = 0;
  mutable int highest_column = -1;

 private:
  static FactorizationResult factor(const SparseMatrix& A, Eigen::MatrixXd* L) {
    Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(A)};
    if (llt.info() != Eigen::Success) return make_result(FactorizationStatus::not_positive_definite, "dense LLT");
    *L = llt.matrixL();
    return FactorizationResult::good();
  }
  Eigen::MatrixXd main_, ordered_;
  std::vector<std::vector<int>> rows_;
  std::vector<std::vector<double>> values_;
};

SparseMatrix random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int t = 0; t < 2; ++t) B(static_cast<int>(rng() % static_cast<unsigned>(n)), j) = u(rng);
  const Eigen::MatrixXd D = B * B.transpose() + Eigen::MatrixXd::Identity(n, n);
  return D.sparseView();
}

struct Blocks {
  std::vector<int> block1, block2;
};

Blocks blocks(int n) {
  Blocks b;
  b.block1 = {n - 2, 3, 7, 1};
  for (int i = 0; i < n; ++i)
    if (std::find(b.block1.begin(), b.block1.end(), i) == b.block1.end()) b.block2.push_back(i);
  return b;
}

Eigen::MatrixXd sub(const Eigen::MatrixXd& A, const std::vector<int>& r, const std::vector<int>& c) {
  Eigen::MatrixXd M(r.size(), c.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t j = 0; j < c.size(); ++j) M(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = A(r[i], c[j]);
  return M;
}

/// A CholeskyEngine with a DenseKernel, and that kernel.
struct DenseEngine {
  DenseEngine() : kernel(new DenseKernel), engine(std::unique_ptr<CholeskyKernel>(kernel), "dense") {}
  DenseKernel* kernel;
  CholeskyEngine engine;
};

TEST(CholeskyEngine, SchurComplementAndInteriorSolveMatchDenseBlocks) {
  const int n = 30;
  const SparseMatrix A = random_spd(n, 3);
  const Eigen::MatrixXd D(A);
  const Blocks b = blocks(n);
  DenseEngine dense;
  DenseKernel& k = *dense.kernel;
  CholeskyEngine& engine = dense.engine;
  Eigen::MatrixXd S, X2;
  ASSERT_TRUE(engine.schur_complement(A, b.block1, &S).ok());
  const Eigen::MatrixXd A22 = sub(D, b.block2, b.block2), A12 = sub(D, b.block1, b.block2);
  const Eigen::MatrixXd reference = sub(D, b.block1, b.block1) - A12 * A22.llt().solve(A12.transpose());
  EXPECT_LT((S - reference).norm(), 1e-12 * reference.norm());
  // P is the lower triangle of A: the stored entries on and below the diagonal.
  EXPECT_EQ(k.last_P_nonzeros, (A.nonZeros() + n) / 2);

  k.highest_column = -1;
  const Eigen::MatrixXd B2 = Eigen::MatrixXd::Random(n - 4, 3);
  ASSERT_TRUE(engine.solve_interior(B2, &X2).ok());
  EXPECT_LT((A22 * X2 - B2).norm(), 1e-12 * B2.norm());
  EXPECT_EQ(k.highest_column, n - 5) << "the interior solve reads the columns of L22 only";
}

TEST(CholeskyEngine, NewValuesOnThePatternAreCopiedWithoutANewAnalysis) {
  const int n = 25;
  const SparseMatrix A = random_spd(n, 4);
  SparseMatrix C = A;
  for (Eigen::Index p = 0; p < C.nonZeros(); ++p) C.valuePtr()[p] *= 2.0;
  const Blocks b = blocks(n);
  DenseEngine dense;
  Eigen::MatrixXd S1, S2;
  CholeskyEngine& engine = dense.engine;
  ASSERT_TRUE(engine.schur_complement(A, b.block1, &S1).ok());
  ASSERT_TRUE(engine.schur_complement(C, b.block1, &S2).ok());
  EXPECT_EQ(dense.kernel->ordered_analyses, 1);
  EXPECT_EQ(engine.num_analyses(), 1);
  EXPECT_LT((S2 - 2.0 * S1).norm(), 1e-12 * S1.norm());
  const std::vector<int> other = {0, 5};
  ASSERT_TRUE(engine.schur_complement(C, other, &S2).ok());
  EXPECT_EQ(dense.kernel->ordered_analyses, 2) << "another block1 is another elimination order";
}

TEST(CholeskyEngine, PivotOfAFailureIsNamedInA) {
  // A22 = diag(1, 2) is positive definite, the Schur complement of index 0 is not.
  Eigen::Matrix3d D;
  D << 1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 2.0;
  class Failing final : public CholeskyKernel {
   public:
    FactorizationResult analyze(const SparseMatrix&) override { return FactorizationResult::good(); }
    FactorizationResult factorize(const SparseMatrix&) override { return FactorizationResult::good(); }
    FactorizationResult solve(const Eigen::MatrixXd&, Eigen::MatrixXd*) const override {
      return FactorizationResult::good();
    }
    FactorizationResult order(const SparseMatrix& lower, std::vector<int>* perm) override {
      perm->resize(static_cast<std::size_t>(lower.rows()));
      for (std::size_t k = 0; k < perm->size(); ++k) (*perm)[k] = static_cast<int>(k);
      return FactorizationResult::good();
    }
    FactorizationResult analyze_ordered(const SparseMatrix&) override { return FactorizationResult::good(); }
    FactorizationResult factorize_ordered(const SparseMatrix&) override {
      return make_result(FactorizationStatus::not_positive_definite, "not positive definite");
    }
    FactorColumn column(int) const override { return {}; }
    int failed_pivot() const override { return 2; }
  };
  CholeskyEngine engine(std::make_unique<Failing>(), "failing");
  Eigen::MatrixXd S;
  const FactorizationResult r = engine.schur_complement(SparseMatrix(D.sparseView()), std::vector<int>{0}, &S);
  EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite);
  EXPECT_NE(r.message.find("index 0 of A"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("A22 is positive definite but its Schur complement is not"), std::string::npos)
      << r.message;
}

}  // namespace
}  // namespace hemivem::linear_detail
