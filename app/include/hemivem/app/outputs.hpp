// The files a solve of a plane or a solid body leaves in its output folder (schema and formats:
// docs/reference/outputs.md): result.json, contact.csv, displacement.csv, stress.csv (stress.hpp),
// history.csv, solution.vtu (vtu.hpp; a solid's also contact-surface.vtu), scene.toml and the gnuplot figures
// (figures.hpp). One writer serves both dimensions; the plane and the solid each have their
// overload of result_json and write_outputs.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/stress.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/obstacle.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/estimate/error_estimate.hpp>
#include <hemivem/estimate/estimate_pieces.hpp>
#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem::app {

/// The version of hemivem ("0.1.0"), as result.json records it.
const char* version();

/// The size of a mesh as result.json's "mesh" and the summary report it (mesh_size).
struct MeshSize {
  int vertices = 0;
  int cells = 0;    ///< a plane's elements, a solid's cells
  int facets = 0;   ///< a plane's edges, a solid's faces
  double h = 0.0;   ///< the largest cell diameter
};
MeshSize mesh_size(const Mesh& mesh);
MeshSize mesh_size(const Mesh3D& mesh);

/// Vertex loops (a mesh's cells by their vertices) in one array: loop i is
/// vertices[offsets[i] .. offsets[i + 1]).
struct VertexLoops {
  std::vector<int> offsets{0};
  std::vector<int> vertices;
  std::size_t size() const noexcept { return offsets.size() - 1; }
  std::span<const int> operator[](std::size_t i) const noexcept {
    return {vertices.data() + offsets[i], static_cast<std::size_t>(offsets[i + 1] - offsets[i])};
  }
};

/// What the results need of a whole mesh that the processes hold in pieces (each piece holding
/// every vertex of the whole mesh, docs/cluster.md), gathered from the pieces by whole_of_pieces:
/// what the first process writes the results from, its mesh being its piece.
struct WholeOfPieces {
  MeshSize size;                     ///< the whole mesh's mesh_size
  std::optional<StressPeak> stress;  ///< its stress_peak (none where a stress is not finite)
  /// stress.csv's rows, on the first process: per cell of the whole mesh, in order, its
  /// centroid (dim values) and its projected stress xx, yy, zz, yz, xz, xy.
  std::vector<double> stress_rows;
  /// A solid's contact faces (contact_faces, part by part) as vertex loops, and the boundary
  /// facets (a solid's faces, a plane's edges) as vertex loops, each in the whole mesh's order, on
  /// the first process.
  std::vector<std::vector<int>> contact_surface, boundary;
  /// A plane's edges, each as its two vertices in the whole mesh's order, on the first process
  /// where a figure draws every edge (deformed.png, error.png).
  std::vector<std::array<int, 2>> edges;
  /// A plane's elements as vertex loops in the whole mesh's order, on the first process (error.png).
  VertexLoops cells;
  /// A scene of several bodies: each body's range of the whole mesh (the pieces number their
  /// cells their own way) and the load applied to it, dim values per body (result.json's
  /// "bodies"), summed over the processes' shares of the vertices in their order; empty for one.
  std::vector<BodyRange> bodies;
  std::vector<double> body_loads;
  /// The files it was gathered for: a file that draws on what is gathered for it alone (stress.csv,
  /// contact-surface.vtu, the figures) can be written from it only when named here (serves).
  std::vector<std::string> files;
  bool serves(const std::string& file) const;
};

/// WholeOfPieces of the whole mesh of which `problem` is posed on this process's piece
/// (`piece`: where it lies), given the whole displacement `u` (dim values per vertex, or empty:
/// no stresses), for the output files `files` (the same on every process). Collective over
/// `rows`: each process takes the cells it owns (owned_cells); every process gets the size and
/// the stress peak, and of a scene of several bodies (`bodies`, the piece's ranges:
/// BasicBuiltProblem::bodies) their whole ranges and loads, the first what the files wanted
/// draw on.
template <int dim>
WholeOfPieces whole_of_pieces(const BasicContactProblem<dim>& problem, const Eigen::VectorXd& u, const PieceOfMesh& piece,
                              const RowDistribution& rows, const std::vector<std::string>& files,
                              const std::vector<BodyRange>& bodies = {});

