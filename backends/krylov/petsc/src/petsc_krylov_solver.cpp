// The PETSc Krylov engines (hemivem/petsc_krylov_solver.hpp): the sequential path on a
// MATSEQAIJ that reads A's arrays, the distributed path on a MATMPIAIJ made from a process's
// owned rows (KrylovHints::rows), and the CG runs, restarts and outcomes both share.
#include <hemivem/petsc_krylov_solver.hpp>

#include <hemivem/error.hpp>

#include <petscksp.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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
  /// `comm` (PETSC_COMM_WORLD; PETSC_COMM_SELF on the sequential path); the MATMPIAIJ holds a copy
  /// of the owned rows, made from their CSR copy with global columns increasing in each row
  /// (copy_rows(); `csr_position` sends the k-th entry of A, in the order of its InnerIterator,
  /// to its place in that copy). Once the matrix is made and A's entries are found to correspond
  /// one to one, in order, to the values PETSc keeps for the two blocks of the MATMPIAIJ
  /// (map_to_blocks()), the CSR copy is freed and `in_blocks` is true: new values are written
  /// into PETSc's arrays by one sweep over A's columns in the order of their global columns
  /// (`block_columns`: j for a column of the diagonal block, -(j + 1) for one of the
  /// off-diagonal block), each row's next place in each block starting at `block_d_starts` and
  /// `block_o_starts`: what is kept is of the size of A's columns and rows, not of its entries.
  /// When the places cannot be found (map_to_blocks()), the CSR copy is kept and new values are
  /// set from it by MatSetValues.
  MPI_Comm comm = PETSC_COMM_SELF;
  bool distributed = false;
  PetscInt first_row = 0;
  std::vector<PetscInt> csr_starts, csr_columns;
  std::vector<PetscScalar> csr_values;
  std::vector<std::size_t> csr_position;
  bool in_blocks = false;
  std::vector<std::int32_t> block_columns;
  std::vector<PetscInt> block_d_starts, block_o_starts;
  /// The arrays of the A the copy was made from and a checksum of its pattern and layout.
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

  /// The CSR copy of A's owned rows with global columns (the pattern and the values).
  void copy_rows(const SparseMatrix& A, const RowLayout& layout) {
    const auto owned = static_cast<std::size_t>(layout.owned);
    csr_starts.assign(owned + 1, 0);
    for (Eigen::Index j = 0; j < A.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) ++csr_starts[static_cast<std::size_t>(it.row()) + 1];
    std::partial_sum(csr_starts.begin(), csr_starts.end(), csr_starts.begin());
    const auto entries = static_cast<std::size_t>(csr_starts.back());
    // each row's entries as (global column, k), sorted by column
    std::vector<std::pair<PetscInt, std::size_t>> row_entries(entries);
    std::vector<PetscInt> next(csr_starts.begin(), csr_starts.end() - 1);
    std::size_t k = 0;
    for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
      const auto column = static_cast<PetscInt>(global_column(layout, j));
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        row_entries[static_cast<std::size_t>(next[static_cast<std::size_t>(it.row())]++)] = {column, k++};
    }
    csr_columns.resize(entries);
    csr_values.resize(entries);
    csr_position.resize(entries);
    for (std::size_t i = 0; i < owned; ++i) {
      const auto begin = row_entries.begin() + csr_starts[i], end = row_entries.begin() + csr_starts[i + 1];
      std::sort(begin, end);
      for (auto e = begin; e != end; ++e) {
        const auto place = static_cast<std::size_t>(e - row_entries.begin());
        csr_columns[place] = e->first;
        csr_position[e->second] = place;
      }
    }
    copy_values(A);
  }

  /// A's values into the CSR copy (A's pattern that of copy_rows()).
  void copy_values(const SparseMatrix& A) {
    std::size_t k = 0;
    for (Eigen::Index j = 0; j < A.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) csr_values[csr_position[k++]] = it.value();
  }

  /// Frees the CSR copy of the owned rows (the vectors' memory, not only their entries).
  void free_csr_copy() {
    std::vector<PetscInt>().swap(csr_starts);
    std::vector<PetscInt>().swap(csr_columns);
    std::vector<PetscScalar>().swap(csr_values);
    std::vector<std::size_t>().swap(csr_position);
  }

  /// Whether A's entries correspond one to one to the values of the two blocks of the MATMPIAIJ,
  /// and the order of the sweep that writes them (block_columns, block_d_starts,
  /// block_o_starts), from the blocks' own row structure: Ad, the diagonal block, holds the
  /// columns [cstart, cend) of the owned rows, numbered from cstart (di, dj); Ao, the off-diagonal
  /// block, holds the other columns, numbered by their place in garray, of garray_size global
  /// columns (oi, oj). A row's entries of a block are given that row's places of the block in
  /// the order of increasing global column, the order in which PETSc keeps them (garray is
  /// sorted); every place is checked to hold the entry's global column and every place of a row
  /// to be given an entry, so that the entries of A and the values of the blocks correspond one
  /// to one. False (the sweep's order empty) when a check fails or A has more columns than an
  /// int32 numbers.
  bool find_block_places(const SparseMatrix& A, const RowLayout& layout, PetscInt cstart, PetscInt cend,
                         const PetscInt* di, const PetscInt* dj, const PetscInt* oi, const PetscInt* oj,
                         const PetscInt* garray, PetscInt garray_size) {
    const auto rows = static_cast<std::size_t>(layout.owned);
    const auto most = static_cast<std::int64_t>(std::numeric_limits<std::int32_t>::max());
    if (static_cast<std::int64_t>(A.cols()) > most) return false;
    if (static_cast<std::int64_t>(di[rows]) + static_cast<std::int64_t>(oi[rows]) !=
        static_cast<std::int64_t>(A.nonZeros()))
      return false;
    const Eigen::Index columns = A.cols();
    // A's local columns by increasing global column
    std::vector<Eigen::Index> order(static_cast<std::size_t>(columns));
    std::iota(order.begin(), order.end(), Eigen::Index{0});
    std::sort(order.begin(), order.end(), [&layout](Eigen::Index a, Eigen::Index b) {
      const Eigen::Index ga = global_column(layout, a), gb = global_column(layout, b);
      return ga < gb || (ga == gb && a < b);
    });
    // the next place of each row in each block
    std::vector<PetscInt> next_d(di, di + rows), next_o(oi, oi + rows);
    std::vector<std::int32_t> sweep(static_cast<std::size_t>(columns));
    bool matches = true;
    for (std::size_t c = 0; c < order.size() && matches; ++c) {
      const Eigen::Index j = order[c];
      const Eigen::Index global = global_column(layout, j);
      const bool diagonal = global >= cstart && global < cend;
      sweep[c] = diagonal ? static_cast<std::int32_t>(j) : -static_cast<std::int32_t>(j) - 1;
      for (SparseMatrix::InnerIterator it(A, j); it && matches; ++it) {
        const auto i = static_cast<std::size_t>(it.row());
        if (diagonal) {
          const PetscInt p = next_d[i]++;
          matches = p < di[i + 1] && static_cast<Eigen::Index>(dj[p]) == global - cstart;
        } else {
          const PetscInt p = next_o[i]++;
          matches = p < oi[i + 1] && oj[p] >= 0 && oj[p] < garray_size &&
                    static_cast<Eigen::Index>(garray[oj[p]]) == global;
        }
      }
    }
    for (std::size_t i = 0; i < rows && matches; ++i) matches = next_d[i] == di[i + 1] && next_o[i] == oi[i + 1];
    if (!matches) return false;
    block_columns = std::move(sweep);
    block_d_starts.assign(di, di + rows + 1);
    block_o_starts.assign(oi, oi + rows + 1);
    return true;
  }

  /// Forgets the sweep that writes A's values into the blocks (its memory, not only its entries).
  void forget_block_places() {
    std::vector<std::int32_t>().swap(block_columns);
    std::vector<PetscInt>().swap(block_d_starts);
    std::vector<PetscInt>().swap(block_o_starts);
  }

  /// Once the MATMPIAIJ is assembled from the CSR copy: the places of A's entries in its
  /// blocks (find_block_places(), on the blocks' row structure read by MatGetRowIJ) and,
  /// when they are found, the CSR copy freed (in_blocks). When they are not, the CSR copy is
  /// kept for update_distributed_values().
  PetscErrorCode map_to_blocks(const SparseMatrix& A, const RowLayout& layout, std::string* error) {
    in_blocks = false;
    forget_block_places();
    Mat Ad = nullptr, Ao = nullptr;
    const PetscInt* garray = nullptr;
    PetscInt cstart = 0, cend = 0, garray_size = 0;
    HEMIVEM_PETSC(MatMPIAIJGetSeqAIJ(matrix, &Ad, &Ao, &garray));
    HEMIVEM_PETSC(MatGetOwnershipRangeColumn(matrix, &cstart, &cend));
    HEMIVEM_PETSC(MatGetLocalSize(Ao, nullptr, &garray_size));
    PetscInt d_rows = 0, o_rows = 0;
    const PetscInt *di = nullptr, *dj = nullptr, *oi = nullptr, *oj = nullptr;
    PetscBool d_done = PETSC_FALSE, o_done = PETSC_FALSE;
    // each structure read is given back, whatever happens after it
    PetscErrorCode code = MatGetRowIJ(Ad, 0, PETSC_FALSE, PETSC_FALSE, &d_rows, &di, &dj, &d_done);
    const char* call = "MatGetRowIJ (the diagonal block)";
    if (code == 0 && d_done) {
      code = MatGetRowIJ(Ao, 0, PETSC_FALSE, PETSC_FALSE, &o_rows, &oi, &oj, &o_done);
      call = "MatGetRowIJ (the off-diagonal block)";
      if (code == 0 && o_done) {
        in_blocks = d_rows == size && o_rows == size && (garray != nullptr || garray_size == 0) &&
                    find_block_places(A, layout, cstart, cend, di, dj, oi, oj, garray, garray_size);
        code = MatRestoreRowIJ(Ao, 0, PETSC_FALSE, PETSC_FALSE, &o_rows, &oi, &oj, &o_done);
        call = "MatRestoreRowIJ (the off-diagonal block)";
      }
      const PetscErrorCode restored = MatRestoreRowIJ(Ad, 0, PETSC_FALSE, PETSC_FALSE, &d_rows, &di, &dj, &d_done);
      if (code == 0 && restored != 0) {
        code = restored;
        call = "MatRestoreRowIJ (the diagonal block)";
      }
    }
    if (code != 0) {
      in_blocks = false;
      forget_block_places();
      *error = petsc::error_message(code, call);
      return code;
    }
    if (in_blocks) free_csr_copy();
    return 0;
  }

  /// A's values written into the values of the blocks of the MATMPIAIJ, at their places: A's
  /// columns in the order of their global columns, each entry at its row's next place in its
  /// block (the order map_to_blocks() checked).
  PetscErrorCode write_block_values(const SparseMatrix& A, std::string* error) {
    Mat Ad = nullptr, Ao = nullptr;
    HEMIVEM_PETSC(MatMPIAIJGetSeqAIJ(matrix, &Ad, &Ao, nullptr));
    PetscScalar *d = nullptr, *o = nullptr;
    HEMIVEM_PETSC(MatSeqAIJGetArray(Ad, &d));
    // the arrays taken are given back, whatever happens after
    PetscErrorCode code = MatSeqAIJGetArray(Ao, &o);
    const char* call = "MatSeqAIJGetArray (the off-diagonal block)";
    if (code == 0) {
      std::vector<PetscInt> next_d(block_d_starts.begin(), block_d_starts.end() - 1);
      std::vector<PetscInt> next_o(block_o_starts.begin(), block_o_starts.end() - 1);
      for (const std::int32_t c : block_columns) {
        const bool diagonal = c >= 0;
        const Eigen::Index j = diagonal ? c : -(c + 1);
        if (diagonal)
          for (SparseMatrix::InnerIterator it(A, j); it; ++it) d[next_d[static_cast<std::size_t>(it.row())]++] = it.value();
        else
          for (SparseMatrix::InnerIterator it(A, j); it; ++it) o[next_o[static_cast<std::size_t>(it.row())]++] = it.value();
      }
      code = MatSeqAIJRestoreArray(Ao, &o);
      call = "MatSeqAIJRestoreArray (the off-diagonal block)";
    }
    const PetscErrorCode restored = MatSeqAIJRestoreArray(Ad, &d);
    if (code == 0 && restored != 0) {
      code = restored;
      call = "MatSeqAIJRestoreArray (the diagonal block)";
    }
    if (code != 0) {
      *error = petsc::error_message(code, call);
      return code;
    }
    return 0;
  }

  /// update_values() for a distributed system: the owned rows' new values put in the matrix,
  /// written into its blocks' arrays (write_block_values()) or, when the places of the entries
  /// in the blocks were not found, set by MatSetValues row by row from the CSR copy; then the
  /// matrix assembled and the preconditioner set up again. The assembly changes no place (the
  /// pattern is the same and nothing is stashed): it increases the matrix's state, so that the
  /// KSP sees a changed operator of the same nonzero pattern (GAMG reuses its interpolation,
  /// make_ksp()), and drops what PETSc keeps of the former values (the blocks' inverted
  /// diagonals, the diagonal vector of the MATMPIAIJ) and the symmetry flag, set again below.
  PetscErrorCode update_distributed_values(const SparseMatrix& A, std::string* error) {
    if (in_blocks) {
      if (const PetscErrorCode code = write_block_values(A, error); code != 0) return code;
    } else {
      copy_values(A);
      for (PetscInt i = 0; i < size; ++i) {
        const PetscInt row = first_row + i;
        const PetscInt start = csr_starts[static_cast<std::size_t>(i)];
        HEMIVEM_PETSC(MatSetValues(matrix, 1, &row, csr_starts[static_cast<std::size_t>(i) + 1] - start,
                                   csr_columns.data() + start, csr_values.data() + start, INSERT_VALUES));
      }
    }
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
    in_blocks = false;
    forget_block_places();
    free_csr_copy();
    comm = PETSC_COMM_SELF;
    if (!PetscRuntime::running()) {
      matrix = nullptr, ksp = nullptr, rhs = solution = residual = nullptr, options = nullptr;
      return;
    }
    const QuietErrors quiet;
    if (ksp) KSPDestroy(&ksp);
    if (matrix) MatDestroy(&matrix);
    if (rhs) VecDestroy(&rhs);
    if (solution) VecDestroy(&solution);
    if (residual) VecDestroy(&residual);
    if (options) PetscOptionsDestroy(&options);
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
    const bool readable = A.isCompressed() && sizeof(PetscInt) == sizeof(int);
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
  /// made from the CSR copy of the owned rows (copy_rows(), freed once the places of A's entries
  /// in the matrix are found: map_to_blocks()), of the block size given, its near-null space
  /// made of MPI vectors, then the vectors and the KSP on PETSC_COMM_WORLD.
  PetscErrorCode setup_distributed(const SparseMatrix& A, const KrylovHints& hints, std::string* error) {
    const RowLayout& layout = hints.rows->layout();
    comm = PETSC_COMM_WORLD;
    distributed = true;
    size = static_cast<PetscInt>(layout.owned);
    first_row = static_cast<PetscInt>(layout.first);
    const auto global = static_cast<PetscInt>(layout.global);
    copy_rows(A, layout);
    HEMIVEM_PETSC(MatCreate(comm, &matrix));
    HEMIVEM_PETSC(MatSetSizes(matrix, size, size, global, global));
    HEMIVEM_PETSC(MatSetType(matrix, MATMPIAIJ));
    if (hints.block_size > 1) HEMIVEM_PETSC(MatSetBlockSize(matrix, static_cast<PetscInt>(hints.block_size)));
    HEMIVEM_PETSC(MatMPIAIJSetPreallocationCSR(matrix, csr_starts.data(), csr_columns.data(), csr_values.data()));
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));
    // the values set again by update_distributed_values() are in the owned rows and the pattern
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE));
    HEMIVEM_PETSC(MatSetOption(matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
    // the matrix holds the values: the CSR copy is freed unless it is needed to set new ones
    if (const PetscErrorCode code = map_to_blocks(A, layout, error); code != 0) return code;
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
    give_back_free_memory();  // the CSR copy of the rows, freed before the preconditioner's set-up
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
