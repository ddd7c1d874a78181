// The contract of a sparse symmetric positive definite factorization engine.
//
// Call sequence (as Eigen's sparse solvers and Ceres' SparseCholesky):
//   analyze(A)     symbolic analysis; reused by factorize() while the pattern holds
//   factorize(A)   numeric factorization (repeatable for new values, same pattern)
//   solve(B, X)    X = A^{-1} B for many right-hand sides at once
// and, for static condensation (docs/reference/engines.md):
//   schur_complement(A, block1, S)   dense S = A11 - A12 A22^{-1} A21 for the index set
//                                    block1, at about the cost of one factorization, and
//                                    a factorization of A22 kept for
//   solve_interior(B2, X2)           X2 = A22^{-1} B2 (the rest of the solve).
// An engine that factorizes A22 within a factorization of the whole A may also offer the
// interior solve in two halves (SplitInteriorSolve, found by split_interior_solve()):
//   condense_rhs(b1, b2, c)          c = b1 - A12 A22^{-1} b2, one forward substitution
//   expand(x1, x2)                   x2 = A22^{-1} (b2 - A21 x1), one backward substitution.
//
// Numerical outcomes are statuses with a human message (a matrix that is not positive
// definite, one with entries that are not finite, memory); a call that breaks the contract
// (sizes, patterns or index sets that do not fit, a null output, a call out of order such as
// solve() before a successful factorize()) is the caller's mistake and throws InternalError
// (hemivem/error.hpp). Nothing prints or exits. Every engine must detect a matrix that is not
// positive definite; a matrix with entries that are not finite is a numerical_failure.
//
// An engine that runs across processes implements hemivem/process_group.hpp's ProcessGroup
// as well; an engine in one process implements this interface alone.
#pragma once

#include <hemivem/engine_names.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hemivem {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// A SparseMatrix that moves by taking the other's arrays, leaving it empty. Eigen's SparseMatrix
/// has no move constructor, so a struct holding one copies it on every move: a struct that holds
/// a large matrix and is moved (a process's share of the full-space route) holds this instead.
class MovableSparseMatrix : public SparseMatrix {
 public:
  using SparseMatrix::SparseMatrix;
  using SparseMatrix::operator=;
  MovableSparseMatrix() = default;
  MovableSparseMatrix(const MovableSparseMatrix&) = default;
  MovableSparseMatrix(MovableSparseMatrix&& other) noexcept { swap(other); }
  MovableSparseMatrix& operator=(const MovableSparseMatrix&) = default;
  MovableSparseMatrix& operator=(MovableSparseMatrix&& other) noexcept {
    swap(other);
    SparseMatrix().swap(other);
    return *this;
  }
  ~MovableSparseMatrix() = default;
};

/// The compressed rows x cols matrix with column starts `outer` (cols + 1 of them) and row
/// indices `inner` (increasing in each column), every stored value `value`: a pattern written
/// straight into the matrix's arrays.
inline SparseMatrix pattern_matrix(Eigen::Index rows, Eigen::Index cols, std::span<const int> outer,
                                   std::span<const int> inner, double value) {
  SparseMatrix M(rows, cols);
  M.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), M.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), M.innerIndexPtr());
  std::fill(M.valuePtr(), M.valuePtr() + inner.size(), value);
  return M;
}

enum class FactorizationStatus {
  success,
  not_positive_definite,  ///< the matrix is not symmetric positive definite
  numerical_failure,      ///< the engine failed for another numerical reason
  out_of_memory,
};
/// "success", "not_positive_definite", "numerical_failure", "out_of_memory".
std::string to_string(FactorizationStatus status);
/// The names of to_string (case-insensitive, '-' or ' ' as '_'); InputError otherwise.
FactorizationStatus factorization_status_from_string(std::string_view name);

struct FactorizationResult {
  FactorizationStatus status = FactorizationStatus::success;
  std::string message;
  bool ok() const noexcept { return status == FactorizationStatus::success; }
  static FactorizationResult good() { return {}; }
};

