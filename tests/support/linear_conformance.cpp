#include "linear_conformance.hpp"

#include "linear_support.hpp"

#include <hemivem/error.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

namespace hemivem::test {

void PrintTo(const LinearEngine& engine, std::ostream* os) { *os << '"' << engine.name << '"'; }

std::string engine_test_name(const ::testing::TestParamInfo<LinearEngine>& info) {
  std::string name = info.param.name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

namespace {

constexpr double kTolerance = 1e-10;
const std::vector<int> kSizes = {1, 5, 40, 200};
const std::vector<unsigned> kSeeds = {1, 2, 3};

using Triplet = Eigen::Triplet<double, int>;

/// The same pattern as A with other (still SPD) values: A + t diag(A) scaled off-diagonal.
SparseMatrix same_pattern_new_values(const SparseMatrix& A, double t) {
  SparseMatrix C = A;
  for (int j = 0; j < C.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(C, j); it; ++it)
      it.valueRef() = it.row() == it.col() ? it.value() * (1.0 + t) : it.value() * (1.0 - 0.5 * t);
  return C;
}

Eigen::MatrixXd submatrix(const Eigen::MatrixXd& A, const std::vector<int>& rows, const std::vector<int>& cols) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < cols.size(); ++c)
      out(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = A(rows[r], cols[c]);
  return out;
}

}  // namespace

void expect_solves_match_dense_reference(SparseFactorization& f, const SparseMatrix& A, unsigned seed) {
  const Eigen::LLT<Eigen::MatrixXd> reference{Eigen::MatrixXd(A)};
  ASSERT_EQ(reference.info(), Eigen::Success);
  const FactorizationResult r = f.factorize(A);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  for (Eigen::Index columns : {1, 4}) {
    const Eigen::MatrixXd B = random_matrix(A.rows(), columns, seed);
    Eigen::MatrixXd X;
    const FactorizationResult s = f.solve(B, &X);
    ASSERT_TRUE(s.ok()) << s.message;
    EXPECT_LT(relative_error(X, reference.solve(B)), kTolerance) << columns << " right-hand sides";
  }
  const double rcond = f.rcond_estimate();
  if (rcond >= 0) {
    EXPECT_GT(rcond, 0.0);
    EXPECT_LE(rcond, 1.0);
  }
}

void expect_schur_complement_matches_dense_reference(SparseFactorization& f, const SparseMatrix& A,
                                                     const std::vector<int>& block1, unsigned seed) {
  const Eigen::MatrixXd D(A);
  const std::vector<int> block2 = complement(static_cast<int>(A.rows()), block1);
  const Eigen::MatrixXd A11 = submatrix(D, block1, block1), A12 = submatrix(D, block1, block2),
                        A22 = submatrix(D, block2, block2);
  const Eigen::LLT<Eigen::MatrixXd> llt22(A22);
  const Eigen::MatrixXd S_reference =
      block2.empty() ? A11 : Eigen::MatrixXd(A11 - A12 * llt22.solve(A12.transpose()));

  Eigen::MatrixXd S;
  const FactorizationResult r = f.schur_complement(A, block1, &S);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  EXPECT_LT(relative_error(S, S_reference), kTolerance);

  // one to four right-hand sides take the engines' few-column substitutions, more the blocked ones
  for (Eigen::Index columns : {1, 2, 3, 4, 5, 9}) {
    const Eigen::MatrixXd B2 = random_matrix(static_cast<Eigen::Index>(block2.size()), columns, seed);
    Eigen::MatrixXd X2;
    const FactorizationResult s = f.solve_interior(B2, &X2);
    ASSERT_TRUE(s.ok()) << s.message;
    if (!block2.empty()) {
      EXPECT_LT(relative_error(X2, llt22.solve(B2)), kTolerance) << columns << " right-hand sides";
    } else {
      EXPECT_EQ(X2.rows(), 0);
      EXPECT_EQ(X2.cols(), columns);
    }
  }
}

namespace {

TEST_P(LinearConformance, NameIsTheEngineName) { EXPECT_EQ(make()->name(), engine()); }

TEST_P(LinearConformance, SolveMatchesDenseReference) {
  for (int n : kSizes) {
    for (unsigned seed : kSeeds) {
      SCOPED_TRACE("n = " + std::to_string(n) + ", seed = " + std::to_string(seed));
      auto f = make();
      expect_solves_match_dense_reference(*f, random_spd(n, seed), seed);
      if (HasFatalFailure()) return;
    }
  }
}

TEST_P(LinearConformance, SchurComplementMatchesDenseReference) {
  for (int n : kSizes) {
    for (unsigned seed : kSeeds) {
      SCOPED_TRACE("n = " + std::to_string(n) + ", seed = " + std::to_string(seed));
      auto f = make();
      expect_schur_complement_matches_dense_reference(*f, random_spd(n, seed), random_block(n, std::max(1, n / 5), seed),
                                                      seed);
      if (HasFatalFailure()) return;
    }
  }
}

// Every engine answers a matrix whose entries are all tiny or all huge as it answers the same
// matrix at unit scale: no absolute pivot threshold may decide (a matrix scaled by 1e-16 once
// came back from MUMPS wrongly factorized and reported as a success).
TEST_P(LinearConformance, SolvesAndSchurComplementsDoNotDependOnTheScale) {
  for (const double scale : {1e-120, 1e-16, 1e16, 1e120}) {
    SCOPED_TRACE("scale " + std::to_string(scale));
    const SparseMatrix A = SparseMatrix(random_spd(40, 3) * scale);
    auto f = make();
    expect_solves_match_dense_reference(*f, A, 3);
    if (HasFatalFailure()) return;
    auto g = make();
    expect_schur_complement_matches_dense_reference(*g, A, random_block(40, 8, 3), 3);
    if (HasFatalFailure()) return;
  }
}

/// The 5-point Laplacian of an m x m grid plus the identity: a matrix whose factor has large
/// supernodes, as a contact problem's has.
SparseMatrix grid_laplacian(int m) {
  std::vector<Triplet> entries;
  auto id = [m](int i, int j) { return i * m + j; };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      entries.emplace_back(id(i, j), id(i, j), 5.0);
      if (i + 1 < m) entries.emplace_back(id(i + 1, j), id(i, j), -1.0), entries.emplace_back(id(i, j), id(i + 1, j), -1.0);
      if (j + 1 < m) entries.emplace_back(id(i, j + 1), id(i, j), -1.0), entries.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

/// condense_rhs() and expand() against c = b1 - A12 A22^{-1} b2 and x2 = A22^{-1} (b2 - A21 x1).
void expect_split_interior_solve(SparseFactorization& f, const SparseMatrix& A, const std::vector<int>& block1,
                                 unsigned seed) {
  const int n = static_cast<int>(A.rows());
  const std::vector<int> block2 = complement(n, block1);
  const Eigen::MatrixXd D(A);
  const Eigen::MatrixXd A12 = submatrix(D, block1, block2), A22 = submatrix(D, block2, block2);
  Eigen::MatrixXd S;
  ASSERT_TRUE(f.schur_complement(A, block1, &S).ok());
  const Eigen::VectorXd b1 = random_matrix(static_cast<Eigen::Index>(block1.size()), 1, seed).col(0);
  const Eigen::VectorXd b2 = random_matrix(static_cast<Eigen::Index>(block2.size()), 1, seed + 1).col(0);
  const Eigen::VectorXd x1 = random_matrix(static_cast<Eigen::Index>(block1.size()), 1, seed + 2).col(0);
  Eigen::VectorXd c, x2;
  SplitInteriorSolve* split = split_interior_solve(f);
  if (split == nullptr) return;
  const FactorizationResult r = split->condense_rhs(b1, b2, &c);
  ASSERT_TRUE(r.ok()) << r.message;
  const FactorizationResult e = split->expand(x1, &x2);
  ASSERT_TRUE(e.ok()) << e.message;
  if (block2.empty()) {
    EXPECT_EQ(c, b1);
    EXPECT_EQ(x2.size(), 0);
    return;
  }
  const Eigen::LLT<Eigen::MatrixXd> llt22(A22);
  EXPECT_LT(relative_error(c, b1 - A12 * llt22.solve(b2)), kTolerance);
  EXPECT_LT(relative_error(x2, llt22.solve(b2 - A12.transpose() * x1)), kTolerance);
  // expand() again with another x1 uses the same b2
  const Eigen::VectorXd x1b = 2.0 * x1;
  ASSERT_TRUE(split->expand(x1b, &x2).ok());
  EXPECT_LT(relative_error(x2, llt22.solve(b2 - A12.transpose() * x1b)), kTolerance);
}

TEST_P(LinearConformance, SplitInteriorSolveMatchesDenseReference) {
  for (int n : kSizes) {
    for (unsigned seed : kSeeds) {
      for (int size1 : {std::max(1, n / 5), n}) {
        SCOPED_TRACE("n = " + std::to_string(n) + ", seed = " + std::to_string(seed) + ", block1 " + std::to_string(size1));
        auto f = make();
        expect_split_interior_solve(*f, random_spd(n, seed), random_block(n, size1, seed), seed);
      }
    }
  }
  // a grid with block1 one side of it (as a contact boundary) and a random block1
  const int m = 30;
  std::vector<int> side(static_cast<std::size_t>(m));
  std::iota(side.begin(), side.end(), 0);
  auto f = make();
  {
    SCOPED_TRACE("grid, one side");
    expect_split_interior_solve(*f, grid_laplacian(m), side, 4);
  }
  {
    SCOPED_TRACE("grid, random block1");
    expect_split_interior_solve(*f, grid_laplacian(m), random_block(m * m, 2 * m, 5), 5);
  }
}

// One engine splitting a grid's interior from one side, then from every index (nothing to
// eliminate), then from the side again: each split interior solve is that of its own block1,
// whatever the engine kept of the split before.
TEST_P(LinearConformance, SplitInteriorSolveAfterAnotherSplitOfTheSameEngine) {
  const int m = 30;
  const SparseMatrix A = grid_laplacian(m);
  std::vector<int> side(static_cast<std::size_t>(m)), every(static_cast<std::size_t>(m * m));
  std::iota(side.begin(), side.end(), 0);
  std::iota(every.begin(), every.end(), 0);
  auto f = make();
  for (const auto* block1 : {&side, &every, &side}) {
    SCOPED_TRACE("block1 of " + std::to_string(block1->size()));
    expect_split_interior_solve(*f, A, *block1, 6);
  }
}

TEST_P(LinearConformance, SplitInteriorSolveOutOfOrderOrWithWrongSizes) {
  auto f = make();
  SplitInteriorSolve* split = split_interior_solve(*f);
  if (split == nullptr) GTEST_SKIP() << engine() << " does not split the interior solve";
  Eigen::VectorXd c, x2;
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(1), four = Eigen::VectorXd::Ones(4);
  EXPECT_THROW(split->condense_rhs(one, four, &c), InternalError);
  EXPECT_THROW(split->expand(one, &x2), InternalError);
  const SparseMatrix A = random_spd(5, 2);
  const std::vector<int> block1{3};
  Eigen::MatrixXd S;
  ASSERT_TRUE(f->schur_complement(A, block1, &S).ok());
  EXPECT_THROW(split->expand(one, &x2), InternalError) << "expand() needs condense_rhs() first";
  EXPECT_THROW(split->condense_rhs(four, four, &c), InternalError);
  EXPECT_THROW(split->condense_rhs(one, one, &c), InternalError);
  EXPECT_THROW(split->condense_rhs(one, four, nullptr), InternalError);
  ASSERT_TRUE(split->condense_rhs(one, four, &c).ok());
  EXPECT_THROW(split->expand(four, &x2), InternalError);
  EXPECT_THROW(split->expand(one, nullptr), InternalError);
  ASSERT_TRUE(split->expand(one, &x2).ok());
  ASSERT_TRUE(f->schur_complement(A, block1, &S).ok());
  EXPECT_THROW(split->expand(one, &x2), InternalError) << "a new Schur complement forgets b2";
}

TEST_P(LinearConformance, RefactorizationOnTheSamePatternReusesTheAnalysis) {
  const int n = 200;
  const SparseMatrix A = random_spd(n, 5);
  const SparseMatrix C = same_pattern_new_values(A, 0.3);
  auto f = make();
  if (f->num_analyses() < 0) GTEST_SKIP() << engine() << " does not count its analyses";
  ASSERT_TRUE(f->analyze(A).ok());
  ASSERT_EQ(f->num_analyses(), 1);
  ASSERT_TRUE(f->factorize(A).ok());
  EXPECT_EQ(f->num_analyses(), 1) << "factorize() repeated the analysis of an analysed pattern";
  const FactorizationResult r = f->factorize(C);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(f->num_analyses(), 1) << "new values on the same pattern must not trigger an analysis";

  const Eigen::MatrixXd B = random_matrix(n, 2, 5);
  Eigen::MatrixXd X;
  ASSERT_TRUE(f->solve(B, &X).ok());
  EXPECT_LT(relative_error(X, Eigen::MatrixXd(C).llt().solve(B)), kTolerance);
}

TEST_P(LinearConformance, PatternChangeTriggersANewAnalysis) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 1);
  const SparseMatrix C = random_spd(n, 2);  // another pattern
  const SparseMatrix E = random_spd(n + 1, 1);  // another size
  auto f = make();
  if (f->num_analyses() < 0) GTEST_SKIP() << engine() << " does not count its analyses";
  ASSERT_TRUE(f->factorize(A).ok());
  EXPECT_EQ(f->num_analyses(), 1);
  ASSERT_TRUE(f->factorize(C).ok());
  EXPECT_EQ(f->num_analyses(), 2);
  const Eigen::MatrixXd B = random_matrix(n, 1, 3);
  Eigen::MatrixXd X;
  ASSERT_TRUE(f->solve(B, &X).ok());
  EXPECT_LT(relative_error(X, Eigen::MatrixXd(C).llt().solve(B)), kTolerance);
  ASSERT_TRUE(f->factorize(E).ok());
  EXPECT_EQ(f->num_analyses(), 3);
  ASSERT_TRUE(f->solve(random_matrix(n + 1, 1, 3), &X).ok());
  EXPECT_EQ(X.rows(), n + 1);
}

TEST_P(LinearConformance, SchurComplementReusesItsAnalysis) {
  const int n = 200;
  const SparseMatrix A = random_spd(n, 4);
  const SparseMatrix C = same_pattern_new_values(A, 0.2);
  const std::vector<int> block1 = random_block(n, 30, 4);
  auto f = make();
  if (f->num_analyses() < 0) GTEST_SKIP() << engine() << " does not count its analyses";
  Eigen::MatrixXd S;
  ASSERT_TRUE(f->schur_complement(A, block1, &S).ok());
  const int after_first = f->num_analyses();
  EXPECT_GE(after_first, 1);
  ASSERT_TRUE(f->schur_complement(C, block1, &S).ok());
  EXPECT_EQ(f->num_analyses(), after_first) << "same pattern and block1 must reuse the analysis";

  const Eigen::MatrixXd D(C);
  const std::vector<int> block2 = complement(n, block1);
  const Eigen::MatrixXd S_reference =
      submatrix(D, block1, block1) -
      submatrix(D, block1, block2) * submatrix(D, block2, block2).llt().solve(submatrix(D, block2, block1));
  EXPECT_LT(relative_error(S, S_reference), kTolerance);

  ASSERT_TRUE(f->schur_complement(C, random_block(n, 30, 9), &S).ok());
  EXPECT_GT(f->num_analyses(), after_first) << "another block1 needs another analysis";
}

TEST_P(LinearConformance, SmallIndefiniteMatrixIsNotPositiveDefinite) {
  SparseMatrix A(3, 3);
  A.insert(0, 0) = 1.0;
  A.insert(1, 1) = -1.0;
  A.insert(2, 2) = 2.0;
  A.makeCompressed();
  auto f = make();
  const FactorizationResult r = f->factorize(A);
  EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite) << r.message;
  EXPECT_FALSE(r.message.empty());
  Eigen::MatrixXd X;
  EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(3, 1), &X), InternalError)
      << "a failed factorization cannot be used to solve";

  Eigen::MatrixXd S;
  const std::vector<int> block1 = {2};  // A22 = diag(1, -1)
  EXPECT_EQ(f->schur_complement(A, block1, &S).status, FactorizationStatus::not_positive_definite);
  EXPECT_THROW(f->solve_interior(Eigen::MatrixXd::Ones(2, 1), &X), InternalError);
}

