// The cells of a mesh not made (cell_topology.hpp).
#include "cell_topology.hpp"

#include <hemivem/error.hpp>

#include <algorithm>
#include <string>

namespace hemivem::detail {

namespace {

using Key = std::array<int, 5>;

/// The sorted vertices of a loop of up to four, padded with -1, and `id` last.
Key key_of(std::span<const int> loop, int id) {
  if (loop.size() > 4) throw InternalError("CellTopology: a facet of " + std::to_string(loop.size()) + " vertices");
  Key key{-1, -1, -1, -1, id};
  std::copy(loop.begin(), loop.end(), key.begin());
  std::sort(key.begin(), key.begin() + static_cast<std::ptrdiff_t>(loop.size()));
  return key;
}

bool same_vertices(const Key& a, const Key& b) { return std::equal(a.begin(), a.begin() + 4, b.begin()); }

}  // namespace

CellTopology::CellTopology(int dim, int num_vertices, std::vector<int> first, std::vector<int> at, std::vector<int> loops)
    : dim_(dim), num_vertices_(num_vertices), first_(std::move(first)), at_(std::move(at)), loops_(std::move(loops)) {
  const auto num_loops = at_.size() - 1;
  // the facets: the loops sorted by their vertices, each run of equal ones a facet
  std::vector<Key> sorted(num_loops);
  for (std::size_t k = 0; k < num_loops; ++k)
    sorted[k] = key_of(std::span<const int>(loops_).subspan(static_cast<std::size_t>(at_[k]), static_cast<std::size_t>(at_[k + 1] - at_[k])),
                       static_cast<int>(k));
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> cell_of_loop(num_loops);
  for (int c = 0; c < num_cells(); ++c)
    for (int k = first_[static_cast<std::size_t>(c)]; k < first_[static_cast<std::size_t>(c) + 1]; ++k)
      cell_of_loop[static_cast<std::size_t>(k)] = c;
  facet_of_loop_.assign(num_loops, -1);
  std::size_t count = 0;  // the facets: the runs of equal vertices
  for (std::size_t i = 0; i < sorted.size(); ++i) count += i == 0 || !same_vertices(sorted[i], sorted[i - 1]) ? 1 : 0;
  facet_cells_.reserve(count);
  loop_of_facet_.reserve(count);
  keys_.reserve(count);
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i + 1;
    while (j < sorted.size() && same_vertices(sorted[j], sorted[i])) ++j;
    const int f = static_cast<int>(facet_cells_.size());
    // the loops of a facet by their cells: its first cell's loop first
    int lowest = sorted[i][4];
    for (std::size_t k = i; k < j; ++k) {
      facet_of_loop_[static_cast<std::size_t>(sorted[k][4])] = f;
      if (cell_of_loop[static_cast<std::size_t>(sorted[k][4])] < cell_of_loop[static_cast<std::size_t>(lowest)]) lowest = sorted[k][4];
    }
    std::array<int, 2> cells{cell_of_loop[static_cast<std::size_t>(lowest)], -1};
    for (std::size_t k = i; k < j && cells[1] < 0; ++k)
      if (sorted[k][4] != lowest) cells[1] = cell_of_loop[static_cast<std::size_t>(sorted[k][4])];
    facet_cells_.push_back(cells);
    loop_of_facet_.push_back(lowest);
    Key key = sorted[i];
    key[4] = f;
    keys_.push_back(key);
    i = j;
  }
  sorted = {};
  cell_of_loop = {};
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
  if (vertices.empty() || vertices.size() > 4) return -1;
  const Key key = key_of(vertices, -1);
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  return it != keys_.end() && same_vertices(*it, key) ? (*it)[4] : -1;
}

}  // namespace hemivem::detail
