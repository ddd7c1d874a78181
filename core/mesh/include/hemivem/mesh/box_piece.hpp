// A process's piece of a mesh generated on a grid of boxes (squares, triangles, distorted
// squares, nonconvex cells and polar grids in the plane, cubes and tetrahedra in a solid): what one process of
// a run across processes makes of the mesh, without making the whole (docs/cluster.md).
//
// A piece holds every vertex of the whole mesh, numbered as the whole numbers them, so that a
// vertex, its dofs and every array indexed by them mean in a piece what they mean in the whole;
// and of the cells, only those of the grid's boxes that
//   - lie within two layers of boxes of the process's vertices (the boxes holding one of them and
//     their neighbours: the rows a process assembles and the cells next to them; of a share
//     flagged vertex by vertex, the boxes within two boxes of each along every axis),
//   - touch one of the named sides of the domain (the cells along the contact of a scene, and
//     along the supports and loads of a body of several: a surface's worth), or
//   - lie in the grid's first column of boxes (which keeps the piece connected, a body as the
//     whole is), or
//   - lie within two boxes of a vertex the piece is given to hold (a support at a point),
// in the whole mesh's order of cells, each as the whole makes it. The vertices are numbered layer
// by layer (along y in the plane, z in a solid), so that a range of vertices is a slab: the
// grid's points, or the nonconvex generator's points of a grid twice as fine (BoxGridVertices).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>

namespace hemivem {

/// What a process makes of a generated mesh.
struct BoxPiece {
  /// The process's vertices: first_vertex, ..., end_vertex - 1 (none when equal), and those
  /// `owned` flags.
  int first_vertex = 0;
  int end_vertex = 0;
  /// Sides of the domain along which every cell is made: left, right, bottom, top in the plane;
  /// x0, x1, y0, y1, z0, z1, bottom, top in a solid.
  std::vector<std::string> sides;
  /// Empty, or one flag per vertex of the grid, 1 for a vertex of the process's: a share that
  /// is no range of the grid's numbering (several bodies shared along a Hilbert curve through
  /// them all, scene_pieces.hpp). The piece then holds the boxes within two boxes of each along
  /// every axis, as it holds those within two layers of a range; a path of boxes along x (then y)
  /// from each part of them apart to the first column, so that the piece is one body as the
  /// whole is; and in a solid the boxes around each edge of the grid that two of its boxes would
  /// meet along alone (so that its surface is one a solid mesh accepts).
  std::vector<char> owned;
  /// Vertices of the grid (numbered as the whole numbers them) whose boxes the piece holds as it
  /// holds those of a flagged vertex, joined to the rest: a support at a point holds such a
  /// vertex, and every piece holds the cells around it (scene_pieces.hpp).
  std::vector<int> held;
};

/// The generators that make a piece: squares, triangles, distorted, nonconvex and polar in the
/// plane, cubes and tetrahedra in a solid (a grid of boxes).
bool makes_pieces(std::string_view generator);

/// The cells such a generator makes of each box of its grid: 1 (squares, distorted, nonconvex,
/// polar, cubes), 2 (triangles) or 6 (tetrahedra); InputError for a generator that makes no piece.
int cells_per_box(std::string_view generator);

/// How a polar grid's boxes (make_polar: its sectors along x, its rings along y) close on
/// themselves: around a full turn, the last column of vertices is the first; around the centre
/// of a disk, the first row of vertices is one vertex, the centre. Neither on a grid of boxes.
struct GridClosure {
  bool around = false;
  bool centre = false;
};

/// How such a generator numbers the vertices of its grid of counts[0] x counts[1] (x counts[2]
/// in a solid) boxes, layer by layer along the last axis, x fastest: the grid's points, or (the
/// nonconvex generator) the points of the grid twice as fine but the boxes' centres and the
/// mid-points of the boundary's boxes' sides; make_polar the points of its rings (rows) and
/// angles (columns), closed as `closure` says.
class BoxGridVertices {
 public:
  /// InputError for a generator that makes no piece.
  BoxGridVertices(std::string_view generator, int dim, std::array<int, 3> counts, GridClosure closure = {});
  /// The number of vertices.
  long long count() const noexcept { return count_; }
  /// The grid point (i, j, k) at or below vertex v along each axis (k = 0 in the plane): a box
  /// corner, which the box (i, j, k) and those before it along each axis hold; v < count(). The
  /// centre of a disk is (0, 0, 0), a corner of every box of the first ring.
  std::array<long long, 3> point(long long v) const;
  /// The vertex at the grid point p (a box corner).
  long long corner(const std::array<long long, 3>& p) const;
  /// The nonconvex generator's: the point (i, j) of the grid twice as fine at vertex v, and the
  /// vertex at that point (-1 where none: a box's centre, the mid-point of a boundary box's side).
  std::array<long long, 2> fine_point(long long v) const;
  long long fine_vertex(long long i, long long j) const;
  /// Whether the vertices `vertices` (of one facet) all lie on one side of the grid: on the
  /// whole mesh's boundary (the sides of its box, a polar grid's inner and outer rings and, short
  /// of a full turn, its first and last rays, which a disk's centre lies on).
  bool on_side(std::span<const int> vertices) const;

