// The MPI MUMPS engine under mpiexec: the conformance suite of the linear engines
// (support/linear_conformance.hpp) run on it, and the checks of its own.
//
// Every process runs every test and every call (the engine's methods are collective); the
// matrices, right-hand sides and blocks are given on rank 0 only (empty elsewhere, which the
// engine ignores). The suite sees the engine through SpmdView, which gives the inputs so,
// checks that the engine writes its outputs on rank 0 only and returns the same status on
// every process, and then hands rank 0's outputs to every process, so that every process
// checks the same numbers and takes the same path (no fatal assertion can stop one process
// before a collective call that the others make). main() reduces the outcome over all
// processes: a failure on any rank fails the program.
#include <hemivem/error.hpp>
#include <hemivem/mumps_mpi_factorization.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <mpi.h>

#include "linear_conformance.hpp"
#include "linear_support.hpp"
#include "mpi_test_main.hpp"

#include <memory>
#include <span>
#include <vector>

namespace {

using hemivem::FactorizationResult;
using hemivem::FactorizationStatus;
using hemivem::InternalError;
using hemivem::MumpsMpiFactorization;
using hemivem::SparseFactorization;
using hemivem::SparseMatrix;
using hemivem::test::LinearConformance;
using hemivem::test::random_matrix;
using hemivem::test::relative_error;

int rank() { return MumpsMpiFactorization::mpi_rank(); }
bool root() { return rank() == 0; }

/// The argument on rank 0, an empty object elsewhere (the engine must ignore it there).
template <class T>
T on_root(const T& value) {
  return root() ? value : T();
}

/// mumps-mpi as every process of the conformance suite sees it (see the top of the file).
class SpmdView final : public SparseFactorization {
 public:
  std::string name() const override { return engine_.name(); }
  FactorizationResult analyze(const SparseMatrix& A) override { return same_everywhere(engine_.analyze(on_root(A))); }
  FactorizationResult factorize(const SparseMatrix& A) override {
    return same_everywhere(engine_.factorize(on_root(A)));
  }
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override {
    return written_on_root(X, [&] { return engine_.solve(on_root(B), X); });
  }
  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                       Eigen::MatrixXd* S) override {
    const std::span<const int> given = root() ? block1 : std::span<const int>();
    return written_on_root(S, [&] { return engine_.schur_complement(on_root(A), given, S); });
  }
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override {
    return written_on_root(X2, [&] { return engine_.solve_interior(on_root(B2), X2); });
  }
  double rcond_estimate() const override { return engine_.rcond_estimate(); }
  int num_analyses() const override { return static_cast<const SparseFactorization&>(engine_).num_analyses(); }

 private:
  static FactorizationResult same_everywhere(FactorizationResult r) {
    int low = static_cast<int>(r.status), high = low;
    MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    EXPECT_EQ(low, high) << "the processes return different statuses";
    return r;
  }

  template <class Matrix, class Call>
  static FactorizationResult written_on_root(Matrix* out, const Call& call) {
    const Matrix before = out != nullptr ? *out : Matrix();
    const FactorizationResult r = same_everywhere(call());
    if (out == nullptr) return r;
    if (!root()) {
      EXPECT_TRUE(out->rows() == before.rows() && out->cols() == before.cols() && *out == before)
          << "outputs are written on rank 0 only";
    }
    int written = r.ok() ? 1 : 0;  // rank 0 decides
    MPI_Bcast(&written, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (written) {
      long shape[2] = {static_cast<long>(out->rows()), static_cast<long>(out->cols())};
      MPI_Bcast(shape, 2, MPI_LONG, 0, MPI_COMM_WORLD);
      out->resize(shape[0], shape[1]);
      MPI_Bcast(out->data(), static_cast<int>(out->size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }
    return r;
  }

  MumpsMpiFactorization engine_;
};

INSTANTIATE_TEST_SUITE_P(MumpsMpi, LinearConformance,
                         ::testing::Values(hemivem::test::LinearEngine{
                             "mumps-mpi", [] { return std::make_unique<SpmdView>(); }}),
                         hemivem::test::engine_test_name);

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

constexpr double kTolerance = 1e-10;

TEST(MumpsMpi, SolveOfGridMatrixMatchesDenseCholesky) {
  SpmdView mumps;
  hemivem::test::expect_solves_match_dense_reference(mumps, grid_matrix(30), 7);
}

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

TEST(MumpsMpi, SchurComplementOfGridBottomRowMatchesDenseReference) {
  // block1: the second unknown of the interior nodes of the bottom row (as in condensation).
  const int m = 24;
  std::vector<int> block1;
  for (int i = 1; i + 1 < m; ++i) block1.push_back(2 * i + 1);
  SpmdView mumps;
  hemivem::test::expect_schur_complement_matches_dense_reference(mumps, grid_matrix(m), block1, 23);
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