/// What the run was, beyond the solution itself: recorded in result.json.
struct RunInfo {
  std::string version = hemivem::app::version();
  std::string scene_name;                     ///< the scene's name (or its file name)
  std::string scene_toml;                     ///< the scene's full TOML text, copied to scene.toml
  std::string mesh;                           ///< how the mesh was made ("squares n=8", a file path ...)
  std::string linear;                         ///< the factorization engine used
  std::string minimizer;                      ///< the nonsmooth minimizer used (a global search's first engine)
  nlohmann::json search = {{"kind", "local"}};  ///< how the minimizer searched (commands.hpp: search_json)
  nlohmann::json options = nlohmann::json::object();  ///< every option in effect, by name (numbers as numbers)
  double mesh_seconds = 0.0;                  ///< wall time spent making or reading the mesh
  int dofs = -1;                              ///< free degrees of freedom; < 0: 2 x vertices
  /// The pieces the processes made the mesh in (docs/cluster.md): 1 when every process made the
  /// whole mesh.
  int mesh_pieces = 1;
  /// What the results need of the whole mesh when the mesh they are written from is this
  /// process's piece of it (BasicSceneSolve::of_pieces); null: the mesh is whole.
  std::shared_ptr<const WholeOfPieces> of_pieces;
  /// solution.vtu written in this many pieces, one per process (solution.piece-K.vtu, named by
  /// solution.pvtu: BasicSceneSolve::share); 0 for one file.
  int vtu_pieces = 0;
  /// The coarser grids solved first (BasicSceneSolve::grid_sequence): result.json's
  /// full_space.grid_sequence.
  nlohmann::json grid_sequence = nlohmann::json::array();
  int processes = 1;                          ///< processes of the linear engine (mpirun -np P with mumps-mpi)
  std::vector<std::string> files;             ///< the files of the run's output folder (set by write_outputs)
  /// The formats of the figures (figure_formats of figures.hpp: png, pdf, svg; the scene's
  /// output.figure_format): each figure is written in each, e.g. u_nu.png and u_nu.pdf.
  std::vector<std::string> figure_formats{"png"};
  std::vector<std::string> warnings;          ///< what the user should know about the problem posed
  std::vector<double> law_breakpoints;        ///< the contact law's breakpoints (u_nu values), for u_nu.png
  bool gap_bound = false;                     ///< u_nu <= g is a constraint: the plots draw the gap and foundation
  std::optional<Obstacle> obstacle;           ///< the rigid obstacle of the contact, drawn in deformed.png
  /// The friction models as a scene names them ("coulomb", "tresca", "slip-weakening",
  /// "piecewise"; several: ", "-joined, each once; "" without friction): Coulomb's law is
  /// "coulomb", though it is solved as Tresca problems with bounds set by a fixed point.
  std::string friction_law;
  /// The same with what sets each bound, for the summary: "coulomb (mu = 0.3)", "tresca (bound
  /// table h(u_nu) of 2 points)", "tresca".
  std::string friction_summary;
  /// result.json's friction.models: per contact part with friction, {"part", "law", and
  /// "coefficient" (coulomb) or "bound_table" (tresca with a table of [u_nu, h])}.
  nlohmann::json friction_models = nlohmann::json::array();
  /// The estimate of the discretization error: result.json's "error_estimate", solution.vtu's
  /// "error_indicator", error.png; none: not made (null in result.json).
  std::optional<ErrorEstimate> error_estimate;
  /// The cell of the largest von Mises stress (stress_peak): result.json's "stress" and the
  /// summary's stress line; none when the displacement is not known or not finite (null).
  std::optional<StressPeak> stress;
  /// An adaptive solve's record (adapt_json of hemivem/app/adapt.hpp): result.json's "adapt",
  /// adapt.png; null for a single solve.
  nlohmann::json adapt;
  /// An adaptive solve's steps as VTU documents, step 0 first (SceneSolve::adapt_steps):
  /// adapt-step-K.vtu and adapt.pvd; null when not kept.
  std::shared_ptr<const std::vector<std::string>> adapt_steps;
  /// A loading path's steps (not owned; must outlive write_outputs): result.json's "path"
  /// summary, path.json, path-contact.csv, path-displacement.csv, solution.pvd with a
  /// solution-NNNN.vtu per frame, path.png; none for a static solve. The path of a plane or
  /// of a solid body (path_of).
  std::variant<std::monostate, const BasicPathSolution<2>*, const BasicPathSolution<3>*> path;
  /// A scene of several bodies (BasicBuiltProblem::bodies): result.json's "bodies" (each body's
  /// vertices, cells and balance of forces), displacement.csv's body column, and with
  /// solution.vtu each body's solution.body-NAME.vtu and solution.vtm naming them. Empty for one
  /// body.
  std::vector<BodyRange> bodies;
  /// result.json's "bodies": each body's range and balance of forces (null for one body).
  nlohmann::json bodies_record;
};

/// The run's path of a body of dimension dim (RunInfo::path), or null.
template <int dim>
const BasicPathSolution<dim>* path_of(const RunInfo& info) {
  const auto* p = std::get_if<const BasicPathSolution<dim>*>(&info.path);
  return p ? *p : nullptr;
}

/// result.json's "error_estimate" of an estimate: energy, norm, relative, parts (its time is
/// the stage "estimate" of the timings).
nlohmann::json error_estimate_json(const ErrorEstimate& estimate);

