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

#include <hemivem/contact_solver.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/scene.hpp>

#include "outputs.hpp"

namespace hemivem::cli {

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
};

/// The scene of a command line: the file (empty: the embedded Example 4.1) with the flags
/// applied in order --mesh, --n, --linear, --minimizer, --tol, then every --set. Unknown keys
/// and bad values are InputErrors (nothing is built).
Scene load_scene(const SolveOptions& options);

/// The minimizer `name`, with the scene's [solver.parameters] when `name` is the scene's
/// minimizer (other engines get their defaults); an error in a parameter names the scene's
/// line of [solver.parameters].
std::unique_ptr<NonsmoothMinimizer> make_scene_minimizer(const Scene& scene, const std::string& name);

/// The minimizer of a scene: make_scene_minimizer(scene, scene.solver.minimizer), or with
/// solver.search = "global" a GlobalSearch over every built minimizer with that one first and
/// the scene's budget (max_starts, time_budget, seed); `progress` reports its runs.
std::unique_ptr<NonsmoothMinimizer> make_scene_search(const Scene& scene,
                                                      std::function<void(const GlobalSearchProgress&)> progress = {});

/// result.json's "search": {"kind": "local"}, or for a GlobalSearch its engines and budget.
nlohmann::json search_json(const NonsmoothMinimizer& minimizer);

/// True when two engine names are the same engine (case-insensitive, '_' read as '-').
bool same_engine(const std::string& a, const std::string& b);

/// One scene solved with the engines it names (scene.solver.linear / .minimizer).
struct SceneSolve {
  std::unique_ptr<BuiltProblem> built;
  ContactSolution solution;
  MinimizerOptions options;      ///< the minimizer options in effect
  std::string linear;            ///< the factorization engine's name
  std::string minimizer;         ///< the minimizer's name (the first engine of a global search)
  nlohmann::json search;         ///< search_json
  double mesh_seconds = 0.0;     ///< wall time of build_problem (mesh, materials, boundary parts)
  bool holds_results = true;     ///< false on the ranks > 0 of mumps-mpi under mpirun: no results there
  int processes = 1;             ///< the processes the linear engine runs on
  double total_seconds() const;  ///< mesh_seconds + the solve's total
};

/// Creates the engines (an unknown or unbuilt name is an InputError before any work), builds
/// the problem and solves it. `on_built` (optional) is called between building and solving;
/// `callback` becomes MinimizerOptions::callback; `reduced`, when not null, receives the
/// reduced problem.
SceneSolve solve_scene(const Scene& scene,
                       const std::function<void(const BuiltProblem&, const SceneSolve&)>& on_built = {},
                       std::function<bool(const IterationRecord&)> callback = {}, ReducedProblem* reduced = nullptr,
                       std::function<void(const GlobalSearchProgress&)> progress = {});

/// The files `hemivem solve` writes for a scene: its [output] write as file names of
/// write_outputs, and scene.toml always; without contact no contact.csv, history.csv or u_nu.png.
std::vector<std::string> wanted_files(const Scene& scene, bool has_contact);

/// What `hemivem solve` records in result.json about a solve of `scene` (the resolved scene):
/// engines, search (search_json), options, mesh time, unknowns, warnings, and what the plots
/// draw. RunInfo::files is left to write_outputs' caller.
RunInfo run_info(const Scene& scene, const SceneSolve& solved);

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
