// A rigid obstacle in place of a given gap: the gap of a contact node is the signed distance
// from the node to the obstacle's surface along the node's outward normal.
#pragma once

#include <string>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

struct Obstacle {
  enum class Shape {
    plane,     ///< the half-plane behind `point` with `normal` pointing into the body
    circle,    ///< a rigid disk (`center`, `radius`)
    polyline,  ///< the surface `points`, the body on its left when walking along it
  };
  Shape shape = Shape::plane;
  Vec2 point = Vec2::Zero();
  Vec2 normal = Vec2(0.0, 1.0);
  Vec2 center = Vec2::Zero();
  double radius = 1.0;
  std::vector<Vec2> points;

  /// The gap of a node at x with outward unit normal nu: the t with x + t nu on the
  /// obstacle's surface where the ray enters the obstacle, the one nearest to x (t < 0 when x
  /// starts inside: an indenter pressed in); +inf when the ray never enters it.
  double gap(const Vec2& x, const Vec2& nu) const;
  /// Empty when the obstacle is well formed, else what is wrong (a zero normal, a radius that
  /// is not positive, fewer than two points or two equal consecutive points).
  std::string defect() const;
};

/// "plane", "circle", "polyline".
std::string to_string(Obstacle::Shape shape);
/// The shape of a name; InputError for another name.
Obstacle::Shape obstacle_shape_from_string(const std::string& name);

/// A rigid obstacle of a three-dimensional body; gap() as Obstacle::gap, along the node's normal.
struct Obstacle3D {
  enum class Shape {
    plane,     ///< the half-space behind `point` with `normal` pointing into the body
    sphere,    ///< a rigid ball (`center`, `radius`)
    cylinder,  ///< a rigid infinite cylinder (`center` on its axis, `axis`, `radius`)
  };
  Shape shape = Shape::plane;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3(0.0, 0.0, 1.0);
  Vec3 center = Vec3::Zero();
  Vec3 axis = Vec3(1.0, 0.0, 0.0);
  double radius = 1.0;
  /// The t with x + t nu on the surface where the ray enters the obstacle, the one nearest to x
  /// (t < 0 when x starts inside); +inf when the ray never enters it.
  double gap(const Vec3& x, const Vec3& nu) const;
  /// Empty when well formed, else what is wrong (a zero normal or axis, a radius that is not positive).
  std::string defect() const;
};
/// "plane", "sphere", "cylinder".
std::string to_string(Obstacle3D::Shape shape);
/// The shape of a name; InputError for another name.
Obstacle3D::Shape obstacle3d_shape_from_string(const std::string& name);

}  // namespace hemivem
