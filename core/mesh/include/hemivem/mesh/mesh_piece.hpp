// A process's piece of a mesh made whole (a Gmsh file, a polygon's mesh, a Voronoi mesh, a
// mesh with region boxes): what one process of a run across processes keeps of it for the
// full-space route (docs/cluster.md), as a generated box's piece is made directly
// (box_piece.hpp).
//
// A piece holds every vertex of the whole mesh, numbered as the whole numbers them (a vertex, its
// dofs and every array indexed by them mean in a piece what they mean in the whole), and of the
// cells only those that
//   - hold one of the process's vertices or a vertex of such a cell (two layers: the cells of
//     the rows the process assembles, and their neighbours, which the error estimate of a cell
//     reads), or
//   - have one of some given facets (the supports, loads and contact of a scene: a surface's
//     worth), or
//   - join the others of each body of the mesh (each connected part) into one (a path of
//     cells through the body to each part not yet joined) or, in a solid, close the piece's surface (every cell around an edge that two
//     kept cells meet along alone),
// in the whole mesh's order, each as the whole holds it with its region; each facet group holds
// those of its facets that the piece holds.
#pragma once

#include <array>
#include <functional>
#include <span>
#include <vector>

#include <hemivem/every_process.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// The cells of the piece of `mesh` around the vertices `owned` flags (one flag per vertex) with
/// the cells of `facets` (see above), increasing. InputError for a flag vector of another size
/// or a facet out of range.
std::vector<int> piece_cells_around(const Mesh& mesh, const std::vector<char>& owned, std::span<const int> facets);
std::vector<int> piece_cells_around(const Mesh3D& mesh, const std::vector<char>& owned, std::span<const int> facets);

/// The mesh of the cells `cells` of `mesh` (increasing, distinct): every vertex of the mesh, the
/// cells in that order with their regions, and each facet group restricted to the facets of
/// those cells (a group none of whose facets is held stays, empty). Given `facets`, sets it to
/// the piece's facet of each facet of `mesh` (-1 where the piece holds none of its cells).
/// InputError for cells out of range or out of order; MeshError as the mesh's constructor.
Mesh cut_mesh_piece(const Mesh& mesh, std::span<const int> cells, std::vector<int>* facets = nullptr);
Mesh3D cut_mesh_piece(const Mesh3D& mesh, std::span<const int> cells, std::vector<int>* facets = nullptr);

/// The piece of a file's mesh that process `rank` of `size` keeps, read without making the
/// whole mesh (read_gmsh_piece, read_gmsh3d_piece): the process's vertices are its share (the
/// positions first, ..., end - 1; even_share) of the whole mesh's vertices along the Hilbert
/// curve (hilbert_vertex_order), and the piece is cut_mesh_piece's of the whole mesh's cells
/// piece_cells_around that share with the facets of the mesh's boundary, of its facet groups
/// and the first facet of each region's first cell (so that every piece holds every region and
/// every facet a support, load or contact part may select by side or group).
/// Points whose nearest vertex (the least numbered of the nearest) a piece read from a file holds
/// with the cells around it, as a support at such a point holds that vertex: x, y, z (z = 0 in
/// the plane).
using HeldPoints = std::span<const std::array<double, 3>>;

template <class MeshType>
struct MeshPieceRead {
  MeshType mesh;
  std::vector<int> cells;  ///< the piece's cells' numbers in the whole mesh, increasing
  int whole_cells = 0;     ///< the whole mesh's number of cells
  std::vector<int> order;  ///< hilbert_vertex_order of the whole mesh
  int first = 0, end = 0;  ///< the process's share of `order`
  /// The piece's boundary facets that lie inside the whole mesh, where the piece meets cells
  /// it does not hold (increasing): no boundary of the whole mesh, so no selector picks them.
  std::vector<int> cut_facets;
  /// The sums over the whole mesh's cells of their numbers of vertices and of their squares,
  /// and the most vertices of one (a memory estimate of the whole mesh's).
  double cell_vertices = 0, cell_vertices_squared = 0;
  int largest_cell = 0;
};

/// A piece as bytes appended to `out`, and read back: its mesh the same to the bit (MeshRecord)
/// and its other fields as they were (what the first process sends another a piece as).
/// InternalError for bytes that end too soon.
void write_piece(const MeshPieceRead<Mesh>& piece, std::vector<char>& out);
void write_piece(const MeshPieceRead<Mesh3D>& piece, std::vector<char>& out);
template <class MeshType>
MeshPieceRead<MeshType> read_piece(std::span<const char> bytes);

/// How the first process gives each process its piece: deliver(rank, piece).
template <class MeshType>
using PieceDelivery = std::function<void(int, MeshPieceRead<MeshType>&&)>;

/// Collective over `processes`: the piece the first process makes for this one, on the first
/// by `make(deliver)`, which delivers every process's piece in turn, the others' sent to them
/// as they are made (made_by_first, hemivem/every_process.hpp: an error on the first ends
/// every process it has not sent to with "process 0 stopped: ...").
template <class MeshType, class Make>
MeshPieceRead<MeshType> piece_made_by_first(const RowDistribution& processes, Make&& make) {
  return made_by_first<MeshPieceRead<MeshType>>(
      processes, [&](const auto& deliver) { make(PieceDelivery<MeshType>(deliver)); },
      [](const MeshPieceRead<MeshType>& piece, std::vector<char>& bytes) { write_piece(piece, bytes); },
      [](std::span<const char> bytes) { return read_piece<MeshType>(bytes); });
}

/// A mesh made or read as lists of its cells' vertices and not yet as a mesh (a Voronoi mesh, a
/// polygon's mesh, a mesh file's: voronoi_lists, mesh_lists, voronoi3d_lists, read_gmsh_lists,
/// read_gmsh3d_lists, read_poly2d_lists), of which a process makes the piece around any of its
/// vertices: a body among several, whose vertices the processes share along the order of every
/// body's.
template <class MeshType>
struct MeshLists {
  int vertices = 0;  ///< the whole mesh's number of vertices
  /// The piece around the vertices `owned` flags (one per vertex; none flagged: the cells of the
  /// boundary alone), by the rule of a piece read from a file: with the cells of every boundary
  /// facet, of a file's facet groups and the first facet of each of its regions' first cell, and
  /// around the vertex nearest each point `held`. Its `order`, `first` and `end` are
  /// left empty. InternalError for flags of another number; MeshError as the whole mesh's.
  std::function<MeshPieceRead<MeshType>(const std::vector<char>& owned, HeldPoints held)> piece;
};

}  // namespace hemivem
