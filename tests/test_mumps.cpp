// The sequential MUMPS engine against dense Eigen references.
#include <hemivem/error.hpp>
#include <hemivem/mumps_factorization.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "linear_support.hpp"

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace {

using hemivem::FactorizationStatus;
using hemivem::InternalError;
using hemivem::MumpsFactorization;
using hemivem::SparseMatrix;
using hemivem::test::complement;
using hemivem::test::random_block;
using hemivem::test::random_matrix;
using hemivem::test::relative_error;

/// A random sparse SPD matrix B Bᵀ + shift·I with both triangles stored.
SparseMatrix random_spd(int n, unsigned seed, double shift = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> row(0, n - 1);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j) {
    t.emplace_back(j, j, value(rng));
    for (int k = 0; k < 2; ++k) t.emplace_back(row(rng), j, value(rng));
  }
  SparseMatrix B(n, n);
  B.setFromTriplets(t.begin(), t.end());
  SparseMatrix I(n, n);
  I.setIdentity();
  SparseMatrix A = SparseMatrix(B * B.transpose()) + shift * I;
  A.makeCompressed();
  return A;
}

SparseMatrix from_dense(const Eigen::MatrixXd& D) {
  SparseMatrix A = D.sparseView();
  A.makeCompressed();
  return A;
}

constexpr double kTolerance = 1e-10;

// ---- solves ------------------------------------------------------------------------------

class MumpsSizes : public ::testing::TestWithParam<int> {};

TEST_P(MumpsSizes, SolveMatchesDenseCholesky) {
  const int n = GetParam();
  const SparseMatrix A = random_spd(n, 11u + static_cast<unsigned>(n));
  const Eigen::MatrixXd D = A;
  const Eigen::LLT<Eigen::MatrixXd> llt(D);
  ASSERT_EQ(llt.info(), Eigen::Success);

  MumpsFactorization mumps;
  EXPECT_EQ(mumps.name(), "mumps");
  const auto f = mumps.factorize(A);
  ASSERT_TRUE(f.ok()) << f.message;

  const Eigen::MatrixXd b = random_matrix(n, 1, 3);
  Eigen::MatrixXd x;
  const auto s = mumps.solve(b, &x);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_LT(relative_error(x, llt.solve(b)), kTolerance);
}

TEST_P(MumpsSizes, MultipleRightHandSides) {
  const int n = GetParam();
  const SparseMatrix A = random_spd(n, 21u + static_cast<unsigned>(n));
  const Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(A)};

  MumpsFactorization mumps;
  ASSERT_TRUE(mumps.analyze(A).ok());
  ASSERT_TRUE(mumps.factorize(A).ok());
  EXPECT_EQ(mumps.num_analyses(), 1);

  const Eigen::MatrixXd B = random_matrix(n, 7, 5);
  Eigen::MatrixXd X;
  const auto s = mumps.solve(B, &X);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_EQ(X.rows(), n);
  ASSERT_EQ(X.cols(), 7);
  EXPECT_LT(relative_error(X, llt.solve(B)), kTolerance);

  // No right-hand side at all is not an error.
  Eigen::MatrixXd X0;
  ASSERT_TRUE(mumps.solve(Eigen::MatrixXd(n, 0), &X0).ok());
  EXPECT_EQ(X0.rows(), n);
  EXPECT_EQ(X0.cols(), 0);
}

TEST_P(MumpsSizes, SchurComplementAndInteriorSolveMatchDenseBlocks) {
  const int n = GetParam();
  const SparseMatrix A = random_spd(n, 31u + static_cast<unsigned>(n));
  const Eigen::MatrixXd D = A;
  const int n1 = std::max(1, n / 5);  // n = 1: block1 is everything, A22 is empty
  const std::vector<int> block1 = random_block(n, n1, 7);
  const std::vector<int> block2 = complement(n, block1);

  const Eigen::MatrixXd A11 = D(block1, block1);
  const Eigen::MatrixXd A12 = D(block1, block2);
  const Eigen::MatrixXd A22 = D(block2, block2);
  const Eigen::LLT<Eigen::MatrixXd> llt22(A22);
  const Eigen::MatrixXd S_ref = n > n1 ? Eigen::MatrixXd(A11 - A12 * llt22.solve(A12.transpose())) : A11;

  MumpsFactorization mumps;
  Eigen::MatrixXd S;
  const auto r = mumps.schur_complement(A, block1, &S);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(S.rows(), n1);
  ASSERT_EQ(S.cols(), n1);
  EXPECT_LT(relative_error(S, S_ref), kTolerance);
  EXPECT_EQ(S, S.transpose());

  const Eigen::MatrixXd B2 = random_matrix(n - n1, 3, 9);
  Eigen::MatrixXd X2;
  const auto s = mumps.solve_interior(B2, &X2);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_EQ(X2.rows(), n - n1);
  ASSERT_EQ(X2.cols(), 3);
  if (n > n1) EXPECT_LT(relative_error(X2, llt22.solve(B2)), kTolerance);

  // The same pattern and block1 again: the analysis is reused, S follows the new values.
  const SparseMatrix A2 = 2.0 * A;
  ASSERT_TRUE(mumps.schur_complement(A2, block1, &S).ok());
  EXPECT_EQ(mumps.num_analyses(), n > n1 ? 1 : 0);  // block1 = everything: no sparse work
  EXPECT_LT(relative_error(S, 2.0 * S_ref), kTolerance);
}

