#include <hemivem/mesh/bodies.hpp>
#include <hemivem/error.hpp>

#include "cell_kernels.hpp"

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

using detail::cell_of;
using detail::facet_groups;
using detail::set_facet_group;

void shift(std::vector<int>& polygon, int offset) {
  for (int& v : polygon) v += offset;
}
void shift(CellFaces& cell, int offset) {
  for (auto& loop : cell) shift(loop, offset);
}

/// Each body's facets in the joined mesh: cell c's local facet l is the joined cell's local
/// facet l (its vertex lists are given in that order); the groups under the body's name.
template <int dim>
void map_facets(const std::vector<const MeshOf<dim>*>& bodies, const std::vector<std::string>& names,
                BasicJoinedMeshes<dim>& out) {
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const MeshOf<dim>& m = *bodies[b];
    std::vector<int>& of = out.facet_of.emplace_back(static_cast<std::size_t>(m.num_facets()), -1);
    for (int c = 0; c < m.num_cells(); ++c) {
      const auto own = cell_facets(m, c);
      const auto joined = cell_facets(out.mesh, out.first_cell[b] + c);
      for (std::size_t l = 0; l < own.size(); ++l) of[static_cast<std::size_t>(own[l])] = joined[l];
    }
    for (const auto& [group, facets] : facet_groups(m)) {
      std::vector<int> mapped;
      mapped.reserve(facets.size());
      for (int f : facets) mapped.push_back(of[static_cast<std::size_t>(f)]);
      set_facet_group(out.mesh, names[b] + "." + group, std::move(mapped));
    }
  }
}

template <int dim>
BasicJoinedMeshes<dim> join(const std::vector<const MeshOf<dim>*>& bodies, const std::vector<std::string>& names,
                            const std::vector<int>& region_counts) {
  check_names(bodies, names);
  if (!region_counts.empty() && region_counts.size() != bodies.size())
    throw InputError("join_meshes: " + std::to_string(region_counts.size()) + " region counts for " +
                     std::to_string(bodies.size()) + " bodies");
  BasicJoinedMeshes<dim> out;
  std::vector<PointOf<dim>> vertices;
  std::vector<decltype(cell_of(*bodies.front(), 0))> cells;
  std::vector<int> regions, body_of;
  int region_offset = 0;
  for (const MeshOf<dim>* m : bodies) {
    const int offset = static_cast<int>(vertices.size());
    body_of.insert(body_of.end(), static_cast<std::size_t>(m->num_vertices()), static_cast<int>(out.first_vertex.size()));
    out.first_vertex.push_back(offset);
    out.first_cell.push_back(static_cast<int>(cells.size()));
    out.first_region.push_back(region_offset);
    vertices.insert(vertices.end(), m->vertices().begin(), m->vertices().end());
    int largest = -1;
    for (int c = 0; c < m->num_cells(); ++c) {
      auto cell = cell_of(*m, c);
      shift(cell, offset);
      cells.push_back(std::move(cell));
      regions.push_back(m->region(c) + region_offset);
      largest = std::max(largest, m->region(c));
    }
    region_offset += std::max(largest + 1, region_counts.empty() ? 0 : region_counts[out.first_region.size() - 1]);
  }
  out.mesh = detail::make_mesh_of(std::move(vertices), std::move(cells), std::move(regions), body_of);
  map_facets<dim>(bodies, names, out);
  return out;
}

}  // namespace

JoinedMeshes join_meshes(const std::vector<const Mesh*>& bodies, const std::vector<std::string>& names,
                         const std::vector<int>& region_counts) {
  return join<2>(bodies, names, region_counts);
}

JoinedMeshes3D join_meshes(const std::vector<const Mesh3D*>& bodies, const std::vector<std::string>& names,
                           const std::vector<int>& region_counts) {
  return join<3>(bodies, names, region_counts);
}

}  // namespace hemivem
