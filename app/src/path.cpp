#include <hemivem/app/path.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include "scene_setup.hpp"

#include <chrono>
#include <sstream>

namespace hemivem::app {

namespace {

bool bound_depends_on_normal(const Scene& scene) {
  for (const SceneContact& c : contact_parts(scene))
    if (c.friction && (c.friction->name == "coulomb" || !c.friction->bound_table.empty())) return true;
  return false;
}

nlohmann::json vec(const Vec2& v) { return nlohmann::json::array({number(v.x()), number(v.y())}); }

}  // namespace

bool scene_is_path(const Scene& scene) { return scene.path.has_value() || bound_depends_on_normal(scene); }

PathLoading scene_path_loading(const Scene& scene) {
  PathLoading loading;
  loading.t = scene.path ? scene.path->factors() : std::vector<double>{1.0};
  if (!scene_is_proportional(scene))
    loading.update = [scene](double t, ContactProblem& problem) { set_load_factor(scene, t, problem); };
  return loading;
}

SceneSolve solve_scene_path(const Scene& scene, SceneSolveOptions o, std::function<void(const PathStep&)> on_step) {
  SceneSolve s;
  PathSolution path;
  if (same_engine(scene.solver.linear, "mumps-mpi"))
    throw InputError("a loading path runs in one process; the linear engine mumps-mpi runs across processes: choose another",
                     scene.where("solver.linear"));
  detail::SceneEngines engines = detail::prepare_scene_solve(scene, o, s);
  auto& factorization = engines.factorization;
  const auto& minimizer = engines.minimizer;
  if (!s.built->has_contact)
    throw InputError("a loading path needs a contact boundary: the scene has none", scene.where("path"));
  if (o.on_built) o.on_built(*s.built, s);
  PathOptions po;
  po.minimizer = s.options;
  if (scene.path) po.frame = [path = *scene.path](int k) { return path.is_frame(k); };
  if (on_step)
    po.on_step = [&](const PathStep& step) {
      on_step(step);
      return true;
    };
  try {
    path = solve_path(s.built->problem, std::move(factorization), *minimizer, scene_path_loading(scene), std::move(po));
  } catch (const InputError& e) {  // a defect found when the problem is set up: name the scene's key
    detail::rethrow_naming_scene_key(scene, e);
  }
  s.solution = path.last;
  s.warnings = s.built->warnings;
  // the problem's data at the last step, for the error estimate
  set_load_factor(scene, path.steps.back().t, s.built->problem);
  if (s.solution.u.size() > 0 && s.solution.u.allFinite()) {
    s.estimate = estimate_error(s.built->problem, s.solution);
    s.solution.stages.push_back("estimate");
    s.solution.timings["estimate"] = s.estimate->seconds;
    s.solution.timings["total"] += s.estimate->seconds;
  }
  s.path = std::make_shared<const PathSolution>(std::move(path));
  return s;
}

nlohmann::json path_step_json(const PathStep& s) {
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
                       {"lower", s.zone.nodes > 0 ? vec(s.zone.lower) : nlohmann::json()},
                       {"upper", s.zone.nodes > 0 ? vec(s.zone.upper) : nlohmann::json()}};
  j["contact_force"] = vec(s.contact_force);
  j["applied_load"] = vec(s.applied);
  int stick = 0, slip = 0;  // among the nodes in contact
  for (const ContactNode& n : s.contact) {
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

nlohmann::json path_json(const PathSolution& path) {
  nlohmann::json steps = nlohmann::json::array();
  for (const PathStep& s : path.steps) steps.push_back(path_step_json(s));
  nlohmann::json j;
  j["schema"] = "hemivem-path/1";
  j["steps"] = std::move(steps);
  j["converged"] = path.converged();
  j["jumps"] = path.jumps();
  j["proportional"] = path.proportional;
  j["timings"] = path.timings;
  return j;
}

std::string path_progress_line(const PathStep& s, int steps) {
  std::ostringstream out;
  out << "  step " << s.index << "/" << steps << "  t = " << fixed(s.t, 4) << "  " << to_string(s.status) << " ("
      << certificate_text(s.certificate) << ")  zone " << s.zone.nodes << " nodes  contact force ("
      << sci(s.contact_force.x(), 4) << ", " << sci(s.contact_force.y(), 4) << ")";
  if (s.slip.size() > 0) {
    int stick = 0;
    for (const ContactNode& n : s.contact) stick += n.friction_state == FrictionState::stick && n.force() > 0.0 ? 1 : 0;
    out << "  stick " << stick;
  }
  if (s.fixed_point.used)
    out << "  fixed point " << s.fixed_point.iterations << " iterations" << (s.fixed_point.converged ? "" : " (not converged)");
  if (s.jump) out << "  jump";
  return out.str();
}

std::string path_report(const PathSolution& path) {
  int converged = 0;
  for (const PathStep& s : path.steps) converged += s.converged() ? 1 : 0;
  std::ostringstream out;
  out << "  path          " << path.steps.size() << " steps to t = " << path.steps.back().t << ", " << converged
      << " converged, " << path.jumps() << " jumps" << (path.proportional ? " (proportional: one condensation, no solve per step)" : "")
      << "\n";
  return out.str();
}

}  // namespace hemivem::app
