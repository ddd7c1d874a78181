// The MPI MUMPS engine against dense Eigen references computed on rank 0.
//
// Every process runs every call (the engine's methods are collective); the matrices and
// right-hand sides are given on rank 0 only (empty elsewhere, which the engine ignores), and
// only rank 0 checks the numbers. Statuses are the same on every process, so every process
// checks them. Nothing fatal (ASSERT_*) may stop one process before a collective call that the
// others make; fatal assertions are used on statuses only, which all processes share.
// main() reduces the outcome over all processes: a failure on any rank fails the program.
#include <hemivem/error.hpp>
#include <hemivem/mumps_mpi_factorization.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <mpi.h>

#include "mpi_test_main.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

namespace {

using hemivem::FactorizationStatus;
using hemivem::InternalError;
using hemivem::MumpsMpiFactorization;
using hemivem::SparseMatrix;

int rank() { return MumpsMpiFactorization::mpi_rank(); }
bool root() { return rank() == 0; }

/// A random sparse SPD matrix B Bᵀ + shift·I with both triangles stored.
SparseMatrix random_spd(int n, unsigned seed) {
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
  SparseMatrix A = SparseMatrix(B * B.transpose()) + I;
  A.makeCompressed();
  return A;
}

/// Vector Laplacian (two unknowns per node) on an m×m grid of nodes with a shift: SPD.
SparseMatrix grid_matrix(int m) {
  const int n = 2 * m * m;
  std::vector<Eigen::Triplet<double>> t;
  auto node = [m](int i, int j) { return j * m + i; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i)
      for (int c = 0; c < 2; ++c) {
        const int k = 2 * node(i, j) + c;
        t.emplace_back(k, k, 4.5 + 0.5 * c);
        t.emplace_back(k, k ^ 1, 0.25);  // couple the two components of a node
        if (i + 1 < m) {
          t.emplace_back(k, 2 * node(i + 1, j) + c, -1.0);
          t.emplace_back(2 * node(i + 1, j) + c, k, -1.0);
        }
        if (j + 1 < m) {
          t.emplace_back(k, 2 * node(i, j + 1) + c, -1.0);
          t.emplace_back(2 * node(i, j + 1) + c, k, -1.0);
        }
      }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd M(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) M(i, j) = value(rng);
  return M;
}

/// Relative error, or infinity when the shapes differ.
double relative_error(const Eigen::MatrixXd& X, const Eigen::MatrixXd& reference) {
  if (X.rows() != reference.rows() || X.cols() != reference.cols()) return INFINITY;
  return (X - reference).norm() / std::max(reference.norm(), 1e-300);
}

std::vector<int> random_block(int n, int count, unsigned seed) {
  std::vector<int> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  std::mt19937 rng(seed);
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(static_cast<std::size_t>(count));
  return all;
}

std::vector<int> complement(int n, const std::vector<int>& block1) {
  std::vector<char> in(static_cast<std::size_t>(n), 0);
  for (int i : block1) in[static_cast<std::size_t>(i)] = 1;
  std::vector<int> rest;
  for (int i = 0; i < n; ++i)
    if (!in[static_cast<std::size_t>(i)]) rest.push_back(i);
  return rest;
}

/// The argument on rank 0, an empty object elsewhere (the engine must ignore it there).
template <class T>
T on_root(const T& value) {
  return root() ? value : T();
}

constexpr double kTolerance = 1e-10;

void check_solves(const SparseMatrix& A_full, unsigned seed) {
  const SparseMatrix A = on_root(A_full);
  const Eigen::MatrixXd B = on_root(random_matrix(A_full.rows(), 4, seed));
  MumpsMpiFactorization mumps;
  EXPECT_EQ(mumps.name(), "mumps-mpi");
  const auto f = mumps.factorize(A);
  ASSERT_TRUE(f.ok()) << f.message;
  Eigen::MatrixXd X;
  const auto s = mumps.solve(B, &X);
  ASSERT_TRUE(s.ok()) << s.message;
  if (root()) {
    const Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(A_full)};
    EXPECT_LT(relative_error(X, llt.solve(B)), kTolerance);
  } else {
    EXPECT_EQ(X.size(), 0) << "outputs are written on rank 0 only";
  }
}

TEST(MumpsMpi, SolveOfRandomMatrixMatchesDenseCholesky) { check_solves(random_spd(200, 5), 3); }

TEST(MumpsMpi, SolveOfGridMatrixMatchesDenseCholesky) { check_solves(grid_matrix(30), 7); }

TEST(MumpsMpi, RefactorizesWithoutNewAnalysis) {
  const SparseMatrix A_full = grid_matrix(20);
  const SparseMatrix A2_full = 3.0 * A_full;
  MumpsMpiFactorization mumps;
  ASSERT_TRUE(mumps.factorize(on_root(A_full)).ok());
  ASSERT_TRUE(mumps.factorize(on_root(A2_full)).ok());
  EXPECT_EQ(mumps.num_analyses(), 1);
  EXPECT_EQ(mumps.num_factorizations(), 2);
  const Eigen::MatrixXd B = on_root(random_matrix(A_full.rows(), 2, 11));
  Eigen::MatrixXd X;
  ASSERT_TRUE(mumps.solve(B, &X).ok());
  if (root()) {
    EXPECT_LT(relative_error(X, Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd(A2_full)).solve(B)), kTolerance);
  }
}

