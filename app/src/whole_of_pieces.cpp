// What the results need of a whole mesh that the processes hold in pieces, gathered from the
// pieces (WholeOfPieces of hemivem/app/outputs.hpp).
#include <hemivem/app/outputs.hpp>

#include <hemivem/error.hpp>
#include <hemivem/mesh/facet_cells.hpp>

#include <algorithm>
#include <array>
#include <string>
#include <utility>

namespace hemivem::app {

namespace {

/// Faces of a solid's piece as [the whole mesh's number of their cell, their place among the
/// cell's faces, their vertices' count, their vertices], the list of `key`'s first value (a
/// contact part's number, or 0) before them.
void put_face(std::vector<double>& out, double key, const Mesh3D& mesh, int f, const std::vector<int>& cells) {
  const int c = mesh.face(f).inner;
  const std::vector<int>& around = mesh.cell_faces(c);
  const auto place = std::find(around.begin(), around.end(), f) - around.begin();
  const std::vector<int>& loop = mesh.face(f).vertices;
  out.insert(out.end(), {key, static_cast<double>(cells[static_cast<std::size_t>(c)]), static_cast<double>(place),
                         static_cast<double>(loop.size())});
  out.insert(out.end(), loop.begin(), loop.end());
}

/// The faces of put_face gathered on the first process, as loops in the order of their keys.
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

}  // namespace

template <int dim>
WholeOfPieces whole_of_pieces(const BasicContactProblem<dim>& problem, const Eigen::VectorXd& u, const PieceOfMesh& piece,
                              const RowDistribution& rows) {
  const auto& mesh = *problem.elasticity.mesh;
  const std::vector<int>& cells = piece.cells;
  if (cells.size() != static_cast<std::size_t>(mesh.num_cells()))
    throw InternalError(std::to_string(cells.size()) + " numbers for a piece of " + std::to_string(mesh.num_cells()) +
                        " cells");
  const std::vector<char> owned = owned_cells(mesh, piece);
  WholeOfPieces whole;
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
    // stress.csv's rows: each owned cell as [its whole number, centroid, xx, yy, zz, yz, xz, xy]
    constexpr Eigen::Index width = 1 + dim + 6;
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
    if (rows.rank() == 0) {
      if (all.size() != width * piece.whole_cells)
        throw InternalError("the processes' pieces give " + std::to_string(all.size() / width) + " cells' stresses of " +
                            std::to_string(piece.whole_cells));
      whole.stress_rows.assign(static_cast<std::size_t>(all.size() / width * (width - 1)), 0.0);
      std::vector<char> given(static_cast<std::size_t>(piece.whole_cells), 0);
      for (Eigen::Index at = 0; at < all.size(); at += width) {
        const auto c = static_cast<std::size_t>(all(at));
        if (c >= given.size() || given[c]) throw InternalError("the processes' pieces give a cell's stress twice");
        given[c] = 1;
        std::copy(all.data() + at + 1, all.data() + at + width, whole.stress_rows.begin() + static_cast<std::ptrdiff_t>(c * (width - 1)));
      }
    }
  }
  if constexpr (dim == 3) {  // the contact faces, part by part, and the boundary faces, of the cells owned
    std::vector<double> contact, boundary;
    for (std::size_t p = 0; p < problem.parts.size(); ++p)
      for (const int f : problem.parts[p].facets)
        if (owned[static_cast<std::size_t>(mesh.face(f).inner)]) put_face(contact, static_cast<double>(p), mesh, f, cells);
    for (const int f : mesh.boundary_faces())  // a face of an owned cell alone in the piece is alone in the whole
      if (owned[static_cast<std::size_t>(mesh.face(f).inner)]) put_face(boundary, 0.0, mesh, f, cells);
    whole.contact_surface = gathered_faces(contact, rows);
    whole.boundary = gathered_faces(boundary, rows);
  }
  return whole;
}

template WholeOfPieces whole_of_pieces<2>(const ContactProblem&, const Eigen::VectorXd&, const PieceOfMesh&,
                                          const RowDistribution&);
template WholeOfPieces whole_of_pieces<3>(const ContactProblem3D&, const Eigen::VectorXd&, const PieceOfMesh&,
                                          const RowDistribution&);

}  // namespace hemivem::app
