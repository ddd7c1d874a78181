// The subcommands of the hemivem tool. Each returns the process exit code (common.hpp) and
// lets InputError / NumericalError escape for main() to report.
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/adapt.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::cli {

using namespace hemivem::app;

struct SolveOptions {
  std::string scene;                    ///< scene file; empty: the embedded Example 4.1
  std::optional<std::string> mesh;      ///< generator name or a .poly2d / .msh path
  std::optional<int> n;
  std::optional<std::string> linear;
  std::optional<std::string> minimizer;
  std::optional<double> tolerance;
  std::vector<std::string> set;         ///< --set key=value, in order
  std::string out = "out/solve";
  std::string export_reduced;           ///< folder for the reduced problem, empty: none
  bool json = false;                    ///< result.json on stdout instead of the summary
  int verbosity = 1;                    ///< 0 quiet, 1 summary, 2 summary and iterations
  bool global = false;                  ///< --global: solver.search = "global"
  bool adapt = false;                   ///< --adapt: refine adaptively ([adapt] with its defaults unless the scene has one)
  std::optional<std::string> figures;   ///< --figures png,pdf: output.figure_format, comma-separated
};

/// The scene of a command line: the file (empty: the embedded Example 4.1) with the flags
/// applied in order --mesh, --n, --linear, --minimizer, --tol, --figures, then every --set. Unknown keys
/// and bad values are InputErrors (nothing is built).
Scene load_scene(const SolveOptions& options);

/// The scene of check and bench: the file (empty: Example 4.1) with --n, --tol and the --set
/// overrides, read as hemivem solve reads it.
Scene load_pairs_scene(const std::string& scene, std::optional<int> n, std::optional<double> tolerance,
                       const std::vector<std::string>& set);

/// hemivem solve [SCENE.toml]: scene -> mesh -> assembly -> condensation -> minimizer ->
/// back-substitution -> the output folder. Exit 0 when converged, kNotConverged otherwise
/// (outputs are still written and marked). Under an MPI launcher with several processes only
/// mumps-mpi is accepted (InputError otherwise); every process solves along, the process
/// holding the results prints and writes, the others return the same exit code silently
/// (docs/cluster.md).
int run_solve(const SolveOptions& options, std::ostream& out, std::ostream& err);

struct MinimizeOptions {
  std::string folder;                   ///< a reduced problem written by --export-reduced
  std::string minimizer = "ssn";
  std::string law;                      ///< replaces law.txt when given
  double tolerance = 1e-10;
  bool json = false;
  int verbosity = 1;
  bool global = false;                  ///< --global: a GlobalSearch with `minimizer` first
  GlobalSearchOptions search;           ///< its budget (--max-starts, --time-budget, --seed)
  std::vector<std::string> engines;     ///< --engines: the search's engines besides `minimizer` (empty: every built one)
};

/// hemivem minimize DIR: the same reduced problem, from files, for any minimizer.
int run_minimize(const MinimizeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
