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
/// matrix B known only through `apply` (X -> B X, for a block of columns): Hager and Higham's
/// iterations, the first x = (1/n, ..., 1/n) solved with Higham's safeguard vector as one block
/// of two columns, and no product the estimate does not use (the last iteration chooses no
/// next x). `apply` is called exactly 2 * iterations - 1 times whatever the data, so that every
/// process of a distributed engine makes the same calls. Non-finite products give +inf.
double estimate_norm1_symmetric_blocks(int n, const std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>& apply,
                                       int iterations = 3);
/// The same with `apply` one column at a time (x -> B x; called 2 * iterations times).
double estimate_norm1_symmetric(int n, const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& apply,
                                int iterations = 3);

}  // namespace hemivem
