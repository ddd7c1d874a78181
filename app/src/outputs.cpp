// The output folder of a solve of a plane or a solid body (outputs.hpp): result.json, the list
// of outputs and the folder's transaction are written once for both dimensions; each has its
// own files (a plane's mesh.poly2d, a solid's contact-surface.vtu) and figures.
#include <hemivem/app/outputs.hpp>

#include "figure_style.hpp"
#include "output_run.hpp"
#include "path_outputs.hpp"
#include "result_json_common.hpp"

#include <hemivem/app/figures.hpp>
#include <hemivem/app/format.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/vtu.hpp>
#include <hemivem/error.hpp>
#include <hemivem/every_process.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/support/output_folder.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include <unistd.h>

namespace hemivem::app {

const char* version() { return HEMIVEM_VERSION; }

namespace fs = std::filesystem;

namespace {

/// result.json's "forces": the applied load, the reactions by part, the contact resultant and
/// the relative residual of their balance.
template <class Vector>
nlohmann::json forces_json(const BasicForceBalance<Vector>& b) {
  nlohmann::json reactions = nlohmann::json::object();
  for (const auto& r : b.reactions) reactions[r.name] = vector_json(r.force);
  return {{"applied", vector_json(b.applied)},
          {"reactions", std::move(reactions)},
          {"contact", vector_json(b.contact)},
          {"balance_residual", number(b.residual())}};
}

/// adapt.png: the relative estimate of every step of an adaptive solve against its unknowns
/// and its elapsed time, for a body of dimension `dimension`.
Figure adapt_figure(const RunInfo& info, int dimension) {
  ConvergenceSeries adaptive;
  adaptive.name = "adaptive (estimate)";
  for (const auto& step : info.adapt.at("steps")) {
    if (!step.at("estimate").is_number()) continue;
    adaptive.unknowns.push_back(step.at("unknowns").get<double>());
    adaptive.seconds.push_back(step.at("elapsed").get<double>());
    adaptive.error.push_back(step.at("estimate").get<double>());
  }
  return convergence_figure({adaptive}, "adaptive refinement: " + info.scene_name, "adapt.png", dimension);
}

/// path.png of a run with a loading path of a body of dimension dim (`files` wrote its files);
/// without one the reason in `report`.
template <int dim>
void path_figures(std::vector<Figure>& figures, const RunInfo& info, const PathFiles<dim>* files,
                  const detail::OutputRun& run, OutputReport& report) {
  if (run.want("path.png") && !files) report.skipped.push_back("path.png: not a loading path");
  if (run.want("path.png") && files) figures.push_back(files->figure(info));
}

}  // namespace

std::vector<std::array<int, 2>> contact_lines(const Mesh& mesh, const ContactSolution& sol) {
  return detail::contact_lines(mesh.num_vertices(), detail::plane_edges(mesh), sol);
}

MeshSize mesh_size(const Mesh& mesh) { return {mesh.num_vertices(), mesh.num_elements(), mesh.num_edges(), mesh.h()}; }
MeshSize mesh_size(const Mesh3D& mesh) { return {mesh.num_vertices(), mesh.num_cells(), mesh.num_faces(), mesh.h()}; }

namespace {

/// result.json's "mesh": how it was made, its size and h (the whole mesh's, info.of_pieces, when
/// `mesh` is a piece of it); a solid's also its faces.
template <class MeshType>
nlohmann::json mesh_json(const MeshType& mesh, const RunInfo& info) {
  constexpr int dim = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;
  const MeshSize size = info.of_pieces ? info.of_pieces->size : mesh_size(mesh);
  nlohmann::json j{{"description", info.mesh}, {"vertices", size.vertices}, {"elements", size.cells}};
  if constexpr (dim == 3) j["faces"] = size.facets;
  j["dofs"] = info.dofs >= 0 ? info.dofs : dim * size.vertices;
  j["h"] = size.h;
  j["pieces"] = info.mesh_pieces;
  return j;
}

/// A contact node's position in result.json: a plane's "x" and "y", a solid's "x" [x, y, z].
void put_position(nlohmann::json& node, const Vec2& x) {
  node["x"] = x.x();
  node["y"] = x.y();
}
void put_position(nlohmann::json& node, const Vec3& x) { node["x"] = vector_json(x); }

/// result.json's "contact": one entry per contact node; with friction (tangential) its
/// friction values, counted by state in `friction_states`.
template <int dim>
nlohmann::json contact_json(const BasicContactSolution<dim>& s, bool tangential, nlohmann::json& friction_states) {
  nlohmann::json contact = nlohmann::json::array();
  for (const auto& n : s.contact) {
    nlohmann::json node{{"vertex", n.vertex},
                        {"u_nu", number(n.u_nu)},
                        {"law_force", number(n.law_force)},
                        {"reaction", number(n.reaction)},
                        {"pressure", number(n.pressure())},
                        {"gap", number(n.gap)},
                        {"normal", vector_json(n.normal)},
                        {"state", to_string(n.state)},
                        {"part", contact_part_name(s, n)}};
    put_position(node, n.x);
    if (tangential && n.friction_state != FrictionState::none) {
      // a plane's along tau; a solid's as vectors in the tangent plane
      if constexpr (dim == 2) {
        node["u_tau"] = number(n.u_tau);
        node["friction_force"] = number(n.friction_force);
        node["friction_traction"] = number(n.friction_force / n.weight);
      } else {
        node["u_tau"] = vector_json(n.u_tangential);
        node["friction_force"] = vector_json(n.friction_vector);
        node["friction_traction"] = vector_json(Vec3(n.friction_vector / n.weight));
      }
      node["friction_state"] = to_string(n.friction_state);
      friction_states[to_string(n.friction_state)] = friction_states.value(to_string(n.friction_state), 0) + 1;
    }
    contact.push_back(std::move(node));
  }
  return contact;
}

/// result.json's "contact_zone": the nodes in compression, their length (a solid's area) and
/// their bounding box; null without one.
template <int dim>
nlohmann::json contact_zone_json(const BasicContactSolution<dim>& s) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  const BasicContactZone<dim> zone = contact_zone(s);
  if (zone.nodes == 0) return nullptr;
  nlohmann::json j{{"nodes", zone.nodes}, {dim == 2 ? "length" : "area", number(zone.length)}};
  for (int c = 0; c < dim; ++c) j[axes[c]] = {number(zone.lower(c)), number(zone.upper(c))};
  return j;
}

template <class MeshType, int dim>
nlohmann::json result_json_of(const MeshType& mesh, const BasicContactSolution<dim>& s, const RunInfo& info) {
  using nlohmann::json;
  json j = detail::result_json_common(s, info, dim);
  j["held_by_contact"] = s.held_by_contact;
  j["condition_estimate"] = number(s.condition_estimate);
  j["mesh"] = mesh_json(mesh, info);
  const bool tangential = has_tangential(s);
  json friction_states = json::object();
  j["contact"] = contact_json(s, tangential, friction_states);
  j["friction"] = tangential ? json{{"law", info.friction_law.empty() ? json(nullptr) : json(info.friction_law)},
                                    {"models", info.friction_models},
                                    {"nodes", friction_states}}
                             : json(nullptr);
  j["contact_force"] = vector_json(s.contact_force());
  j["forces"] = forces_json(s.forces);
  j["contact_zone"] = contact_zone_json(s);
  j["bodies"] = info.bodies_record.is_null() ? json(nullptr) : info.bodies_record;
  j["adapt"] = info.adapt.is_null() ? json(nullptr) : info.adapt;
  j["path"] = path_of<dim>(info) ? path_summary_json(*path_of<dim>(info)) : json(nullptr);
  return j;
}

}  // namespace

