// Kernels on planar polygons in local coordinates, shared by the refinement of polygonal and
// polyhedral meshes (private to the mesh module): the cross product, clipping by a half-plane,
// area and centroid, mean value coordinates.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <utility>
#include <vector>

namespace hemivem::detail {

/// The z component of the cross product of two plane vectors.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// The polygon clipped to the half-plane left of the line a -> b (Sutherland-Hodgman).
inline std::vector<Eigen::Vector2d> clip_left(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& a,
                                              const Eigen::Vector2d& b) {
  std::vector<Eigen::Vector2d> out;
  const Eigen::Vector2d d = b - a;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = poly[i];
    const Eigen::Vector2d& r = poly[(i + 1) % n];
    const double sp = cross2(d, p - a), sr = cross2(d, r - a);
    if (sp >= 0.0) out.push_back(p);
    if ((sp > 0.0 && sr < 0.0) || (sp < 0.0 && sr > 0.0)) out.push_back(p + (sp / (sp - sr)) * (r - p));
  }
  return out;
}

/// Area and centroid of a polygon (a fan around its first vertex); zero area and the origin when
/// it is degenerate or clockwise.
inline std::pair<double, Eigen::Vector2d> area_centroid(const std::vector<Eigen::Vector2d>& poly) {
  if (poly.size() < 3) return {0.0, Eigen::Vector2d::Zero()};
  const Eigen::Vector2d o = poly[0];
  double twice = 0.0;
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i] - o, b = poly[i + 1] - o;
    const double cr = cross2(a, b);
    twice += cr;
    moment += cr * (a + b);
  }
  if (!(twice > 0.0)) return {0.0, Eigen::Vector2d::Zero()};
  return {0.5 * twice, o + moment / (3.0 * twice)};
}

/// The mean value coordinates of c with respect to the polygon q (both in the polygon's plane):
/// weights summing to 1, exact for linear fields at any point from which the whole boundary is
/// seen.
inline std::vector<double> mean_value_coordinates(const std::vector<Eigen::Vector2d>& q, const Eigen::Vector2d& c) {
  const std::size_t n = q.size();
  std::vector<Eigen::Vector2d> d(n);
  std::vector<double> r(n), tan_half(n), w(n);
  for (std::size_t i = 0; i < n; ++i) {
    d[i] = q[i] - c;
    r[i] = d[i].norm();
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const double cr = cross2(d[i], d[j]), dt = d[i].dot(d[j]), rr = r[i] * r[j];
    // tan(alpha/2) = sin / (1 + cos) = (1 - cos) / sin, each form where it does not cancel
    tan_half[i] = dt >= 0.0 ? cr / (rr + dt) : (rr - dt) / cr;
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    w[i] = (tan_half[(i + n - 1) % n] + tan_half[i]) / r[i];
    sum += w[i];
  }
  for (double& x : w) x /= sum;
  return w;
}

}  // namespace hemivem::detail
