// A search for the lowest critical point of a reduced problem that may have several
// (uniqueness margin lambda_min(S - diag(alpha_i w_i)) <= 0): local runs of several minimizers
// from several starting points, every certified critical point kept.
//
// The search is a heuristic. Its claim is "the lowest of the certified critical points found",
// each certified by the one certificate of docs/reference/certificate.md; it is no proof that no lower one exists.
//
// Phase 1 (multistart): every engine from each start, in this order: the given start, the
// minimizer of the quadratic part alone (S^{-1} c projected onto C), the lower bounds, the
// upper bounds (where finite), every breakpoint of the laws and the middle of every bounded
// piece between them (each coordinate at the k-th of its own law's), then `random_starts`
// points drawn uniformly (std::mt19937_64 seeded by `seed`) in a box around the bounds, the
// breakpoints and the quadratic minimizer.
// Phase 2 (single-coordinate moves): from the lowest critical point, one coordinate is moved
// to a breakpoint, the middle of a piece or a bound of its law, most promising first (the
// smallest change of F by that move alone), and the first engine runs from there; a lower
// certified point replaces the lowest and the moves start again from it. It ends when no move
// lowers F or the budget is spent.
// Order and budget: phase 1 up to half of `max_starts` local runs, then phase 2, then the rest
// of phase 1, then phase 2 again when that found a lower point; at most `max_starts` local runs
// in all, and none begins after `time_budget` seconds.
//
// A problem whose uniqueness margin is positive has one critical point: it is solved once by
// the first engine and the result says so.
//
// Groups of coordinates (ReducedProblem::groups: a law of a pair's norm) are taken when every
// engine takes them (takes_groups()); otherwise minimize() refuses such a problem and
// engines_without_groups() names the engines that do not. A group's breakpoints are radii: its
// starts put the pair at 0, at the law's positive breakpoints or at the middles between them
// along the quadratic minimizer's pair, its random starts are drawn in a disc, and its moves
// put the pair's norm at 0 (stuck) or at such a radius along its current direction or along
// -(S a - c)_G.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

/// What the search reports after every local run.
struct GlobalSearchProgress {
  int run = 0;           ///< 1, 2, ... (local runs so far)
  int max_runs = 0;      ///< the budget
  std::string engine;    ///< the engine of this run
  std::string start;     ///< the start's name ("quadratic minimizer", "breakpoint 0.01", "random 3", "move 12 -> 0.005" ...)
  bool certified = false;
  double objective = 0.0;     ///< F at the run's point
  double lowest = 0.0;        ///< the lowest F of a certified point so far (NaN: none yet)
  int critical_points = 0;    ///< distinct certified critical points so far
  double seconds = 0.0;       ///< since the search began
};

struct GlobalSearchOptions {
  int max_starts = 64;        ///< local runs in all (both phases)
  double time_budget = 60.0;  ///< seconds after which no new run begins
  int seed = 1;               ///< of the random starts
  int random_starts = 8;      ///< random starts in phase 1
  /// Two certified points are one critical point when ||a - b||_inf <= agree * the larger of
  /// their certificates' length scales.
  double agree = 1e-6;
  std::function<void(const GlobalSearchProgress&)> progress;  ///< after every run (may be empty)

  bool is_valid(std::string* error) const {
    if (max_starts < 1) return invalid_field(error, "max_starts", ">= 1", max_starts);
    if (!(time_budget > 0.0)) return invalid_field(error, "time_budget", "> 0", time_budget);
    if (seed < 0) return invalid_field(error, "seed", ">= 0", seed);
    if (random_starts < 0) return invalid_field(error, "random_starts", ">= 0", random_starts);
    if (!(agree > 0.0 && agree < 1.0)) return invalid_field(error, "agree", "in (0, 1)", agree);
    return true;
  }
};

/// A named starting point of phase 1.
struct SearchStart {
  std::string name;
  Eigen::VectorXd a;
};

class GlobalSearch final : public NonsmoothMinimizer {
 public:
  /// `engines` in the order they run from each start; the first solves unique problems and
  /// runs the moves of phase 2. InputError for no engine or invalid options.
  explicit GlobalSearch(std::vector<std::shared_ptr<const NonsmoothMinimizer>> engines,
                        GlobalSearchOptions options = {});
  std::string name() const override { return "global"; }
  const GlobalSearchOptions& options() const noexcept { return options_; }
  /// The names of the engines, in order.
  std::vector<std::string> engine_names() const;
  /// True when every engine takes groups of coordinates.
  bool takes_groups() const noexcept override;
  /// Names the engines that do not take groups.
  std::string groups_refusal() const override;
  /// The names of the engines that do not take groups of coordinates, in order (empty when
  /// the search takes them).
  std::vector<std::string> engines_without_groups() const;

  /// The starts of phase 1 for `problem` (the given start first; projected onto C; duplicates
  /// removed), deterministic for a given seed.
  std::vector<SearchStart> starts(const ReducedProblem& problem, const Eigen::VectorXd& given) const;

 protected:
  bool answers_certified_start() const noexcept override { return false; }
  MinimizerResult run(MinimizerRun& run) const override;

 private:
  std::vector<std::shared_ptr<const NonsmoothMinimizer>> engines_;
  GlobalSearchOptions options_;
};

/// A global search with `first` first and then `others` by name with their defaults (empty:
/// every built minimizer; `first` is not repeated). InputError for a name unknown or not built.
std::unique_ptr<GlobalSearch> make_global_search(std::unique_ptr<NonsmoothMinimizer> first,
                                                 GlobalSearchOptions options = {},
                                                 const std::vector<std::string>& others = {});
/// The same with `first` = make_minimizer(first, parameters): InputError for an unknown or
/// unbuilt name or a bad parameter.
std::unique_ptr<GlobalSearch> make_global_search(const std::string& first,
                                                 const std::map<std::string, double>& parameters = {},
                                                 GlobalSearchOptions options = {},
                                                 const std::vector<std::string>& others = {});

}  // namespace hemivem
