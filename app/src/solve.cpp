#include <hemivem/support/blas_threads.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/launcher.hpp>

#include <hemivem/scene/grid_sequence.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/app/path.hpp>

#include "output_run.hpp"
#include "scene_setup.hpp"

#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/process_group.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hemivem::app {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

bool runs_across_processes(const std::string& linear) {
  return is_krylov_solver(linear) && make_krylov_solver(linear)->runs_across_processes();
}

bool same_engine(const std::string& a, const std::string& b) { return normalized_engine_name(a) == normalized_engine_name(b); }

/// An engine named by a key the scene file gave (line > 0): its error names the file and line.
template <class Make>
auto named_engine(const Scene& scene, const std::string& key, Make make) {
  try {
    return make();
  } catch (const InputError& e) {
    const auto it = scene.lines.find(key);
    if (it == scene.lines.end() || it->second <= 0) throw;
    throw InputError(key + ": " + e.detail(), scene.where(key));
  }
}

std::unique_ptr<NonsmoothMinimizer> make_scene_minimizer(const Scene& scene, const std::string& name) {
  if (scene.solver.parameters.empty() || !same_engine(name, scene.solver.minimizer))
    return named_engine(scene, "solver.minimizer", [&] { return make_minimizer(name); });
  try {
    return make_minimizer(name, scene.solver.parameters);
  } catch (const InputError& e) {
    throw InputError("solver.parameters: minimizer '" + e.where() + "': " + e.detail(), scene.where("solver.parameters"));
  }
}

std::unique_ptr<NonsmoothMinimizer> make_scene_search(const Scene& scene,
                                                      std::function<void(const GlobalSearchProgress&)> progress) {
  auto first = make_scene_minimizer(scene, scene.solver.minimizer);
  if (scene.solver.search != "global") return first;
  GlobalSearchOptions go;
  go.max_starts = scene.solver.max_starts;
  go.time_budget = scene.solver.time_budget;
  go.seed = scene.solver.seed;
  go.progress = std::move(progress);
  try {
    return make_global_search(std::move(first), std::move(go), scene.solver.search_engines);
  } catch (const InputError& e) {
    throw InputError("solver.search_engines: " + e.detail(), scene.where("solver.search_engines"));
  }
}

std::string first_engine(const NonsmoothMinimizer& m) {
  const auto* g = dynamic_cast<const GlobalSearch*>(&m);
  return g ? g->engine_names().front() : m.name();
}

nlohmann::json search_json(const NonsmoothMinimizer& minimizer) {
  const auto* search = dynamic_cast<const GlobalSearch*>(&minimizer);
  if (!search) return {{"kind", "local"}};
  const GlobalSearchOptions& go = search->options();
  return {{"kind", "global"},
          {"engines", search->engine_names()},
          {"max_starts", go.max_starts},
          {"time_budget", go.time_budget},
          {"seed", go.seed},
          {"random_starts", go.random_starts},
          {"agree", go.agree}};
}

SceneSolve solve_scene(const Scene& scene, const std::function<void(const BuiltProblem&, const SceneSolve&)>& on_built,
                       std::function<bool(const IterationRecord&)> callback, ReducedProblem* reduced,
                       std::function<void(const GlobalSearchProgress&)> progress) {
  SceneSolveOptions o;
  o.on_built = on_built;
  o.callback = std::move(callback);
  o.reduced = reduced;
  o.progress = std::move(progress);
  return solve_scene(scene, std::move(o));
}

void refuse_path(const Scene& scene, const std::string& what) {
  if (!scene_is_path(scene)) return;
  const bool table = scene.path.has_value();
  throw InputError(what + " solves one static problem; this scene is a loading path (" +
                       (table ? std::string("[path]") : std::string("friction whose bound depends on the normal contact")) +
                       ", docs/paths.md): `hemivem solve` and hemivem.solve_path solve it step by step",
                   scene.where(table ? "path" : "contact.friction"));
}

