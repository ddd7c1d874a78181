#include <hemivem/app/path.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/resources.hpp>

#include "output_run.hpp"
#include "scene_setup.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <sstream>

namespace hemivem::app {

namespace {

bool bound_depends_on_normal(const Scene& scene) {
  for (const SceneContact& c : contact_parts(scene))
    if (c.friction && (c.friction->name == "coulomb" || !c.friction->bound_table.empty())) return true;
  return false;
}

template <int dim>
nlohmann::json vec(const Eigen::Matrix<double, dim, 1>& v) {
  nlohmann::json out = nlohmann::json::array();
  for (int c = 0; c < dim; ++c) out.push_back(number(v(c)));
  return out;
}

}  // namespace

bool writes_frames(const Scene& scene) { return scene.writes("displacement-csv") || scene.writes("vtu"); }

bool scene_is_path(const Scene& scene) { return scene.path.has_value() || bound_depends_on_normal(scene); }

std::vector<std::string> path_files(const Scene& scene, bool has_contact) {
  if (!has_contact || !scene_is_path(scene)) return {};
  std::vector<std::string> files{"path.json", "path-contact.csv"};
  if (scene.writes("displacement-csv")) files.push_back("path-displacement.csv");
  if (scene.writes("vtu")) files.push_back("solution.pvd");
  files.push_back("path.png");
  return files;
}

template <int dim>
BasicPathLoading<dim> scene_path_loading(const Scene& scene) {
  BasicPathLoading<dim> loading;
  loading.t = scene.path ? scene.path->factors() : std::vector<double>{1.0};
  if (!scene_is_proportional(scene)) {
    loading.update = [scene](double t, BasicContactProblem<dim>& problem) { set_load_factor(scene, t, problem); };
    // [clamped] stays zero; a scene of several bodies has each body's [[dirichlet]]
    loading.updates_prescribed = !scene.dirichlet.empty() || std::any_of(scene.bodies.begin(), scene.bodies.end(),
                                                                         [](const SceneBody& b) { return !b.dirichlet.empty(); });
    loading.updates_gaps = scene_path_moves_gaps(scene);
  }
  return loading;
}

namespace detail {

void refuse_path_across_processes(const Scene& scene) {
  if (same_engine(scene.solver.linear, "mumps-mpi"))
    throw InputError("a loading path runs in one process; the linear engine mumps-mpi runs across processes: choose another",
                     scene.where("solver.linear"));
}

// A path that keeps its steps (for path.json, path-contact.csv and path.png, written after its
// last step) holds each step's contact nodes and each frame's displacement: about 400 bytes per
// contact node and step (340 measured) and 8 per dof and frame, beside the solve. A path writing
// its steps as they come (`streamed`) holds one step and one frame at a time, and path.png's
// row of each step (56 bytes, up to twice that as its array grows; 170 bytes a step measured
// in all). Refused before the path's first solve when that exceeds the memory available.
template <int dim>
void require_path_memory(const Scene& scene, const BasicContactProblem<dim>& problem, bool streamed) {
  const auto& mesh = *problem.elasticity.mesh;
  std::vector<char> on_contact(static_cast<std::size_t>(mesh.num_vertices()), 0);
  double nodes = 0.0;
  for (const auto& part : problem.parts)
    for (int facet : part.facets)
      for (int v : mesh.facet_vertices(facet))
        if (!on_contact[static_cast<std::size_t>(v)]) on_contact[static_cast<std::size_t>(v)] = 1, nodes += 1.0;
  const double steps = scene.path ? static_cast<double>(scene.path->factors().size()) : 1.0;
  const double frames = scene.path && writes_frames(scene) ? std::min(steps, static_cast<double>(scene.path->frames)) : 1.0;
  const double vertices = mesh.num_vertices();
  // the solve's own estimate, for the mesh at hand in the plane, on the scene's route
  MemoryEstimate condensed;
  if constexpr (dim == 2)
    condensed = estimate_memory(mesh);
  else
    condensed = estimate_memory_3d(vertices, nodes);
  const double solve =
      is_krylov_solver(scene.solver.linear)
          ? full_space_memory(condensed, full_space_cost(dim, scene.mesh.generator, scene.solver.linear)).solve_bytes
          : condensed.solve_bytes;
  const double path = streamed ? 400.0 * nodes * 2.0 + 200.0 * steps + 8.0 * dim * vertices
                               : 400.0 * nodes * (steps + frames) + 8.0 * dim * vertices * frames;
  std::ostringstream what;
  what << "a path of " << static_cast<long long>(steps) << " steps and " << static_cast<long long>(frames) << " frames on "
       << static_cast<long long>(vertices) << " vertices, " << static_cast<long long>(nodes)
       << " on the contact: " << format_bytes(path) << " beside the solve";
  require_memory(solve + path, what.str(), scene.where("path"));
}

// The files of the frames a path writes (SceneSolveOptions::out owns them before it runs), in
// `pieces` pieces each when > 0.
std::vector<std::string> planned_frames(const Scene& scene, int pieces) {
  std::vector<std::string> frames;
  if (!scene.path || !writes_frames(scene)) return frames;
  const int steps = static_cast<int>(scene.path->factors().size());
  for (int k = 1; k <= steps; ++k)
    if (scene.path->is_frame(k))
      for (const std::string& file : frame_files_of(k, pieces)) frames.push_back(file);
  return frames;
}

template <int dim, class Solved>
void solve_path_built(const Scene& scene, SceneEngines& e, Solved& s,
                      std::function<void(const BasicPathStep<dim>&)> on_step, const std::filesystem::path& out) {
  if (!s.built->has_contact)
    throw InputError("a loading path needs a contact boundary: the scene has none", scene.where("path"));
  require_path_memory<dim>(scene, s.built->problem, !out.empty());
  std::vector<std::string> parts;
  for (const auto& part : s.built->problem.parts) parts.push_back(part.name);
  // across processes on pieces of the mesh, each process writes its piece of every VTU frame
  const bool in_pieces = e.piece && e.writes_to_folder && scene.writes("vtu");
  std::exception_ptr unopened;
  if (!out.empty() && s.holds_results) {  // the folder's transaction, before the first step: each step is written as it comes
    try {
      check_output_folder(out);
      s.path_output = std::make_shared<PathOutput<dim>>(out, wanted_files(scene, true),
                                                        planned_frames(scene, in_pieces ? e.processes : 0), s.built->mesh,
                                                        s.built->problem.elasticity.materials, parts, s.built->bodies);
    } catch (...) {
      if (!in_pieces) throw;
      unopened = std::current_exception();
    }
  }
  if (in_pieces) {  // every process learns whether the first opened the folder
    s.frame_pieces = std::make_shared<FramePieces<dim>>(
        s.path_output ? &s.path_output->run.transaction() : nullptr, s.built->mesh, s.built->problem.elasticity.materials,
        e.piece->vertices);
    if (unopened) std::rethrow_exception(unopened);
    if (!s.frame_pieces->opened())
      throw InputError("the first process could not open the output folder", out.string());
    if (s.path_output) s.path_output->frame_pieces = s.frame_pieces.get();
  }
  BasicPathOptions<dim> po;
  po.minimizer = s.options;
  // a frame costs an interior solve and a displacement kept until the files are written: only
  // for a run that writes them
  if (scene.path && writes_frames(scene)) po.frame = [path = *scene.path](int k) { return path.is_frame(k); };
  // the full-space route across processes: each process solves its share and holds every step
  const bool across = e.krylov && e.processes > 1;
  // with an output folder each step goes to its files as it comes (on the process that writes)
  // and none is kept; without one, wherever the solution is (not the ranks > 0 of mumps-mpi)
  po.keep_steps = out.empty() && (s.holds_results || across);
  if (across) {
    po.distribute = make_distributed_rows;
    po.world = krylov_world();
    po.vertex_order = shared_vertex_order<dim>(e, s.built->mesh);
  }
  if (on_step || s.path_output || s.frame_pieces)
    po.on_step = [&](const BasicPathStep<dim>& step) {
      if (s.path_output) {
        s.path_output->files.add(step);  // its frames through s.frame_pieces
      } else if (s.frame_pieces && step.u.size() > 0) {
        s.frame_pieces->write(step.index, frame_of(step, parts), nullptr);
      }
      if (on_step) on_step(step);
      return true;
    };
  BasicPathSolution<dim> path;
  try {
    path = e.krylov ? solve_path(s.built->problem, std::move(e.krylov), *e.minimizer, scene_path_loading<dim>(scene),
                                 std::move(po))
                    : solve_path(s.built->problem, std::move(e.factorization), *e.minimizer,
                                 scene_path_loading<dim>(scene), std::move(po));
  } catch (const InputError& error) {  // a defect found when the problem is set up: name the scene's key
    rethrow_naming_scene_key(scene, error);
  }
  s.solution = path.last;
  s.warnings = s.built->warnings;
  // the problem's data at the last step, for the error estimate
  const double last_t = path.steps.back().t;
  set_load_factor(scene, last_t, s.built->problem);
  estimate_solution<dim>(e, s, [](const auto& problem, const auto& solution) { return estimate_error(problem, solution); });
  // the last step's solution.vtu in pieces too, where every file is made from the pieces
  if (in_pieces && results_of_pieces(scene)) s.share = e.piece->vertices;
  make_results_mesh_whole<dim>(scene, e, s, last_t);
  s.path = std::make_shared<const BasicPathSolution<dim>>(std::move(path));
}

template void solve_path_built(const Scene&, SceneEngines&, SceneSolve&, std::function<void(const BasicPathStep<2>&)>,
                               const std::filesystem::path&);
template void solve_path_built(const Scene&, SceneEngines&, SceneSolve3D&, std::function<void(const BasicPathStep<3>&)>,
                               const std::filesystem::path&);

}  // namespace detail

SceneSolve solve_scene_path(const Scene& scene, SceneSolveOptions o, std::function<void(const PathStep&)> on_step) {
  detail::refuse_path_across_processes(scene);
  SceneSolve s;
  detail::SceneEngines engines = detail::prepare_scene_solve(scene, o, s);
  if (o.on_built && s.built->has_contact) o.on_built(*s.built, s);
  detail::solve_path_built<2>(scene, engines, s, std::move(on_step), o.out);
  return s;
}

template <int dim>
nlohmann::json path_step_json(const BasicPathStep<dim>& s) {
  nlohmann::json j;
  j["step"] = s.index;
  j["t"] = s.t;
  j["status"] = to_string(s.status);
  j["converged"] = s.converged();
  j["message"] = s.message;
  j["certificate"] = certificate_json(s.certificate);
  j["may_be_nonunique"] = s.may_be_nonunique;
  j["iterations"] = s.iterations;
  j["energy"] = number(s.energy);
  j["contact_zone"] = {{"nodes", s.zone.nodes},
                       {"length", number(s.zone.length)},
                       {"lower", s.zone.nodes > 0 ? vec<dim>(s.zone.lower) : nlohmann::json()},
                       {"upper", s.zone.nodes > 0 ? vec<dim>(s.zone.upper) : nlohmann::json()}};
  j["contact_force"] = vec<dim>(s.contact_force);
  j["applied_load"] = vec<dim>(s.applied);
  int stick = 0, slip = 0;  // among the nodes in contact
  for (const auto& n : s.contact) {
    if (n.friction_state == FrictionState::none || !(n.force() > 0.0)) continue;
    (n.friction_state == FrictionState::stick ? stick : slip) += 1;
  }
  j["friction"] = s.slip.size() > 0 ? nlohmann::json{{"stick", stick}, {"slip", slip}} : nlohmann::json();
  j["fixed_point"] = s.fixed_point.used ? nlohmann::json{{"iterations", s.fixed_point.iterations},
                                                          {"change", number(s.fixed_point.change)},
                                                          {"relaxation", s.fixed_point.relaxation},
                                                          {"converged", s.fixed_point.converged}}
                                        : nlohmann::json();
  j["change"] = number(s.change);
  j["jump"] = s.jump;
  j["frame"] = s.u.size() > 0;
  j["balance"] = s.forces ? number(s.forces->residual()) : nlohmann::json();
  j["seconds"] = s.seconds;
  return j;
}

template <int dim>
nlohmann::json path_json_members(const BasicPathSolution<dim>& path) {
  nlohmann::json j;
  j["schema"] = "hemivem-path/1";
  j["converged"] = path.converged();
  j["jumps"] = path.jumps();
  j["proportional"] = path.proportional;
  j["timings"] = path.timings;
  return j;
}

template <int dim>
nlohmann::json path_json(const BasicPathSolution<dim>& path) {
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& s : path.steps) steps.push_back(path_step_json(s));
  nlohmann::json j = path_json_members(path);
  j["steps"] = std::move(steps);
  return j;
}

