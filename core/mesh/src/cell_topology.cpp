// The cells of a mesh not made (cell_topology.hpp).
#include "cell_topology.hpp"

#include <hemivem/error.hpp>

#include <algorithm>
#include <string>

namespace hemivem::detail {

int CellShapes::add(const std::vector<std::vector<int>>& loops) {
  for (const std::vector<int>& loop : loops) {
    corner.insert(corner.end(), loop.begin(), loop.end());
    at.push_back(static_cast<int>(corner.size()));
  }
  first.push_back(static_cast<int>(at.size()) - 1);
  return size() - 1;
}

int CellShapes::corners(int s) const {
  int n = 0;
  for (int i = at[static_cast<std::size_t>(first[static_cast<std::size_t>(s)])];
       i < at[static_cast<std::size_t>(first[static_cast<std::size_t>(s) + 1])]; ++i)
    n = std::max(n, corner[static_cast<std::size_t>(i)] + 1);
  return n;
}

CellTopology::CellTopology(int dim, int num_vertices, CellShapes shapes, std::vector<int> shape_of,
                           std::vector<int> corner_start, std::vector<int> corners)
    : dim_(dim),
      num_vertices_(num_vertices),
      shapes_(std::move(shapes)),
      shape_of_(std::move(shape_of)),
      corner_start_(std::move(corner_start)),
      corners_(std::move(corners)) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  if (corner_start_.size() != shape_of_.size() + 1 || corner_start_.front() != 0 ||
      corner_start_.back() != static_cast<int>(corners_.size()))
    throw InternalError("the corners of " + std::to_string(shape_of_.size()) + " cells listed for " +
                        std::to_string(static_cast<long long>(corner_start_.size()) - 1));
  for (std::size_t j = 0; j + 1 < shapes_.at.size(); ++j)
    if (shapes_.at[j] >= shapes_.at[j + 1]) throw InternalError("a cell's facet of no vertex");
  for (int c : shapes_.corner)
    if (c < 0) throw InternalError("a cell shape's loop through the corner " + std::to_string(c));
  std::vector<int> shape_corners(at(shapes_.size()));
  for (int s = 0; s < shapes_.size(); ++s) shape_corners[at(s)] = shapes_.corners(s);
  for (std::size_t c = 0; c < shape_of_.size(); ++c) {
    const int s = shape_of_[c];
    if (s < 0 || s >= shapes_.size() || corner_start_[c + 1] - corner_start_[c] != shape_corners[at(s)])
      throw InternalError("cell " + std::to_string(c) + " has " + std::to_string(corner_start_[c + 1] - corner_start_[c]) +
                          " corners, which its shape does not run through");
  }
  for (int v : corners_)
    if (v < 0 || v >= num_vertices_)
      throw InternalError("a cell's facet names the vertex " + std::to_string(v) + " of " + std::to_string(num_vertices_));
  first_.reserve(shape_of_.size() + 1);
  first_.assign(1, 0);
  for (int s : shape_of_) first_.push_back(first_.back() + shapes_.first[at(s) + 1] - shapes_.first[at(s)]);
  around_ = hemivem::vertex_cells(num_vertices_, num_cells(), [&](int c) { return cell_vertices(c); });
  // the facets: each loop not yet a facet's is the first of its vertices (an earlier one would
  // have found it), and numbers the later ones
  const auto num_loops = at(first_.back());
  facet_of_loop_.assign(num_loops, -1);
  second_.assign(num_loops, -1);
  std::vector<int> key, scratch;
  for (int c = 0; c < num_cells(); ++c)
    for (int k = first_[at(c)]; k < first_[at(c) + 1]; ++k) {
      if (facet_of_loop_[at(k)] >= 0) continue;
      key.clear();
      for_loop(shape_loop(c) + k, corners_of(c), [&](int v) { key.push_back(v); });
      std::sort(key.begin(), key.end());
      facet_of_loop_[at(k)] = k;
      int j = next_loop(key, k + 1, scratch);
      if (j >= 0) second_[at(k)] = cell_of_loop(j);
      for (; j >= 0; j = next_loop(key, j + 1, scratch)) facet_of_loop_[at(j)] = k;
    }
}

int CellTopology::cell_of_loop(int k) const {
  // first a guess from the mean number of loops of a cell, right on a mesh of one kind of cell
  const auto cells = static_cast<long long>(num_cells());
  const auto guess = static_cast<std::size_t>(static_cast<long long>(k) * cells / static_cast<long long>(first_.back()));
  if (first_[guess] <= k && k < first_[guess + 1]) return static_cast<int>(guess);
  return static_cast<int>(std::upper_bound(first_.begin(), first_.end(), k) - first_.begin()) - 1;
}

std::span<const int> CellTopology::corners_of(int c) const {
  const auto from = static_cast<std::size_t>(corner_start_[static_cast<std::size_t>(c)]);
  return std::span<const int>(corners_).subspan(from, static_cast<std::size_t>(corner_start_[static_cast<std::size_t>(c) + 1]) - from);
}

