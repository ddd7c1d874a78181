// The one entry point for a scene, whatever it holds: a plane or a solid body, one static
// solve, a loading path or an adaptive sequence. The command (`hemivem solve`), the Python
// module (`hemivem.solve`) and a host program call run_scene and read one SceneRun, which
// writes and reports itself; none of them chooses between the solvers.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/adapt.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// What a scene asks for.
enum class RunKind {
  static_solve,  ///< one static solve
  path,          ///< a loading path (scene_is_path: a [path] table, or a friction bound from the normal contact)
  adaptive,      ///< an adaptive sequence of meshes ([adapt])
};
/// "static", "path", "adaptive".
std::string to_string(RunKind kind);

/// The kind of run `scene` asks for. InputError (naming the scene's [path] key) when it asks
/// for a path and an adaptive sequence at once.
RunKind run_kind(const Scene& scene);

/// What a run says about the problem it built, before it solves it (for progress lines).
struct BuiltSummary {
  int dimension = 2;
  int vertices = 0;
  int cells = 0;              ///< elements of a plane mesh, cells of a solid one
  std::string linear;         ///< the factorization engine
  std::string minimizer;      ///< the minimizer (the first engine of a global search)
  bool holds_results = true;  ///< false on the ranks > 0 of mumps-mpi under mpirun
};

/// What run_scene does besides solving the scene as it is written.
struct RunOptions {
  /// Called between building and solving (every step of an adaptive sequence calls it).
  std::function<void(const BuiltSummary&)> on_built;
  /// Becomes MinimizerOptions::callback (false ends the minimization).
  std::function<bool(const IterationRecord&)> callback;
  /// Receives the reduced problem of a static solve with contact; InputError (naming
  /// `reduced_key`) for a path or an adaptive sequence, which have no one reduced problem.
  ReducedProblem* reduced = nullptr;
  std::string reduced_key = "reduced";
  /// The reduced problem is wanted where the route has one only (Python's default): "auto" may
  /// still take the full-space route (choose_route), which leaves `reduced` untouched.
  bool reduced_optional = false;
  /// Reports the runs of a global search.
  std::function<void(const GlobalSearchProgress&)> progress;
  /// Called after each step of a path, plane or solid (the step, the number of steps and the
  /// line `hemivem solve` prints), and of an adaptive sequence.
  std::function<void(const PathProgress&)> on_path_step;
  std::function<void(const AdaptStep&)> on_adapt_step;
  /// Called after each coarser grid of a grid sequence (SceneSolveOptions::on_coarser_grid).
  std::function<void(const nlohmann::json&)> on_coarser_grid;
  /// A mesh of one's own to solve on instead of the scene's (SceneSolveOptions::mesh,
  /// SceneSolve3DOptions::mesh): a Mesh for a plane scene, a Mesh3D for a solid one; the other
  /// is an InputError naming `mesh_key`.
  std::optional<std::variant<Mesh, Mesh3D>> mesh;
  std::string mesh_key = "mesh";
  bool apply_region_boxes = true;
  std::string mesh_description = "a mesh given by the caller";
  /// The output folder the run is written to (SceneSolveOptions::out): a loading path writes
  /// each step's files there as it solves it, in the folder's transaction, and keeps only its
  /// last step, so that its memory does not grow with its steps; SceneRun::write must then be
  /// given this folder and no list of files. Empty: a path keeps its steps until written.
  /// Across processes on pieces of the mesh, a static solve given it writes its solution in
  /// pieces (solution.pvtu), a path its VTU frames (solution-NNNN.pvtu), and every process
  /// calls SceneRun::write.
  std::filesystem::path out;
  /// The Krylov engines solver.linear = "auto" may choose when the condensed route does not fit
  /// in memory (choose_route), in order of preference; empty: every one built.
  std::vector<std::string> krylov_engines;
};

/// A scene solved: the solve of a plane or a solid body, the steps of its path or of its
/// adaptive sequence, and everything the command writes and prints about it. The dimension
/// is a value (dimension()); plane() and solid() give the solve of each, one of them null.
class SceneRun {
 public:
  SceneRun() = default;
  SceneRun(SceneRun&&) noexcept = default;
  SceneRun& operator=(SceneRun&&) noexcept = default;
  ~SceneRun();