/// The result.json document ("schema": "hemivem-result/26", "dimension": 2).
nlohmann::json result_json(const Mesh& mesh, const ContactSolution& solution, const RunInfo& info);
/// The result.json document of a solid ("dimension": 3): the same keys, points and vectors with
/// three components (contact[].x and contact[].normal [x, y, z]), mesh.faces, contact_zone with
/// its area; adapt and friction null.
nlohmann::json result_json(const Mesh3D& mesh, const ContactSolution3D& solution, const RunInfo& info);

/// Whether the contact nodes carry a tangential displacement (friction or a bilateral
/// constraint; never a solid's): contact.csv, result.json, solution.vtu and u_nu.png then show it.
template <int dim>
bool has_tangential(const BasicContactSolution<dim>& solution) {
  for (const auto& n : solution.contact)
    if (n.friction_state != FrictionState::none) return true;
  return false;
}

/// The name of contact node n's part (by `parts`, or solution.contact_parts; "contact" when it has none):
/// contact.csv's part column (with several parts), result.json's "part", solution.vtu's
/// contact_part field (its index).
template <int dim>
std::string contact_part_name(const std::vector<std::string>& parts, const BasicContactNode<dim>& n) {
  return n.part >= 0 && n.part < static_cast<int>(parts.size()) ? parts[static_cast<std::size_t>(n.part)]
                                                                : std::string("contact");
}
template <int dim>
std::string contact_part_name(const BasicContactSolution<dim>& solution, const BasicContactNode<dim>& n) {
  return contact_part_name(solution.contact_parts, n);
}

/// The names write_outputs knows for a body of dimension `dim` (2 or 3), in the order it writes
/// them. Both: result.json, contact.csv, displacement.csv, stress.csv (the projected stress of
/// every cell), history.csv, solution.vtu, then a
/// solid's contact-surface.vtu, scene.toml, a plane's mesh.poly2d (the mesh solved on), u_nu.png,
/// both's deformed.png, a plane's error.png (the error indicators; with info.error_estimate),
/// mesh.png (the mesh) and adapt.png (the estimate of each step against unknowns and time; with
/// info.adapt), a plane's adapt.pvd (with info.adapt_steps: the steps of an adaptive solve as
/// a ParaView series, with an adapt-step-K.vtu per step, which it names), a solid's pressure.png, and with info.path: path.json, path-contact.csv,
/// path-displacement.csv, solution.pvd (and the frames' solution-NNNN.vtu, which it names) and
/// path.png. A run of either dimension owns the names of both: it removes an earlier run's file
/// of any of them that it did not write. InputError for another dimension.
const std::vector<std::string>& all_outputs(int dim);

/// What write_outputs did.
struct OutputReport {
  std::vector<std::filesystem::path> written;  ///< files written, in order
  std::vector<std::string> skipped;            ///< "name: reason" for each wanted file not made (plots only)
  std::vector<std::string> removed;            ///< names of earlier runs' outputs this run did not write
  /// The figures wanted that could not be drawn (gnuplot missing or failing), one sentence per
  /// reason naming them; also in result.json's "warnings". The command prints them on stderr.
  std::vector<std::string> warnings;
};

/// Checks, before any work, that `dir` can be the output folder: a folder that can be written
/// into, or a path that does not exist below a folder that can. Creates nothing; throws
/// InputError naming the folder otherwise.
void check_output_folder(const std::filesystem::path& dir);

/// Writes the `wanted` files (names from all_outputs(2)) into `dir`, creating it, as one
/// transaction (OutputTransaction of hemivem/support/output_folder.hpp): the whole set is
/// written beside `dir` with every write checked, then replaces the previous set at once; the
/// names of all_outputs(2) and all_outputs(3) this run did not write go, other files of `dir`
/// stay. The plots are made by running gnuplot; when gnuplot is missing or fails they are
/// skipped, listed in the report and warned of (OutputReport::warnings, result.json's
/// "warnings"), never an error. Throws InputError for an unknown name
/// (before writing anything), a solution whose size does not match the mesh, when another
/// process is writing `dir` ("another hemivem run is writing DIR"), and for any I/O failure
/// (WriteError: `dir` then keeps its previous set); never prints.
OutputReport write_outputs(const std::filesystem::path& dir, const Mesh& mesh, const MaterialTable& materials,
                           const ContactSolution& solution, const RunInfo& info,
                           const std::vector<std::string>& wanted = all_outputs(2));
/// The same for a solid: the names of all_outputs(3), contact-surface.vtu and pressure.png
/// showing the contact faces `contact_faces`.
OutputReport write_outputs(const std::filesystem::path& dir, const Mesh3D& mesh, const MaterialTable& materials,
                           const std::vector<int>& contact_faces, const ContactSolution3D& solution,
                           const RunInfo& info, const std::vector<std::string>& wanted = all_outputs(3));

/// The boundary edges of Gamma_3 whose both ends are contact nodes, as vertex pairs (the line
/// cells of solution.vtu, the contact boundary of deformed.png).
std::vector<std::array<int, 2>> contact_lines(const Mesh& mesh, const ContactSolution& solution);

}  // namespace hemivem::app
