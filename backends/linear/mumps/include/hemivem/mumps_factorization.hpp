// The sequential MUMPS engine ("mumps"): SparseFactorization on top of MUMPS' sequential
// build (libdmumps_seq), including MUMPS' own Schur-complement feature for static condensation.
//
// MUMPS is called with SYM=1 (symmetric positive definite, LDLᵀ without pivoting) and the
// lower triangle of A in centralized assembled format. A matrix that is not positive definite
// is reported as not_positive_definite: a zero pivot (INFOG(1) = -10), a structurally
// singular matrix (-6) or any negative pivot (INFOG(12) > 0); for schur_complement() a
// Schur complement S that fails a dense Cholesky factorization as well (A is positive definite
// exactly when A22 and S are).
//
// Analysis (JOB=1) is reused while the pattern holds: factorize() on a matrix with the pattern
// of the last analysis runs only the numeric factorization (JOB=2), and schur_complement() with
// the pattern and the same block1 as the last Schur analysis likewise. num_analyses() counts
// the analyses run. An analysis for a Schur complement and one without are different analyses,
// so alternating factorize() and schur_complement() on one object re-analyses each time; keep
// one object per use.
//
// schur_complement(A, block1, S) returns the full dense S (both triangles, rows and columns in
// the order of block1; MUMPS' centralized Schur, ICNTL(19)=1) at about the cost of one
// factorization. The factors of A22 stay for solve_interior(), which solves the internal
// problem (ICNTL(26)=0). Special cases: empty block1 gives a 0×0 S and a factorization of all
// of A (solve() works too); block1 holding every index gives S = A(block1, block1) without a
// sparse factorization and solve_interior() returns 0-row matrices.
// After schur_complement() with a non-empty block1, solve() throws InternalError (MUMPS holds
// the factors of A22 only); call factorize() for solves with all of A.
//
// rcond_estimate() after factorize() is 1/cond1, where cond1 is MUMPS' componentwise
// (Arioli–Demmel–Duff) condition number of A x = A·1 (RINFOG(10), error analysis ICNTL(11)=1).
// It is computed on the first call after each factorization (a few solves) and cached. It is
// invariant under diagonal scaling, so it is not the same number as CHOLMOD's rcond; it is
// −1 when no factorization of all of A is held.
//
// Outputs (X, X2, S) are written only on success. Options used: verbosity (0: MUMPS prints
// nothing; 1–4: MUMPS' ICNTL(4) print level on standard output), threads (ICNTL(16), the
// number of OpenMP threads when MUMPS was built with OpenMP).
//
// One MUMPS instance (DMUMPS_STRUC_C) per object, released (JOB=-2) by the destructor. An
// object is not thread-safe (its const methods call MUMPS too); distinct objects are
// independent.
//
// Never link this backend and hemivem::linear_mumps_mpi into one program: the sequential and
// the MPI builds of MUMPS export the same symbols. CMake refuses such a target (property
// MUMPS_FLAVOUR); the linker does too (both define hemivem_mumps_flavour_guard).
#pragma once

#include <hemivem/sparse_factorization.hpp>

#include <memory>
#include <span>
#include <string>

namespace hemivem {

class MumpsFactorization final : public SparseFactorization {
 public:
  explicit MumpsFactorization(const FactorizationOptions& options = {});
  ~MumpsFactorization() override;
  MumpsFactorization(const MumpsFactorization&) = delete;
  MumpsFactorization& operator=(const MumpsFactorization&) = delete;

  std::string name() const override { return "mumps"; }

  FactorizationResult analyze(const SparseMatrix& A) override;
  FactorizationResult factorize(const SparseMatrix& A) override;
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override;
  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                       Eigen::MatrixXd* S) override;
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override;
  double rcond_estimate() const override;

  /// Number of symbolic analyses (MUMPS JOB=1) this object has run.
  int num_analyses() const noexcept;
  /// Number of successful numeric factorizations (MUMPS JOB=2) this object has run.
  int num_factorizations() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hemivem
