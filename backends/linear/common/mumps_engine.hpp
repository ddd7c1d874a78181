// The MUMPS driver shared by the sequential and the MPI backends (private; no public header
// includes it). It is compiled separately into each backend, against that backend's MUMPS
// build, and instantiated with a communication policy:
//
//   struct Comm {
//     bool is_root() const;                 // the MUMPS host (rank 0), where A, B, S, X live
//     MUMPS_INT fortran_comm() const;       // MUMPS' COMM
//     void broadcast(void* data, int bytes) const;   // from the root to every process
//   };
//
// Every public method is collective: all processes call it in the same order. The root checks
// the arguments and decides; decisions and results are broadcast so that every process takes
// the same path and returns the same status.
#pragma once

#include <dmumps_c.h>
#include <hemivem/sparse_factorization.hpp>

#include "linear_common.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hemivem {
namespace {  // internal linkage: each backend has its own copy

#define HEMIVEM_ICNTL(I) icntl[(I) - 1]
#define HEMIVEM_INFOG(I) infog[(I) - 1]
#define HEMIVEM_RINFOG(I) rinfog[(I) - 1]

constexpr MUMPS_INT kJobInit = -1;
constexpr MUMPS_INT kJobEnd = -2;
constexpr MUMPS_INT kJobAnalyze = 1;
constexpr MUMPS_INT kJobFactorize = 2;
constexpr MUMPS_INT kJobSolve = 3;

using namespace linear_detail;

/// Every call into MUMPS, one at a time in the process: MUMPS keeps global state (its MPI
/// stand-in, the ordering libraries' workspaces), so two instances driven from two threads
/// at once corrupt each other. A solve in one thread waits for a factorization in another.
void call_mumps(DMUMPS_STRUC_C& id) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  dmumps_c(&id);
}

template <class Comm>
class MumpsEngine {
 public:
  MumpsEngine(const FactorizationOptions& options, Comm comm, std::string name)
      : comm_(std::move(comm)), name_(std::move(name)) {
    id_.comm_fortran = comm_.fortran_comm();
    id_.par = 1;  // the host works too
    id_.sym = 1;  // symmetric positive definite
    id_.job = kJobInit;
    call_mumps(id_);
    if (id_.HEMIVEM_INFOG(1) < 0) {
      init_error_ = make_result(FactorizationStatus::numerical_failure,
                                name_ + ": MUMPS initialization failed" + codes());
      return;
    }
    initialized_ = true;
    if (options.verbosity <= 0) {
      id_.HEMIVEM_ICNTL(1) = -1;  // errors
      id_.HEMIVEM_ICNTL(2) = -1;  // diagnostics and warnings
      id_.HEMIVEM_ICNTL(3) = -1;  // global information
      id_.HEMIVEM_ICNTL(4) = 0;   // print level
    } else {
      id_.HEMIVEM_ICNTL(1) = 6;
      id_.HEMIVEM_ICNTL(2) = 6;
      id_.HEMIVEM_ICNTL(3) = 6;
      id_.HEMIVEM_ICNTL(4) = std::min(options.verbosity, 4);
    }
    id_.HEMIVEM_ICNTL(5) = 0;   // assembled matrix
    id_.HEMIVEM_ICNTL(18) = 0;  // centralized on the host
    id_.HEMIVEM_ICNTL(20) = 0;  // dense right-hand sides
    id_.HEMIVEM_ICNTL(21) = 0;  // centralized solution
    if (options.threads > 0) id_.HEMIVEM_ICNTL(16) = options.threads;
  }

  ~MumpsEngine() {
    if (initialized_) {
      id_.job = kJobEnd;
      call_mumps(id_);
    }
  }

  MumpsEngine(const MumpsEngine&) = delete;
  MumpsEngine& operator=(const MumpsEngine&) = delete;

  int num_analyses() const noexcept { return num_analyses_; }
  int num_factorizations() const noexcept { return num_factorizations_; }
  bool is_root() const { return comm_.is_root(); }
  /// Collective: the root's value on every process.
  int share(int value) const {
    comm_.broadcast(&value, sizeof value);
    return value;
  }

