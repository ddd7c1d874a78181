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
//   - join the others of each body of the mesh (each connected part) into one (the cells of the
//     given facets joined once, and a shortest path of cells from each other part to them) or, in a solid, close the piece's surface (every cell around an edge that two
//     kept cells meet along alone),
// in the whole mesh's order, each as the whole holds it with its region; each facet group holds
// those of its facets that the piece holds.
#pragma once

#include <array>
#include <exception>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <hemivem/every_process.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/dimension.hpp>
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
/// every facet a support, load or contact part may select by side or group). Given a
/// BoundaryPick (below), a mesh of one connected body is cut with the facets it picks in place
/// of the boundary's and the groups'.
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
  /// Whether the piece holds, of the boundary and the facet groups, the cells of the facets a
  /// BoundaryPick picked alone; otherwise of every boundary facet and every group's facet.
  bool picked = false;
};

/// Facets by their vertices, each increasing: a piece's facet groups and where it meets the
/// rest of the mesh, as they are known before its mesh is made.
using FacetKeys = std::vector<std::vector<int>>;

/// The facets `facets` of `mesh` by their vertices (FacetKeys), in that order.
FacetKeys facet_keys(const Mesh& mesh, std::span<const int> facets);
FacetKeys facet_keys(const Mesh3D& mesh, std::span<const int> facets);

/// Which facets every piece of a mesh of one connected body holds the cells of, in place of
/// every boundary facet and facet group: given `sides`, the piece of no vertex (the cells of
/// every boundary facet, of every group's facet and of each region's first cell, with every
/// vertex; its cut_facets where it meets the rest), the facets of its boundary that the caller
/// needs on every piece (a scene's contact: hemivem/scene/scene_pieces.hpp), by their vertices
/// (facet_keys of sides.mesh). Called once, where the pieces are made, before the first piece is
/// made; its errors end the reading. Not called for a mesh of several bodies, nor for one whose
/// boundary cells make no mesh (the pieces then find the defect as they do without a pick).
template <class MeshType>
using BoundaryPick = std::function<FacetKeys(MeshPieceRead<MeshType>&& sides)>;

/// A piece as the lists its mesh is made of, before the mesh is made: what a reader chooses of
/// a mesh not made whole, and what the first process sends another (read_gmsh3d_piece across
/// processes). make_piece makes of it `piece` with its mesh: made of `cells` (a plane's
/// elements as vertex loops, a solid's cells as their faces' loops) with their `regions` on
/// every vertex `vertices`, then given each facet group of `groups` (its facets by their
/// vertices, in order: a plane's edge groups are then sorted, as read_gmsh makes them), and
/// `piece.cut_facets` the boundary facets among `cuts`.
template <class MeshType>
struct PieceLists {
  using Point = PointOf<dimension_of<MeshType>>;
  using Cell = std::conditional_t<dimension_of<MeshType> == 2, std::vector<int>, CellFaces>;
  MeshPieceRead<MeshType> piece;  ///< all but its mesh and cut_facets
  std::vector<Point> vertices;
  std::vector<Cell> cells;
  std::vector<int> regions;
  std::vector<std::pair<std::string, FacetKeys>> groups;
  FacetKeys cuts;
};

/// The piece of the lists: MeshError as the mesh's constructor (a cell numbered among the
/// piece's cells); InternalError for a group's facet or a cut that is none of the mesh's.
MeshPieceRead<Mesh> make_piece(PieceLists<Mesh> lists);
MeshPieceRead<Mesh3D> make_piece(PieceLists<Mesh3D> lists);

/// The lists as bytes appended to `out`, and read back (what the first process sends
/// another); without `shared`, all but the vertices and the piece's `order`, which every piece
/// of a mesh holds alike and which write_shared and read_shared carry (read_piece then leaves
/// them empty). InternalError for bytes that end too soon.
void write_piece(const PieceLists<Mesh>& lists, std::vector<char>& out, bool shared = true);
void write_piece(const PieceLists<Mesh3D>& lists, std::vector<char>& out, bool shared = true);
template <class MeshType>
PieceLists<MeshType> read_piece(std::span<const char> bytes);
void write_shared(const PieceLists<Mesh>& lists, std::vector<char>& out);
void write_shared(const PieceLists<Mesh3D>& lists, std::vector<char>& out);
void read_shared(std::span<const char> bytes, PieceLists<Mesh>& lists);
void read_shared(std::span<const char> bytes, PieceLists<Mesh3D>& lists);

/// How the first process gives each process its piece's lists: deliver(rank, lists).
template <class MeshType>
using PieceDelivery = std::function<void(int, PieceLists<MeshType>&&)>;

