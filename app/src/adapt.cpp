#include <hemivem/app/adapt.hpp>

#include <hemivem/app/vtu.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/refine.hpp>
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

AdaptStep step_of(const SceneSolve& s, int step, double elapsed) {
  AdaptStep a;
  a.step = step;
  a.elements = s.built->mesh.num_elements();
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

// Why the next mesh is not solved, if it is too large: more unknowns than max_unknowns, or a
// solve whose estimated memory (as for a mesh file: HEMIVEM_MEMORY_LIMIT, or what the machine has
// available) would not fit.
std::optional<std::pair<AdaptStop, std::string>> too_large(const Mesh& next, const SceneAdapt& adapt) {
  const long long unknowns = 2LL * next.num_vertices();
  if (unknowns > adapt.max_unknowns)
    return std::pair{AdaptStop::max_unknowns, "the next mesh would have " + std::to_string(next.num_vertices()) +
                                                  " vertices (" + std::to_string(unknowns) +
                                                  " displacement components), more than max_unknowns = " +
                                                  std::to_string(adapt.max_unknowns)};
  try {
    require_memory(estimate_memory(next).solve_bytes, "the next mesh (" + std::to_string(next.num_vertices()) + " vertices)",
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

AdaptiveSolve solve_adaptively(const Scene& scene, const SceneAdapt& adapt, SceneSolveOptions options,
                               const std::function<void(const AdaptStep&)>& progress) {
  refuse_path(scene, "an adaptive solve");
  if (same_engine(scene.solver.linear, "mumps-mpi"))  // its processes would have to refine the same meshes in step
    throw InputError("an adaptive solve runs in one process; the linear engine mumps-mpi runs across processes: "
                     "choose another engine (solver.linear)",
                     scene.where("solver.linear"));
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  AdaptiveSolve out;
  const std::string base = options.mesh ? options.mesh_description : scene.mesh.description();
  // each step's mesh and start, moved into that step's options (the rest is shared by every step)
  std::optional<Mesh> mesh = std::move(options.mesh);
  Eigen::VectorXd start_u = std::move(options.start);
  options.mesh.reset();
  // each step's solution.vtu, for adapt.pvd, when the scene writes the output vtu
  const bool keep_steps = std::find(scene.outputs.begin(), scene.outputs.end(), "vtu") != scene.outputs.end();
  auto steps_vtu = std::make_shared<std::vector<std::string>>();
  for (int step = 0;; ++step) {
    SceneSolveOptions o = options;
    o.mesh = std::move(mesh);
    o.start = std::move(start_u);
    if (step > 0) {
      o.mesh_description = base + ", refined adaptively in " + std::to_string(step) + " steps";
      o.apply_region_boxes = false;  // the children inherit their parents' regions
    }
    out.last = solve_scene(scene, std::move(o));
    const SceneSolve& s = out.last;
    if (keep_steps) {
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
    RefinedMesh refined = refine_mesh(s.built->mesh, marked);
    if (auto stop = too_large(refined.mesh, adapt)) {
      finish(stop->first, stop->second + "; the relative error estimate is " + percent(now.estimate) +
                              ", above the target " + percent(adapt.target));
      break;
    }
    now.marked = static_cast<int>(marked.size());
    now.refined = static_cast<int>(refined.refined.size());
    if (progress) progress(now);
    start_u = prolongate(refined, s.solution.u);
    mesh = std::move(refined.mesh);
  }
  out.seconds = elapsed();
  out.last.adapt = adapt_json(out, adapt);
  if (keep_steps) out.last.adapt_steps = std::move(steps_vtu);
  return out;
}

nlohmann::json adapt_json(const AdaptiveSolve& solved, const SceneAdapt& adapt) {
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

std::string adapt_progress_line(const AdaptStep& a) {
  std::ostringstream o;
  o << "hemivem: adapt step " << a.step << ": " << a.elements << " elements, " << a.unknowns << " unknowns, estimate "
    << percent(a.estimate) << ", energy " << std::setprecision(8) << a.potential_energy << ", " << std::setprecision(3)
    << a.elapsed << " s";
  if (a.marked > 0) o << "; refining " << a.refined << " elements (" << a.marked << " marked)";
  return o.str();
}

}  // namespace hemivem::app
