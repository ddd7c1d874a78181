// hemivem check: every built (linear, minimizer) pair of engines on one scene, compared with
// each other. Columns, JSON fields and exit codes: docs/reference/check-bench.md.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace hemivem::cli {

struct CheckOptions {
  std::string scene;                    ///< scene file; empty: the embedded Example 4.1
  std::optional<int> n;
  std::optional<double> tolerance;      ///< certificate tolerance for every pair
  std::vector<std::string> set;         ///< --set key=value, in order
  double agree = 1e-6;                  ///< largest relative difference of u accepted between two pairs
  bool json = false;                    ///< the report as JSON on stdout instead of the table
  int verbosity = 1;                    ///< 0 quiet, 1 table and progress
};

/// hemivem check [SCENE]: the scene solved by every available (linear, minimizer) pair.
/// Exit: kSuccess; kBackendFailure when an engine failed; else kNotConverged when a pair did
/// not converge; else kDisagreement when two converged pairs differ by more than `agree`.
int run_check(const CheckOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
