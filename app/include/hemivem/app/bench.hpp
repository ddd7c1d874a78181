// The bench of a scene: every built (linear, minimizer) pair of engines (engine_pairs.hpp: the
// condensed route's pairs and the full-space route's, each Krylov engine with ssn) timed by
// stage against its error for several mesh sizes (a full-space pair whose route refuses the
// scene is a row with status "refused", which does not fail the bench), the error measured against a
// reference solution on a nested grid; and a refinement study (uniform levels, adaptive steps
// in 2D, true errors against a reference energy given or extrapolated by Aitken's method).
// `hemivem bench` prints it and writes bench.csv, bench.json, bench.png and bench-error.png
// (write_bench); Python's hemivem.bench returns it. Columns and JSON fields:
// docs/reference/check-bench.md.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <hemivem/app/engine_pairs.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// The defaults of a scene of dimension 2 or 3: the mesh sizes (16, 32, 64, 128 in 2D; 4, 8, 16
/// in 3D), the reference's size (256; 32) and the uniform levels of the refinement study (3; 2).
std::vector<int> bench_default_sizes(int dimension);
int bench_default_ref(int dimension);
int bench_default_levels(int dimension);

/// The reference energy of the refinement study by Aitken's delta-squared extrapolation of the
/// potential energies of three successive uniform refinements (coarse to fine):
/// phi2 - (phi1 - phi2)^2 / ((phi0 - phi1) - (phi1 - phi2)). None unless the differences
/// d1 = phi0 - phi1 and d2 = phi1 - phi2 have the same sign and decay (0 < d2 / d1 < 1) and the
/// result is finite.
std::optional<double> aitken_reference(double phi0, double phi1, double phi2);

/// One series of bench.png: a pair of engines and its points (relative error, wall time).
struct BenchSeries {
  std::string linear, minimizer;
  std::vector<std::array<double, 2>> points;
};

/// The gnuplot script of bench.png (its data inline): error (x, log) against time (y, log),
/// one line per series, coloured by minimizer, dashed and marked by linear engine; the key
/// groups the series by linear engine, a heading per engine (a Krylov engine's says "full-space
/// route") with its pairs named by their minimizer. Empty when no series has a point.
std::string bench_plot_script(const std::vector<BenchSeries>& series);

/// The displacement of a squares mesh (u: 2 per vertex) interpolated bilinearly at `points`,
/// for a mesh made by the squares generator with `n` cells per side on `domain` (x0, x1, y0,
/// y1). Throws InputError when the mesh is not that grid.
Eigen::VectorXd interpolate_squares(const Mesh& mesh, const Eigen::VectorXd& u, int n,
                                    const std::array<double, 4>& domain, const std::vector<Vec2>& points);

/// The displacement of a cubes mesh (u: 3 per vertex) interpolated trilinearly at `points`, for
/// a mesh made by the cubes generator with `n` cells on `box` (x0, x1, y0, y1, z0, z1). Throws
/// InputError when the mesh is not that grid.
Eigen::VectorXd interpolate_cubes(const Mesh3D& mesh, const Eigen::VectorXd& u, const GridSize3& n,
                                  const std::array<double, 6>& box, const std::vector<Vec3>& points);

/// One solve of the refinement study: a uniform level or an adaptive step.
struct RefinementPoint {
  std::string kind;  ///< "uniform" or "adaptive"
  int index = 0;     ///< the level or the step
  int unknowns = 0;
  double seconds = 0.0;  ///< uniform: the level's solve; adaptive: since the adaptive solve started
  double estimate = std::numeric_limits<double>::quiet_NaN();  ///< relative estimate eta / ||u_h||_E
  double norm = std::numeric_limits<double>::quiet_NaN();      ///< ||u_h||_E
  double potential_energy = std::numeric_limits<double>::quiet_NaN();
  /// Phi_h - Phi_ref (NaN without a reference); negative: the reference is too high.
  double energy_difference = std::numeric_limits<double>::quiet_NaN();
  double error = std::numeric_limits<double>::quiet_NaN();        ///< sqrt(Phi_h - Phi_ref) / ||u_h||_E; NaN below the reference
  double effectivity = std::numeric_limits<double>::quiet_NaN();  ///< estimate / error
  std::string status;
  bool converged = false;
};

/// The refinement study: the scene with its own engines on its own mesh refined uniformly
/// `levels` times (2D; in 3D its generator's cell counts doubled), then adaptively to the
/// finest level's estimate (2D only), and the true errors against a reference energy.
struct Refinement {
  std::string engines;  ///< "linear + minimizer" of the scene
  /// How the uniform levels are made: "refine_uniformly" (2D: the previous level's mesh refined)
  /// or "cells_doubled" (3D: the scene's generator with its cell counts times 2^level).
  std::string method = "refine_uniformly";
  int levels = 0;
  std::vector<RefinementPoint> uniform, adaptive;
  std::string stopped, reason;
  std::optional<double> reference_energy;
  std::string reference;  ///< how the reference energy was obtained, or why there is none
  int below_reference = 0;  ///< points whose potential energy is below the reference energy (their error is NaN)
  bool all_converged = true;
};