INSTANTIATE_TEST_SUITE_P(Sizes, MumpsSizes, ::testing::Values(1, 5, 40, 200));

// ---- analysis reuse --------------------------------------------------------------------

TEST(Mumps, RefactorizesWithoutNewAnalysisWhileThePatternHolds) {
  const int n = 200;
  const SparseMatrix A = random_spd(n, 41);
  MumpsFactorization mumps;
  ASSERT_TRUE(mumps.factorize(A).ok());
  EXPECT_EQ(mumps.num_analyses(), 1);

  // New values on the same pattern (still SPD): no new analysis.
  SparseMatrix A2 = A;
  for (int k = 0; k < A2.nonZeros(); ++k) A2.valuePtr()[k] *= 0.5;
  A2.diagonal().array() += 3.0;
  ASSERT_TRUE(mumps.factorize(A2).ok());
  EXPECT_EQ(mumps.num_analyses(), 1);
  EXPECT_EQ(mumps.num_factorizations(), 2);
  const Eigen::MatrixXd b = random_matrix(n, 2, 13);
  Eigen::MatrixXd x;
  ASSERT_TRUE(mumps.solve(b, &x).ok());
  EXPECT_LT(relative_error(x, Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd(A2)).solve(b)), kTolerance);

  // A different pattern: a new analysis.
  const SparseMatrix A3 = random_spd(n, 43);
  ASSERT_TRUE(mumps.factorize(A3).ok());
  EXPECT_EQ(mumps.num_analyses(), 2);
  ASSERT_TRUE(mumps.solve(b, &x).ok());
  EXPECT_LT(relative_error(x, Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd(A3)).solve(b)), kTolerance);
}

TEST(Mumps, AcceptsAnUncompressedMatrix) {
  const SparseMatrix A = random_spd(40, 47);
  SparseMatrix U = A;
  U.uncompress();
  ASSERT_FALSE(U.isCompressed());
  MumpsFactorization mumps;
  ASSERT_TRUE(mumps.factorize(U).ok());
  ASSERT_TRUE(mumps.factorize(A).ok());
  EXPECT_EQ(mumps.num_analyses(), 1);
}

TEST(Mumps, SchurAnalysisIsReusedForTheSameBlock1Only) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 49);
  MumpsFactorization mumps;
  Eigen::MatrixXd S1, S2, S3;
  ASSERT_TRUE(mumps.schur_complement(A, std::vector<int>{4, 9, 30}, &S1).ok());
  ASSERT_TRUE(mumps.schur_complement(A, std::vector<int>{4, 9, 30}, &S2).ok());
  EXPECT_EQ(mumps.num_analyses(), 1);
  EXPECT_EQ(mumps.num_factorizations(), 2);
  // Another order is another block1: a new analysis, and S follows the order asked for.
  ASSERT_TRUE(mumps.schur_complement(A, std::vector<int>{30, 4, 9}, &S3).ok());
  EXPECT_EQ(mumps.num_analyses(), 2);
  const std::vector<int> order{2, 0, 1};
  EXPECT_LT(relative_error(S3, S1(order, order)), kTolerance);
}

// ---- Schur special cases -------------------------------------------------------------

TEST(Mumps, EmptyBlock1FactorizesAllOfA) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 51);
  const Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(A)};
  MumpsFactorization mumps;
  Eigen::MatrixXd S(3, 3);
  const auto r = mumps.schur_complement(A, std::span<const int>{}, &S);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(S.rows(), 0);
  EXPECT_EQ(S.cols(), 0);
  const Eigen::MatrixXd B = random_matrix(n, 2, 17);
  Eigen::MatrixXd X2, X;
  ASSERT_TRUE(mumps.solve_interior(B, &X2).ok());
  EXPECT_LT(relative_error(X2, llt.solve(B)), kTolerance);
  ASSERT_TRUE(mumps.solve(B, &X).ok());
  EXPECT_LT(relative_error(X, llt.solve(B)), kTolerance);
}

