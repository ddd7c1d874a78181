// The Krylov engines "petsc-gamg" and "petsc-hypre": PETSc's conjugate gradient (KSPCG, the
// unpreconditioned residual norm), in one process on a sequential AIJ matrix that reads A's own
// arrays (A's compressed columns are its rows: A is symmetric; no copy is made where PETSc's
// index type is int and A is compressed), across processes on an MPI AIJ matrix (below),
// preconditioned by
//   petsc-gamg   PETSc's smoothed aggregation multigrid (PCGAMG) given the near-null space
//                (MatSetNearNullSpace with the columns of `near_null`, orthonormalized: the
//                rigid motions of an elastic body make its coarse spaces those of elasticity)
//                and the block size (the graph it aggregates is then one of nodes);
//   petsc-hypre  hypre's BoomerAMG (PCHYPRE); with a near-null space of six columns (a solid's
//                rigid motions) its strong threshold is 0.5, hypre's advice for 3D elasticity,
//                otherwise hypre's default 0.25.
//
// solve() runs CG from *x until PETSc's recursive residual is below rtol ||b||_2, then computes
// the true residual ||b - A x||_2 / ||b||_2 and restarts CG from x (at most four times, within
// max_iterations in all) while it is above rtol. CG stopping on negative curvature
// (KSP_DIVERGED_INDEFINITE_MAT) or on an indefinite preconditioner (KSP_DIVERGED_INDEFINITE_PC)
// is not_positive_definite, as is a diagonal entry <= 0 found by compute(); any other reason
// to stop short of rtol (the iteration limit, a breakdown, a PETSc error) is numerical_failure
// with PETSc's name for the reason.
//
// A system distributed over processes (KrylovHints::rows of several processes, made by
// make_distributed_rows(): hemivem/petsc_row_distribution.hpp) runs on PETSC_COMM_WORLD:
// compute() copies this process's owned rows into the CSR rows of a MATMPIAIJ with global
// columns (local column c < owned is row first + c, the others layout().ghosts[c - owned]), of
// the block size given, with the near-null space's owned rows orthonormalized together (each
// process's rows factored by QR, the stacked R factors by the pivoted QR of the sequential
// path, threshold 1e-12, on every process alike) as MPI vectors; solve() takes the owned rows
// of b and x and runs the same CG, restarts and true-residual check with global norms. Calling
// compute() again with the same matrix object, values changed in place, sets the copy's values
// again (MatSetValues) and keeps the KSP, so GAMG reuses its interpolation. Everything is
// collective and every process reaches the same outcome: arguments that break the contract on
// one process throw InternalError on all (the lowest such process's message), a diagonal entry
// <= 0 or a PETSc error on one process is the status of all, PETSc's reasons are collective.
// The global option -matptap_via rap (below) is cleared during the distributed set-ups and
// solves (PETSc's MPI matrices do not know it). With rows of one process (OneProcessRows) the
// sequential path runs, unchanged.
//
// PETSc is initialized by the first object (PetscInitializeNoArguments, without PETSc's signal
// handlers; MPI through it when nobody initialized MPI: a program started without mpirun is a
// singleton), and finalized at program exit when hemivem initialized it, no object is left and
// MPI is still running. Every PETSc call runs under PETSc's PetscReturnErrorHandler, so nothing
// prints; each object keeps its options in its own PETSc options database.
//
// PETSc's Debian build links the MPI build of MUMPS, whose symbols are those of the sequential
// MUMPS hemivem links: these classes live in a module that hemivem's Krylov factory loads at run
// time (hemivem/petsc_krylov_plugin.hpp), never in a library a hemivem program links.
#pragma once

#include <hemivem/krylov_solver.hpp>

#include <memory>
#include <string>

namespace hemivem {

class PetscKrylovSolver : public KrylovSolver {
 public:
  enum class Preconditioner { gamg, hypre };

  ~PetscKrylovSolver() override;
  PetscKrylovSolver(const PetscKrylovSolver&) = delete;
  PetscKrylovSolver& operator=(const PetscKrylovSolver&) = delete;

  std::string name() const override;
  bool runs_across_processes() const noexcept override { return true; }
  FactorizationResult compute(const SparseMatrix& A, const KrylovHints& hints) override;
  /// Not thread-safe: the PETSc solver and vectors live in the object.
  KrylovSolveResult solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol,
                          int max_iterations) const override;
  void release() override;

 protected:
  explicit PetscKrylovSolver(Preconditioner preconditioner);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// "petsc-gamg".
class PetscGamgSolver final : public PetscKrylovSolver {
 public:
  PetscGamgSolver() : PetscKrylovSolver(Preconditioner::gamg) {}
};

/// "petsc-hypre".
class PetscHypreSolver final : public PetscKrylovSolver {
 public:
  PetscHypreSolver() : PetscKrylovSolver(Preconditioner::hypre) {}
};

}  // namespace hemivem
