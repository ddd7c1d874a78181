// Private helpers of the Krylov engines (not installed): the contract's checks of compute()
// and solve() arguments, the start of solve() and its restarts, the screening of a matrix
// before a preconditioner is built, the true relative residual every engine reports and the
// format of numbers in messages.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>

#include <Eigen/Core>

#include <cmath>
#include <sstream>
#include <string>

namespace hemivem::krylov {

/// The restarts from the last x when the engine's recursive residual says converged and the
/// true residual does not.
constexpr int kMaxRestarts = 4;

/// value in the messages: scientific notation, 3 digits after the point ("1.235e-08").
inline std::string scientific(double value) {
  std::ostringstream s;
  s.precision(3);
  s << std::scientific << value;
  return s.str();
}

/// Throws InternalError unless A is square, `hints.near_null` has A.rows() rows or no columns,
/// `hints.block_size` is positive and divides A.rows(), and `hints.rows`, when not null, are
/// those of one process owning A's rows (the engine runs the system in one process).
inline void check_compute_arguments(const std::string& engine, const SparseMatrix& A, const KrylovHints& hints) {
  const Eigen::MatrixXd& near_null = hints.near_null;
  if (A.rows() != A.cols())
    throw InternalError(engine + ": compute() needs a square matrix, not " + std::to_string(A.rows()) + " x " +
                        std::to_string(A.cols()));
  if (const RowDistribution* rows = hints.rows) {
    const RowLayout& layout = rows->layout();
    if (rows->size() != 1 || layout.first != 0 || layout.owned != A.rows() || layout.global != A.rows() ||
        !layout.ghosts.empty())
      throw InternalError(engine + ": the rows of process " + std::to_string(rows->rank()) + " of " +
                          std::to_string(rows->size()) + " (" + std::to_string(layout.owned) + " owned of " +
                          std::to_string(layout.global) + ", " + std::to_string(layout.ghosts.size()) +
                          " ghosts) for the whole matrix of " + std::to_string(A.rows()) + " rows in one process");
  }
  if (near_null.cols() > 0 && near_null.rows() != A.rows())
    throw InternalError(engine + ": the near-null space has " + std::to_string(near_null.rows()) +
                        " rows for a matrix of " + std::to_string(A.rows()));
  if (hints.block_size < 1 || A.rows() % hints.block_size != 0)
    throw InternalError(engine + ": a block size of " + std::to_string(hints.block_size) + " for a matrix of " +
                        std::to_string(A.rows()) + " rows");
}

/// Throws InternalError unless b fits the matrix of size n, x is not null, rtol > 0 and
/// max_iterations >= 0.
inline void check_solve_arguments(const std::string& engine, Eigen::Index n, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd* x, double rtol, int max_iterations) {
  if (b.size() != n)
    throw InternalError(engine + ": solve() got a right-hand side of size " + std::to_string(b.size()) +
                        " for a matrix of " + std::to_string(n));
  if (!x) throw InternalError(engine + ": solve() needs an x");
  if (!(rtol > 0.0)) throw InternalError(engine + ": solve() needs rtol > 0, not " + std::to_string(rtol));
  if (max_iterations < 0)
    throw InternalError(engine + ": solve() needs max_iterations >= 0, not " + std::to_string(max_iterations));
}

/// The start of solve() once its arguments are checked: x of b's size (zeros when it was not),
/// and x = 0 when b = 0 or when an entry of x is not finite. Returns ||b||_2; for 0, x = 0 is
/// the answer and no iteration is run.
inline double prepare_start(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  if (x->size() != b.size()) x->setZero(b.size());
  const double bn = b.norm();
  if (bn == 0.0 || !x->allFinite()) x->setZero();
  return bn;
}

/// What the entries of A say before any preconditioner is built: numerical_failure for an
/// entry that is not finite, not_positive_definite for a diagonal entry <= 0 (a symmetric
/// positive definite matrix has a positive diagonal), success otherwise.
inline FactorizationResult screen_matrix(const SparseMatrix& A) {
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (!std::isfinite(it.value()))
        return {FactorizationStatus::numerical_failure,
                "the entry (" + std::to_string(it.row()) + ", " + std::to_string(it.col()) + ") is not finite"};
  const Eigen::VectorXd d = A.diagonal();
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (!(d(i) > 0.0))
      return {FactorizationStatus::not_positive_definite,
              "the diagonal entry " + std::to_string(i) + " is " + std::to_string(d(i)) + " <= 0"};
  return FactorizationResult::good();
}

/// ||b - A x||_2 / ||b||_2 (||b - A x||_2 for b = 0).
inline double relative_residual(const SparseMatrix& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const double bn = b.norm();
  const double rn = (b - A * x).norm();
  return bn > 0.0 ? rn / bn : rn;
}

}  // namespace hemivem::krylov
