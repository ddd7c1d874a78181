// The PETSc Krylov engines (hemivem/petsc_krylov_solver.hpp): the sequential path on a
// MATSEQAIJ that reads A's arrays, the distributed path on a MATMPIAIJ that reads a process's
// owned rows where they lie (KrylovHints::rows), and the CG runs, restarts and outcomes both share.
#include <hemivem/petsc_krylov_solver.hpp>

#include <hemivem/error.hpp>

#include <petscksp.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "krylov_common.hpp"
#include "petsc_support.hpp"

namespace hemivem {

namespace {

/// Gives the heap's free pages back to the system (glibc's malloc_trim; nothing elsewhere): the
/// set-up of a preconditioner frees large temporaries (GAMG's Galerkin products, the CSR copy of
/// the rows) that the allocator would otherwise keep in the process's resident memory.
void give_back_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

using krylov::kMaxRestarts;
using krylov::scientific;

using petsc::PetscRuntime;
using petsc::QuietErrors;

/// The orthonormal basis of the span of the columns of V (rank by a pivoted QR, columns whose
/// pivot is below 1e-12 of the largest dropped).
Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& V) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(V);
  qr.setThreshold(1e-12);
  const Eigen::Index rank = qr.rank();
  Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(V.rows(), rank);
  Q.applyOnTheLeft(qr.householderQ());
  return Q;
}

/// Collective over comm: the owned rows of an orthonormal basis of the span of the columns of
/// the distributed V (each process's V holds its owned rows), as orthonormal_basis() finds it
/// for the whole V: each process factors its rows V_p = Q_p R_p (Householder), every process
/// gathers the stacked R_p and factors them by the same pivoted QR (threshold 1e-12), S P =
/// Q_S R, whose rank is that of V; this process's rows of the basis are Q_p times its rows of
/// Q_S. Every process finds the same rank.
Eigen::MatrixXd distributed_orthonormal_basis(MPI_Comm comm, const Eigen::MatrixXd& V) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Index n = V.rows(), k = V.cols(), m = std::min(n, k);
  Eigen::HouseholderQR<Eigen::MatrixXd> local(V);
  const RowMajor R = local.matrixQR().topRows(m).triangularView<Eigen::Upper>();
  Eigen::MatrixXd Q_local = Eigen::MatrixXd::Identity(n, m);
  if (n > 0 && m > 0) Q_local.applyOnTheLeft(local.householderQ());
  const double my_rows = static_cast<double>(m);
  const std::vector<double> rows = petsc::all_gather(comm, &my_rows, 1);
  const std::vector<double> stacked = petsc::all_gather(comm, R.data(), static_cast<std::int64_t>(m * k));
  const Eigen::Index total = static_cast<Eigen::Index>(stacked.size()) / std::max<Eigen::Index>(k, 1);
  Eigen::Index offset = 0;
  for (int r = 0; r < petsc::comm_rank(comm); ++r) offset += static_cast<Eigen::Index>(rows[static_cast<std::size_t>(r)]);
  const Eigen::MatrixXd S = Eigen::Map<const RowMajor>(stacked.data(), total, k);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(S);
  qr.setThreshold(1e-12);
  const Eigen::Index rank = qr.rank();
  Eigen::MatrixXd Q_stacked = Eigen::MatrixXd::Identity(total, rank);
  if (total > 0 && rank > 0) Q_stacked.applyOnTheLeft(qr.householderQ());
  return Q_local * Q_stacked.middleRows(offset, m);
}

/// Whether PETSc can read A's compressed arrays as its own (its indices are int as Eigen's): the
/// sequential matrix and the diagonal block of a distributed one are then A's arrays.
bool petsc_reads_in_place(const SparseMatrix& A) { return A.isCompressed() && sizeof(PetscInt) == sizeof(int); }

/// The global column of local column c of a process's rows (its owned rows, then its ghosts).
Eigen::Index global_column(const RowLayout& layout, Eigen::Index c) {
  return c < layout.owned ? layout.first + c : layout.ghosts[static_cast<std::size_t>(c - layout.owned)];
}

/// krylov::screen_matrix on a process's owned rows, its messages in global rows and columns.
FactorizationResult screen_owned_rows(const SparseMatrix& A, const RowLayout& layout) {
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (!std::isfinite(it.value()))
        return {FactorizationStatus::numerical_failure,
                "the entry (" + std::to_string(layout.first + it.row()) + ", " +
                    std::to_string(global_column(layout, it.col())) + ") is not finite"};
  for (Eigen::Index i = 0; i < layout.owned; ++i) {
    const double d = A.coeff(i, i);  // local column i: global row first + i
    if (!(d > 0.0))
      return {FactorizationStatus::not_positive_definite,
              "the diagonal entry " + std::to_string(layout.first + i) + " is " + std::to_string(d) + " <= 0"};
  }
  return FactorizationResult::good();
}

