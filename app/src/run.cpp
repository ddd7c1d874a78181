// A scene run, whatever it holds (run.hpp).
#include <hemivem/app/run.hpp>

#include <hemivem/app/outputs.hpp>
#include <hemivem/app/report.hpp>
#include <hemivem/error.hpp>
#include <hemivem/support/blas_threads.hpp>

#include <type_traits>

namespace hemivem::app {

std::string to_string(RunKind kind) {
  switch (kind) {
    case RunKind::static_solve: return "static";
    case RunKind::path: return "path";
    case RunKind::adaptive: return "adaptive";
  }
  return "static";
}

RunKind run_kind(const Scene& scene) {
  const bool path = scene_is_path(scene);
  if (path && scene.adapt) throw InputError("a loading path is solved on one mesh; remove [adapt] or [path]", scene.where("path"));
  return path ? RunKind::path : scene.adapt ? RunKind::adaptive : RunKind::static_solve;
}

SceneRun::~SceneRun() = default;

const PathSolution* SceneRun::path() const noexcept { return plane_ ? plane_->path.get() : nullptr; }

const BasicPathSolution<3>* SceneRun::solid_path() const noexcept { return solid_ ? solid_->path.get() : nullptr; }

bool SceneRun::holds_results() const noexcept {
  return ran() && visit([](const auto& s) { return s.holds_results; });
}

bool SceneRun::has_contact() const noexcept {
  return ran() && visit([](const auto& s) { return s.built && s.built->has_contact; });
}

MinimizerStatus SceneRun::status() const noexcept {
  return ran() ? visit([](const auto& s) { return s.solution.status; }) : MinimizerStatus::failed;
}

bool SceneRun::converged() const noexcept { return status() == MinimizerStatus::converged; }

const std::string& SceneRun::linear() const noexcept {
  return visit([](const auto& s) -> const std::string& { return s.linear; });
}

const std::string& SceneRun::minimizer() const noexcept {
  return visit([](const auto& s) -> const std::string& { return s.minimizer; });
}

RunInfo SceneRun::info() const {
  return visit([this](const auto& s) { return run_info(scene_, s); });
}

nlohmann::json SceneRun::result_json(const std::vector<std::string>& files) const {
  RunInfo i = info();
  i.files = files;
  return visit([&i](const auto& s) { return app::result_json(s.built->mesh, s.solution, i); });
}

std::vector<std::string> SceneRun::warnings() const { return info().warnings; }

std::vector<std::string> SceneRun::wanted_files() const { return app::wanted_files(scene_, has_contact()); }

OutputReport SceneRun::write(const std::filesystem::path& dir, const std::vector<std::string>* files) const {
  return visit([&](const auto& s) { return write_results(dir, scene_, s, files); });
}

std::string SceneRun::brief() const {
  return visit([](const auto& s) { return brief_report(s); });
}

std::string SceneRun::report(const RunInfo& info) const {
  std::string text = visit([&](const auto& s) {
    return full_report(s, info) + (s.path ? path_report(*s.path) : std::string());
  });
  if (adaptive_) text += adapt_report(*adaptive_);
  if (solid_adaptive_) text += adapt_report(*solid_adaptive_);
  return text;
}

namespace {

int cells(const Mesh& mesh) { return mesh.num_elements(); }
int cells(const Mesh3D& mesh) { return mesh.num_cells(); }

/// The on_built callback of a solve of either dimension that tells `f` a BuiltSummary.
template <class Built, class Solved>
std::function<void(const Built&, const Solved&)> announce(const std::function<void(const BuiltSummary&)>& f) {
  if (!f) return {};
  return [f](const Built& built, const Solved& s) {
    f({std::is_same_v<Built, BuiltProblem3D> ? 3 : 2, built.mesh.num_vertices(),
       s.mesh_pieces > 1 ? s.whole_cells : cells(built.mesh), s.linear, s.minimizer, s.holds_results});
  };
}

/// The path step callback of a path of dimension dim that tells `f` the step's progress.
template <int dim>
std::function<void(const BasicPathStep<dim>&)> announce_steps(const Scene& scene,
                                                              const std::function<void(const PathProgress&)>& f) {
  if (!f) return {};
  const int steps = scene.path ? static_cast<int>(scene.path->factors().size()) : 1;
  return [f, steps](const BasicPathStep<dim>& s) { f(path_progress(s, steps)); };
}

/// The options of a solid scene's solve.
SceneSolve3DOptions solid_options(const Scene& scene, RunOptions& o) {
  if (o.mesh && !std::holds_alternative<Mesh3D>(*o.mesh))
    throw InputError("a three-dimensional scene is solved on a three-dimensional mesh (Mesh3D); the mesh given is "
                     "two-dimensional",
                     o.mesh_key);
  SceneSolve3DOptions s;
  if (o.mesh) s.mesh = std::get<Mesh3D>(std::move(*o.mesh));
  s.mesh_description = o.mesh_description;
  s.on_built = announce<BuiltProblem3D, SceneSolve3D>(o.on_built);
  s.callback = std::move(o.callback);
  s.reduced = o.reduced;
  s.progress = std::move(o.progress);
  s.on_path_step = announce_steps<3>(scene, o.on_path_step);
  s.out = o.out;
  s.on_coarser_grid = o.on_coarser_grid;
  return s;
}

SceneSolveOptions plane_options(RunOptions& o) {
  SceneSolveOptions s;
  s.on_built = announce<BuiltProblem, SceneSolve>(o.on_built);
  s.callback = std::move(o.callback);
  s.reduced = o.reduced;
  s.progress = std::move(o.progress);
  if (o.mesh && !std::holds_alternative<Mesh>(*o.mesh))
    throw InputError("a two-dimensional scene is solved on a plane mesh (Mesh); the mesh given is three-dimensional",
                     o.mesh_key);
  if (o.mesh) s.mesh = std::get<Mesh>(std::move(*o.mesh));
  s.apply_region_boxes = o.apply_region_boxes;
  s.mesh_description = o.mesh_description;
  s.out = o.out;
  s.on_coarser_grid = o.on_coarser_grid;
  return s;
}

}  // namespace

SceneRun run_scene(const Scene& given, RunOptions options) {
  // OpenBLAS and OpenMP on one thread unless the environment asks otherwise: their idle threads
  // spin on the cores another process needs (docs/performance.md, "Threads")
  const SingleThreadedRun one_thread;
  std::string route;  // why "auto" took the full-space route, when it did
  const Scene scene = choose_route(given, options.krylov_engines, (options.reduced != nullptr && !options.reduced_optional) || options.mesh.has_value(), &route);
  const auto noted = [&route](auto& solved) {
    if (!route.empty()) solved.warnings.insert(solved.warnings.begin(), route);
  };
  SceneRun run;
  run.scene_ = scene;
  run.kind_ = run_kind(scene);
  if (options.reduced && run.kind_ != RunKind::static_solve)
    throw InputError(run.kind_ == RunKind::path
                         ? "a loading path has a reduced problem per step; export it from a static solve"
                         : "an adaptive solve has no one reduced problem; export it from a solve of one mesh",
                     options.reduced_key);
  if (scene.dimension() == 3) {
    SceneSolve3DOptions o = solid_options(scene, options);
    if (run.kind_ == RunKind::adaptive) {
      run.solid_adaptive_ =
          std::make_unique<AdaptiveSolve3D>(solve_adaptively(scene, *scene.adapt, std::move(o), options.on_adapt_step));
      run.solid_ = std::make_unique<SceneSolve3D>(std::move(run.solid_adaptive_->last));
    } else {
      run.solid_ = std::make_unique<SceneSolve3D>(solve_scene_3d(scene, std::move(o)));
    }
    noted(*run.solid_);
    return run;
  }
  SceneSolveOptions o = plane_options(options);
  switch (run.kind_) {
    case RunKind::path:
      run.plane_ = std::make_unique<SceneSolve>(solve_scene_path(scene, std::move(o), announce_steps<2>(scene, options.on_path_step)));
      break;
    case RunKind::adaptive: {
      run.adaptive_ = std::make_unique<AdaptiveSolve>(solve_adaptively(scene, *scene.adapt, std::move(o), options.on_adapt_step));
      run.plane_ = std::make_unique<SceneSolve>(std::move(run.adaptive_->last));
      break;
    }
    case RunKind::static_solve:
      run.plane_ = std::make_unique<SceneSolve>(solve_scene(scene, std::move(o)));
      break;
  }
  noted(*run.plane_);
  return run;
}

}  // namespace hemivem::app
