// The contract of an iterative engine for sparse symmetric positive definite systems: a
// preconditioned conjugate gradient method, the linear engine of the full-space route
// (docs/full-space.md), which never factorizes the whole matrix.
//
// Call sequence (as Eigen's iterative solvers):
//   compute(A, near_null)      sets the preconditioner up for A (both triangles stored, as
//                              hemivem assembles it); `near_null` holds, column by column, the
//                              vectors A nearly annihilates (the rigid motions of an elastic
//                              body, for algebraic multigrid), and may have no columns;
//   solve(b, x, rtol, max_it)  x ~ A^{-1} b by CG started from *x, until the true residual
//                              ||b - A x||_2 <= rtol ||b||_2 or max_it iterations.
// Numerical outcomes are statuses with a human message (FactorizationStatus: an indefinite
// matrix met by CG is not_positive_definite; no convergence within max_it, or a breakdown, is
// numerical_failure); a call that breaks the contract (sizes, solve() before a successful
// compute()) throws InternalError. Nothing prints or exits.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

/// What one solve did.
struct KrylovSolveResult {
  FactorizationStatus status = FactorizationStatus::success;
  std::string message;
  int iterations = 0;
  /// ||b - A x||_2 / ||b||_2 of the x returned (0 for b = 0).
  double relative_residual = 0.0;
  bool ok() const noexcept { return status == FactorizationStatus::success; }
};

class KrylovSolver {
 public:
  virtual ~KrylovSolver() = default;
  /// The engine's name, as make_krylov_solver() takes it.
  virtual std::string name() const = 0;
  /// Sets the preconditioner up for A (square, symmetric, both triangles stored); `near_null`
  /// has A.rows() rows (or no columns).
  virtual FactorizationResult compute(const SparseMatrix& A, const Eigen::MatrixXd& near_null) = 0;
  /// CG from the start *x (resized to zeros when its size is not b's) on the A of the last
  /// successful compute().
  virtual KrylovSolveResult solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol,
                                  int max_iterations) const = 0;
};

/// The Krylov engines, in order of preference: "petsc-gamg" (PETSc's CG with its smoothed
/// aggregation multigrid, GAMG, given the near-null space), "petsc-hypre" (PETSc's CG with
/// hypre's BoomerAMG), "eigen-cg" (Eigen's CG with an incomplete Cholesky factor, always built).
const std::vector<std::string>& known_krylov_solvers();
/// Those built into this hemivem.
std::vector<std::string> available_krylov_solvers();
/// True when `name` (case-insensitive, '_' as '-') is one of known_krylov_solvers().
bool is_krylov_solver(const std::string& name);
/// The engine `name` ("auto": the first available); InputError naming the engine for one
/// not known, or known and not built (with the list of those built).
std::unique_ptr<KrylovSolver> make_krylov_solver(const std::string& name);

}  // namespace hemivem
