// Positions along the Hilbert curve of the cells of a regular grid, in the plane and in space:
// a compact order of points (the seeds of Voronoi meshes, a mesh's vertices).
#pragma once

#include <array>
#include <cstdint>
#include <utility>

namespace hemivem::detail {

/// Position of cell (x, y) of a 2^order x 2^order grid along the Hilbert curve.
inline std::uint64_t hilbert_index(std::uint64_t x, std::uint64_t y, int order) {
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
inline std::uint64_t hilbert_index(std::array<std::uint32_t, 3> X, int bits) {
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

}  // namespace hemivem::detail
