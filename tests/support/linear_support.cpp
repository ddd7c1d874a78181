#include "linear_support.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

namespace hemivem::test {

SparseMatrix random_spd(int n, unsigned seed, int per_column) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> row(0, n - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double, int>> entries;
  for (int j = 0; j < n; ++j) {
    entries.emplace_back(j, j, 1.0 + value(rng));
    for (int k = 0; k < per_column; ++k) entries.emplace_back(row(rng), j, value(rng));
  }
  SparseMatrix B(n, n);
  B.setFromTriplets(entries.begin(), entries.end());
  SparseMatrix BBt = B * SparseMatrix(B.transpose());
  SparseMatrix A = SparseMatrix(0.5 * (BBt + SparseMatrix(BBt.transpose())));
  SparseMatrix I(n, n);
  I.setIdentity();
  A += I;
  A.makeCompressed();
  return A;
}

SparseMatrix one_negative_eigenvalue(int n, unsigned seed) {
  SparseMatrix A = random_spd(n, seed);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig{Eigen::MatrixXd(A)};
  const double sigma = 0.5 * (eig.eigenvalues()(0) + eig.eigenvalues()(1));
  SparseMatrix I(n, n);
  I.setIdentity();
  SparseMatrix C = A - sigma * I;
  C.makeCompressed();
  return C;
}

Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd M(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) M(i, j) = value(rng);
  return M;
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
  std::vector<char> in1(static_cast<std::size_t>(n), 0);
  for (int i : block1) in1[static_cast<std::size_t>(i)] = 1;
  std::vector<int> block2;
  for (int i = 0; i < n; ++i)
    if (!in1[static_cast<std::size_t>(i)]) block2.push_back(i);
  return block2;
}

double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  if (x.rows() != reference.rows() || x.cols() != reference.cols()) return std::numeric_limits<double>::infinity();
  return (x - reference).norm() / std::max(reference.norm(), std::numeric_limits<double>::min());
}

}  // namespace hemivem::test
