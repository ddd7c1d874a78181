// hemivem check --extreme: the stiff and extreme scenes of scenes/extreme/ solved with every
// built pair of engines, one assembly per scene and one condensation per (scene, linear engine), and a
// stability table (columns and exit codes: docs/reference/check-bench.md, discussion: docs/stability.md).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace hemivem::cli {

struct ExtremeOptions {
  std::string scenes;                ///< folder of *.toml scenes; empty: the source tree's scenes/extreme
  std::vector<std::string> only;     ///< scene names (file names without .toml) to run; empty: all
  std::optional<double> tolerance;   ///< certificate tolerance for every pair (default: each scene's)
  double agree = 1e-6;               ///< largest relative difference of u accepted between converged pairs
  bool json = false;                 ///< the report as JSON on stdout instead of the table
  int verbosity = 1;                 ///< 0 quiet, 1 table and progress
};

/// Runs every scene of options.scenes with every available (linear, minimizer) pair.
/// Exit: kInternalError when a guarantee was broken (a pair claimed convergence with a
/// non-finite displacement or an infeasible point); else kDisagreement when two converged
/// pairs differ by more than `agree` on a scene whose solution is unique (uniqueness margin
/// > 0); else kSuccess. Pairs that do not converge or engines that fail are reported, not
/// errors: extreme scenes are expected to defeat some engines.
int run_check_extreme(const ExtremeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
