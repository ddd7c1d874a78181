// Condition estimates that do not depend on the engine: the 1-norm condition number
// kappa_1(A) = ||A||_1 ||A^{-1}||_1 of a symmetric matrix, with ||A^{-1}||_1 estimated by the
// Hager-Higham method (LAPACK's xLACN2) from solves with an existing factorization.
#pragma once

#include <Eigen/Core>

#include <functional>

#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

/// ||A||_1: the largest column sum of absolute values.
double norm1(const SparseMatrix& A);

/// A lower bound on ||B||_1 (usually within a factor 3, often exact) for a symmetric n x n
/// matrix B known only through `apply` (X -> B X, for a block of columns), from two blocks of
/// products in the manner of Hager and Higham: first B x for x = (1/n, ..., 1/n) and Higham's
/// safeguard vector; then B sign(B x) and the two columns of B at the largest entries of the
/// first products. Every 1-norm (and the largest entry of B sign(B x)) found is a lower bound
/// of ||B||_1; the estimate is the largest. `apply` is called exactly twice, with two and then
/// three columns, whatever the data, so that every process of a distributed engine makes the
/// same calls. Non-finite products give +inf.
double estimate_norm1_symmetric_blocks(int n, const std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>& apply);

}  // namespace hemivem