/// What breaks the contract of compute() on a distributed system in this process's arguments
/// (empty when nothing): A of the owned rows and the local columns, the near-null space of the
/// owned rows, a block size dividing the owned rows, the rows of this world. Collective: the
/// near-null space's columns and the block size must be the same on every process.
std::string distributed_argument_problem(MPI_Comm comm, const std::string& engine, const SparseMatrix& A,
                                         const KrylovHints& hints) {
  const RowDistribution& rows = *hints.rows;
  const RowLayout& layout = rows.layout();
  const std::string sizes = std::to_string(layout.owned) + " owned rows and " + std::to_string(rows.columns()) +
                            " local columns";
  std::string problem;
  if (rows.size() != petsc::comm_size(comm) || rows.rank() != petsc::comm_rank(comm))
    problem = "the rows are those of process " + std::to_string(rows.rank()) + " of " + std::to_string(rows.size()) +
              ", this is process " + std::to_string(petsc::comm_rank(comm)) + " of " +
              std::to_string(petsc::comm_size(comm));
  else if (A.rows() != layout.owned || A.cols() != rows.columns())
    problem = "compute() needs the owned rows of the matrix in local columns (" + sizes + "), not " +
              std::to_string(A.rows()) + " x " + std::to_string(A.cols());
  else if (hints.near_null.cols() > 0 && hints.near_null.rows() != layout.owned)
    problem = "the near-null space has " + std::to_string(hints.near_null.rows()) + " rows for " +
              std::to_string(layout.owned) + " owned rows";
  else if (hints.block_size < 1 || layout.owned % hints.block_size != 0)
    problem = "a block size of " + std::to_string(hints.block_size) + " for " + std::to_string(layout.owned) +
              " owned rows";
  int mine[4] = {static_cast<int>(hints.near_null.cols()), -static_cast<int>(hints.near_null.cols()),
                 hints.block_size, -hints.block_size};
  int most[4] = {0, 0, 0, 0};
  MPI_Allreduce(mine, most, 4, MPI_INT, MPI_MAX, comm);
  if (problem.empty() && most[0] != -most[1])
    problem = "the near-null space has " + std::to_string(hints.near_null.cols()) +
              " columns here, between " + std::to_string(-most[1]) + " and " + std::to_string(most[0]) +
              " on the processes";
  if (problem.empty() && most[2] != -most[3])
    problem = "the block size is " + std::to_string(hints.block_size) + " here, between " +
              std::to_string(-most[3]) + " and " + std::to_string(most[2]) + " on the processes";
  return problem.empty() ? problem : engine + ": " + problem;
}

}  // namespace

struct PetscKrylovSolver::Impl {
  Preconditioner preconditioner;
  Mat matrix = nullptr;
  KSP ksp = nullptr;
  Vec rhs = nullptr, solution = nullptr, residual = nullptr;
  PetscOptions options = nullptr;
  PetscInt size = 0;
  bool computed = false;
  bool reused = false;  ///< the preconditioner was set up again on values changed in place
  /// The arrays of A the AIJ matrix reads (null where it holds its own copy) and a checksum of
  /// their pattern.
  const void* wrapped_values = nullptr;
  const void* wrapped_starts = nullptr;
  const void* wrapped_indices = nullptr;
  std::size_t wrapped_pattern = 0;

  /// The distributed path (KrylovHints::rows of several processes). PETSc's objects live on
  /// `comm` (PETSC_COMM_WORLD; PETSC_COMM_SELF on the sequential path). The MATMPIAIJ is made of
  /// its two blocks' arrays (MatCreateMPIAIJWithSplitArrays), which PETSc reads where they lie:
  /// - the diagonal block (the owned rows and columns) is A's first `owned` columns: A is
  ///   symmetric (the contract), so that its compressed columns are the block's rows. Where
  ///   PETSc's indices are int and A is compressed, the block is A's own arrays (the contract
  ///   keeps A alive and unchanged until the solves are done), so that the rows are not held
  ///   twice; otherwise a copy (d_starts, d_columns, d_values);
  /// - the off-diagonal block (the owned rows, the columns of other processes: a layer of the
  ///   rows' neighbours) is a CSR copy, its columns global and increasing in each row (PETSc
  ///   numbers them again in place), its values written from A's ghost columns, whose global
  ///   columns increase with them (RowLayout::ghosts).
  MPI_Comm comm = PETSC_COMM_SELF;
  bool distributed = false;
  bool diagonal_copied = false;
  std::vector<PetscInt> d_starts, d_columns;
  std::vector<PetscScalar> d_values;
  std::vector<PetscInt> o_starts, o_columns;
  std::vector<PetscScalar> o_values;
  /// The arrays of the A the matrix was made from and a checksum of its pattern and layout.
  const void* source_values = nullptr;
  const void* source_starts = nullptr;
  const void* source_indices = nullptr;
  std::size_t source_pattern = 0;

