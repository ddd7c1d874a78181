// A static solve's start from the scene's coarser grids (solver.grid_sequence,
// hemivem/scene/grid_sequence.hpp, docs/full-space.md).
#include "scene_setup.hpp"

#include <hemivem/app/solve3d.hpp>
#include <hemivem/mesh/finer_grid.hpp>
#include <hemivem/scene/grid_sequence.hpp>

#include <hemivem/error.hpp>

#include <chrono>
#include <string>
#include <vector>

namespace hemivem::app::detail {
namespace {

SceneSolve solve_grid(const Scene& scene, Eigen::VectorXd start) {
  SceneSolveOptions o;
  o.start = std::move(start);
  return solve_scene(scene, std::move(o));
}

SceneSolve3D solve_grid3(const Scene& scene, Eigen::VectorXd start) {
  SceneSolve3DOptions o;
  o.start = std::move(start);
  return solve_scene_3d(scene, std::move(o));
}

// The scene's grid of boxes, to carry values from.
GridSize grid_of(const Scene& scene, std::integral_constant<int, 2>) { return scene.mesh.cells(); }
GridSize3 grid_of(const Scene& scene, std::integral_constant<int, 3>) { return scene.mesh.cells3(); }

}  // namespace

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
    const BasicSceneSolve<dim> coarse = [&] {
      if constexpr (dim == 2)
        return solve_grid(*grid, std::move(start));
      else
        return solve_grid3(*grid, std::move(start));
    }();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const BasicContactSolution<dim>& u = coarse.solution;
    s.grid_sequence.push_back({{"n", dim == 3 ? grid->mesh.cells3().text() : grid->mesh.cells().text()},
                               {"unknowns", u.unknowns},
                               {"converged", u.converged()},
                               {"newton_iterations", u.full_space ? u.full_space->newton_iterations : 0},
                               {"krylov_iterations", u.full_space ? u.full_space->krylov_iterations : 0},
                               {"preconditioner_setups", u.full_space ? u.full_space->preconditioner_setups : 0},
                               {"seconds", seconds}});
    start = values_on_finer_grid(u.u, grid_of(*grid, std::integral_constant<int, dim>{}), dim);
  }
  return start;
}

template Eigen::VectorXd grid_sequence_start<2>(const Scene&, const SceneEngines&, SceneSolve&, bool);
template Eigen::VectorXd grid_sequence_start<3>(const Scene&, const SceneEngines&, SceneSolve3D&, bool);

}  // namespace hemivem::app::detail
