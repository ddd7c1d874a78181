// A three-dimensional scene solved, written and reported (solve3d.hpp).
#include <hemivem/app/solve3d.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/app/outputs3d.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/report.hpp>
#include <hemivem/error.hpp>
#include <hemivem/uniqueness.hpp>

#include "scene_setup.hpp"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <sstream>

namespace hemivem::app {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

bool wants(const Scene& scene, const std::string& name) {
  return std::find(scene.outputs.begin(), scene.outputs.end(), name) != scene.outputs.end();
}

}  // namespace

double SceneSolve3D::total_seconds() const {
  const auto it = solution.timings.find("total");
  return mesh_seconds + (it == solution.timings.end() ? 0.0 : it->second);
}

SceneSolve3D solve_scene_3d(const Scene& scene, SceneSolve3DOptions o) {
  if (scene.dimension() != 3)
    throw InputError("mesh: this solve takes three-dimensional scenes (solve_scene solves this one)", scene.where("mesh"));
  if (scene_is_path(scene)) detail::refuse_path_across_processes(scene);
  SceneSolve3D s;
  detail::SceneEngines e = detail::make_scene_engines(scene, std::move(o.progress), std::move(o.callback));
  detail::record_engines(e, s);
  const auto t = Clock::now();
  s.built = o.mesh ? build_problem_3d(scene, std::move(*o.mesh)) : build_problem_3d(scene);
  s.mesh_description = o.mesh ? o.mesh_description : scene.mesh.description();
  s.mesh_seconds = since(t);
  if (o.on_built) o.on_built(*s.built, s);
  if (scene_is_path(scene)) {
    detail::solve_path_built<3>(scene, e, s, std::move(o.on_path_step));
    return s;
  }
  detail::solve_built<3>(scene, e, s, o.reduced, Eigen::VectorXd(),
                         [](const ContactProblem3D& p, const ContactSolution3D& u) { return estimate_error(p, u); });
  return s;
}

std::vector<std::string> wanted_files_3d(const Scene& scene, bool has_contact) {
  std::vector<std::string> files;
  if (wants(scene, "result-json")) files.push_back("result.json");
  if (has_contact && wants(scene, "contact-csv")) files.push_back("contact.csv");
  if (wants(scene, "displacement-csv")) files.push_back("displacement.csv");
  if (has_contact && wants(scene, "history-csv")) files.push_back("history.csv");
  if (wants(scene, "vtu")) files.push_back("solution.vtu");
  if (has_contact && wants(scene, "vtu")) files.push_back("contact-surface.vtu");
  files.push_back("scene.toml");
  if (wants(scene, "deformed-png")) files.push_back("deformed.png");
  if (has_contact && wants(scene, "pressure-png")) files.push_back("pressure.png");
  for (auto& name : path_files(scene, has_contact)) files.push_back(std::move(name));
  return files;
}

RunInfo run_info_3d(const Scene& scene, const SceneSolve3D& solved) {
  const BuiltProblem3D& built = *solved.built;
  RunInfo info = detail::run_info_common(scene, solved);
  if (built.has_contact) detail::add_contact_parts(info, contact_parts(built.problem));
  info.path = solved.path.get();
  return info;
}

OutputReport write_results_3d(const std::filesystem::path& dir, const Scene& scene, const SceneSolve3D& solved,
                              const std::vector<std::string>* files) {
  const BuiltProblem3D& built = *solved.built;
  check_output_folder(dir);
  const RunInfo info = run_info_3d(scene, solved);
  return write_outputs_3d(dir, built.mesh, built.problem.elasticity.materials, contact_faces(built.problem),
                          solved.solution, info, files ? *files : wanted_files_3d(scene, built.has_contact));
}

namespace {

std::string triple_text(const Vec3& v) {
  std::ostringstream o;
  o << std::setprecision(6) << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return o.str();
}

}  // namespace

std::string brief_report_3d(const SceneSolve3D& solved) {
  const ContactSolution3D& sol = solved.solution;
  std::ostringstream out;
  out << std::setprecision(6) << to_string(sol.status) << " (certificate: " << certificate_text(sol.certificate)
      << "), " << sol.iterations() << " iterations, energy " << sol.energy << ", " << std::setprecision(3)
      << solved.total_seconds() << " s";
  return out.str();
}

