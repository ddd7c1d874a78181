// Quadrature on triangles, polygons (a signed fan of triangles) and segments.
#pragma once

#include <array>
#include <cmath>
#include <span>
#include <type_traits>

#include <hemivem/mesh/mesh.hpp>

namespace hemivem::quadrature {

namespace detail {
template <class T>
auto materialize(T&& x) {
  if constexpr (std::is_arithmetic_v<std::decay_t<T>>)
    return static_cast<std::decay_t<T>>(x);
  else
    return x.eval();
}
}  // namespace detail

/// Degree-5 rule on a triangle (7 points, Dunavant): barycentric points and weights
/// summing to one.
struct TrianglePoint {
  double l1, l2, l3, weight;
};
inline const std::array<TrianglePoint, 7>& triangle_rule() {
  static const std::array<TrianglePoint, 7> rule = [] {
    const double s = std::sqrt(15.0);
    const double a1 = (9.0 - 2.0 * s) / 21.0, b1 = (6.0 + s) / 21.0, w1 = (155.0 + s) / 1200.0;
    const double a2 = (9.0 + 2.0 * s) / 21.0, b2 = (6.0 - s) / 21.0, w2 = (155.0 - s) / 1200.0;
    return std::array<TrianglePoint, 7>{{{1.0 / 3, 1.0 / 3, 1.0 / 3, 0.225},
                                         {a1, b1, b1, w1},
                                         {b1, a1, b1, w1},
                                         {b1, b1, a1, w1},
                                         {a2, b2, b2, w2},
                                         {b2, a2, b2, w2},
                                         {b2, b2, a2, w2}}};
  }();
  return rule;
}

/// Integral of f over the triangle (a, b, c), signed: negative when (a, b, c) is clockwise.
template <class F>
auto integrate_triangle(const Vec2& a, const Vec2& b, const Vec2& c, F&& f) {
  const Vec2 ab = b - a, ac = c - a;
  const double area = 0.5 * (ab.x() * ac.y() - ab.y() * ac.x());
  const auto& rule = triangle_rule();
  auto sum = detail::materialize(rule[0].weight * f(Vec2(rule[0].l1 * a + rule[0].l2 * b + rule[0].l3 * c)));
  for (std::size_t q = 1; q < rule.size(); ++q)
    sum += rule[q].weight * f(Vec2(rule[q].l1 * a + rule[q].l2 * b + rule[q].l3 * c));
  return detail::materialize(area * sum);
}

/// Integral of f over a simple polygon (any orientation-consistent, possibly non-convex)
/// as a signed fan of triangles from its first vertex: exact for polynomials of degree 5
/// defined on the fan's triangles.
template <class F>
auto integrate_polygon(std::span<const Vec2> polygon, F&& f) {
  auto sum = integrate_triangle(polygon[0], polygon[1], polygon[2], f);
  for (std::size_t i = 2; i + 1 < polygon.size(); ++i) sum += integrate_triangle(polygon[0], polygon[i], polygon[i + 1], f);
  return sum;
}

/// 3-point Gauss-Legendre rule on [0, 1] (exact to degree 5).
struct SegmentPoint {
  double t, weight;
};
inline const std::array<SegmentPoint, 3>& segment_rule() {
  static const std::array<SegmentPoint, 3> rule = [] {
    const double d = 0.5 * std::sqrt(0.6);
    return std::array<SegmentPoint, 3>{{{0.5 - d, 5.0 / 18.0}, {0.5, 8.0 / 18.0}, {0.5 + d, 5.0 / 18.0}}};
  }();
  return rule;
}

}  // namespace hemivem::quadrature
