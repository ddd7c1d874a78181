#include <hemivem/mesh/mesh.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <sstream>

namespace hemivem {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

std::string fmt_point(const Vec2& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

// Vertices lying strictly inside a boundary edge they do not belong to (hanging vertices).
// Boundary vertices are bucketed on a uniform grid; each boundary edge queries the buckets
// its bounding box covers. A vertex counts as inside when its distance to the edge line is
// below 1e-10 of the edge length and it projects at least 1e-6 of the length away from
// both end points, so near-coincident twins of an end point (edges of ~1e-13) are legal.
void find_hanging_vertices(const std::vector<Vec2>& vertices,
                           const std::vector<std::array<int, 3>>& boundary,  // v0, v1, element
                           std::vector<MeshDefect>& out, std::size_t max_defects, const std::vector<int>& pieces) {
  if (boundary.empty()) return;
  std::vector<int> bverts;
  bverts.reserve(2 * boundary.size());
  for (const auto& b : boundary) {
    bverts.push_back(b[0]);
    bverts.push_back(b[1]);
  }
  std::sort(bverts.begin(), bverts.end());
  bverts.erase(std::unique(bverts.begin(), bverts.end()), bverts.end());

  Vec2 lo = vertices[bverts[0]], hi = lo;
  for (int v : bverts) {
    lo = lo.cwiseMin(vertices[v]);
    hi = hi.cwiseMax(vertices[v]);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const int cells = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(bverts.size()))));
  const double cell = extent / cells * (1.0 + 1e-12);
  auto cell_of = [&](double x, double x0) {
    return std::clamp(static_cast<int>((x - x0) / cell), 0, cells - 1);
  };
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(cells) * cells);
  for (int v : bverts) {
    grid[static_cast<std::size_t>(cell_of(vertices[v].y(), lo.y())) * cells + cell_of(vertices[v].x(), lo.x())]
        .push_back(v);
  }
  for (const auto& b : boundary) {
    const Vec2& a = vertices[b[0]];
    const Vec2& c = vertices[b[1]];
    const Vec2 d = c - a;
    const double len2 = d.squaredNorm();
    if (len2 <= 0.0) continue;
    const double len = std::sqrt(len2);
    const double tol = 1e-10 * len;
    const int ix0 = cell_of(std::min(a.x(), c.x()) - tol, lo.x()), ix1 = cell_of(std::max(a.x(), c.x()) + tol, lo.x());
    const int iy0 = cell_of(std::min(a.y(), c.y()) - tol, lo.y()), iy1 = cell_of(std::max(a.y(), c.y()) + tol, lo.y());
    for (int iy = iy0; iy <= iy1; ++iy) {
      for (int ix = ix0; ix <= ix1; ++ix) {
        for (int v : grid[static_cast<std::size_t>(iy) * cells + ix]) {
          if (v == b[0] || v == b[1]) continue;
          // another body's vertex may lie on this body's boundary (bodies in contact)
          if (!pieces.empty() && pieces[static_cast<std::size_t>(v)] != pieces[static_cast<std::size_t>(b[0])]) continue;
          const Vec2 p = vertices[v] - a;
          const double t = p.dot(d) / len2;
          if (t <= 1e-6 || t >= 1.0 - 1e-6) continue;
          const double dist = std::abs(d.x() * p.y() - d.y() * p.x()) / len;
          if (dist > tol) continue;
          out.push_back({b[2], "has vertex " + std::to_string(v) + " " + fmt_point(vertices[v]) +
                                   " inside its boundary edge " + std::to_string(b[0]) + "-" +
                                   std::to_string(b[1]) + " (hanging vertex: the mesh is not conforming)"});
          if (out.size() >= max_defects) return;
        }
      }
    }
  }
}

// Vertices with a non-finite coordinate or one of magnitude above max_mesh_coordinate.
void find_vertex_defects(const std::vector<Vec2>& vertices, std::vector<MeshDefect>& out, std::size_t max_defects) {
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!std::isfinite(vertices[i].x()) || !std::isfinite(vertices[i].y())) {
      out.push_back({-1, "vertex " + std::to_string(i) + " has a non-finite coordinate"});
      if (out.size() >= max_defects) return;
    } else if (std::abs(vertices[i].x()) > max_mesh_coordinate || std::abs(vertices[i].y()) > max_mesh_coordinate) {
      out.push_back({-1, "vertex " + std::to_string(i) + " " + fmt_point(vertices[i]) +
                             " has a coordinate of magnitude above 1e150 (element areas would overflow)"});
      if (out.size() >= max_defects) return;
    }
  }
}