TEST_P(LinearConformance, MatrixWithOneNegativeEigenvalueIsNotPositiveDefinite) {
  for (int n : {40, 200}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const SparseMatrix A = one_negative_eigenvalue(n, 11);
    auto f = make();
    const FactorizationResult r = f->factorize(A);
    EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite) << r.message;
    Eigen::MatrixXd S;
    const FactorizationResult s = f->schur_complement(A, std::vector<int>{}, &S);  // A22 = A
    EXPECT_EQ(s.status, FactorizationStatus::not_positive_definite) << s.message;
  }
}

TEST_P(LinearConformance, CallsOutOfOrderThrow) {
  auto f = make();
  Eigen::MatrixXd X;
  EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(5, 1), &X), InternalError);
  EXPECT_THROW(f->solve_interior(Eigen::MatrixXd::Ones(5, 1), &X), InternalError);
  ASSERT_TRUE(f->analyze(random_spd(5, 1)).ok());
  EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(5, 1), &X), InternalError)
      << "analyze() alone does not allow a solve";
}

TEST_P(LinearConformance, WrongSizesThrow) {
  const SparseMatrix A = random_spd(5, 1);
  auto f = make();
  ASSERT_TRUE(f->factorize(A).ok());
  Eigen::MatrixXd X;
  EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(4, 1), &X), InternalError);
  EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(6, 2), &X), InternalError);
  EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(5, 1), nullptr), InternalError);
  try {
    (void)f->solve(Eigen::MatrixXd::Ones(4, 1), &X);
    ADD_FAILURE() << "expected an InternalError";
  } catch (const InternalError& e) {
    EXPECT_FALSE(std::string(e.what()).empty());
  }

  Eigen::MatrixXd S;
  const std::vector<int> block1 = {3, 1};
  ASSERT_TRUE(f->schur_complement(A, block1, &S).ok());
  EXPECT_THROW(f->solve_interior(Eigen::MatrixXd::Ones(5, 1), &X), InternalError);
  EXPECT_THROW(f->solve_interior(Eigen::MatrixXd::Ones(2, 1), &X), InternalError);
  EXPECT_TRUE(f->solve_interior(Eigen::MatrixXd::Ones(3, 1), &X).ok());
  EXPECT_THROW(f->schur_complement(A, block1, nullptr), InternalError);

  SparseMatrix rectangular(4, 5);
  rectangular.insert(0, 0) = 1.0;
  EXPECT_THROW(f->analyze(rectangular), InternalError);
  EXPECT_THROW(f->factorize(rectangular), InternalError);
  EXPECT_THROW(f->schur_complement(rectangular, block1, &S), InternalError);
}

