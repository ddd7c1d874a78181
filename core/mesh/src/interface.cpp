#include <hemivem/mesh/interface.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace hemivem {

namespace {

constexpr double max_tolerance = 0.1;

// The shortest of %.15g, %.16g, %.17g that reads back as x.
std::string fmt_number(double x) {
  char buf[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    if (std::strtod(buf, nullptr) == x || !std::isfinite(x)) break;
  }
  return buf;
}

std::string fmt_point(const Vec2& p) { return "(" + fmt_number(p.x()) + ", " + fmt_number(p.y()) + ")"; }

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

// One side's interface: its vertices in order and the edges between them, edges[k] running from
// vertices[k] to vertices[k + 1] (the direction of the edge in its element: counter-clockwise).
struct Chain {
  std::vector<int> vertices;
  std::vector<int> edges;
};

Chain make_chain(const Mesh& mesh, std::vector<int> edges, const std::string& side) {
  const std::string of = " of the " + side + " mesh";
  if (edges.empty()) throw InputError("the interface" + of + " has no edges; give the ids of its boundary edges");
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const int ne = mesh.num_edges();
  // Per vertex: the interface edge leaving it and the one arriving at it.
  std::unordered_map<int, int> leaving, arriving;
  for (int g : edges) {
    if (g < 0 || g >= ne)
      throw InputError("interface edge id " + std::to_string(g) + of + " is out of range [0, " + std::to_string(ne) + ")");
    const MeshEdge& ed = mesh.edge(g);
    if (!ed.on_boundary())
      throw InputError("interface edge " + std::to_string(g) + of + " is not a boundary edge (it lies between elements " +
                       std::to_string(ed.left) + " and " + std::to_string(ed.right) +
                       "); an interface is made of boundary edges");
    // A boundary vertex of a valid mesh may be on four boundary edges (two parts of the body
    // touching at a point): it may start or end only one interface edge.
    if (!leaving.emplace(ed.v0, g).second)
      throw InputError("vertex " + std::to_string(ed.v0) + of + " starts two of its interface edges (" +
                       std::to_string(leaving.at(ed.v0)) + " and " + std::to_string(g) +
                       "): the interface branches there; an interface is one chain of edges");
    if (!arriving.emplace(ed.v1, g).second)
      throw InputError("vertex " + std::to_string(ed.v1) + of + " ends two of its interface edges (" +
                       std::to_string(arriving.at(ed.v1)) + " and " + std::to_string(g) +
                       "): the interface branches there; an interface is one chain of edges");
  }
  int start = -1;
  for (int g : edges) {
    const int v = mesh.edge(g).v0;
    if (!arriving.count(v)) {
      if (start >= 0)
        throw InputError("the interface edges" + of + " do not form one chain: it starts at vertex " +
                         std::to_string(mesh.edge(leaving.at(start)).v0) + " and again at vertex " + std::to_string(v) +
                         " (edge " + std::to_string(g) + "); an interface is one chain of edges joined end to end");
      start = v;
    }
  }
  if (start < 0)
    throw InputError("the interface edges" + of + " form a closed loop (through edge " + std::to_string(edges.front()) +
                     "); an interface must be an open chain with two ends");
  Chain chain;
  chain.vertices.push_back(start);
  for (int v = start; leaving.count(v);) {
    const int g = leaving.at(v);
    chain.edges.push_back(g);
    v = mesh.edge(g).v1;
    chain.vertices.push_back(v);
    if (chain.edges.size() > edges.size()) break;  // cannot happen: one start, no loop through it
  }
  if (chain.edges.size() != edges.size()) {
    // A loop apart from the chain that starts at `start`.
    int apart = -1;
    for (int g : edges)
      if (std::find(chain.edges.begin(), chain.edges.end(), g) == chain.edges.end()) {
        apart = g;
        break;
      }
    throw InputError("the interface edges" + of + " do not form one chain: edge " + std::to_string(apart) +
                     " is not joined to the chain from vertex " + std::to_string(start) +
                     "; an interface is one chain of edges joined end to end");
  }
  return chain;
}

double chain_length(const Mesh& mesh, const Chain& c) {
  double length = 0.0;
  for (int g : c.edges) length += mesh.edge_length(g);
  return length;
}

// Where a vertex of one chain goes on the other: paired with a vertex of it (`vertex`, a
// position in the other chain) or inserted into an edge (`edge`, a position, at parameter t).
struct Placement {
  int vertex = -1;
  int edge = -1;
  double t = 0.0;
};

// The nearest point of segment [a, b] to p: (distance, parameter in [0, 1]).
std::pair<double, double> to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double dd = d.squaredNorm();
  double t = dd > 0.0 ? (p - a).dot(d) / dd : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return {(a + t * d - p).norm(), t};
}

