// hemivem bench --limit: every stage of a solve (cholmod and the scene's minimizer) against the
// limit of the same job, measured by hemivem::app::run_limit (hemivem/app/limit.hpp); here its
// table, ratios and limit.json (docs/performance.md, docs/reference/check-bench.md).
#pragma once

#include "bench.hpp"

#include <ostream>
#include <vector>

namespace hemivem::cli {

/// Measures each size in `sizes` (app::run_limit, in increasing order) and prints the stages,
/// the limits and their ratios with the targets of docs/performance.md; writes limit.json
/// (app::limit_json, "hemivem-bench-limit/4") into options.out. InputErrors as app::plan_limit's:
/// a scene whose mesh is not made by the squares (a solid: cubes) generator, no cholmod engine
/// (at --limit), --repeat < 1. `sizes` empty: app::limit_default_sizes of the scene's dimension.
int run_bench_limit(const BenchOptions& options, const std::vector<int>& sizes, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
