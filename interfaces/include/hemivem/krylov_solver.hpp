// The contract of an iterative engine for sparse symmetric positive definite systems: a
// preconditioned conjugate gradient method, the linear engine of the full-space route
// (docs/full-space.md), which never factorizes the whole matrix.
//
// Call sequence (as Eigen's iterative solvers):
//   compute(A, hints)          sets the preconditioner up for A (both triangles stored, as
//                              hemivem assembles it), with what KrylovHints tells of A (the
//                              vectors it nearly annihilates, its node blocks); the engine may
//                              keep a reference to A instead of a copy (as Eigen's iterative
//                              solvers do), so A stays alive and unchanged while solve() is
//                              called on it (the engine never reads it otherwise, not even
//                              when it is destroyed). Calling compute() again with the
//                              same matrix object, its values changed in place and its pattern
//                              not, sets the preconditioner up again reusing what the engine
//                              can (GAMG keeps its aggregates and interpolation);
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
#include <utility>
#include <vector>

#include <hemivem/row_distribution.hpp>
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

/// What a preconditioner may use besides A's entries.
struct KrylovHints {
  /// Column by column, the vectors A nearly annihilates (the rigid motions of an elastic body,
  /// for the aggregates of algebraic multigrid), with A.rows() rows; or no columns.
  Eigen::MatrixXd near_null;
  /// The unknowns come in consecutive groups of this many that belong to one node (the
  /// components of a displacement), so that multigrid can aggregate nodes; 1 when they do not.
  int block_size = 1;
  /// Null: A is the whole matrix, in one process. Otherwise the system is distributed by these
  /// rows (hemivem/row_distribution.hpp): A holds this process's owned rows with local column
  /// numbers (its columns(): owned rows, then ghosts), and near_null, b and x hold the owned rows;
  /// compute() and solve() are collective. An engine that runs in one process refuses more than
  /// one process (InputError naming it).
  const RowDistribution* rows = nullptr;
  KrylovHints(Eigen::MatrixXd near_null_space = {}, int node_block = 1)  // NOLINT: a near-null space alone converts
      : near_null(std::move(near_null_space)), block_size(node_block) {}
};

class KrylovSolver {
 public:
  virtual ~KrylovSolver() = default;
  /// The engine's name, as make_krylov_solver() takes it.
  virtual std::string name() const = 0;
  /// True when compute() and solve() take a system distributed over the processes of
  /// krylov_world() (KrylovHints::rows); false for an engine of one process.
  virtual bool runs_across_processes() const noexcept { return false; }
  /// Sets the preconditioner up for A (square, symmetric, both triangles stored; kept by
  /// reference, see above); `hints.near_null` has A.rows() rows (or no columns) and
  /// `hints.block_size` divides A.rows().
  virtual FactorizationResult compute(const SparseMatrix& A, const KrylovHints& hints) = 0;
  /// CG from the start *x (resized to zeros when its size is not b's) on the A of the last
  /// successful compute().
  virtual KrylovSolveResult solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol,
                                  int max_iterations) const = 0;
  /// Gives back what compute() set up (the preconditioner and the engine's matrix); solve()
  /// then needs a compute() again. Collective where compute() is.
  virtual void release() {}
};

/// The Krylov engines, in order of preference: "petsc-gamg" (PETSc's CG with its smoothed
/// aggregation multigrid, GAMG, given the near-null space), "petsc-hypre" (PETSc's CG with
/// hypre's BoomerAMG), "eigen-cg" (Eigen's CG with an incomplete Cholesky factor, always built).
const std::vector<std::string>& known_krylov_solvers();
/// Those built into this hemivem.
std::vector<std::string> available_krylov_solvers();
/// True when `name` (case-insensitive, '_' as '-') is one of known_krylov_solvers().
bool is_krylov_solver(const std::string& name);
/// The processes of MPI_COMM_WORLD: this one's rank and their number, MPI initialized through the
/// PETSc Krylov module when it is built (an MPI singleton when started without mpirun);
/// {0, 1} without it. InputError when the module is built but cannot be loaded or PETSc cannot
/// start.
struct ProcessWorld {
  int rank = 0;
  int size = 1;
};
ProcessWorld krylov_world();
/// Collective over krylov_world(): the distribution of `layout`'s rows over its processes, for the
/// PETSc engines (KrylovHints::rows). Layouts must be consistent: ranges in the order of the
/// ranks covering 0..global-1, ghosts owned by other processes; an inconsistent layout throws
/// InternalError on every process (with the same message). In one process, OneProcessRows
/// (without PETSc: only that, InputError otherwise).
std::unique_ptr<RowDistribution> make_distributed_rows(RowLayout layout);
/// Collective over krylov_world(): one row on each process, for the collectives among the
/// processes themselves (gathering a value or a text from each); make_distributed_rows.
std::unique_ptr<RowDistribution> process_rows();

/// The engine `name` ("auto": the first available); InputError naming the engine for one
/// not known, or known and not built (with the list of those built).
std::unique_ptr<KrylovSolver> make_krylov_solver(const std::string& name);

}  // namespace hemivem
