// From a scene to a solved problem: the engines a scene names, the problem it poses, the solve,
// and what result.json records about the run.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/estimate/error_estimate.hpp>
#include <hemivem/estimate/error_estimate3d.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// The minimizer `name`, with the scene's [solver.parameters] when `name` is the scene's
/// minimizer (other engines get their defaults); an error in a parameter names the scene's
/// line of [solver.parameters].
std::unique_ptr<NonsmoothMinimizer> make_scene_minimizer(const Scene& scene, const std::string& name);

/// The minimizer of a scene: make_scene_minimizer(scene, scene.solver.minimizer), or with
/// solver.search = "global" a GlobalSearch over every built minimizer with that one first and
/// the scene's budget (max_starts, time_budget, seed); `progress` reports its runs.
std::unique_ptr<NonsmoothMinimizer> make_scene_search(const Scene& scene,
                                                      std::function<void(const GlobalSearchProgress&)> progress = {});

/// The engine a minimizer stands for: itself, or the first engine of a global search.
std::string first_engine(const NonsmoothMinimizer& minimizer);

/// result.json's "search": {"kind": "local"}, or for a GlobalSearch its engines and budget.
nlohmann::json search_json(const NonsmoothMinimizer& minimizer);

/// True when two engine names are the same engine (case-insensitive, '_' read as '-').
bool same_engine(const std::string& a, const std::string& b);

/// Whether the linear engine `linear` is a Krylov engine that solves across the processes of a
/// launcher (petsc-gamg, petsc-hypre). InputError where it cannot be made (its module not
/// loaded).
bool runs_across_processes(const std::string& linear);

/// The route solver.linear = "auto" takes (docs/full-space.md, "Chosen by the memory"), where
/// the full-space route can take the scene (the minimizer ssn, a local search; `as_given`
/// false: no reduced problem asked, no mesh of the caller's):
/// - started by an MPI launcher as several processes (launched_processes()), the scene with
///   solver.linear the first of `krylov_engines` (in order of preference; empty: every one
///   built) that runs across processes, and *why (when not null) saying so (docs/cluster.md);
/// - else, for one body on a generated mesh whose condensed route's memory estimate exceeds the
///   memory available (HEMIVEM_MEMORY_LIMIT, or the machine's), the scene with solver.linear
///   the first of them whose estimate fits, and *why saying so.
/// Otherwise the scene is returned as given: where none fits, its build refuses it; under a
/// launcher, the command refuses an engine of one process.
Scene choose_route(const Scene& scene, const std::vector<std::string>& krylov_engines, bool as_given,
                   std::string* why = nullptr);

namespace detail {
template <int dim>
struct PathOutput;
template <int dim>
class FramePieces;
}  // namespace detail

