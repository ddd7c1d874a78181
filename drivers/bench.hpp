// hemivem bench: every built (linear, minimizer) pair of engines on one scene, timed by stage
// against its error for several mesh sizes, computed by hemivem::app::run_bench
// (hemivem/app/bench.hpp); here its flags, table and exit code. Columns, JSON fields and exit
// codes: docs/reference/check-bench.md.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/app/bench.hpp>

namespace hemivem::cli {

using namespace hemivem::app;

struct BenchOptions {
  std::string scene;
  std::vector<int> n;                   ///< empty: bench_default_sizes of the scene's dimension
  std::optional<int> ref;               ///< none: bench_default_ref of the scene's dimension
  std::optional<double> tolerance;
  std::vector<std::string> set;
  std::string out = "out/bench";
  bool json = false;                    ///< bench.json also on stdout instead of the table
  int verbosity = 1;                    ///< 0 quiet, 1 table and progress
  int repeat = 1;                       ///< bench --limit: measurements per size, the fastest kept
  /// Refinement study: uniform levels beyond the scene's mesh (>= 1); none: bench_default_levels.
  std::optional<int> levels;
  std::optional<double> reference_energy;  ///< refinement study: the exact potential energy, when known
};

/// hemivem bench [SCENE]: wall time by stage and error against a reference solution for
/// every pair and mesh size; writes bench.csv, bench.json and bench.png into options.out.
/// Exit: kSuccess, or kNotConverged when the reference or a pair did not converge (files are
/// still written).
int run_bench(const BenchOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
