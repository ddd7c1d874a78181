// Quadrature in space: triangles (a degree-5 rule) and polyhedral cells (a signed fan of
// tetrahedra with a degree-2 rule on each).
#pragma once

#include <vector>

#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/quadrature.hpp>

namespace hemivem::quadrature {

/// Integral of g over the triangle (a, b, c) in space (degree 5).
template <class G>
auto integrate_triangle_3d(const Vec3& a, const Vec3& b, const Vec3& c, G&& g) {
  const double area = 0.5 * scale_free_norm((b - a).cross(c - a));
  const auto& rule = triangle_rule();
  auto sum = detail::materialize(rule[0].weight * g(Vec3(rule[0].l1 * a + rule[0].l2 * b + rule[0].l3 * c)));
  for (std::size_t q = 1; q < rule.size(); ++q) sum += rule[q].weight * g(Vec3(rule[q].l1 * a + rule[q].l2 * b + rule[q].l3 * c));
  return detail::materialize(area * sum);
}

/// Integral of g over a planar polygon in space as the fan of triangles (centroid, z_i,
/// z_{i+1}) with the degree-5 rule on each: exact for polynomials of degree 5 on polygons
/// star-shaped about their centroid.
template <class G>
auto integrate_polygon_3d(std::span<const Vec3> polygon, G&& g) {
  const Vec3 c = polygon_centroid(polygon);
  const std::size_t n = polygon.size();
  auto sum = integrate_triangle_3d(c, polygon[0], polygon[1 % n], g);
  for (std::size_t i = 1; i < n; ++i) sum += integrate_triangle_3d(c, polygon[i], polygon[(i + 1) % n], g);
  return sum;
}

/// Integral of g over a cell (vertices z, faces as outward loops of positions in z) as a
/// signed fan of tetrahedra (cell vertex mean, face centroid, edge): a degree-2 rule on each
/// (exact for quadratic g, non-convex cells included).
template <class G>
auto integrate_cell(const std::vector<Vec3>& z, const std::vector<std::vector<int>>& faces, G&& g) {
  Vec3 apex = Vec3::Zero();
  for (const Vec3& p : z) apex += p;
  apex /= static_cast<double>(z.size());
  constexpr double a = 0.5854101966249685, b = 0.1381966011250105;
  using R = decltype(detail::materialize(g(apex)));
  R sum = detail::materialize(0.0 * g(apex));
  std::vector<Vec3> loop;
  for (const auto& face : faces) {
    loop.clear();
    for (int i : face) loop.push_back(z[static_cast<std::size_t>(i)]);
    const Vec3 fc = polygon_centroid(loop);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Vec3 p[4] = {apex, fc, loop[i], loop[(i + 1) % loop.size()]};
      const double volume = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6.0;
      for (int q = 0; q < 4; ++q) {
        Vec3 x = Vec3::Zero();
        for (int k = 0; k < 4; ++k) x += (k == q ? a : b) * p[k];
        sum += (0.25 * volume) * g(x);
      }
    }
  }
  return sum;
}

}  // namespace hemivem::quadrature