/// One scene solved with the engines it names (scene.solver.linear / .minimizer), a plane
/// (dim = 2, SceneSolve) or a solid (dim = 3, SceneSolve3D) body.
template <int dim>
struct BasicSceneSolve {
  std::unique_ptr<BasicBuiltProblem<dim>> built;
  BasicContactSolution<dim> solution;
  MinimizerOptions options;      ///< the minimizer options in effect
  std::string linear;            ///< the factorization engine's name
  std::string minimizer;         ///< the minimizer's name (the first engine of a global search)
  nlohmann::json search;         ///< search_json
  double mesh_seconds = 0.0;     ///< wall time of building the problem (mesh, materials, boundary parts)
  /// The pieces the mesh was made in (docs/cluster.md): on the full-space route across
  /// processes each process may make only its piece of a generated mesh (scene_piece,
  /// hemivem/scene/scene_pieces.hpp); `built` then holds the piece until the solve and its
  /// error estimate end, when each process makes the whole mesh of the results it holds (the
  /// solve's memory given back by then), but for a process that keeps its piece (piece_cells).
  /// 1 when every process made the whole mesh.
  int mesh_pieces = 1;
  /// With mesh_pieces > 1, the cells of the whole mesh.
  int whole_cells = 0;
  /// A static solve whose mesh was made in pieces, given an output folder
  /// (SceneSolveOptions::out), or a path's whose files are all made from the pieces (its frames
  /// written in pieces): this process's share of the whole mesh's vertices. Its piece of
  /// solution.vtu (a path's last step's) is written by this process, the pieces named by
  /// solution.pvtu (write_results, collective then: every process calls it); none otherwise.
  std::optional<VertexShare> share;
  /// A process that kept its piece of the mesh after a solve on pieces, given an output folder
  /// (SceneSolveOptions::out): one that does not write the results, and every process when the
  /// files the scene writes need no more of the mesh than the pieces (docs/cluster.md): the
  /// whole mesh's number of each cell of `built`. Empty where `built` is the whole mesh.
  std::vector<int> piece_cells;
  /// Where every process kept its piece for the results: what they need of the whole mesh,
  /// gathered from the pieces (whole_of_pieces). Null where `built` is the whole mesh.
  std::shared_ptr<const WholeOfPieces> of_pieces;
  /// The coarser grids a static solve on the full-space route solved first to start from
  /// (solver.grid_sequence, docs/full-space.md), coarsest first, each {n, unknowns, converged,
  /// newton_iterations, krylov_iterations, preconditioner_setups, seconds}; empty when none.
  nlohmann::json grid_sequence = nlohmann::json::array();
  bool holds_results = true;     ///< false on the ranks > 0 of mumps-mpi under mpirun: no results there
  int processes = 1;             ///< the processes the linear engine runs on
  /// What the user should know: the scene's warnings (BuiltProblem::warnings), then the
  /// solve's (conditioning_warning).
  std::vector<std::string> warnings;
  /// How the mesh solved on was made, for reports (RunInfo::mesh): the scene's
  /// (SceneMesh::description) unless the options gave another mesh and its description.
  std::string mesh_description;
  /// The a posteriori estimate of the discretization error (hemivem/estimate/error_estimate.hpp),
  /// made after every solve whose displacement is finite, on the process holding the results;
  /// none otherwise. Its time is the solution's stage "estimate".
  std::optional<ErrorEstimate> estimate;
  /// The last solve of an adaptive sequence (plane bodies) carries the sequence's record
  /// (adapt_json of hemivem/app/adapt.hpp; RunInfo::adapt); null otherwise.
  nlohmann::json adapt;
  /// The last solve of an adaptive sequence whose scene writes the output vtu carries every
  /// step's solution.vtu, step 0 first (RunInfo::adapt_steps: adapt.pvd); null otherwise.
  std::shared_ptr<const std::vector<std::string>> adapt_steps;
  /// The last step of a loading path carries the path (hemivem/app/path.hpp; RunInfo::path);
  /// null otherwise.
  std::shared_ptr<const BasicPathSolution<dim>> path;
  /// A path solved with an output folder (SceneSolveOptions::out) has written its steps there
  /// as they were made, and kept only its last: write_results to that folder finishes the
  /// outputs. Null otherwise.
  std::shared_ptr<detail::PathOutput<dim>> path_output;
  /// A path across processes on pieces of the mesh, given its output folder, writes its VTU
  /// frames in pieces, every process its own (docs/cluster.md): write_results then learns from
  /// every process whether each piece was written. Null otherwise.
  std::shared_ptr<detail::FramePieces<dim>> frame_pieces;
  /// mesh_seconds + the solve's total.
  double total_seconds() const {
    const auto it = solution.timings.find("total");
    return mesh_seconds + (it == solution.timings.end() ? 0.0 : it->second);
  }
};
using SceneSolve = BasicSceneSolve<2>;
using SceneSolve3D = BasicSceneSolve<3>;

/// The estimated condition number above which the displacement's digits are unreliable:
/// cond * eps > 1e-6, i.e. fewer than about six significant digits can be trusted.
inline constexpr double unreliable_condition = 1e-6 / 2.220446049250313e-16;

/// A warning when `condition` (ContactSolution::condition_estimate, the engine-independent
/// estimate of the factorized matrix's 1-norm condition number) is at least
/// unreliable_condition; empty otherwise (also for NaN).
std::string conditioning_warning(double condition);

