// A mesh whose vertices are numbered in a random order: the same cells and coordinates as the
// given mesh, the vertex numbered v there numbered order[v] here. A split of its vertices in
// their order is scattered over the whole mesh, as a Gmsh file's or a refined mesh's can be.
#pragma once

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace hemivem::test {

/// A random permutation of 0, ..., n - 1 (the same for the same seed).
inline std::vector<int> random_order(int n, unsigned seed) {
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  return order;
}

inline Mesh scrambled(const Mesh& mesh, unsigned seed = 5) {
  const std::vector<int> to = random_order(mesh.num_vertices(), seed);
  std::vector<Vec2> vertices(mesh.vertices().size());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    vertices[static_cast<std::size_t>(to[static_cast<std::size_t>(v)])] = mesh.vertex(v);
  std::vector<std::vector<int>> elements = mesh.elements();
  for (auto& e : elements)
    for (int& v : e) v = to[static_cast<std::size_t>(v)];
  return Mesh(std::move(vertices), std::move(elements));
}

inline Mesh3D scrambled(const Mesh3D& mesh, unsigned seed = 5) {
  const std::vector<int> to = random_order(mesh.num_vertices(), seed);
  std::vector<Vec3> vertices(mesh.vertices().size());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    vertices[static_cast<std::size_t>(to[static_cast<std::size_t>(v)])] = mesh.vertex(v);
  std::vector<CellFaces> cells;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    CellFaces faces = mesh.cell(c);
    for (auto& loop : faces)
      for (int& v : loop) v = to[static_cast<std::size_t>(v)];
    cells.push_back(std::move(faces));
  }
  return Mesh3D(std::move(vertices), std::move(cells));
}

}  // namespace hemivem::test