TEST_P(LinearConformance, InvalidBlock1Throws) {
  const SparseMatrix A = random_spd(5, 2);
  auto f = make();
  Eigen::MatrixXd S;
  for (const std::vector<int>& block1 :
       {std::vector<int>{1, 3, 1}, std::vector<int>{5}, std::vector<int>{0, -1}, std::vector<int>{0, 1, 2, 3, 4, 0}}) {
    try {
      (void)f->schur_complement(A, block1, &S);
      ADD_FAILURE() << "expected an InternalError";
    } catch (const InternalError& e) {
      EXPECT_FALSE(std::string(e.what()).empty());
    }
  }
  Eigen::MatrixXd X;
  EXPECT_THROW(f->solve_interior(Eigen::MatrixXd::Ones(3, 1), &X), InternalError);
}

TEST_P(LinearConformance, EmptyBlock1GivesAnEmptySchurComplement) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 3);
  auto f = make();
  Eigen::MatrixXd S = Eigen::MatrixXd::Ones(2, 2);
  const FactorizationResult r = f->schur_complement(A, std::vector<int>{}, &S);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(S.rows(), 0);
  EXPECT_EQ(S.cols(), 0);
  const Eigen::MatrixXd B = random_matrix(n, 2, 3);
  Eigen::MatrixXd X;
  ASSERT_TRUE(f->solve_interior(B, &X).ok());
  EXPECT_LT(relative_error(X, Eigen::MatrixXd(A).llt().solve(B)), kTolerance);
}

