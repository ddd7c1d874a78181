// Engine 'nlopt-mma': NLopt's MMA (NLOPT_LD_MMA, C API) on the smoothed energy F_eps with a
// continuation eps -> 0; see backends/nonsmooth/nlopt-mma/README.md.
#pragma once

#include <string>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

struct NloptMmaOptions {
  double epsilon = 1e-9;        ///< final smoothing scale (0: the law itself in the last stage), finite >= 0
  double epsilon0 = 1e-3;       ///< initial smoothing scale, finite > 0
  double reduction = 0.1;       ///< epsilon_{k+1} = reduction * epsilon_k, in (0, 1)
  double xtol_rel = 1e-10;      ///< MMA's relative step tolerance in a stage, >= 0
  int stage_evaluations = 20000;  ///< evaluation budget of one MMA run, >= 1
  int inner_maxeval = 50;       ///< MMA's inner iterations (0: NLopt's default), >= 0
  double snap = 1e-7;           ///< distance to a bound, relative to the length scale, under which a node pushed outward is put on it; in [0, 1)
  int polish_passes = 5;        ///< runs at the final scale with the nodes pushed onto a bound pinned, >= 0

  template <class Visit>
  void fields(Visit&& visit) {
    visit("epsilon", epsilon);
    visit("epsilon0", epsilon0);
    visit("reduction", reduction);
    visit("xtol_rel", xtol_rel);
    visit("stage_evaluations", stage_evaluations);
    visit("inner_maxeval", inner_maxeval);
    visit("snap", snap);
    visit("polish_passes", polish_passes);
  }
  bool is_valid(std::string* error) const;
};

class NloptMmaMinimizer final : public NonsmoothMinimizer {
 public:
  using Options = NloptMmaOptions;
  /// InputError naming the field when the options are not valid.
  explicit NloptMmaMinimizer(NloptMmaOptions options = {}) : options_(options) { require_valid(options_, "nlopt-mma"); }
  std::string name() const override { return "nlopt-mma"; }
  /// Groups of coordinates are smoothed as laws of their norm (README.md).
  bool takes_groups() const noexcept override { return true; }
  const NloptMmaOptions& options() const noexcept { return options_; }

 protected:
  MinimizerResult run(MinimizerRun& run) const override;

 private:
  NloptMmaOptions options_;
};

}  // namespace hemivem
