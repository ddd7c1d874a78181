// The types of a dimension, for code written once for plane (dim = 2) and solid (dim = 3)
// bodies: a point and the mesh of polygons or polyhedra.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <utility>
#include <vector>
#include <type_traits>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// A point or vector of the dimension (Vec2, Vec3).
template <int dim>
using PointOf = Eigen::Matrix<double, dim, 1>;

/// The mesh of the dimension: polygons (Mesh) or polyhedra (Mesh3D).
template <int dim>
using MeshOf = std::conditional_t<dim == 2, Mesh, Mesh3D>;

/// A vector field of the dimension (VectorField, VectorField3).
template <int dim>
using VectorFieldOf = std::function<PointOf<dim>(const PointOf<dim>&)>;

/// The dimension of a mesh type.
template <class MeshType>
inline constexpr int dimension_of = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;

/// The point of `points` nearest `x`, the least numbered of the nearest, and its distance (-1
/// and infinity when there is none): the vertex a support at `x` holds (a scene's point support,
/// and the piece of a mesh that holds it).
template <int dim>
std::pair<int, double> nearest_point(const std::vector<PointOf<dim>>& points, const PointOf<dim>& x) {
  int best = -1;
  double distance = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < points.size(); ++v)
    if (const double d = (points[v] - x).norm(); d < distance) {
      distance = d;
      best = static_cast<int>(v);
    }
  return {best, distance};
}

}  // namespace hemivem
