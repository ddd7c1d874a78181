// Where one body lies in a mesh of several.
#pragma once

#include <string>
#include <vector>

namespace hemivem {

/// One body of a mesh of several (a scene's [[body]]): its name, and its vertices and cells, each
/// a consecutive range of the mesh's; its cells' regions are its own shifted by first_region.
struct BodyRange {
  std::string name;
  int first_vertex = 0, vertices = 0;
  int first_cell = 0, cells = 0;
  int first_region = 0;
  bool has_vertex(int v) const noexcept { return v >= first_vertex && v < first_vertex + vertices; }
  bool operator==(const BodyRange&) const = default;
};

/// The first vertex of each body of a mesh of `num_vertices` vertices, and `num_vertices` last:
/// {0, num_vertices} for a mesh of one body (`bodies` empty), whose first body starts at 0.
inline std::vector<int> body_vertex_starts(const std::vector<BodyRange>& bodies, int num_vertices) {
  std::vector<int> starts{0};
  for (std::size_t b = 1; b < bodies.size(); ++b) starts.push_back(bodies[b].first_vertex);
  starts.push_back(num_vertices);
  return starts;
}

/// The bodies of a whole mesh as a process's piece of it sees them, the piece holding every
/// vertex of the whole, numbered as the whole numbers them (BasicElasticityProblem::piece_bodies):
/// body b's vertices are first_vertex[b], ..., first_vertex[b + 1] - 1 (first_vertex.back() the
/// number of vertices), and it has cells[b] cells in the whole mesh.
struct PieceBodies {
  std::vector<int> first_vertex;
  std::vector<int> cells;
  bool empty() const noexcept { return first_vertex.empty(); }
};

}  // namespace hemivem
