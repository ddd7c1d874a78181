#include <hemivem/mesh/vertex_order.hpp>

#include "hilbert.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>

namespace hemivem {

namespace {

/// The cell of coordinate t in [lower, lower + size] on a grid of `cells` cells (0 for a flat box).
std::uint64_t grid_cell(double t, double lower, double size, double cells) {
  return size > 0.0 ? static_cast<std::uint64_t>(std::clamp((t - lower) / size * cells, 0.0, cells - 1.0)) : 0;
}

/// The vertices sorted by `key`, then by their coordinates, then by their numbers.
template <class Point>
std::vector<int> sorted_by_key(const std::vector<std::uint64_t>& key, const std::vector<Point>& points) {
  std::vector<int> order(key.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
    if (key[i] != key[j]) return key[i] < key[j];
    const auto& p = points[i];
    const auto& q = points[j];
    for (Eigen::Index c = 0; c < p.size(); ++c)
      if (p(c) != q(c)) return p(c) < q(c);
    return a < b;
  });
  return order;
}

/// The vertices of a mesh sorted by key_of(their point) (sorted_by_key).
template <class MeshType, class Key>
std::vector<int> sorted_by(const MeshType& mesh, Key&& key_of) {
  std::vector<std::uint64_t> key(static_cast<std::size_t>(mesh.num_vertices()));
  for (int v = 0; v < mesh.num_vertices(); ++v) key[static_cast<std::size_t>(v)] = key_of(mesh.vertex(v));
  return sorted_by_key(key, mesh.vertices());
}

}  // namespace

std::vector<int> hilbert_vertex_order(const Mesh& mesh) {
  constexpr int order = 20;
  constexpr double cells = 1 << order;
  if (mesh.num_vertices() == 0) return {};
  const Rectangle box = mesh.bounding_box();
  return sorted_by(mesh, [&](const Vec2& p) {
    return detail::hilbert_index(grid_cell(p.x(), box.x0, box.width(), cells),
                                 grid_cell(p.y(), box.y0, box.height(), cells), order);
  });
}

std::vector<int> hilbert_vertex_order(const Mesh3D& mesh) {
  constexpr int bits = 21;
  constexpr double cells = 1 << bits;
  if (mesh.num_vertices() == 0) return {};
  const Box box = mesh.bounding_box();
  return sorted_by(mesh, [&](const Vec3& p) {
    std::array<std::uint32_t, 3> X{};
    for (int a = 0; a < 3; ++a)
      X[static_cast<std::size_t>(a)] = static_cast<std::uint32_t>(grid_cell(p(a), box.lower(a), box.size(a), cells));
    return detail::hilbert_index(X, bits);
  });
}

}  // namespace hemivem
