// A scene's loading history (docs/paths.md): the steps of its [path] table solved on one
// condensation (hemivem/path/path.hpp), what path.json records about them and the line
// `hemivem solve` prints per step. A scene whose friction bound depends on the normal contact
// (Coulomb's law, or a bound h(u_nu)) and has no [path] is the one-step path t = 1. Plane
// and solid scenes alike: the functions on a path's steps are templates over the dimension.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/solve.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// Whether `scene` is solved as a path: it has a [path] table, or a friction bound that depends
/// on the normal contact.
bool scene_is_path(const Scene& scene);

/// The files a path adds to the run's folder (wanted_files): path.json, path-contact.csv,
/// path-displacement.csv (with the output displacement-csv), solution.pvd (with the output vtu)
/// and path.png; none when the scene is not a path or has no contact.
std::vector<std::string> path_files(const Scene& scene, bool has_contact);

/// Whether the scene's outputs hold a file of the path's frames (displacement-csv, vtu): only
/// then are the frames' displacements computed ([path] frames), each at the cost of an interior
/// solve and kept until the files are written; otherwise the last step alone has its
/// displacement.
bool writes_frames(const Scene& scene);

/// The load factors of the scene's path (t = 1 alone without [path]) and, unless the scene is
/// proportional (scene_is_proportional), the update that sets a problem built from it to t.
template <int dim>
BasicPathLoading<dim> scene_path_loading(const Scene& scene);

/// Solves the scene's path with the engines it names (an unknown engine or mumps-mpi is an
/// InputError before any work): the last step as a static solve reports it (its problem set to
/// the last t, so that every output and report reads the path's end state), with
/// SceneSolve::path holding every step (the frames, ScenePath::is_frame, with their
/// displacement). `options` as solve_scene's (its `reduced` and `start` are not used);
/// `on_step` is called after each step (for progress lines).
SceneSolve solve_scene_path(const Scene& scene, SceneSolveOptions options = {},
                            std::function<void(const PathStep&)> on_step = {});

/// path.json ("schema": "hemivem-path/1"): per step t, status, certificate, energy, the
/// contact zone, the contact resultant, the applied load, the fixed point, jumps (docs/reference/outputs.md).
template <int dim>
nlohmann::json path_json(const BasicPathSolution<dim>& path);
/// path.json's members besides its steps: schema, converged, jumps, proportional, timings.
template <int dim>
nlohmann::json path_json_members(const BasicPathSolution<dim>& path);
/// One step of path.json's "steps".
template <int dim>
nlohmann::json path_step_json(const BasicPathStep<dim>& step);

/// One line per step for `hemivem solve`: "step 3/10  t = 0.3  converged (primal 0, dual 2e-12)
/// zone 12 nodes  contact force (0.1, 7.9)  [fixed point 5 iterations]  [jump]".
template <int dim>
std::string path_progress_line(const BasicPathStep<dim>& step, int steps);

/// A step of a path as it is reported while the path runs, whatever the dimension.
struct PathProgress {
  int step = 0;    ///< 1-based
  int steps = 0;   ///< of the path
  double t = 0.0;
  MinimizerStatus status = MinimizerStatus::failed;
  std::string line;  ///< path_progress_line
};
/// The progress record of `step` of a path of `steps` steps.
template <int dim>
PathProgress path_progress(const BasicPathStep<dim>& step, int steps);

/// The lines `hemivem solve` adds to its report for a path.
template <int dim>
std::string path_report(const BasicPathSolution<dim>& path);

}  // namespace hemivem::app