// Places every vertex of chain `c` (mesh `m`, side `side`) on chain `o` (mesh `om`, side `oside`).
std::vector<Placement> place(const Mesh& m, const Chain& c, const std::string& side, const Mesh& om, const Chain& o,
                             const std::string& oside, double tol, double relative, double length) {
  const std::size_t p = c.vertices.size(), q = o.vertices.size();
  std::vector<Placement> out(p);
  // The ends first: an end off the other side says best that the interfaces do not match.
  std::vector<std::size_t> order{0, p - 1};
  for (std::size_t i = 1; i + 1 < p; ++i) order.push_back(i);
  for (const std::size_t i : order) {
    const int v = c.vertices[i];
    const Vec2& x = m.vertex(v);
    Placement& pl = out[i];
    for (std::size_t j = 0; j < q; ++j) {
      if ((om.vertex(o.vertices[j]) - x).norm() > tol) continue;
      if (pl.vertex >= 0)
        throw InputError("interface vertex " + std::to_string(v) + " " + fmt_point(x) + " of the " + side +
                         " mesh is within the tolerance " + fmt_number(tol) + " of two interface vertices of the " +
                         oside + " mesh (" + std::to_string(o.vertices[static_cast<std::size_t>(pl.vertex)]) + " and " +
                         std::to_string(o.vertices[j]) + "); each vertex can pair with one only: use a smaller tolerance");
      pl.vertex = static_cast<int>(j);
    }
    if (pl.vertex >= 0) continue;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < q; ++k) {
      const auto [d, t] = to_segment(x, om.vertex(o.vertices[k]), om.vertex(o.vertices[k + 1]));
      if (d < best) {
        best = d;
        pl.edge = static_cast<int>(k);
        pl.t = t;
      }
    }
    if (!(best <= tol) || !(pl.t > 0.0 && pl.t < 1.0)) {
      const bool end = i == 0 || i + 1 == p;
      throw InputError(std::string(end ? "end vertex " : "interface vertex ") + std::to_string(v) + " " + fmt_point(x) +
                       " of the " + side + " mesh is " + fmt_number(best) + " away from the interface of the " + oside +
                       " mesh, more than the tolerance " + fmt_number(tol) + " (" + fmt_number(relative) +
                       " of the interface's length " + fmt_number(length) +
                       "): the two interfaces must cover the same curve from end to end");
    }
  }
  return out;
}

// A side after the match: its new vertices and polygons, and its chain with the inserted vertices
// (`walk`, ids in the new mesh) and each walked vertex's partner (an id in the other new mesh).
struct Side {
  std::vector<Vec2> vertices;
  std::vector<int> walk;
  std::vector<int> partner;
};

