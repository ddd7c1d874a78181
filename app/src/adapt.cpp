#include <hemivem/app/adapt.hpp>
#include "scene_setup.hpp"

#include <hemivem/app/vtu.hpp>
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/mesh/dimension.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/mesh/refine3d.hpp>
#include <hemivem/scene/resources.hpp>

#include <algorithm>
#include <memory>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <utility>
#include <sstream>

namespace hemivem::app {

namespace {

using Clock = std::chrono::steady_clock;

int cells(const Mesh& mesh) { return mesh.num_elements(); }
int cells(const Mesh3D& mesh) { return mesh.num_cells(); }

template <int dim>
AdaptStep step_of(const BasicSceneSolve<dim>& s, int step, double elapsed) {
  AdaptStep a;
  a.step = step;
  a.elements = cells(s.built->mesh);
  a.vertices = s.built->mesh.num_vertices();
  a.unknowns = s.solution.unknowns;
  if (s.estimate) {
    a.estimate = s.estimate->relative;
    a.estimate_energy = s.estimate->energy;
  } else {
    a.estimate = a.estimate_energy = std::numeric_limits<double>::quiet_NaN();
  }
  a.potential_energy = s.solution.energy;
  a.elapsed = elapsed;
  a.status = to_string(s.solution.status);
  return a;
}

// The condensed route's memory for a refined mesh (resources.hpp): a plane's from its elements;
// a solid's from its vertices and the contact nodes of the faces that refine the contact faces
// of `built`, with the coefficient of polyhedra when a cell has more than eight vertices.
MemoryEstimate condensed_memory(const RefinedMesh& refined, const BuiltProblem&) { return estimate_memory(refined.mesh); }

MemoryEstimate condensed_memory(const RefinedMesh3D& refined, const BuiltProblem3D& built) {
  const Mesh3D& next = refined.mesh;
  std::vector<char> contact_face(static_cast<std::size_t>(built.mesh.num_faces()), 0);
  for (const auto& part : built.problem.parts)
    for (int f : part.facets) contact_face[static_cast<std::size_t>(f)] = 1;
  std::vector<char> on_contact(static_cast<std::size_t>(next.num_vertices()), 0);
  double nodes = 0.0;
  for (int f : next.boundary_faces()) {
    const int parent = refined.parent_face[static_cast<std::size_t>(f)];
    if (parent < 0 || !contact_face[static_cast<std::size_t>(parent)]) continue;
    for (int v : next.face(f).vertices)
      if (!on_contact[static_cast<std::size_t>(v)]) on_contact[static_cast<std::size_t>(v)] = 1, nodes += 1.0;
  }
  bool polyhedra = false;
  for (int c = 0; c < next.num_cells() && !polyhedra; ++c) polyhedra = next.cell_vertices(c).size() > 8;
  return estimate_memory_3d(next.num_vertices(), nodes, polyhedra ? 3600.0 : 1200.0);
}

// The memory the solve of a refined mesh needs on the scene's route: the condensed route's, or
// the full-space route's for a Krylov engine.
template <class Refined, class Built>
double solve_bytes(const Scene& scene, const Refined& refined, const Built& built) {
  const MemoryEstimate condensed = condensed_memory(refined, built);
  if (!is_krylov_solver(scene.solver.linear)) return condensed.solve_bytes;
  return full_space_memory(condensed, full_space_cost(scene.dimension(), scene.mesh.generator, scene.solver.linear))
      .solve_bytes;
}

// Why the next mesh is not solved, if it is too large: more unknowns than max_unknowns, or a
// solve on the scene's route whose estimated memory (as for a mesh file: HEMIVEM_MEMORY_LIMIT, or
// what the machine has available) would not fit.
template <int dim, class Refined>
std::optional<std::pair<AdaptStop, std::string>> too_large(const Scene& scene, const Refined& refined,
                                                           const BasicBuiltProblem<dim>& built, const SceneAdapt& adapt) {
  const long long vertices = refined.mesh.num_vertices();
  const long long unknowns = dim * vertices;
  if (unknowns > adapt.max_unknowns)
    return std::pair{AdaptStop::max_unknowns, "the next mesh would have " + std::to_string(vertices) + " vertices (" +
                                                  std::to_string(unknowns) +
                                                  " displacement components), more than max_unknowns = " +
                                                  std::to_string(adapt.max_unknowns)};
  try {
    const std::string route = is_krylov_solver(scene.solver.linear) ? ") on the full-space route with " + scene.solver.linear : ")";
    require_memory(solve_bytes(scene, refined, built), "the next mesh (" + std::to_string(vertices) + " vertices" + route,
                   "adapt");
  } catch (const InputError& e) {
    return std::pair{AdaptStop::memory, e.detail()};
  }
  return std::nullopt;
}

std::string percent(double x) {
  std::ostringstream o;
  o << std::setprecision(3) << 100.0 * x << " %";
  return o.str();
}

}  // namespace

std::string to_string(AdaptStop stop) {
  switch (stop) {
    case AdaptStop::target: return "target";
    case AdaptStop::max_steps: return "max_steps";
    case AdaptStop::max_unknowns: return "max_unknowns";
    case AdaptStop::memory: return "memory";
    case AdaptStop::not_converged: return "not_converged";
  }
  return "unknown";
}

namespace {

template <int dim, class Options>
BasicAdaptiveSolve<dim> adapt_scene(const Scene& scene, const SceneAdapt& adapt, Options options,
                                    const std::function<void(const AdaptStep&)>& progress) {
  refuse_path(scene, "an adaptive solve");
  if (!scene.bodies.empty())  // [adapt] is refused when the scene is read; `--adapt` comes here
    throw InputError("an adaptive solve refines the mesh of one body; a scene of several bodies ([[body]]) is solved "
                     "on the meshes its bodies make",
                     scene.where("adapt"));
  // its ranks > 0 hold no displacement, from which each process would have to refine the same mesh
  // (the full-space route's processes each hold the whole solution, and refine alike)
  if (same_engine(scene.solver.linear, "mumps-mpi"))
    throw InputError("an adaptive solve runs in one process; the linear engine mumps-mpi runs across processes: "
                     "choose another engine (solver.linear)",
                     scene.where("solver.linear"));
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  BasicAdaptiveSolve<dim> out;
  const std::string base = options.mesh ? options.mesh_description : scene_mesh_description(scene);
  // each step's mesh and start, moved into that step's options (the rest is shared by every step)
  std::optional<MeshOf<dim>> mesh = std::move(options.mesh);
  Eigen::VectorXd start_u = std::move(options.start);
  options.mesh.reset();
  // each step's solution.vtu, for adapt.pvd, when the scene writes the output vtu
  const bool keep_steps = scene.writes("vtu");
  auto steps_vtu = std::make_shared<std::vector<std::string>>();
  for (int step = 0;; ++step) {
    Options o = options;
    o.mesh = std::move(mesh);
    o.start = std::move(start_u);
    if (step > 0) {
      o.mesh_description = base + ", refined adaptively in " + std::to_string(step) + " steps";
      if constexpr (dim == 2) o.apply_region_boxes = false;  // the children inherit their parents' regions
    }
    out.last = detail::solve_scene_of(scene, std::move(o));
    const BasicSceneSolve<dim>& s = out.last;
    if (keep_steps && s.holds_results) {  // the process that writes
      std::ostringstream vtu;
      write_vtu(vtu, s.built->mesh, s.built->problem.elasticity.materials, s.solution,
                s.estimate ? &s.estimate->indicators : nullptr);
      steps_vtu->push_back(vtu.str());
    }
    out.steps.push_back(step_of(s, step, elapsed()));
    AdaptStep& now = out.steps.back();
    auto finish = [&](AdaptStop why, std::string reason) {
      out.stopped = why;
      out.reason = std::move(reason);
      if (progress) progress(now);
    };
    if (!s.solution.converged() || !s.estimate) {
      finish(AdaptStop::not_converged, "step " + std::to_string(step) + " did not converge (" + now.status +
                                           "): its error indicators do not describe a solution");
      break;
    }
    if (now.estimate <= adapt.target) {
      finish(AdaptStop::target, "the relative error estimate " + percent(now.estimate) + " is at most the target " +
                                    percent(adapt.target));
      break;
    }
    if (step + 1 >= adapt.max_steps) {
      finish(AdaptStop::max_steps, "max_steps = " + std::to_string(adapt.max_steps) +
                                       " solves were done; the relative error estimate is " + percent(now.estimate) +
                                       ", above the target " + percent(adapt.target));
      break;
    }
    const std::vector<int> marked = dorfler_marking(s.estimate->indicators, adapt.fraction);
    auto refined = refine_mesh(s.built->mesh, marked);
    if (auto stop = too_large<dim>(scene, refined, *s.built, adapt)) {
      finish(stop->first, stop->second + "; the relative error estimate is " + percent(now.estimate) +
                              ", above the target " + percent(adapt.target));
      break;
    }
    now.marked = static_cast<int>(marked.size());
    now.refined = static_cast<int>(refined.refined.size());
    if (progress) progress(now);
    start_u = prolongate(refined, s.solution.u);
    mesh = std::move(refined.mesh);
    out.last = BasicSceneSolve<dim>{};  // given back before the next step is solved, not held beside it
  }
  out.seconds = elapsed();
  out.last.adapt = adapt_json(out, adapt);
  if (keep_steps) out.last.adapt_steps = std::move(steps_vtu);
  return out;
}

}  // namespace

AdaptiveSolve solve_adaptively(const Scene& scene, const SceneAdapt& adapt, SceneSolveOptions options,
                               const std::function<void(const AdaptStep&)>& progress) {
  return adapt_scene<2>(scene, adapt, std::move(options), progress);
}

AdaptiveSolve3D solve_adaptively(const Scene& scene, const SceneAdapt& adapt, SceneSolve3DOptions options,
                                 const std::function<void(const AdaptStep&)>& progress) {
  if (scene.dimension() != 3)
    throw InputError("mesh: this adaptive solve takes three-dimensional scenes", scene.where("mesh"));
  return adapt_scene<3>(scene, adapt, std::move(options), progress);
}

template <int dim>
nlohmann::json adapt_json(const BasicAdaptiveSolve<dim>& solved, const SceneAdapt& adapt) {
  nlohmann::json steps = nlohmann::json::array();
  for (const AdaptStep& a : solved.steps)
    steps.push_back({{"step", a.step},
                     {"elements", a.elements},
                     {"vertices", a.vertices},
                     {"unknowns", a.unknowns},
                     {"estimate", std::isfinite(a.estimate) ? nlohmann::json(a.estimate) : nlohmann::json(nullptr)},
                     {"estimate_energy",
                      std::isfinite(a.estimate_energy) ? nlohmann::json(a.estimate_energy) : nlohmann::json(nullptr)},
                     {"potential_energy", std::isfinite(a.potential_energy) ? nlohmann::json(a.potential_energy)
                                                                             : nlohmann::json(nullptr)},
                     {"elapsed", a.elapsed},
                     {"status", a.status},
                     {"marked", a.marked},
                     {"refined", a.refined}});
  return {{"target", adapt.target},
          {"fraction", adapt.fraction},
          {"max_steps", adapt.max_steps},
          {"max_unknowns", adapt.max_unknowns},
          {"stopped", to_string(solved.stopped)},
          {"reached_target", solved.reached_target()},
          {"reason", solved.reason},
          {"seconds", solved.seconds},
          {"steps", std::move(steps)}};
}

template nlohmann::json adapt_json(const BasicAdaptiveSolve<2>&, const SceneAdapt&);
template nlohmann::json adapt_json(const BasicAdaptiveSolve<3>&, const SceneAdapt&);

std::string adapt_progress_line(const AdaptStep& a) {
  std::ostringstream o;
  o << "hemivem: adapt step " << a.step << ": " << a.elements << " elements, " << a.unknowns << " unknowns, estimate "
    << percent(a.estimate) << ", energy " << std::setprecision(8) << a.potential_energy << ", " << std::setprecision(3)
    << a.elapsed << " s";
  if (a.marked > 0) o << "; refining " << a.refined << " elements (" << a.marked << " marked)";
  return o.str();
}

}  // namespace hemivem::app
