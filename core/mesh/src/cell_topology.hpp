// The cells of a mesh not made: each cell given by its facets' vertex loops alone, as a file's
// elements are read, with the facets they share found. Enough to choose a process's piece of
// the mesh (mesh_piece.hpp) without the whole mesh's geometry; a few integers per cell.
#pragma once

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <istream>
#include <memory>
#include <string>
#include <span>
#include <type_traits>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>
#include <hemivem/mesh/vertex_cells.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/support/text_lines.hpp>

namespace hemivem::detail {

/// The facets of kinds of cells, each a list of loops through a cell's corners: loop j runs
/// through the corners corner[at[j]], ..., corner[at[j + 1] - 1] (numbers among the cell's own
/// corners), and shape s has the loops first[s], ..., first[s + 1] - 1. Cells of one kind (a
/// file's hexahedra, a plane's quadrilaterals) share a shape.
struct CellShapes {
  std::vector<int> first{0}, at{0}, corner;
  int size() const { return static_cast<int>(first.size()) - 1; }
  /// Adds the shape of the loops `loops` (each a list of corner numbers); returns its number.
  int add(const std::vector<std::vector<int>>& loops);
  /// The number of corners its loops run through: one more than the largest.
  int corners(int s) const;
};

class CellTopology {
 public:
  /// Cell c has the corners corners[corner_start[c]], ..., corners[corner_start[c + 1] - 1]
  /// (vertices below `num_vertices`, as many as its shape's loops run through) and the shape
  /// shapes[shape_of[c]]: its facets are the shape's loops through its corners (a solid's cell:
  /// its faces; a plane element: its edges, loops of two vertices). `dim` is 2 or 3. Loops of
  /// the same vertices (in any order) are one facet, found among the cells around their
  /// smallest vertex; the loops are numbered cell after cell, and a facet by its first loop,
  /// that of its first cell. InternalError for lists that do not fit.
  CellTopology(int dim, int num_vertices, CellShapes shapes, std::vector<int> shape_of, std::vector<int> corner_start,
               std::vector<int> corners);

  int dim() const { return dim_; }
  int num_vertices() const { return num_vertices_; }
  int num_cells() const { return static_cast<int>(first_.size()) - 1; }
  /// Every facet's number is below num_facets() (the number of loops); is_facet tells which are.
  int num_facets() const { return static_cast<int>(facet_of_loop_.size()); }
  bool is_facet(int f) const { return facet_of_loop_[static_cast<std::size_t>(f)] == f; }
  /// Cell c's vertices, increasing.
  std::vector<int> cell_vertices(int c) const;
  /// The cells of each vertex.
  const VertexCells& vertex_cells() const noexcept { return around_; }
  /// Cell c's facets, in the order of its loops.
  std::span<const int> cell_facets(int c) const;
  /// The cells of facet f: the first cell with a loop of it, then the cell of its next loop (-1
  /// on the boundary).
  std::array<int, 2> facet_cells(int f) const { return {cell_of_loop(f), second_[static_cast<std::size_t>(f)]}; }
  /// Facet f's vertex loop, as its first cell gives it.
  std::vector<int> facet_loop(int f) const;
  /// The facet of the vertices `vertices` (in any order); -1 when no cell has it.
  int find_facet(std::vector<int> vertices) const;

 private:
  int cell_of_loop(int k) const;
  /// Cell c's corners.
  std::span<const int> corners_of(int c) const;
  /// Loop k of cell c among its shape's loops (shapes_.at): loop shape_loop(c) + k.
  int shape_loop(int c) const {
    return shapes_.first[static_cast<std::size_t>(shape_of_[static_cast<std::size_t>(c)])] - first_[static_cast<std::size_t>(c)];
  }
  /// The corners of loop j of a shape's loops (shapes_.at), among the cell's `corners`.
  template <class Visit>
  void for_loop(int j, std::span<const int> corners, Visit&& visit) const {
    for (int i = shapes_.at[static_cast<std::size_t>(j)]; i < shapes_.at[static_cast<std::size_t>(j) + 1]; ++i)
      visit(corners[static_cast<std::size_t>(shapes_.corner[static_cast<std::size_t>(i)])]);
  }
  /// The first loop of the vertices `key` (increasing) among the cells around key[0], from
  /// loop `from` on; -1 when there is none. `scratch` holds a loop's vertices sorted.
  int next_loop(std::span<const int> key, int from, std::vector<int>& scratch) const;

