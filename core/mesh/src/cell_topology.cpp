// The cells of a mesh not made (cell_topology.hpp).
#include "cell_topology.hpp"

#include <hemivem/error.hpp>

#include <algorithm>
#include <string>

namespace hemivem::detail {

namespace {

/// Whether the increasing vertex list a comes before b (a shorter list before one it begins).
bool before(std::span<const int> a, std::span<const int> b) {
  return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end());
}
bool same(std::span<const int> a, std::span<const int> b) { return std::equal(a.begin(), a.end(), b.begin(), b.end()); }

}  // namespace

CellTopology::CellTopology(int dim, int num_vertices, std::vector<int> first, std::vector<int> at, std::vector<int> loops)
    : dim_(dim), num_vertices_(num_vertices), first_(std::move(first)), at_(std::move(at)), loops_(std::move(loops)) {
  const auto num_loops = at_.size() - 1;
  // the facets: the loops sorted by their increasing vertices (then by number), each run of
  // equal ones a facet
  std::vector<int> increasing = loops_;
  for (std::size_t k = 0; k < num_loops; ++k)
    std::sort(increasing.begin() + at_[k], increasing.begin() + at_[k + 1]);
  const auto vertices_of = [&](int k) {
    const auto from = static_cast<std::size_t>(at_[static_cast<std::size_t>(k)]);
    return std::span<const int>(increasing).subspan(from, static_cast<std::size_t>(at_[static_cast<std::size_t>(k) + 1]) - from);
  };
  std::vector<int> sorted(num_loops);
  for (std::size_t k = 0; k < num_loops; ++k) sorted[k] = static_cast<int>(k);
  std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
    const auto x = vertices_of(a), y = vertices_of(b);
    return before(x, y) || (same(x, y) && a < b);
  });
  std::vector<int> cell_of_loop(num_loops);
  for (int c = 0; c < num_cells(); ++c)
    for (int k = first_[static_cast<std::size_t>(c)]; k < first_[static_cast<std::size_t>(c) + 1]; ++k)
      cell_of_loop[static_cast<std::size_t>(k)] = c;
  facet_of_loop_.assign(num_loops, -1);
  std::size_t count = 0;  // the facets: the runs of equal vertices
  for (std::size_t i = 0; i < sorted.size(); ++i)
    count += i == 0 || !same(vertices_of(sorted[i]), vertices_of(sorted[i - 1])) ? 1 : 0;
  facet_cells_.reserve(count);
  loop_of_facet_.reserve(count);
  key_at_.reserve(count + 1);
  key_at_.assign(1, 0);
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i + 1;
    while (j < sorted.size() && same(vertices_of(sorted[j]), vertices_of(sorted[i]))) ++j;
    const int f = static_cast<int>(facet_cells_.size());
    // the loops of a facet by their cells: its first cell's loop first
    int lowest = sorted[i];
    for (std::size_t k = i; k < j; ++k) {
      facet_of_loop_[static_cast<std::size_t>(sorted[k])] = f;
      if (cell_of_loop[static_cast<std::size_t>(sorted[k])] < cell_of_loop[static_cast<std::size_t>(lowest)]) lowest = sorted[k];
    }
    std::array<int, 2> cells{cell_of_loop[static_cast<std::size_t>(lowest)], -1};
    for (std::size_t k = i; k < j && cells[1] < 0; ++k)
      if (sorted[k] != lowest) cells[1] = cell_of_loop[static_cast<std::size_t>(sorted[k])];
    facet_cells_.push_back(cells);
    loop_of_facet_.push_back(lowest);
    const auto key = vertices_of(sorted[i]);
    keys_.insert(keys_.end(), key.begin(), key.end());
    key_at_.push_back(static_cast<int>(keys_.size()));
    i = j;
  }
  decltype(sorted)().swap(sorted);  // given back (assigning an empty one keeps the storage)
  decltype(increasing)().swap(increasing);
  decltype(cell_of_loop)().swap(cell_of_loop);
  vertex_start_.reserve(first_.size());
  vertices_.reserve(loops_.size() / 2);
  vertex_start_.assign(1, 0);
  for (int c = 0; c < num_cells(); ++c) {
    const auto from = vertices_.size();
    for (int k = first_[static_cast<std::size_t>(c)]; k < first_[static_cast<std::size_t>(c) + 1]; ++k)
      vertices_.insert(vertices_.end(), loops_.begin() + at_[static_cast<std::size_t>(k)], loops_.begin() + at_[static_cast<std::size_t>(k) + 1]);
    std::sort(vertices_.begin() + static_cast<std::ptrdiff_t>(from), vertices_.end());
    vertices_.erase(std::unique(vertices_.begin() + static_cast<std::ptrdiff_t>(from), vertices_.end()), vertices_.end());
    vertex_start_.push_back(static_cast<int>(vertices_.size()));
  }
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
  const auto k = static_cast<std::size_t>(loop_of_facet_[static_cast<std::size_t>(f)]);
  return std::span<const int>(loops_).subspan(static_cast<std::size_t>(at_[k]), static_cast<std::size_t>(at_[k + 1] - at_[k]));
}

int CellTopology::find_facet(std::vector<int> vertices) const {
  if (vertices.empty()) return -1;
  std::sort(vertices.begin(), vertices.end());
  const auto key = [&](int f) {
    const auto from = static_cast<std::size_t>(key_at_[static_cast<std::size_t>(f)]);
    return std::span<const int>(keys_).subspan(from, static_cast<std::size_t>(key_at_[static_cast<std::size_t>(f) + 1]) - from);
  };
  int lo = 0, hi = num_facets();  // the facets' keys increase with their numbers
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (before(key(mid), vertices)) lo = mid + 1;
    else hi = mid;
  }
  return lo < num_facets() && same(key(lo), vertices) ? lo : -1;
}

CellTopology plane_topology(int num_vertices, const std::vector<std::vector<int>>& elements) {
  std::vector<int> first{0}, at{0}, loops;
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
