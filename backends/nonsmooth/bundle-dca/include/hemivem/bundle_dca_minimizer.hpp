// "bundle-dca": the DC algorithm for F = F1 - F2 (paper, section 4) whose convex subproblems
// min_{a in C} F1(a) - y^T a are solved by a proximal bundle method. The quadratic part of F1
// and the constraint set are kept exactly in the bundle subproblem; only the separable
// nonsmooth part sum_i w_i j1(a_i) is modelled by cutting planes (see README.md).
#pragma once

#include <hemivem/nonsmooth_minimizer.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hemivem {

class BundleDcaMinimizer final : public NonsmoothMinimizer {
 public:
  std::string name() const override { return "bundle-dca"; }
  MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options) const override;

  /// The names accepted in MinimizerOptions::parameters with their defaults.
  static const std::vector<std::pair<std::string, double>>& parameter_defaults();
};

}  // namespace hemivem