nlohmann::json result_json(const Mesh& mesh, const ContactSolution& s, const RunInfo& info) {
  return result_json_of(mesh, s, info);
}

nlohmann::json result_json(const Mesh3D& mesh, const ContactSolution3D& s, const RunInfo& info) {
  return result_json_of(mesh, s, info);
}

nlohmann::json error_estimate_json(const ErrorEstimate& e) {
  nlohmann::json parts = nlohmann::json::object();
  for (const auto& [name, value] : e.parts) parts[name] = number(value);
  return {{"energy", number(e.energy)},
          {"norm", number(e.norm)},
          {"relative", number(e.relative)},
          {"parts", std::move(parts)}};
}

namespace {

/// What a run on the processes' pieces of the mesh makes a file from: not the pieces (`no`: an
/// adaptive solve's files and a plane's mesh.poly2d, of the whole mesh), the first process's
/// piece and the whole solution every process holds (`made`), or besides what the processes
/// gathered of their pieces for the file alone (`gathered`: WholeOfPieces::serves).
enum class FromPieces { no, made, gathered };

/// When a solve writes an output whose key its scene's output.write names: always, with contact
/// only, in an adaptive solve only, or as a loading path's file (path_files).
enum class When { always, contact, adapt, path };

/// Every name in the order a run writes it, with the dimensions that write it, what a run on
/// pieces makes it from, the key of output.write that asks for it (none: written whenever
/// `when` holds) and when.
struct Output {
  const char* name;
  bool plane, solid;
  FromPieces pieces;
  const char* key;
  When when;
};
using enum FromPieces;
constexpr Output outputs[] = {
    {"result.json", true, true, made, "result-json", When::always},
    {"contact.csv", true, true, made, "contact-csv", When::contact},
    {"displacement.csv", true, true, made, "displacement-csv", When::always},
    {"stress.csv", true, true, gathered, "stress-csv", When::always},
    {"history.csv", true, true, made, "history-csv", When::contact},
    {"solution.vtu", true, true, made, "vtu", When::always},
    {"contact-surface.vtu", false, true, gathered, "vtu", When::contact},
    {"scene.toml", true, true, made, nullptr, When::always},
    {"mesh.poly2d", true, false, no, nullptr, When::adapt},
    {"u_nu.png", true, false, gathered, "u-nu-png", When::contact},
    {"deformed.png", true, true, gathered, "deformed-png", When::always},
    {"error.png", true, false, gathered, "error-png", When::always},
    {"mesh.png", true, false, no, "mesh-png", When::adapt},
    {"adapt.png", true, true, no, "adapt-png", When::adapt},
    {"adapt.pvd", true, true, no, "vtu", When::adapt},
    {"pressure.png", false, true, gathered, "pressure-png", When::contact},
    {"path.json", true, true, made, nullptr, When::path},
    {"path-contact.csv", true, true, made, nullptr, When::path},
    {"path-displacement.csv", true, true, made, nullptr, When::path},
    {"solution.pvd", true, true, made, nullptr, When::path},
    {"path.png", true, true, made, nullptr, When::path}};

/// The output `name` of a body of dimension `dim`; null when it writes none of that name.
const Output* output_named(const std::string& name, int dim) {
  for (const Output& o : outputs)
    if (name == o.name && (dim == 3 ? o.solid : o.plane)) return &o;
  return nullptr;
}

}  // namespace