TEST(Mumps, Block1WithEveryIndexIsThePermutedMatrix) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 53);
  const Eigen::MatrixXd D = A;
  const std::vector<int> block1 = random_block(n, n, 19);
  MumpsFactorization mumps;
  Eigen::MatrixXd S;
  const auto r = mumps.schur_complement(A, block1, &S);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(relative_error(S, D(block1, block1)), kTolerance);
  Eigen::MatrixXd X2;
  ASSERT_TRUE(mumps.solve_interior(Eigen::MatrixXd(0, 2), &X2).ok());
  EXPECT_EQ(X2.rows(), 0);
  EXPECT_EQ(X2.cols(), 2);
  Eigen::MatrixXd X;
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(n, 1), &X), InternalError);
}

TEST(Mumps, SolveAfterSchurComplementThrows) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 55);
  const std::vector<int> block1{3, 1, 4};
  MumpsFactorization mumps;
  Eigen::MatrixXd S, X;
  ASSERT_TRUE(mumps.schur_complement(A, block1, &S).ok());
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(n, 1), &X), InternalError);
  // factorize() brings full solves back (with a new analysis: one without Schur variables).
  ASSERT_TRUE(mumps.factorize(A).ok());
  EXPECT_EQ(mumps.num_analyses(), 2);
  EXPECT_TRUE(mumps.solve(Eigen::MatrixXd::Ones(n, 1), &X).ok());
  EXPECT_THROW(mumps.solve_interior(Eigen::MatrixXd::Ones(n - 3, 1), &X), InternalError);
}

// ---- matrices that are not positive definite ------------------------------------------

TEST(Mumps, IndefiniteDiagonalIsNotPositiveDefinite) {
  Eigen::MatrixXd D = Eigen::Vector3d(1.0, -1.0, 2.0).asDiagonal();
  MumpsFactorization mumps;
  const auto r = mumps.factorize(from_dense(D));
  EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite) << r.message;
  EXPECT_FALSE(r.message.empty());
  Eigen::MatrixXd X;
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(3, 1), &X), InternalError);
}

TEST(Mumps, OneVeryNegativeDiagonalEntryIsNotPositiveDefinite) {
  const int n = 200;
  SparseMatrix A = random_spd(n, 61);
  MumpsFactorization mumps;
  ASSERT_TRUE(mumps.factorize(A).ok());
  A.coeffRef(117, 117) = -1e6;  // same pattern
  const auto r = mumps.factorize(A);
  EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite) << r.message;
  EXPECT_EQ(mumps.num_analyses(), 1);
  // The same matrix through the Schur path, the bad entry inside A22 and inside A11.
  Eigen::MatrixXd S;
  EXPECT_EQ(mumps.schur_complement(A, std::vector<int>{0, 1, 2}, &S).status,
            FactorizationStatus::not_positive_definite);
  EXPECT_EQ(mumps.schur_complement(A, std::vector<int>{0, 117, 2}, &S).status,
            FactorizationStatus::not_positive_definite);
}

TEST(Mumps, SingularAndIndefiniteDenseMatricesAreNotPositiveDefinite) {
  MumpsFactorization mumps;
  Eigen::Matrix2d singular;
  singular << 1.0, 1.0, 1.0, 1.0;
  EXPECT_EQ(mumps.factorize(from_dense(singular)).status, FactorizationStatus::not_positive_definite);
  Eigen::Matrix2d zero_diagonal;
  zero_diagonal << 0.0, 1.0, 1.0, 0.0;
  EXPECT_EQ(mumps.factorize(from_dense(zero_diagonal)).status, FactorizationStatus::not_positive_definite);
  Eigen::Matrix3d indefinite;  // eigenvalues -1, 1, 3
  indefinite << 1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0;
  EXPECT_EQ(mumps.factorize(from_dense(indefinite)).status, FactorizationStatus::not_positive_definite);
}

TEST(Mumps, IndefiniteSchurComplementIsNotPositiveDefinite) {
  // A22 = diag(1, 2) is positive definite, S = (-1) is not.
  const Eigen::MatrixXd D = Eigen::Vector3d(1.0, -1.0, 2.0).asDiagonal();
  MumpsFactorization mumps;
  Eigen::MatrixXd S;
  const auto r = mumps.schur_complement(from_dense(D), std::vector<int>{1}, &S);
  EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite) << r.message;
  EXPECT_THROW(mumps.solve_interior(Eigen::MatrixXd::Ones(2, 1), &S), InternalError);
  // Every index in block1: the dense check applies as well.
  EXPECT_EQ(mumps.schur_complement(from_dense(D), std::vector<int>{2, 0, 1}, &S).status,
            FactorizationStatus::not_positive_definite);
}