// Mesh `m`'s side: the vertices of the other chain placed on its edges (`others`, placements of
// the other chain's vertices on this one) are appended in the other chain's order; `mine` places
// this chain's vertices on the other one, `other_new` is the id of the vertex the other side
// makes for each of this chain's vertices it does not pair (-1 for paired ones).
Side make_side(const Mesh& m, const Chain& c, const Mesh& om, const Chain& o, const std::vector<Placement>& mine,
               const std::vector<Placement>& others, const std::vector<int>& other_new,
               std::vector<std::vector<std::pair<double, int>>>& cut) {
  Side s;
  s.vertices = m.vertices();
  cut.assign(c.edges.size(), {});
  // (parameter, new id, partner) per edge of the chain.
  std::vector<std::vector<std::tuple<double, int, int>>> on_edge(c.edges.size());
  for (std::size_t j = 0; j < others.size(); ++j) {
    const Placement& pl = others[j];
    if (pl.vertex >= 0) continue;
    const int id = static_cast<int>(s.vertices.size());
    s.vertices.push_back(om.vertex(o.vertices[j]));
    on_edge[static_cast<std::size_t>(pl.edge)].emplace_back(pl.t, id, o.vertices[j]);
  }
  for (std::size_t k = 0; k < c.vertices.size(); ++k) {
    const Placement& pl = mine[k];
    s.walk.push_back(c.vertices[k]);
    s.partner.push_back(pl.vertex >= 0 ? o.vertices[static_cast<std::size_t>(pl.vertex)] : other_new[k]);
    if (k + 1 == c.vertices.size()) break;
    auto& list = on_edge[k];
    std::stable_sort(list.begin(), list.end(),
                     [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
    for (const auto& [t, id, partner] : list) {
      s.walk.push_back(id);
      s.partner.push_back(partner);
      cut[k].emplace_back(t, id);
    }
  }
  return s;
}

// The ids each side makes for the vertices of the other chain it does not pair, in the order
// make_side appends them.
std::vector<int> new_ids(const Mesh& m, const std::vector<Placement>& others) {
  std::vector<int> ids(others.size(), -1);
  int next = m.num_vertices();
  for (std::size_t j = 0; j < others.size(); ++j)
    if (others[j].vertex < 0) ids[j] = next++;
  return ids;
}

std::unordered_map<std::uint64_t, int> edge_ids(const Mesh& m) {
  std::unordered_map<std::uint64_t, int> ids;
  ids.reserve(static_cast<std::size_t>(m.num_edges()));
  for (int i = 0; i < m.num_edges(); ++i) ids.emplace(edge_key(m.edge(i).v0, m.edge(i).v1), i);
  return ids;
}

// The mesh of a side: each polygon with the cut points of its interface edges spliced in, and the
// edge groups carried over to the pieces.
Mesh build_mesh(const Mesh& m, const Chain& c, const Side& s, const std::vector<std::vector<std::pair<double, int>>>& cut,
                const std::string& side) {
  std::unordered_map<int, std::size_t> position;  // interface edge id -> position in the chain
  for (std::size_t k = 0; k < c.edges.size(); ++k) position.emplace(c.edges[k], k);
  std::vector<std::vector<int>> elements;
  elements.reserve(static_cast<std::size_t>(m.num_elements()));
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto el = m.element(e);
    const auto edges = m.element_edges(e);
    std::vector<int> polygon;
    polygon.reserve(el.size());
    for (std::size_t j = 0; j < el.size(); ++j) {
      polygon.push_back(el[j]);
      const auto it = position.find(edges[j]);
      if (it == position.end()) continue;
      // A boundary edge runs v0 -> v1 in its element, as the chain does.
      for (const auto& piece : cut[it->second]) polygon.push_back(piece.second);
    }
    elements.push_back(std::move(polygon));
  }
  Mesh out;
  try {
    out = Mesh(s.vertices, std::move(elements), m.regions());
  } catch (const MeshError& error) {
    throw MeshError("inserting the interface vertices of the other mesh into element " + std::to_string(error.element()) +
                        " of the " + side + " mesh gives an invalid mesh: " + error.what(),
                    error.element());
  }
  if (!m.edge_groups().empty()) {
    const auto edge_id = edge_ids(out);
    for (const auto& [name, group] : m.edge_groups()) {
      std::vector<int> pieces;
      for (int g : group) {
        const auto it = position.find(g);
        int from = m.edge(g).v0;
        if (it != position.end())
          for (const auto& piece : cut[it->second]) {
            pieces.push_back(edge_id.at(edge_key(from, piece.second)));
            from = piece.second;
          }
        pieces.push_back(edge_id.at(edge_key(from, m.edge(g).v1)));
      }
      out.set_edge_group(name, std::move(pieces));
    }
  }
  return out;
}


}  // namespace

