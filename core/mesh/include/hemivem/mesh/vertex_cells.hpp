// The cells of each vertex of a mesh, in compressed rows.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace hemivem {

/// The cells of vertex v: cells[start[v]], ..., cells[start[v + 1] - 1], increasing.
struct VertexCells {
  std::vector<int> start{0}, cells;
  std::span<const int> of(int v) const {
    const auto from = static_cast<std::size_t>(start[static_cast<std::size_t>(v)]);
    return std::span<const int>(cells).subspan(from, static_cast<std::size_t>(start[static_cast<std::size_t>(v) + 1]) - from);
  }
};

/// The cells of each of `num_vertices` vertices among `num_cells` cells, cell c's vertices being
/// `vertices_of(c)` (each once).
template <class Vertices>
VertexCells vertex_cells(int num_vertices, int num_cells, Vertices&& vertices_of) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  VertexCells out;
  out.start.assign(at(num_vertices) + 1, 0);
  for (int c = 0; c < num_cells; ++c)
    for (int v : vertices_of(c)) ++out.start[at(v) + 1];
  for (int v = 0; v < num_vertices; ++v) out.start[at(v) + 1] += out.start[at(v)];
  out.cells.resize(at(out.start[at(num_vertices)]));
  std::vector<int> next(out.start.begin(), out.start.end() - 1);
  for (int c = 0; c < num_cells; ++c)
    for (int v : vertices_of(c)) out.cells[at(next[at(v)]++)] = c;
  return out;
}

}  // namespace hemivem
