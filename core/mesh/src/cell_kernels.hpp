// What differs between the dimensions when a mesh is remade from some of another's cells (the
// meshes of several bodies joined, a process's piece of a mesh): a cell's vertex lists, the mesh
// made of them and the named facet groups (a cell's facets: hemivem/mesh/facet_cells.hpp).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/mesh/facet_cells.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem::detail {

inline std::vector<int> cell_of(const Mesh& m, int c) { return {m.element(c).begin(), m.element(c).end()}; }
inline CellFaces cell_of(const Mesh3D& m, int c) { return m.cell(c); }
inline Mesh make_mesh_of(std::vector<Vec2> v, std::vector<std::vector<int>> cells, std::vector<int> regions,
                         const std::vector<int>& body_of = {}) {
  return Mesh(std::move(v), std::move(cells), std::move(regions), body_of);
}
inline Mesh3D make_mesh_of(std::vector<Vec3> v, std::vector<CellFaces> cells, std::vector<int> regions,
                           const std::vector<int>& = {}) {
  return Mesh3D(std::move(v), std::move(cells), std::move(regions));
}
inline const std::map<std::string, std::vector<int>>& facet_groups(const Mesh& m) { return m.edge_groups(); }
inline const std::map<std::string, std::vector<int>>& facet_groups(const Mesh3D& m) { return m.face_groups(); }
inline void set_facet_group(Mesh& m, const std::string& name, std::vector<int> facets) {
  m.set_edge_group(name, std::move(facets));
}
inline void set_facet_group(Mesh3D& m, const std::string& name, std::vector<int> facets) {
  m.set_face_group(name, std::move(facets));
}

}  // namespace hemivem::detail
