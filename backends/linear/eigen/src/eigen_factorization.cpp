#include <hemivem/eigen_factorization.hpp>

#include "linear_common.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <new>
#include <vector>

namespace hemivem {

using namespace linear_detail;

namespace {

using MainSolver = Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>;
// The Schur complement solver receives a matrix that is already in elimination order.
using OrderedSolver = Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>>;

template <class Solver>
bool factor_is_finite(const Solver& solver) {
  const SparseMatrix& L = solver.matrixL().nestedExpression();
  const double* x = L.valuePtr();
  for (Eigen::Index k = 0; k < L.nonZeros(); ++k)
    if (!std::isfinite(x[k])) return false;
  return true;
}

template <class Solver>
FactorizationResult check_numeric(const Solver& solver) {
  if (solver.info() == Eigen::NumericalIssue)
    return make_result(FactorizationStatus::not_positive_definite,
                       "the matrix is not positive definite (SimplicialLLT met a pivot <= 0)");
  if (solver.info() != Eigen::Success)
    return make_result(FactorizationStatus::numerical_failure, "SimplicialLLT failed");
  if (!factor_is_finite(solver))
    return make_result(FactorizationStatus::numerical_failure,
                       "the Cholesky factor has entries that are not finite (NaN or Inf in the matrix?)");
  return FactorizationResult::good();
}

FactorizationResult out_of_memory() {
  return make_result(FactorizationStatus::out_of_memory, "out of memory in the Eigen engine");
}

}  // namespace

struct EigenFactorization::Impl {
  FactorizationOptions options;
  int analyses = 0;

  // analyze / factorize / solve
  MainSolver main;
  PatternKey main_pattern;
  bool main_analyzed = false;
  bool main_factorized = false;
  Eigen::Index main_n = 0;

  // schur_complement / solve_interior
  OrderedSolver ordered;
  PatternKey schur_pattern;
  BlockSplit split;
  std::vector<int> order;     // order[k]: index of A eliminated k-th (block2 by AMD, then block1)
  std::vector<int> new_pos;   // inverse of order
  bool schur_analyzed = false;
  bool schur_factorized = false;

  FactorizationResult analyze_main(const SparseMatrix& M) {
    main_factorized = false;
    main_analyzed = false;
    main_pattern.clear();
    main.analyzePattern(M);
    ++analyses;
    if (main.info() != Eigen::Success)
      return make_result(FactorizationStatus::numerical_failure, "SimplicialLLT::analyzePattern failed");
    main_pattern.capture(M);
    main_analyzed = true;
    main_n = M.rows();
    return FactorizationResult::good();
  }

  // The lower triangle of A permuted to elimination order.
  SparseMatrix ordered_lower(const SparseMatrix& M) const {
    const Eigen::Index n = M.rows();
    std::vector<Eigen::Triplet<double, int>> entries;
    entries.reserve(static_cast<std::size_t>(M.nonZeros() / 2 + n));
    for (Eigen::Index j = 0; j < n; ++j) {
      for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
        if (it.row() < j) continue;
        const int a = new_pos[static_cast<std::size_t>(it.row())];
        const int b = new_pos[static_cast<std::size_t>(j)];
        entries.emplace_back(std::max(a, b), std::min(a, b), it.value());
      }
    }
    SparseMatrix P(n, n);
    P.setFromTriplets(entries.begin(), entries.end());
    return P;
  }

  void analyze_schur(const SparseMatrix& M) {
    const int n = static_cast<int>(M.rows());
    const int n2 = static_cast<int>(split.block2.size());
    // Fill-reducing ordering of A22 alone (pattern of its lower triangle).
    std::vector<Eigen::Triplet<double, int>> entries;
    for (int j = 0; j < n; ++j) {
      const int pj = split.position[static_cast<std::size_t>(j)];
      if (pj < 0) continue;
      for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
        if (it.row() < j) continue;
        const int pi = split.position[static_cast<std::size_t>(it.row())];
        if (pi >= 0) entries.emplace_back(pi, pj, 1.0);
      }
    }
    SparseMatrix A22(n2, n2);
    A22.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
    Eigen::AMDOrdering<int> amd;
    amd(A22, inverse);

    order.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n2; ++k) order[static_cast<std::size_t>(k)] = split.block2[static_cast<std::size_t>(inverse.indices()[k])];
    for (std::size_t t = 0; t < split.block1.size(); ++t) order[static_cast<std::size_t>(n2) + t] = split.block1[t];
    new_pos.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) new_pos[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;

    ordered.analyzePattern(ordered_lower(M));
    ++analyses;
  }
};

EigenFactorization::EigenFactorization(const FactorizationOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
}
EigenFactorization::~EigenFactorization() = default;
EigenFactorization::EigenFactorization(EigenFactorization&&) noexcept = default;
EigenFactorization& EigenFactorization::operator=(EigenFactorization&&) noexcept = default;

int EigenFactorization::num_analyses() const { return impl_->analyses; }

FactorizationResult EigenFactorization::analyze(const SparseMatrix& A) {
  if (auto r = check_matrix(A); !r.ok()) return r;
  try {
    SparseMatrix storage;
    return impl_->analyze_main(compressed(A, storage));
  } catch (const std::bad_alloc&) {
    impl_->main_analyzed = impl_->main_factorized = false;
    return out_of_memory();
  }
}