 private:
  /// The distinct grid points along `axis`.
  long long columns(int axis) const;

  int dim_;
  std::array<int, 3> counts_;
  GridClosure closure_;
  bool fine_;
  long long count_ = 0;
  /// The fine grid's: the first vertex of each of its rows, and count() last.
  std::vector<long long> row_start_;
};

/// The piece of make_mesh(generator, n, domain, seed) described by `piece` (see above; the seed
/// moves a distorted mesh's vertices, every one of which each piece holds). InputError for a
/// generator that makes no piece, an unknown side, a range of vertices outside the mesh, and as
/// make_mesh.
Mesh make_mesh_piece(std::string_view generator, GridSize n, const Rectangle& domain, const BoxPiece& piece,
                     std::uint64_t seed = 1);

/// The piece of make_polar(center, radii, angles) described by `piece`: the boxes of its grid are
/// its cells, sector along x and ring along y (its sides left, right, bottom, top the edge groups
/// start, end, inner, outer), its vertices numbered as make_polar numbers them; each group the
/// whole mesh's edges of it among the piece's. InputError as make_mesh_piece and make_polar.
Mesh make_polar_piece(const Vec2& center, const std::vector<double>& radii, const std::vector<double>& angles,
                      const BoxPiece& piece);

/// How the polar grid of make_polar(center, radii, angles) closes on itself; InputError as
/// make_polar.
GridClosure polar_closure(const std::vector<double>& radii, const std::vector<double>& angles);

/// The whole mesh's number of each cell of make_polar_piece(center, radii, angles, piece), in its
/// order (increasing).
std::vector<int> polar_piece_cells(const std::vector<double>& radii, const std::vector<double>& angles,
                                   const BoxPiece& piece);

/// The piece of make_mesh3d(generator, n, domain) described by `piece`; InputError as
/// make_mesh_piece.
Mesh3D make_mesh3d_piece(std::string_view generator, GridSize3 n, const Box& domain, const BoxPiece& piece);

/// The boundary facets of `piece`, a piece of a generated grid's mesh (make_mesh_piece,
/// make_polar_piece, make_mesh3d_piece) whose vertices `grid` numbers, that lie on no side of the
/// grid (BoxGridVertices::on_side): where the piece meets the cells it does not hold, inside the
/// whole mesh (increasing; MeshPieceRead::cut_facets).
std::vector<int> grid_cut_facets(const Mesh& piece, const BoxGridVertices& grid);
std::vector<int> grid_cut_facets(const Mesh3D& piece, const BoxGridVertices& grid);

/// The whole mesh's number of each cell of the piece make_mesh_piece(generator, n, domain,
/// piece) makes, in its order (increasing); InputError as make_mesh_piece.
std::vector<int> piece_cells(std::string_view generator, GridSize n, const BoxPiece& piece);
/// The same for make_mesh3d_piece.
std::vector<int> piece_cells(std::string_view generator, GridSize3 n, const BoxPiece& piece);

}  // namespace hemivem
