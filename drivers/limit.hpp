// hemivem bench --limit: every stage of a solve (cholmod and the scene's minimizer) against the
// limit of the same job, measured in the same process: a plain Q1 triplet assembly of the same
// sparsity and one CHOLMOD analysis and factorization of hemivem's A with the faster of AMD and
// METIS (docs/performance.md).
#pragma once

#include "bench.hpp"

#include <ostream>
#include <vector>

namespace hemivem::cli {

/// Measures each size in `sizes` (run in increasing order) and prints the stages, the limits
/// and their ratios with the targets of docs/performance.md; writes limit.json
/// ("hemivem-bench-limit/2") into options.out. The scene's mesh must come from the squares
/// generator, or for a three-dimensional scene the cubes generator, against the plain Q1 assembly
/// of boxes (InputError otherwise); without the cholmod engine the limit cannot be measured
/// (InputError).
/// `sizes` empty: the default sizes, 128, 256, 512 for a plane scene and 16, 24, 32 for a
/// three-dimensional one.
int run_bench_limit(const BenchOptions& options, const std::vector<int>& sizes, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
