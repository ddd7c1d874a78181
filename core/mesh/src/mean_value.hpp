// Mean value coordinates of a point with respect to a polygon, shared by the refinement of
// polygonal and polyhedral meshes (private to the mesh module).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace hemivem::detail {

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
    const double cr = d[i].x() * d[j].y() - d[i].y() * d[j].x(), dt = d[i].dot(d[j]), rr = r[i] * r[j];
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
