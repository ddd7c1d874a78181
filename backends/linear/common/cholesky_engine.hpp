// The SparseFactorization contract for an engine that offers a sparse Cholesky factorization
// (private to backends/linear). The engine supplies a CholeskyKernel: its own fill-reducing
// ordering and factorization for analyze/factorize/solve, and a factorization in a given
// order whose columns can be read. CholeskyEngine does the rest once for every such engine:
// argument checks, reuse of the analysis while the pattern holds, and the Schur complement
// by an ordered factorization:
//
//   block2 is ordered by the kernel's fill-reducing ordering of A22 alone and block1 is put
//   last in the order given; P, the lower triangle of A in that order, is factorized once,
//   P = L L^T with L = [L22 0; L21 L11], so that S = A11 - A12 A22^{-1} A21 = L11 L11^T and
//   A22 = L22 L22^T. solve_interior() solves with L22 alone (the leading n2 columns of L,
//   rows < n2): the trailing block is never touched.
//
// The elimination order, P's pattern and its analysis are kept while A's pattern and block1
// are unchanged, so that a new schur_complement() only copies values and factorizes.
#pragma once

#include "linear_common.hpp"
#include "supernodal_substitution.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hemivem::linear_detail {

/// Column j of a lower triangular factor L: `size` entries, rows increasing, the diagonal first.
struct FactorColumn {
  const int* rows = nullptr;
  const double* values = nullptr;
  int size = 0;
};

/// A lower triangular factor stored by supernodes: supernode k holds the columns
/// [first[k], first[k + 1]) and the rows rows[row_start[k]] .. rows[row_start[k + 1] - 1]
/// (its own columns first, then the rows below, increasing), as a column-major dense block
/// with one row per stored row, at values + value_start[k].
struct Supernodes {
  int count = 0;
  const int* first = nullptr;
  const int* row_start = nullptr;
  const int* rows = nullptr;
  const int* value_start = nullptr;
  const double* values = nullptr;
};

/// What an engine supplies to CholeskyEngine. Every matrix passed is compressed, square and
/// non-empty with finite values; only its lower triangle is to be read.
class CholeskyKernel {
 public:
  virtual ~CholeskyKernel() = default;

  /// Symbolic analysis of A with the engine's fill-reducing ordering.
  virtual FactorizationResult analyze(const SparseMatrix& A) = 0;
  /// Numeric factorization of A with the analysis of the last analyze().
  virtual FactorizationResult factorize(const SparseMatrix& A) = 0;
  /// X = A^{-1} B with that factorization (B has A's rows and at least one column).
  virtual FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const = 0;
  /// Reciprocal condition estimate of the last factorize(), or negative.
  virtual double rcond() const { return -1.0; }

  /// A fill-reducing ordering of the symmetric matrix whose lower triangle `lower` holds:
  /// (*perm)[k] is the index eliminated k-th.
  virtual FactorizationResult order(const SparseMatrix& lower, std::vector<int>* perm) = 0;
  /// Symbolic analysis of P (lower triangle) to be factorized in its own order, unpermuted.
  virtual FactorizationResult analyze_ordered(const SparseMatrix& P) = 0;
  /// Numeric factorization P = L L^T with the analysis of the last analyze_ordered().
  /// Not positive definite: not_positive_definite, with failed_pivot() set when known.
  virtual FactorizationResult factorize_ordered(const SparseMatrix& P) = 0;
  /// Column j of L after a successful factorize_ordered().
  virtual FactorColumn column(int j) const = 0;
  /// The factor of the last factorize_ordered() by supernodes, when the engine stores it so:
  /// the substitutions of solve_interior() then run block by block.
  virtual bool supernodes(Supernodes* /*out*/) const { return false; }
  /// The column of P where the last factorize_ordered() stopped, or -1 when not known.
  virtual int failed_pivot() const { return -1; }
  /// S += L L^T on the lower triangle of S (n x n, column-major, leading dimension lds) for L
  /// (n x k, leading dimension ld), when the engine has a faster product than Eigen's (its
  /// BLAS); false, with S untouched, otherwise.
  virtual bool add_lower_product(int /*n*/, int /*k*/, const double* /*L*/, int /*ld*/, double* /*S*/,
                                 int /*lds*/) const {
    return false;
  }
};

class CholeskyEngine {
 public:
  CholeskyEngine(std::unique_ptr<CholeskyKernel> kernel, std::string name)
      : kernel_(std::move(kernel)), name_(std::move(name)) {}

