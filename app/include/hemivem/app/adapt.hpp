// Adaptive refinement of a scene (docs/adaptivity.md): solve -> estimate -> mark -> refine ->
// solve again from the previous solution, until the error estimate reaches the target or a
// budget is spent.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// One solve of an adaptive sequence.
struct AdaptStep {
  int step = 0;                  ///< 0 for the scene's own mesh
  int elements = 0;              ///< elements of a plane mesh, cells of a solid one
  int vertices = 0;
  int unknowns = 0;              ///< free degrees of freedom
  double estimate = 0.0;         ///< the relative error estimate eta / ||u_h||_E
  double estimate_energy = 0.0;  ///< the absolute estimate eta
  double potential_energy = 0.0;
  double elapsed = 0.0;          ///< seconds since the adaptive solve started, this step's solve and estimate included
  std::string status;            ///< the solve's status (to_string(MinimizerStatus))
  int marked = 0;                ///< elements marked after this step (0 for the last step)
  int refined = 0;               ///< elements split after this step (marked ones and the one-hanging-node closure)
};

/// Why an adaptive solve stopped.
enum class AdaptStop {
  target,         ///< the relative estimate reached the target
  max_steps,      ///< max_steps solves were done
  max_unknowns,   ///< the next mesh would have had more unknowns than max_unknowns
  memory,         ///< the next mesh's solve would have needed more memory than is available
  not_converged,  ///< a solve did not converge: refining its solution would mean nothing
};
std::string to_string(AdaptStop stop);

/// An adaptive solve of a plane (dim = 2) or a solid (dim = 3) body: its steps and its last
/// solve, whose mesh is the final mesh.
template <int dim>
struct BasicAdaptiveSolve {
  BasicSceneSolve<dim> last;
  std::vector<AdaptStep> steps;
  AdaptStop stopped = AdaptStop::target;
  std::string reason;  ///< why it stopped, in words
  double seconds = 0.0;  ///< wall time of the whole sequence
  bool reached_target() const noexcept { return stopped == AdaptStop::target; }
};
using AdaptiveSolve = BasicAdaptiveSolve<2>;
using AdaptiveSolve3D = BasicAdaptiveSolve<3>;

/// Solves `scene` adaptively with the parameters of `adapt` (the scene's [adapt], or the
/// defaults for `hemivem solve --adapt`). Step 0 solves the scene's mesh; each further step
/// marks the elements (cells) of the previous one by Doerfler marking with adapt.fraction on the
/// error indicators (hemivem/estimate/error_estimate.hpp, error_estimate3d.hpp), refines them
/// (refine_mesh of hemivem/mesh/refine.hpp, refine3d.hpp: every part, load, gap, obstacle and
/// region of the scene is selected again on the refined mesh, regions and a solid's face groups
/// inherited from the parents) and solves again, the
/// minimizer starting from the previous solution interpolated onto the new mesh. `options`
/// serves every step (its mesh and start are set per step; a given mesh replaces the scene's
/// at step 0); `progress`, when given, is called after every step. When the scene writes the
/// output vtu, the last solve carries every step's solution.vtu (SceneSolve::adapt_steps). Errors as solve_scene's, and
/// an InputError for the engine mumps-mpi (an adaptive solve runs in one process).
AdaptiveSolve solve_adaptively(const Scene& scene, const SceneAdapt& adapt, SceneSolveOptions options = {},
                               const std::function<void(const AdaptStep&)>& progress = {});
/// The same for a solid scene (solve_scene_3d per step).
AdaptiveSolve3D solve_adaptively(const Scene& scene, const SceneAdapt& adapt, SceneSolve3DOptions options,
                                 const std::function<void(const AdaptStep&)>& progress = {});

/// result.json's "adapt": the parameters, why it stopped, and per step its numbers.
template <int dim>
nlohmann::json adapt_json(const BasicAdaptiveSolve<dim>& solved, const SceneAdapt& adapt);

/// A progress line for stderr: "adapt step 3: 1234 unknowns, estimate 2.31 %, energy -0.2169, 1.2 s".
std::string adapt_progress_line(const AdaptStep& step);

}  // namespace hemivem::app
