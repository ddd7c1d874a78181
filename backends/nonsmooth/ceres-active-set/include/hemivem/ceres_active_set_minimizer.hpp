// Engine 'ceres-active-set': Ceres' GradientProblemSolver (LBFGS) on the smoothed energy over
// the nodes not pinned to a bound, inside a projected active-set loop, with a continuation
// eps -> 0; see backends/nonsmooth/ceres-active-set/README.md.
#pragma once

#include <string>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

struct CeresActiveSetOptions {
  double epsilon = 1e-9;           ///< final smoothing scale (0: the law itself in the last stage), finite >= 0
  double epsilon0 = 1e-3;          ///< initial smoothing scale, finite > 0
  double reduction = 0.1;          ///< epsilon_{k+1} = reduction * epsilon_k, in (0, 1)
  int max_passes = 50;             ///< active-set passes per stage, >= 1
  int subproblem_iterations = 10000;  ///< Ceres iterations per pass, >= 1
  int lbfgs_rank = 20;             ///< LBFGS memory, in [1, 1000]
  double snap = 1e-7;              ///< distance to a bound, relative to the length scale, under which a node pushed outward is put on it; in [0, 1)

  template <class Visit>
  void fields(Visit&& visit) {
    visit("epsilon", epsilon);
    visit("epsilon0", epsilon0);
    visit("reduction", reduction);
    visit("max_passes", max_passes);
    visit("subproblem_iterations", subproblem_iterations);
    visit("lbfgs_rank", lbfgs_rank);
    visit("snap", snap);
  }
  bool is_valid(std::string* error) const;
};

class CeresActiveSetMinimizer final : public NonsmoothMinimizer {
 public:
  using Options = CeresActiveSetOptions;
  /// InputError naming the field when the options are not valid.
  explicit CeresActiveSetMinimizer(CeresActiveSetOptions options = {}) : options_(options) { require_valid(options_, "ceres-active-set"); }
  std::string name() const override { return "ceres-active-set"; }
  /// Groups of coordinates are smoothed as laws of their norm (README.md).
  bool takes_groups() const noexcept override { return true; }
  const CeresActiveSetOptions& options() const noexcept { return options_; }

 protected:
  MinimizerResult run(MinimizerRun& run) const override;

 private:
  CeresActiveSetOptions options_;
};

}  // namespace hemivem
