#include <hemivem/cholmod_factorization.hpp>

#include "linear_common.hpp"

#include <cholmod.h>

#include <algorithm>
#include <new>
#include <vector>

namespace hemivem {

using namespace linear_detail;

namespace {

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
    case CHOLMOD_INVALID: return invalid(what + ": CHOLMOD reports invalid input");
    case CHOLMOD_NOT_INSTALLED:
      return make_result(FactorizationStatus::numerical_failure, what + ": a CHOLMOD method is not installed");
    default:
      if (status > 0) return FactorizationResult::good();  // warnings (e.g. tiny diagonal)
      return make_result(FactorizationStatus::numerical_failure,
                         what + ": CHOLMOD failed with status " + std::to_string(status));
  }
}

FactorizationResult out_of_memory() {
  return make_result(FactorizationStatus::out_of_memory, "out of memory in the CHOLMOD engine");
}

}  // namespace

struct CholmodFactorization::Impl {
  cholmod_common c{};
  int analyses = 0;
  double rcond = -1.0;

  // analyze / factorize / solve
  cholmod_factor* L = nullptr;
  PatternKey main_pattern;
  bool main_factorized = false;

  // schur_complement / solve_interior: one factor of A with block2 first, block1 last
  cholmod_factor* LS = nullptr;
  PatternKey schur_pattern;
  BlockSplit split;
  std::vector<int> order;  // order[k]: index of A eliminated k-th
  bool schur_analyzed = false;
  bool schur_factorized = false;

