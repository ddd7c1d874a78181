// EigenCgSolver (hemivem/eigen_cg_solver.hpp): Eigen's CG with the incomplete Cholesky or the
// diagonal preconditioner, the true-residual restarts and the outcomes.
#include <hemivem/eigen_cg_solver.hpp>

#include <hemivem/error.hpp>

#include <Eigen/IterativeLinearSolvers>

#include <cmath>
#include <utility>

#include "krylov_common.hpp"

namespace hemivem {

namespace {

using krylov::kMaxRestarts;
using krylov::scientific;

using IcCg = Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>>;
using DiagonalCg =
    Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>>;

}  // namespace

struct EigenCgSolver::Impl {
  SparseMatrix A;  // Eigen's solvers keep a reference to the matrix they were computed on
  mutable IcCg ic;
  mutable DiagonalCg diagonal;
  bool use_diagonal = false;
  bool computed = false;

  /// One CG run from *x; returns its iterations and whether it reported success.
  template <class Cg>
  std::pair<int, bool> run(Cg& cg, const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol, int budget) const {
    cg.setTolerance(rtol);
    cg.setMaxIterations(budget);
    *x = cg.solveWithGuess(b, *x);
    return {static_cast<int>(cg.iterations()), cg.info() == Eigen::Success};
  }
};

EigenCgSolver::EigenCgSolver() : impl_(std::make_unique<Impl>()) {}
EigenCgSolver::~EigenCgSolver() = default;

void EigenCgSolver::release() { impl_ = std::make_unique<Impl>(); }

bool EigenCgSolver::uses_diagonal_preconditioner() const noexcept { return impl_->use_diagonal; }

FactorizationResult EigenCgSolver::compute(const SparseMatrix& A, const KrylovHints& hints) {
  if (hints.rows && hints.rows->size() > 1)
    throw InputError("eigen-cg runs in one process; the system is distributed over " +
                         std::to_string(hints.rows->size()) +
                         " processes (the PETSc engines petsc-gamg and petsc-hypre run it there)",
                     "krylov engine");
  krylov::check_compute_arguments(name(), A, hints);
  Impl& m = *impl_;
  m.computed = false;
  if (const FactorizationResult screened = krylov::screen_matrix(A); !screened.ok())
    return {screened.status, "eigen-cg: " + screened.message};
  m.A = A;
  m.A.makeCompressed();
  m.use_diagonal = false;
  m.ic.compute(m.A);
  if (m.ic.info() != Eigen::Success) {
    m.use_diagonal = true;
    m.diagonal.compute(m.A);
    if (m.diagonal.info() != Eigen::Success)
      return {FactorizationStatus::numerical_failure, "eigen-cg: neither the incomplete Cholesky nor the diagonal "
                                                      "preconditioner could be set up"};
  }
  m.computed = true;
  return FactorizationResult::good();
}

KrylovSolveResult EigenCgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol,
                                       int max_iterations) const {
  const Impl& m = *impl_;
  if (!m.computed) throw InternalError("eigen-cg: solve() before a successful compute()");
  krylov::check_solve_arguments(name(), m.A.rows(), b, x, rtol, max_iterations);
  KrylovSolveResult out;
  if (krylov::prepare_start(b, x) == 0.0) return out;
  double relative = krylov::relative_residual(m.A, b, *x);
  for (int restart = 0; relative > rtol && out.iterations < max_iterations && restart <= kMaxRestarts; ++restart) {
    const int budget = max_iterations - out.iterations;
    const auto [iterations, converged] =
        m.use_diagonal ? m.run(m.diagonal, b, x, rtol, budget) : m.run(m.ic, b, x, rtol, budget);
    out.iterations += iterations;
    relative = krylov::relative_residual(m.A, b, *x);
    if (!converged || iterations == 0) break;
  }
  out.relative_residual = relative;
  const Eigen::VectorXd Ax = m.A * *x;
  const double curvature = x->dot(Ax);
  if (!std::isfinite(relative)) {
    out.status = FactorizationStatus::numerical_failure;
    out.message = "eigen-cg: the iterate is not finite after " + std::to_string(out.iterations) + " iterations";
  } else if (x->squaredNorm() > 0.0 && !(curvature > 0.0)) {
    out.status = FactorizationStatus::not_positive_definite;
    out.message =
        "eigen-cg: x^T A x = " + scientific(curvature) + " <= 0 for the x of CG: the matrix is not positive definite";
  } else if (relative > rtol) {
    out.status = FactorizationStatus::numerical_failure;
    out.message = "eigen-cg: no convergence in " + std::to_string(out.iterations) + " iterations (of " +
                  std::to_string(max_iterations) + "): relative residual " + scientific(relative) + " > " +
                  scientific(rtol);
  }
  return out;
}

}  // namespace hemivem
