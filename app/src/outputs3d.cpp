// The output folder of a three-dimensional solve (outputs3d.hpp): result.json, the CSV tables,
// the two VTU files (vtu3d.cpp), scene.toml and the pictures (figures3d.cpp), written as one
// transaction.
#include <hemivem/app/outputs3d.hpp>

#include "output_run.hpp"
#include "path_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <ostream>

#include <hemivem/app/format.hpp>
#include <hemivem/app/text_writer.hpp>
#include <hemivem/error.hpp>
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/support/output_folder.hpp>
#include <hemivem/uniqueness.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include "path_outputs.hpp"
#include "result_json_common.hpp"

namespace hemivem::app {

namespace fs = std::filesystem;

const std::vector<std::string>& all_outputs_3d() {
  static const std::vector<std::string> names{"result.json",         "contact.csv", "displacement.csv",
                                              "history.csv",         "solution.vtu", "contact-surface.vtu",
                                              "scene.toml",          "deformed.png", "pressure.png",
                                              "path.json",           "path-contact.csv", "path-displacement.csv",
                                              "solution.pvd",        "path.png"};
  return names;
}

double CellStress3D::von_mises() const {
  return std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx)) +
                   3.0 * (yz * yz + xz * xz + xy * xy));
}

std::vector<CellStress3D> cell_stresses_3d(const Mesh3D& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  if (u.size() != 3 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("a displacement of " + std::to_string(u.size()) + " values for a mesh of " +
                     std::to_string(mesh.num_vertices()) + " vertices (3 per vertex)");
  const std::vector<LinearField3> projected = project_solution(mesh, u);
  std::vector<CellStress3D> out(static_cast<std::size_t>(mesh.num_cells()));
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const Eigen::Matrix3d sigma = stress_3d(projected[static_cast<std::size_t>(c)].gradient, materials.lame(mesh.region(c)));
    CellStress3D& s = out[static_cast<std::size_t>(c)];
    s.xx = sigma(0, 0), s.yy = sigma(1, 1), s.zz = sigma(2, 2);
    s.yz = sigma(1, 2), s.xz = sigma(0, 2), s.xy = sigma(0, 1);
  }
  return out;
}

namespace {

nlohmann::json triple(const Vec3& v) { return {number(v.x()), number(v.y()), number(v.z())}; }


/// The nodes in compression (a positive force): how many, their area and their bounding box.
nlohmann::json contact_zone_json(const ContactSolution3D& s) {
  int nodes = 0;
  double area = 0.0;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  for (const auto& n : s.contact) {
    if (!(n.force() > 0.0)) continue;
    lo = nodes == 0 ? n.x : Vec3(lo.cwiseMin(n.x));
    hi = nodes == 0 ? n.x : Vec3(hi.cwiseMax(n.x));
    area += n.weight;
    ++nodes;
  }
  if (nodes == 0) return nullptr;
  return {{"nodes", nodes},
          {"area", number(area)},
          {"x", {number(lo.x()), number(hi.x())}},
          {"y", {number(lo.y()), number(hi.y())}},
          {"z", {number(lo.z()), number(hi.z())}}};
}

nlohmann::json forces_json(const ForceBalance3D& b) {
  nlohmann::json reactions = nlohmann::json::object();
  for (const auto& r : b.reactions) reactions[r.name] = triple(r.force);
  return {{"applied", triple(b.applied)},
          {"reactions", std::move(reactions)},
          {"contact", triple(b.contact)},
          {"balance_residual", number(b.residual())}};
}


}  // namespace

nlohmann::json result_json(const Mesh3D& mesh, const ContactSolution3D& s, const RunInfo& info) {
  using nlohmann::json;
  json j = detail::result_json_common(s, info, 3);
  j["held_by_contact"] = s.held_by_contact;
  j["condition_estimate"] = number(s.condition_estimate);
  j["mesh"] = {{"description", info.mesh},
               {"vertices", mesh.num_vertices()},
               {"elements", mesh.num_cells()},
               {"faces", mesh.num_faces()},
               {"dofs", info.dofs >= 0 ? info.dofs : 3 * mesh.num_vertices()},
               {"h", mesh.h()}};
  json contact = json::array();
  for (const auto& n : s.contact)
    contact.push_back({{"vertex", n.vertex},
                       {"x", triple(n.x)},
                       {"u_nu", number(n.u_nu)},
                       {"law_force", number(n.law_force)},
                       {"reaction", number(n.reaction)},
                       {"pressure", number(n.pressure())},
                       {"gap", number(n.gap)},
                       {"normal", triple(n.normal)},
                       {"state", to_string(n.state)},
                       {"part", contact_part_name(s, n)}});
  j["contact"] = std::move(contact);
  j["friction"] = nullptr;
  j["contact_force"] = triple(s.contact_force());
  j["forces"] = forces_json(s.forces);
  j["contact_zone"] = contact_zone_json(s);
  j["adapt"] = nullptr;
  j["path"] = path_of<3>(info) ? path_summary_json(*path_of<3>(info)) : nlohmann::json(nullptr);
  return j;
}

OutputReport write_outputs(const fs::path& dir, const Mesh3D& mesh, const MaterialTable& materials,
                              const std::vector<int>& contact_faces, const ContactSolution3D& solution,
                              const RunInfo& info, const std::vector<std::string>& wanted) {
  detail::require_known_outputs(wanted, all_outputs_3d(), " of a three-dimensional solve");
  if (solution.u.size() != 3 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("the solution has " + std::to_string(solution.u.size()) + " values for " +
                     std::to_string(mesh.num_vertices()) + " vertices (3 per vertex)");
  // the folder changes at once, in commit(), or not at all; a plane's names and an earlier
  // path's frames are ours too
  const BasicPathSolution<3>* path = path_of<3>(info);
  detail::OutputRun run(dir, all_outputs_3d(), all_outputs(), wanted, info,
                        path ? frame_files(*path) : std::vector<std::string>());
  auto result = [&](const RunInfo& listed) { return result_json(mesh, solution, listed); };
  detail::write_solve_files(run, mesh, materials, solution, info, result);
  run.write("contact-surface.vtu", [&](std::ostream& os) { write_contact_surface_vtu(os, mesh, contact_faces, solution); });
  run.write("scene.toml", [&](std::ostream& os) { os << info.scene_toml; });
  write_path_files<Mesh3D, 3>(run.transaction(), dir, mesh, path, [&run](const std::string& n) { return run.want(n); },
                              [&](std::ostream& os, const ContactSolution3D& frame) { write_vtu(os, mesh, materials, frame); },
                              run.report());
  // the pictures: one that cannot be drawn is skipped with its reason, never an error
  run.draw([&](std::vector<Figure>& figures) {
    OutputReport& report = run.report();
    if (run.want("pressure.png") && solution.contact.empty()) report.skipped.push_back("pressure.png: no contact boundary");
    if (run.want("deformed.png")) figures.push_back(deformed_figure_3d(mesh, solution, info));
    if (run.want("path.png") && !path) report.skipped.push_back("path.png: not a loading path");
    if (run.want("path.png") && path) figures.push_back(path_figure(*path, info));
    if (run.want("pressure.png") && !solution.contact.empty())
      figures.push_back(pressure_figure(mesh, contact_faces, solution, info));
  });
  return run.finish(result);
}

}  // namespace hemivem::app