  /// A checksum of A's pattern (its size, column starts and row indices).
  static std::size_t pattern_checksum(const SparseMatrix& A) {
    std::size_t h = static_cast<std::size_t>(A.rows()) * 1000003u + static_cast<std::size_t>(A.nonZeros());
    auto mix = [&h](int v) { h = (h ^ static_cast<std::size_t>(static_cast<unsigned>(v))) * 1099511628211ull; };
    for (Eigen::Index j = 0; j <= A.outerSize(); ++j) mix(A.outerIndexPtr()[j]);
    for (Eigen::Index k = 0; k < A.nonZeros(); ++k) mix(A.innerIndexPtr()[k]);
    return h;
  }

  /// True when A is the matrix object the AIJ matrix reads, its pattern unchanged (its values
  /// changed in place: the systems of one Newton iteration).
  bool same_matrix(const SparseMatrix& A) const {
    return computed && wrapped_values != nullptr && A.isCompressed() && A.rows() == size &&
           static_cast<const void*>(A.valuePtr()) == wrapped_values &&
           static_cast<const void*>(A.outerIndexPtr()) == wrapped_starts &&
           static_cast<const void*>(A.innerIndexPtr()) == wrapped_indices && pattern_checksum(A) == wrapped_pattern;
  }

  /// A checksum of a process's rows: A's pattern and the layout.
  static std::size_t layout_checksum(const SparseMatrix& A, const RowLayout& layout) {
    std::size_t h = pattern_checksum(A);
    auto mix = [&h](Eigen::Index v) { h = (h ^ static_cast<std::size_t>(v)) * 1099511628211ull; };
    mix(layout.first);
    mix(layout.owned);
    mix(layout.global);
    for (const Eigen::Index g : layout.ghosts) mix(g);
    return h;
  }

  /// same_matrix() for this process's rows of a distributed system.
  bool same_distributed_matrix(const SparseMatrix& A, const RowLayout& layout) const {
    return computed && distributed && A.isCompressed() && A.rows() == size &&
           static_cast<const void*>(A.valuePtr()) == source_values &&
           static_cast<const void*>(A.outerIndexPtr()) == source_starts &&
           static_cast<const void*>(A.innerIndexPtr()) == source_indices && layout_checksum(A, layout) == source_pattern;
  }

