// The types of a dimension, for code written once for plane (dim = 2) and solid (dim = 3)
// bodies: a point and the mesh of polygons or polyhedra.
#pragma once

#include <Eigen/Core>

#include <functional>
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

}  // namespace hemivem