/// One pair at one mesh size, with its error against the reference.
struct BenchRow {
  PairRun run;
  int n = 0;
  double error = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not defined (not squares, triangles or cubes)
};

/// The reference solution errors are measured against (on squares, triangles or cubes meshes only).
struct BenchReference {
  Pair pair;
  PairRun run;
  std::vector<Vec2> points;    ///< the vertices of its mesh (2D)
  std::vector<Vec3> points3d;  ///< the vertices of its mesh (3D)
  double scale = 0.0;          ///< max|u_ref|, 1 when that is 0
};

/// Where a bad option is reported (InputError's `where`), and how messages name the options.
struct BenchKeys {
  std::string n = "n", ref = "ref", levels = "levels", reference_energy = "reference_energy";
};

/// What is reported as the bench goes.
struct BenchProgress {
  std::function<void(const Pair&, int n)> reference_started;   ///< the reference solve begins
  std::function<void(const PairRun&)> reference_done;
  std::function<void(const std::string& generator)> not_gridded;  ///< errors are not computed
  std::function<void(const PairRun&, int n)> pair_done;
  std::function<void(const RefinementPoint&)> refinement;      ///< a level or an adaptive step is done
};

struct BenchOptions {
  std::vector<int> n;                      ///< empty: bench_default_sizes of the scene's dimension
  std::optional<int> ref;                  ///< none: bench_default_ref of the scene's dimension
  std::optional<int> levels;               ///< uniform levels (>= 1); none: bench_default_levels
  std::optional<double> reference_energy;  ///< the exact potential energy, when known
  std::vector<Pair> pairs;                 ///< empty: available_pairs()
  BenchKeys keys;
  BenchProgress progress;
};

/// A bench checked and ready to run: the options with the defaults of the scene's dimension,
/// the scene at each size and, in 3D, at each refinement level.
struct BenchPlan {
  Scene base;
  BenchOptions options;      ///< n, ref, levels and pairs resolved
  std::vector<Scene> scenes;  ///< at each size of options.n
  std::vector<Scene> levels;  ///< 3D: the scene at each uniform level
  bool gridded = false;       ///< the scene's mesh is squares or triangles (2D) or cubes (3D): errors are measured
};

/// The options that need no scene (sizes, ref, levels >= 1, a finite reference energy):
/// InputError at the option's key.
void check_bench_options(const BenchOptions& options);

/// Checks `options` against `scene` before any work (a mesh read from a file, sizes that do not
/// nest or do not fit in memory, a reference size given for a mesh whose errors are not measured
/// are InputErrors) and resolves the defaults. A loading path is benchmarked at its last step.
BenchPlan plan_bench(const Scene& scene, const BenchOptions& options);

struct BenchResult {
  BenchPlan plan;
  BenchReference reference;  ///< empty when the plan is not gridded
  std::vector<BenchRow> rows;  ///< pair by pair, each pair's sizes in order
  Refinement refinement;
  bool converged = true;     ///< the reference, every pair (but those refused) and every refinement solve converged
};

/// Runs a plan: the reference, every pair at every size, the refinement study. Never prints.
BenchResult run_bench(const BenchPlan& plan);
/// plan_bench, then run_bench.
BenchResult run_bench(const Scene& scene, const BenchOptions& options);

/// bench.json's "path": {steps, t, measured} of a loading path (scene_is_path), whose last
/// step is what bench measures; null for a static scene.
nlohmann::json bench_path_json(const Scene& scene);

/// bench.json (schema hemivem-bench/6) without the names of the plots (write_bench adds them).
nlohmann::json bench_json(const BenchResult& result);

/// What write_bench wrote: bench.json's content as written, why each plot was skipped (empty:
/// drawn), and the plots gnuplot could not draw as warnings (figure_warnings of figures.hpp;
/// bench.json's "warnings"), which the command prints on stderr.
struct BenchFiles {
  nlohmann::json json;
  std::string plot_skipped, refinement_plot_skipped;
  std::vector<std::string> warnings;
};

/// bench.csv, bench.json, bench.png and bench-error.png (each plot in the formats of the
/// scene's output.figure_format) into `dir`, the folder changed at once.
BenchFiles write_bench(const std::filesystem::path& dir, const BenchResult& result);

/// A stage's seconds of a pair: mesh, assembly, linear_solve, condensation, minimize,
/// back_substitution, posing, full_space (a full-space pair's stages) or total.
double bench_stage(const PairRun& run, const std::string& name);

/// The generators on whose meshes errors are measured, in words: "squares or triangles" in 2D,
/// "cubes" in 3D.
std::string gridded_generator(const Scene& scene);
/// Whether bench measures the errors of `scene`: its mesh is made by one of those generators.
bool measures_errors(const Scene& scene);

/// The displacement of a triangle mesh (u: 2 per vertex) interpolated linearly at `points`
/// (on triangles the lowest-order virtual element function is linear: its value there). Throws
/// InputError when an element is not a triangle or a point is outside the mesh.
Eigen::VectorXd interpolate_triangles(const Mesh& mesh, const Eigen::VectorXd& u, const std::vector<Vec2>& points);

}  // namespace hemivem::app