  int num_analyses() const { return analyses_; }
  double rcond_estimate() const { return main_factorized_ ? kernel_->rcond() : -1.0; }

  FactorizationResult analyze(const SparseMatrix& A) {
    return guarded([&] {
      if (auto r = check_matrix(A); !r.ok()) return r;
      SparseMatrix storage;
      return analyze_main(compressed(A, storage));
    });
  }

  FactorizationResult factorize(const SparseMatrix& A) {
    return guarded([&] {
      main_factorized_ = false;
      SparseMatrix storage;
      const SparseMatrix& M = compressed(A, storage);
      if (auto r = check_values(M); !r.ok()) return r;
      if (!main_pattern_.matches(M)) {
        if (auto r = analyze_main(M); !r.ok()) return r;
      }
      if (auto r = kernel_->factorize(M); !r.ok()) return r;
      main_factorized_ = true;
      return FactorizationResult::good();
    });
  }

  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
    if (!main_factorized_) contract_violation("solve() needs a successful factorize() first");
    if (auto r = check_right_hand_sides("solve()", "B", B, X, main_n_, "the matrix"); !r.ok()) return r;
    if (B.cols() == 0) {
      X->resize(main_n_, 0);
      return FactorizationResult::good();
    }
    return guarded([&] { return kernel_->solve(B, X); });
  }

  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1, Eigen::MatrixXd* S) {
    return guarded([&] {
      schur_factorized_ = false;
      rhs_condensed_ = false;
      supernodal_ = false;  // the pieces of an earlier factor are made again below, or not used
      if (S == nullptr) contract_violation("schur_complement(): S is null");
      SparseMatrix storage;
      const SparseMatrix& M = compressed(A, storage);
      if (auto r = check_values(M); !r.ok()) return r;
      const bool reuse = schur_pattern_.matches(M) &&
                         std::equal(block1.begin(), block1.end(), split_.block1.begin(), split_.block1.end());
      if (!reuse) {
        schur_pattern_.clear();
        schedules_made_ = false;
        if (auto r = split_blocks(M.rows(), block1, &split_); !r.ok()) return r;
      }
      const int n = static_cast<int>(M.rows());
      const int n2 = static_cast<int>(split_.block2.size());
      if (n2 == 0) {  // nothing to eliminate: S = A (in block1's order)
        *S = dense_lower_block(M, split_);
        schur_pattern_.capture(M);
        schur_factorized_ = true;
        return FactorizationResult::good();
      }
      if (reuse) {
        copy_ordered_values(M);
      } else {
        if (auto r = analyze_ordered(M); !r.ok()) return r;
        schur_pattern_.capture(M);
      }
      if (auto r = kernel_->factorize_ordered(P_); !r.ok()) return explain(std::move(r), n2);
      prepare_substitutions(n, n2);
      read_schur(n, n2, S);
      schur_factorized_ = true;
      return FactorizationResult::good();
    });
  }

  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
    if (!schur_factorized_) contract_violation("solve_interior() needs a successful schur_complement() first");
    const auto n2 = static_cast<Eigen::Index>(split_.block2.size());
    if (auto r = check_right_hand_sides("solve_interior()", "B2", B2, X2, n2, "A22"); !r.ok()) return r;
    return guarded([&] {
      // X = B2 in elimination order (row k: the index of A eliminated k-th)
      Eigen::MatrixXd X(n2, B2.cols());
      for (Eigen::Index k = 0; k < n2; ++k) X.row(k) = B2.row(split_.position[order(k)]);
      substitute(X, Pass::forward, false);
      substitute(X, Pass::backward, false);
      X2->resize(n2, B2.cols());
      for (Eigen::Index k = 0; k < n2; ++k) X2->row(split_.position[order(k)]) = X.row(k);
      return FactorizationResult::good();
    });
  }

  /// c = b1 - A12 A22^{-1} b2 by one forward substitution: with z = (b2, b1) in elimination
  /// order, L22 y = b2 and c = b1 - L21 y (L21 = A12 L22^{-T}). y is kept for expand().
  FactorizationResult condense_rhs(const Eigen::VectorXd& b1, const Eigen::VectorXd& b2, Eigen::VectorXd* c) {
    rhs_condensed_ = false;
    if (!schur_factorized_) contract_violation("condense_rhs() needs a successful schur_complement() first");
    const auto n1 = static_cast<Eigen::Index>(split_.block1.size());
    const auto n2 = static_cast<Eigen::Index>(split_.block2.size());
    if (c == nullptr) contract_violation("condense_rhs(): c is null");
    if (b1.size() != n1 || b2.size() != n2)
      contract_violation("condense_rhs(): b1 and b2 need " + std::to_string(n1) + " and " + std::to_string(n2) +
                     " rows (block1 and the rest), got " + std::to_string(b1.size()) + " and " +
                     std::to_string(b2.size()));
    return guarded([&] {
      Eigen::MatrixXd z(n1 + n2, 1);
      for (Eigen::Index k = 0; k < n2; ++k) z(k, 0) = b2(split_.position[order(k)]);
      z.col(0).tail(n1) = b1;
      substitute(z, Pass::forward, true);
      y_ = z.col(0).head(n2);
      *c = z.col(0).tail(n1);
      rhs_condensed_ = true;
      return FactorizationResult::good();
    });
  }

  /// x2 = A22^{-1} (b2 - A21 x1) = L22^{-T} (y - L21^T x1) by one backward substitution.
  FactorizationResult expand(const Eigen::VectorXd& x1, Eigen::VectorXd* x2) const {
    if (!rhs_condensed_) contract_violation("expand() needs a successful condense_rhs() first");
    const auto n1 = static_cast<Eigen::Index>(split_.block1.size());
    const auto n2 = static_cast<Eigen::Index>(split_.block2.size());
    if (x2 == nullptr) contract_violation("expand(): x2 is null");
    if (x1.size() != n1)
      contract_violation("expand(): x1 needs " + std::to_string(n1) + " rows (block1), got " + std::to_string(x1.size()));
    return guarded([&] {
      Eigen::MatrixXd z(n1 + n2, 1);
      z.col(0).head(n2) = y_;
      z.col(0).tail(n1) = x1;
      substitute(z, Pass::backward, true);
      x2->resize(n2);
      for (Eigen::Index k = 0; k < n2; ++k) (*x2)(split_.position[order(k)]) = z(k, 0);
      return FactorizationResult::good();
    });
  }

 private:
  enum class Pass { forward, backward };

  /// One substitution with the leading n2 columns of L, X in elimination order:
  ///   forward:  X2 = L22^{-1} X2, and with `tail` X1 -= L21 X2;
  ///   backward: X2 = L22^{-T} X2, with `tail` X2 = L22^{-T} (X2 - L21^T X1);
  /// X2 the first n2 rows of X and X1 the rest (present with `tail` only).
  void substitute(Eigen::MatrixXd& X, Pass pass, bool tail) const {
    const int n2 = static_cast<int>(split_.block2.size());
    const int end = tail ? static_cast<int>(X.rows()) : n2;  // the rows of L read
    if (supernodal_) {
      substitute_by_supernodes(by_supernodes_[tail ? 1 : 0], pass, X);
      return;
    }
    // Column by column, on X transposed, so that each step reads one contiguous column of m values.
    const Eigen::Index m = X.cols();
    Eigen::MatrixXd z = X.transpose();
    double* zd = z.data();
    auto zc = [&](int k) { return zd + static_cast<std::ptrdiff_t>(k) * m; };
    if (pass == Pass::forward) {
      for (int j = 0; j < n2; ++j) {
        const FactorColumn c = kernel_->column(j);
        double* zj = zc(j);
        const double d = c.values[0];
        for (Eigen::Index r = 0; r < m; ++r) zj[r] /= d;
        for (int t = 1; t < c.size && c.rows[t] < end; ++t) {
          double* zt = zc(c.rows[t]);
          const double v = c.values[t];
          for (Eigen::Index r = 0; r < m; ++r) zt[r] -= v * zj[r];
        }
      }
    } else {
      for (int j = n2 - 1; j >= 0; --j) {
        const FactorColumn c = kernel_->column(j);
        double* zj = zc(j);
        for (int t = 1; t < c.size && c.rows[t] < end; ++t) {
          const double* zt = zc(c.rows[t]);
          const double v = c.values[t];
          for (Eigen::Index r = 0; r < m; ++r) zj[r] -= v * zt[r];
        }
        const double d = c.values[0];
        for (Eigen::Index r = 0; r < m; ++r) zj[r] /= d;
      }
    }
    X = z.transpose();
  }

  /// substitute_by_supernodes() for at most four columns, on X transposed (each row's values
  /// contiguous) with the loops of supernodal_substitution.hpp, on two threads where the
  /// schedule splits the factor.
  static void substitute_few(const std::vector<SupernodePiece>& pieces, const SubstitutionSchedule& schedule, Pass pass,
                             Eigen::MatrixXd& X) {
    Eigen::MatrixXd z = X.transpose();
    auto run = [&]<int M>() {
      if (pass == Pass::forward)
        forward_few<M>(pieces, schedule, z.data());
      else
        backward_few<M>(pieces, schedule, z.data());
    };
    switch (X.cols()) {
      case 1: run.template operator()<1>(); break;
      case 2: run.template operator()<2>(); break;
      case 3: run.template operator()<3>(); break;
      case 4: run.template operator()<4>(); break;
      default: contract_violation("substitute_few() takes one to four columns");
    }
    X = z.transpose();
  }

  /// The size of a factor (entries read by a substitution) from which the substitutions with a
  /// few right-hand sides run on two threads: about 16 MB, a few milliseconds a pass.
  static constexpr double substitution_split_entries = 2.0e6;

  /// The pieces of a supernodal L's supernodes with a column of L22 for the rows read up to
  /// `end` (n2: an interior solve; n: with the rows of block1), and their schedule.
  struct PiecesAndSchedule {
    std::vector<SupernodePiece> pieces;
    SubstitutionSchedule schedule;
  };

  /// Makes by_supernodes_ after a factorization: the pieces (they point into the factor's
  /// values), and their schedules once per pattern (they depend on its structure alone).
  void prepare_substitutions(int n, int n2) {
    Supernodes L;
    supernodal_ = kernel_->supernodes(&L);
    if (!supernodal_) return;
    int last = 0;  // the supernodes with a column of L22
    while (last < L.count && L.first[last] < n2) ++last;
    for (int t = 0; t < 2; ++t) {
      const int end = t == 0 ? n2 : n;
      PiecesAndSchedule& s = by_supernodes_[t];
      s.pieces.resize(static_cast<std::size_t>(last));
      for (int k = 0; k < last; ++k) {
        const int j0 = L.first[k], ncol = L.first[k + 1] - j0;
        const int nrow = L.row_start[k + 1] - L.row_start[k];
        const int* rows = L.rows + L.row_start[k];
        const int nc = std::min(ncol, n2 - j0);  // the supernode's columns in L22
        // the block's rows after those nc columns (rows increase) that are < end
        const int count = static_cast<int>(std::lower_bound(rows + nc, rows + nrow, end) - (rows + nc));
        s.pieces[static_cast<std::size_t>(k)] = SupernodePiece{j0, nc, count, nrow, rows, L.values + L.value_start[k]};
      }
      if (!schedules_made_) s.schedule = schedule_substitution(s.pieces, n2, end, substitution_split_entries);
    }
    schedules_made_ = true;
  }

  /// substitute() for a supernodal L: per supernode with a column of L22, a dense triangular
  /// solve with its diagonal block and a dense product with its rows of L below (those < end),
  /// gathered and scattered through their row indices.
  static void substitute_by_supernodes(const PiecesAndSchedule& by, Pass pass, Eigen::MatrixXd& X) {
    const std::vector<SupernodePiece>& pieces = by.pieces;
    if (X.cols() <= 4) {  // a few columns: each block read once for all of them
      substitute_few(pieces, by.schedule, pass, X);
      return;
    }
    // more columns: dense products per block (the block's leading nc columns, its first
    // nc + count rows)
    using Block = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
    Eigen::MatrixXd T;
    if (pass == Pass::forward) {
      for (const SupernodePiece& p : pieces) {
        const Block block(p.values, p.nc + p.count, p.nc, Eigen::OuterStride<>(p.ld));
        auto x = X.middleRows(p.j0, p.nc);
        block.topLeftCorner(p.nc, p.nc).triangularView<Eigen::Lower>().solveInPlace(x);
        if (p.count == 0) continue;
        T.noalias() = block.bottomRows(p.count) * x;
        for (int r = 0; r < p.count; ++r) X.row(p.rows[p.nc + r]) -= T.row(r);
      }
    } else {
      for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) {
        const SupernodePiece& p = *it;
        const Block block(p.values, p.nc + p.count, p.nc, Eigen::OuterStride<>(p.ld));
        auto x = X.middleRows(p.j0, p.nc);
        if (p.count > 0) {
          T.resize(p.count, X.cols());
          for (int r = 0; r < p.count; ++r) T.row(r) = X.row(p.rows[p.nc + r]);
          x.noalias() -= block.bottomRows(p.count).transpose() * T;
        }
        block.topLeftCorner(p.nc, p.nc).transpose().triangularView<Eigen::Upper>().solveInPlace(x);
      }
    }
  }

  /// Runs `f`, turning an allocation failure into out_of_memory.
  template <class F>
  FactorizationResult guarded(F&& f) const {
    try {
      return f();
    } catch (const std::bad_alloc&) {
      return make_result(FactorizationStatus::out_of_memory, "out of memory in the " + name_ + " engine");
    }
  }

  std::size_t order(Eigen::Index k) const { return static_cast<std::size_t>(order_[static_cast<std::size_t>(k)]); }

  FactorizationResult analyze_main(const SparseMatrix& M) {
    main_factorized_ = false;
    main_pattern_.clear();
    ++analyses_;
    if (auto r = kernel_->analyze(M); !r.ok()) return r;
    main_pattern_.capture(M);
    main_n_ = M.rows();
    return FactorizationResult::good();
  }

  /// The elimination order (block2 by the kernel's ordering of A22, then block1), P's pattern,
  /// the map from A's entries to P's, and the kernel's analysis of P.
  FactorizationResult analyze_ordered(const SparseMatrix& M) {
    const int n = static_cast<int>(M.rows());
    const int n2 = static_cast<int>(split_.block2.size());
    std::vector<int> perm22;
    if (auto r = kernel_->order(lower_pattern_a22(M), &perm22); !r.ok()) return r;
    order_.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n2; ++k)
      order_[static_cast<std::size_t>(k)] = split_.block2[static_cast<std::size_t>(perm22[static_cast<std::size_t>(k)])];
    std::copy(split_.block1.begin(), split_.block1.end(), order_.begin() + n2);
    build_ordered_pattern(M);
    ++analyses_;
    return kernel_->analyze_ordered(P_);
  }

  /// The pattern of the lower triangle of A22 (block2 is increasing, so each column's rows stay
  /// sorted), its diagonal always included; values are 1.
  SparseMatrix lower_pattern_a22(const SparseMatrix& M) const {
    const int n = static_cast<int>(M.rows());
    const int n2 = static_cast<int>(split_.block2.size());
    const int* outer = M.outerIndexPtr();
    const int* inner = M.innerIndexPtr();
    std::vector<int> col(static_cast<std::size_t>(n2) + 1, 0), row;
    row.reserve(static_cast<std::size_t>(M.nonZeros() / 2 + n2));
    for (int j = 0; j < n; ++j) {
      const int pj = split_.position[static_cast<std::size_t>(j)];
      if (pj < 0) continue;
      row.push_back(pj);
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        const int pi = split_.position[static_cast<std::size_t>(inner[k])];
        if (inner[k] > j && pi >= 0) row.push_back(pi);
      }
      col[static_cast<std::size_t>(pj) + 1] = static_cast<int>(row.size());
    }
    return pattern_matrix(n2, n2, col, row, 1.0);
  }

  /// Calls f(k, row, column) for each entry k of A's lower triangle with its (row, column) in P.
  template <class F>
  void for_each_ordered_entry(const SparseMatrix& M, F&& f) const {
    const int n = static_cast<int>(M.rows());
    const int* outer = M.outerIndexPtr();
    const int* inner = M.innerIndexPtr();
    std::vector<int> new_pos(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) new_pos[static_cast<std::size_t>(order_[static_cast<std::size_t>(k)])] = k;
    for (int j = 0; j < n; ++j) {
      const int b = new_pos[static_cast<std::size_t>(j)];
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        if (inner[k] < j) continue;
        const int a = new_pos[static_cast<std::size_t>(inner[k])];
        f(k, std::max(a, b), std::min(a, b));
      }
    }
  }

  /// P: the lower triangle of A in elimination order. Its transpose (the upper triangle, an
  /// entry (row, column) of P in column `row`) is placed first, in any order within its
  /// columns; transposing it visits its columns in increasing order, so each column of P
  /// comes out sorted by row, with no sort.
  void build_ordered_pattern(const SparseMatrix& M) {
    const int n = static_cast<int>(M.rows());
    const auto at = [](int k) { return static_cast<std::size_t>(k); };
    std::vector<int> start(at(n) + 1, 0);  // of the columns of the transpose
    for_each_ordered_entry(M, [&](int, int row, int) { ++start[at(row) + 1]; });
    for (int j = 0; j < n; ++j) start[at(j) + 1] += start[at(j)];
    const int nnz = start[at(n)];
    std::vector<int> upper_row(at(nnz));
    std::vector<double> upper_value(at(nnz));
    std::vector<int> column_size(at(n) + 1, 0);  // of P
    {
      std::vector<int> next(start.begin(), start.end() - 1);
      const double* source = M.valuePtr();
      for_each_ordered_entry(M, [&](int k, int row, int column) {
        const int p = next[at(row)]++;
        upper_row[at(p)] = column;
        upper_value[at(p)] = source[k];
        ++column_size[at(column) + 1];
      });
    }
    P_ = SparseMatrix(n, n);
    P_.resizeNonZeros(nnz);
    int* outer = P_.outerIndexPtr();
    for (int j = 0; j < n; ++j) column_size[at(j) + 1] += column_size[at(j)];
    std::copy(column_size.begin(), column_size.end(), outer);
    int* rows = P_.innerIndexPtr();
    double* values = P_.valuePtr();
    column_size.pop_back();  // from here: the next free position in each column of P
    for (int b = 0; b < n; ++b)
      for (int p = start[at(b)]; p < start[at(b) + 1]; ++p) {
        const int q = column_size[at(upper_row[at(p)])]++;
        rows[q] = b;
        values[q] = upper_value[at(p)];
      }
  }

  /// P's values from A's, P's pattern unchanged: each entry found by its row in its column.
  void copy_ordered_values(const SparseMatrix& M) {
    const int* outer = P_.outerIndexPtr();
    const int* rows = P_.innerIndexPtr();
    double* values = P_.valuePtr();
    const double* source = M.valuePtr();
    for_each_ordered_entry(M, [&](int k, int row, int column) {
      values[std::lower_bound(rows + outer[column], rows + outer[column + 1], row) - rows] = source[k];
    });
  }

  /// S = L11 L11^T from the trailing n - n2 columns of L: its lower triangle by blocks of
  /// columns of L11 (the columns [k, k + w) are zero above row k, so they update S(k:, k:)
  /// alone: n1^3 / 6 multiplications, a third of a triangular times a full matrix), mirrored.
  void read_schur(int n, int n2, Eigen::MatrixXd* S) const {
    const int n1 = n - n2;
    Eigen::MatrixXd L11 = Eigen::MatrixXd::Zero(n1, n1);
    for (int j = n2; j < n; ++j) {
      const FactorColumn c = kernel_->column(j);
      for (int t = 0; t < c.size; ++t) L11(c.rows[t] - n2, j - n2) = c.values[t];
    }
    S->setZero(n1, n1);
    constexpr int block = 128;
    for (int k = 0; k < n1; k += block) {
      const int w = std::min(block, n1 - k);
      if (!kernel_->add_lower_product(n1 - k, w, &L11(k, k), n1, &(*S)(k, k), n1))
        S->bottomRightCorner(n1 - k, n1 - k).selfadjointView<Eigen::Lower>().rankUpdate(L11.block(k, k, n1 - k, w));
    }
    for (int j = 1; j < n1; ++j)
      for (int i = 0; i < j; ++i) (*S)(i, j) = (*S)(j, i);
  }

  /// Names, for a factorization of P that is not positive definite, where it stopped.
  FactorizationResult explain(FactorizationResult r, int n2) const {
    const int pivot = kernel_->failed_pivot();
    if (r.status != FactorizationStatus::not_positive_definite || pivot < 0) return r;
    r.message += " (stopped at pivot " + std::to_string(pivot) + " of the ordered matrix, index " +
                 std::to_string(order_[static_cast<std::size_t>(pivot)]) + " of A)";
    if (pivot >= n2) r.message += "; A22 is positive definite but its Schur complement is not";
    return r;
  }

  std::unique_ptr<CholeskyKernel> kernel_;
  std::string name_;
  int analyses_ = 0;

  // analyze / factorize / solve
  PatternKey main_pattern_;
  Eigen::Index main_n_ = 0;
  bool main_factorized_ = false;

  // schur_complement / solve_interior
  PatternKey schur_pattern_;
  BlockSplit split_;
  std::vector<int> order_;    // order_[k]: the index of A eliminated k-th
  SparseMatrix P_;            // lower triangle of A in elimination order
  bool schur_factorized_ = false;
  bool supernodal_ = false;                 // L is supernodal: by_supernodes_ holds its pieces
  PiecesAndSchedule by_supernodes_[2];      // for the rows up to n2 and up to n
  bool schedules_made_ = false;             // their schedules are those of schur_pattern_
  Eigen::VectorXd y_;           // L22^{-1} b2 of the last condense_rhs(), in elimination order
  bool rhs_condensed_ = false;
};

}  // namespace hemivem::linear_detail
