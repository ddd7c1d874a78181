// Checks and bookkeeping shared by the linear engines (private to backends/linear).
// Messages do not name the engine: the caller of an engine does.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <algorithm>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace hemivem::linear_detail {

inline FactorizationResult make_result(FactorizationStatus status, std::string message) {
  return FactorizationResult{status, std::move(message)};
}

/// A call that breaks the engine's contract (arguments that do not fit, a call out of order):
/// the caller's mistake, an InternalError; statuses are for numerical outcomes only.
[[noreturn]] inline void contract_violation(const std::string& message) { throw InternalError(message); }

/// A square matrix with at least one row (InternalError otherwise).
inline FactorizationResult check_matrix(const SparseMatrix& A) {
  if (A.rows() != A.cols())
    contract_violation("the matrix is " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()) +
                   ", not square");
  if (A.rows() == 0) contract_violation("the matrix is empty (0x0)");
  return FactorizationResult::good();
}

/// check_matrix, and every stored value of the compressed matrix A finite (a matrix with NaN
/// or Inf cannot be factorized: a numerical failure, as when the factorization meets one).
inline FactorizationResult check_values(const SparseMatrix& A) {
  if (auto r = check_matrix(A); !r.ok()) return r;
  const Eigen::Map<const Eigen::VectorXd> values(A.valuePtr(), A.nonZeros());
  if (!values.allFinite())
    return make_result(FactorizationStatus::numerical_failure, "the matrix has entries that are not finite");
  return FactorizationResult::good();
}

/// Both triangles stored: the pattern of A equals that of its transpose.
inline bool symmetric_pattern(const SparseMatrix& A) {
  const SparseMatrix At = A.transpose();  // sorted inner indices
  if (At.nonZeros() != A.nonZeros() || A.outerSize() != At.outerSize()) return false;
  std::vector<int> column;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    const int b = A.outerIndexPtr()[j], e = A.outerIndexPtr()[j + 1];
    if (At.outerIndexPtr()[j] != b || At.outerIndexPtr()[j + 1] != e) return false;
    column.assign(A.innerIndexPtr() + b, A.innerIndexPtr() + e);
    std::sort(column.begin(), column.end());
    if (!std::equal(column.begin(), column.end(), At.innerIndexPtr() + b)) return false;
  }
  return true;
}

/// The arguments of a solve: an output, and `rows` rows in `B` (named `b_name`; `matrix`
/// names what was factorized); InternalError otherwise.
inline FactorizationResult check_right_hand_sides(const std::string& call, const std::string& b_name,
                                                  const Eigen::MatrixXd& B, const Eigen::MatrixXd* X,
                                                  Eigen::Index rows, const std::string& matrix) {
  if (X == nullptr) contract_violation(call + ": the output is null");
  if (B.rows() != rows)
    contract_violation(call + ": " + b_name + " has " + std::to_string(B.rows()) + " rows, " + matrix + " " +
                   std::to_string(rows));
  return FactorizationResult::good();
}

/// A compressed view of A: A itself, or a compressed copy kept in `storage`.
inline const SparseMatrix& compressed(const SparseMatrix& A, SparseMatrix& storage) {
  if (A.isCompressed()) return A;
  storage = A;
  storage.makeCompressed();
  return storage;
}

/// The sparsity pattern of a compressed matrix (sizes, column pointers and row indices),
/// kept to decide whether a symbolic analysis can be reused.
class PatternKey {
 public:
  void capture(const SparseMatrix& A) {
    rows_ = A.rows();
    cols_ = A.cols();
    outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
    inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
    valid_ = true;
  }
  bool matches(const SparseMatrix& A) const {
    if (!valid_ || !A.isCompressed() || A.rows() != rows_ || A.cols() != cols_) return false;
    if (static_cast<std::size_t>(A.nonZeros()) != inner_.size()) return false;
    return std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
           std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
  }
  void clear() {
    valid_ = false;
    outer_.clear();
    inner_.clear();
  }

 private:
  bool valid_ = false;
  Eigen::Index rows_ = -1, cols_ = -1;
  std::vector<int> outer_, inner_;
};

/// The split of 0..n-1 into block1 (as given) and block2 (the rest, increasing).
struct BlockSplit {
  std::vector<int> block1;
  std::vector<int> block2;
  /// For each index i: its position in block2 when >= 0, or -(t+1) when it is block1[t].
  std::vector<int> position;
};

/// Validates block1 (distinct indices in [0, n); InternalError otherwise) and fills *out.
inline FactorizationResult split_blocks(Eigen::Index n, std::span<const int> block1, BlockSplit* out) {
  if (static_cast<Eigen::Index>(block1.size()) > n)
    contract_violation("block1 has " + std::to_string(block1.size()) + " indices but the matrix only " +
                   std::to_string(n) + " rows");
  std::vector<int> position(static_cast<std::size_t>(n), 0);
  for (std::size_t t = 0; t < block1.size(); ++t) {
    const int i = block1[t];
    if (i < 0 || i >= n)
      contract_violation("block1[" + std::to_string(t) + "] = " + std::to_string(i) + " is outside [0, " +
                     std::to_string(n) + ")");
    if (position[static_cast<std::size_t>(i)] != 0)
      contract_violation("block1[" + std::to_string(t) + "] = " + std::to_string(i) + " appears twice");
    position[static_cast<std::size_t>(i)] = -static_cast<int>(t) - 1;
  }
  out->block1.assign(block1.begin(), block1.end());
  out->block2.clear();
  out->block2.reserve(static_cast<std::size_t>(n) - block1.size());
  for (int i = 0; i < n; ++i) {
    if (position[static_cast<std::size_t>(i)] == 0) {
      position[static_cast<std::size_t>(i)] = static_cast<int>(out->block2.size());
      out->block2.push_back(i);
    }
  }
  out->position = std::move(position);
  return FactorizationResult::good();
}

/// S = A when block1 holds every index: the block of A in block1's order, from its lower
/// triangle (the triangle the engines read), as a dense symmetric matrix.
inline Eigen::MatrixXd dense_lower_block(const SparseMatrix& A, const BlockSplit& split) {
  const Eigen::Index n1 = static_cast<Eigen::Index>(split.block1.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n1, n1);
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    const int pj = split.position[static_cast<std::size_t>(j)];
    if (pj >= 0) continue;
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      if (it.row() < j) continue;
      const int pi = split.position[static_cast<std::size_t>(it.row())];
      if (pi >= 0) continue;
      const Eigen::Index r = -pi - 1, c = -pj - 1;
      S(r, c) += it.value();
      if (r != c) S(c, r) += it.value();
    }
  }
  return S;
}

}  // namespace hemivem::linear_detail
