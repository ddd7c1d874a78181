#include <hemivem/app/outputs.hpp>
#include <hemivem/app/path.hpp>

#include "output_run.hpp"
#include "path_outputs.hpp"
#include "result_json_common.hpp"
#include <hemivem/app/figures.hpp>
#include <hemivem/app/text_writer.hpp>
#include <hemivem/app/vtu.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/uniqueness.hpp>

#include <hemivem/support/atomic_file.hpp>
#include <hemivem/support/output_folder.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <random>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>

#include <unistd.h>

namespace hemivem::app {

const char* version() { return HEMIVEM_VERSION; }

namespace fs = std::filesystem;

namespace {

/// A number for JSON: non-finite values become null (JSON has no inf or NaN).



nlohmann::json pair(const Vec2& v) { return {number(v.x()), number(v.y())}; }

/// result.json's "forces": the applied load, the reactions by part, the contact resultant and
/// the relative residual of their balance.
nlohmann::json forces_json(const ForceBalance& b) {
  nlohmann::json reactions = nlohmann::json::object();
  for (const auto& r : b.reactions) reactions[r.name] = pair(r.force);
  return {{"applied", pair(b.applied)},
          {"reactions", std::move(reactions)},
          {"contact", pair(b.contact)},
          {"balance_residual", number(b.residual())}};
}

/// adapt.png: the relative estimate of every step of an adaptive solve against its unknowns
/// and its elapsed time.
Figure adapt_figure(const RunInfo& info) {
  ConvergenceSeries adaptive;
  adaptive.name = "adaptive (estimate)";
  for (const auto& step : info.adapt.at("steps")) {
    if (!step.at("estimate").is_number()) continue;
    adaptive.unknowns.push_back(step.at("unknowns").get<double>());
    adaptive.seconds.push_back(step.at("elapsed").get<double>());
    adaptive.error.push_back(step.at("estimate").get<double>());
  }
  return convergence_figure({adaptive}, "adaptive refinement: " + info.scene_name);
}

/// The plots of a solve (OutputRun::draw): those wanted, and the reason for each that cannot be
/// made in `report`.
void solve_figures(std::vector<Figure>& figures, const Mesh& mesh, const ContactSolution& solution, const RunInfo& info,
                   const detail::OutputRun& run, OutputReport& report) {
  auto want = [&run](const std::string& name) { return run.want(name); };
  if (want("u_nu.png") && solution.contact.empty()) report.skipped.push_back("u_nu.png: no contact boundary");
  if (want("u_nu.png") && !solution.contact.empty()) figures.push_back(u_nu_figure(mesh, solution, info));
  if (want("deformed.png")) figures.push_back(deformed_figure(mesh, solution, info));
  if (want("error.png") && !info.error_estimate) report.skipped.push_back("error.png: no error estimate");
  if (want("error.png") && info.error_estimate)
    figures.push_back(indicator_figure(mesh, info.error_estimate->indicators, info));
  if (want("mesh.png"))
    figures.push_back(mesh_figure(mesh, info, "mesh, " + std::to_string(mesh.num_elements()) + " elements"));
  if (want("adapt.png") && info.adapt.is_null()) report.skipped.push_back("adapt.png: not an adaptive solve");
  if (want("adapt.png") && !info.adapt.is_null()) figures.push_back(adapt_figure(info));
  if (want("path.png") && !path_of<2>(info)) report.skipped.push_back("path.png: not a loading path");
  if (want("path.png") && path_of<2>(info)) figures.push_back(path_figure(*path_of<2>(info), info));
}

}  // namespace

bool has_tangential(const ContactSolution& s) {
  return std::any_of(s.contact.begin(), s.contact.end(), [](const ContactNode& n) { return n.friction_state != FrictionState::none; });
}

std::vector<std::array<int, 2>> contact_lines(const Mesh& mesh, const ContactSolution& sol) {
  std::vector<char> on(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (const auto& n : sol.contact) on[static_cast<std::size_t>(n.vertex)] = 1;
  std::vector<std::array<int, 2>> lines;
  if (sol.contact.empty()) return lines;
  for (int e : mesh.boundary_edges()) {
    const auto& edge = mesh.edge(e);
    if (on[static_cast<std::size_t>(edge.v0)] && on[static_cast<std::size_t>(edge.v1)]) lines.push_back({edge.v0, edge.v1});
  }
  return lines;
}

nlohmann::json result_json(const Mesh& mesh, const ContactSolution& s, const RunInfo& info) {
  using nlohmann::json;
  json j = detail::result_json_common(s, info, 2);
  j["held_by_contact"] = s.held_by_contact;
  j["condition_estimate"] = number(s.condition_estimate);
  j["mesh"] = {{"description", info.mesh},
               {"vertices", mesh.num_vertices()},
               {"elements", mesh.num_elements()},
               {"dofs", info.dofs >= 0 ? info.dofs : 2 * mesh.num_vertices()},
               {"h", mesh.h()}};
  const bool tangential = has_tangential(s);
  json contact = json::array();
  json friction_states = json::object();
  for (const auto& n : s.contact) {
    json node{{"vertex", n.vertex},
              {"x", n.x.x()},
              {"y", n.x.y()},
              {"u_nu", number(n.u_nu)},
              {"law_force", number(n.law_force)},
              {"reaction", number(n.reaction)},
              {"pressure", number(n.pressure())},
              {"gap", number(n.gap)},
              {"normal", {number(n.normal.x()), number(n.normal.y())}},
              {"state", to_string(n.state)},
              {"part", contact_part_name(s, n)}};
    if (tangential && n.friction_state != FrictionState::none) {
      node["u_tau"] = number(n.u_tau);
      node["friction_force"] = number(n.friction_force);
      node["friction_traction"] = number(n.friction_force / n.weight);
      node["friction_state"] = to_string(n.friction_state);
      friction_states[to_string(n.friction_state)] = friction_states.value(to_string(n.friction_state), 0) + 1;
    }
    contact.push_back(std::move(node));
  }
  j["contact"] = std::move(contact);
  j["friction"] = tangential ? json{{"law", info.friction_law.empty() ? json(nullptr) : json(info.friction_law)}, {"nodes", friction_states}} : json(nullptr);
  const Vec2 force = s.contact_force();
  j["contact_force"] = {number(force.x()), number(force.y())};
  j["forces"] = forces_json(s.forces);
  const ContactZone zone = contact_zone(s);
  j["contact_zone"] = zone.nodes == 0 ? json(nullptr)
                                      : json{{"nodes", zone.nodes},
                                             {"length", number(zone.length)},
                                             {"x", {number(zone.lower.x()), number(zone.upper.x())}},
                                             {"y", {number(zone.lower.y()), number(zone.upper.y())}}};
  j["adapt"] = info.adapt.is_null() ? json(nullptr) : info.adapt;
  j["path"] = path_of<2>(info) ? path_summary_json(*path_of<2>(info)) : json(nullptr);
  return j;
}

nlohmann::json error_estimate_json(const ErrorEstimate& e) {
  nlohmann::json parts = nlohmann::json::object();
  for (const auto& [name, value] : e.parts) parts[name] = number(value);
  return {{"energy", number(e.energy)},
          {"norm", number(e.norm)},
          {"relative", number(e.relative)},
          {"parts", std::move(parts)}};
}

const std::vector<std::string>& all_outputs() {
  static const std::vector<std::string> names{"result.json",  "contact.csv",      "displacement.csv",      "history.csv",
                                              "solution.vtu", "scene.toml",       "mesh.poly2d",           "u_nu.png",
                                              "deformed.png", "error.png",        "mesh.png",              "adapt.png",
                                              "path.json",    "path-contact.csv", "path-displacement.csv", "solution.pvd",
                                              "path.png"};
  return names;
}

namespace {

/// Makes and removes a file (or, with `folder`, a folder) in `dir`: access() grants root
/// everything, even in a folder such as /sys/kernel where nothing can be made. Empty when it
/// works, else the reason.
std::string probe_writing(const fs::path& dir, bool folder) {
  std::string name = (dir / ".hemivem-probe-XXXXXX").string();
  if (folder) {
    if (::mkdtemp(name.data()) == nullptr) return std::strerror(errno);
    ::rmdir(name.c_str());
    return {};
  }
  const int fd = ::mkstemp(name.data());
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  ::unlink(name.c_str());
  return {};
}

}  // namespace

void check_output_folder(const fs::path& dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) throw InputError("the output folder is a file, not a folder", dir.string());
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw InputError("cannot write into the output folder: " + std::string(std::strerror(errno)), dir.string());
    if (const std::string why = probe_writing(dir, false); !why.empty())
      throw InputError("cannot write into the output folder: " + why, dir.string());
    return;
  }
  // the folder will be made: its nearest existing ancestor must be a writable folder
  fs::path p = fs::absolute(dir, ec).parent_path();
  while (!p.empty() && !fs::exists(fs::status(p, ec))) {
    if (p == p.root_path()) break;
    p = p.parent_path();
  }
  if (!fs::is_directory(fs::status(p, ec)))
    throw InputError("cannot make the output folder: " + p.string() + " is not a folder", dir.string());
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError("cannot make the output folder: cannot write into " + p.string() + ": " + std::strerror(errno),
                     dir.string());
  if (const std::string why = probe_writing(p, true); !why.empty())
    throw InputError("cannot make the output folder: cannot write into " + p.string() + ": " + why, dir.string());
}