// What is wrong with the vertex list of one element (too short, an index out of [0, nv), a
// repeated vertex), or "" when nothing is; `sorted` is scratch space.
std::string element_index_defect(const std::vector<int>& el, int nv, std::vector<int>& sorted) {
  if (el.size() < 3) return "has " + std::to_string(el.size()) + " vertices; an element needs at least 3";
  for (int v : el)
    if (v < 0 || v >= nv) return "vertex index " + std::to_string(v) + " is out of range [0, " + std::to_string(nv) + ")";
  sorted.assign(el.begin(), el.end());
  std::sort(sorted.begin(), sorted.end());
  if (auto it = std::adjacent_find(sorted.begin(), sorted.end()); it != sorted.end())
    return "repeats vertex " + std::to_string(*it);
  return "";
}

// What is wrong with the polygon of one element (zero area, self-intersecting, clockwise, an
// area below the smallest normal double), or "" when nothing is; `cgal_poly` and `poly` are
// scratch space.
std::string element_shape_defect(const std::vector<int>& el, const std::vector<Vec2>& vertices,
                                 std::vector<Kernel::Point_2>& cgal_poly, std::vector<Vec2>& poly) {
  // Exact predicates throughout: collinear -> zero area; then simplicity; then the
  // orientation of the (simple) polygon.
  cgal_poly.clear();
  for (int v : el) cgal_poly.emplace_back(vertices[v].x(), vertices[v].y());
  // A triangle or quadrilateral turning strictly left at every vertex is convex, hence simple
  // and counter-clockwise (with five vertices or more it could wind twice: a pentagram).
  bool convex_small = cgal_poly.size() <= 4;
  for (std::size_t i = 0; i < cgal_poly.size() && convex_small; ++i)
    convex_small = CGAL::orientation(cgal_poly[i], cgal_poly[(i + 1) % cgal_poly.size()],
                                     cgal_poly[(i + 2) % cgal_poly.size()]) == CGAL::LEFT_TURN;
  bool all_collinear = !convex_small;
  for (std::size_t i = 2; i < cgal_poly.size() && all_collinear; ++i)
    all_collinear = CGAL::collinear(cgal_poly[0], cgal_poly[1], cgal_poly[i]) &&
                    CGAL::collinear(cgal_poly[i - 1], cgal_poly[i], cgal_poly[0]);
  if (all_collinear) return "has zero area (all its vertices are collinear)";
  if (!convex_small && !CGAL::is_simple_2(cgal_poly.begin(), cgal_poly.end(), Kernel()))
    return "is self-intersecting (its boundary crosses or touches itself)";
  poly.clear();
  for (int v : el) poly.push_back(vertices[v]);
  char area[32];
  if (!convex_small && CGAL::orientation_2(cgal_poly.begin(), cgal_poly.end(), Kernel()) != CGAL::COUNTERCLOCKWISE) {
    std::snprintf(area, sizeof area, "%.3g", signed_area(poly));
    return std::string("is clockwise (signed area ") + area + "); elements must be counter-clockwise";
  }
  if (const double a = signed_area(poly); !(a >= std::numeric_limits<double>::min())) {
    std::snprintf(area, sizeof area, "%.3g", a);
    return std::string("has an area (") + area + ") below the smallest normal double 2.2e-308: too small for double precision";
  }
  return "";
}

// One defect at most per element: its vertex list first, then its polygon.
void find_element_defects(const std::vector<Vec2>& vertices, const std::vector<std::vector<int>>& elements,
                          std::vector<MeshDefect>& out, std::size_t max_defects) {
  const int nv = static_cast<int>(vertices.size());
  std::vector<Vec2> poly;
  std::vector<Kernel::Point_2> cgal_poly;
  std::vector<int> sorted;
  for (std::size_t e = 0; e < elements.size() && out.size() < max_defects; ++e) {
    std::string defect = element_index_defect(elements[e], nv, sorted);
    if (defect.empty()) defect = element_shape_defect(elements[e], vertices, cgal_poly, poly);
    if (!defect.empty()) out.push_back({static_cast<int>(e), std::move(defect)});
  }
}

