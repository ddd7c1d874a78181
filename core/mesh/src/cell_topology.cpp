// The cells of a mesh not made (cell_topology.hpp).
#include "cell_topology.hpp"

#include <hemivem/error.hpp>

#include <algorithm>
#include <string>

namespace hemivem::detail {

CellTopology::CellTopology(int dim, int num_vertices, std::vector<int> first, std::vector<int> at, std::vector<int> loops)
    : dim_(dim), num_vertices_(num_vertices), first_(std::move(first)), at_(std::move(at)), loops_(std::move(loops)) {
  const auto num_loops = at_.size() - 1;
  for (std::size_t k = 0; k < num_loops; ++k)
    if (at_[k] == at_[k + 1]) throw InternalError("a cell's facet of no vertex");
  for (int v : loops_)
    if (v < 0 || v >= num_vertices_)
      throw InternalError("a cell's facet names the vertex " + std::to_string(v) + " of " + std::to_string(num_vertices_));
  // each cell's vertices, increasing: counted, then listed
  std::vector<int> scratch;
  const auto distinct_vertices = [&](int c) {
    scratch.clear();
    for (int k = first_[static_cast<std::size_t>(c)]; k < first_[static_cast<std::size_t>(c) + 1]; ++k)
      scratch.insert(scratch.end(), loops_.begin() + at_[static_cast<std::size_t>(k)], loops_.begin() + at_[static_cast<std::size_t>(k) + 1]);
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
  };
  vertex_start_.reserve(first_.size());
  vertex_start_.assign(1, 0);
  for (int c = 0; c < num_cells(); ++c) {
    distinct_vertices(c);
    vertex_start_.push_back(vertex_start_.back() + static_cast<int>(scratch.size()));
  }
  vertices_.reserve(static_cast<std::size_t>(vertex_start_.back()));
  for (int c = 0; c < num_cells(); ++c) {
    distinct_vertices(c);
    vertices_.insert(vertices_.end(), scratch.begin(), scratch.end());
  }
  around_ = hemivem::vertex_cells(num_vertices_, num_cells(), [&](int c) { return cell_vertices(c); });
  // the facets: each loop not yet a facet's is the first of its vertices (an earlier one would
  // have found it), and numbers the later ones
  facet_of_loop_.assign(num_loops, -1);
  second_.assign(num_loops, -1);
  std::vector<int> key;
  for (std::size_t k = 0; k < num_loops; ++k) {
    if (facet_of_loop_[k] >= 0) continue;
    key.assign(loops_.begin() + at_[k], loops_.begin() + at_[k + 1]);
    std::sort(key.begin(), key.end());
    const int f = static_cast<int>(k);
    facet_of_loop_[k] = f;
    int j = next_loop(key, f + 1, scratch);
    if (j >= 0) second_[k] = cell_of_loop(j);
    for (; j >= 0; j = next_loop(key, j + 1, scratch)) facet_of_loop_[static_cast<std::size_t>(j)] = f;
  }
}

int CellTopology::cell_of_loop(int k) const {
  // first a guess from the mean number of loops of a cell, right on a mesh of one kind of cell
  const auto cells = static_cast<long long>(num_cells());
  const auto guess = static_cast<std::size_t>(static_cast<long long>(k) * cells / static_cast<long long>(at_.size() - 1));
  if (first_[guess] <= k && k < first_[guess + 1]) return static_cast<int>(guess);
  return static_cast<int>(std::upper_bound(first_.begin(), first_.end(), k) - first_.begin()) - 1;
}

int CellTopology::next_loop(std::span<const int> key, int from, std::vector<int>& scratch) const {
  for (const int cell : around_.of(key[0])) {
    const auto c = static_cast<std::size_t>(cell);
    if (first_[c + 1] <= from) continue;
    for (int j = std::max(first_[c], from); j < first_[c + 1]; ++j) {
      const auto b = loops_.begin() + at_[static_cast<std::size_t>(j)], e = loops_.begin() + at_[static_cast<std::size_t>(j) + 1];
      if (static_cast<std::size_t>(e - b) != key.size() || *std::min_element(b, e) != key[0]) continue;
      scratch.assign(b, e);
      std::sort(scratch.begin(), scratch.end());
      if (std::equal(scratch.begin(), scratch.end(), key.begin(), key.end())) return j;
    }
  }
  return -1;
}

std::span<const int> CellTopology::cell_vertices(int c) const {
  const auto from = static_cast<std::size_t>(vertex_start_[static_cast<std::size_t>(c)]);
  return std::span<const int>(vertices_).subspan(from, static_cast<std::size_t>(vertex_start_[static_cast<std::size_t>(c) + 1]) - from);
}

std::span<const int> CellTopology::cell_facets(int c) const {
  const auto from = static_cast<std::size_t>(first_[static_cast<std::size_t>(c)]);
  return std::span<const int>(facet_of_loop_).subspan(from, static_cast<std::size_t>(first_[static_cast<std::size_t>(c) + 1]) - from);
}

std::span<const int> CellTopology::facet_loop(int f) const {
  const auto k = static_cast<std::size_t>(f);
  return std::span<const int>(loops_).subspan(static_cast<std::size_t>(at_[k]), static_cast<std::size_t>(at_[k + 1] - at_[k]));
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
  std::vector<int> first{0}, at{0}, loops;
  std::size_t num_edges = 0;
  for (const std::vector<int>& e : elements) num_edges += e.size();
  first.reserve(elements.size() + 1);
  at.reserve(num_edges + 1);
  loops.reserve(2 * num_edges);
  for (const std::vector<int>& e : elements) {
    for (std::size_t i = 0; i < e.size(); ++i) {
      loops.insert(loops.end(), {e[i], e[(i + 1) % e.size()]});
      at.push_back(static_cast<int>(loops.size()));
    }
    first.push_back(static_cast<int>(at.size()) - 1);
  }
  return CellTopology(2, num_vertices, std::move(first), std::move(at), std::move(loops));
}

CellTopology solid_topology(int num_vertices, const std::vector<CellFaces>& cells) {
  std::vector<int> first{0}, at{0}, loops;
  std::size_t num_faces = 0, num_ends = 0;
  for (const CellFaces& cell : cells)
    for (const std::vector<int>& face : cell) ++num_faces, num_ends += face.size();
  first.reserve(cells.size() + 1);
  at.reserve(num_faces + 1);
  loops.reserve(num_ends);
  for (const CellFaces& cell : cells) {
    for (const std::vector<int>& face : cell) {
      loops.insert(loops.end(), face.begin(), face.end());
      at.push_back(static_cast<int>(loops.size()));
    }
    first.push_back(static_cast<int>(at.size()) - 1);
  }
  return CellTopology(3, num_vertices, std::move(first), std::move(at), std::move(loops));
}

}  // namespace hemivem::detail
