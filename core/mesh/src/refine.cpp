#include <hemivem/mesh/refine.hpp>

#include "polygon_kernels.hpp"

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

namespace hemivem {

namespace {

using detail::area_centroid;
using detail::clip_left;
using detail::mean_value_coordinates;
using detail::cross2;

// A vertex is hanging in an element when its distance to the line through its neighbours is
// at most this fraction of the element's diameter.
constexpr double hanging_tolerance = 1e-10;
// An existing vertex within this fraction of a side's length of its midpoint is reused; two
// points cut on one edge this close (in the edge's parameter) are one.
constexpr double midpoint_tolerance = 1e-8;
// The interior point of a split element is at least this fraction of its diameter away from
// the line of every side.
constexpr double kernel_margin = 1e-8;

std::string fmt_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// The vertices of an element relative to its first vertex, scaled by a power of two (exactly)
// so that the diameter is in [1, 2): every geometric quantity is of order one at any scale.
struct LocalFrame {
  Vec2 origin;
  int exponent = 0;       // global = origin + 2^exponent * local
  double diameter = 1.0;  // in local units
  std::vector<Vec2> q;

  Vec2 to_global(const Vec2& l) const {
    return origin + Vec2(std::ldexp(l.x(), exponent), std::ldexp(l.y(), exponent));
  }
};

LocalFrame local_frame(const Mesh& mesh, int e) {
  LocalFrame f;
  const auto el = mesh.element(e);
  f.origin = mesh.vertex(el[0]);
  f.exponent = std::ilogb(mesh.diameter(e));
  f.diameter = std::ldexp(mesh.diameter(e), -f.exponent);
  f.q.reserve(el.size());
  for (int v : el) {
    const Vec2 d = mesh.vertex(v) - f.origin;
    f.q.emplace_back(std::ldexp(d.x(), -f.exponent), std::ldexp(d.y(), -f.exponent));
  }
  return f;
}

// Local indices of the vertices that are not hanging (see element_corners): hanging vertices
// are taken out one at a time, the one nearest to the segment between its neighbours first, and
// the neighbours of a vertex taken out are joined. So of two vertices a round-off apart at a
// corner (an edge of nearly zero length), one stays a corner.
std::vector<int> corners_of(const LocalFrame& f) {
  const int n = static_cast<int>(f.q.size());
  std::vector<int> prev(static_cast<std::size_t>(n)), next(static_cast<std::size_t>(n));
  std::vector<char> corner(static_cast<std::size_t>(n), 1);
  for (int i = 0; i < n; ++i) {
    prev[static_cast<std::size_t>(i)] = (i + n - 1) % n;
    next[static_cast<std::size_t>(i)] = (i + 1) % n;
  }
  // Distance of vertex i to the segment between its neighbours, relative to the diameter, when
  // it lies strictly between them; infinity otherwise.
  auto deviation = [&](int i) {
    const Vec2& a = f.q[static_cast<std::size_t>(prev[static_cast<std::size_t>(i)])];
    const Vec2& v = f.q[static_cast<std::size_t>(i)];
    const Vec2& b = f.q[static_cast<std::size_t>(next[static_cast<std::size_t>(i)])];
    const Vec2 w = b - a;
    const double len = w.norm();
    if (!(len > 0.0) || !((v - a).dot(w) > 0.0) || !((v - b).dot(a - b) > 0.0))
      return std::numeric_limits<double>::infinity();
    return std::abs(cross2(w, v - a)) / (len * f.diameter);
  };
  for (int left = n; left > 3; --left) {
    int best = -1;
    double best_deviation = hanging_tolerance;
    for (int i = 0; i < n; ++i) {
      if (!corner[static_cast<std::size_t>(i)]) continue;
      const double d = deviation(i);
      if (d <= best_deviation && (best < 0 || d < best_deviation)) {
        best = i;
        best_deviation = d;
      }
    }
    if (best < 0) break;
    corner[static_cast<std::size_t>(best)] = 0;
    next[static_cast<std::size_t>(prev[static_cast<std::size_t>(best)])] = next[static_cast<std::size_t>(best)];
    prev[static_cast<std::size_t>(next[static_cast<std::size_t>(best)])] = prev[static_cast<std::size_t>(best)];
  }
  std::vector<int> corners;
  for (int i = 0; i < n; ++i)
    if (corner[static_cast<std::size_t>(i)]) corners.push_back(i);
  return corners;
}

// One geometric side of an element and where its midpoint goes.
struct SidePlan {
  int corner = 0;   // local index of the corner it starts at
  int length = 1;   // its number of edges: local edges corner, ..., corner + length - 1 (mod n)
  int reuse = -1;   // local index of an existing vertex at its midpoint, or -1
  int edge = -1;    // else the local edge (from local vertex edge to edge + 1) the midpoint cuts
  double t = 0.5;   // the midpoint's position along that edge, from its first vertex
};

struct ElementPlan {
  std::vector<SidePlan> sides;
};

ElementPlan plan_element(const Mesh& mesh, int e) {
  const LocalFrame f = local_frame(mesh, e);
  const std::vector<int> corners = corners_of(f);
  const int n = static_cast<int>(f.q.size());
  const int k = static_cast<int>(corners.size());
  ElementPlan plan;
  plan.sides.reserve(static_cast<std::size_t>(k));
  for (int s = 0; s < k; ++s) {
    const int c0 = corners[static_cast<std::size_t>(s)], c1 = corners[static_cast<std::size_t>((s + 1) % k)];
    SidePlan side;
    side.corner = c0;
    side.length = (c1 - c0 + n) % n;
    if (side.length == 1) {
      side.edge = c0;
      plan.sides.push_back(side);
      continue;
    }
    // Positions along the chord from corner c0 (0) to corner c1 (1).
    const Vec2 a = f.q[static_cast<std::size_t>(c0)];
    const Vec2 u = f.q[static_cast<std::size_t>(c1)] - a;
    const double uu = u.squaredNorm();
    auto tau = [&](int m) {  // m-th vertex of the side
      if (m == 0) return 0.0;
      if (m == side.length) return 1.0;
      return (f.q[static_cast<std::size_t>((c0 + m) % n)] - a).dot(u) / uu;
    };
    for (int m = 1; m < side.length && side.reuse < 0; ++m)
      if (std::abs(tau(m) - 0.5) <= midpoint_tolerance) side.reuse = (c0 + m) % n;
    if (side.reuse < 0) {
      for (int m = 0; m < side.length && side.edge < 0; ++m) {
        const double t0 = tau(m), t1 = tau(m + 1);
        if (t0 < 0.5 && 0.5 < t1) {
          side.edge = (c0 + m) % n;
          side.t = (0.5 - t0) / (t1 - t0);
        }
      }
      if (side.edge < 0) {
        // A side whose vertices do not advance along its chord (round-off on edges of nearly
        // zero length): its longest edge is cut in half.
        double longest = -1.0;
        for (int m = 0; m < side.length; ++m) {
          const int j = (c0 + m) % n;
          const double len = (f.q[static_cast<std::size_t>((j + 1) % n)] - f.q[static_cast<std::size_t>(j)]).norm();
          if (len > longest) {
            longest = len;
            side.edge = j;
          }
        }
        side.t = 0.5;
      }
    }
    plan.sides.push_back(side);
  }
  return plan;
}

// The point an element is split around, in its local frame: its centroid when that lies
// strictly inside the kernel of the polygon of its geometric sides, else the kernel's centroid.
Vec2 split_point(const LocalFrame& f, const std::vector<int>& corners, int e, bool added_by_rule) {
  std::vector<Vec2> chords;
  chords.reserve(corners.size());
  for (int c : corners) chords.push_back(f.q[static_cast<std::size_t>(c)]);
  const std::size_t k = chords.size();
  auto strictly_inside = [&](const Vec2& c) {
    for (std::size_t i = 0; i < k; ++i) {
      const Vec2 d = chords[(i + 1) % k] - chords[i];
      if (!(cross2(d, c - chords[i]) > kernel_margin * d.norm() * f.diameter)) return false;
    }
    return true;
  };
  const Vec2 centroid = area_centroid(f.q).second;
  if (strictly_inside(centroid)) return centroid;

  Vec2 lo = chords[0], hi = chords[0];
  for (const Vec2& p : chords) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  std::vector<Vec2> kernel{lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
  for (std::size_t i = 0; i < k && !kernel.empty(); ++i) kernel = clip_left(kernel, chords[i], chords[(i + 1) % k]);
  const auto [kernel_area, kernel_centroid] = area_centroid(kernel);
  const std::string name = "element " + std::to_string(e) + " is not star-shaped: it cannot be split around an interior point";
  const std::string why = added_by_rule ? " (it is split because the one-hanging-node rule requires it)" : "";
  if (kernel.empty()) throw InputError(name + " (no point of it sees its whole boundary: its kernel is empty)" + why);
  if (!(kernel_area > 0.0) || !strictly_inside(kernel_centroid))
    throw InputError(name + " (the points that see its whole boundary form a degenerate region, of relative area " +
                     fmt_number(kernel_area / area_centroid(f.q).first) + ")" + why);
  return kernel_centroid;
}

// The one-hanging-node closure of the marked set: marks every element one of whose sides
// would receive a new midpoint and then carry more than one vertex inside it.
std::vector<char> close_marked_set(const Mesh& mesh, const std::vector<ElementPlan>& plans, std::span<const int> marked) {
  const int ne = mesh.num_elements();
  std::vector<char> is_marked(static_cast<std::size_t>(ne), 0);
  std::vector<int> inserts(static_cast<std::size_t>(mesh.num_edges()), 0);  // new midpoints per edge
  std::vector<int> to_check;
  auto mark = [&](int e) {
    is_marked[static_cast<std::size_t>(e)] = 1;
    const auto edges = mesh.element_edges(e);
    for (const SidePlan& s : plans[static_cast<std::size_t>(e)].sides) {
      if (s.reuse >= 0) continue;
      const int g = edges[static_cast<std::size_t>(s.edge)];
      ++inserts[static_cast<std::size_t>(g)];
      const MeshEdge& ed = mesh.edge(g);
      const int other = ed.left == e ? ed.right : ed.left;
      if (other >= 0 && !is_marked[static_cast<std::size_t>(other)]) to_check.push_back(other);
    }
  };
  for (int e : marked)
    if (!is_marked[static_cast<std::size_t>(e)]) mark(e);
  while (!to_check.empty()) {
    const int e = to_check.back();
    to_check.pop_back();
    if (is_marked[static_cast<std::size_t>(e)]) continue;
    const auto edges = mesh.element_edges(e);
    const int n = static_cast<int>(edges.size());
    for (const SidePlan& s : plans[static_cast<std::size_t>(e)].sides) {
      int added = 0;
      for (int m = 0; m < s.length; ++m) added += inserts[static_cast<std::size_t>(edges[static_cast<std::size_t>((s.corner + m) % n)])];
      if (added >= 1 && (s.length - 1) + added > 1) {
        mark(e);
        break;
      }
    }
  }
  return is_marked;
}

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

// The vertices of a refinement: the old ones, then per split element its side midpoints not made
// before and its interior point; with the prolongation's rows (each new vertex's weights on the
// old ones).
struct NewVertices {
  std::vector<Vec2> vertices;
  std::vector<Eigen::Triplet<double>> rows;
  std::vector<std::vector<std::pair<double, int>>> cut;  // per old edge: (t from v0, vertex), sorted by t
  std::vector<std::vector<int>> midpoints;               // per split element: each side's midpoint
  std::vector<int> centre;                               // per split element: its interior point
};

NewVertices new_vertices(const Mesh& mesh, const std::vector<ElementPlan>& plans, const std::vector<char>& is_marked,
                         const std::vector<char>& asked) {
  const int ne = mesh.num_elements();
  const int nv = mesh.num_vertices();
  NewVertices out;
  std::vector<Vec2>& vertices = out.vertices;
  std::vector<Eigen::Triplet<double>>& rows = out.rows;
  auto& cut = out.cut;
  vertices = mesh.vertices();
  rows.reserve(static_cast<std::size_t>(nv) + 8 * static_cast<std::size_t>(ne));
  for (int v = 0; v < nv; ++v) rows.emplace_back(v, v, 1.0);
  cut.resize(static_cast<std::size_t>(mesh.num_edges()));
  out.midpoints.resize(static_cast<std::size_t>(ne));
  out.centre.assign(static_cast<std::size_t>(ne), -1);
  for (int e = 0; e < ne; ++e) {
    if (!is_marked[static_cast<std::size_t>(e)]) continue;
    const auto el = mesh.element(e);
    const auto edges = mesh.element_edges(e);
    auto& mids = out.midpoints[static_cast<std::size_t>(e)];
    for (const SidePlan& s : plans[static_cast<std::size_t>(e)].sides) {
      if (s.reuse >= 0) {
        mids.push_back(el[static_cast<std::size_t>(s.reuse)]);
        continue;
      }
      const int g = edges[static_cast<std::size_t>(s.edge)];
      const MeshEdge& ed = mesh.edge(g);
      const double t = ed.v0 == el[static_cast<std::size_t>(s.edge)] ? s.t : 1.0 - s.t;
      auto& on_edge = cut[static_cast<std::size_t>(g)];
      const auto same = std::find_if(on_edge.begin(), on_edge.end(),
                                     [&](const auto& p) { return std::abs(p.first - t) <= midpoint_tolerance; });
      if (same != on_edge.end()) {
        mids.push_back(same->second);
        continue;
      }
      const int id = static_cast<int>(vertices.size());
      vertices.push_back((1.0 - t) * mesh.vertex(ed.v0) + t * mesh.vertex(ed.v1));
      rows.emplace_back(id, ed.v0, 1.0 - t);
      rows.emplace_back(id, ed.v1, t);
      on_edge.emplace_back(t, id);
      mids.push_back(id);
    }
    const LocalFrame f = local_frame(mesh, e);
    std::vector<int> corners;
    for (const SidePlan& s : plans[static_cast<std::size_t>(e)].sides) corners.push_back(s.corner);
    const Vec2 c = split_point(f, corners, e, !asked[static_cast<std::size_t>(e)]);
    const int id = static_cast<int>(vertices.size());
    vertices.push_back(f.to_global(c));
    const std::vector<double> weights = mean_value_coordinates(f.q, c);
    for (std::size_t i = 0; i < el.size(); ++i) rows.emplace_back(id, el[i], weights[i]);
    out.centre[static_cast<std::size_t>(e)] = id;
  }
  for (auto& on_edge : cut) std::sort(on_edge.begin(), on_edge.end());
  return out;
}

// The elements of a refinement, with their regions and parents.
struct ChildElements {
  std::vector<std::vector<int>> elements;
  std::vector<int> regions, parent_element;
};

// A split element's children, one quadrilateral per corner: its polygon (with the cut points of
// its edges spliced in) from the corner to the next side's midpoint, the centre, and back from
// the previous side's midpoint. `local_position`: where each of its vertices is in `polygon`.
void split_element(const Mesh& mesh, int e, const ElementPlan& plan, const NewVertices& made,
                   const std::vector<int>& polygon, const std::vector<int>& local_position, ChildElements& out) {
  const auto& sides = plan.sides;
  const auto& mids = made.midpoints[static_cast<std::size_t>(e)];
  const int m = static_cast<int>(polygon.size());
  const std::size_t k = sides.size();
  std::vector<int> corner_at(k), mid_at(k);
  for (std::size_t s = 0; s < k; ++s) {
    corner_at[s] = local_position[static_cast<std::size_t>(sides[s].corner)];
    int i = corner_at[s], steps = 0;
    while (polygon[static_cast<std::size_t>(i)] != mids[s] && ++steps < m) i = (i + 1) % m;
    if (steps == m) throw InternalError("refine_mesh: the midpoint of a side of element " + std::to_string(e) + " is not on it");
    mid_at[s] = i;
  }
  for (std::size_t s = 0; s < k; ++s) {
    std::vector<int> child;
    for (int i = corner_at[s];; i = (i + 1) % m) {
      child.push_back(polygon[static_cast<std::size_t>(i)]);
      if (i == mid_at[s]) break;
    }
    child.push_back(made.centre[static_cast<std::size_t>(e)]);
    for (int i = mid_at[(s + k - 1) % k]; i != corner_at[s]; i = (i + 1) % m) child.push_back(polygon[static_cast<std::size_t>(i)]);
    out.elements.push_back(std::move(child));
    out.regions.push_back(mesh.region(e));
    out.parent_element.push_back(e);
  }
}

// Elements: each parent's polygon with the cut points of its edges spliced in; a split one cut
// into one quadrilateral per corner.
ChildElements child_elements(const Mesh& mesh, const std::vector<ElementPlan>& plans, const std::vector<char>& is_marked,
                             const NewVertices& made) {
  const int ne = mesh.num_elements();
  ChildElements out;
  out.elements.reserve(static_cast<std::size_t>(ne));
  std::vector<int> polygon, local_position;
  for (int e = 0; e < ne; ++e) {
    const auto el = mesh.element(e);
    const auto edges = mesh.element_edges(e);
    polygon.clear();
    local_position.assign(el.size(), 0);
    for (std::size_t j = 0; j < el.size(); ++j) {
      local_position[j] = static_cast<int>(polygon.size());
      polygon.push_back(el[j]);
      const auto& on_edge = made.cut[static_cast<std::size_t>(edges[j])];
      if (mesh.edge(edges[j]).v0 == el[j]) {
        for (const auto& p : on_edge) polygon.push_back(p.second);
      } else {
        for (auto it = on_edge.rbegin(); it != on_edge.rend(); ++it) polygon.push_back(it->second);
      }
    }
    if (!is_marked[static_cast<std::size_t>(e)]) {
      out.elements.push_back(polygon);
      out.regions.push_back(mesh.region(e));
      out.parent_element.push_back(e);
      continue;
    }
    split_element(mesh, e, plans[static_cast<std::size_t>(e)], made, polygon, local_position, out);
  }
  return out;
}

// Each parent edge and its pieces, in order from v0: out.parent_edge, and the edge groups of
// `mesh` on out.mesh.
void set_edge_pieces(const Mesh& mesh, const std::vector<std::vector<std::pair<double, int>>>& cut, RefinedMesh& out) {
  std::unordered_map<std::uint64_t, int> edge_id;
  edge_id.reserve(static_cast<std::size_t>(out.mesh.num_edges()));
  for (int i = 0; i < out.mesh.num_edges(); ++i) edge_id.emplace(edge_key(out.mesh.edge(i).v0, out.mesh.edge(i).v1), i);
  out.parent_edge.assign(static_cast<std::size_t>(out.mesh.num_edges()), -1);
  std::vector<int> piece_offsets(static_cast<std::size_t>(mesh.num_edges()) + 1, 0), pieces;
  for (int g = 0; g < mesh.num_edges(); ++g) {
    int from = mesh.edge(g).v0;
    auto add_piece = [&](int to) {
      const int id = edge_id.at(edge_key(from, to));
      out.parent_edge[static_cast<std::size_t>(id)] = g;
      pieces.push_back(id);
      from = to;
    };
    for (const auto& p : cut[static_cast<std::size_t>(g)]) add_piece(p.second);
    add_piece(mesh.edge(g).v1);
    piece_offsets[static_cast<std::size_t>(g) + 1] = static_cast<int>(pieces.size());
  }
  for (const auto& [name, group] : mesh.edge_groups()) {
    std::vector<int> children;
    for (int g : group)
      children.insert(children.end(), pieces.begin() + piece_offsets[static_cast<std::size_t>(g)],
                      pieces.begin() + piece_offsets[static_cast<std::size_t>(g) + 1]);
    out.mesh.set_edge_group(name, std::move(children));
  }
}

}  // namespace

std::vector<int> element_corners(const Mesh& mesh, int e) {
  if (e < 0 || e >= mesh.num_elements())
    throw InputError("element id " + std::to_string(e) + " is out of range [0, " + std::to_string(mesh.num_elements()) + ")");
  return corners_of(local_frame(mesh, e));
}

RefinedMesh refine_mesh(const Mesh& mesh, std::span<const int> marked) {
  const int ne = mesh.num_elements();
  const int nv = mesh.num_vertices();
  for (int e : marked)
    if (e < 0 || e >= ne)
      throw InputError("marked element id " + std::to_string(e) + " is out of range [0, " + std::to_string(ne) + ")");

  // The sides of every element and where their midpoints go; the closure of the marked set.
  std::vector<ElementPlan> plans;
  plans.reserve(static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) plans.push_back(plan_element(mesh, e));
  const std::vector<char> is_marked = close_marked_set(mesh, plans, marked);
  std::vector<char> asked(static_cast<std::size_t>(ne), 0);
  for (int e : marked) asked[static_cast<std::size_t>(e)] = 1;

  NewVertices made = new_vertices(mesh, plans, is_marked, asked);
  ChildElements children = child_elements(mesh, plans, is_marked, made);

  RefinedMesh out;
  try {
    out.mesh = Mesh(std::move(made.vertices), std::move(children.elements), std::move(children.regions));
  } catch (const MeshError& error) {
    const int parent = error.element() >= 0 ? children.parent_element[static_cast<std::size_t>(error.element())] : -1;
    throw MeshError((parent >= 0 ? "refining element " + std::to_string(parent) : std::string("refining the mesh")) +
                        " gives an invalid mesh: " + error.what(),
                    parent);
  }

  set_edge_pieces(mesh, made.cut, out);

  out.parent_element = std::move(children.parent_element);
  out.prolongation.resize(out.mesh.num_vertices(), nv);
  out.prolongation.setFromTriplets(made.rows.begin(), made.rows.end());
  for (int e = 0; e < ne; ++e)
    if (is_marked[static_cast<std::size_t>(e)]) out.refined.push_back(e);
  return out;
}

RefinedMesh refine_uniformly(const Mesh& mesh) {
  std::vector<int> all(static_cast<std::size_t>(mesh.num_elements()));
  std::iota(all.begin(), all.end(), 0);
  return refine_mesh(mesh, all);
}

namespace {
/// Indicators within this fraction of the largest are one tie for the marking (dorfler_marking).
constexpr double kMarkingTie = 1e-6;
}  // namespace

std::vector<int> dorfler_marking(std::span<const double> eta, double theta) {
  if (!(theta > 0.0 && theta <= 1.0))
    throw InputError("Dörfler marking needs theta in (0, 1]; got " + fmt_number(theta));
  double largest = 0.0;
  for (std::size_t i = 0; i < eta.size(); ++i) {
    if (!std::isfinite(eta[i]) || eta[i] < 0.0)
      throw InputError("error indicator " + std::to_string(i) + " is " + fmt_number(eta[i]) +
                       "; indicators must be finite and non-negative");
    largest = std::max(largest, eta[i]);
  }
  std::vector<int> out;
  if (largest == 0.0) return out;
  std::vector<int> order(eta.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double ea = eta[static_cast<std::size_t>(a)], eb = eta[static_cast<std::size_t>(b)];
    return ea > eb || (ea == eb && a < b);
  });
  if (theta == 1.0) {
    for (int i : order)
      if (eta[static_cast<std::size_t>(i)] > 0.0) out.push_back(i);
  } else {
    // Squares of eta / largest: no overflow or underflow of the largest terms.
    double total = 0.0;
    for (int i : order) total += std::pow(eta[static_cast<std::size_t>(i)] / largest, 2);
    const double target = theta * total;
    double sum = 0.0;
    std::size_t k = 0;
    while (k < order.size()) {
      sum += std::pow(eta[static_cast<std::size_t>(order[k])] / largest, 2);
      out.push_back(order[k++]);
      if (sum >= target) break;
    }
    // the indicators tied with the last one marked, to round-off of the solution, go with it
    const double last = eta[static_cast<std::size_t>(out.back())];
    for (; k < order.size() && eta[static_cast<std::size_t>(order[k])] >= last - kMarkingTie * largest; ++k)
      out.push_back(order[k]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

Eigen::VectorXd prolongate(const RefinedMesh& refined, const Eigen::VectorXd& parent_values) {
  const Eigen::Index parent_vertices = refined.prolongation.cols();
  if (parent_values.size() != 2 * parent_vertices)
    throw InputError("the parent nodal vector has " + std::to_string(parent_values.size()) + " entries; the parent mesh has " +
                     std::to_string(parent_vertices) + " vertices, so it needs " + std::to_string(2 * parent_vertices));
  using Nodal = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
  const Eigen::Map<const Nodal> parent(parent_values.data(), parent_vertices, 2);
  Eigen::VectorXd out(2 * refined.prolongation.rows());
  Eigen::Map<Nodal>(out.data(), refined.prolongation.rows(), 2) = refined.prolongation * parent;
  return out;
}

}  // namespace hemivem
