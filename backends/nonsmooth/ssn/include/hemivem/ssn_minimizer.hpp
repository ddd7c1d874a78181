// The semismooth Newton / active-set engine "ssn" (DESIGN §5).
//
// Each iteration splits the nodes into fixed ones (at a bound or at a kink of j whose
// one-sided derivatives of F say "stay") and moving ones, each moving node confined to its
// "piece box": the interval between the neighbouring knots (bounds and kinks of j) in the
// direction it moves. On the product of piece boxes F is C^1 with a piecewise-smooth
// Hessian S + W j''(side), so a projected Newton step (Bertsekas' epsilon-active sets, the
// generalized Hessian on the side of motion, an LLT of the reduced free-set system, a
// diagonal shift when that system is indefinite) with Armijo backtracking along the
// projection arc, and a scaled projected-gradient fallback, decreases F monotonically.
// Nodes land exactly on knots, so kinks with 0 in the Clarke interval are recognised like
// active bounds and the certificate reaches round-off level.
//
// Parameters (MinimizerOptions::parameters, all optional):
//   armijo          sufficient-decrease constant sigma in (0, 1/2)         (1e-4)
//   backtrack       step reduction factor in (0, 1)                        (0.5)
//   max_backtracks  backtracking steps before the gradient fallback (>= 1) (30)
//   active_scale    scale of the epsilon of the epsilon-active sets (>= 0) (1)
//   shift           first diagonal shift, relative to max |H_ii|, tried
//                   when the free-set Hessian is not positive definite (>0) (1e-8)
#pragma once

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

class SsnMinimizer final : public NonsmoothMinimizer {
 public:
  std::string name() const override { return "ssn"; }
  MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options) const override;
};

}  // namespace hemivem
