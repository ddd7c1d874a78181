// The Eigen engine: Eigen::SimplicialLLT (a simplicial up-looking Cholesky factorization).
//
// SimplicialLLT stops at the first pivot that is not > 0, so a matrix that is not positive
// definite is reported as not_positive_definite (SimplicialLDLT would not notice it).
//
// - analyze(): AMD ordering and symbolic factorization; always runs when called.
// - factorize(): numeric factorization, reusing the analysis while the pattern of A
//   (sizes, column pointers, row indices) is the one analysed.
// - schur_complement(): orders block2 by AMD on A22 alone and block1 last, factorizes the
//   permuted matrix once, L = [L22 0; L12 L11], and returns S = L11 L11^T. The cost is one
//   factorization of A plus the dense trailing block (|block1|^3 / 3 flops) — not one solve per
//   column of A21. The analysis is reused while the pattern and block1 are unchanged.
//   A (not only A22) must be positive definite.
// - solve_interior(): forward and back substitution with the leading block L22 of that factor
//   alone (the trailing block is not touched).
//
// Only the lower triangle of A is read.
#pragma once

#include <hemivem/sparse_factorization.hpp>

#include <memory>
#include <span>
#include <string>

namespace hemivem {

class EigenFactorization final : public SparseFactorization, public SplitInteriorSolve {
 public:
  explicit EigenFactorization(const FactorizationOptions& options = {});
  ~EigenFactorization() override;
  EigenFactorization(const EigenFactorization&) = delete;
  EigenFactorization& operator=(const EigenFactorization&) = delete;
  EigenFactorization(EigenFactorization&&) noexcept;
  EigenFactorization& operator=(EigenFactorization&&) noexcept;

  std::string name() const override { return "eigen"; }

  FactorizationResult analyze(const SparseMatrix& A) override;
  FactorizationResult factorize(const SparseMatrix& A) override;
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override;

  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                       Eigen::MatrixXd* S) override;
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override;
  FactorizationResult condense_rhs(const Eigen::VectorXd& b1, const Eigen::VectorXd& b2, Eigen::VectorXd* c) override;
  FactorizationResult expand(const Eigen::VectorXd& x1, Eigen::VectorXd* x2) const override;

  int num_analyses() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hemivem