template <int dim>
std::string path_progress_line(const BasicPathStep<dim>& s, int steps) {
  std::ostringstream out;
  out << "  step " << s.index << "/" << steps << "  t = " << fixed(s.t, 4) << "  " << to_string(s.status) << " ("
      << certificate_text(s.certificate) << ")  zone " << s.zone.nodes << " nodes  contact force (";
  for (int c = 0; c < dim; ++c) out << (c ? ", " : "") << sci(s.contact_force(c), 4);
  out << ")";
  if (s.slip.size() > 0) {
    int stick = 0;
    for (const auto& n : s.contact) stick += n.friction_state == FrictionState::stick && n.force() > 0.0 ? 1 : 0;
    out << "  stick " << stick;
  }
  if (s.fixed_point.used)
    out << "  fixed point " << s.fixed_point.iterations << " iterations" << (s.fixed_point.converged ? "" : " (not converged)");
  if (s.jump) out << "  jump";
  if (!s.converged() && !s.message.empty()) out << ": " << s.message;
  return out.str();
}

template <int dim>
PathProgress path_progress(const BasicPathStep<dim>& step, int steps) {
  return {step.index, steps, step.t, step.status, path_progress_line(step, steps)};
}

template <int dim>
std::string path_report(const BasicPathSolution<dim>& path) {
  std::ostringstream out;
  out << "  path          " << path.solved_steps << " steps to t = " << path.steps.back().t << ", " << path.converged_steps
      << " converged, " << path.jumps() << " jumps" << (path.proportional ? " (proportional: one condensation, no solve per step)" : "")
      << "\n";
  return out.str();
}

#define HEMIVEM_APP_PATH(dim)                                                               \
  template BasicPathLoading<dim> scene_path_loading(const Scene&);                          \
  template nlohmann::json path_json(const BasicPathSolution<dim>&);                         \
  template nlohmann::json path_json_members(const BasicPathSolution<dim>&);                 \
  template nlohmann::json path_step_json(const BasicPathStep<dim>&);                        \
  template std::string path_progress_line(const BasicPathStep<dim>&, int);                  \
  template PathProgress path_progress(const BasicPathStep<dim>&, int);                      \
  template std::string path_report(const BasicPathSolution<dim>&);

HEMIVEM_APP_PATH(2)
HEMIVEM_APP_PATH(3)

}  // namespace hemivem::app