TEST_P(LinearConformance, Block1WithEveryIndexGivesTheMatrix) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 3);
  std::vector<int> block1(n);
  std::iota(block1.rbegin(), block1.rend(), 0);  // n-1, ..., 0
  auto f = make();
  Eigen::MatrixXd S;
  const FactorizationResult r = f->schur_complement(A, block1, &S);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(relative_error(S, submatrix(Eigen::MatrixXd(A), block1, block1)), kTolerance);
  Eigen::MatrixXd X;
  ASSERT_TRUE(f->solve_interior(Eigen::MatrixXd(0, 2), &X).ok());
  EXPECT_EQ(X.rows(), 0);
}

TEST_P(LinearConformance, UncompressedInputIsAccepted) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 6);
  SparseMatrix U(n, n);
  U.reserve(Eigen::VectorXi::Constant(n, 40));
  for (int j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) U.insert(it.row(), it.col()) = it.value();
  ASSERT_FALSE(U.isCompressed());
  auto f = make();
  ASSERT_TRUE(f->factorize(U).ok());
  const Eigen::MatrixXd B = random_matrix(n, 1, 6);
  Eigen::MatrixXd X;
  ASSERT_TRUE(f->solve(B, &X).ok());
  EXPECT_LT(relative_error(X, Eigen::MatrixXd(A).llt().solve(B)), kTolerance);
  Eigen::MatrixXd S;
  ASSERT_TRUE(f->schur_complement(U, random_block(n, 5, 6), &S).ok());
  EXPECT_EQ(S.rows(), 5);
}

