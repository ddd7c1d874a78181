// The conformance suite of the linear engines (as Ceres' sparse_cholesky_test): solves and
// Schur complements against dense Eigen references, reuse of the symbolic analysis,
// detection of matrices that are not positive definite, and the statuses of calls out of
// order or with bad sizes.
//
// A program runs it on its engines by compiling linear_conformance.cpp and instantiating the
// suite, e.g.
//   INSTANTIATE_TEST_SUITE_P(Engines, LinearConformance, ::testing::ValuesIn(engines),
//                            test::engine_test_name);
// test_linear_conformance runs it on every engine of the factory in one process,
// tests/mpi/test_mumps_mpi on mumps-mpi under mpiexec.
#pragma once

#include <hemivem/sparse_factorization.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace hemivem::test {

/// An engine under test: its name and how to make a fresh one.
struct LinearEngine {
  std::string name;
  std::function<std::unique_ptr<SparseFactorization>()> make;
};

void PrintTo(const LinearEngine& engine, std::ostream* os);

/// The engine's name with every character other than a letter or a digit replaced by '_'.
std::string engine_test_name(const ::testing::TestParamInfo<LinearEngine>& info);

class LinearConformance : public ::testing::TestWithParam<LinearEngine> {
 protected:
  std::unique_ptr<SparseFactorization> make() const { return GetParam().make(); }
  const std::string& engine() const { return GetParam().name; }
};

/// Factorizes A (it must succeed), solves with 1 and with 4 right-hand sides against a dense
/// Cholesky factorization, and checks that an offered rcond_estimate() lies in (0, 1].
void expect_solves_match_dense_reference(SparseFactorization& f, const SparseMatrix& A, unsigned seed);

/// schur_complement(A, block1) (it must succeed) against A11 - A12 A22^{-1} A21, then
/// solve_interior() with 1, 2, 3, 4, 5 and 9 right-hand sides against A22^{-1} B2.
void expect_schur_complement_matches_dense_reference(SparseFactorization& f, const SparseMatrix& A,
                                                     const std::vector<int>& block1, unsigned seed);

}  // namespace hemivem::test
