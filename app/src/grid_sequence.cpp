// A static solve's start from the scene's coarser grids (solver.grid_sequence,
// hemivem/scene/grid_sequence.hpp, docs/full-space.md).
#include "result_json_common.hpp"
#include "scene_setup.hpp"

#include <hemivem/error.hpp>
#include <hemivem/scene/grid_sequence.hpp>

#include <chrono>
#include <string>
#include <type_traits>
#include <vector>

namespace hemivem::app::detail {

SceneSolve solve_scene_of(const Scene& scene, SceneSolveOptions o) { return solve_scene(scene, std::move(o)); }
SceneSolve3D solve_scene_of(const Scene& scene, SceneSolve3DOptions o) { return solve_scene_3d(scene, std::move(o)); }

template <int dim>
Eigen::VectorXd grid_sequence_start(const Scene& scene, const SceneEngines& e, BasicSceneSolve<dim>& s,
                                    bool given_start) {
  if (e.grid_levels > 0 && scene.solver.grid_sequence > 0 && (given_start || !e.scene_mesh))
    throw InputError("solver.grid_sequence = " + std::to_string(scene.solver.grid_sequence) + ": " +
                         (given_start ? "this solve starts from the displacement it was given"
                                      : "this solve is on a mesh it was given, which has no coarser grids"),
                     scene.where("solver.grid_sequence"));
  if (given_start || !e.scene_mesh || e.grid_levels == 0) return {};
  std::vector<Scene> grids{coarser_grid_scene(scene)};  // the scene's coarser grids, finest first
  while (static_cast<int>(grids.size()) < e.grid_levels) grids.push_back(coarser_grid_scene(grids.back()));
  Eigen::VectorXd start;
  for (auto grid = grids.rbegin(); grid != grids.rend(); ++grid) {
    const auto started = std::chrono::steady_clock::now();
    std::conditional_t<dim == 2, SceneSolveOptions, SceneSolve3DOptions> o;
    o.start = std::move(start);
    const BasicSceneSolve<dim> coarse = solve_scene_of(*grid, std::move(o));
    const BasicContactSolution<dim>& u = coarse.solution;
    nlohmann::json record = u.full_space ? full_space_counts_json(*u.full_space) : nlohmann::json::object();
    record["n"] = grid->mesh.n_text();
    record["unknowns"] = u.unknowns;
    record["converged"] = u.converged();
    record["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    s.grid_sequence.push_back(std::move(record));
    if (e.on_coarser_grid) e.on_coarser_grid(s.grid_sequence.back());
    start = carried_onto_finer_grid(*grid, u.u);
  }
  return start;
}

template Eigen::VectorXd grid_sequence_start<2>(const Scene&, const SceneEngines&, SceneSolve&, bool);
template Eigen::VectorXd grid_sequence_start<3>(const Scene&, const SceneEngines&, SceneSolve3D&, bool);

}  // namespace hemivem::app::detail
