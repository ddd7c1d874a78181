// The semismooth Newton / active-set engine "ssn" (docs/reference/engines.md).
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
// active bounds and the certificate reaches round-off level. A group of coordinates (a law of
// the pair's norm) moves in its plane with its radius confined to the piece between the
// neighbouring kinks of j in radius, by radial scaling; a group stuck at 0 stays there while
// -(S a - c)_G lies in its subdifferential disc, and lands exactly on 0 like a node on a knot.
#pragma once

#include <memory>
#include <string>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

struct SsnOptions {
  double armijo = 1e-4;      ///< sufficient-decrease constant sigma in (0, 1/2)
  double backtrack = 0.5;    ///< step reduction factor in (0, 1)
  int max_backtracks = 30;   ///< backtracking steps before the gradient fallback, in [1, 1000]
  double active_scale = 1.0; ///< scale of the epsilon of the epsilon-active sets, finite >= 0
  double shift = 1e-8;       ///< first diagonal shift, relative to max |H_ii|, of an indefinite system; finite > 0

  template <class Visit>
  void fields(Visit&& visit) {
    visit("armijo", armijo);
    visit("backtrack", backtrack);
    visit("max_backtracks", max_backtracks);
    visit("active_scale", active_scale);
    visit("shift", shift);
  }
  bool is_valid(std::string* error) const {
    if (!(armijo > 0.0 && armijo < 0.5)) return invalid_field(error, "armijo", "in (0, 1/2)", armijo);
    if (!(backtrack > 0.0 && backtrack < 1.0)) return invalid_field(error, "backtrack", "in (0, 1)", backtrack);
    if (!(max_backtracks >= 1 && max_backtracks <= 1000))
      return invalid_field(error, "max_backtracks", "in [1, 1000]", max_backtracks);
    if (!(active_scale >= 0.0 && std::isfinite(active_scale)))
      return invalid_field(error, "active_scale", "finite and >= 0", active_scale);
    if (!(shift > 0.0 && std::isfinite(shift))) return invalid_field(error, "shift", "finite and > 0", shift);
    return true;
  }
};

class SsnMinimizer final : public NonsmoothMinimizer {
 public:
  using Options = SsnOptions;
  /// InputError naming the field when the options are not valid.
  explicit SsnMinimizer(SsnOptions options = {});
  std::string name() const override { return "ssn"; }
  const SsnOptions& options() const noexcept { return options_; }
  /// Groups of coordinates (a law of a pair's norm) are minimized in their plane (README.md).
  bool takes_groups() const noexcept override { return true; }

 protected:
  MinimizerResult run(MinimizerRun& run) const override;

 public:
  struct Memo;  ///< the last Newton system's factor, reused (only) for the same matrix

 private:
  SsnOptions options_;
  std::shared_ptr<Memo> memo_;
};

}  // namespace hemivem