FactorizationResult EigenFactorization::factorize(const SparseMatrix& A) {
  if (auto r = check_matrix(A); !r.ok()) return r;
  Impl& d = *impl_;
  try {
    SparseMatrix storage;
    const SparseMatrix& M = compressed(A, storage);
    if (!d.main_analyzed || !d.main_pattern.matches(M)) {
      if (auto r = d.analyze_main(M); !r.ok()) return r;
    }
    d.main_factorized = false;
    d.main.factorize(M);
    if (auto r = check_numeric(d.main); !r.ok()) return r;
    d.main_factorized = true;
    return FactorizationResult::good();
  } catch (const std::bad_alloc&) {
    d.main_analyzed = d.main_factorized = false;
    return out_of_memory();
  }
}

FactorizationResult EigenFactorization::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
  const Impl& d = *impl_;
  if (!d.main_factorized) return not_ready("solve() needs a successful factorize() first");
  if (X == nullptr) return invalid("solve(): X is null");
  if (B.rows() != d.main_n)
    return invalid("solve(): B has " + std::to_string(B.rows()) + " rows, the matrix " +
                   std::to_string(d.main_n));
  try {
    *X = d.main.solve(B);
  } catch (const std::bad_alloc&) {
    return out_of_memory();
  }
  return FactorizationResult::good();
}

FactorizationResult EigenFactorization::schur_complement(const SparseMatrix& A, std::span<const int> block1,
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
      if (auto r = split_blocks(M.rows(), block1, &d.split); !r.ok()) return r;
    }
    const Eigen::Index n = M.rows();
    const Eigen::Index n1 = static_cast<Eigen::Index>(d.split.block1.size());
    const Eigen::Index n2 = n - n1;
    if (n2 == 0) {  // nothing to eliminate: S = A (in block1's order)
      *S = dense_lower_block(M, d.split);
      d.schur_pattern.capture(M);
      d.schur_analyzed = d.schur_factorized = true;
      return FactorizationResult::good();
    }
    if (!reuse) {
      d.analyze_schur(M);
      if (d.ordered.info() != Eigen::Success)
        return make_result(FactorizationStatus::numerical_failure, "SimplicialLLT::analyzePattern failed");
      d.schur_pattern.capture(M);
      d.schur_analyzed = true;
    }
    d.ordered.factorize(d.ordered_lower(M));
    if (auto r = check_numeric(d.ordered); !r.ok()) return r;

    // L = [L22 0; L12 L11] in elimination order, so S = L11 L11^T (already in block1's order).
    const SparseMatrix& L = d.ordered.matrixL().nestedExpression();
    Eigen::MatrixXd L11 = Eigen::MatrixXd::Zero(n1, n1);
    for (Eigen::Index j = n2; j < n; ++j)
      for (SparseMatrix::InnerIterator it(L, j); it; ++it)
        if (it.row() >= j) L11(it.row() - n2, j - n2) = it.value();
    S->resize(n1, n1);
    // (Eigen's triangular product binds a reference to the data of an empty matrix: skip it)
    if (n1 > 0) S->noalias() = L11.triangularView<Eigen::Lower>() * L11.transpose();
    d.schur_factorized = true;
    return FactorizationResult::good();
  } catch (const std::bad_alloc&) {
    d.schur_analyzed = d.schur_factorized = false;
    return out_of_memory();
  }
}

FactorizationResult EigenFactorization::solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
  const Impl& d = *impl_;
  if (!d.schur_factorized) return not_ready("solve_interior() needs a successful schur_complement() first");
  if (X2 == nullptr) return invalid("solve_interior(): X2 is null");
  const Eigen::Index n2 = static_cast<Eigen::Index>(d.split.block2.size());
  const Eigen::Index n = static_cast<Eigen::Index>(d.split.position.size());
  if (B2.rows() != n2)
    return invalid("solve_interior(): B2 has " + std::to_string(B2.rows()) + " rows, A22 " + std::to_string(n2));
  try {
    if (n2 == 0) {
      X2->resize(0, B2.cols());
      return FactorizationResult::good();
    }
    // Solve with the leading block L22 of the factor: forward with L on [b2; 0], drop the
    // trailing part, back substitution with L^T.
    Eigen::MatrixXd z = Eigen::MatrixXd::Zero(n, B2.cols());
    for (Eigen::Index k = 0; k < n2; ++k)
      z.row(k) = B2.row(d.split.position[static_cast<std::size_t>(d.order[static_cast<std::size_t>(k)])]);
    d.ordered.matrixL().solveInPlace(z);
    z.bottomRows(n - n2).setZero();
    d.ordered.matrixU().solveInPlace(z);
    X2->resize(n2, B2.cols());
    for (Eigen::Index k = 0; k < n2; ++k)
      X2->row(d.split.position[static_cast<std::size_t>(d.order[static_cast<std::size_t>(k)])]) = z.row(k);
  } catch (const std::bad_alloc&) {
    return out_of_memory();
  }
  return FactorizationResult::good();
}

}  // namespace hemivem
