// What solve_scene and solve_scene_path do before they solve (private to hemivem::app).
#pragma once

#include <memory>

#include <hemivem/app/solve.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/sparse_factorization.hpp>

namespace hemivem::app::detail {

struct SceneEngines {
  std::unique_ptr<SparseFactorization> factorization;
  std::unique_ptr<NonsmoothMinimizer> minimizer;
};

/// The engines the scene names (an unknown or unbuilt name is an InputError naming its key,
/// before any work), recorded in `s` with the minimizer options (o.callback moved into them),
/// then the problem built (on o.mesh when given) with its time. on_built is left to the caller.
SceneEngines prepare_scene_solve(const Scene& scene, SceneSolveOptions& o, SceneSolve& s);

}  // namespace hemivem::app::detail