Scene choose_route(const Scene& scene, const std::vector<std::string>& krylov_engines, bool as_given,
                   std::string* why) {
  if (!same_engine(scene.solver.linear, "auto") || as_given || scene.solver.search != "local" ||
      !same_engine(scene.solver.minimizer, "ssn"))
    return scene;
  const std::vector<std::string> engines = krylov_engines.empty() ? available_krylov_solvers() : krylov_engines;
  if (const int processes = launched_processes().size; processes > 1) {
    // started by an MPI launcher: the route that runs across the processes
    for (const std::string& engine : engines) {
      try {
        if (!runs_across_processes(engine)) continue;
      } catch (const InputError&) {  // its module not loaded: not an engine "auto" can take
        continue;
      }
      Scene chosen = scene;
      chosen.solver.linear = engine;
      if (why)
        *why = "solver.linear = \"auto\": started as " + std::to_string(processes) +
               " processes by an MPI launcher; solved across them on the full-space route with " + engine +
               " (docs/cluster.md)";
      return chosen;
    }
    return scene;
  }
  if (!scene.bodies.empty()) return scene;
  const std::optional<MemoryEstimate> condensed = generated_mesh_memory(scene);
  const double available = available_memory();
  if (!condensed || condensed->solve_bytes <= available) return scene;
  for (const std::string& engine : engines) {
    const double full =
        full_space_memory(*condensed, full_space_cost(scene.dimension(), scene.mesh.generator, engine)).solve_bytes;
    if (full > available) continue;
    Scene chosen = scene;
    chosen.solver.linear = engine;
    if (why)
      *why = "solver.linear = \"auto\": the condensed route would need an estimated " +
             format_bytes(condensed->solve_bytes) + ", more than the " + format_bytes(available) +
             " available; solved on the full-space route with " + engine + " (an estimated " + format_bytes(full) +
             ", nothing factorized; docs/full-space.md)";
    return chosen;
  }
  return scene;
}

namespace detail {

SceneEngines make_scene_engines(const Scene& scene, std::function<void(const GlobalSearchProgress&)> progress,
                                std::function<bool(const IterationRecord&)> callback) {
  SceneEngines e;
  if (is_krylov_solver(scene.solver.linear)) {
    // a Krylov engine: the full-space route (docs/full-space.md)
    e.krylov = named_engine(scene, "solver.linear", [&] { return make_krylov_solver(scene.solver.linear); });
    e.linear = e.krylov->name();
    if (e.krylov->runs_across_processes()) {  // under mpirun each process solves its share
      const ProcessWorld world = krylov_world();
      e.holds_results = world.rank == 0;
      e.processes = world.size;
      // each process its share of the problem, besides its libraries and what every process holds
      e.memory_of_processes = std::make_unique<MemoryOfProcesses>(
          world.size, false, full_space_cost(scene.dimension(), scene.mesh.generator, e.linear).base_bytes);
    }
  } else {
    FactorizationOptions fo;
    fo.engine = same_engine(scene.solver.linear, "auto") ? fastest_factorization() : scene.solver.linear;
    e.factorization = named_engine(scene, "solver.linear", [&] { return make_factorization(fo); });
    e.linear = e.factorization->name();
    e.holds_results = processes_of(*e.factorization).holds_results();
    e.processes = processes_of(*e.factorization).num_processes();
    // every process builds and assembles the whole problem (mumps-mpi)
    if (e.processes > 1) e.memory_of_processes = std::make_unique<MemoryOfProcesses>(e.processes, true, 0.0);
  }
  e.grid_levels = grid_sequence_levels(scene, e.krylov != nullptr, scene_is_path(scene));
  e.minimizer = make_scene_search(scene, std::move(progress));
  e.minimizer_name = first_engine(*e.minimizer);
  e.search = search_json(*e.minimizer);
  e.options.tolerance = scene.solver.tolerance;
  e.options.max_iterations = scene.solver.max_iterations;
  e.options.callback = std::move(callback);
  return e;
}

void require_memory_of(const Scene& s, const std::string& where) {
  if (s.dimension() == 3) {
    const GridSize3 cells = s.mesh.cells3();
    require_memory(estimate_memory_3d(s.mesh.generator, cells.nx, cells.ny, cells.nz).solve_bytes,
                   s.mesh.generator + " n = " + cells.text(), where);
  } else {
    const GridSize cells = s.mesh.cells();
    require_memory(estimate_memory(s.mesh.generator, cells.nx, cells.ny).solve_bytes,
                   s.mesh.generator + " n = " + cells.text(), where);
  }
}

SceneEngines prepare_scene_solve(const Scene& scene, SceneSolveOptions& o, SceneSolve& s) {
  // Engines first: a name that was not built is an input error before any work.
  SceneEngines e = make_scene_engines(scene, std::move(o.progress), std::move(o.callback));
  e.on_coarser_grid = o.on_coarser_grid;
  record_engines(e, s);

  const auto t = Clock::now();
  if (o.mesh)
    build_given_problem<2>(scene, e, s, std::move(*o.mesh), o.apply_region_boxes);
  else
    build_scene_problem<2>(scene, e, s, o.out);
  s.mesh_description = o.mesh ? o.mesh_description : scene_mesh_description(scene);
  s.mesh_seconds = since(t);
  return e;
}

}  // namespace detail