  const Scene& scene() const noexcept { return scene_; }
  int dimension() const noexcept { return solid_ ? 3 : 2; }
  RunKind kind() const noexcept { return kind_; }

  /// The plane solve (the last step of a path or an adaptive sequence), or null in 3D.
  const SceneSolve* plane() const noexcept { return plane_.get(); }
  SceneSolve* plane() noexcept { return plane_.get(); }
  /// The solid solve, or null in 2D.
  const SceneSolve3D* solid() const noexcept { return solid_.get(); }
  /// The solve of dimension dim (plane() or solid(), for code written once for both), or null.
  template <int dim>
  const BasicSceneSolve<dim>* solve() const noexcept {
    if constexpr (dim == 2) return plane_.get();
    else return solid_.get();
  }
  /// The adaptive sequence of a plane body (its last solve is plane()), or null.
  const AdaptiveSolve* adaptive() const noexcept { return adaptive_.get(); }
  /// The adaptive sequence of a solid body (its last solve is solid()), or null.
  const AdaptiveSolve3D* solid_adaptive() const noexcept { return solid_adaptive_.get(); }
  /// The loading path's steps, or null.
  const PathSolution* path() const noexcept;
  /// The loading path's steps of a solid, or null.
  const BasicPathSolution<3>* solid_path() const noexcept;

  /// False on the processes of mumps-mpi that hold no results (they report nothing).
  bool holds_results() const noexcept;
  bool has_contact() const noexcept;
  bool converged() const noexcept;
  MinimizerStatus status() const noexcept;
  /// The factorization engine and the minimizer (the first engine of a global search).
  const std::string& linear() const noexcept;
  const std::string& minimizer() const noexcept;

  /// What result.json records about the run (run_info).
  RunInfo info() const;
  /// result.json of the run (files: the names `write` wrote, when given).
  nlohmann::json result_json(const std::vector<std::string>& files = {}) const;
  /// The warnings of info(), in order.
  std::vector<std::string> warnings() const;
  /// The files `hemivem solve` writes for this run (wanted_files).
  std::vector<std::string> wanted_files() const;
  /// Writes what `hemivem solve --out dir` writes (write_results): the files
  /// of wanted_files(), or `files` when not null. Never prints. Across processes the first
  /// writes and the others return an empty report; a static solve or a path on pieces given
  /// its output folder (RunOptions::out) writes its solution or its frames in pieces, and every
  /// process calls it.
  OutputReport write(const std::filesystem::path& dir, const std::vector<std::string>* files = nullptr) const;
  /// One line: status, certificate, iterations, energy and total time.
  std::string brief() const;
  /// The lines of `hemivem solve`'s report after its first line (the report of the solve, then
  /// the adaptive sequence's or the path's lines); `info` as info() returned it (with the
  /// files written).
  std::string report(const RunInfo& info) const;
  std::string report() const { return report(info()); }

 private:
  friend SceneRun run_scene(const Scene& scene, RunOptions options);
  bool ran() const noexcept { return plane_ || solid_; }
  /// f of the solve of the run's dimension (f's results have one type).
  template <class F>
  decltype(auto) visit(F&& f) const {
    if (solid_) return f(*solid_);
    return f(*plane_);
  }
  Scene scene_;
  RunKind kind_ = RunKind::static_solve;
  std::unique_ptr<SceneSolve> plane_;
  std::unique_ptr<SceneSolve3D> solid_;
  std::unique_ptr<AdaptiveSolve> adaptive_;
  std::unique_ptr<AdaptiveSolve3D> solid_adaptive_;
};

/// Solves `scene`, whatever it holds (run_kind): a plane static solve (solve_scene), a loading
/// path (solve_scene_path), an adaptive sequence (solve_adaptively, in either dimension) or a
/// solid, static or along a path (solve_scene_3d).
/// Errors as those functions', and InputError for what a kind cannot do (a plane mesh given
/// for a solid scene, a reduced problem asked of a path).
SceneRun run_scene(const Scene& scene, RunOptions options = {});

}  // namespace hemivem::app