/// One flat options struct (as Ceres' Solver::Options). `engine` names the backend.
struct FactorizationOptions {
  std::string engine = "eigen";  ///< one of known_linear_engines(), or "auto" (the fastest built; case-insensitive, '_' as '-')
  /// Forwarded to engines that print diagnostics; hemivem itself never prints.
  int verbosity = 0;
  /// Threads an engine may use where it has such a setting (0: engine default).
  int threads = 0;
  /// Returns false and fills *error naming the offending field when the options cannot be used.
  bool is_valid(std::string* error) const;
};

/// A sparse symmetric positive definite factorization. The matrix is passed with both
/// triangles stored (as hemivem assembles it); an engine reads what it needs.
class SparseFactorization {
 public:
  virtual ~SparseFactorization() = default;

  /// The engine's name, as accepted by FactorizationOptions::engine.
  virtual std::string name() const = 0;

  /// Symbolic analysis of the pattern of A (square, symmetric pattern).
  virtual FactorizationResult analyze(const SparseMatrix& A) = 0;
  /// Numeric factorization; runs analyze() first when the pattern differs from the one
  /// analysed (or none was).
  virtual FactorizationResult factorize(const SparseMatrix& A) = 0;
  /// X = A^{-1} B after factorize(); B has A.rows() rows and any number of columns.
  virtual FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const = 0;

  /// Dense Schur complement S = A11 - A12 A22^{-1} A21 of the rows/columns `block1`
  /// (distinct indices into A, in the order S is wanted), keeping a factorization of
  /// A22 (the remaining indices in increasing order) for solve_interior().
  virtual FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                               Eigen::MatrixXd* S) = 0;
  /// X2 = A22^{-1} B2 after schur_complement(); B2 has A.rows() - block1.size() rows,
  /// ordered as the remaining indices in increasing order.
  virtual FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const = 0;

  /// Reciprocal condition estimate of the last factorized matrix where the engine
  /// offers one (CHOLMOD's rcond, MUMPS' RINFOG); negative when it does not.
  virtual double rcond_estimate() const { return -1.0; }

  /// Number of symbolic analyses this object has run so far (explicit analyze() calls,
  /// those factorize() ran because the pattern changed, and those of schur_complement()),
  /// so that callers and tests can see that an analysis is reused; -1 when the engine
  /// does not count them.
  virtual int num_analyses() const { return -1; }
};

/// The interior solve in its two halves: an optional interface of the engines that factorize
/// A22 within a factorization of the whole A (L = [L22 0; L21 L11]), where each half is one
/// triangular substitution instead of a full interior solve. After schur_complement(), with b1
/// in block1's order and b2, x2 ordered as for solve_interior():
///   condense_rhs(b1, b2, c): c = b1 - A12 A22^{-1} b2, the reduced right-hand side; the engine
///                            keeps what expand() needs of b2;
///   expand(x1, x2):          x2 = A22^{-1} (b2 - A21 x1) for the b2 of the last condense_rhs().
class SplitInteriorSolve {
 public:
  virtual ~SplitInteriorSolve() = default;
  virtual FactorizationResult condense_rhs(const Eigen::VectorXd& b1, const Eigen::VectorXd& b2,
                                           Eigen::VectorXd* c) = 0;
  virtual FactorizationResult expand(const Eigen::VectorXd& x1, Eigen::VectorXd* x2) const = 0;
};

/// The engine's split interior solve, or null when it has none (callers then use
/// solve_interior()).
inline SplitInteriorSolve* split_interior_solve(SparseFactorization& engine) {
  return dynamic_cast<SplitInteriorSolve*>(&engine);
}
inline const SplitInteriorSolve* split_interior_solve(const SparseFactorization& engine) {
  return dynamic_cast<const SplitInteriorSolve*>(&engine);
}

}  // namespace hemivem
