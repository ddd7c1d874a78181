// The cells of a mesh not made: each cell given by its facets' vertex loops alone, as a file's
// elements are read, with the facets they share found. Enough to choose a process's piece of
// the mesh (mesh_piece.hpp) without the whole mesh's geometry; a few integers per cell.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>

namespace hemivem::detail {

class CellTopology {
 public:
  /// Cell c's facets are the loops first[c], ..., first[c + 1] - 1; loop k's vertices are
  /// loops[at[k]], ..., loops[at[k + 1] - 1] (a solid's cell: its faces; a plane element: its
  /// edges, loops of two vertices). `dim` is 2 or 3. Facets of the same vertices (in any
  /// order) are one facet.
  CellTopology(int dim, int num_vertices, std::vector<int> first, std::vector<int> at, std::vector<int> loops);

  int dim() const { return dim_; }
  int num_vertices() const { return num_vertices_; }
  int num_cells() const { return static_cast<int>(first_.size()) - 1; }
  int num_facets() const { return static_cast<int>(facet_cells_.size()); }
  /// Cell c's vertices, increasing.
  std::span<const int> cell_vertices(int c) const;
  /// Cell c's facets, in the order of its loops.
  std::span<const int> cell_facets(int c) const;
  /// The cells of facet f: the first cell with a loop of it, then the next (-1 on the boundary).
  const std::array<int, 2>& facet_cells(int f) const { return facet_cells_[static_cast<std::size_t>(f)]; }
  /// Facet f's vertex loop, as its first cell gives it.
  std::span<const int> facet_loop(int f) const;
  /// The facet of the vertices `vertices` (in any order); -1 when no cell has it.
  int find_facet(std::vector<int> vertices) const;

 private:
  int dim_, num_vertices_;
  std::vector<int> first_, at_, loops_;
  std::vector<int> facet_of_loop_;                  // the facet of each loop
  std::vector<int> loop_of_facet_;                  // a loop of each facet, its first cell's
  std::vector<std::array<int, 2>> facet_cells_;
  std::vector<int> vertex_start_, vertices_;        // each cell's vertices, increasing
  std::vector<std::array<int, 5>> keys_;            // each facet's sorted vertices (up to four, then -1) and the facet
};

inline std::span<const int> cell_facets(const CellTopology& cells, int c) { return cells.cell_facets(c); }

/// Sets `out`'s cells, order, share, whole_cells and cell sums (MeshPieceRead, mesh_piece.hpp)
/// to those of the piece process `rank` of `size` keeps of the mesh of `cells`, with its vertices
/// at `vertices` and its cells' regions `regions`: `order` the vertices along the Hilbert curve
/// through their box, the process's share of it the positions first, ..., end - 1, and `cells`
/// piece_cells_around of that share with the facets `facets` (a file's facet groups), every
/// boundary facet and the first facet of each region's first cell, and the cells around the
/// vertex nearest each point `held` (HeldPoints). `out.mesh` is left alone.
void choose_piece(const CellTopology& cells, const std::vector<Vec2>& vertices, const std::vector<int>& regions,
                  std::vector<int> facets, int rank, int size, HeldPoints held, MeshPieceRead<Mesh>& out);
void choose_piece(const CellTopology& cells, const std::vector<Vec3>& vertices, const std::vector<int>& regions,
                  std::vector<int> facets, int rank, int size, HeldPoints held, MeshPieceRead<Mesh3D>& out);

}  // namespace hemivem::detail