  explicit Impl(const FactorizationOptions& options) {
    cholmod_start(&c);
    c.print = std::clamp(options.verbosity, 0, 5);
    c.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Impl() {
    cholmod_free_factor(&L, &c);
    cholmod_free_factor(&LS, &c);
    cholmod_finish(&c);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  FactorizationResult analyze_main(const SparseMatrix& M) {
    main_factorized = false;
    main_pattern.clear();
    cholmod_free_factor(&L, &c);
    cholmod_sparse Av = lower_view(M);
    L = cholmod_analyze(&Av, &c);
    ++analyses;
    if (L == nullptr) return from_status(c.status < 0 ? c.status : CHOLMOD_INVALID, "cholmod_analyze");
    main_pattern.capture(M);
    return FactorizationResult::good();
  }

  /// Numeric factorization of `M` into `F`; not_positive_definite names where it stopped.
  FactorizationResult numeric(const SparseMatrix& M, cholmod_factor* F, const std::string& what) {
    cholmod_sparse Av = lower_view(M);
    const int ok = cholmod_factorize(&Av, F, &c);
    if (c.status == CHOLMOD_NOT_POSDEF || (ok && F->minor < F->n)) {
      const std::size_t minor = F->minor;
      const int* perm = static_cast<const int*>(F->Perm);
      std::string where;
      if (perm != nullptr && minor < F->n)
        where = " (stopped at pivot " + std::to_string(minor) + " of the ordered matrix, index " +
                std::to_string(perm[minor]) + " of A)";
      return make_result(FactorizationStatus::not_positive_definite,
                         what + ": the matrix is not positive definite" + where);
    }
    if (!ok || c.status < CHOLMOD_OK) return from_status(c.status < 0 ? c.status : CHOLMOD_INVALID, what);
    rcond = cholmod_rcond(F, &c);
    return FactorizationResult::good();
  }

  /// Elimination order: A22 ordered alone by CHOLMOD's default strategy, then block1 as given;
  /// LS = symbolic supernodal factor of A in that order (no postordering, which could move
  /// block1 away from the end).
  FactorizationResult analyze_schur(const SparseMatrix& M) {
    cholmod_free_factor(&LS, &c);
    const int n = static_cast<int>(M.rows());
    const int n2 = static_cast<int>(split.block2.size());

    // Pattern of the lower triangle of A22 (block2 is increasing, so rows stay sorted and lower).
    std::vector<int> p2(static_cast<std::size_t>(n2) + 1, 0), i2;
    i2.reserve(static_cast<std::size_t>(M.nonZeros() / 2 + n));
    for (int j = 0; j < n; ++j) {
      const int pj = split.position[static_cast<std::size_t>(j)];
      if (pj < 0) continue;
      for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
        if (it.row() < j) continue;
        const int pi = split.position[static_cast<std::size_t>(it.row())];
        if (pi >= 0) i2.push_back(pi);
      }
      p2[static_cast<std::size_t>(pj) + 1] = static_cast<int>(i2.size());
    }
    cholmod_sparse A22{};
    A22.nrow = A22.ncol = static_cast<std::size_t>(n2);
    A22.nzmax = std::max<std::size_t>(i2.size(), 1);
    if (i2.empty()) i2.push_back(0);
    A22.p = p2.data();
    A22.i = i2.data();
    A22.stype = -1;
    A22.itype = CHOLMOD_INT;
    A22.xtype = CHOLMOD_PATTERN;
    A22.dtype = CHOLMOD_DOUBLE;
    A22.sorted = 1;
    A22.packed = 1;

    const int supernodal = c.supernodal;
    c.supernodal = CHOLMOD_SIMPLICIAL;  // only the ordering is wanted
    cholmod_factor* L22 = cholmod_analyze(&A22, &c);
    c.supernodal = supernodal;
    if (L22 == nullptr) return from_status(c.status < 0 ? c.status : CHOLMOD_INVALID, "cholmod_analyze (A22)");
    order.resize(static_cast<std::size_t>(n));
    const int* perm22 = static_cast<const int*>(L22->Perm);
    for (int k = 0; k < n2; ++k)
      order[static_cast<std::size_t>(k)] = split.block2[static_cast<std::size_t>(perm22[k])];
    cholmod_free_factor(&L22, &c);
    std::copy(split.block1.begin(), split.block1.end(), order.begin() + n2);

    const int nmethods = c.nmethods;
    const int ordering = c.method[0].ordering;
    const int postorder = c.postorder;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 0;
    cholmod_sparse Av = lower_view(M);
    LS = cholmod_analyze_p(&Av, order.data(), nullptr, 0, &c);
    c.nmethods = nmethods;
    c.method[0].ordering = ordering;
    c.postorder = postorder;
    ++analyses;
    if (LS == nullptr) return from_status(c.status < 0 ? c.status : CHOLMOD_INVALID, "cholmod_analyze_p");
    const int* perm = static_cast<const int*>(LS->Perm);
    if (!LS->is_super || !std::equal(order.begin(), order.end(), perm)) {
      cholmod_free_factor(&LS, &c);
      return make_result(FactorizationStatus::numerical_failure,
                         "cholmod_analyze_p did not keep the requested elimination order");
    }
    return FactorizationResult::good();
  }

  /// S = L11 L11^T from the trailing n1 columns of the supernodal factor LS.
  void trailing_schur(Eigen::MatrixXd* S) const {
    const int n = static_cast<int>(LS->n);
    const int n1 = static_cast<int>(split.block1.size());
    const int n2 = n - n1;
    Eigen::MatrixXd L11 = Eigen::MatrixXd::Zero(n1, n1);
    const int* super = static_cast<const int*>(LS->super);
    const int* pi = static_cast<const int*>(LS->pi);
    const int* px = static_cast<const int*>(LS->px);
    const int* s = static_cast<const int*>(LS->s);
    const double* x = static_cast<const double*>(LS->x);
    for (std::size_t k = 0; k < LS->nsuper; ++k) {
      const int k1 = super[k], k2 = super[k + 1];
      if (k2 <= n2) continue;
      const int nsrow = pi[k + 1] - pi[k];
      const int* rows = s + pi[k];
      for (int j = std::max(k1, n2); j < k2; ++j) {
        const double* column = x + px[k] + static_cast<std::ptrdiff_t>(j - k1) * nsrow;
        for (int r = j - k1; r < nsrow; ++r) L11(rows[r] - n2, j - n2) = column[r];
      }
    }
    S->resize(n1, n1);
    // (Eigen's triangular product binds a reference to the data of an empty matrix: skip it)
    if (n1 > 0) S->noalias() = L11.triangularView<Eigen::Lower>() * L11.transpose();
  }
};

CholmodFactorization::CholmodFactorization(const FactorizationOptions& options)
    : impl_(std::make_unique<Impl>(options)) {}
CholmodFactorization::~CholmodFactorization() = default;
CholmodFactorization::CholmodFactorization(CholmodFactorization&&) noexcept = default;
CholmodFactorization& CholmodFactorization::operator=(CholmodFactorization&&) noexcept = default;

int CholmodFactorization::num_analyses() const { return impl_->analyses; }
double CholmodFactorization::rcond_estimate() const { return impl_->rcond; }

FactorizationResult CholmodFactorization::analyze(const SparseMatrix& A) {
  if (auto r = check_matrix(A); !r.ok()) return r;
  try {
    SparseMatrix storage;
    return impl_->analyze_main(compressed(A, storage));
  } catch (const std::bad_alloc&) {
    return out_of_memory();
  }
}

FactorizationResult CholmodFactorization::factorize(const SparseMatrix& A) {
  if (auto r = check_matrix(A); !r.ok()) return r;
  Impl& d = *impl_;
  try {
    SparseMatrix storage;
    const SparseMatrix& M = compressed(A, storage);
    if (d.L == nullptr || !d.main_pattern.matches(M)) {
      if (auto r = d.analyze_main(M); !r.ok()) return r;
    }
    d.main_factorized = false;
    d.rcond = -1.0;
    if (auto r = d.numeric(M, d.L, "cholmod_factorize"); !r.ok()) return r;
    d.main_factorized = true;
    return FactorizationResult::good();
  } catch (const std::bad_alloc&) {
    return out_of_memory();
  }
}

FactorizationResult CholmodFactorization::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
  Impl& d = *impl_;
  if (!d.main_factorized) return not_ready("solve() needs a successful factorize() first");
  if (X == nullptr) return invalid("solve(): X is null");
  const auto n = static_cast<Eigen::Index>(d.L->n);
  if (B.rows() != n)
    return invalid("solve(): B has " + std::to_string(B.rows()) + " rows, the matrix " + std::to_string(n));
  if (B.cols() == 0) {
    X->resize(n, 0);
    return FactorizationResult::good();
  }
  cholmod_dense Bv = dense_view(B);
  cholmod_dense* Xc = cholmod_solve(CHOLMOD_A, d.L, &Bv, &d.c);
  if (Xc == nullptr) return from_status(d.c.status < 0 ? d.c.status : CHOLMOD_INVALID, "cholmod_solve");
  try {
    *X = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
        static_cast<const double*>(Xc->x), n, B.cols(), Eigen::OuterStride<>(static_cast<Eigen::Index>(Xc->d)));
  } catch (const std::bad_alloc&) {
    cholmod_free_dense(&Xc, &d.c);
    return out_of_memory();
  }
  cholmod_free_dense(&Xc, &d.c);
  return FactorizationResult::good();
}

