#include "hilbert.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>

namespace hemivem::detail {

namespace {

/// Position of cell (x, y) of a 2^order x 2^order grid along the Hilbert curve.
std::uint64_t hilbert_index(std::uint64_t x, std::uint64_t y, int order) {
  std::uint64_t d = 0;
  for (std::uint64_t s = std::uint64_t{1} << (order - 1); s > 0; s >>= 1) {
    const std::uint64_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {  // rotate the quadrant
      if (rx == 1) {
        x = s - 1 - (x & (s - 1));
        y = s - 1 - (y & (s - 1));
      }
      std::swap(x, y);
    }
    x &= s - 1;
    y &= s - 1;
  }
  return d;
}

/// The position of grid point X (each coordinate `bits` bits) along the 3D Hilbert curve
/// (J. Skilling, "Programming the Hilbert curve", AIP Conf. Proc. 707, 2004).
std::uint64_t hilbert_index(std::array<std::uint32_t, 3> X, int bits) {
  const std::uint32_t M = 1u << (bits - 1);
  for (std::uint32_t Q = M; Q > 1; Q >>= 1) {  // inverse undo
    const std::uint32_t P = Q - 1;
    for (int i = 0; i < 3; ++i) {
      if (X[static_cast<std::size_t>(i)] & Q) {
        X[0] ^= P;
      } else {
        const std::uint32_t t = (X[0] ^ X[static_cast<std::size_t>(i)]) & P;
        X[0] ^= t;
        X[static_cast<std::size_t>(i)] ^= t;
      }
    }
  }
  for (std::size_t i = 1; i < 3; ++i) X[i] ^= X[i - 1];  // Gray encode
  std::uint32_t t = 0;
  for (std::uint32_t Q = M; Q > 1; Q >>= 1)
    if (X[2] & Q) t ^= Q - 1;
  for (auto& x : X) x ^= t;
  std::uint64_t d = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (std::size_t i = 0; i < 3; ++i) d = (d << 1) | ((X[i] >> b) & 1u);
  return d;
}

/// The cell of coordinate t in [lower, lower + size] on a grid of `cells` cells (0 for a flat side).
std::uint64_t grid_cell(double t, double lower, double size, double cells) {
  return size > 0.0 ? static_cast<std::uint64_t>(std::clamp((t - lower) / size * cells, 0.0, cells - 1.0)) : 0;
}

/// The indices of `pts` sorted by `key`, then by their coordinates, then by index.
template <class Point>
std::vector<std::size_t> sorted_by_key(const std::vector<std::uint64_t>& key, const std::vector<Point>& pts) {
  std::vector<std::size_t> perm(pts.size());
  std::iota(perm.begin(), perm.end(), std::size_t{0});
  std::sort(perm.begin(), perm.end(), [&](std::size_t a, std::size_t b) {
    if (key[a] != key[b]) return key[a] < key[b];
    for (Eigen::Index c = 0; c < pts[a].size(); ++c)
      if (pts[a](c) != pts[b](c)) return pts[a](c) < pts[b](c);
    return a < b;
  });
  return perm;
}

}  // namespace

std::vector<std::size_t> hilbert_order(const std::vector<Vec2>& pts, const Rectangle& d) {
  constexpr int order = 20;
  constexpr double cells = 1 << order;
  std::vector<std::uint64_t> key(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    key[i] = hilbert_index(grid_cell(pts[i].x(), d.x0, d.width(), cells),
                           grid_cell(pts[i].y(), d.y0, d.height(), cells), order);
  return sorted_by_key(key, pts);
}

std::vector<std::size_t> hilbert_order(const std::vector<Vec3>& pts, const Box& d) {
  constexpr int bits = 21;
  constexpr double cells = 1 << bits;
  std::vector<std::uint64_t> key(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    std::array<std::uint32_t, 3> X{};
    for (int a = 0; a < 3; ++a)
      X[static_cast<std::size_t>(a)] = static_cast<std::uint32_t>(grid_cell(pts[i][a], d.lower(a), d.size(a), cells));
    key[i] = hilbert_index(X, bits);
  }
  return sorted_by_key(key, pts);
}

}  // namespace hemivem::detail
