// A compact order of a mesh's vertices: split into consecutive ranges, each range is a compact
// part of the mesh, whatever the order its vertices are numbered in (a Gmsh file's, a refined
// mesh's whose new vertices come last).
#pragma once

#include <string>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// The mesh's vertices along a Hilbert curve through its bounding box (2^20 cells a side in the
/// plane, 2^21 in space; vertices in one cell in the lexicographic order of their coordinates,
/// then of their numbers): a permutation of 0, ..., num_vertices() - 1, the same on every
/// machine for the same mesh. A space-filling curve's ranges are the parts p4est and deal.II
/// share a mesh out by. Cost: a sort of the vertices.
std::vector<int> hilbert_vertex_order(const Mesh& mesh);
std::vector<int> hilbert_vertex_order(const Mesh3D& mesh);

/// A process's vertices in a split of a mesh's among processes: the vertices at the positions
/// first, ..., end - 1 of `order` (a permutation of the mesh's vertices: hilbert_vertex_order),
/// or the vertices first, ..., end - 1 themselves where `order` is empty (a generated box's
/// slab, box_piece.hpp).
struct VertexShare {
  int first = 0;
  int end = 0;
  std::vector<int> order;
  /// One flag per vertex of a mesh of `num_vertices`: 1 for the share's. InputError when the
  /// share is not one of such a mesh (a range outside it, an order of another size).
  std::vector<char> mask(int num_vertices) const;
  /// For messages: "the vertices 0 to 99", "the vertices at 0 to 99 of the shared order".
  std::string text() const;
};

}  // namespace hemivem