MatchedInterface match_interface(const Mesh& first, const std::vector<int>& first_edges, const Mesh& second,
                                 const std::vector<int>& second_edges, double tolerance) {
  if (!(tolerance >= 0.0 && tolerance <= max_tolerance))
    throw InputError("the interface tolerance is " + fmt_number(tolerance) + "; it must be in [0, " +
                     fmt_number(max_tolerance) + "] (a fraction of the interface's length)");
  const Chain a = make_chain(first, first_edges, "first");
  const Chain b = make_chain(second, second_edges, "second");

  // The distance tolerance: relative to the interface's length, at least the coordinates' round-off.
  const double length = std::max(chain_length(first, a), chain_length(second, b));
  double magnitude = 0.0;
  for (int v : a.vertices) magnitude = std::max(magnitude, first.vertex(v).cwiseAbs().maxCoeff());
  for (int v : b.vertices) magnitude = std::max(magnitude, second.vertex(v).cwiseAbs().maxCoeff());
  const double tol = std::max(tolerance * length, 16.0 * std::numeric_limits<double>::epsilon() * magnitude);

  const std::vector<Placement> a_on_b = place(first, a, "first", second, b, "second", tol, tolerance, length);
  const std::vector<Placement> b_on_a = place(second, b, "second", first, a, "first", tol, tolerance, length);
  // Pairing must be mutual: a vertex of one side within the tolerance of one of the other is the
  // only one within it of that one.
  for (std::size_t i = 0; i < a_on_b.size(); ++i) {
    const int j = a_on_b[i].vertex;
    if (j >= 0 && b_on_a[static_cast<std::size_t>(j)].vertex != static_cast<int>(i))
      throw InputError("interface vertex " + std::to_string(b.vertices[static_cast<std::size_t>(j)]) +
                       " of the second mesh is within the tolerance " + fmt_number(tol) +
                       " of two interface vertices of the first mesh; use a smaller tolerance");
  }

  std::vector<std::vector<std::pair<double, int>>> a_cut, b_cut;
  const std::vector<int> made_in_first = new_ids(first, b_on_a);   // per vertex of b
  const std::vector<int> made_in_second = new_ids(second, a_on_b);  // per vertex of a
  const Side sa = make_side(first, a, second, b, a_on_b, b_on_a, made_in_second, a_cut);
  const Side sb = make_side(second, b, first, a, b_on_a, a_on_b, made_in_first, b_cut);

  // Both walks hold every paired point once; the second runs the other way.
  const std::size_t m = sa.walk.size();
  if (sb.walk.size() != m)
    throw InternalError("match_interface: the two interfaces have " + std::to_string(m) + " and " +
                        std::to_string(sb.walk.size()) + " vertices after the match");
  bool forward = true, backward = true;
  std::size_t first_wrong = m;
  for (std::size_t k = 0; k < m; ++k) {
    forward = forward && sa.partner[k] == sb.walk[k];
    if (sa.partner[k] != sb.walk[m - 1 - k]) {
      backward = false;
      first_wrong = std::min(first_wrong, k);
    }
  }
  if (!backward) {
    if (forward)
      throw InputError("the interfaces of the first mesh (from vertex " + std::to_string(a.vertices.front()) +
                       ") and of the second mesh (from vertex " + std::to_string(b.vertices.front()) +
                       ") run the same way: the two bodies lie on the same side of the interface (they overlap); "
                       "the bodies must lie on either side of it");
    const int va = sa.walk[first_wrong];
    const Vec2& x = sa.vertices[static_cast<std::size_t>(va)];
    throw InputError("the interfaces of the first and second meshes do not run along the same curve in the same order: "
                     "point " + fmt_point(x) + " (vertex " + std::to_string(va) + " of the first mesh after the match) is the " +
                     std::to_string(first_wrong + 1) + "-th of " + std::to_string(m) +
                     " along the first interface but not along the second; the two interfaces must cover the same curve");
  }

  MatchedInterface out;
  out.first = build_mesh(first, a, sa, a_cut, "first");
  out.second = build_mesh(second, b, sb, b_cut, "second");
  out.pairs.reserve(m);
  for (std::size_t k = 0; k < m; ++k) out.pairs.push_back({sa.walk[k], sa.partner[k]});
  const auto first_ids = edge_ids(out.first), second_ids = edge_ids(out.second);
  for (std::size_t k = 0; k + 1 < m; ++k) {
    out.first_edges.push_back(first_ids.at(edge_key(out.pairs[k][0], out.pairs[k + 1][0])));
    out.second_edges.push_back(second_ids.at(edge_key(out.pairs[k][1], out.pairs[k + 1][1])));
  }
  out.first_vertex_of.resize(static_cast<std::size_t>(first.num_vertices()));
  out.second_vertex_of.resize(static_cast<std::size_t>(second.num_vertices()));
  for (int v = 0; v < first.num_vertices(); ++v) out.first_vertex_of[static_cast<std::size_t>(v)] = v;
  for (int v = 0; v < second.num_vertices(); ++v) out.second_vertex_of[static_cast<std::size_t>(v)] = v;
  return out;
}

}  // namespace hemivem
