// Engine 'ceres-active-set': a projected active-set loop whose subproblems (the smoothed
// energy F_eps over the free nodes) are solved by Ceres' GradientProblemSolver (LBFGS), with
// a continuation eps -> 0; see backends/nonsmooth/ceres-active-set/README.md.
#pragma once

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

class CeresActiveSetMinimizer final : public NonsmoothMinimizer {
 public:
  std::string name() const override { return "ceres-active-set"; }
  MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options) const override;
};

}  // namespace hemivem