/// Collective over `processes`: this process's piece, whose lists the first process makes for
/// every process by `make(deliver)`, delivering them in turn, the others' sent to them as they
/// are made (made_by_first, hemivem/every_process.hpp), but for the vertices and the order,
/// which every piece holds alike and which the first then gives all at once
/// (RowDistribution::broadcast_from_first); an error there ends every process
/// (on_every_process: the first with its own error, the others saying that process 0 stopped
/// with it). Every process then makes its piece's mesh (make_piece). When that meets a defect
/// on any process, the first calls `name_defect()`, which throws the whole mesh's first defect
/// as the whole reader names it, and every process ends with it (the others saying that
/// process 0 stopped with it); should it not throw, every process ends with the defect its own
/// piece met, or saying which process met one.
template <class MeshType, class Make, class NameDefect>
MeshPieceRead<MeshType> piece_made_by_first(const RowDistribution& processes, Make&& make, NameDefect&& name_defect) {
  PieceLists<MeshType> lists = on_every_process(processes, [&] {
    return made_by_first<PieceLists<MeshType>>(
        processes, [&](const auto& deliver) { make(PieceDelivery<MeshType>(deliver)); },
        [](const PieceLists<MeshType>& made, std::vector<char>& bytes) { write_piece(made, bytes, false); },
        [](std::span<const char> bytes) { return read_piece<MeshType>(bytes); });
  });
  {  // the vertices and the order, every piece's alike, from the first to all at once
    std::vector<char> shared;
    if (processes.rank() == 0) write_shared(lists, shared);
    processes.broadcast_from_first(shared);
    if (processes.rank() != 0) read_shared(shared, lists);
  }
  MeshPieceRead<MeshType> out;
  std::exception_ptr defect;
  try {
    out = make_piece(std::move(lists));
  } catch (const MeshError&) {
    defect = std::current_exception();
  }
  if (processes.max(defect ? 1.0 : 0.0) > 0.0) {
    on_every_process(processes, [&] {
      if (processes.rank() == 0) name_defect();
      return 0;
    });
    on_every_process(processes, [&] {
      if (defect) std::rethrow_exception(defect);
      return 0;
    });
  }
  return out;
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
  /// The lists of the pieces around the vertices owned(r) flags (one flag per vertex, asked for
  /// as each piece is chosen) for each process r of `size`, by piece's rule (the cells around the
  /// vertex nearest each point `held` too), each given to deliver(r, lists) as it is made: what
  /// the first process sends the others (piece_made_by_first). Their `order`, `first` and `end`
  /// are left empty; a piece's mesh made of its lists (make_piece) is piece's but for a
  /// polygon's edge groups (ListsOfFirst::finish).
  std::function<void(int size, const std::function<std::vector<char>(int)>& owned, HeldPoints held,
                     const PieceDelivery<MeshType>& deliver)>
      pieces;
  /// Throws the whole mesh's first defect as its reader or generator names it, if it has one.
  std::function<void()> name_defect;
};

/// A mesh that the first process alone makes or reads as lists (MeshLists), of which it makes
/// every process's piece and sends it (piece_of_lists_by_first): `make()` makes the lists, on
/// the first process alone; `finish(piece)`, when given, completes on every process the piece
/// made of the lists it received (a polygon's mesh names its edges after the polygon's edges).
template <class MeshType>
struct ListsOfFirst {
  std::function<MeshLists<MeshType>()> make;
  std::function<void(MeshPieceRead<MeshType>&)> finish;
};

/// Collective over `processes`: this process's piece of the mesh `source` makes on the first
/// process, around the vertices owned(rank) flags of each process (MeshLists::pieces), or,
/// without `owned`, the piece of no vertex, every process's alike (the cells of the boundary:
/// MeshLists::piece of no flag). The first process makes `lists` by source.make() unless it holds
/// them already (kept there for the next call; empty on the others), makes every process's piece
/// in turn and sends it (piece_made_by_first), and a defect a piece meets is named by the lists'
/// name_defect. An error there ends every process, the first with it, the others with "process 0
/// stopped: <that error>". The piece's `order`, `first` and `end` are left empty.
template <class MeshType>
MeshPieceRead<MeshType> piece_of_lists_by_first(const RowDistribution& processes, const ListsOfFirst<MeshType>& source,
                                                std::optional<MeshLists<MeshType>>& lists,
                                                const std::function<std::vector<char>(int)>& owned, HeldPoints held) {
  MeshPieceRead<MeshType> out = piece_made_by_first<MeshType>(
      processes,
      [&](const PieceDelivery<MeshType>& deliver) {
        if (!lists) lists = source.make();
        if (owned) {
          lists->pieces(processes.size(), owned, held, deliver);
          return;
        }
        PieceLists<MeshType> sides;  // made once, given to every process
        lists->pieces(
            1, [&](int) { return std::vector<char>(static_cast<std::size_t>(lists->vertices), 0); }, {},
            [&](int, PieceLists<MeshType>&& made) { sides = std::move(made); });
        // the others' copies without the vertices, which the first gives every process at once
        std::vector<typename PieceLists<MeshType>::Point> vertices = std::move(sides.vertices);
        sides.vertices.clear();
        for (int r = 1; r < processes.size(); ++r) deliver(r, PieceLists<MeshType>(sides));
        sides.vertices = std::move(vertices);
        deliver(0, std::move(sides));
      },
      [&] { lists->name_defect(); });
  if (source.finish) source.finish(out);
  return out;
}

}  // namespace hemivem