std::string full_report_3d(const SceneSolve3D& solved, const RunInfo& info) {
  const BuiltProblem3D& built = *solved.built;
  const ContactSolution3D& sol = solved.solution;
  std::ostringstream out;
  out << std::setprecision(6);
  out << "  mesh          " << info.mesh << ": " << built.mesh.num_vertices() << " vertices, " << built.mesh.num_cells()
      << " cells, " << built.mesh.num_faces() << " faces, h = " << built.mesh.h() << ", " << info.dofs
      << " unknowns (three-dimensional)\n"
      << "  engines       linear " << info.linear
      << (info.processes > 1 ? " (" + std::to_string(info.processes) + " processes)" : std::string())
      << (built.has_contact ? ", minimizer " + info.minimizer : std::string(" (no contact: one linear solve)")) << "\n"
      << "  stages        ";
  for (std::size_t i = 0; i < sol.stages.size(); ++i) out << (i ? ", " : "") << sol.stages[i];
  out << "\n  status        " << to_string(sol.status) << " (certificate: " << certificate_text(sol.certificate) << "), "
      << sol.iterations() << " iterations\n";
  for (std::size_t k = 0; k < sol.held_by_contact.size(); ++k)
    out << (k == 0 ? "  supports      free, held by the contact alone: " : "                and ")
        << sol.held_by_contact[k] << "\n";
  if (info.search.value("kind", "local") == "global")
    out << (sol.minimizer ? critical_points_text(*sol.minimizer, sol.energy - sol.minimizer->objective)
                          : "  search        " + sol.message + "\n");
  if (!sol.contact.empty()) {
    out << "  uniqueness    lambda_min(S - alpha_j W) = " << sol.uniqueness_margin;
    if (sol.uniqueness_margin == 0.0) out << " (|computed| <= round-off bound " << sol.uniqueness_roundoff << ")";
    else if (sol.uniqueness_margin > 0) out << " > 0";
    else if (sol.uniqueness_margin < 0) out << " < 0";
    out << ": " << uniqueness_meaning(sol.uniqueness_margin) << "\n";
    int upper = 0, lower = 0, bilateral = 0;
    double law = 0.0, reaction = 0.0, area = 0.0;
    for (const auto& c : sol.contact) {
      upper += c.state == ContactState::upper, lower += c.state == ContactState::lower, bilateral += c.state == ContactState::bilateral;
      law += c.law_force, reaction += c.reaction;
      if (c.force() > 0.0) area += c.weight;
    }
    out << "  contact       " << sol.contact.size() << " nodes: " << upper << " at the upper bound, " << lower
        << " at the lower bound, ";
    if (bilateral > 0) out << bilateral << " bilateral, ";
    out << sol.contact.size() - static_cast<std::size_t>(upper + lower + bilateral) << " free; area in compression "
        << area << "\n"
        << "  normal forces " << law + reaction << " summed over the contact nodes (a sum, not a resultant): law " << law
        << ", constraint " << reaction << "\n";
  }
  if (solved.holds_results) {
    const ForceBalance3D& b = sol.forces;
    out << "  forces        applied " << triple_text(b.applied) << ", reactions";
    if (b.reactions.empty()) out << " none";
    for (std::size_t i = 0; i < b.reactions.size(); ++i)
      out << (i ? ", " : " ") << b.reactions[i].name << " " << triple_text(b.reactions[i].force);
    if (!sol.contact.empty()) out << ", contact " << triple_text(b.contact);
    out << "\n  balance       |applied + reactions" << (sol.contact.empty() ? "" : " + contact") << "| = "
        << std::setprecision(2) << b.residual() << std::setprecision(6)
        << (b.applied.norm() > 0.0 ? " x |applied|\n" : " x the largest force (no load is applied)\n");
  }
  if (solved.estimate) out << error_estimate_line(*solved.estimate);
  out << "  energy        potential " << sol.energy << "\n  time [s]      mesh " << solved.mesh_seconds;
  for (const char* k : {"assembly", "linear_solve", "condensation", "minimize", "back_substitution", "estimate"})
    if (sol.timings.count(k)) out << ", " << k << " " << sol.timings.at(k);
  const auto total = sol.timings.find("total");
  out << ", total " << solved.mesh_seconds + (total == sol.timings.end() ? 0.0 : total->second) << "\n";
  return out.str();
}

}  // namespace hemivem::app
