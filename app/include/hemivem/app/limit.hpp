// The limit of a scene: every stage of a cholmod solve (the scene's minimizer) against the
// limit of the same job on this machine, a plain Q1 triplet assembly of the same sparsity and
// one CHOLMOD analysis and factorization of hemivem's A with the faster of AMD and METIS, each
// measured in a fresh child process (docs/performance.md). `hemivem bench --limit` prints it
// and writes limit.json (schema hemivem-bench-limit/4, limit_json); Python's hemivem.limit
// returns limit.json's dict. Fields: docs/reference/check-bench.md.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/vem/assembly.hpp>

namespace hemivem::app {

/// The default sizes of a scene of dimension 2 or 3: 128, 256, 512 (N x N squares) in 2D;
/// 16, 24, 32 (N x N x N boxes) in 3D.
std::vector<int> limit_default_sizes(int dimension);

/// The plain assembly of the limit: the bilinear (Q1) plane-strain stiffness of one h x h
/// square (2 x 2 Gauss) added for every element of `mesh` with Eigen triplets, one
/// setFromTriplets: the lower triangle of the matrix on the free dofs of `dofs`. The same
/// sparsity as the VEM matrix on squares; InputError (mesh.generator) for an element that is not
/// a quadrilateral.
SparseMatrix plain_q1_matrix(const Mesh& mesh, const DofMap& dofs, double lambda, double mu);

/// The same for a solid made by the cubes generator: the trilinear (Q1) stiffness of one box
/// (2 x 2 x 2 Gauss) for every cell; InputError (mesh.generator) for a cell that is not a box.
SparseMatrix plain_q1_matrix(const Mesh3D& mesh, const DofMap& dofs, double lambda, double mu);

/// The seconds plain_q1_matrix takes (its checks of the mesh before the clock starts).
double plain_q1_assembly_seconds(const Mesh& mesh, const DofMap& dofs, double lambda, double mu);
double plain_q1_assembly_seconds(const Mesh3D& mesh, const DofMap& dofs, double lambda, double mu);

/// One mesh size: the stages of the fastest solve and the fastest limit.
struct LimitRow {
  int n = 0;
  int dofs = 0;           ///< the solve's unknowns
  int contact_nodes = 0;  ///< the reduced problem's size
  /// Seconds of mesh, assembly, condensation, minimize, back_substitution and result_json (the
  /// solve up to result.json), then margin (the uniqueness margin) and outputs (every file),
  /// timed after it.
  std::map<std::string, double> stage;
  double solve = 0.0;     ///< wall time from the scene to result.json
  double peak_rss = 0.0;  ///< bytes, the peak resident memory of the solve's process
  double plain_assembly = 0.0;  ///< seconds, the fastest of every measurement
  std::string ordering;         ///< CHOLMOD's faster ordering: "amd" or "metis"
  double analysis = 0.0, factorization = 0.0;  ///< seconds, with that ordering
  double factor_bytes = 0.0;    ///< the factor's values and row indices
  double matrix_bytes = 0.0;    ///< A's compressed storage
  std::map<std::string, double> alternative;  ///< the other ordering: analysis + factorization
  std::string status;           ///< the solve's status (to_string of SolverStatus)
};

/// One ratio of a row against its target (docs/performance.md).
struct LimitRatio {
  std::string key;    ///< its name in limit.json ("solve_over_limit", ...)
  std::string label;  ///< its short name in a table ("solve/limit", ...)
  double target = 0.0;
  double value = 0.0;  ///< inf or NaN when its denominator is 0
};

/// Every ratio of a row: solve / (plain assembly + factor), mesh / factor, assembly / plain,
/// condensation / factor, (minimize + back_substitution + margin) / factor, outputs / (solve -
/// result_json + outputs), peak RSS / (factor bytes + matrix bytes), where factor is analysis +
/// factorization.
std::vector<LimitRatio> limit_ratios(const LimitRow& row);

/// Where a bad option is reported (InputError's `where`).
struct LimitKeys {
  std::string sizes = "n", repeat = "repeat", limit = "limit";
};

struct LimitOptions {
  std::vector<int> sizes;  ///< empty: limit_default_sizes; measured in increasing order, once each
  int repeat = 1;          ///< measurements per size, the fastest of each kept (>= 1)
  LimitKeys keys;
  /// Called before and after each size is measured (in this process).
  std::function<void(int n)> size_started;
  std::function<void(const LimitRow&)> size_done;
};

/// The options that need no scene: InputError at keys.limit without the cholmod engine, at
/// keys.repeat for repeat < 1.
void check_limit_options(const LimitOptions& options);

/// A measurement checked and ready to run.
struct LimitPlan {
  Scene base;                ///< the scene on cholmod
  LimitOptions options;      ///< sizes resolved: sorted, each once
  std::vector<Scene> scenes;  ///< the base at each size (mesh.n)
};

/// Checks the options (check_limit_options), the sizes (>= 1, InputError at keys.sizes) and the
/// scene, set on solver.linear = "cholmod": its mesh must come from the squares generator, a
/// solid's from the cubes generator (InputError at mesh.generator otherwise).
LimitPlan plan_limit(const Scene& scene, const LimitOptions& options);

struct LimitResult {
  LimitPlan plan;
  std::vector<LimitRow> rows;  ///< one per size, in increasing order
};

/// Measures each size: the solve and the limit with AMD and with METIS, each `repeat` times in
/// fresh child processes (fork), taken in turn so that a machine that slows down or speeds up
/// affects both alike; keeps the fastest solve (by wall time), the fastest analysis +
/// factorization of each ordering and the fastest plain assembly. A failure in a child comes
/// back as the same kind of error (InputError or NumericalError); a child that ends without a
/// result (out of memory) is a NumericalError. Never prints.
LimitResult run_limit(const LimitPlan& plan);
/// plan_limit, then run_limit.
LimitResult run_limit(const Scene& scene, const LimitOptions& options);

/// One row of limit.json: n, dofs, contact_nodes, status, stages, solve, peak_rss_bytes, limit
/// {plain_assembly, ordering, analysis, factorization, other_orderings, factor_bytes,
/// matrix_bytes} and ratios (limit_ratios by key).
nlohmann::json limit_row_json(const LimitRow& row);

/// limit.json (schema hemivem-bench-limit/4): scene, linear, minimizer, repeat and the rows.
nlohmann::json limit_json(const LimitResult& result);

}  // namespace hemivem::app
