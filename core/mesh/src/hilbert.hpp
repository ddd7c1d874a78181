// Orders of points along the Hilbert curve through a rectangle or a box: a compact order (the
// seeds of Voronoi meshes, a polygon mesh's cells, a mesh's vertices shared among processes).
#pragma once

#include <cstddef>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem::detail {

/// The order of the points in the rectangle (box) along its Hilbert curve: their indices, sorted
/// by the position along the curve of their cell of a grid of 2^20 (in space 2^21) cells a side,
/// then lexicographically by their coordinates, then by index. A flat side puts every point in
/// its first cell.
std::vector<std::size_t> hilbert_order(const std::vector<Vec2>& pts, const Rectangle& d);
std::vector<std::size_t> hilbert_order(const std::vector<Vec3>& pts, const Box& d);

/// Sorts points in the rectangle (box) along its Hilbert curve (hilbert_order).
template <class Point, class Domain>
void sort_along_hilbert_curve(std::vector<Point>& pts, const Domain& d) {
  const std::vector<std::size_t> perm = hilbert_order(pts, d);
  std::vector<Point> sorted(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) sorted[i] = pts[perm[i]];
  pts = std::move(sorted);
}

}  // namespace hemivem::detail