// Distinct vertices used by elements must not sit at the same point (that would be a
// crack: two boundaries on top of each other). Near-twins (e.g. 1e-13 apart) are legal.
void find_coincident_vertices(const std::vector<Vec2>& vertices, const std::vector<std::vector<int>>& elements,
                              std::vector<MeshDefect>& out, std::size_t max_defects, const std::vector<int>& pieces) {
  const auto piece = [&](int v) { return pieces.empty() ? 0 : pieces[static_cast<std::size_t>(v)]; };
  std::vector<char> used(vertices.size(), 0);
  std::vector<int> first_element(vertices.size(), -1);
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (int v : elements[e]) {
      used[static_cast<std::size_t>(v)] = 1;
      if (first_element[static_cast<std::size_t>(v)] < 0) first_element[static_cast<std::size_t>(v)] = static_cast<int>(e);
    }
  // used vertices strictly increasing in (y, x) in the order of their indices (a generated
  // grid's rows) are distinct: nothing to sort
  const Vec2* previous = nullptr;
  bool increasing = true;
  for (std::size_t i = 0; i < vertices.size() && increasing; ++i) {
    if (!used[i]) continue;
    const Vec2& v = vertices[i];
    increasing = !previous || std::tie(previous->y(), previous->x()) < std::tie(v.y(), v.x());
    previous = &v;
  }
  if (increasing) return;
  // the used vertices as records (x, y, piece, index), sorted in place: one contiguous array
  struct Point {
    double x, y;
    int piece, index;
  };
  std::vector<Point> order;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (used[i]) order.push_back({vertices[i].x(), vertices[i].y(), piece(static_cast<int>(i)), static_cast<int>(i)});
  std::sort(order.begin(), order.end(), [](const Point& a, const Point& b) {
    return std::tie(a.x, a.y, a.piece, a.index) < std::tie(b.x, b.y, b.piece, b.index);
  });
  for (std::size_t i = 1; i < order.size() && out.size() < max_defects; ++i) {
    const int a = std::min(order[i - 1].index, order[i].index), b = std::max(order[i - 1].index, order[i].index);
    if (vertices[a] == vertices[b] && piece(a) == piece(b))
      out.push_back({first_element[static_cast<std::size_t>(b)],
                     "uses vertex " + std::to_string(b) + " " + fmt_point(vertices[b]) + ", which coincides with vertex " +
                         std::to_string(a) + " (duplicate vertices: the mesh is not conforming)"});
  }
}

// An undirected edge: the element and direction of its first use, how often it is used, and
// the element that runs it the other way.
struct EdgeUse {
  int element;
  int from;
  int to;
  int count = 0;
  int second_element = -1;
};

// Conformity: each undirected edge at most twice, and then in opposite directions. Returns
// the undirected edges in order of first use, found through the list of edges at their lower
// vertex (first_at, next): a few entries per vertex.
std::vector<EdgeUse> find_edge_defects(const std::vector<Vec2>& vertices, const std::vector<std::vector<int>>& elements,
                                       std::vector<MeshDefect>& out, std::size_t max_defects) {
  std::vector<EdgeUse> uses;
  std::vector<int> first_at(vertices.size(), -1), next;
  std::size_t total = 0;
  for (const auto& el : elements) total += el.size();
  uses.reserve(total);
  next.reserve(total);
  for (std::size_t e = 0; e < elements.size() && out.size() < max_defects; ++e) {
    const auto& el = elements[e];
    const int ie = static_cast<int>(e);
    for (std::size_t i = 0; i < el.size(); ++i) {
      const int a = el[i], b = el[(i + 1) % el.size()];
      const int lo = std::min(a, b), hi = std::max(a, b);
      int id = first_at[static_cast<std::size_t>(lo)];
      while (id >= 0 && std::max(uses[static_cast<std::size_t>(id)].from, uses[static_cast<std::size_t>(id)].to) != hi)
        id = next[static_cast<std::size_t>(id)];
      if (id < 0) {
        next.push_back(first_at[static_cast<std::size_t>(lo)]);
        first_at[static_cast<std::size_t>(lo)] = static_cast<int>(uses.size());
        uses.push_back(EdgeUse{ie, a, b, 1});
        continue;
      }
      EdgeUse& u = uses[static_cast<std::size_t>(id)];
      ++u.count;
      if (u.count == 2 && u.from != a) {
        u.second_element = ie;
        continue;
      }
      const std::string edge = std::to_string(a) + "-" + std::to_string(b);
      if (u.count > 2) {
        out.push_back({ie, "shares edge " + edge + " that already belongs to elements " + std::to_string(u.element) +
                               " and " + std::to_string(u.second_element) + " (an edge may belong to at most two elements)"});
      } else {
        out.push_back({ie, "runs edge " + edge + " in the same direction as element " + std::to_string(u.element) +
                               " (overlapping or inconsistently oriented elements)"});
      }
      if (out.size() >= max_defects) break;
    }
  }
  return uses;
}

