#include <hemivem/mesh/bodies.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace hemivem {

namespace {

template <class MeshType>
void check_names(const std::vector<const MeshType*>& bodies, const std::vector<std::string>& names) {
  if (bodies.empty()) throw InputError("joining meshes needs at least one body");
  if (names.size() != bodies.size())
    throw InputError("joining " + std::to_string(bodies.size()) + " meshes needs as many names, got " +
                     std::to_string(names.size()));
  std::set<std::string> seen;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (!bodies[b]) throw InputError("body " + std::to_string(b) + " has no mesh");
    if (names[b].empty()) throw InputError("body " + std::to_string(b) + " has no name");
    if (!seen.insert(names[b]).second) throw InputError("two bodies are named '" + names[b] + "'");
  }
}

}  // namespace

JoinedMeshes join_meshes(const std::vector<const Mesh*>& bodies, const std::vector<std::string>& names) {
  check_names(bodies, names);
  JoinedMeshes out;
  std::vector<Vec2> vertices;
  std::vector<std::vector<int>> elements;
  std::vector<int> regions;
  std::vector<int> body_of;
  int region_offset = 0;
  for (const Mesh* m : bodies) {
    const int offset = static_cast<int>(vertices.size());
    body_of.insert(body_of.end(), static_cast<std::size_t>(m->num_vertices()), static_cast<int>(out.first_vertex.size()));
    out.first_vertex.push_back(offset);
    out.first_element.push_back(static_cast<int>(elements.size()));
    out.first_region.push_back(region_offset);
    vertices.insert(vertices.end(), m->vertices().begin(), m->vertices().end());
    int largest = -1;
    for (int e = 0; e < m->num_elements(); ++e) {
      std::vector<int> polygon(m->element(e).begin(), m->element(e).end());
      for (int& v : polygon) v += offset;
      elements.push_back(std::move(polygon));
      regions.push_back(m->region(e) + region_offset);
      largest = std::max(largest, m->region(e));
    }
    region_offset += largest + 1;
  }
  out.mesh = Mesh(std::move(vertices), std::move(elements), std::move(regions), body_of);
  std::map<std::pair<int, int>, int> edge_at;
  for (int k = 0; k < out.mesh.num_edges(); ++k) {
    const MeshEdge& e = out.mesh.edge(k);
    edge_at[{std::min(e.v0, e.v1), std::max(e.v0, e.v1)}] = k;
  }
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Mesh& m = *bodies[b];
    const int offset = out.first_vertex[b];
    std::vector<int>& of = out.edge_of.emplace_back(static_cast<std::size_t>(m.num_edges()));
    for (int k = 0; k < m.num_edges(); ++k) {
      const int v0 = m.edge(k).v0 + offset, v1 = m.edge(k).v1 + offset;
      of[static_cast<std::size_t>(k)] = edge_at.at({std::min(v0, v1), std::max(v0, v1)});
    }
    for (const auto& [group, edges] : m.edge_groups()) {
      std::vector<int> mapped;
      mapped.reserve(edges.size());
      for (int k : edges) mapped.push_back(of[static_cast<std::size_t>(k)]);
      out.mesh.set_edge_group(names[b] + "." + group, std::move(mapped));
    }
  }
  return out;
}

JoinedMeshes3D join_meshes(const std::vector<const Mesh3D*>& bodies, const std::vector<std::string>& names) {
  check_names(bodies, names);
  JoinedMeshes3D out;
  std::vector<Vec3> vertices;
  std::vector<CellFaces> cells;
  std::vector<int> regions;
  int region_offset = 0;
  for (const Mesh3D* m : bodies) {
    const int offset = static_cast<int>(vertices.size());
    out.first_vertex.push_back(offset);
    out.first_cell.push_back(static_cast<int>(cells.size()));
    out.first_region.push_back(region_offset);
    vertices.insert(vertices.end(), m->vertices().begin(), m->vertices().end());
    int largest = -1;
    for (int c = 0; c < m->num_cells(); ++c) {
      CellFaces cell = m->cell(c);
      for (auto& loop : cell)
        for (int& v : loop) v += offset;
      cells.push_back(std::move(cell));
      regions.push_back(m->region(c) + region_offset);
      largest = std::max(largest, m->region(c));
    }
    region_offset += largest + 1;
  }
  out.mesh = Mesh3D(std::move(vertices), std::move(cells), std::move(regions));
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Mesh3D& m = *bodies[b];
    // cell c's local face l is the joined cell's local face l (the loops are given in that order)
    std::vector<int>& of = out.face_of.emplace_back(static_cast<std::size_t>(m.num_faces()), -1);
    for (int c = 0; c < m.num_cells(); ++c) {
      const std::vector<int>& own = m.cell_faces(c);
      const std::vector<int>& joined = out.mesh.cell_faces(out.first_cell[b] + c);
      for (std::size_t l = 0; l < own.size(); ++l) of[static_cast<std::size_t>(own[l])] = joined[l];
    }
    for (const auto& [group, faces] : m.face_groups()) {
      std::vector<int> mapped;
      mapped.reserve(faces.size());
      for (int f : faces) mapped.push_back(of[static_cast<std::size_t>(f)]);
      out.mesh.set_face_group(names[b] + "." + group, std::move(mapped));
    }
  }
  return out;
}

}  // namespace hemivem
