// A three-dimensional scene solved (docs/reference/scenes.md, "Three-dimensional scenes"): the
// engines the scene names (those of solve_scene), its ContactProblem3D (build_problem<3>), the
// solve (solve_contact), and what `hemivem solve` writes and prints about it.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/estimate/error_estimate3d.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// What solve_scene_3d does besides solving the scene as it is written.
struct SceneSolve3DOptions {
  /// Called between building and solving.
  std::function<void(const BuiltProblem3D&, const SceneSolve3D&)> on_built;
  /// Becomes MinimizerOptions::callback.
  std::function<bool(const IterationRecord&)> callback;
  /// When not null, receives the reduced problem.
  ReducedProblem* reduced = nullptr;
  /// Reports the runs of a global search.
  std::function<void(const GlobalSearchProgress&)> progress;
  /// A mesh to solve on instead of the scene's (build_problem(scene, mesh)); across processes
  /// as SceneSolveOptions::mesh.
  std::optional<Mesh3D> mesh;
  /// How that mesh was made, for reports (SceneSolve3D::mesh_description).
  std::string mesh_description = "a mesh given by the caller";
  /// Called after each step of a loading path.
  std::function<void(const BasicPathStep<3>&)> on_path_step;
  /// As SceneSolveOptions::out.
  std::filesystem::path out;
  /// As SceneSolveOptions::on_coarser_grid.
  std::function<void(const nlohmann::json&)> on_coarser_grid;
  /// A full nodal displacement on that mesh (3 per vertex) the minimizer starts from; empty: zero.
  Eigen::VectorXd start;
};

/// Creates the engines the scene names (an unknown or unbuilt name is an InputError before any
/// work, as in solve_scene), builds the problem (build_problem<3>) and solves it
/// (solve_contact), or its loading path when it is one (scene_is_path: the path's steps in
/// SceneSolve3D::path, its last step in the solution; `reduced` is then not used). A defect found when the contact part or the supports are set up (a
/// contact node with a prescribed normal component, rigid motions the supports leave free) is
/// an InputError naming the scene's key. InputError for a two-dimensional scene.
SceneSolve3D solve_scene_3d(const Scene& scene, SceneSolve3DOptions options = {});

}  // namespace hemivem::app
