// A cell's facets and a facet's cells in a mesh of either dimension (MeshOf<dim>): a plane's
// elements and edges, a solid's cells and faces.
#pragma once

#include <array>
#include <span>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// The two cells of facet f (the second -1 on the boundary).
inline std::array<int, 2> facet_cells(const Mesh& mesh, int f) { return {mesh.edge(f).left, mesh.edge(f).right}; }
inline std::array<int, 2> facet_cells(const Mesh3D& mesh, int f) { return {mesh.face(f).inner, mesh.face(f).outer}; }

/// The facets of cell c, in the order of its vertex lists (a plane's edge i from its vertex i).
inline std::span<const int> cell_facets(const Mesh& mesh, int c) { return mesh.element_edges(c); }
inline std::span<const int> cell_facets(const Mesh3D& mesh, int c) { return mesh.cell_faces(c); }

}  // namespace hemivem
