#include <hemivem/cholmod_factorization.hpp>

#include "cholesky_engine.hpp"

#include <cholmod.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

#if defined(HEMIVEM_CHOLMOD_WITH_BLAS)
// the BLAS CHOLMOD calls (Fortran interface; the trailing lengths are those of the character
// arguments, gfortran's hidden arguments)
extern "C" void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
                       const double* a, const int* lda, const double* beta, double* c, const int* ldc,
                       std::size_t uplo_length, std::size_t trans_length);
#endif

namespace hemivem {

using namespace linear_detail;

namespace {

/// CHOLMOD's supernodal factorization runs some of its loops (clearing its work arrays, zeroing
/// and filling supernodes, supernode by supernode) with num_threads(CHOLMOD_OMP_NUM_THREADS),
/// 4 unless SuiteSparse was built otherwise, whatever OMP_NUM_THREADS asks. Where OpenMP allows
/// one thread, this guard sets max-active-levels to 0 for the length of a CHOLMOD call, so that
/// those regions run on the calling thread (their forks and joins made the factorization of
/// 32^3 boxes 13 % slower on two busy cores; docs/performance.md). Otherwise nothing changes.
class OneThreadWhereAsked {
 public:
  OneThreadWhereAsked() {
#if defined(_OPENMP)
    if (omp_get_max_threads() == 1 && !omp_in_parallel()) {
      saved_ = omp_get_max_active_levels();
      omp_set_max_active_levels(0);
    }
#endif
  }
  ~OneThreadWhereAsked() {
#if defined(_OPENMP)
    if (saved_ >= 0) omp_set_max_active_levels(saved_);
#endif
  }
  OneThreadWhereAsked(const OneThreadWhereAsked&) = delete;
  OneThreadWhereAsked& operator=(const OneThreadWhereAsked&) = delete;

