// "bundle-dca": the DC algorithm for F = F1 - F2 (paper, section 4) whose convex subproblems
// min_{a in C} F1(a) - y^T a are solved by a proximal bundle method. The quadratic part of F1
// and the constraint set are kept exactly in the bundle subproblem; only the nonsmooth part
// sum_i w_i j1(a_i) (and w j1(|a_G|) per group of coordinates, as a function of the pair) is
// modelled by cutting planes (see README.md).
#pragma once

#include <string>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

struct BundleDcaOptions {
  int bundle_size = 12;                 ///< cuts kept per coordinate, in [4, 1e6]
  double proximal_weight = 1e-3;        ///< mu = proximal_weight * max_i S_ii, finite >= 0
  double descent = 0.1;                 ///< serious-step test m, in (0, 1)
  double inner_tolerance_factor = 0.1;  ///< inner tolerance = max(factor * certificate, floor * tolerance), (0, 1]
  double inner_tolerance_floor = 0.1;   ///< (0, 1]
  int max_bundle_iterations = 500;      ///< per DC subproblem, >= 1
  int stall_iterations = 5;             ///< DC steps without progress before "stalled", >= 1
  bool two_sided_cuts = true;           ///< at a kink of j1 add the cuts of both one-sided derivatives

  template <class Visit>
  void fields(Visit&& visit) {
    visit("bundle_size", bundle_size);
    visit("proximal_weight", proximal_weight);
    visit("descent", descent);
    visit("inner_tolerance_factor", inner_tolerance_factor);
    visit("inner_tolerance_floor", inner_tolerance_floor);
    visit("max_bundle_iterations", max_bundle_iterations);
    visit("stall_iterations", stall_iterations);
    visit("two_sided_cuts", two_sided_cuts);
  }
  bool is_valid(std::string* error) const {
    if (!(bundle_size >= 4 && bundle_size <= 1000000))
      return invalid_field(error, "bundle_size", "in [4, 1000000]", bundle_size);
    if (!(proximal_weight >= 0.0 && std::isfinite(proximal_weight)))
      return invalid_field(error, "proximal_weight", "finite and >= 0", proximal_weight);
    if (!(descent > 0.0 && descent < 1.0)) return invalid_field(error, "descent", "in (0, 1)", descent);
    if (!(inner_tolerance_factor > 0.0 && inner_tolerance_factor <= 1.0))
      return invalid_field(error, "inner_tolerance_factor", "in (0, 1]", inner_tolerance_factor);
    if (!(inner_tolerance_floor > 0.0 && inner_tolerance_floor <= 1.0))
      return invalid_field(error, "inner_tolerance_floor", "in (0, 1]", inner_tolerance_floor);
    if (max_bundle_iterations < 1) return invalid_field(error, "max_bundle_iterations", ">= 1", max_bundle_iterations);
    if (stall_iterations < 1) return invalid_field(error, "stall_iterations", ">= 1", stall_iterations);
    return true;
  }
};

class BundleDcaMinimizer final : public NonsmoothMinimizer {
 public:
  using Options = BundleDcaOptions;
  /// InputError naming the field when the options are not valid.
  explicit BundleDcaMinimizer(BundleDcaOptions options = {}) : options_(options) {
    require_valid(options_, "bundle-dca");
  }
  std::string name() const override { return "bundle-dca"; }
  /// Groups of coordinates are modelled by cuts of their pair (README.md).
  bool takes_groups() const noexcept override { return true; }
  const BundleDcaOptions& options() const noexcept { return options_; }

 protected:
  MinimizerResult run(MinimizerRun& run) const override;

 private:
  BundleDcaOptions options_;
};

}  // namespace hemivem
