#include <hemivem/contact/condensation.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

namespace hemivem {

namespace {

template <int dim>
std::string point_text(const PointOf<dim>& x) {
  std::ostringstream out;
  out << "(";
  for (int c = 0; c < dim; ++c) out << (c ? ", " : "") << x(c);
  out << ")";
  return out.str();
}

/// The largest extent of the mesh's vertices along an axis.
template <int dim>
double mesh_size(const MeshOf<dim>& mesh) {
  PointOf<dim> lo = mesh.vertex(0), hi = mesh.vertex(0);
  for (int v = 1; v < mesh.num_vertices(); ++v) {
    lo = lo.cwiseMin(mesh.vertex(v));
    hi = hi.cwiseMax(mesh.vertex(v));
  }
  return (hi - lo).maxCoeff();
}

/// The vertices of each part's `against` facets, sorted by x; InputError for a facet out of range.
template <int dim>
std::vector<std::vector<std::pair<double, int>>> against_vertices(const MeshOf<dim>& mesh,
                                                                 const std::vector<BasicContactPart<dim>>& parts) {
  std::vector<std::vector<std::pair<double, int>>> by_x(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    std::set<int> vertices;
    for (int f : parts[k].against) {
      if (f < 0 || f >= mesh.num_facets())
        throw InputError("contact part '" + parts[k].name + "': facet " + std::to_string(f) +
                         " of the other body is out of range");
      for (int q : mesh.facet_vertices(f)) vertices.insert(q);
    }
    for (int q : vertices) by_x[k].emplace_back(mesh.vertex(q)(0), q);
    std::sort(by_x[k].begin(), by_x[k].end());
  }
  return by_x;
}

/// The vertex of `candidates` (sorted by x) at x within `tolerance`, other than p; -1 for none.
template <int dim>
int vertex_at(const MeshOf<dim>& mesh, const std::vector<std::pair<double, int>>& candidates, const PointOf<dim>& x,
              int p, double tolerance) {
  int best = -1;
  double distance = tolerance;
  for (auto it = std::lower_bound(candidates.begin(), candidates.end(), std::make_pair(x(0) - tolerance, -1));
       it != candidates.end() && it->first <= x(0) + tolerance; ++it)
    if (const double d = (mesh.vertex(it->second) - x).norm(); d <= distance && it->second != p) {
      best = it->second;
      distance = d;
    }
  return best;
}

/// A point of the line x + s nu on a facet: s and the facet's vertices with their weights.
struct Hit {
  double s = std::numeric_limits<double>::infinity();
  Across across;
};

/// Where the line x + s nu meets the plane edge (a, b), if it does (within a relative 1e-12
/// of the edge's ends).
std::optional<Hit> meet(const Mesh& mesh, const std::array<int, 2>& edge, const Vec2& x, const Vec2& nu) {
  const Vec2 a = mesh.vertex(edge[0]), d = mesh.vertex(edge[1]) - a;
  // x + s nu = a + t d: [nu, -d] (s, t) = a - x
  const double det = -nu(0) * d(1) + nu(1) * d(0);
  if (std::abs(det) <= 1e-12 * d.norm()) return std::nullopt;  // the line runs along the edge
  const Vec2 r = a - x;
  const double s = (-r(0) * d(1) + r(1) * d(0)) / det, t = (nu(0) * r(1) - nu(1) * r(0)) / det;
  constexpr double slack = 1e-12;
  if (t < -slack || t > 1.0 + slack) return std::nullopt;
  Hit h;
  h.s = s;
  const double tc = t <= slack ? 0.0 : t >= 1.0 - slack ? 1.0 : t;
  int n = 0;
  if (tc < 1.0) {
    h.across.vertex[n] = edge[0];
    h.across.weight[n++] = 1.0 - tc;
  }
  if (tc > 0.0) {
    h.across.vertex[n] = edge[1];
    h.across.weight[n++] = tc;
  }
  return h;
}

/// The same for a triangular face of a solid; InputError for a face of more corners.
std::optional<Hit> meet(const Mesh3D& mesh, const std::vector<int>& face, const Vec3& x, const Vec3& nu,
                        const std::string& part, int f) {
  if (face.size() != 3)
    throw InputError("contact part '" + part + "': face " + std::to_string(f) + " of the other body has " +
                     std::to_string(face.size()) +
                     " corners; a part paired by projection meets triangular faces (the virtual space is linear "
                     "on a triangle only): mesh the other body's surface in triangles (tetrahedra)");
  const Vec3 a = mesh.vertex(face[0]), e1 = mesh.vertex(face[1]) - a, e2 = mesh.vertex(face[2]) - a;
  // x + s nu = a + b1 e1 + b2 e2
  Eigen::Matrix3d m;
  m.col(0) = nu;
  m.col(1) = -e1;
  m.col(2) = -e2;
  const double det = m.determinant();
  if (std::abs(det) <= 1e-12 * e1.cross(e2).norm()) return std::nullopt;
  const Vec3 sol = m.partialPivLu().solve(a - x);
  constexpr double slack = 1e-12;
  const double b1 = sol(1), b2 = sol(2);
  if (b1 < -slack || b2 < -slack || b1 + b2 > 1.0 + slack) return std::nullopt;
  Hit h;
  h.s = sol(0);
  // weights within round-off of 0 are 0: a point on an edge of the triangle is of that edge alone
  const auto clean = [](double x) { return x > slack ? x : 0.0; };
  const std::array<double, 3> w{clean(1.0 - b1 - b2), clean(b1), clean(b2)};
  const double sum = w[0] + w[1] + w[2];
  int n = 0;
  for (int k = 0; k < 3; ++k)
    if (w[static_cast<std::size_t>(k)] > 0.0) {
      h.across.vertex[static_cast<std::size_t>(n)] = face[static_cast<std::size_t>(k)];
      h.across.weight[static_cast<std::size_t>(n++)] = w[static_cast<std::size_t>(k)] / sum;
    }
  return h;
}

/// The point of `against` nearest along the line through vertex p along `nu` (the least |s|).
template <int dim>
Hit projection(const MeshOf<dim>& mesh, const BasicContactPart<dim>& part, int p, const PointOf<dim>& nu) {
  Hit best;
  for (int f : part.against) {
    std::optional<Hit> h;
    if constexpr (dim == 2) h = meet(mesh, mesh.facet_vertices(f), mesh.vertex(p), nu);
    else h = meet(mesh, mesh.facet_vertices(f), mesh.vertex(p), nu, part.name, f);
    if (h && std::abs(h->s) < std::abs(best.s)) best = *h;
  }
  return best;
}

}  // namespace

std::string to_string(BodyPairing pairing) { return pairing == BodyPairing::vertex ? "vertex" : "projection"; }

template <int dim>
void pair_with_other_body(const MeshOf<dim>& mesh, const std::vector<BasicContactPart<dim>>& parts,
                          ContactBoundary& boundary) {
  const bool any = std::any_of(parts.begin(), parts.end(), [](const auto& p) { return !p.against.empty(); });
  if (!any || boundary.size() == 0) return;
  const double tolerance = 1e-9 * mesh_size<dim>(mesh);
  std::set<int> nodes(boundary.nodes.begin(), boundary.nodes.end()), taken;
  boundary.across.assign(boundary.nodes.size(), Across{});
  const auto by_x = against_vertices<dim>(mesh, parts);
  for (int i = 0; i < boundary.size(); ++i) {
    const auto k = static_cast<std::size_t>(boundary.part_of(i));
    const auto& part = parts[k];
    if (part.against.empty()) continue;
    const int p = boundary.nodes[static_cast<std::size_t>(i)];
    const PointOf<dim>& x = mesh.vertex(p);
    Across across;
    if (part.pairing == BodyPairing::vertex) {
      const int q = vertex_at<dim>(mesh, by_x[k], x, p, tolerance);
      if (q < 0)
        throw InputError("contact part '" + part.name + "': its node " + std::to_string(p) + " at " + point_text<dim>(x) +
                         " has no vertex of the other body's surface at its point; the two bodies' meshes must match "
                         "along their contact (a scene with [[body]] tables matches them), or the part is paired by "
                         "projection");
      if (!taken.insert(q).second)
        throw InputError("contact part '" + part.name + "': two nodes meet the vertex " + std::to_string(q) + " at " +
                         point_text<dim>(x));
      across = Across::vertex_at(q);
    } else {
      PointOf<dim> nu;
      if constexpr (dim == 2) nu = boundary.normals[static_cast<std::size_t>(i)];
      else nu = boundary.normals3d[static_cast<std::size_t>(i)];
      const Hit hit = projection<dim>(mesh, part, p, nu);
      if (!std::isfinite(hit.s)) {
        boundary.gaps(i) = std::numeric_limits<double>::infinity();
        continue;
      }
      boundary.gaps(i) += hit.s;
      across = hit.across;
    }
    for (int j = 0; j < across.size(); ++j)
      if (const int q = across.vertex[static_cast<std::size_t>(j)]; nodes.count(q))
        throw InputError("contact part '" + part.name + "': the vertex " + std::to_string(q) + " at " +
                         point_text<dim>(mesh.vertex(q)) + " across from node " + std::to_string(p) +
                         " is itself a contact node; a surface meets another body from one side only");
    boundary.across[static_cast<std::size_t>(i)] = across;
  }
}

template void pair_with_other_body<2>(const Mesh&, const std::vector<BasicContactPart<2>>&, ContactBoundary&);
template void pair_with_other_body<3>(const Mesh3D&, const std::vector<BasicContactPart<3>>&, ContactBoundary&);

}  // namespace hemivem
