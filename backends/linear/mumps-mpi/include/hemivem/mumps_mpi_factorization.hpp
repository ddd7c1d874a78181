// The MPI MUMPS engine ("mumps-mpi"): SparseFactorization on top of MUMPS' MPI build
// (libdmumps), with the factorization distributed over MPI_COMM_WORLD. It is also the
// ProcessGroup of its processes (hemivem/process_group.hpp).
//
// Everything the sequential engine documents (hemivem/mumps_factorization.hpp: SYM=1, lower
// triangle read, not-positive-definite detection, analysis reuse, MUMPS' Schur complement,
// solve_interior, rcond_estimate) holds here too; the difference is where the data lives.
//
// SPMD contract
//   - Every process of MPI_COMM_WORLD constructs the object and calls the same methods in the
//     same order (every method, the const ones and the destructor included, is collective;
//     num_analyses(), num_factorizations(), name(), holds_results(), num_processes() and the
//     static functions are not; share() is).
//   - Rank 0 is MUMPS' host (PAR=1: it works too). The problem is centralized there: the
//     matrix A (assembled, ICNTL(18)=0), the right-hand sides B and B2 and block1 are read on
//     rank 0 only; on the other ranks these arguments are ignored and may be empty.
//   - Outputs (X, X2, S) are written on rank 0 only (on success), and left untouched elsewhere
//     (where the output pointers may be null).
//   - Every process returns the same FactorizationResult (rank 0 decides and broadcasts), and
//     rcond_estimate() returns the same number everywhere.
//
// MPI lifetime
//   - If MPI is not initialized when the first object is constructed (or mpi_rank()/mpi_size()
//     is called), hemivem initializes it (MPI_Init_thread, MPI_THREAD_FUNNELED) and finalizes
//     it at program exit (a function-local static guard whose destructor calls MPI_Finalize).
//     A program started without mpirun is then an MPI singleton (one process).
//   - If the caller initialized MPI, the caller finalizes it, after destroying every object.
//   - Constructing an object after MPI_Finalize gives an object whose calls throw InternalError.
//
// Never link this backend and hemivem::linear_mumps into one program: the MPI and the
// sequential builds of MUMPS export the same symbols. CMake refuses such a target (property
// MUMPS_FLAVOUR); the linker does too (both define hemivem_mumps_flavour_guard). A tool
// offering both either builds one executable per flavour or loads this engine as a module
// (hemivem/mumps_mpi_plugin.hpp: dlopen with RTLD_LOCAL | RTLD_DEEPBIND).
#pragma once

#include <hemivem/process_group.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <memory>
#include <span>
#include <string>

namespace hemivem {

class MumpsMpiFactorization final : public SparseFactorization, public ProcessGroup {
 public:
  /// Collective over MPI_COMM_WORLD; initializes MPI when nobody did (see above).
  explicit MumpsMpiFactorization(const FactorizationOptions& options = {});
  /// Collective (MUMPS JOB=-2).
  ~MumpsMpiFactorization() override;
  MumpsMpiFactorization(const MumpsMpiFactorization&) = delete;
  MumpsMpiFactorization& operator=(const MumpsMpiFactorization&) = delete;

  std::string name() const override { return "mumps-mpi"; }

  FactorizationResult analyze(const SparseMatrix& A) override;
  FactorizationResult factorize(const SparseMatrix& A) override;
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override;
  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                       Eigen::MatrixXd* S) override;
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override;
  double rcond_estimate() const override;
  /// True on rank 0 (MUMPS' host), where the outputs are written.
  bool holds_results() const override;
  /// The size of MPI_COMM_WORLD (1 after MPI_Finalize).
  int num_processes() const override;
  /// Collective: rank 0's `value` on every process (a broadcast over MPI_COMM_WORLD).
  int share(int value) const override;

  /// Number of symbolic analyses (MUMPS JOB=1) this object has run.
  int num_analyses() const noexcept;
  /// Number of successful numeric factorizations (MUMPS JOB=2) this object has run.
  int num_factorizations() const noexcept;

  /// This process' rank in MPI_COMM_WORLD (initializes MPI when needed, as the constructor).
  static int mpi_rank();
  /// The number of processes in MPI_COMM_WORLD (initializes MPI when needed).
  static int mpi_size();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hemivem
