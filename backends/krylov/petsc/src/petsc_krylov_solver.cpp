#include <hemivem/petsc_krylov_solver.hpp>

#include <hemivem/error.hpp>

#include <petscksp.h>

#include <Eigen/QR>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <vector>

#include "krylov_common.hpp"

namespace hemivem {

namespace {

using krylov::kMaxRestarts;
using krylov::scientific;

/// "PETSc error <code> in <call>: <message>".
std::string petsc_error(PetscErrorCode code, const char* call) {
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(static_cast<int>(code), &text, &specific);
  std::string out = "PETSc error " + std::to_string(static_cast<int>(code)) + " in " + call;
  if (text && *text) out += std::string(": ") + text;
  if (specific && *specific) out += std::string(" (") + specific + ")";
  return out;
}

/// Inside a function returning PetscErrorCode with a std::string* error: the call, and on
/// failure its message in *error and its code returned.
#define HEMIVEM_PETSC(call)                             \
  do {                                                  \
    const PetscErrorCode hemivem_code_ = (call);        \
    if (hemivem_code_ != 0) {                           \
      *error = petsc_error(hemivem_code_, #call);       \
      return hemivem_code_;                             \
    }                                                   \
  } while (0)

/// PETSc in this process: initialized once by the first object that needs it, finalized at
/// program exit when hemivem initialized it, no object is left and MPI still runs.
class PetscRuntime {
 public:
  static PetscRuntime& instance() {
    static PetscRuntime runtime;
    return runtime;
  }

  /// Empty when PETSc runs; why it does not otherwise.
  const std::string& start() {
    std::call_once(once_, [this] {
      PetscBool initialized = PETSC_FALSE;
      if (PetscInitialized(&initialized) == 0 && initialized) return;  // the program's own PETSc
      PetscBool finalized = PETSC_FALSE;
      if (PetscFinalized(&finalized) == 0 && finalized) {
        error_ = "PETSc was finalized in this process";
        return;
      }
      // Before PetscInitialize: PETSc leaves the program's signal handlers alone.
      PetscOptionsSetValue(nullptr, "-no_signal_handler", "true");
      // GAMG's Galerkin products P^T A P by forming P^T: 40 % less time in its set-ups for about
      // a quarter more memory at the peak of a solve (docs/full-space.md); PETSC_OPTIONS, read
      // by PetscInitialize, may choose otherwise
      PetscOptionsSetValue(nullptr, "-matptap_via", "rap");
      const PetscErrorCode code = PetscInitializeNoArguments();
      if (code != 0) {
        error_ = "PetscInitialize failed with error " + std::to_string(static_cast<int>(code));
        return;
      }
      owned_ = true;
    });
    return error_;
  }

  void attach() noexcept { ++live_; }
  void detach() noexcept { --live_; }

  /// True while PETSc objects may be created and destroyed.
  static bool running() noexcept {
    PetscBool initialized = PETSC_FALSE, finalized = PETSC_TRUE;
    return PetscInitialized(&initialized) == 0 && initialized && PetscFinalized(&finalized) == 0 && !finalized;
  }

  ~PetscRuntime() {
    if (!owned_ || live_.load() > 0 || !running()) return;
    int mpi_finalized = 0;
    if (MPI_Finalized(&mpi_finalized) != MPI_SUCCESS || mpi_finalized) return;
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    PetscFinalize();
  }

 private:
  PetscRuntime() = default;

  std::once_flag once_;
  std::string error_;
  bool owned_ = false;
  std::atomic<int> live_{0};
};

/// PETSc's error handler is PetscReturnErrorHandler (nothing printed) while it lives.
class QuietErrors {
 public:
  QuietErrors() { pushed_ = PetscPushErrorHandler(PetscReturnErrorHandler, nullptr) == 0; }
  ~QuietErrors() {
    if (pushed_) PetscPopErrorHandler();
  }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  bool pushed_ = false;
};

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

  /// The near-null space of the matrix (an orthonormal basis of the columns of `near_null`), for
  /// GAMG's aggregates.
  PetscErrorCode set_near_null_space(const Eigen::MatrixXd& near_null, std::string* error) {
    const Eigen::MatrixXd Q = orthonormal_basis(near_null);
    std::vector<Vec> vectors(static_cast<std::size_t>(Q.cols()), nullptr);
    PetscErrorCode code = 0;
    for (Eigen::Index k = 0; k < Q.cols() && code == 0; ++k) {
      Vec& v = vectors[static_cast<std::size_t>(k)];
      code = VecCreateSeq(PETSC_COMM_SELF, size, &v);
      PetscScalar* data = nullptr;
      if (code == 0) code = VecGetArray(v, &data);
      if (code == 0) {
        for (PetscInt i = 0; i < size; ++i) data[i] = Q(i, k);
        code = VecRestoreArray(v, &data);
      }
    }
    MatNullSpace space = nullptr;
    if (code == 0) code = MatNullSpaceCreate(PETSC_COMM_SELF, PETSC_FALSE, static_cast<PetscInt>(Q.cols()),
                                             vectors.data(), &space);
    if (code == 0) code = MatSetNearNullSpace(matrix, space);
    if (space) MatNullSpaceDestroy(&space);
    for (Vec& v : vectors)
      if (v) VecDestroy(&v);
    if (code != 0) {
      *error = petsc_error(code, "the near-null space (MatNullSpaceCreate, MatSetNearNullSpace)");
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
      if (const PetscErrorCode code = set_near_null_space(near_null, error); code != 0) return code;

    HEMIVEM_PETSC(MatCreateVecs(matrix, &solution, &rhs));
    HEMIVEM_PETSC(VecDuplicate(rhs, &residual));

    HEMIVEM_PETSC(PetscOptionsCreate(&options));
    if (preconditioner == Preconditioner::hypre && near_null.cols() == 6)
      HEMIVEM_PETSC(PetscOptionsSetValue(options, "-pc_hypre_boomeramg_strong_threshold", "0.5"));
    return make_ksp(error);
  }

  /// The KSP and its preconditioner, set up on the matrix.
  PetscErrorCode make_ksp(std::string* error) {
    reused = false;
    HEMIVEM_PETSC(KSPCreate(PETSC_COMM_SELF, &ksp));
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
  krylov::check_compute_arguments(name(), A, hints);
  Impl& m = *impl_;
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
  krylov::check_solve_arguments(name(), static_cast<Eigen::Index>(m.size), b, x, rtol, max_iterations);
  KrylovSolveResult out;
  const double bn = krylov::prepare_start(b, x);
  if (bn == 0.0) return out;
  if (!PetscRuntime::running())
    return {FactorizationStatus::numerical_failure, name() + ": PETSc was finalized", 0, 0.0};

  const QuietErrors quiet;
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
  if (code != 0) {
    out.status = FactorizationStatus::numerical_failure;
    out.message = name() + ": " + failure;
    return out;
  }
  m.classify(run.reason, rtol, max_iterations, &out);
  return out;
}

}  // namespace hemivem