void check_schur(const SparseMatrix& A_full, const std::vector<int>& block1_full, unsigned seed) {
  const int n = static_cast<int>(A_full.rows());
  const int n1 = static_cast<int>(block1_full.size());
  MumpsMpiFactorization mumps;
  Eigen::MatrixXd S;
  const auto r = mumps.schur_complement(on_root(A_full), on_root(block1_full), &S);
  ASSERT_TRUE(r.ok()) << r.message;
  const Eigen::MatrixXd B2 = on_root(random_matrix(n - n1, 3, seed));
  Eigen::MatrixXd X2;
  const auto s = mumps.solve_interior(B2, &X2);
  ASSERT_TRUE(s.ok()) << s.message;
  if (root()) {
    const Eigen::MatrixXd D = A_full;
    const std::vector<int> block2 = complement(n, block1_full);
    const Eigen::MatrixXd A12 = D(block1_full, block2);
    const Eigen::LLT<Eigen::MatrixXd> llt22{Eigen::MatrixXd(D(block2, block2))};
    const Eigen::MatrixXd S_ref = D(block1_full, block1_full) - A12 * llt22.solve(A12.transpose());
    EXPECT_LT(relative_error(S, S_ref), kTolerance);
    EXPECT_LT(relative_error(X2, llt22.solve(B2)), kTolerance);
  } else {
    EXPECT_EQ(S.size(), 0);
    EXPECT_EQ(X2.size(), 0);
  }
}

TEST(MumpsMpi, SchurComplementOfRandomMatrixMatchesDenseReference) {
  check_schur(random_spd(200, 13), random_block(200, 40, 17), 19);
}

TEST(MumpsMpi, SchurComplementOfGridBottomRowMatchesDenseReference) {
  // block1: the second unknown of the interior nodes of the bottom row (as in condensation).
  const int m = 24;
  std::vector<int> block1;
  for (int i = 1; i + 1 < m; ++i) block1.push_back(2 * i + 1);
  check_schur(grid_matrix(m), block1, 23);
}

TEST(MumpsMpi, NotPositiveDefiniteEverywhere) {
  SparseMatrix A_full = grid_matrix(20);
  A_full.coeffRef(101, 101) = -1e6;
  MumpsMpiFactorization mumps;
  const auto r = mumps.factorize(on_root(A_full));
  EXPECT_EQ(r.status, FactorizationStatus::not_positive_definite) << r.message;
  Eigen::MatrixXd S;
  EXPECT_EQ(mumps.schur_complement(on_root(A_full), on_root(std::vector<int>{0, 101}), &S).status,
            FactorizationStatus::not_positive_definite);
  EXPECT_EQ(mumps.schur_complement(on_root(A_full), on_root(std::vector<int>{0, 1}), &S).status,
            FactorizationStatus::not_positive_definite);
  const Eigen::MatrixXd D = Eigen::Vector3d(1.0, -1.0, 2.0).asDiagonal();
  EXPECT_EQ(mumps.factorize(on_root(SparseMatrix(D.sparseView()))).status,
            FactorizationStatus::not_positive_definite);
}

TEST(MumpsMpi, BadInputOnRankZeroIsReportedEverywhere) {
  const SparseMatrix A_full = random_spd(40, 29);
  MumpsMpiFactorization mumps;
  Eigen::MatrixXd S, X;
  EXPECT_THROW(mumps.solve(on_root(Eigen::MatrixXd::Ones(40, 1).eval()), &X), InternalError);
  EXPECT_THROW(mumps.schur_complement(on_root(A_full), on_root(std::vector<int>{1, 1}), &S), InternalError);
  ASSERT_TRUE(mumps.factorize(on_root(A_full)).ok());
  try {
    (void)mumps.solve(on_root(Eigen::MatrixXd::Ones(41, 1).eval()), &X);
    ADD_FAILURE() << "expected an InternalError";
  } catch (const InternalError& e) {
    EXPECT_FALSE(std::string(e.what()).empty());
  }
}

TEST(MumpsMpi, ReciprocalConditionEstimateIsTheSameEverywhere) {
  MumpsMpiFactorization mumps;
  EXPECT_LT(mumps.rcond_estimate(), 0.0);
  ASSERT_TRUE(mumps.factorize(on_root(grid_matrix(10))).ok());
  const double rcond = mumps.rcond_estimate();
  EXPECT_GT(rcond, 0.0);
  EXPECT_LE(rcond, 1.0);
  double low = rcond, high = rcond;
  MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_EQ(low, high);
}

}  // namespace

int main(int argc, char** argv) { return hemivem::test::run_tests_on_every_rank(argc, argv, "mumps-mpi tests"); }
