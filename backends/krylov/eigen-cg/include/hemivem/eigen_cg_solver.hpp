// The Krylov engine "eigen-cg": Eigen's ConjugateGradient on both triangles of A, preconditioned
// by Eigen's IncompleteCholesky (zero fill-in beyond A's pattern, AMD ordering, a diagonal
// shift raised until the factorization exists), or by the diagonal of A when the incomplete
// factorization fails. Always built. It runs in one process: KrylovHints::rows may be null or
// one process's rows (OneProcessRows); rows of several processes are refused with an
// InputError ("eigen-cg runs in one process; ...") thrown on every process.
//
// Eigen's CG stops on its recursive residual; solve() then computes the true residual
// ||b - A x||_2 / ||b||_2 and, when it is above rtol, restarts CG from x (at most four times,
// within max_iterations in all). The near-null space is not used.
//
// Definiteness: compute() reports not_positive_definite for a diagonal entry <= 0, and solve()
// for an x != 0 with x^T A x <= 0. Eigen's CG itself does not stop on negative curvature, so
// an indefinite matrix with a positive diagonal is not always recognised as such: CG may then
// end with numerical_failure (no convergence), or even converge.
#pragma once

#include <hemivem/krylov_solver.hpp>

#include <memory>
#include <string>

namespace hemivem {

class EigenCgSolver final : public KrylovSolver {
 public:
  EigenCgSolver();
  ~EigenCgSolver() override;
  EigenCgSolver(const EigenCgSolver&) = delete;
  EigenCgSolver& operator=(const EigenCgSolver&) = delete;

  std::string name() const override { return "eigen-cg"; }
  FactorizationResult compute(const SparseMatrix& A, const KrylovHints& hints) override;
  /// Not thread-safe: the solver's tolerances live in the object.
  KrylovSolveResult solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol,
                          int max_iterations) const override;
  void release() override;

  /// True when the last compute() fell back to the diagonal preconditioner.
  bool uses_diagonal_preconditioner() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hemivem
