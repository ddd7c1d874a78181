// What the results need of a whole mesh that the processes hold in pieces, gathered from the
// pieces (WholeOfPieces of hemivem/app/outputs.hpp).
#include <hemivem/app/outputs.hpp>

#include "bodies.hpp"
#include "output_run.hpp"

#include <hemivem/app/figures.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/facet_cells.hpp>

#include <algorithm>
#include <array>
#include <string>
#include <type_traits>
#include <utility>

namespace hemivem::app {

namespace {

/// The vertices of facet f: a plane's edge from v0 to v1, a solid's face.
std::vector<int> facet_loop(const Mesh& mesh, int f) { return {mesh.edge(f).v0, mesh.edge(f).v1}; }
const std::vector<int>& facet_loop(const Mesh3D& mesh, int f) { return mesh.face(f).vertices; }

/// Facet f of a piece as [`key` (a contact part's number, or 0), the whole mesh's number of its
/// first cell, its place among that cell's facets, its vertices' count, its vertices]: the
/// first two numbers order the facets as the whole mesh numbers them (by their first cell and
/// place in it), the piece holding both cells of a facet of a cell the process owns.
template <class MeshType>
void put_facet(std::vector<double>& out, double key, const MeshType& mesh, int f, const std::vector<int>& cells) {
  const int c = facet_cells(mesh, f)[0];
  const std::span<const int> around = cell_facets(mesh, c);
  const auto place = std::find(around.begin(), around.end(), f) - around.begin();
  const auto& loop = facet_loop(mesh, f);
  out.insert(out.end(), {key, static_cast<double>(cells[static_cast<std::size_t>(c)]), static_cast<double>(place),
                         static_cast<double>(loop.size())});
  out.insert(out.end(), loop.begin(), loop.end());
}

/// The facets of put_facet gathered on the first process, as loops in the order of their keys.
std::vector<std::vector<int>> gathered_faces(const std::vector<double>& mine, const RowDistribution& rows) {
  const Eigen::VectorXd all =
      rows.gather_to_first(Eigen::Map<const Eigen::VectorXd>(mine.data(), static_cast<Eigen::Index>(mine.size())));
  std::vector<std::pair<std::array<double, 3>, std::vector<int>>> faces;
  for (Eigen::Index at = 0; at < all.size();) {
    const auto n = static_cast<Eigen::Index>(all(at + 3));
    if (at + 4 + n > all.size()) throw InternalError("the processes' faces end inside a face");
    std::vector<int> loop(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) loop[static_cast<std::size_t>(i)] = static_cast<int>(all(at + 4 + i));
    faces.emplace_back(std::array<double, 3>{all(at), all(at + 1), all(at + 2)}, std::move(loop));
    at += 4 + n;
  }
  std::sort(faces.begin(), faces.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::vector<int>> loops;
  loops.reserve(faces.size());
  for (auto& face : faces) loops.push_back(std::move(face.second));
  return loops;
}

/// The cells of the records [the whole mesh's number of a cell, its vertices' count, its
/// vertices] gathered on the first process, as loops in the whole mesh's order: each of the
/// `cells` cells once (record_starts).
VertexLoops gathered_cells(const std::vector<double>& mine, int cells, const RowDistribution& rows) {
  const Eigen::VectorXd all =
      rows.gather_to_first(Eigen::Map<const Eigen::VectorXd>(mine.data(), static_cast<Eigen::Index>(mine.size())));
  VertexLoops loops;
  if (rows.rank() != 0) return loops;
  const auto count = [&all](Eigen::Index at) {
    if (at + 1 >= all.size()) throw InternalError("the processes' records end inside the record of a cell");
    return 1 + static_cast<Eigen::Index>(all(at + 1));
  };
  const std::vector<Eigen::Index> records = record_starts(all, cells, count);
  loops.offsets.reserve(records.size() + 1);
  for (const Eigen::Index at : records) {
    for (Eigen::Index i = 2; i < 1 + count(at); ++i) loops.vertices.push_back(static_cast<int>(all(at + i)));
    loops.offsets.push_back(static_cast<int>(loops.vertices.size()));
  }
  return loops;
}

bool named(const std::vector<std::string>& files, const std::string& file) {
  return std::find(files.begin(), files.end(), file) != files.end();
}

/// stress.csv's rows gathered on the first process, per cell of the whole mesh in order (its
/// centroid and its stresses xx, yy, zz, yz, xz, xy), from each process's owned cells.
template <class MeshType, class Stress>
std::vector<double> gathered_stress_rows(const MeshType& mesh, const std::vector<Stress>& stresses,
                                         const std::vector<char>& owned, const std::vector<int>& cells, int whole_cells,
                                         const RowDistribution& rows) {
  constexpr int dim = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;
  constexpr Eigen::Index width = dim + 6;  // after the cell's whole number
  std::vector<double> mine;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    if (!owned[static_cast<std::size_t>(c)]) continue;
    const auto& s = stresses[static_cast<std::size_t>(c)];
    const auto x = mesh.centroid(c);
    mine.push_back(cells[static_cast<std::size_t>(c)]);
    for (int i = 0; i < dim; ++i) mine.push_back(x(i));
    mine.insert(mine.end(), {s.xx, s.yy, s.zz, s.yz, s.xz, s.xy});
  }
  const Eigen::VectorXd all =
      rows.gather_to_first(Eigen::Map<const Eigen::VectorXd>(mine.data(), static_cast<Eigen::Index>(mine.size())));
  std::vector<double> out;
  if (rows.rank() != 0) return out;
  const std::vector<Eigen::Index> records = record_starts(all, whole_cells, [](Eigen::Index) { return width; });
  out.reserve(records.size() * width);
  for (const Eigen::Index at : records) out.insert(out.end(), all.data() + at + 1, all.data() + at + 1 + width);
  return out;
}

/// The facets the files of whole.files are drawn from, gathered on the first process
/// (WholeOfPieces::contact_surface, boundary, edges, cells), from the cells each process owns.
template <int dim>
void gather_facets(WholeOfPieces& whole, const BasicContactProblem<dim>& problem, const std::vector<char>& owned,
                   const std::vector<int>& cells, int whole_cells, const RowDistribution& rows) {
  const auto& mesh = *problem.elasticity.mesh;
  const auto wants = [&whole](const char* file) { return named(whole.files, file); };
  // the facets of the cells owned: each by the owner of its first cell, a boundary facet (of an
  // owned cell alone in the piece, alone in the whole) by its cell's
  const auto counted = [&](int f) { return owned[static_cast<std::size_t>(facet_cells(mesh, f)[0])] != 0; };
  if (dim == 3 && (wants("contact-surface.vtu") || wants("pressure.png"))) {  // part by part
    std::vector<double> contact;
    for (std::size_t p = 0; p < problem.parts.size(); ++p)
      for (const int f : problem.parts[p].facets)
        if (counted(f)) put_facet(contact, static_cast<double>(p), mesh, f, cells);
    whole.contact_surface = gathered_faces(contact, rows);
  }
  if (wants("deformed.png") || (dim == 2 && wants("u_nu.png"))) {
    std::vector<double> boundary;
    for (const int f : mesh.boundary_facets())
      if (counted(f)) put_facet(boundary, 0.0, mesh, f, cells);
    whole.boundary = gathered_faces(boundary, rows);
  }
  if constexpr (dim == 2) {
    if ((wants("deformed.png") && draws_every_edge(static_cast<std::size_t>(whole.size.facets))) ||
        (wants("error.png") && indicator_draws_edges(whole.size.cells))) {
      std::vector<double> edges;
      for (int f = 0; f < mesh.num_edges(); ++f)
        if (counted(f)) put_facet(edges, 0.0, mesh, f, cells);
      for (const std::vector<int>& e : gathered_faces(edges, rows)) whole.edges.push_back({e[0], e[1]});
    }
    if (wants("error.png")) {  // each owned element as [its whole number, its vertices' count, its vertices]
      std::vector<double> elements;
      for (int c = 0; c < mesh.num_cells(); ++c) {
        if (!owned[static_cast<std::size_t>(c)]) continue;
        const auto loop = mesh.element(c);
        elements.insert(elements.end(), {static_cast<double>(cells[static_cast<std::size_t>(c)]), static_cast<double>(loop.size())});
        elements.insert(elements.end(), loop.begin(), loop.end());
      }
      whole.cells = gathered_cells(elements, whole_cells, rows);
    }
  }
}

/// The bodies' whole ranges and loads (WholeOfPieces::bodies, body_loads) from each process's
/// owned cells and share of the vertices, the same on every process (collective): a body's
/// first cell the least of the whole numbers of its cells owned, its cells their count.
template <int dim>
void gather_bodies(WholeOfPieces& whole, const BasicContactProblem<dim>& problem, const std::vector<BodyRange>& bodies,
                   const PieceOfMesh& piece, const std::vector<char>& owned, const RowDistribution& rows) {
  if (bodies.empty()) return;
  const auto& mesh = *problem.elasticity.mesh;
  const std::vector<char> share = piece.vertices.mask(mesh.num_vertices());
  const std::vector<double> loads = detail::body_loads(problem, bodies, &share);
  const auto n = static_cast<Eigen::Index>(bodies.size());
  Eigen::VectorXd mine(n * (1 + dim));  // per body its cells owned, then its load
  for (Eigen::Index b = 0; b < n; ++b) {
    const BodyRange& body = bodies[static_cast<std::size_t>(b)];
    int count = 0, first = piece.whole_cells;
    for (int c = body.first_cell; c < body.first_cell + body.cells; ++c)
      if (owned[static_cast<std::size_t>(c)]) {
        ++count;
        first = std::min(first, piece.cells[static_cast<std::size_t>(c)]);
      }
    mine(b) = count;
    for (int i = 0; i < dim; ++i) mine(n + dim * b + i) = loads[static_cast<std::size_t>(dim * b + i)];
    whole.bodies.push_back(body);
    whole.bodies.back().first_cell = static_cast<int>(rows.min(first));
  }
  const Eigen::VectorXd sum = rows.sum_in_rank_order(mine);
  for (Eigen::Index b = 0; b < n; ++b) whole.bodies[static_cast<std::size_t>(b)].cells = static_cast<int>(sum(b));
  whole.body_loads.assign(sum.data() + n, sum.data() + sum.size());
}

}  // namespace

bool WholeOfPieces::serves(const std::string& file) const {
  return !detail::gathered_for_itself(file) || named(files, file);
}

template <int dim>
WholeOfPieces whole_of_pieces(const BasicContactProblem<dim>& problem, const Eigen::VectorXd& u, const PieceOfMesh& piece,
                              const RowDistribution& rows, const std::vector<std::string>& files,
                              const std::vector<BodyRange>& bodies) {
  const auto& mesh = *problem.elasticity.mesh;
  const std::vector<int>& cells = piece.cells;
  if (cells.size() != static_cast<std::size_t>(mesh.num_cells()))
    throw InternalError(std::to_string(cells.size()) + " numbers for a piece of " + std::to_string(mesh.num_cells()) +
                        " cells");
  const std::vector<char> owned = owned_cells(mesh, piece);
  WholeOfPieces whole;
  whole.files = files;
  // each facet counted by the process owning the first of its cells in the whole mesh's order
  // (the piece holds every neighbour of a cell it owns); h the largest diameter of owned cells
  double facets = 0.0, h = 0.0;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    if (!owned[static_cast<std::size_t>(c)]) continue;
    h = std::max(h, mesh.diameter(c));
    for (const int f : cell_facets(mesh, c)) {
      const auto [one, other] = facet_cells(mesh, f);
      const int neighbour = one == c ? other : one;
      if (neighbour < 0 || cells[static_cast<std::size_t>(c)] < cells[static_cast<std::size_t>(neighbour)]) facets += 1.0;
    }
  }
  whole.size = {mesh.num_vertices(), piece.whole_cells, static_cast<int>(rows.sum(facets)), rows.max(h)};
  if (u.size() > 0) {
    const auto stresses = cell_stresses(mesh, problem.elasticity.materials, u);
    whole.stress = stress_peak_of_pieces(mesh, stresses, owned, cells, rows);
    if (named(files, "stress.csv"))
      whole.stress_rows = gathered_stress_rows(mesh, stresses, owned, cells, piece.whole_cells, rows);
  }
  gather_facets(whole, problem, owned, cells, piece.whole_cells, rows);
  gather_bodies(whole, problem, bodies, piece, owned, rows);
  return whole;
}

template WholeOfPieces whole_of_pieces<2>(const ContactProblem&, const Eigen::VectorXd&, const PieceOfMesh&,
                                          const RowDistribution&, const std::vector<std::string>&,
                                          const std::vector<BodyRange>&);
template WholeOfPieces whole_of_pieces<3>(const ContactProblem3D&, const Eigen::VectorXd&, const PieceOfMesh&,
                                          const RowDistribution&, const std::vector<std::string>&,
                                          const std::vector<BodyRange>&);

}  // namespace hemivem::app
