#include <hemivem/error.hpp>
#include <hemivem/mesh/boundary.hpp>

#include "box_sides.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hemivem {

bool Segment::contains(const Vec2& p) const {
  // Round-off of the coordinates themselves: a point closer than that counts as on the segment.
  const double magnitude = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), p.cwiseAbs().maxCoeff()});
  const double tol = std::max(tolerance, 16.0 * std::numeric_limits<double>::epsilon() * magnitude);
  const Vec2 d = b - a;
  const Vec2 pa = p - a;
  const double len2 = d.squaredNorm();
  if (len2 == 0.0) return pa.norm() <= tol;
  const double t = pa.dot(d) / len2;
  if (t <= 0.0) return pa.norm() <= tol;
  if (t >= 1.0) return (p - b).norm() <= tol;
  // the distance to the line from the cross product: exact for points on an axis-parallel side
  return std::abs(d.x() * pa.y() - d.y() * pa.x()) <= tol * std::sqrt(len2);
}

std::vector<int> select_boundary_edges(const Mesh& mesh, const std::function<bool(const Vec2&, const Vec2&)>& keep) {
  std::vector<int> out;
  for (int id : mesh.boundary_edges()) {
    const auto& e = mesh.edge(id);
    if (keep(mesh.vertex(e.v0), mesh.vertex(e.v1))) out.push_back(id);
  }
  return out;
}

std::vector<int> select_boundary_edges(const Mesh& mesh, const std::vector<Segment>& segments) {
  return select_boundary_edges(mesh, [&](const Vec2& p, const Vec2& q) {
    return std::any_of(segments.begin(), segments.end(), [&](const Segment& s) { return s.contains(p) && s.contains(q); });
  });
}

std::vector<int> select_boundary_edges(const Mesh& mesh, const std::string& group) {
  const auto& edges = mesh.edge_group(group);
  for (int id : edges)
    if (!mesh.edge(id).on_boundary())
      throw InputError("edge " + std::to_string(id) + " (" + std::to_string(mesh.edge(id).v0) + "-" +
                           std::to_string(mesh.edge(id).v1) + ") is not on the boundary; a boundary part needs boundary edges",
                       "edge group '" + group + "'");
  return edges;
}

Segment rectangle_side(const Rectangle& r, const std::string& side, double relative_tolerance) {
  const double tolerance = relative_tolerance * std::max(r.width(), r.height());
  const auto [axis, upper] = detail::box_side_axis(2, side);
  if (axis == 0) {
    const double x = upper ? r.x1 : r.x0;
    return {{x, r.y0}, {x, r.y1}, tolerance};
  }
  const double y = upper ? r.y1 : r.y0;
  return {{r.x0, y}, {r.x1, y}, tolerance};
}

namespace detail {

std::pair<int, bool> box_side_axis(int dim, const std::string& side) {
  if (dim == 2) {
    if (side == "left") return {0, false};
    if (side == "right") return {0, true};
    if (side == "bottom") return {1, false};
    if (side == "top") return {1, true};
    throw InputError("unknown side '" + side + "'; expected left, right, bottom or top");
  }
  if (side == "x0") return {0, false};
  if (side == "x1") return {0, true};
  if (side == "y0") return {1, false};
  if (side == "y1") return {1, true};
  if (side == "z0" || side == "bottom") return {2, false};
  if (side == "z1" || side == "top") return {2, true};
  throw InputError("unknown side '" + side + "' of a box; expected x0, x1, y0, y1, z0, z1, bottom or top");
}

}  // namespace detail

}  // namespace hemivem