// The edges used once (v0, v1, element), in order of element, then vertices.
std::vector<std::array<int, 3>> boundary_edges(const std::vector<EdgeUse>& uses) {
  std::vector<std::array<int, 3>> boundary;
  for (const auto& u : uses)
    if (u.count == 1) boundary.push_back({u.from, u.to, u.element});
  std::sort(boundary.begin(), boundary.end(), [](const auto& x, const auto& y) {
    return std::tie(x[2], x[0], x[1]) < std::tie(y[2], y[0], y[1]);
  });
  return boundary;
}

}  // namespace

double signed_area(std::span<const Vec2> polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return 0.0;
  // Shoelace relative to the first vertex: less cancellation far from the origin.
  double twice = 0.0;
  const Vec2& o = polygon[0];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Vec2 a = polygon[i] - o, b = polygon[i + 1] - o;
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

std::vector<MeshDefect> find_mesh_defects(const std::vector<Vec2>& vertices,
                                          const std::vector<std::vector<int>>& elements,
                                          std::size_t max_defects, const std::vector<int>& pieces) {
  std::vector<MeshDefect> out;
  auto full = [&] { return out.size() >= max_defects; };
  if (vertices.empty()) out.push_back({-1, "the mesh has no vertices"});
  if (elements.empty()) out.push_back({-1, "the mesh has no elements"});
  if (!out.empty()) return out;

  find_vertex_defects(vertices, out, max_defects);
  if (!out.empty()) return out;
  find_element_defects(vertices, elements, out, max_defects);
  if (full() || !out.empty()) return out;
  if (!pieces.empty() && pieces.size() != vertices.size())
    out.push_back({-1, "the pieces of the vertices are given for " + std::to_string(pieces.size()) + " of " +
                           std::to_string(vertices.size()) + " vertices"});
  if (!out.empty()) return out;
  find_coincident_vertices(vertices, elements, out, max_defects, pieces);
  if (!out.empty()) return out;
  const std::vector<EdgeUse> uses = find_edge_defects(vertices, elements, out, max_defects);
  if (!out.empty()) return out;
  find_hanging_vertices(vertices, boundary_edges(uses), out, max_defects, pieces);
  return out;
}

Mesh::Mesh(std::vector<Vec2> vertices, std::vector<std::vector<int>> elements, std::vector<int> regions,
           const std::vector<int>& bodies) {
  if (auto defects = find_mesh_defects(vertices, elements, 1, bodies); !defects.empty()) {
    const auto& d = defects.front();
    throw MeshError(d.element >= 0 ? "element " + std::to_string(d.element) + " " + d.message : d.message, d.element);
  }
  vertices_ = std::move(vertices);
  const std::size_t ne = elements.size();
  offsets_.assign(ne + 1, 0);
  for (std::size_t e = 0; e < ne; ++e) offsets_[e + 1] = offsets_[e] + static_cast<int>(elements[e].size());
  element_vertices_.reserve(static_cast<std::size_t>(offsets_.back()));
  for (const auto& el : elements) element_vertices_.insert(element_vertices_.end(), el.begin(), el.end());
  element_edges_.assign(element_vertices_.size(), -1);

  // Edges numbered in order of first use; the edges at each vertex (as its lower end) are kept
  // in a list (first_at, next), a few entries long.
  std::vector<int> first_at(vertices_.size(), -1), next;
  next.reserve(element_vertices_.size());
  edges_.reserve(element_vertices_.size());
  for (std::size_t e = 0; e < ne; ++e) {
    const auto el = element(static_cast<int>(e));
    const std::size_t k = el.size();
    for (std::size_t i = 0; i < k; ++i) {
      const int a = el[i], b = el[(i + 1) % k];
      const int lo = std::min(a, b), hi = std::max(a, b);
      int id = first_at[static_cast<std::size_t>(lo)];
      while (id >= 0 && std::max(edges_[static_cast<std::size_t>(id)].v0, edges_[static_cast<std::size_t>(id)].v1) != hi)
        id = next[static_cast<std::size_t>(id)];
      if (id < 0) {
        id = static_cast<int>(edges_.size());
        edges_.push_back({a, b, static_cast<int>(e), -1});
        next.push_back(first_at[static_cast<std::size_t>(lo)]);
        first_at[static_cast<std::size_t>(lo)] = id;
      } else {
        edges_[static_cast<std::size_t>(id)].right = static_cast<int>(e);
      }
      element_edges_[static_cast<std::size_t>(offsets_[e]) + i] = id;
    }
  }
  edges_.shrink_to_fit();
  for (std::size_t i = 0; i < edges_.size(); ++i)
    if (edges_[i].on_boundary()) boundary_edges_.push_back(static_cast<int>(i));

  area_.resize(ne);
  centroid_.resize(ne);
  diameter_.resize(ne);
  std::vector<Vec2> poly;
  for (std::size_t e = 0; e < ne; ++e) {
    poly.clear();
    for (int v : element(static_cast<int>(e))) poly.push_back(vertices_[static_cast<std::size_t>(v)]);
    // Area and centroid from a fan around the first vertex (exact for any simple polygon).
    const Vec2 o = poly[0];
    double twice = 0.0;
    Vec2 moment = Vec2::Zero();
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      const Vec2 a = poly[i] - o, b = poly[i + 1] - o;
      const double cr = a.x() * b.y() - a.y() * b.x();
      twice += cr;
      moment += cr * (a + b) / 3.0;
    }
    area_[e] = 0.5 * twice;
    centroid_[e] = o + moment / twice;
    double d2 = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i)
      for (std::size_t j = i + 1; j < poly.size(); ++j) d2 = std::max(d2, (poly[i] - poly[j]).squaredNorm());
    diameter_[e] = std::sqrt(d2);
    h_ = std::max(h_, diameter_[e]);
  }
  set_regions(std::move(regions));
}