FactorizationResult CholmodFactorization::schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                                           Eigen::MatrixXd* S) {
  if (auto r = check_matrix(A); !r.ok()) return r;
  if (S == nullptr) return invalid("schur_complement(): S is null");
  Impl& d = *impl_;
  try {
    SparseMatrix storage;
    const SparseMatrix& M = compressed(A, storage);
    const bool same_block1 = d.schur_analyzed && std::equal(block1.begin(), block1.end(), d.split.block1.begin(),
                                                            d.split.block1.end());
    const bool reuse = same_block1 && d.schur_pattern.matches(M);
    d.schur_factorized = false;
    if (!reuse) {
      d.schur_analyzed = false;
      d.schur_pattern.clear();
      cholmod_free_factor(&d.LS, &d.c);
      if (auto r = split_blocks(M.rows(), block1, &d.split); !r.ok()) return r;
    }
    const std::size_t n2 = d.split.block2.size();
    if (n2 == 0) {  // nothing to eliminate: S = A (in block1's order)
      *S = dense_lower_block(M, d.split);
      d.schur_pattern.capture(M);
      d.schur_analyzed = d.schur_factorized = true;
      return FactorizationResult::good();
    }
    if (!reuse) {
      if (auto r = d.analyze_schur(M); !r.ok()) return r;
      d.schur_pattern.capture(M);
      d.schur_analyzed = true;
    }
    d.rcond = -1.0;
    if (auto r = d.numeric(M, d.LS, "cholmod_factorize (Schur complement)"); !r.ok()) {
      if (r.status == FactorizationStatus::not_positive_definite && d.LS->minor >= n2 && d.LS->minor < d.LS->n)
        r.message += "; A22 is positive definite but its Schur complement is not";
      return r;
    }
    d.trailing_schur(S);
    d.schur_factorized = true;
    return FactorizationResult::good();
  } catch (const std::bad_alloc&) {
    d.schur_factorized = false;
    return out_of_memory();
  }
}