// ---- calls out of order and bad arguments -----------------------------------------------

TEST(Mumps, CallsBeforeFactorizationThrow) {
  MumpsFactorization mumps;
  Eigen::MatrixXd X;
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(3, 1), &X), InternalError);
  EXPECT_THROW(mumps.solve_interior(Eigen::MatrixXd::Ones(3, 1), &X), InternalError);
  EXPECT_LT(mumps.rcond_estimate(), 0.0);
  ASSERT_TRUE(mumps.analyze(random_spd(5, 71)).ok());
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(5, 1), &X), InternalError);
}

TEST(Mumps, WrongSizesThrow) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 73);
  MumpsFactorization mumps;
  SparseMatrix rectangular(4, 5);
  EXPECT_THROW(mumps.factorize(rectangular), InternalError);
  EXPECT_THROW(mumps.analyze(rectangular), InternalError);
  EXPECT_THROW(mumps.factorize(SparseMatrix(0, 0)), InternalError);

  ASSERT_TRUE(mumps.factorize(A).ok());
  Eigen::MatrixXd X;
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(n + 1, 1), &X), InternalError);
  EXPECT_THROW(mumps.solve(Eigen::MatrixXd::Ones(n, 1), nullptr), InternalError);

  Eigen::MatrixXd S;
  ASSERT_TRUE(mumps.schur_complement(A, std::vector<int>{5, 6}, &S).ok());
  EXPECT_THROW(mumps.solve_interior(Eigen::MatrixXd::Ones(n, 1), &X), InternalError);
  EXPECT_THROW(mumps.schur_complement(A, std::vector<int>{5, 6}, nullptr), InternalError);
}

TEST(Mumps, BadBlock1Throws) {
  const int n = 40;
  const SparseMatrix A = random_spd(n, 79);
  MumpsFactorization mumps;
  Eigen::MatrixXd S;
  EXPECT_THROW(mumps.schur_complement(A, std::vector<int>{3, 7, 3}, &S), InternalError);
  EXPECT_THROW(mumps.schur_complement(A, std::vector<int>{3, n}, &S), InternalError);
  EXPECT_THROW(mumps.schur_complement(A, std::vector<int>{-1, 3}, &S), InternalError);
  std::vector<int> too_many(static_cast<std::size_t>(n + 1));
  std::iota(too_many.begin(), too_many.end(), 0);
  EXPECT_THROW(mumps.schur_complement(A, too_many, &S), InternalError);
  EXPECT_EQ(mumps.num_analyses(), 0);
}

TEST(Mumps, OneTriangleOnlyThrows) {
  const SparseMatrix A = random_spd(40, 83);
  const SparseMatrix lower = A.triangularView<Eigen::Lower>();
  MumpsFactorization mumps;
  try {
    (void)mumps.factorize(lower);
    ADD_FAILURE() << "expected an InternalError";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("symmetric"), std::string::npos) << e.what();
  }
}

TEST(Mumps, NonFiniteEntriesAreANumericalFailure) {
  SparseMatrix A = random_spd(5, 89);
  A.coeffRef(2, 2) = std::numeric_limits<double>::quiet_NaN();
  MumpsFactorization mumps;
  EXPECT_EQ(mumps.factorize(A).status, FactorizationStatus::numerical_failure);
  ASSERT_TRUE(mumps.factorize(random_spd(5, 89)).ok());
  Eigen::MatrixXd X;
  Eigen::MatrixXd B = Eigen::MatrixXd::Ones(5, 1);
  B(3, 0) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(mumps.solve(B, &X).status, FactorizationStatus::numerical_failure);
}

// ---- condition estimate ----------------------------------------------------------------

TEST(Mumps, ReciprocalConditionEstimateTracksIllConditioning) {
  MumpsFactorization mumps;
  ASSERT_TRUE(mumps.factorize(random_spd(40, 97, 5.0)).ok());
  const double well = mumps.rcond_estimate();
  EXPECT_GT(well, 1e-3);
  EXPECT_LE(well, 1.0);
  EXPECT_EQ(mumps.rcond_estimate(), well);  // cached

  // [[1, 1-d], [1-d, 1]]: condition number about 2/d.
  const double d = 1e-8;
  Eigen::Matrix2d near_singular;
  near_singular << 1.0, 1.0 - d, 1.0 - d, 1.0;
  ASSERT_TRUE(mumps.factorize(from_dense(near_singular)).ok());
  const double ill = mumps.rcond_estimate();
  EXPECT_GT(ill, 0.0);
  EXPECT_LT(ill, 1e-7);
}

}  // namespace