void Mesh::set_regions(std::vector<int> regions) {
  if (regions.empty()) regions.assign(static_cast<std::size_t>(num_elements()), 0);
  if (regions.size() != static_cast<std::size_t>(num_elements()))
    throw InputError("region list has " + std::to_string(regions.size()) + " entries for " +
                     std::to_string(num_elements()) + " elements");
  for (std::size_t e = 0; e < regions.size(); ++e)
    if (regions[e] < 0)
      throw MeshError("element " + std::to_string(e) + " has negative region id " + std::to_string(regions[e]),
                      static_cast<int>(e));
  regions_ = std::move(regions);
}

void Mesh::set_edge_group(const std::string& name, std::vector<int> edges) {
  for (int id : edges)
    if (id < 0 || id >= num_edges())
      throw InputError("edge id " + std::to_string(id) + " is out of range [0, " + std::to_string(num_edges()) + ")",
                       "edge group '" + name + "'");
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  edge_groups_[name] = std::move(edges);
}

const std::vector<int>& Mesh::edge_group(const std::string& name) const {
  const auto it = edge_groups_.find(name);
  if (it == edge_groups_.end()) {
    std::string known;
    for (const auto& [n, _] : edge_groups_) known += (known.empty() ? "" : ", ") + n;
    throw InputError("the mesh has no edge group '" + name + "'; its groups: " + (known.empty() ? "none" : known));
  }
  return it->second;
}

std::vector<std::vector<int>> Mesh::elements() const {
  std::vector<std::vector<int>> out(static_cast<std::size_t>(num_elements()));
  for (int e = 0; e < num_elements(); ++e) out[e].assign(element(e).begin(), element(e).end());
  return out;
}

double Mesh::edge_length(int i) const {
  const auto& ed = edge(i);
  return (vertex(ed.v1) - vertex(ed.v0)).norm();
}

std::vector<int> Mesh::boundary_vertices() const {
  std::vector<int> out;
  out.reserve(2 * boundary_edges_.size());
  for (int i : boundary_edges_) {
    out.push_back(edges_[i].v0);
    out.push_back(edges_[i].v1);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

double Mesh::min_edge_length() const {
  double m = std::numeric_limits<double>::infinity();
  for (int i = 0; i < num_edges(); ++i) m = std::min(m, edge_length(i));
  return m;
}

double Mesh::total_area() const {
  double s = 0.0;
  for (double a : area_) s += a;
  return s;
}

Rectangle Mesh::bounding_box() const {
  Rectangle r{vertices_.at(0).x(), vertices_[0].x(), vertices_[0].y(), vertices_[0].y()};
  for (const auto& v : vertices_) {
    r.x0 = std::min(r.x0, v.x());
    r.x1 = std::max(r.x1, v.x());
    r.y0 = std::min(r.y0, v.y());
    r.y1 = std::max(r.y1, v.y());
  }
  return r;
}

}  // namespace hemivem
