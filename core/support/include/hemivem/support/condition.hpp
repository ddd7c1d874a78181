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
/// matrix B known only through `apply` (x -> B x). `apply` is called exactly
/// 2 * iterations + 1 times whatever the data, so that every process of a distributed engine
/// makes the same calls. Non-finite products give +inf.
double estimate_norm1_symmetric(int n, const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& apply,
                                int iterations = 3);

}  // namespace hemivem
