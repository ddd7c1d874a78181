// A three-dimensional scene solved, written and reported (solve3d.hpp).
#include <hemivem/support/blas_threads.hpp>
#include <hemivem/app/solve3d.hpp>

#include <hemivem/app/outputs.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/error.hpp>

#include "output_run.hpp"
#include "scene_setup.hpp"

#include <algorithm>
#include <chrono>

namespace hemivem::app {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

SceneSolve3D solve_scene_3d(const Scene& scene, SceneSolve3DOptions o) {
  const SingleThreadedRun one_thread;  // docs/performance.md, "Threads"
  if (scene.dimension() != 3)
    throw InputError("mesh: this solve takes three-dimensional scenes (solve_scene solves this one)", scene.where("mesh"));
  if (scene_is_path(scene)) detail::refuse_path_across_processes(scene);
  SceneSolve3D s;
  detail::SceneEngines e = detail::make_scene_engines(scene, std::move(o.progress), std::move(o.callback));
  e.on_coarser_grid = o.on_coarser_grid;
  detail::record_engines(e, s);
  const auto t = Clock::now();
  if (o.mesh)
    detail::build_given_problem<3>(scene, e, s, std::move(*o.mesh), false);
  else
    detail::build_scene_problem<3>(scene, e, s, o.out);
  s.mesh_description = o.mesh ? o.mesh_description : scene_mesh_description(scene);
  s.mesh_seconds = since(t);
  if (o.on_built) o.on_built(*s.built, s);
  if (scene_is_path(scene)) {
    detail::solve_path_built<3>(scene, e, s, std::move(o.on_path_step), o.out);
    return s;
  }
  detail::solve_built<3>(scene, e, s, o.reduced, std::move(o.start),
                         [](const ContactProblem3D& p, const ContactSolution3D& u) { return estimate_error(p, u); });
  return s;
}

}  // namespace hemivem::app
