// hemivem bench: every built (linear, minimizer) pair of engines on one scene, timed by stage
// against its error for several mesh sizes. Columns, JSON fields and exit codes:
// docs/reference/check-bench.md.
#pragma once

#include <array>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem::cli {

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

/// The defaults of a scene of dimension 2 or 3: the mesh sizes (16, 32, 64, 128 in 2D; 4, 8, 16
/// in 3D), the reference's size (256; 32) and the uniform levels of the refinement study (3; 2).
std::vector<int> bench_default_sizes(int dimension);
int bench_default_ref(int dimension);
int bench_default_levels(int dimension);

/// hemivem bench [SCENE]: wall time by stage and error against a reference solution for
/// every pair and mesh size; writes bench.csv, bench.json and bench.png into options.out.
/// Exit: kSuccess, or kNotConverged when the reference or a pair did not converge (files are
/// still written).
int run_bench(const BenchOptions& options, std::ostream& out, std::ostream& err);

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
/// groups the series by linear engine, a heading per engine with its pairs named by their
/// minimizer. Empty when no series has a point.
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

}  // namespace hemivem::cli