int CellTopology::next_loop(std::span<const int> key, int from, std::vector<int>& scratch) const {
  for (const int cell : around_.of(key[0])) {
    const auto c = static_cast<std::size_t>(cell);
    if (first_[c + 1] <= from) continue;
    const std::span<const int> corners = corners_of(cell);
    const int offset = shape_loop(cell);  // loop j is the shape's loop offset + j
    for (int j = std::max(first_[c], from); j < first_[c + 1]; ++j) {
      const int l = offset + j;
      if (shapes_.at[static_cast<std::size_t>(l) + 1] - shapes_.at[static_cast<std::size_t>(l)] != static_cast<int>(key.size()))
        continue;
      int smallest = num_vertices_;
      for_loop(l, corners, [&](int v) { smallest = std::min(smallest, v); });
      if (smallest != key[0]) continue;
      scratch.clear();
      for_loop(l, corners, [&](int v) { scratch.push_back(v); });
      std::sort(scratch.begin(), scratch.end());
      if (std::equal(scratch.begin(), scratch.end(), key.begin(), key.end())) return j;
    }
  }
  return -1;
}

std::vector<int> CellTopology::cell_vertices(int c) const {
  const std::span<const int> corners = corners_of(c);
  std::vector<int> vertices(corners.begin(), corners.end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

std::span<const int> CellTopology::cell_facets(int c) const {
  const auto from = static_cast<std::size_t>(first_[static_cast<std::size_t>(c)]);
  return std::span<const int>(facet_of_loop_).subspan(from, static_cast<std::size_t>(first_[static_cast<std::size_t>(c) + 1]) - from);
}

std::vector<int> CellTopology::facet_loop(int f) const {
  const int c = cell_of_loop(f);
  std::vector<int> loop;
  for_loop(shape_loop(c) + f, corners_of(c), [&](int v) { loop.push_back(v); });
  return loop;
}

int CellTopology::find_facet(std::vector<int> vertices) const {
  if (vertices.empty()) return -1;
  std::sort(vertices.begin(), vertices.end());
  if (vertices.front() < 0 || vertices.back() >= num_vertices_) return -1;
  std::vector<int> scratch;
  const int j = next_loop(vertices, 0, scratch);
  return j < 0 ? -1 : facet_of_loop_[static_cast<std::size_t>(j)];
}

CellTopology plane_topology(int num_vertices, const std::vector<std::vector<int>>& elements) {
  CellShapes shapes;
  std::vector<int> shape_of_size;  // the shape of each number of vertices (-1: none yet)
  std::vector<int> shape_of, corner_start{0}, corners;
  std::size_t num_corners = 0;
  for (const std::vector<int>& e : elements) num_corners += e.size();
  shape_of.reserve(elements.size());
  corner_start.reserve(elements.size() + 1);
  corners.reserve(num_corners);
  for (const std::vector<int>& e : elements) {
    const std::size_t n = e.size();
    if (n >= shape_of_size.size()) shape_of_size.resize(n + 1, -1);
    if (shape_of_size[n] < 0) {
      std::vector<std::vector<int>> edges;
      for (std::size_t i = 0; i < n; ++i) edges.push_back({static_cast<int>(i), static_cast<int>((i + 1) % n)});
      shape_of_size[n] = shapes.add(edges);
    }
    shape_of.push_back(shape_of_size[n]);
    corners.insert(corners.end(), e.begin(), e.end());
    corner_start.push_back(static_cast<int>(corners.size()));
  }
  return CellTopology(2, num_vertices, std::move(shapes), std::move(shape_of), std::move(corner_start), std::move(corners));
}

CellTopology solid_topology(int num_vertices, const std::vector<CellFaces>& cells) {
  CellShapes shapes;
  std::vector<int> shape_of, corner_start{0}, corners;
  shape_of.reserve(cells.size());
  corner_start.reserve(cells.size() + 1);
  std::vector<std::vector<int>> loops;
  for (const CellFaces& cell : cells) {
    const auto from = static_cast<std::ptrdiff_t>(corners.size());
    for (const std::vector<int>& face : cell) corners.insert(corners.end(), face.begin(), face.end());
    std::sort(corners.begin() + from, corners.end());
    corners.erase(std::unique(corners.begin() + from, corners.end()), corners.end());
    loops.assign(cell.size(), {});
    for (std::size_t f = 0; f < cell.size(); ++f)
      for (int v : cell[f])
        loops[f].push_back(static_cast<int>(std::lower_bound(corners.begin() + from, corners.end(), v) - corners.begin() - from));
    shape_of.push_back(shapes.add(loops));
    corner_start.push_back(static_cast<int>(corners.size()));
  }
  return CellTopology(3, num_vertices, std::move(shapes), std::move(shape_of), std::move(corner_start), std::move(corners));
}

}  // namespace hemivem::detail