TEST_P(LinearConformance, NonFiniteEntriesAreANumericalFailure) {
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    SparseMatrix A = random_spd(20, 7);
    A.coeffRef(4, 4) = bad;
    auto f = make();
    const FactorizationResult r = f->factorize(A);
    EXPECT_EQ(r.status, FactorizationStatus::numerical_failure) << r.message;
    Eigen::MatrixXd X, S;
    EXPECT_THROW(f->solve(Eigen::MatrixXd::Ones(20, 1), &X), InternalError);
    const FactorizationResult s = f->schur_complement(A, std::vector<int>{1, 4, 9}, &S);
    EXPECT_EQ(s.status, FactorizationStatus::numerical_failure) << s.message;
    EXPECT_THROW(f->solve_interior(Eigen::MatrixXd::Ones(17, 1), &X), InternalError);
  }
}

TEST_P(LinearConformance, InteriorSolveAfterAReusedAnalysisUsesTheNewValues) {
  const int n = 120;
  const SparseMatrix A = random_spd(n, 8);
  const SparseMatrix C = same_pattern_new_values(A, 0.4);
  const std::vector<int> block1 = random_block(n, 17, 8);
  const std::vector<int> block2 = complement(n, block1);
  auto f = make();
  Eigen::MatrixXd S, X2;
  ASSERT_TRUE(f->schur_complement(A, block1, &S).ok());
  ASSERT_TRUE(f->schur_complement(C, block1, &S).ok());
  const Eigen::MatrixXd B2 = random_matrix(static_cast<Eigen::Index>(block2.size()), 2, 8);
  ASSERT_TRUE(f->solve_interior(B2, &X2).ok());
  EXPECT_LT(relative_error(X2, submatrix(Eigen::MatrixXd(C), block2, block2).llt().solve(B2)), kTolerance);
}

}  // namespace
}  // namespace hemivem::test
