// Matrices, blocks and errors for the tests of the linear engines (tests/, tests/mpi,
// tests/bench). It needs the interfaces and Eigen only, so that a program linking one engine
// and nothing else of hemivem (the MPI tests) can use it.
#pragma once

#include <hemivem/sparse_factorization.hpp>

#include <Eigen/Dense>

#include <vector>

namespace hemivem::test {

/// A random sparse SPD matrix B B^T + I (both triangles stored, exactly symmetric).
SparseMatrix random_spd(int n, unsigned seed, int per_column = 3);

/// A symmetric matrix with the pattern of random_spd(n, seed) and exactly one negative
/// eigenvalue: A - sigma I with sigma between the two smallest eigenvalues of A.
SparseMatrix one_negative_eigenvalue(int n, unsigned seed);

/// A rows x cols matrix of numbers uniform in [-1, 1] drawn by std::mt19937(seed).
Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed);

/// `count` distinct indices of 0..n-1 in a random order drawn by std::mt19937(seed).
std::vector<int> random_block(int n, int count, unsigned seed);

/// The indices of 0..n-1 that are not in block1, in increasing order.
std::vector<int> complement(int n, const std::vector<int>& block1);

/// |x - reference| / |reference| in the Frobenius norm (|x - reference| over the smallest
/// normal double when the reference is zero); infinity when the shapes differ.
double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference);

}  // namespace hemivem::test