FactorizationResult CholmodFactorization::solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
  Impl& d = *impl_;
  if (!d.schur_factorized) return not_ready("solve_interior() needs a successful schur_complement() first");
  if (X2 == nullptr) return invalid("solve_interior(): X2 is null");
  const auto n2 = static_cast<Eigen::Index>(d.split.block2.size());
  const auto n = static_cast<Eigen::Index>(d.split.position.size());
  if (B2.rows() != n2)
    return invalid("solve_interior(): B2 has " + std::to_string(B2.rows()) + " rows, A22 " + std::to_string(n2));
  if (n2 == 0 || B2.cols() == 0) {
    X2->setZero(n2, B2.cols());
    return FactorizationResult::good();
  }
  try {
    // Forward solve with L on [b2; 0] in elimination order, drop the trailing part, back solve
    // with L^T: x2 = L22^{-T} L22^{-1} b2 = A22^{-1} b2 with the one factor of A.
    Eigen::MatrixXd z = Eigen::MatrixXd::Zero(n, B2.cols());
    for (Eigen::Index k = 0; k < n2; ++k)
      z.row(k) = B2.row(d.split.position[static_cast<std::size_t>(d.order[static_cast<std::size_t>(k)])]);
    cholmod_dense zv = dense_view(z);
    cholmod_dense* y = cholmod_solve(CHOLMOD_L, d.LS, &zv, &d.c);
    if (y == nullptr) return from_status(d.c.status < 0 ? d.c.status : CHOLMOD_INVALID, "cholmod_solve (L)");
    Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>> ym(static_cast<double*>(y->x), n, B2.cols(),
                                                             Eigen::OuterStride<>(static_cast<Eigen::Index>(y->d)));
    ym.bottomRows(n - n2).setZero();
    cholmod_dense* w = cholmod_solve(CHOLMOD_Lt, d.LS, y, &d.c);
    cholmod_free_dense(&y, &d.c);
    if (w == nullptr) return from_status(d.c.status < 0 ? d.c.status : CHOLMOD_INVALID, "cholmod_solve (L^T)");
    Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> wm(
        static_cast<const double*>(w->x), n, B2.cols(), Eigen::OuterStride<>(static_cast<Eigen::Index>(w->d)));
    X2->resize(n2, B2.cols());
    for (Eigen::Index k = 0; k < n2; ++k)
      X2->row(d.split.position[static_cast<std::size_t>(d.order[static_cast<std::size_t>(k)])]) = wm.row(k);
    cholmod_free_dense(&w, &d.c);
  } catch (const std::bad_alloc&) {
    return out_of_memory();
  }
  return FactorizationResult::good();
}

}  // namespace hemivem