  /// The blocks' values from A: the off-diagonal block's from A's ghost columns, each row's
  /// entries in the order of their global columns; the diagonal block's from A's first columns
  /// where it is a copy (otherwise PETSc reads them in A).
  void write_block_values(const SparseMatrix& A) {
    std::vector<PetscInt> next(o_starts.begin(), o_starts.end() - 1);
    for (Eigen::Index j = size; j < A.cols(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        o_values[static_cast<std::size_t>(next[static_cast<std::size_t>(it.row())]++)] = it.value();
    if (!diagonal_copied) return;
    std::size_t k = 0;
    for (Eigen::Index j = 0; j < size; ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) d_values[k++] = it.value();
  }

  /// The blocks' structure from A and `layout` (the off-diagonal block's always, the diagonal
  /// block's where it is a copy), then their values (write_block_values()).
  void make_blocks(const SparseMatrix& A, const RowLayout& layout) {
    const auto owned = static_cast<std::size_t>(layout.owned);
    o_starts.assign(owned + 1, 0);
    for (Eigen::Index j = layout.owned; j < A.cols(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) ++o_starts[static_cast<std::size_t>(it.row()) + 1];
    std::partial_sum(o_starts.begin(), o_starts.end(), o_starts.begin());
    // never a null array for PETSc, even without entries
    o_columns.reserve(1);
    o_values.reserve(1);
    o_columns.resize(static_cast<std::size_t>(o_starts.back()));
    o_values.resize(static_cast<std::size_t>(o_starts.back()));
    std::vector<PetscInt> next(o_starts.begin(), o_starts.end() - 1);
    for (Eigen::Index j = layout.owned; j < A.cols(); ++j) {
      const auto column = static_cast<PetscInt>(global_column(layout, j));
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        o_columns[static_cast<std::size_t>(next[static_cast<std::size_t>(it.row())]++)] = column;
    }
    diagonal_copied = !petsc_reads_in_place(A);
    if (diagonal_copied) {
      d_starts.assign(owned + 1, 0);
      for (Eigen::Index j = 0; j < layout.owned; ++j)
        d_starts[static_cast<std::size_t>(j) + 1] =
            d_starts[static_cast<std::size_t>(j)] + static_cast<PetscInt>(A.innerVector(j).nonZeros());
      d_columns.reserve(1);
      d_values.reserve(1);
      d_columns.resize(static_cast<std::size_t>(d_starts.back()));
      d_values.resize(static_cast<std::size_t>(d_starts.back()));
      std::size_t k = 0;
      for (Eigen::Index j = 0; j < layout.owned; ++j)
        for (SparseMatrix::InnerIterator it(A, j); it; ++it) d_columns[k++] = static_cast<PetscInt>(it.row());
    }
    write_block_values(A);
  }

  /// Frees the blocks' arrays (their memory, not only their entries): after the matrix that
  /// reads them is destroyed.
  void free_blocks() {
    std::vector<PetscInt>().swap(d_starts);
    std::vector<PetscInt>().swap(d_columns);
    std::vector<PetscScalar>().swap(d_values);
    std::vector<PetscInt>().swap(o_starts);
    std::vector<PetscInt>().swap(o_columns);
    std::vector<PetscScalar>().swap(o_values);
    diagonal_copied = false;
  }

  /// update_values() for a distributed system: the blocks' new values (write_block_values());
  /// then the matrix assembled and the preconditioner set up again. The assembly changes no
  /// place (the pattern is the same and nothing is stashed): it increases the matrix's state, so
  /// that the KSP sees a changed operator of the same nonzero pattern (GAMG reuses its
  /// interpolation, make_ksp()), and drops what PETSc keeps of the former values (the blocks'
  /// inverted diagonals, the diagonal vector of the MATMPIAIJ) and the symmetry flag, set again
  /// below.
  PetscErrorCode update_distributed_values(const SparseMatrix& A, std::string* error) {
    write_block_values(A);
    HEMIVEM_PETSC(MatAssemblyBegin(matrix, MAT_FINAL_ASSEMBLY));
    HEMIVEM_PETSC(MatAssemblyEnd(matrix, MAT_FINAL_ASSEMBLY));
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));
    HEMIVEM_PETSC(KSPSetOperators(ksp, matrix, matrix));
    HEMIVEM_PETSC(KSPSetUp(ksp));
    give_back_free_memory();
    reused = true;
    return 0;
  }

  /// A's values changed in place: PETSc is told, and the preconditioner is set up again at the
  /// next solve (GAMG reusing its interpolation, below).
  PetscErrorCode update_values(std::string* error) {
    // the access to its values and their return: PETSc counts the matrix changed (its state
    // increased, its cached diagonal invalidated)
    PetscScalar* values = nullptr;
    HEMIVEM_PETSC(MatSeqAIJGetArray(matrix, &values));
    HEMIVEM_PETSC(MatSeqAIJRestoreArray(matrix, &values));
    HEMIVEM_PETSC(KSPSetOperators(ksp, matrix, matrix));
    HEMIVEM_PETSC(KSPSetUp(ksp));
    reused = true;
    return 0;
  }

  explicit Impl(Preconditioner pc) : preconditioner(pc) { PetscRuntime::instance().attach(); }
  ~Impl() {
    release();
    PetscRuntime::instance().detach();
  }

  const char* name() const { return preconditioner == Preconditioner::gamg ? "petsc-gamg" : "petsc-hypre"; }

  /// Destroys the PETSc objects (left alone once PETSc is finalized).
  void release() {
    computed = false;
    wrapped_values = wrapped_starts = wrapped_indices = nullptr;
    source_values = source_starts = source_indices = nullptr;
    distributed = false;
    comm = PETSC_COMM_SELF;
    if (!PetscRuntime::running()) {
      matrix = nullptr, ksp = nullptr, rhs = solution = residual = nullptr, options = nullptr;
      free_blocks();
      return;
    }
    {
      const QuietErrors quiet;
      if (ksp) KSPDestroy(&ksp);
      if (matrix) MatDestroy(&matrix);
      if (rhs) VecDestroy(&rhs);
      if (solution) VecDestroy(&solution);
      if (residual) VecDestroy(&residual);
      if (options) PetscOptionsDestroy(&options);
    }
    free_blocks();
  }

  /// The near-null space of the matrix, for GAMG's aggregates: Q, an orthonormal basis of the
  /// columns of the near-null space given (orthonormal_basis(), or on a distributed system
  /// this process's rows of distributed_orthonormal_basis()).
  PetscErrorCode set_near_null_space(const Eigen::MatrixXd& Q, std::string* error) {
    std::vector<Vec> vectors(static_cast<std::size_t>(Q.cols()), nullptr);
    PetscErrorCode code = 0;
    for (Eigen::Index k = 0; k < Q.cols() && code == 0; ++k) {
      Vec& v = vectors[static_cast<std::size_t>(k)];
      code = distributed ? VecCreateMPI(comm, size, PETSC_DETERMINE, &v) : VecCreateSeq(PETSC_COMM_SELF, size, &v);
      PetscScalar* data = nullptr;
      if (code == 0) code = VecGetArray(v, &data);
      if (code == 0) {
        for (PetscInt i = 0; i < size; ++i) data[i] = Q(i, k);
        code = VecRestoreArray(v, &data);
      }
    }
    MatNullSpace space = nullptr;
    if (code == 0)
      code = MatNullSpaceCreate(comm, PETSC_FALSE, static_cast<PetscInt>(Q.cols()), vectors.data(), &space);
    if (code == 0) code = MatSetNearNullSpace(matrix, space);
    if (space) MatNullSpaceDestroy(&space);
    for (Vec& v : vectors)
      if (v) VecDestroy(&v);
    if (code != 0) {
      *error = petsc::error_message(code, "the near-null space (MatNullSpaceCreate, MatSetNearNullSpace)");
      return code;
    }
    return 0;
  }

  /// The AIJ matrix of A, its near-null space, the vectors and the KSP with its preconditioner.
  /// A's compressed columns are given as the rows: A is symmetric (the contract), so no
  /// row-major copy of it is made (its two triangles may differ by round-off; PETSc's matrix is
  /// then the transpose, as close to A). Where PETSc's indices are int and A is compressed, the
  /// matrix reads A's own arrays; otherwise it holds a copy.
  PetscErrorCode setup(const SparseMatrix& A, const KrylovHints& hints, std::string* error) {
    const bool readable = petsc_reads_in_place(A);
    size = static_cast<PetscInt>(A.rows());
    if (readable) {
      // PETSc reads A's arrays for as long as the matrix lives (the contract keeps A alive)
      HEMIVEM_PETSC(MatCreateSeqAIJWithArrays(
          PETSC_COMM_SELF, size, size, reinterpret_cast<PetscInt*>(const_cast<int*>(A.outerIndexPtr())),
          reinterpret_cast<PetscInt*>(const_cast<int*>(A.innerIndexPtr())), const_cast<double*>(A.valuePtr()),
          &matrix));
    } else {
      SparseMatrix C = A;
      C.makeCompressed();
      const std::vector<PetscInt> rows(C.outerIndexPtr(), C.outerIndexPtr() + C.cols() + 1);
      const std::vector<PetscInt> columns(C.innerIndexPtr(), C.innerIndexPtr() + C.nonZeros());
      HEMIVEM_PETSC(MatCreate(PETSC_COMM_SELF, &matrix));
      HEMIVEM_PETSC(MatSetSizes(matrix, size, size, size, size));
      HEMIVEM_PETSC(MatSetType(matrix, MATSEQAIJ));
      HEMIVEM_PETSC(MatSeqAIJSetPreallocationCSR(matrix, rows.data(), columns.data(), C.valuePtr()));
    }
    wrapped_values = readable ? static_cast<const void*>(A.valuePtr()) : nullptr;
    wrapped_starts = readable ? static_cast<const void*>(A.outerIndexPtr()) : nullptr;
    wrapped_indices = readable ? static_cast<const void*>(A.innerIndexPtr()) : nullptr;
    wrapped_pattern = readable ? pattern_checksum(A) : 0;
    if (hints.block_size > 1) HEMIVEM_PETSC(MatSetBlockSize(matrix, static_cast<PetscInt>(hints.block_size)));
    const Eigen::MatrixXd& near_null = hints.near_null;
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));