 private:
  int saved_ = -1;
};

/// A read-only CHOLMOD view of the lower triangle of a compressed Eigen matrix.
cholmod_sparse lower_view(const SparseMatrix& M) {
  cholmod_sparse s{};
  s.nrow = static_cast<std::size_t>(M.rows());
  s.ncol = static_cast<std::size_t>(M.cols());
  s.nzmax = static_cast<std::size_t>(M.nonZeros());
  s.p = const_cast<int*>(M.outerIndexPtr());
  s.i = const_cast<int*>(M.innerIndexPtr());
  s.nz = nullptr;
  s.x = const_cast<double*>(M.valuePtr());
  s.z = nullptr;
  s.stype = -1;  // symmetric, lower triangle used, upper ignored
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 0;
  s.packed = 1;
  return s;
}

cholmod_dense dense_view(const Eigen::MatrixXd& B) {
  cholmod_dense d{};
  d.nrow = static_cast<std::size_t>(B.rows());
  d.ncol = static_cast<std::size_t>(B.cols());
  d.nzmax = d.nrow * d.ncol;
  d.d = d.nrow;
  d.x = const_cast<double*>(B.data());
  d.z = nullptr;
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

FactorizationResult from_status(int status, const std::string& what) {
  switch (status) {
    case CHOLMOD_OK: return FactorizationResult::good();
    case CHOLMOD_OUT_OF_MEMORY:
      return make_result(FactorizationStatus::out_of_memory, what + ": CHOLMOD ran out of memory");
    case CHOLMOD_TOO_LARGE:
      return make_result(FactorizationStatus::out_of_memory, what + ": the problem is too large for CHOLMOD");
    case CHOLMOD_NOT_POSDEF:
      return make_result(FactorizationStatus::not_positive_definite, what + ": the matrix is not positive definite");
    case CHOLMOD_INVALID: contract_violation(what + ": CHOLMOD reports invalid input");
    case CHOLMOD_NOT_INSTALLED:
      return make_result(FactorizationStatus::numerical_failure, what + ": a CHOLMOD method is not installed");
    default:
      if (status > 0) return FactorizationResult::good();  // warnings (e.g. tiny diagonal)
      return make_result(FactorizationStatus::numerical_failure,
                         what + ": CHOLMOD failed with status " + std::to_string(status));
  }
}

/// CHOLMOD's status after a call that returned nothing.
FactorizationResult failure(const cholmod_common& c, const std::string& what) {
  return from_status(c.status < 0 ? c.status : CHOLMOD_INVALID, what);
}

class CholmodKernel final : public CholeskyKernel {
 public:
  explicit CholmodKernel(const FactorizationOptions& options) {
    cholmod_start(&c_);
    c_.print = std::clamp(options.verbosity, 0, 5);
    c_.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~CholmodKernel() override {
    cholmod_free_factor(&L_, &c_);
    cholmod_free_factor(&LS_, &c_);
    cholmod_finish(&c_);
  }
  CholmodKernel(const CholmodKernel&) = delete;
  CholmodKernel& operator=(const CholmodKernel&) = delete;

  FactorizationResult analyze(const SparseMatrix& A) override {
    const OneThreadWhereAsked one_thread;
    cholmod_free_factor(&L_, &c_);
    cholmod_sparse Av = lower_view(A);
    L_ = cholmod_analyze(&Av, &c_);
    return L_ != nullptr ? FactorizationResult::good() : failure(c_, "cholmod_analyze");
  }
  FactorizationResult factorize(const SparseMatrix& A) override {
    rcond_ = -1.0;
    if (auto r = numeric(A, L_, "cholmod_factorize"); !r.ok()) return r;
    rcond_ = cholmod_rcond(L_, &c_);
    return FactorizationResult::good();
  }
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override {
    const OneThreadWhereAsked one_thread;
    cholmod_dense Bv = dense_view(B);
    cholmod_dense* Xc = cholmod_solve(CHOLMOD_A, L_, &Bv, &c_);
    if (Xc == nullptr) return failure(c_, "cholmod_solve");
    try {
      *X = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
          static_cast<const double*>(Xc->x), B.rows(), B.cols(), Eigen::OuterStride<>(static_cast<Eigen::Index>(Xc->d)));
    } catch (...) {
      cholmod_free_dense(&Xc, &c_);
      throw;
    }
    cholmod_free_dense(&Xc, &c_);
    return FactorizationResult::good();
  }
  double rcond() const override { return rcond_; }

  /// AMD (cholmod_amd: no symbolic factorization of A22; AMD's order is a postorder of its
  /// assembly tree), or METIS where AMD's fill is that of a three-dimensional body, its workspace freed at once so that the factorization's peak does not
  /// carry it. CHOLMOD's default strategy would also try METIS when AMD's fill looks high (from
  /// about 2 million unknowns on squares): there METIS took 23 s against 2 s for AMD and saved
  /// less in the factorization (docs/performance.md).
  FactorizationResult order(const SparseMatrix& lower, std::vector<int>* perm) override {
    const OneThreadWhereAsked one_thread;
    cholmod_sparse Av = lower_view(lower);
    perm->assign(static_cast<std::size_t>(lower.rows()), 0);
    const int ok = cholmod_amd(&Av, nullptr, 0, perm->data(), &c_);
    cholmod_free_work(&c_);
    if (!ok) return failure(c_, "cholmod_amd (A22)");
    // AMD's factor of a three-dimensional stiffness holds many times the matrix and costs many
    // flops per entry; there METIS's nested dissection is several times faster
    // (docs/three-dimensions.md). No plane mesh up to millions of unknowns comes near these
    // bounds (AMD fills squares of 2 million unknowns 12-fold at 850 flops per entry).
    if (c_.lnz >= 20.0 * static_cast<double>(lower.nonZeros()) && c_.fl >= 1000.0 * c_.lnz) {
      const int metis = cholmod_metis(&Av, nullptr, 0, 1, perm->data(), &c_);
      cholmod_free_work(&c_);
      if (!metis) return failure(c_, "cholmod_metis (A22)");
    }
    return FactorizationResult::good();
  }
  /// Supernodal analysis in P's own order (no fill-reducing ordering, no postordering, which
  /// could move block1 away from the end).
  FactorizationResult analyze_ordered(const SparseMatrix& P) override {
    const OneThreadWhereAsked one_thread;
    cholmod_free_factor(&LS_, &c_);
    const int nmethods = c_.nmethods, ordering = c_.method[0].ordering, postorder = c_.postorder;
    c_.nmethods = 1;
    c_.method[0].ordering = CHOLMOD_NATURAL;
    c_.postorder = 0;
    cholmod_sparse Pv = lower_view(P);
    LS_ = cholmod_analyze(&Pv, &c_);
    c_.nmethods = nmethods;
    c_.method[0].ordering = ordering;
    c_.postorder = postorder;
    if (LS_ == nullptr) return failure(c_, "cholmod_analyze (ordered)");
    const int* perm = static_cast<const int*>(LS_->Perm);
    for (std::size_t k = 0; k < LS_->n; ++k)
      if (perm != nullptr && perm[k] != static_cast<int>(k)) {
        cholmod_free_factor(&LS_, &c_);
        return make_result(FactorizationStatus::numerical_failure,
                           "cholmod_analyze did not keep the requested elimination order");
      }
    if (!LS_->is_super) {
      cholmod_free_factor(&LS_, &c_);
      return make_result(FactorizationStatus::numerical_failure, "cholmod_analyze did not give a supernodal factor");
    }
    return FactorizationResult::good();
  }
  FactorizationResult factorize_ordered(const SparseMatrix& P) override {
    rcond_ = -1.0;
    return numeric(P, LS_, "cholmod_factorize (Schur complement)");
  }
  /// Column j of the supernodal factor: in its supernode's column-major block, from the
  /// diagonal down (the supernode's own rows, then the rows below it, increasing).
  FactorColumn column(int j) const override {
    const int* super = static_cast<const int*>(LS_->super);
    const int* pi = static_cast<const int*>(LS_->pi);
    const int* px = static_cast<const int*>(LS_->px);
    const int k = static_cast<int>(std::upper_bound(super, super + LS_->nsuper + 1, j) - super) - 1;
    const int nsrow = pi[k + 1] - pi[k];
    const int offset = j - super[k];
    return {static_cast<const int*>(LS_->s) + pi[k] + offset,
            static_cast<const double*>(LS_->x) + px[k] + static_cast<std::ptrdiff_t>(offset) * nsrow + offset,
            nsrow - offset};
  }
  bool supernodes(Supernodes* out) const override {
    if (LS_ == nullptr || !LS_->is_super) return false;
    out->count = static_cast<int>(LS_->nsuper);
    out->first = static_cast<const int*>(LS_->super);
    out->row_start = static_cast<const int*>(LS_->pi);
    out->rows = static_cast<const int*>(LS_->s);
    out->value_start = static_cast<const int*>(LS_->px);
    out->values = static_cast<const double*>(LS_->x);
    return true;
  }
  int failed_pivot() const override { return failed_pivot_; }
#if defined(HEMIVEM_CHOLMOD_WITH_BLAS)
  /// S += L L^T by the BLAS's dsyrk (4 times Eigen's speed here: it has the wider kernels).
  bool add_lower_product(int n, int k, const double* L, int ld, double* S, int lds) const override {
    const char uplo = 'L', trans = 'N';
    const double one = 1.0;
    dsyrk_(&uplo, &trans, &n, &k, &one, L, &ld, &one, S, &lds, 1, 1);
    return true;
  }
#endif

 private:
  /// Numeric factorization of `M` into `F`; not_positive_definite keeps where it stopped.
  FactorizationResult numeric(const SparseMatrix& M, cholmod_factor* F, const std::string& what) {
    failed_pivot_ = -1;
    cholmod_sparse Av = lower_view(M);
    const OneThreadWhereAsked one_thread;
    const int ok = cholmod_factorize(&Av, F, &c_);
    if (c_.status == CHOLMOD_NOT_POSDEF || (ok && F->minor < F->n)) {
      if (F->minor < F->n) failed_pivot_ = static_cast<int>(F->minor);
      return make_result(FactorizationStatus::not_positive_definite, what + ": the matrix is not positive definite");
    }
    if (!ok || c_.status < CHOLMOD_OK) return failure(c_, what);
    return FactorizationResult::good();
  }

  mutable cholmod_common c_{};  // the solves use it too
  cholmod_factor* L_ = nullptr;   // analyze / factorize / solve
  cholmod_factor* LS_ = nullptr;  // the ordered factorization of the Schur complement
  double rcond_ = -1.0;
  int failed_pivot_ = -1;
};

}  // namespace

ReferenceFactorization measure_cholmod_factorization(const SparseMatrix& A, bool metis) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  ReferenceFactorization r;
  r.ordering = metis ? "metis" : "amd";
  SparseMatrix storage;
  const SparseMatrix& M = compressed(A, storage);
  cholmod_common c{};
  cholmod_start(&c);
  c.print = 0;
  c.supernodal = CHOLMOD_SUPERNODAL;
  c.nmethods = 1;
  c.method[0].ordering = metis ? CHOLMOD_METIS : CHOLMOD_AMD;
  cholmod_sparse Av = lower_view(M);
  const OneThreadWhereAsked one_thread;
  const auto t0 = Clock::now();
  cholmod_factor* L = cholmod_analyze(&Av, &c);
  const auto t1 = Clock::now();
  if (L == nullptr) {
    r.message = "cholmod_analyze failed (status " + std::to_string(c.status) + ")";
  } else {
    const int ok = cholmod_factorize(&Av, L, &c);
    const auto t2 = Clock::now();
    r.analysis_seconds = seconds(t0, t1);
    r.factorization_seconds = seconds(t1, t2);
    r.ok = ok != 0 && c.status == CHOLMOD_OK && L->minor == L->n;
    if (!r.ok) r.message = "cholmod_factorize failed (status " + std::to_string(c.status) + ")";
    r.factor_bytes = static_cast<double>(L->xsize) * sizeof(double) + static_cast<double>(L->ssize) * sizeof(int);
  }
  cholmod_free_factor(&L, &c);
  cholmod_finish(&c);
  return r;
}

struct CholmodFactorization::Impl : CholeskyEngine {
  explicit Impl(const FactorizationOptions& options)
      : CholeskyEngine(std::make_unique<CholmodKernel>(options), "cholmod") {}
};

CholmodFactorization::CholmodFactorization(const FactorizationOptions& options)
    : impl_(std::make_unique<Impl>(options)) {}
CholmodFactorization::~CholmodFactorization() = default;
CholmodFactorization::CholmodFactorization(CholmodFactorization&&) noexcept = default;
CholmodFactorization& CholmodFactorization::operator=(CholmodFactorization&&) noexcept = default;

int CholmodFactorization::num_analyses() const { return impl_->num_analyses(); }
double CholmodFactorization::rcond_estimate() const { return impl_->rcond_estimate(); }

FactorizationResult CholmodFactorization::analyze(const SparseMatrix& A) { return impl_->analyze(A); }

FactorizationResult CholmodFactorization::factorize(const SparseMatrix& A) { return impl_->factorize(A); }

FactorizationResult CholmodFactorization::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
  return impl_->solve(B, X);
}

FactorizationResult CholmodFactorization::schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                                           Eigen::MatrixXd* S) {
  return impl_->schur_complement(A, block1, S);
}

FactorizationResult CholmodFactorization::solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
  return impl_->solve_interior(B2, X2);
}

FactorizationResult CholmodFactorization::condense_rhs(const Eigen::VectorXd& b1, const Eigen::VectorXd& b2, Eigen::VectorXd* c) {
  return impl_->condense_rhs(b1, b2, c);
}

FactorizationResult CholmodFactorization::expand(const Eigen::VectorXd& x1, Eigen::VectorXd* x2) const {
  return impl_->expand(x1, x2);
}

}  // namespace hemivem