  // ---- the contract ---------------------------------------------------------------------

  FactorizationResult analyze(const SparseMatrix& A) {
    if (!initialized_) return init_error_;
    SparseMatrix storage;
    const SparseMatrix& M = compressed(A, storage);
    FactorizationResult r = checked_on_root([&] { return check_pattern(M); });
    if (!r.ok()) return r;
    if (comm_.is_root()) {
      gather_pattern(M);
      gather_values(M);
    }
    return run_analysis({});
  }

  FactorizationResult factorize(const SparseMatrix& A) {
    if (!initialized_) return init_error_;
    SparseMatrix storage;
    const SparseMatrix& M = compressed(A, storage);
    int need_analysis = 0;
    FactorizationResult r = checked_on_root([&] {
      need_analysis = !(analysis_ == Analysis::plain && pattern_.matches(M));
      return check_matrix_values(M);
    }, /*forgets_factors=*/true);
    if (!r.ok()) return invalidate(std::move(r));
    comm_.broadcast(&need_analysis, sizeof need_analysis);
    if (comm_.is_root() && need_analysis) gather_pattern(M);
    if (comm_.is_root()) gather_values(M);
    if (need_analysis) {
      r = run_analysis({});
      if (!r.ok()) return r;
    }
    return run_factorization();
  }

  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) {
    if (!initialized_) return init_error_;
    std::int64_t nrhs = 0;
    FactorizationResult r = checked_on_root([&] {
      if (factors_ != Factors::full)
        contract_violation(factors_ == Factors::schur ? "solve() after schur_complement(): the factors held are those "
                                                        "of A22; call factorize() to solve with all of A"
                                                      : "solve() needs a successful factorize() first");
      nrhs = B.cols();
      return check_solve("solve()", "B", B, X, n_, "the matrix");
    });
    if (!r.ok()) return r;
    comm_.broadcast(&nrhs, sizeof nrhs);
    Eigen::MatrixXd R;
    if (comm_.is_root()) R = B;
    if (nrhs > 0) {
      r = run_solve(R, nrhs, /*error_analysis=*/false);
      if (!r.ok()) return r;
    }
    if (comm_.is_root()) *X = std::move(R) * scaled(-exponent_);
    return r;
  }

  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                       Eigen::MatrixXd* S) {
    if (!initialized_) return init_error_;
    interior_ready_ = false;
    SparseMatrix storage;
    const SparseMatrix& M = compressed(A, storage);
    std::int64_t n1 = 0;
    int need_analysis = 0;
    FactorizationResult r = checked_on_root([&] {
      if (S == nullptr) contract_violation("schur_complement(): S is null");
      FactorizationResult checked = check_matrix_values(M);
      if (checked.ok()) checked = split_blocks(M.rows(), block1, &split_);
      n1 = static_cast<std::int64_t>(block1.size());
      if (checked.ok() && n1 > 0 && n1 < M.rows())
        need_analysis = !(analysis_ == Analysis::schur && pattern_.matches(M) &&
                          std::equal(block1.begin(), block1.end(), block1_.begin(), block1_.end()));
      if (checked.ok() && n1 == 0) need_analysis = !(analysis_ == Analysis::plain && pattern_.matches(M));
      return checked;
    }, /*forgets_factors=*/true);
    if (!r.ok()) return invalidate(std::move(r));
    comm_.broadcast(&n1, sizeof n1);
    comm_.broadcast(&need_analysis, sizeof need_analysis);
    std::int64_t n = 0;
    if (comm_.is_root()) n = M.rows();
    comm_.broadcast(&n, sizeof n);

    if (n1 == n) return schur_of_everything(M, n, S);

    if (comm_.is_root()) {
      if (need_analysis) gather_pattern(M);
      gather_values(M);
    }
    if (need_analysis) {
      r = run_analysis(block1);
      if (!r.ok()) return r;
    }
    r = run_factorization();
    if (!r.ok()) return r;

    if (n1 > 0 && comm_.is_root()) {
      // ICNTL(19)=1 with SYM≠0: MUMPS fills the lower triangle by rows, that is the upper
      // triangle of the column-major n1×n1 array, in the order of LISTVAR_SCHUR.
      const auto m = static_cast<Eigen::Index>(n1);
      Eigen::Map<const Eigen::MatrixXd> raw(schur_.data(), m, m);
      Eigen::MatrixXd full = raw.template selfadjointView<Eigen::Upper>();
      r = check_schur_definite(full);
      if (r.ok()) *S = std::move(full) * scaled(exponent_);
    } else if (n1 == 0 && comm_.is_root()) {
      S->resize(0, 0);
    }
    r = agree(std::move(r));
    if (r.ok()) {
      schur_n_ = n;
      n1_ = n1;
      interior_ready_ = true;
    }
    return r;
  }

  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) {
    if (!initialized_) return init_error_;
    std::int64_t nrhs = 0;
    FactorizationResult r = checked_on_root([&] {
      if (!interior_ready_) contract_violation("solve_interior() needs a successful schur_complement() first");
      nrhs = B2.cols();
      return check_solve("solve_interior()", "B2", B2, X2, schur_n_ - n1_, "A22");
    });
    if (!r.ok()) return r;
    comm_.broadcast(&nrhs, sizeof nrhs);

    if (n1_ == schur_n_ || nrhs == 0) {  // A22 is empty, or nothing to solve
      if (comm_.is_root()) X2->setZero(schur_n_ - n1_, static_cast<Eigen::Index>(nrhs));
      return r;
    }
    Eigen::MatrixXd R;
    if (comm_.is_root()) {
      if (n1_ == 0) {
        R = B2;
      } else {
        R.setZero(n_, static_cast<Eigen::Index>(nrhs));
        for (std::size_t k = 0; k < split_.block2.size(); ++k)
          R.row(split_.block2[k]) = B2.row(static_cast<Eigen::Index>(k));
      }
    }
    r = run_solve(R, nrhs, /*error_analysis=*/false);
    if (!r.ok()) return r;
    if (comm_.is_root()) {
      R *= scaled(-exponent_);
      if (n1_ == 0) {
        *X2 = std::move(R);
      } else {
        X2->resize(schur_n_ - n1_, static_cast<Eigen::Index>(nrhs));
        for (std::size_t k = 0; k < split_.block2.size(); ++k)
          X2->row(static_cast<Eigen::Index>(k)) = R.row(split_.block2[k]);
      }
    }
    return r;
  }

  double rcond_estimate() {
    if (!initialized_ || factors_ != Factors::full) return -1.0;
    if (rcond_known_) return rcond_;
    Eigen::MatrixXd R;
    if (comm_.is_root()) {  // b = A·1, so that x = 1
      R.setZero(n_, 1);
      for (std::size_t k = 0; k < values_.size(); ++k) {
        const auto i = irn_[k] - 1, j = jcn_[k] - 1;
        R(i, 0) += values_[k];
        if (i != j) R(j, 0) += values_[k];
      }
    }
    const FactorizationResult r = run_solve(R, 1, /*error_analysis=*/true);
    double rcond = -1.0;
    if (comm_.is_root() && r.ok()) {
      const double cond1 = id_.HEMIVEM_RINFOG(10);
      if (std::isfinite(cond1) && cond1 > 0.0) rcond = 1.0 / cond1;
    }
    comm_.broadcast(&rcond, sizeof rcond);
    rcond_ = rcond;
    rcond_known_ = true;
    return rcond_;
  }

 private:
  enum class Analysis { none, plain, schur };
  enum class Factors { none, full, schur };

  // ---- checks (root) --------------------------------------------------------------------

  /// A square, non-empty matrix with both triangles stored (MUMPS reads the lower one, in
  /// the coordinates of the pattern, which must be that of a symmetric matrix).
  static FactorizationResult check_pattern(const SparseMatrix& A) {
    if (auto r = check_matrix(A); !r.ok()) return r;
    if (!symmetric_pattern(A))
      contract_violation("the pattern of the matrix is not symmetric (both triangles must be stored)");
    return FactorizationResult::good();
  }

  static FactorizationResult check_matrix_values(const SparseMatrix& A) {
    if (auto r = check_pattern(A); !r.ok()) return r;
    return check_values(A);
  }

  /// check_right_hand_sides, and finite right-hand sides (MUMPS' scaling and error analysis
  /// fail on others).
  static FactorizationResult check_solve(const std::string& call, const std::string& b_name, const Eigen::MatrixXd& B,
                                         const Eigen::MatrixXd* X, Eigen::Index rows, const std::string& matrix) {
    if (auto r = check_right_hand_sides(call, b_name, B, X, rows, matrix); !r.ok()) return r;
    if (!B.allFinite())
      return make_result(FactorizationStatus::numerical_failure, call + ": " + b_name + " has entries that are not finite");
    return FactorizationResult::good();
  }

  static FactorizationResult check_schur_definite(const Eigen::MatrixXd& S) {
    Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success)
      return make_result(FactorizationStatus::not_positive_definite,
                         "the Schur complement S is not positive definite, so A is not");
    return {};
  }

  // ---- data handed to MUMPS (root) -----------------------------------------------------

  void gather_pattern(const SparseMatrix& A) {
    pattern_.capture(A);
    pattern_n_ = A.rows();
    irn_.clear();
    jcn_.clear();
    positions_.clear();
    for (Eigen::Index j = 0; j < A.outerSize(); ++j)
      for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k)
        if (A.innerIndexPtr()[k] >= j) {  // lower triangle, 1-based for MUMPS
          irn_.push_back(static_cast<MUMPS_INT>(A.innerIndexPtr()[k] + 1));
          jcn_.push_back(static_cast<MUMPS_INT>(j + 1));
          positions_.push_back(k);
        }
    values_.assign(positions_.size(), 0.0);
  }

  // The values handed to MUMPS are A scaled by a power of two, 2^-exponent_, that brings its
  // largest entry to [1, 2): MUMPS' pivot thresholds are absolute, and a matrix whose entries
  // are all around 1e-16 was factorized wrongly without a word. The scaling is exact; solve()
  // and solve_interior() multiply their results by 2^-exponent_ and the Schur complement by
  // 2^exponent_.
  void gather_values(const SparseMatrix& A) {
    values_.resize(positions_.size());
    double largest = 0.0;
    for (std::size_t k = 0; k < positions_.size(); ++k) {
      values_[k] = A.valuePtr()[positions_[k]];
      largest = std::max(largest, std::abs(values_[k]));
    }
    exponent_ = largest > 0.0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
    if (exponent_ != 0)
      for (double& v : values_) v = std::ldexp(v, -exponent_);
  }
  /// 2^e for the exponent of the last gathered values.
  double scaled(int e) const { return std::ldexp(1.0, e); }

  // ---- MUMPS phases (collective) --------------------------------------------------------

  FactorizationResult run_analysis(std::span<const int> block1) {
    factors_ = Factors::none;
    interior_ready_ = false;
    rcond_known_ = false;
    std::int64_t n1 = static_cast<std::int64_t>(block1.size());
    comm_.broadcast(&n1, sizeof n1);
    std::int64_t n = 0;
    if (comm_.is_root()) {
      n = static_cast<std::int64_t>(pattern_n_);
      id_.n = static_cast<MUMPS_INT>(n);
      id_.nnz = static_cast<MUMPS_INT8>(irn_.size());
      id_.irn = irn_.data();
      id_.jcn = jcn_.data();
      id_.a = values_.data();
      block1_.assign(block1.begin(), block1.end());
      listvar_.resize(block1_.size());
      for (std::size_t k = 0; k < block1_.size(); ++k) listvar_[k] = static_cast<MUMPS_INT>(block1_[k] + 1);
      id_.size_schur = static_cast<MUMPS_INT>(listvar_.size());
      id_.listvar_schur = listvar_.empty() ? nullptr : listvar_.data();
    }
    id_.HEMIVEM_ICNTL(19) = n1 > 0 ? 1 : 0;  // centralized Schur complement on the host
    id_.job = kJobAnalyze;
    call_mumps(id_);
    ++num_analyses_;
    if (id_.HEMIVEM_INFOG(1) < 0) {
      analysis_ = Analysis::none;
      return error("analysis");
    }
    analysis_ = n1 > 0 ? Analysis::schur : Analysis::plain;
    comm_.broadcast(&n, sizeof n);
    n_ = n;
    return {};
  }

  FactorizationResult run_factorization() {
    factors_ = Factors::none;
    interior_ready_ = false;
    rcond_known_ = false;
    if (comm_.is_root()) {
      id_.a = values_.data();
      if (analysis_ == Analysis::schur) {
        const auto m = static_cast<std::size_t>(id_.size_schur);
        schur_.assign(m * m, 0.0);
        id_.schur = schur_.data();
        id_.schur_lld = id_.size_schur;
      } else {
        id_.schur = nullptr;
      }
    }
    id_.job = kJobFactorize;
    for (int attempt = 0;; ++attempt) {
      call_mumps(id_);
      const MUMPS_INT e = id_.HEMIVEM_INFOG(1);
      const bool workspace = e == -8 || e == -9 || e == -14 || e == -15 || e == -17 || e == -20;
      if (!workspace || attempt >= 4) break;
      // MUMPS underestimated its workspace: allow more (ICNTL(14) is a percentage).
      id_.HEMIVEM_ICNTL(14) = std::max<MUMPS_INT>(2 * id_.HEMIVEM_ICNTL(14), 50);
    }
    if (id_.HEMIVEM_INFOG(1) < 0) return error("factorization");
    if (id_.HEMIVEM_INFOG(12) > 0)
      return make_result(FactorizationStatus::not_positive_definite,
                         name_ + ": the matrix is not positive definite (" +
                             std::to_string(id_.HEMIVEM_INFOG(12)) + " negative pivot" +
                             (id_.HEMIVEM_INFOG(12) > 1 ? "s" : "") + ")");
    factors_ = analysis_ == Analysis::schur ? Factors::schur : Factors::full;
    ++num_factorizations_;
    return {};
  }

  /// Solves in place with the held factors (internal problem after a Schur factorization).
  FactorizationResult run_solve(Eigen::MatrixXd& R, std::int64_t nrhs, bool error_analysis) {
    if (comm_.is_root()) {
      id_.rhs = R.data();
      id_.lrhs = static_cast<MUMPS_INT>(n_);
    } else {
      id_.rhs = nullptr;
    }
    id_.nrhs = static_cast<MUMPS_INT>(nrhs);
    id_.HEMIVEM_ICNTL(11) = error_analysis ? 1 : 0;
    id_.HEMIVEM_ICNTL(26) = 0;  // with a Schur complement: solve the internal problem
    id_.job = kJobSolve;
    call_mumps(id_);
    id_.HEMIVEM_ICNTL(11) = 0;
    id_.rhs = nullptr;
    if (id_.HEMIVEM_INFOG(1) < 0) return error("solve");
    return {};
  }

  /// block1 = every index: S = A(block1, block1), no sparse factorization, A22 empty.
  FactorizationResult schur_of_everything(const SparseMatrix& A, std::int64_t n, Eigen::MatrixXd* S) {
    factors_ = Factors::none;  // the MUMPS factors held (if any) are not those of this A
    rcond_known_ = false;
    FactorizationResult r;
    if (comm_.is_root()) {
      Eigen::MatrixXd full = dense_lower_block(A, split_);
      r = check_schur_definite(full);
      if (r.ok()) *S = std::move(full);
    }
    r = agree(std::move(r));
    if (r.ok()) {
      schur_n_ = n;
      n1_ = n;
      interior_ready_ = true;
    }
    return r;
  }

  // ---- statuses ----------------------------------------------------------------------

  std::string codes() const {
    return " (INFOG(1) = " + std::to_string(id_.HEMIVEM_INFOG(1)) +
           ", INFOG(2) = " + std::to_string(id_.HEMIVEM_INFOG(2)) + ")";
  }

  FactorizationResult error(const char* phase) {
    const MUMPS_INT e = id_.HEMIVEM_INFOG(1);
    const std::string where = name_ + ": MUMPS " + phase + " failed" + codes() + ": ";
    switch (e) {
      case -6:
        return make_result(FactorizationStatus::not_positive_definite,
                           where + "the matrix is structurally singular");
      case -10:
        return make_result(FactorizationStatus::not_positive_definite,
                           where + "zero pivot: the matrix is singular or not positive definite");
      case -40:
        return make_result(FactorizationStatus::not_positive_definite,
                           where + "negative or zero pivot in the root front: the matrix is not positive definite");
      case -5:
      case -7:
      case -13:
      case -19:
        return make_result(FactorizationStatus::out_of_memory, where + "not enough memory");
      case -8:
      case -9:
      case -14:
      case -15:
      case -17:
      case -20:
        return make_result(FactorizationStatus::numerical_failure,
                           where + "internal workspace too small even after enlarging it (ICNTL(14))");
      default:
        return make_result(FactorizationStatus::numerical_failure,
                           where + "see 'Error diagnostics' in the MUMPS user guide");
    }
  }

  /// A failed call forgets the factors: a later solve is a broken contract.
  FactorizationResult invalidate(FactorizationResult r) {
    factors_ = Factors::none;
    interior_ready_ = false;
    rcond_known_ = false;
    return r;
  }

  /// Runs `checks` (the arguments of a call) on the root and agrees on their result; a broken
  /// contract (an InternalError on the root) is thrown on every process, so that none is left
  /// waiting in a collective call, after forgetting the factors when `forgets_factors` (a
  /// factorization that fails).
  template <class Checks>
  FactorizationResult checked_on_root(Checks&& checks, bool forgets_factors = false) {
    FactorizationResult r;
    std::string mistake;
    if (comm_.is_root()) {
      try {
        r = checks();
      } catch (const InternalError& e) {
        mistake = e.what();
      }
    }
    const FactorizationResult shared = agree({mistake.empty() ? FactorizationStatus::success
                                                              : FactorizationStatus::numerical_failure,
                                              mistake});
    if (!shared.ok()) {
      if (forgets_factors) invalidate({});
      throw InternalError(shared.message);
    }
    return agree(std::move(r));
  }

  /// The root's result, on every process.

  FactorizationResult agree(FactorizationResult r) const {
    int status = static_cast<int>(r.status);
    comm_.broadcast(&status, sizeof status);
    std::int64_t length = static_cast<std::int64_t>(r.message.size());
    comm_.broadcast(&length, sizeof length);
    r.message.resize(static_cast<std::size_t>(length));
    if (length > 0) comm_.broadcast(r.message.data(), static_cast<int>(length));
    r.status = static_cast<FactorizationStatus>(status);
    return r;
  }

  Comm comm_;
  std::string name_;
  DMUMPS_STRUC_C id_{};
  bool initialized_ = false;
  FactorizationResult init_error_;

  Analysis analysis_ = Analysis::none;  // same on every process
  Factors factors_ = Factors::none;     // same on every process
  bool interior_ready_ = false;         // same on every process
  std::int64_t n_ = 0;                  // order of the analysed matrix (every process)
  std::int64_t schur_n_ = 0;            // order of A at the last schur_complement()
  std::int64_t n1_ = 0;                 // size of its block1
  int num_analyses_ = 0;
  int num_factorizations_ = 0;
  double rcond_ = -1.0;
  bool rcond_known_ = false;

  // root only
  PatternKey pattern_;                   // pattern of the analysed matrix
  Eigen::Index pattern_n_ = 0;           // its order
  std::vector<MUMPS_INT> irn_, jcn_;     // its lower triangle, 1-based
  std::vector<int> positions_;           // where those entries sit in A's value array
  std::vector<double> values_;
  int exponent_ = 0;  // the values handed to MUMPS are 2^-exponent_ A
  std::vector<int> block1_;              // Schur indices of the last Schur analysis
  std::vector<MUMPS_INT> listvar_;
  BlockSplit split_;                     // block1 and its complement (block2) of the last schur_complement()
  std::vector<double> schur_;
};

#undef HEMIVEM_ICNTL
#undef HEMIVEM_INFOG
#undef HEMIVEM_RINFOG

}  // namespace
}  // namespace hemivem