    if (near_null.cols() > 0)
      if (const PetscErrorCode code = set_near_null_space(orthonormal_basis(near_null), error); code != 0)
        return code;
    return make_vectors_and_ksp(near_null.cols(), error);
  }

  /// The end of a set-up, once the matrix and its near-null space (of `near_null_columns`) are
  /// made: the vectors, the options and the KSP.
  PetscErrorCode make_vectors_and_ksp(Eigen::Index near_null_columns, std::string* error) {
    HEMIVEM_PETSC(MatCreateVecs(matrix, &solution, &rhs));
    HEMIVEM_PETSC(VecDuplicate(rhs, &residual));

    HEMIVEM_PETSC(PetscOptionsCreate(&options));
    if (preconditioner == Preconditioner::hypre && near_null_columns == 6)
      HEMIVEM_PETSC(PetscOptionsSetValue(options, "-pc_hypre_boomeramg_strong_threshold", "0.5"));
    return make_ksp(error);
  }

  /// setup() for this process's rows of a distributed system: a MATMPIAIJ on PETSC_COMM_WORLD
  /// made of its two blocks (make_blocks(): the diagonal block A's own arrays where it can be),
  /// of the block size given, its near-null space made of MPI vectors, then the vectors and the
  /// KSP on PETSC_COMM_WORLD.
  PetscErrorCode setup_distributed(const SparseMatrix& A, const KrylovHints& hints, std::string* error) {
    const RowLayout& layout = hints.rows->layout();
    comm = PETSC_COMM_WORLD;
    distributed = true;
    size = static_cast<PetscInt>(layout.owned);
    const auto global = static_cast<PetscInt>(layout.global);
    make_blocks(A, layout);
    PetscInt* di = d_starts.data();
    PetscInt* dj = d_columns.data();
    PetscScalar* da = d_values.data();
    if (!diagonal_copied) {
      // PETSc reads A's first columns for as long as the matrix lives (the contract keeps A alive)
      di = reinterpret_cast<PetscInt*>(const_cast<int*>(A.outerIndexPtr()));
      dj = reinterpret_cast<PetscInt*>(const_cast<int*>(A.innerIndexPtr()));
      da = const_cast<double*>(A.valuePtr());
    }
    HEMIVEM_PETSC(MatCreateMPIAIJWithSplitArrays(comm, size, size, global, global, di, dj, da, o_starts.data(),
                                                 o_columns.data(), o_values.data(), &matrix));
    if (hints.block_size > 1) HEMIVEM_PETSC(MatSetBlockSize(matrix, static_cast<PetscInt>(hints.block_size)));
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));
    // the values set again by update_distributed_values() are in the owned rows and the pattern
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE));
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
    const bool compressed = A.isCompressed();
    source_values = compressed ? static_cast<const void*>(A.valuePtr()) : nullptr;
    source_starts = compressed ? static_cast<const void*>(A.outerIndexPtr()) : nullptr;
    source_indices = compressed ? static_cast<const void*>(A.innerIndexPtr()) : nullptr;
    source_pattern = compressed ? layout_checksum(A, layout) : 0;
    const Eigen::MatrixXd& near_null = hints.near_null;
    // collective (every process has as many columns: distributed_argument_problem())
    if (near_null.cols() > 0)
      if (const PetscErrorCode code = set_near_null_space(distributed_orthonormal_basis(comm, near_null), error);
          code != 0)
        return code;
    return make_vectors_and_ksp(near_null.cols(), error);
  }

  /// compute() for this process's rows of a distributed system (hints.rows of several
  /// processes). Every decision is the same on every process: the checks of the arguments
  /// (InternalError on every process), whether the matrix is the last one with values changed
  /// in place, the screening of the entries and the outcome of PETSc's set-up (the first
  /// process's that failed, petsc::agreed()).
  FactorizationResult compute_distributed(const SparseMatrix& A, const KrylovHints& hints) {
    const std::string engine = name();
    if (const std::string& why = PetscRuntime::instance().start(); !why.empty()) {
      release();
      return {FactorizationStatus::numerical_failure, engine + ": " + why};
    }
    if (!PetscRuntime::running()) {
      release();
      return {FactorizationStatus::numerical_failure, engine + ": PETSc is not running"};
    }
    const MPI_Comm world = PETSC_COMM_WORLD;
    const int processes = petsc::comm_size(world);
    if (const std::string broken = petsc::first_problem(world, distributed_argument_problem(world, engine, A, hints));
        !broken.empty())
      throw InternalError(broken);
    const RowLayout& layout = hints.rows->layout();
    const QuietErrors quiet;
    const petsc::WithoutSequentialProducts mpi_products;
    if (petsc::first_rank_where(world, !same_distributed_matrix(A, layout)) == processes) {
      const FactorizationResult screened = petsc::agreed(world, screen_owned_rows(A, layout));
      if (!screened.ok()) {
        computed = false;
        return {screened.status, engine + ": " + screened.message};
      }
      std::string error;
      const int code = update_distributed_values(A, &error);
      const FactorizationResult updated =
          petsc::agreed(world, code == 0 ? FactorizationResult::good()
                                         : FactorizationResult{FactorizationStatus::numerical_failure, error});
      if (updated.ok()) return updated;
    }
    release();
    const FactorizationResult screened = petsc::agreed(world, screen_owned_rows(A, layout));
    if (!screened.ok()) return {screened.status, engine + ": " + screened.message};
    std::string error;
    const int code = setup_distributed(A, hints, &error);
    const FactorizationResult made = petsc::agreed(
        world, code == 0 ? FactorizationResult::good() : FactorizationResult{FactorizationStatus::numerical_failure, error});
    if (!made.ok()) {
      release();
      return {made.status, engine + ": " + made.message};
    }
    computed = true;
    return made;
  }

  /// The start of solve() on a distributed system, as krylov::prepare_start() with global
  /// norms: x of b's size (zeros when it was not), x = 0 on every process when b = 0 or when an
  /// entry of x is not finite on some process. Returns ||b||_2 (one MPI_Allreduce).
  double distributed_start(const Eigen::VectorXd& b, Eigen::VectorXd* x) const {
    if (x->size() != b.size()) x->setZero(b.size());
    const double mine[2] = {b.squaredNorm(), x->allFinite() ? 0.0 : 1.0};
    double all[2] = {0.0, 0.0};
    MPI_Allreduce(mine, all, 2, MPI_DOUBLE, MPI_SUM, comm);
    const double bn = std::sqrt(all[0]);
    if (bn == 0.0 || all[1] > 0.0) x->setZero();
    return bn;
  }

  /// The KSP and its preconditioner, set up on the matrix.
  PetscErrorCode make_ksp(std::string* error) {
    give_back_free_memory();  // what the matrix's set-up freed, before the preconditioner's
    reused = false;
    HEMIVEM_PETSC(KSPCreate(comm, &ksp));
    HEMIVEM_PETSC(PetscObjectSetOptions(reinterpret_cast<PetscObject>(ksp), options));
    HEMIVEM_PETSC(KSPSetOperators(ksp, matrix, matrix));
    HEMIVEM_PETSC(KSPSetType(ksp, KSPCG));
    HEMIVEM_PETSC(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
    HEMIVEM_PETSC(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
    PC pc = nullptr;
    HEMIVEM_PETSC(KSPGetPC(ksp, &pc));
    HEMIVEM_PETSC(PetscObjectSetOptions(reinterpret_cast<PetscObject>(pc), options));
    if (preconditioner == Preconditioner::gamg) {
      HEMIVEM_PETSC(PCSetType(pc, PCGAMG));
      HEMIVEM_PETSC(PCGAMGSetType(pc, PCGAMGAGG));
      // a new matrix of the same pattern keeps the aggregates and the prolongator of the first
      // (only the coarse operators are formed again): a Newton iteration's systems differ in a
      // few rows
      HEMIVEM_PETSC(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
    } else {
      HEMIVEM_PETSC(PCSetType(pc, PCHYPRE));
      HEMIVEM_PETSC(PCHYPRESetType(pc, "boomeramg"));
    }
    HEMIVEM_PETSC(PCSetFromOptions(pc));
    HEMIVEM_PETSC(KSPSetUp(ksp));
    give_back_free_memory();
    return 0;
  }

  /// After a preconditioner set up again on values changed in place turned out indefinite (the
  /// smoother's eigenvalue bounds and the prolongator are the first system's): one set up
  /// afresh on the current values.
  PetscErrorCode renew_ksp(std::string* error) {
    HEMIVEM_PETSC(KSPDestroy(&ksp));
    return make_ksp(error);
  }

  /// What CG did in one solve(): its iterations, PETSc's last reason (KSP_CONVERGED_ITERATING
  /// when the start was accepted) and the true relative residual of the x it left.
  struct CgRun {
    int iterations = 0;
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    double relative = 0.0;
  };

  /// CG from *x with PETSc's vectors holding b (of norm bn) and x, restarted from the last x
  /// while PETSc's recursive residual says converged and the true residual does not; x copied
  /// back.
  PetscErrorCode run_cg(const Eigen::VectorXd& b, double bn, Eigen::VectorXd* x, double rtol, int max_iterations,
                        CgRun* run, std::string* error) {
    PetscScalar* data = nullptr;
    HEMIVEM_PETSC(VecGetArray(rhs, &data));
    std::copy(b.data(), b.data() + b.size(), data);
    HEMIVEM_PETSC(VecRestoreArray(rhs, &data));
    HEMIVEM_PETSC(VecGetArray(solution, &data));
    std::copy(x->data(), x->data() + x->size(), data);
    HEMIVEM_PETSC(VecRestoreArray(solution, &data));
    PetscReal residual_norm = 0.0;
    HEMIVEM_PETSC(MatResidual(matrix, rhs, solution, residual));
    HEMIVEM_PETSC(VecNorm(residual, NORM_2, &residual_norm));
    run->relative = static_cast<double>(residual_norm) / bn;
    for (int restart = 0; run->relative > rtol && run->iterations < max_iterations && restart <= kMaxRestarts;
         ++restart) {
      HEMIVEM_PETSC(KSPSetTolerances(ksp, rtol, 0.0, PETSC_DEFAULT, max_iterations - run->iterations));
      HEMIVEM_PETSC(KSPSolve(ksp, rhs, solution));
      PetscInt iterations = 0;
      HEMIVEM_PETSC(KSPGetIterationNumber(ksp, &iterations));
      HEMIVEM_PETSC(KSPGetConvergedReason(ksp, &run->reason));
      run->iterations += static_cast<int>(iterations);
      HEMIVEM_PETSC(MatResidual(matrix, rhs, solution, residual));
      HEMIVEM_PETSC(VecNorm(residual, NORM_2, &residual_norm));
      run->relative = static_cast<double>(residual_norm) / bn;
      if (run->reason < 0 || iterations == 0) break;
    }
    const PetscScalar* result = nullptr;
    HEMIVEM_PETSC(VecGetArrayRead(solution, &result));
    std::copy(result, result + size, x->data());
    HEMIVEM_PETSC(VecRestoreArrayRead(solution, &result));
    return 0;
  }

  /// The outcome of a run PETSc completed (out holds its iterations and relative residual),
  /// from its converged reason: not_positive_definite when CG found the matrix or the
  /// preconditioner indefinite, numerical_failure for an iterate not finite or a residual above
  /// rtol, success otherwise.
  void classify(KSPConvergedReason reason, double rtol, int max_iterations, KrylovSolveResult* out) const {
    const std::string engine = name();
    const std::string iterations = std::to_string(out->iterations);
    const double relative = out->relative_residual;
    const std::string why =
        reason == KSP_CONVERGED_ITERATING ? std::string("start accepted") : std::string(KSPConvergedReasons[reason]);
    if (reason == KSP_DIVERGED_INDEFINITE_MAT || reason == KSP_DIVERGED_INDEFINITE_PC) {
      out->status = FactorizationStatus::not_positive_definite;
      out->message = engine + ": CG stopped after " + iterations + " iterations (" + why + "): " +
                     (reason == KSP_DIVERGED_INDEFINITE_MAT ? "the matrix" : "the preconditioner") +
                     " is not positive definite";
    } else if (!std::isfinite(relative)) {
      out->status = FactorizationStatus::numerical_failure;
      out->message = engine + ": the iterate is not finite after " + iterations + " iterations (" + why + ")";
    } else if (relative > rtol) {
      out->status = FactorizationStatus::numerical_failure;
      std::string detail = why;
      PC pc = nullptr;
      PCFailedReason failed = PC_NOERROR;
      if (reason == KSP_DIVERGED_PC_FAILED && KSPGetPC(ksp, &pc) == 0 && PCGetFailedReason(pc, &failed) == 0)
        detail += std::string(", ") + PCFailedReasons[failed];
      out->message = engine + ": no convergence in " + iterations + " iterations (of " +
                     std::to_string(max_iterations) + ", " + detail + "): relative residual " + scientific(relative) +
                     " > " + scientific(rtol);
    }
  }
};

PetscKrylovSolver::PetscKrylovSolver(Preconditioner preconditioner)
    : impl_(std::make_unique<Impl>(preconditioner)) {}
PetscKrylovSolver::~PetscKrylovSolver() = default;

std::string PetscKrylovSolver::name() const { return impl_->name(); }

FactorizationResult PetscKrylovSolver::compute(const SparseMatrix& A, const KrylovHints& hints) {
  Impl& m = *impl_;
  if (hints.rows && hints.rows->size() > 1) return m.compute_distributed(A, hints);
  krylov::check_compute_arguments(name(), A, hints);
  if (m.same_matrix(A) && PetscRuntime::running()) {
    if (const FactorizationResult screened = krylov::screen_matrix(A); !screened.ok()) {
      m.computed = false;
      return {screened.status, name() + ": " + screened.message};
    }
    const QuietErrors quiet;
    std::string error;
    if (m.update_values(&error) == 0) return FactorizationResult::good();
  }
  m.release();
  if (const std::string& why = PetscRuntime::instance().start(); !why.empty())
    return {FactorizationStatus::numerical_failure, name() + ": " + why};
  if (!PetscRuntime::running()) return {FactorizationStatus::numerical_failure, name() + ": PETSc is not running"};
  if (const FactorizationResult screened = krylov::screen_matrix(A); !screened.ok())
    return {screened.status, name() + ": " + screened.message};
  const QuietErrors quiet;
  std::string error;
  if (m.setup(A, hints, &error) != 0) {
    m.release();
    return {FactorizationStatus::numerical_failure, name() + ": " + error};
  }
  m.computed = true;
  return FactorizationResult::good();
}

void PetscKrylovSolver::release() { impl_->release(); }

KrylovSolveResult PetscKrylovSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol,
                                           int max_iterations) const {
  Impl& m = *impl_;
  if (!m.computed) throw InternalError(name() + ": solve() before a successful compute()");
  if (m.distributed) {
    // the arguments' checks, on every process
    std::string broken;
    try {
      krylov::check_solve_arguments(name(), static_cast<Eigen::Index>(m.size), b, x, rtol, max_iterations);
    } catch (const InternalError& e) {
      broken = e.what();
    }
    if (const std::string problem = petsc::first_problem(m.comm, broken); !problem.empty()) throw InternalError(problem);
  } else {
    krylov::check_solve_arguments(name(), static_cast<Eigen::Index>(m.size), b, x, rtol, max_iterations);
  }
  KrylovSolveResult out;
  const double bn = m.distributed ? m.distributed_start(b, x) : krylov::prepare_start(b, x);
  if (bn == 0.0) return out;
  if (!PetscRuntime::running())
    return {FactorizationStatus::numerical_failure, name() + ": PETSc was finalized", 0, 0.0};

  const QuietErrors quiet;
  std::optional<petsc::WithoutSequentialProducts> mpi_products;
  if (m.distributed) mpi_products.emplace();
  std::string failure;
  Impl::CgRun run;
  const Eigen::VectorXd start = *x;
  PetscErrorCode code = m.run_cg(b, bn, x, rtol, max_iterations, &run, &failure);
  if (code == 0 && run.reason == KSP_DIVERGED_INDEFINITE_PC && m.reused) {
    const int spent = run.iterations;
    *x = start;
    code = m.renew_ksp(&failure);
    run = Impl::CgRun();
    if (code == 0) code = m.run_cg(b, bn, x, rtol, std::max(0, max_iterations - spent), &run, &failure);
    run.iterations += spent;
  }
  out.iterations = run.iterations;
  out.relative_residual = run.relative;
  if (m.distributed) {
    // a PETSc error on one process is the outcome of every process
    const FactorizationResult ran = petsc::agreed(
        m.comm, code == 0 ? FactorizationResult::good()
                          : FactorizationResult{FactorizationStatus::numerical_failure, failure});
    if (!ran.ok()) {
      out.status = ran.status;
      out.message = name() + ": " + ran.message;
      return out;
    }
  }
  if (code != 0) {
    out.status = FactorizationStatus::numerical_failure;
    out.message = name() + ": " + failure;
    return out;
  }
  m.classify(run.reason, rtol, max_iterations, &out);
  return out;
}

}  // namespace hemivem