const std::vector<std::string>& all_outputs(int dim) {
  auto of = [](bool solid) {
    std::vector<std::string> names;
    for (const Output& o : outputs)
      if (solid ? o.solid : o.plane) names.emplace_back(o.name);
    return names;
  };
  static const std::vector<std::string> plane = of(false), solid = of(true);
  if (dim != 2 && dim != 3) throw InputError("no outputs for a body of dimension " + std::to_string(dim));
  return dim == 2 ? plane : solid;
}

bool detail::made_from_pieces(const std::string& file, int dim) {
  const Output* o = output_named(file, dim);
  return o && o->pieces != FromPieces::no;
}

std::vector<std::string> wanted_files(const Scene& scene, bool has_contact) {
  const int dim = scene.dimension();
  const std::vector<std::string> path = path_files(scene, has_contact);
  std::vector<std::string> files;
  for (const Output& o : outputs) {
    if (!(dim == 3 ? o.solid : o.plane)) continue;
    if (o.when == When::path) {
      if (std::find(path.begin(), path.end(), o.name) != path.end()) files.emplace_back(o.name);
      continue;
    }
    if ((o.when == When::contact && !has_contact) || (o.when == When::adapt && !scene.adapt)) continue;
    if (!o.key || scene.writes(o.key)) files.emplace_back(o.name);
  }
  return files;
}

