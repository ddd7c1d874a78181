// Checks and grid points shared by the generators on a box (generators3d.hpp).
#pragma once

#include <hemivem/mesh/box_piece.hpp>
#include <hemivem/mesh/generators3d.hpp>

#include <array>
#include <vector>

namespace hemivem::detail {

/// InputError naming `generator` for a size outside [1, 1000] per axis, a box that is not
/// finite with x0 < x1, y0 < y1, z0 < z1 or beyond 1e100, or cells too small for double precision.
void check_box_grid(const char* generator, GridSize3 n, const Box& box);

/// The point i/n of the way from a to b, exactly b for i == n.
double box_grid_coordinate(double a, double b, long i, long n);

/// InputError for a generator that makes no piece of a mesh of dimension `dim`.
void require_piece_generator(std::string_view generator, int dim);

/// Which boxes of a grid a process's piece makes (box_piece.hpp): box (i, j, k) of the grid of
/// counts[0] x counts[1] (x counts[2] in a solid) boxes, k = 0 in the plane. An empty filter (made
/// by default) makes every box.
class PieceBoxes {
 public:
  PieceBoxes() = default;
  /// The boxes of `piece` on a grid of `dim` axes of the mesh `generator` makes, whose vertices
  /// number layer by layer along the last axis (BoxGridVertices, closed as `closure` says: the
  /// boxes around a vertex of the last column are also those of the first, and those around the
  /// centre every box of the first two rings); InputError for an unknown side
  /// or a range of vertices outside the grid's.
  PieceBoxes(std::string_view generator, int dim, std::array<int, 3> counts, const BoxPiece& piece,
             GridClosure closure = {});
  bool operator()(int i, int j, int k) const;

 private:
  /// Whether the slab, the sides and the first column make box (i, j, k).
  bool by_rules(int i, int j, int k) const;

 private:
  bool all_ = true;
  int dim_ = 3;
  std::array<int, 3> counts_{1, 1, 1};
  int first_layer_ = 0, last_layer_ = -1;  // the slab's boxes along the last axis, [first, last]
  std::array<bool, 3> lower_{}, upper_{};  // the sides whose boxes are made
  std::vector<char> near_;  // per box (x fastest): made, of a piece with flagged vertices; empty otherwise
};

}  // namespace hemivem::detail
