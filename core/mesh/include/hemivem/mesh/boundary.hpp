// Boundary parts of a mesh: boundary edges selected by segments, by a predicate on their end
// points, or by a named edge group.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// A straight segment with a tolerance: the boundary edges whose two end points lie
/// within `tolerance` (a distance) of the segment [a, b]. A point closer than the round-off of
/// the coordinates (16 machine epsilons of the largest |coordinate| of a, b and the point)
/// counts as on the segment whatever the tolerance.
struct Segment {
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();
  double tolerance = 1e-8;
  bool contains(const Vec2& p) const;
};

/// Boundary edges (ids into mesh.edges()) whose both end points lie on one of the segments.
std::vector<int> select_boundary_edges(const Mesh& mesh, const std::vector<Segment>& segments);
/// Boundary edges accepted by a predicate on their end points.
std::vector<int> select_boundary_edges(const Mesh& mesh, const std::function<bool(const Vec2&, const Vec2&)>& keep);
/// The boundary edges of a named edge group of the mesh; InputError when the group is unknown
/// or holds an edge that is not on the boundary.
std::vector<int> select_boundary_edges(const Mesh& mesh, const std::string& group);
/// The sides of a rectangle as segments: "left" (x = x0), "right", "bottom" (y = y0), "top",
/// with the distance tolerance relative_tolerance * max(width, height): the same selection at
/// every scale. Throws InputError for any other name.
Segment rectangle_side(const Rectangle& r, const std::string& side, double relative_tolerance = 1e-8);

}  // namespace hemivem
