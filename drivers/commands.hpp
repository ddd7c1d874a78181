// The subcommands of the hemivem tool. Each returns the process exit code (common.hpp) and
// lets InputError / NumericalError escape for main() to report.
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/contact_solver.hpp>
#include <hemivem/scene.hpp>

namespace hemivem::cli {

/// One scene solved: what run_solve and run_study share.
struct SceneSolve {
  std::unique_ptr<BuiltProblem> built;
  ContactSolution solution;
  MinimizerOptions options;     ///< the minimizer options in effect (tolerance, iterations)
  std::string minimizer;        ///< the minimizer's name
  double mesh_seconds = 0.0;    ///< wall time of build_problem
};

/// Hooks of solve_scene: `on_built` runs after the mesh is made and before the solve (with the
/// engine names), `on_iteration` is the minimizer's callback. Both optional.
struct SceneSolveHooks {
  std::function<void(const BuiltProblem&, const std::string& linear, const std::string& minimizer)> on_built;
  std::function<bool(const IterationRecord&)> on_iteration;
};

/// The engines named by the scene (unknown names are InputError before any work), then
/// build_problem and solve_contact. `reduced` as in solve_contact.
SceneSolve solve_scene(const Scene& scene, const SceneSolveHooks& hooks = {}, ReducedProblem* reduced = nullptr);

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
};

/// hemivem solve [SCENE.toml]: scene -> mesh -> assembly -> condensation -> minimizer ->
/// back-substitution -> the output folder. Exit 0 when converged, kNotConverged otherwise
/// (outputs are still written and marked).
int run_solve(const SolveOptions& options, std::ostream& out, std::ostream& err);

struct MinimizeOptions {
  std::string folder;                   ///< a reduced problem written by --export-reduced
  std::string minimizer = "ssn";
  std::string law;                      ///< replaces law.txt when given
  double tolerance = 1e-10;
  bool json = false;
  int verbosity = 1;
};

/// hemivem minimize DIR: the same reduced problem, from files, for any minimizer.
int run_minimize(const MinimizeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