OutputReport write_outputs(const fs::path& dir, const Mesh& mesh, const MaterialTable& materials,
                           const ContactSolution& solution, const RunInfo& info, const std::vector<std::string>& wanted) {
  detail::require_known_outputs(wanted, all_outputs(), "");
  if (solution.u.size() != 2 * mesh.num_vertices())
    throw InputError("the solution has " + std::to_string(solution.u.size()) + " values for " +
                     std::to_string(mesh.num_vertices()) + " vertices");
  // the folder changes at once, in commit(), or not at all; a solid's names and an earlier
  // path's frames are ours too
  const PathSolution* path = path_of<2>(info);
  detail::OutputRun run(dir, all_outputs(), all_outputs_3d(), wanted, info, path ? frame_files(*path) : std::vector<std::string>());
  auto result = [&](const RunInfo& listed) { return result_json(mesh, solution, listed); };
  detail::write_solve_files(run, mesh, materials, solution, info, result);
  run.write("scene.toml", [&](std::ostream& os) { os << info.scene_toml; });
  run.write("mesh.poly2d", [&](std::ostream& os) {
    write_poly2d(os, mesh, {"the mesh of " + info.mesh, "regions and edge groups are not part of this format"});
  });
  write_path_files<Mesh, 2>(run.transaction(), dir, mesh, path, [&run](const std::string& n) { return run.want(n); },
                            [&](std::ostream& os, const ContactSolution& frame) { write_vtu(os, mesh, materials, frame, nullptr); },
                            run.report());
  run.draw([&](std::vector<Figure>& figures) { solve_figures(figures, mesh, solution, info, run, run.report()); });
  return run.finish(result);
}

}  // namespace hemivem::app