  int dim_, num_vertices_;
  CellShapes shapes_;
  std::vector<int> shape_of_, corner_start_, corners_;
  std::vector<int> first_;                          // each cell's first loop
  std::vector<int> facet_of_loop_;                  // the facet of each loop
  std::vector<int> second_;                         // of a facet's loop: the cell of its next loop, or -1
  VertexCells around_;                              // the cells around each vertex
};

inline std::span<const int> cell_facets(const CellTopology& cells, int c) { return cells.cell_facets(c); }

/// The cells of plane elements, each given by its vertices in order: element k's edges are
/// (e[i], e[i + 1]), the last closing the loop (elements of one number of vertices share a shape).
CellTopology plane_topology(int num_vertices, const std::vector<std::vector<int>>& elements);
/// The cells of solid cells, each given by its faces' vertex loops (its corners its vertices,
/// increasing, and a shape of its own).
CellTopology solid_topology(int num_vertices, const std::vector<CellFaces>& cells);

/// Whose piece make_pieces makes: the vertices `owned` flags (one per vertex) when given, or
/// those flags() flags, made as the piece is chosen, else process `rank` of `size`'s share of
/// the vertices along the Hilbert curve.
struct PieceOwner {
  int rank = 0, size = 1;
  const std::vector<char>* owned = nullptr;
  std::function<std::vector<char>()> flags;
};

/// The pieces a reader makes of a mesh from one reading, in turn: those of whose[0], whose[1],
/// ..., each given to deliver(k, piece) once made (k its place in `whose`).
template <class MeshType>
struct PiecesInTurn {
  std::vector<PieceOwner> whose;
  std::function<void(std::size_t, PieceLists<MeshType>&&)> deliver;
  BoundaryPick<MeshType> pick;  ///< empty: every piece holds every boundary facet's cells
};

/// The pieces of the processes of `size`: of each but the first in the order of the ranks, then
/// the first's, each given to deliver(rank, piece).
template <class MeshType>
PiecesInTurn<MeshType> pieces_of_processes(int size, std::function<void(int, PieceLists<MeshType>&&)> deliver) {
  PiecesInTurn<MeshType> turn;
  for (int r = 1; r <= size; ++r) turn.whose.push_back(PieceOwner{r % size, size});
  turn.deliver = [whose = turn.whose, deliver = std::move(deliver)](std::size_t k, PieceLists<MeshType>&& lists) {
    deliver(whose[k].rank, std::move(lists));
  };
  return turn;
}

/// The pieces around the vertices owned(r) flags for each process r of `size` (MeshLists::pieces):
/// of each but the first in the order of the ranks, then the first's, each given to
/// deliver(r, piece).
template <class MeshType>
PiecesInTurn<MeshType> pieces_around(int size, const std::function<std::vector<char>(int)>& owned,
                                     const PieceDelivery<MeshType>& deliver) {
  PiecesInTurn<MeshType> turn = pieces_of_processes<MeshType>(size, deliver);
  for (PieceOwner& who : turn.whose) who.flags = [owned, rank = who.rank] { return owned(rank); };
  return turn;
}

/// The one piece of `who`, its lists into `out`.
template <class MeshType>
PiecesInTurn<MeshType> piece_of(const PieceOwner& who, PieceLists<MeshType>& out) {
  return {{who}, [&out](std::size_t, PieceLists<MeshType>&& lists) { out = std::move(lists); }};
}

using hemivem::FacetKeys;

/// Makes the pieces `turn` asks for of the mesh of `cells`, with its vertices at `vertices` and
/// its cells' regions `regions`, in turn. A piece is chosen as the piece `who` keeps: of a
/// process's share, its out.order the vertices along the Hilbert curve through their box
/// (found once for all the pieces) and out.first, out.end its share of them (of flagged
/// vertices, these three left empty); its cells piece_cells_around those vertices with the
/// facets `facets` (a file's facet groups), every boundary facet and the first facet of each
/// region's first cell (found once; of a mesh of one connected body given turn.pick, the facets
/// it picks on the piece of no vertex and each region's first facet: BoundaryPick), and the
/// cells around the vertex nearest each point `held`
/// (HeldPoints); out.whole_cells and the cell sums the whole mesh's; its cuts the facets of a
/// kept cell whose other cell is not kept. Then the rest of its lists (PieceLists: vertices,
/// cells, regions, groups) are made by make_lists(lists, kept, last), `kept` flagging its cells
/// among the mesh's (the last piece's may take `vertices`: `cells` is freed, and `vertices` no
/// more read, before it), and it is delivered. InternalError for flags of another number or a
/// rank outside its size.
template <class MeshType>
using MakePieceLists = std::function<void(PieceLists<MeshType>&, const std::vector<char>& kept, bool last)>;
void make_pieces(std::unique_ptr<const CellTopology> cells, const std::vector<Vec2>& vertices,
                 const std::vector<int>& regions, const std::vector<int>& facets, HeldPoints held,
                 const PiecesInTurn<Mesh>& turn, const MakePieceLists<Mesh>& make_lists);
void make_pieces(std::unique_ptr<const CellTopology> cells, const std::vector<Vec3>& vertices,
                 const std::vector<int>& regions, const std::vector<int>& facets, HeldPoints held,
                 const PiecesInTurn<Mesh3D>& turn, const MakePieceLists<Mesh3D>& make_lists);

/// A file's piece for process `rank` of `size`, read by a Reader (in, name) that makes the
/// lists of the pieces a PiecesInTurn asks for (read_pieces) and the piece of its lists
/// (made, naming a defect as the whole reader does).
template <class MeshType, class Reader>
MeshPieceRead<MeshType> read_own_piece(std::istream& in, const std::string& name, int rank, int size,
                                       HeldPoints held, const BoundaryPick<MeshType>& pick = {}) {
  Reader reader(in, name);
  PieceLists<MeshType> lists;
  PiecesInTurn<MeshType> turn = piece_of({rank, size}, lists);
  turn.pick = pick;
  reader.read_pieces(turn, held);
  return reader.made(std::move(lists));
}

/// The same collectively over `processes`, the file read by the first process alone, which
/// makes every process's lists and names a defect any piece meets (name_defect):
/// piece_made_by_first.
template <class MeshType, class Reader>
MeshPieceRead<MeshType> read_piece_by_first(const std::filesystem::path& path, const RowDistribution& processes,
                                            HeldPoints held, const BoundaryPick<MeshType>& pick = {}) {
  std::ifstream in;
  std::unique_ptr<Reader> reader;  // the first process's, kept to name a defect of any piece
  return piece_made_by_first<MeshType>(
      processes,
      [&](const PieceDelivery<MeshType>& deliver) {
        in = text::open_for_reading(path, "mesh file");
        reader = std::make_unique<Reader>(in, path.string());
        PiecesInTurn<MeshType> turn = pieces_of_processes(processes.size(), deliver);
        turn.pick = pick;
        reader->read_pieces(turn, held);
      },
      [&] { reader->name_defect(); });
}

/// A plane mesh not made: its vertices and its elements' vertices in order.
struct PlaneCells {
  std::vector<Vec2> vertices;
  std::vector<std::vector<int>> elements;
};

/// The piece process `rank` of `size` keeps of the plane mesh of `cells`, all in region 0 and
/// without facet groups (make_pieces): `out` whole but for its mesh, then out.mesh made of the
/// kept elements with every vertex (Mesh's MeshError for a defect among them) and its
/// cut_facets (make_piece).
void make_plane_piece(const PlaneCells& cells, HeldPoints held, int rank, int size, MeshPieceRead<Mesh>& out);
/// The same around the vertices `owned` flags (one per vertex) in place of a process's share:
/// out.order, first and end left empty (MeshLists::piece).
void make_plane_piece(const PlaneCells& cells, const std::vector<char>& owned, HeldPoints held, MeshPieceRead<Mesh>& out);
/// The same of the piece `who` keeps.
void make_plane_piece(const PlaneCells& cells, const PieceOwner& who, HeldPoints held, MeshPieceRead<Mesh>& out);
/// The lists of the pieces `turn` asks for (make_pieces).
void make_plane_pieces(const PlaneCells& cells, HeldPoints held, const PiecesInTurn<Mesh>& turn);
/// MeshLists of the plane mesh of `cells`: its pieces make_plane_piece's, each given to
/// finish(piece) when given (a polygon's mesh naming its edges), and make_plane_pieces's; a
/// defect named as the mesh's constructor names it.
MeshLists<Mesh> plane_lists(std::shared_ptr<const PlaneCells> cells,
                            std::function<void(MeshPieceRead<Mesh>&)> finish = {});

/// A solid mesh not made: its vertices and its cells' faces (vertex loops).
struct SolidCells {
  std::vector<Vec3> vertices;
  std::vector<CellFaces> cells;
};

/// make_plane_piece of a solid mesh: its cells' faces the facets (Mesh3D's MeshError).
void make_solid_piece(const SolidCells& cells, HeldPoints held, int rank, int size, MeshPieceRead<Mesh3D>& out);
void make_solid_piece(const SolidCells& cells, const std::vector<char>& owned, HeldPoints held,
                      MeshPieceRead<Mesh3D>& out);
/// The lists of the pieces `turn` asks for (make_pieces).
void make_solid_pieces(const SolidCells& cells, HeldPoints held, const PiecesInTurn<Mesh3D>& turn);

/// Collective over `processes`: this process's piece of the mesh of the lists (PlaneCells,
/// SolidCells) that `make()` makes on the first process alone, the first making every process's
/// piece of them in turn, `pick` choosing what of the boundary they hold (make_plane_pieces,
/// make_solid_pieces; PiecesInTurn::pick), and sending each (piece_made_by_first). An error in
/// `make()` or the pick ends every process; a defect a piece meets is named by
/// `whole(std::move(lists))` on the first, which makes the whole mesh of them (throwing its
/// error).
template <class MeshType, class Cells>
MeshPieceRead<MeshType> lists_piece_by_first(const RowDistribution& processes, const std::function<Cells()>& make,
                                             HeldPoints held, const BoundaryPick<MeshType>& pick,
                                             const std::function<void(Cells&&)>& whole) {
  Cells lists;  // the first process's
  return piece_made_by_first<MeshType>(
      processes,
      [&](const PieceDelivery<MeshType>& deliver) {
        lists = make();
        PiecesInTurn<MeshType> turn = pieces_of_processes<MeshType>(processes.size(), deliver);
        turn.pick = pick;
        if constexpr (std::is_same_v<MeshType, Mesh>) make_plane_pieces(lists, held, turn);
        else make_solid_pieces(lists, held, turn);
      },
      [&] { whole(std::move(lists)); });
}


}  // namespace hemivem::detail