bool detail::gathered_for_itself(const std::string& file) {
  for (const int dim : {2, 3})
    if (const Output* o = output_named(file, dim); o && o->pieces == FromPieces::gathered) return true;
  return false;
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

namespace {

/// The figures of a plane's solve (OutputRun::draw): those wanted, and the reason for each that
/// cannot be made in `report`.
void solve_figures(std::vector<Figure>& figures, const Mesh& mesh, const ContactSolution& solution, const RunInfo& info,
                   const std::vector<int>*, const PathFiles<2>* path, const detail::OutputRun& run, OutputReport& report) {
  auto want = [&run](const std::string& name) { return run.want(name); };
  // `mesh` a piece: the edges and elements gathered from every process's (info.of_pieces)
  const WholeOfPieces* whole = info.of_pieces.get();
  if (want("u_nu.png") && solution.contact.empty()) report.skipped.push_back("u_nu.png: no contact boundary");
  if (want("u_nu.png") && !solution.contact.empty())
    figures.push_back(whole ? u_nu_figure(mesh, *whole, solution, info) : u_nu_figure(mesh, solution, info));
  if (want("deformed.png"))
    figures.push_back(whole ? deformed_figure(mesh, *whole, solution, info) : deformed_figure(mesh, solution, info));
  if (want("error.png") && !info.error_estimate) report.skipped.push_back("error.png: no error estimate");
  if (want("error.png") && info.error_estimate)
    figures.push_back(whole ? indicator_figure(mesh, *whole, info.error_estimate->indicators, info)
                            : indicator_figure(mesh, info.error_estimate->indicators, info));
  if (want("mesh.png"))
    figures.push_back(mesh_figure(mesh, info, "mesh, " + std::to_string(mesh.num_elements()) + " elements"));
  if (want("adapt.png") && info.adapt.is_null()) report.skipped.push_back("adapt.png: not an adaptive solve");
  if (want("adapt.png") && !info.adapt.is_null()) figures.push_back(adapt_figure(info, 2));
  path_figures<2>(figures, info, path, run, report);
}

/// The figures of a solid's solve: deformed.png, path.png, then pressure.png over the contact
/// faces `faces`.
void solve_figures(std::vector<Figure>& figures, const Mesh3D& mesh, const ContactSolution3D& solution,
                   const RunInfo& info, const std::vector<int>* faces, const PathFiles<3>* path,
                   const detail::OutputRun& run, OutputReport& report) {
  if (run.want("pressure.png") && solution.contact.empty()) report.skipped.push_back("pressure.png: no contact boundary");
  // `mesh` a piece: the faces gathered from every process's (info.of_pieces)
  if (run.want("deformed.png"))
    figures.push_back(info.of_pieces ? deformed_figure(mesh, info.of_pieces->boundary, solution, info)
                                     : deformed_figure(mesh, solution, info));
  if (run.want("adapt.png") && info.adapt.is_null()) report.skipped.push_back("adapt.png: not an adaptive solve");
  if (run.want("adapt.png") && !info.adapt.is_null()) figures.push_back(adapt_figure(info, 3));
  path_figures<3>(figures, info, path, run, report);
  if (run.want("pressure.png") && !solution.contact.empty())
    figures.push_back(info.of_pieces ? pressure_figure(mesh, info.of_pieces->contact_surface, solution, info)
                                     : pressure_figure(mesh, *faces, solution, info));
}

/// The frames of a path written whole into `tx`: solution-0007.vtu of the whole mesh.
template <class MeshType, int dim>
typename PathFiles<dim>::WriteFrame whole_frames(OutputTransaction& tx, const MeshType& mesh, const MaterialTable& materials) {
  return [&tx, &mesh, &materials](int step, const BasicContactSolution<dim>& frame) {
    const std::string name = frame_file(step);
    tx.write(name, [&](std::ostream& os) { write_vtu(os, mesh, materials, frame, nullptr); });
    return std::vector<std::string>{name};
  };
}

/// The output folder of a solve of either dimension: the files every solve writes, a solid's
/// contact-surface.vtu (over `contact_faces`), scene.toml, a plane's mesh.poly2d, the path's
/// files and the figures, as one transaction: `streamed`'s, opened before its path ran and
/// holding its steps' files, or a new one.
template <class MeshType, int dim>
OutputReport write_outputs_of(const fs::path& dir, const MeshType& mesh, const MaterialTable& materials,
                              const std::vector<int>* contact_faces, const BasicContactSolution<dim>& solution,
                              const RunInfo& info, const std::vector<std::string>& wanted,
                              detail::PathOutput<dim>* streamed = nullptr, detail::OutputRun* opened = nullptr,
                              const SolutionVtu* pieces = nullptr) {
  detail::require_known_outputs(wanted, all_outputs(dim), dim == 3 ? " of a three-dimensional solve" : "");
  if (solution.u.size() != dim * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("the solution has " + std::to_string(solution.u.size()) + " values for " +
                     std::to_string(mesh.num_vertices()) + " vertices" + (dim == 3 ? " (3 per vertex)" : ""));
  // the folder changes at once, in commit(), or not at all; the other dimension's names and an
  // earlier path's frames are ours too
  const BasicPathSolution<dim>* path = path_of<dim>(info);
  std::optional<detail::OutputRun> own;
  if (streamed) {
    streamed->run.list(info, streamed->files.frames());
  } else if (!opened) {
    own.emplace(dir, all_outputs(dim), all_outputs(5 - dim), wanted, info, path ? frame_files(*path) : std::vector<std::string>());
  }
  detail::OutputRun& run = streamed ? streamed->run : opened ? *opened : *own;
  auto result = [&](const RunInfo& listed) { return result_json(mesh, solution, listed); };
  detail::write_solve_files(run, mesh, materials, solution, info, result, pieces);
  if constexpr (dim == 3)
    run.write("contact-surface.vtu", [&](std::ostream& os) {
      if (info.of_pieces)  // `mesh` is a piece: the faces gathered from every process's
        write_contact_surface_vtu(os, mesh, info.of_pieces->contact_surface, solution);
      else
        write_contact_surface_vtu(os, mesh, *contact_faces, solution);
    });
  run.write("scene.toml", [&](std::ostream& os) { os << info.scene_toml; });
  if constexpr (dim == 2) {
    run.write("mesh.poly2d", [&](std::ostream& os) {
      write_poly2d(os, mesh, {"the mesh of " + info.mesh, "regions and edge groups are not part of this format"});
    });
  }
  detail::write_adapt_steps(run, info);
  std::unique_ptr<PathFiles<dim>> own_files;
  const PathFiles<dim>* files = nullptr;
  if (streamed) {
    if (!path) throw InternalError("a path's outputs without its path");
    streamed->files.finish(*path, run.report());
    files = &streamed->files;
  } else {
    own_files = write_path_files<MeshType, dim>(
        run.transaction(), mesh, path, [&run](const std::string& n) { return run.want(n); },
        whole_frames<MeshType, dim>(run.transaction(), mesh, materials), run.report(), info.bodies);
    files = own_files.get();
  }
  // the figures: one that cannot be drawn is skipped with its reason, never an error
  run.draw([&](std::vector<Figure>& figures) {
    solve_figures(figures, mesh, solution, info, contact_faces, files, run, run.report());
  });
  return run.finish(result);
}

}  // namespace

OutputReport write_outputs(const fs::path& dir, const Mesh& mesh, const MaterialTable& materials,
                           const ContactSolution& solution, const RunInfo& info, const std::vector<std::string>& wanted) {
  return write_outputs_of(dir, mesh, materials, nullptr, solution, info, wanted);
}

OutputReport write_outputs(const fs::path& dir, const Mesh3D& mesh, const MaterialTable& materials,
                           const std::vector<int>& contact_faces, const ContactSolution3D& solution,
                           const RunInfo& info, const std::vector<std::string>& wanted) {
  return write_outputs_of(dir, mesh, materials, &contact_faces, solution, info, wanted);
}

namespace detail {

namespace {


/// The staging folder of the first process's transaction `tx` (null there when it could not
/// open the folder; ignored on the others), told to every process: empty when it is not open.
/// Collective over `rows` (a row per process).
fs::path staging_of_first(const RowDistribution& rows, const OutputTransaction* tx) {
  return hemivem::detail::text_of(rows.all_gather(hemivem::detail::bytes_of(tx ? tx->staging().string() : "")));
}

/// Collective over `rows`: an InputError, on the process that could not write its piece (`why`
/// says why, empty when it could) and on the first process, naming the piece (`piece_of(k)` the
/// piece of process k); the folder `dir` keeps its previous outputs.
void require_pieces_written(const RowDistribution& rows, const std::string& why,
                            const std::function<std::string(int)>& piece_of, const fs::path& dir) {
  const Eigen::VectorXd unwritten = rows.all_gather(Eigen::VectorXd::Constant(1, why.empty() ? 0.0 : 1.0));
  const std::string reach = " (each process writes its pieces of the solution into the output folder's transaction, "
                            "so the folder is on a file system every process reaches); " +
                            previous_outputs_kept(dir);
  if (!why.empty())
    throw InputError("process " + std::to_string(rows.rank()) + " could not write " + piece_of(rows.rank()) + ": " + why + reach,
                     dir.string());
  if (rows.rank() != 0) return;
  for (Eigen::Index k = 0; k < unwritten.size(); ++k)
    if (unwritten(k) != 0.0)
      throw InputError("process " + std::to_string(k) + " could not write " + piece_of(static_cast<int>(k)) + reach,
                       dir.string());
}

/// Collective over `rows`: this process's piece of solution.pvtu (vtu_piece_file of its rank,
/// SolutionVtu::write_share of `share`), and of each body's file of a scene of several
/// (body_piece_file), written into `staging`, the first process's transaction's, with the error
/// indicators of the whole mesh's cells, or of the piece's that this process kept
/// (`piece_cells`); `vtu` holds its arrays, from which the first writes solution.pvtu. Then
/// every process learns whether each could (require_pieces_written).
template <class MeshType, int dim>
void write_solution_piece(const RowDistribution& rows, const fs::path& staging, const MeshType& mesh,
                          const MaterialTable& materials, const BasicContactSolution<dim>& solution, const RunInfo& info,
                          const VertexShare& share, const std::vector<int>& piece_cells, const fs::path& dir,
                          std::optional<SolutionVtu>& vtu) {
  if (info.vtu_pieces != rows.size())
    throw InternalError("solution.pvtu of " + std::to_string(info.vtu_pieces) + " pieces written by " +
                        std::to_string(rows.size()) + " processes");
  const std::vector<double>* indicators = info.error_estimate ? &info.error_estimate->indicators : nullptr;
  std::vector<double> of_piece;
  std::string file = vtu_piece_file(rows.rank()), why;
  try {
    if (indicators && !piece_cells.empty()) {
      for (const int c : piece_cells) of_piece.push_back(indicators->at(static_cast<std::size_t>(c)));
      indicators = &of_piece;
    }
    vtu.emplace(mesh, materials, solution, indicators);
    write_file_atomically(staging / file, [&](std::ostream& os) { vtu->write_share(os, share); });
    for (const BodyRange& body : info.bodies) {  // several bodies: the piece of each body's file too
      file = body_piece_file(body.name, rows.rank());
      write_file_atomically(staging / file, [&](std::ostream& os) { vtu->write_share(os, share, &body); });
    }
  } catch (const std::exception& e) {
    why = e.what();
  }
  require_pieces_written(
      rows, why,
      [&](int k) {
        return k == rows.rank() ? file : info.bodies.empty() ? vtu_piece_file(k) : std::string("its pieces of the solution");
      },
      dir);
}

}  // namespace

template <class MeshType, int dim>
OutputReport write_outputs_in_pieces(const fs::path& dir, const MeshType& mesh, const MaterialTable& materials,
                                     const std::vector<int>* contact_faces, const BasicContactSolution<dim>& solution,
                                     const RunInfo& info, const std::vector<std::string>& wanted,
                                     const VertexShare& share, const std::vector<int>& piece_cells) {
  const ProcessWorld world = krylov_world();
  const bool writer = world.rank == 0;
  if (info.of_pieces)  // the first process holds its piece: what it cannot make from it (the same `wanted` on every process)
    for (const std::string& file : wanted) {
      if (!made_from_pieces(file, dim))
        throw InputError(file + " is drawn from the whole mesh, which no process made for this solve on pieces: name it in "
                                "output.write before the solve",
                         dir.string());
      if (!info.of_pieces->serves(file))
        throw InputError(file + " is made from what the processes gather of their pieces at the solve for the files "
                                "output.write names: name it there before the solve",
                         dir.string());
    }
  if (std::find(wanted.begin(), wanted.end(), "solution.vtu") == wanted.end()) {  // nothing in pieces: as in one process
    if (!writer) return {};
    check_output_folder(dir);
    return write_outputs_of(dir, mesh, materials, contact_faces, solution, info, wanted);
  }
  const std::unique_ptr<RowDistribution> rows = process_rows();  // the collectives below
  // the first process opens the folder's transaction, and every process learns its staging folder
  std::optional<OutputRun> run;
  std::exception_ptr failed;
  if (writer) {
    try {
      check_output_folder(dir);
      require_known_outputs(wanted, all_outputs(dim), dim == 3 ? " of a three-dimensional solve" : "");
      run.emplace(dir, all_outputs(dim), all_outputs(5 - dim), wanted, info, std::vector<std::string>());
    } catch (...) {
      failed = std::current_exception();
    }
  }
  const fs::path staging = staging_of_first(*rows, run ? &run->transaction() : nullptr);
  if (staging.empty()) {  // the folder could not be opened: the first process says why
    if (failed) std::rethrow_exception(failed);
    return {};
  }
  std::optional<SolutionVtu> vtu;
  write_solution_piece(*rows, staging, mesh, materials, solution, info, share, piece_cells, dir, vtu);
  if (!writer) return {};
  return write_outputs_of<MeshType, dim>(dir, mesh, materials, contact_faces, solution, info, wanted, nullptr, &*run,
                                         &*vtu);
}

template OutputReport write_outputs_in_pieces(const fs::path&, const Mesh&, const MaterialTable&, const std::vector<int>*,
                                              const ContactSolution&, const RunInfo&, const std::vector<std::string>&,
                                              const VertexShare&, const std::vector<int>&);
template OutputReport write_outputs_in_pieces(const fs::path&, const Mesh3D&, const MaterialTable&, const std::vector<int>*,
                                              const ContactSolution3D&, const RunInfo&, const std::vector<std::string>&,
                                              const VertexShare&, const std::vector<int>&);

template <int dim>
PathOutput<dim>::PathOutput(const fs::path& dir, const std::vector<std::string>& wanted, const std::vector<std::string>& frames,
                            const MeshType& mesh, const MaterialTable& materials, std::vector<std::string> parts,
                            std::vector<BodyRange> bodies)
    : run(dir, all_outputs(dim), all_outputs(5 - dim), wanted, 0, frames),
      files(
          run.transaction(), [this](const std::string& n) { return run.want(n); }, mesh, std::move(parts),
          [this, whole = whole_frames<MeshType, dim>(run.transaction(), mesh, materials)](
              int step, const BasicContactSolution<dim>& frame) {
            return frame_pieces ? frame_pieces->write(step, frame, &run.transaction()) : whole(step, frame);
          },
          std::move(bodies)) {
  require_known_outputs(wanted, all_outputs(dim), dim == 3 ? " of a three-dimensional solve" : "");
}

template <int dim>
FramePieces<dim>::FramePieces(const OutputTransaction* tx, const MeshType& mesh, const MaterialTable& materials,
                              VertexShare share)
    : rows_(process_rows()), mesh_(mesh), materials_(materials), share_(std::move(share)) {
  staging_ = staging_of_first(*rows_, tx);
}

template <int dim>
FramePieces<dim>::~FramePieces() = default;

template <int dim>
std::vector<std::string> FramePieces<dim>::write(int step, const BasicContactSolution<dim>& frame, OutputTransaction* tx) {
  const std::string file = frame_piece_file(step, rows_->rank());
  std::optional<SolutionVtu> vtu;
  if (failed_why_.empty()) {
    try {
      vtu.emplace(mesh_, materials_, frame, nullptr);
      write_file_atomically(staging_ / file, [&](std::ostream& os) { vtu->write_share(os, share_); });
    } catch (const std::exception& e) {
      failed_file_ = file;
      failed_why_ = e.what();
    }
  }
  std::vector<std::string> files = frame_files_of(step, rows_->size());
  if (tx && vtu) {
    const std::vector<std::string> named(files.begin(), files.end() - 1);
    tx->write(files.back(), [&](std::ostream& os) { vtu->write_pieces(os, named); });
  }
  return files;
}

template <int dim>
void FramePieces<dim>::require_written(const fs::path& dir) {
  require_pieces_written(
      *rows_, failed_why_,
      [this](int k) { return k == rows_->rank() ? failed_file_ : std::string("its pieces of the path's frames"); }, dir);
}

template class FramePieces<2>;
template class FramePieces<3>;

template <int dim>
void require_path_output_folder(const PathOutput<dim>& out, const fs::path& dir, const std::vector<std::string>* files) {
  std::error_code ec;
  const bool same = fs::weakly_canonical(dir, ec) == fs::weakly_canonical(out.run.dir(), ec);
  if (out.written)
    throw InputError("the loading path's outputs were written to " + out.run.dir().string() +
                         " as its steps were solved, and committed: a path writing as it runs is written once",
                     dir.string());
  if (!same || files)
    throw InputError("the loading path wrote its steps into the transaction of " + out.run.dir().string() +
                         " as it solved them and kept none: its outputs go there, all of them (solve without an "
                         "output folder to keep the steps)",
                     dir.string());
}

template void require_path_output_folder(const PathOutput<2>&, const fs::path&, const std::vector<std::string>*);
template void require_path_output_folder(const PathOutput<3>&, const fs::path&, const std::vector<std::string>*);

template struct PathOutput<2>;
template struct PathOutput<3>;

template <int dim>
OutputReport write_path_outputs(const fs::path& dir, const std::vector<std::string>* files, PathOutput<dim>* out,
                                FramePieces<dim>* pieces, const typename PathOutput<dim>::MeshType& mesh,
                                const MaterialTable& materials, const std::vector<int>* contact_faces,
                                const BasicContactSolution<dim>& solution, const RunInfo& info,
                                const std::vector<int>& piece_cells) {
  std::exception_ptr refused;
  if (out) {
    try {
      require_path_output_folder(*out, dir, files);
    } catch (...) {
      refused = std::current_exception();
    }
  }
  std::optional<SolutionVtu> vtu;
  if (pieces && info.vtu_pieces > 0) {  // the last step's solution.vtu in pieces, into the path's transaction
    // every process learns whether the first writes the outputs
    if (pieces->rows().all_gather(Eigen::VectorXd::Constant(1, refused ? 0.0 : 1.0))(0) == 0.0) {
      if (refused) std::rethrow_exception(refused);
      return {};
    }
    write_solution_piece(pieces->rows(), pieces->staging(), mesh, materials, solution, info, pieces->share(),
                         piece_cells, dir, vtu);
  }
  if (refused) std::rethrow_exception(refused);
  if (!out) return {};
  out->written = true;
  return write_outputs_of(out->run.dir(), mesh, materials, contact_faces, solution, info, {}, out, nullptr,
                          vtu ? &*vtu : nullptr);
}

template OutputReport write_path_outputs(const fs::path&, const std::vector<std::string>*, PathOutput<2>*, FramePieces<2>*,
                                         const Mesh&, const MaterialTable&, const std::vector<int>*,
                                         const ContactSolution&, const RunInfo&, const std::vector<int>&);
template OutputReport write_path_outputs(const fs::path&, const std::vector<std::string>*, PathOutput<3>*, FramePieces<3>*,
                                         const Mesh3D&, const MaterialTable&, const std::vector<int>*,
                                         const ContactSolution3D&, const RunInfo&, const std::vector<int>&);

}  // namespace detail

}  // namespace hemivem::app
