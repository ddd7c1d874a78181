// Engine 'nlopt-mma': NLopt's MMA (NLOPT_LD_MMA, C API) on the smoothed energy F_eps with a
// continuation eps -> 0; see backends/nonsmooth/nlopt-mma/README.md.
#pragma once

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

class NloptMmaMinimizer final : public NonsmoothMinimizer {
 public:
  std::string name() const override { return "nlopt-mma"; }
  MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options) const override;
};

}  // namespace hemivem
