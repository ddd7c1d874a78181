// A compact order of a mesh's vertices: split into consecutive ranges, each range is a compact
// part of the mesh, whatever the order its vertices are numbered in (a Gmsh file's, a refined
// mesh's whose new vertices come last).
#pragma once

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

}  // namespace hemivem
