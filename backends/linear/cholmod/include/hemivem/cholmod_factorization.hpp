// The CHOLMOD engine: SuiteSparse's supernodal sparse Cholesky factorization.
//
// One cholmod_common per object (created in the constructor, finished in the destructor);
// the object is movable, not copyable. CHOLMOD's headers stay out of this header.
//
// - analyze(): CHOLMOD's default ordering strategy (AMD, and METIS when AMD's fill is high)
//   and supernodal symbolic factorization; always runs when called.
// - factorize(): numeric factorization, reusing the analysis while the pattern of A
//   (sizes, column pointers, row indices) is the one analysed. A matrix that is not positive
//   definite is reported as not_positive_definite (CHOLMOD_NOT_POSDEF, L->minor < n).
// - rcond_estimate(): cholmod_rcond of the last factor (a cheap estimate from diag(L)).
// - schur_complement(): orders A22 alone with AMD (measured faster overall than CHOLMOD's
//   default, which adds a METIS trial on large problems), puts block1 last in
//   the given order, and factorizes the lower triangle of A so permuted once, in that order
//   (CHOLMOD_NATURAL, no postordering, which could move block1 away from the end):
//   L = [L22 0; L12 L11], S = L11 L11^T, read from the trailing supernodes. Cost: one
//   factorization of A (plus |block1|^3/3 flops for the dense trailing block) — not one solve
//   per column of A21. Reused analysis while the pattern and block1 are unchanged. A (not only
//   A22) must be positive definite.
// - solve_interior(): forward and back substitution with the leading block L22 of that factor
//   alone (the trailing block is not touched), supernode by supernode with dense blocks.
//
// Only the lower triangle of A is read. `verbosity` becomes CHOLMOD's print level (0: silent).
// The const solves use the object's cholmod_common: one object serves one thread at a time.
#pragma once

#include <hemivem/reference_factorization.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <memory>
#include <span>
#include <string>

namespace hemivem {

/// One analysis and one numeric factorization of A (its lower triangle) by CHOLMOD alone,
/// supernodal, with AMD (`metis` false) or METIS (`metis` true), timed: the yardstick of
/// `hemivem bench --limit` (docs/performance.md). factor_bytes: the supernodal factor's.
ReferenceFactorization measure_cholmod_factorization(const SparseMatrix& A, bool metis);

class CholmodFactorization final : public SparseFactorization, public SplitInteriorSolve {
 public:
  explicit CholmodFactorization(const FactorizationOptions& options = {});
  ~CholmodFactorization() override;
  CholmodFactorization(const CholmodFactorization&) = delete;
  CholmodFactorization& operator=(const CholmodFactorization&) = delete;
  CholmodFactorization(CholmodFactorization&&) noexcept;
  CholmodFactorization& operator=(CholmodFactorization&&) noexcept;

  std::string name() const override { return "cholmod"; }

  FactorizationResult analyze(const SparseMatrix& A) override;
  FactorizationResult factorize(const SparseMatrix& A) override;
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override;

  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                       Eigen::MatrixXd* S) override;
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override;
  FactorizationResult condense_rhs(const Eigen::VectorXd& b1, const Eigen::VectorXd& b2, Eigen::VectorXd* c) override;
  FactorizationResult expand(const Eigen::VectorXd& x1, Eigen::VectorXd* x2) const override;

  double rcond_estimate() const override;
  int num_analyses() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hemivem