SceneSolve solve_scene(const Scene& scene, SceneSolveOptions o) {
  const SingleThreadedRun one_thread;  // docs/performance.md, "Threads"
  refuse_path(scene, "this solve");
  SceneSolve s;
  detail::SceneEngines engines = detail::prepare_scene_solve(scene, o, s);
  if (o.on_built) o.on_built(*s.built, s);
  detail::solve_built<2>(scene, engines, s, o.reduced, o.start,
                         [](const ContactProblem& p, const ContactSolution& u) { return estimate_error(p, u); });
  return s;
}

std::string conditioning_warning(double condition) {
  if (!(condition >= unreliable_condition)) return {};
  const double digits = -std::log10(condition * std::numeric_limits<double>::epsilon());
  std::ostringstream out;
  out << std::setprecision(2) << "the estimated condition number of the factorized matrix is " << condition
      << ": round-off alone may change the displacement in its "
      << (digits >= 1.0 ? std::to_string(static_cast<int>(digits) + 1) + "th significant digit"
                        : std::string("first significant digit"))
      << " (relative error up to about cond * eps = " << condition * std::numeric_limits<double>::epsilon()
      << "); elements with nearly coincident vertices or extreme material contrasts cause this";
  return out.str();
}

bool detail::results_of_pieces(const Scene& scene) {
  if (scene.adapt) return false;
  for (const std::string& file : wanted_files(scene, true))
    if (!made_from_pieces(file, scene.dimension())) return false;
  return true;
}

template <int dim>
RunInfo run_info(const Scene& scene, const BasicSceneSolve<dim>& solved) {
  const BasicBuiltProblem<dim>& built = *solved.built;
  RunInfo info = detail::run_info_common(scene, solved);
  if constexpr (dim == 2) info.options["plane_model"] = to_string(scene.material.model);
  if (built.has_contact) detail::add_contact_parts(info, contact_parts(built.problem));
  info.adapt = solved.adapt;
  info.adapt_steps = solved.adapt_steps;
  info.path = solved.path.get();
  return info;
}

template <int dim>
OutputReport write_results(const std::filesystem::path& dir, const Scene& scene, const BasicSceneSolve<dim>& solved,
                           const std::vector<std::string>* files) {
  // a path's frames in pieces: every process learns whether each was written
  if (solved.frame_pieces) solved.frame_pieces->require_written(dir);
  if (!solved.holds_results && !solved.share) return {};  // another process writes
  const BasicBuiltProblem<dim>& built = *solved.built;
  const RunInfo info = run_info(scene, solved);
  // a solid's contact faces, drawn by contact-surface.vtu and pressure.png
  std::vector<int> faces;
  if constexpr (dim == 3) faces = contact_faces(built.problem);
  const std::vector<int>* faces_drawn = dim == 3 ? &faces : nullptr;
  if (solved.path_output || solved.frame_pieces)  // on every process when the last step is written in pieces
    return detail::write_path_outputs<dim>(dir, files, solved.path_output.get(), solved.frame_pieces.get(), built.mesh,
                                           built.problem.elasticity.materials, faces_drawn, solved.solution, info,
                                           solved.piece_cells);
  const std::vector<std::string> wanted = files ? *files : wanted_files(scene, built.has_contact);
  if (solved.share)  // every process writes its piece of the solution
    return detail::write_outputs_in_pieces(dir, built.mesh, built.problem.elasticity.materials, faces_drawn,
                                           solved.solution, info, wanted, *solved.share, solved.piece_cells);
  check_output_folder(dir);
  if constexpr (dim == 2)
    return write_outputs(dir, built.mesh, built.problem.elasticity.materials, solved.solution, info, wanted);
  else
    return write_outputs(dir, built.mesh, built.problem.elasticity.materials, faces, solved.solution, info, wanted);
}

template RunInfo run_info(const Scene&, const SceneSolve&);
template RunInfo run_info(const Scene&, const SceneSolve3D&);
template OutputReport write_results(const std::filesystem::path&, const Scene&, const SceneSolve&,
                                    const std::vector<std::string>*);
template OutputReport write_results(const std::filesystem::path&, const Scene&, const SceneSolve3D&,
                                    const std::vector<std::string>*);

}  // namespace hemivem::app