/// What solve_scene does besides solving the scene as it is written.
struct SceneSolveOptions {
  /// Called between building and solving.
  std::function<void(const BuiltProblem&, const SceneSolve&)> on_built;
  /// Becomes MinimizerOptions::callback.
  std::function<bool(const IterationRecord&)> callback;
  /// When not null, receives the reduced problem.
  ReducedProblem* reduced = nullptr;
  /// Reports the runs of a global search.
  std::function<void(const GlobalSearchProgress&)> progress;
  /// A mesh to solve on instead of the scene's (build_problem(scene, mesh, apply_region_boxes)).
  /// On the full-space route across processes, each process keeps only its piece of a mesh of
  /// one body for the solve and holds the whole as a MeshRecord meanwhile; SceneSolve::built is
  /// the whole mesh's problem again after the solve.
  std::optional<Mesh> mesh;
  bool apply_region_boxes = true;
  /// How that mesh was made, for reports (SceneSolve::mesh_description).
  std::string mesh_description = "a mesh given by the caller";
  /// A full nodal displacement on that mesh (2 per vertex) the minimizer starts from
  /// (ContactSolver::start_from); empty: zero.
  Eigen::VectorXd start;
  /// The output folder a loading path writes its steps' files into as it solves them, in the
  /// folder's transaction (nothing changes there before write_results commits): its memory then
  /// does not grow with its steps. write_results must then be given this folder and no list of
  /// files. Empty: the path keeps its steps (SceneSolve::path) until they are written. Given
  /// across processes on pieces of the mesh, a static solve writes its solution there in pieces
  /// (SceneSolve::share) and a path its VTU frames (SceneSolve::frame_pieces); write_results is
  /// then called by every process, and a process that does not write the results keeps its
  /// piece after the solve (SceneSolve::piece_cells).
  std::filesystem::path out;
  /// Called after each coarser grid of a grid sequence is solved (solver.grid_sequence), with
  /// its record (an entry of SceneSolve::grid_sequence; coarser_grid_text, hemivem/app/report.hpp).
  std::function<void(const nlohmann::json&)> on_coarser_grid;
};

/// InputError (naming the scene's [path] or friction key) when `scene` is a loading path
/// (scene_is_path of hemivem/app/path.hpp), which `what` ("hemivem check", an adaptive solve)
/// cannot solve: it solves static problems.
void refuse_path(const Scene& scene, const std::string& what);

/// Solves `scene` as solve_scene below does, with `options`. A loading path is refused
/// (refuse_path): solve_scene_path solves it.
SceneSolve solve_scene(const Scene& scene, SceneSolveOptions options);

/// Creates the engines (an unknown or unbuilt name is an InputError before any work), builds
/// the problem and solves it, with the condition estimate (ContactSolution::condition_estimate)
/// and the warnings (SceneSolve::warnings). `on_built` (optional) is called between building and solving;
/// `callback` becomes MinimizerOptions::callback; `reduced`, when not null, receives the
/// reduced problem.
SceneSolve solve_scene(const Scene& scene,
                       const std::function<void(const BuiltProblem&, const SceneSolve&)>& on_built = {},
                       std::function<bool(const IterationRecord&)> callback = {}, ReducedProblem* reduced = nullptr,
                       std::function<void(const GlobalSearchProgress&)> progress = {});

/// The files `hemivem solve` writes for a scene, in the order of all_outputs of its dimension:
/// those of its [output] write that its dimension writes, as file names of write_outputs (a
/// solid's contact-surface.vtu with vtu; a plane's u_nu.png, error.png and mesh.png, a solid's
/// pressure.png), and scene.toml always; without contact no contact.csv, history.csv, u_nu.png,
/// contact-surface.vtu or pressure.png; an adaptive solve's files (a plane's mesh.poly2d always,
/// mesh.png, adapt.png, and adapt.pvd with vtu); a path's files (path_files).
std::vector<std::string> wanted_files(const Scene& scene, bool has_contact);

/// Writes what `hemivem solve --out dir` writes for a solve of `scene`, a plane (SceneSolve)
/// or a solid (SceneSolve3D): the files of wanted_files (or `files`, names of all_outputs(dim),
/// when not null) through write_outputs, with run_info's record; a solid's contact-surface.vtu
/// and pressure.png show its contact faces (contact_faces). Checks the folder first
/// (check_output_folder). Never prints. A process that does not hold the results returns an
/// empty report, but for a solve written in pieces (BasicSceneSolve::share), where every process
/// calls it and writes its piece of solution.pvtu, and a path whose frames were written in
/// pieces (BasicSceneSolve::frame_pieces), where every process calls it to learn whether each
/// piece was (docs/reference/outputs.md).
template <int dim>
OutputReport write_results(const std::filesystem::path& dir, const Scene& scene, const BasicSceneSolve<dim>& solved,
                           const std::vector<std::string>* files = nullptr);

/// What `hemivem solve` records in result.json about a solve of `scene` (the resolved scene):
/// engines, search (search_json), options (a plane's plane_model among them), mesh time,
/// unknowns, warnings, the contact parts, and what the plots draw. RunInfo::files is left to
/// write_outputs' caller.
template <int dim>
RunInfo run_info(const Scene& scene, const BasicSceneSolve<dim>& solved);

}  // namespace hemivem::app
