#include <hemivem/mesh/refine3d.hpp>

#include "polygon_kernels.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
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
using detail::cross2;
using detail::mean_value_coordinates;

// A vertex is hanging in a geometric face when its distance to the segment between its
// neighbours along the face's boundary is at most this fraction of the face's diameter.
constexpr double hanging_tolerance = 1e-10;
// A vertex already this close to a side's midpoint (relative to the side's length) is reused,
// and two points cut on one edge this close in the edge's parameter are the same point.
constexpr double midpoint_tolerance = 1e-8;
// Face points and interior points are at least this fraction of the diameter away from the
// line of every side of the face, or the plane of every face of the cell.
constexpr double kernel_margin = 1e-8;
// Two faces of a cell that share an edge lie in one plane when their unit normals differ by
// at most this.
constexpr double coplanar_tolerance = 1e-9;
// An interior face is one quadrilateral when its four points are this close (relative to its
// diameter) to one plane; else it is two triangles.
constexpr double fold_tolerance = 1e-12;

using Point2 = Eigen::Vector2d;

std::string fmt_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b)));
  const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::max(a, b)));
  return (lo << 32) | hi;
}

std::size_t at(int i) { return static_cast<std::size_t>(i); }

// Coordinates relative to an origin and scaled by a power of two (exactly), so that a face or
// a cell has a diameter in [1, 2): every geometric quantity is of order one at any scale.
struct Frame {
  Vec3 origin = Vec3::Zero();
  int exponent = 0;  // global = origin + 2^exponent * local

  Vec3 local(const Vec3& p) const {
    const Vec3 d = p - origin;
    return {std::ldexp(d.x(), -exponent), std::ldexp(d.y(), -exponent), std::ldexp(d.z(), -exponent)};
  }
  Vec3 global(const Vec3& l) const {
    return origin + Vec3(std::ldexp(l.x(), exponent), std::ldexp(l.y(), exponent), std::ldexp(l.z(), exponent));
  }
};

// The largest distance between two of the points.
double diameter_of(const std::vector<Vec3>& p) {
  double d2 = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) d2 = std::max(d2, (p[i] - p[j]).squaredNorm());
  return std::sqrt(d2);
}

// The vertices of a loop (or path) of vertex ids in a frame of their own: `q` their local
// coordinates, `diameter` in local units.
struct LocalPoints {
  Frame frame;
  double diameter = 1.0;
  std::vector<Vec3> q;
};

LocalPoints local_points(const Mesh3D& mesh, const std::vector<int>& ids) {
  LocalPoints out;
  std::vector<Vec3> p;
  p.reserve(ids.size());
  for (int v : ids) p.push_back(mesh.vertex(v) - mesh.vertex(ids.front()));
  const double d = diameter_of(p);
  out.frame.origin = mesh.vertex(ids.front());
  out.frame.exponent = d > 0.0 ? std::ilogb(d) : 0;
  out.q.reserve(ids.size());
  for (int v : ids) out.q.push_back(out.frame.local(mesh.vertex(v)));
  out.diameter = std::ldexp(d, -out.frame.exponent);
  return out;
}

// The edges of the mesh (each face's consecutive vertices), numbered in the order the faces
// meet them, with the faces around each.
struct EdgeTable {
  std::unordered_map<std::uint64_t, int> id;
  std::vector<std::array<int, 2>> ends;  // lower vertex id first
  std::vector<int> face_start, faces;    // faces[face_start[g] .. face_start[g + 1]) hold edge g

  int find(int a, int b) const {
    const auto it = id.find(edge_key(a, b));
    return it == id.end() ? -1 : it->second;
  }
};

EdgeTable edge_table(const Mesh3D& mesh) {
  EdgeTable t;
  std::size_t total = 0;
  for (const MeshFace& f : mesh.faces()) total += f.vertices.size();
  t.id.reserve(total);
  std::vector<int> edge_of;  // per face edge, in face order
  edge_of.reserve(total);
  for (const MeshFace& f : mesh.faces()) {
    const std::size_t n = f.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const int a = f.vertices[i], b = f.vertices[(i + 1) % n];
      const auto [it, inserted] = t.id.emplace(edge_key(a, b), static_cast<int>(t.ends.size()));
      if (inserted) t.ends.push_back({std::min(a, b), std::max(a, b)});
      edge_of.push_back(it->second);
    }
  }
  t.face_start.assign(t.ends.size() + 1, 0);
  for (int g : edge_of) ++t.face_start[at(g) + 1];
  for (std::size_t g = 0; g < t.ends.size(); ++g) t.face_start[g + 1] += t.face_start[g];
  t.faces.resize(total);
  std::vector<int> next(t.face_start.begin(), t.face_start.end() - 1);
  std::size_t k = 0;
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (std::size_t i = 0; i < mesh.face(f).vertices.size(); ++i) t.faces[at(next[at(edge_of[k++])]++)] = f;
  return t;
}

// The cells around edge g, each once, in increasing id.
void cells_of_edge(const Mesh3D& mesh, const EdgeTable& edges, int g, std::vector<int>& out) {
  out.clear();
  for (int k = edges.face_start[at(g)]; k < edges.face_start[at(g) + 1]; ++k) {
    const MeshFace& f = mesh.face(edges.faces[at(k)]);
    out.push_back(f.inner);
    if (f.outer >= 0) out.push_back(f.outer);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// The corners of a closed loop of points (local coordinates, diameter in the same units):
// positions in the loop, increasing. A vertex strictly between its neighbours and at most
// hanging_tolerance of the diameter from the segment joining them is taken out, the nearest
// first, the neighbours of a vertex taken out being joined; at least 3 remain.
std::vector<int> loop_corners(const std::vector<Vec3>& q, double diameter) {
  const int n = static_cast<int>(q.size());
  std::vector<int> prev(at(n)), next(at(n));
  std::vector<char> corner(at(n), 1);
  for (int i = 0; i < n; ++i) {
    prev[at(i)] = (i + n - 1) % n;
    next[at(i)] = (i + 1) % n;
  }
  auto deviation = [&](int i) {
    const Vec3& a = q[at(prev[at(i)])];
    const Vec3& v = q[at(i)];
    const Vec3& b = q[at(next[at(i)])];
    const Vec3 w = b - a;
    const double len = w.norm();
    if (!(len > 0.0) || !((v - a).dot(w) > 0.0) || !((v - b).dot(a - b) > 0.0))
      return std::numeric_limits<double>::infinity();
    return w.cross(v - a).norm() / (len * diameter);
  };
  for (int left = n; left > 3; --left) {
    int best = -1;
    double best_deviation = hanging_tolerance;
    for (int i = 0; i < n; ++i) {
      if (!corner[at(i)]) continue;
      const double d = deviation(i);
      if (d <= best_deviation && (best < 0 || d < best_deviation)) {
        best = i;
        best_deviation = d;
      }
    }
    if (best < 0) break;
    corner[at(best)] = 0;
    next[at(prev[at(best)])] = next[at(best)];
    prev[at(next[at(best)])] = prev[at(best)];
  }
  std::vector<int> corners;
  for (int i = 0; i < n; ++i)
    if (corner[at(i)]) corners.push_back(i);
  return corners;
}

// Where the midpoint of a side goes: an existing vertex, or a point cut on an edge.
struct Midpoint {
  int reuse = -1;  // an existing vertex at the midpoint, or -1
  int edge = -1;   // else the edge that holds it
  double t = 0.5;  // its position along that edge, from the edge's lower-numbered end
};

// The midpoint of the side running along `path` (vertex ids from corner to corner). The same
// for the path and its reverse: computed from the end with the lower vertex id.
Midpoint plan_midpoint(const Mesh3D& mesh, const EdgeTable& edges, std::vector<int> path) {
  if (path.front() > path.back()) std::reverse(path.begin(), path.end());
  const LocalPoints p = local_points(mesh, path);
  const int len = static_cast<int>(path.size()) - 1;  // number of edges
  Midpoint m;
  auto cut = [&](int j, double s) {  // the point at s along path edge j
    m.edge = edges.find(path[at(j)], path[at(j) + 1]);
    m.t = path[at(j)] == edges.ends[at(m.edge)][0] ? s : 1.0 - s;
  };
  if (len == 1) {
    cut(0, 0.5);
    return m;
  }
  const Vec3 u = p.q.back() - p.q.front();
  const double uu = u.squaredNorm();
  auto tau = [&](int j) {
    if (j == 0) return 0.0;
    if (j == len) return 1.0;
    return (p.q[at(j)] - p.q.front()).dot(u) / uu;
  };
  for (int j = 1; j < len; ++j)
    if (std::abs(tau(j) - 0.5) <= midpoint_tolerance) {
      m.reuse = path[at(j)];
      return m;
    }
  for (int j = 0; j < len; ++j) {
    const double t0 = tau(j), t1 = tau(j + 1);
    if (t0 < 0.5 && 0.5 < t1) {
      cut(j, (0.5 - t0) / (t1 - t0));
      return m;
    }
  }
  // A side whose vertices do not advance along its chord (round-off on edges of nearly zero
  // length): its longest edge is cut in half.
  int longest = 0;
  for (int j = 1; j < len; ++j)
    if ((p.q[at(j) + 1] - p.q[at(j)]).norm() > (p.q[at(longest) + 1] - p.q[at(longest)]).norm()) longest = j;
  cut(longest, 0.5);
  return m;
}

// The path along a closed loop from position i to position j (both included).
std::vector<int> loop_path(const std::vector<int>& loop, int i, int j) {
  const int n = static_cast<int>(loop.size());
  std::vector<int> out;
  for (int k = i;; k = (k + 1) % n) {
    out.push_back(loop[at(k)]);
    if (k == j) break;
  }
  return out;
}

int position_in(const std::vector<int>& loop, int v) {
  const auto it = std::find(loop.begin(), loop.end(), v);
  return it == loop.end() ? -1 : static_cast<int>(it - loop.begin());
}

// The loop around two faces that share the edge a-b, given with consistent orientations (the
// edge runs a -> b in one and b -> a in the other): the first from b round to a, then the
// second from a round to b.
std::vector<int> joined_loop(const std::vector<int>& first, const std::vector<int>& second, int a, int b) {
  const int n = static_cast<int>(first.size()), m = static_cast<int>(second.size());
  if (first[at((position_in(first, a) + 1) % n)] != b) std::swap(a, b);
  const int i = position_in(first, a);
  std::vector<int> loop;
  for (int k = 1; k <= n; ++k) loop.push_back(first[at((i + k) % n)]);  // b ... a
  const int j = position_in(second, a);
  for (int k = (j + 1) % m; second[at(k)] != b; k = (k + 1) % m) loop.push_back(second[at(k)]);
  return loop;
}

// Folded pairs: two triangles (three corners each, any vertices along their sides) between the
// same two cells, sharing a side: the two halves of a quadrilateral whose corners are not
// coplanar, cut along a diagonal (an interior face of a split cell, or a piece of one). Such a
// pair is one geometric face of each of its cells, with the four corners of its loop.
struct FoldedPairs {
  std::vector<int> partner;               // per face: its other half, or -1
  std::vector<int> diagonal;              // per face with a partner: the edge they share
  std::vector<std::vector<int>> corners;  // per face with a partner: the pair's corner vertices, sorted
};

FoldedPairs folded_pairs(const Mesh3D& mesh, const EdgeTable& edges,
                         const std::vector<std::vector<int>>& face_corners) {
  const int nf = mesh.num_faces();
  FoldedPairs out;
  out.partner.assign(at(nf), -1);
  out.diagonal.assign(at(nf), -1);
  out.corners.resize(at(nf));
  auto cells = [&](int f) { return std::minmax(mesh.face(f).inner, mesh.face(f).outer); };
  auto candidate = [&](int f, int& edge) {  // the unique other half of f, or -1
    int found = -1, count = 0;
    const MeshFace& face = mesh.face(f);
    if (face.on_boundary() || face_corners[at(f)].size() != 3) return -1;
    const auto& loop = face.vertices;
    const auto& fc = face_corners[at(f)];
    for (std::size_t s = 0; s < 3; ++s) {
      const int i = fc[s], j = fc[(s + 1) % 3];
      if ((i + 1) % static_cast<int>(loop.size()) != j) continue;  // a side of one edge only
      const int g = edges.find(loop[at(i)], loop[at(j)]);
      for (int k = edges.face_start[at(g)]; k < edges.face_start[at(g) + 1]; ++k) {
        const int h = edges.faces[at(k)];
        if (h == f || cells(h) != cells(f) || face_corners[at(h)].size() != 3) continue;
        const auto& hl = mesh.face(h).vertices;
        const auto& hc = face_corners[at(h)];
        const bool corners_there = std::any_of(hc.begin(), hc.end(), [&](int p) { return hl[at(p)] == loop[at(i)]; }) &&
                                   std::any_of(hc.begin(), hc.end(), [&](int p) { return hl[at(p)] == loop[at(j)]; });
        if (!corners_there) continue;
        found = h;
        edge = g;
        ++count;
      }
    }
    return count == 1 ? found : -1;
  };
  std::vector<int> edge_of(at(nf), -1);
  std::vector<int> first(at(nf), -1);
  for (int f = 0; f < nf; ++f) first[at(f)] = candidate(f, edge_of[at(f)]);
  for (int f = 0; f < nf; ++f) {
    const int h = first[at(f)];
    if (h < f || first[at(h)] != f) continue;
    // the loop of the pair in f's orientation, and its corners
    std::vector<int> other = mesh.face(h).vertices;
    if (mesh.face(h).inner != mesh.face(f).inner) std::reverse(other.begin(), other.end());
    const auto& e = edges.ends[at(edge_of[at(f)])];
    const std::vector<int> loop = joined_loop(mesh.face(f).vertices, other, e[0], e[1]);
    const LocalPoints p = local_points(mesh, loop);
    std::vector<int> corners;
    for (int i : loop_corners(p.q, p.diameter)) corners.push_back(loop[at(i)]);
    std::sort(corners.begin(), corners.end());
    if (corners.size() != 4 || !std::binary_search(corners.begin(), corners.end(), e[0]) ||
        !std::binary_search(corners.begin(), corners.end(), e[1]))
      continue;
    for (const int x : {f, h}) {
      out.partner[at(x)] = x == f ? h : f;
      out.diagonal[at(x)] = edge_of[at(f)];
      out.corners[at(x)] = corners;
    }
  }
  return out;
}

// A unit of a cell's boundary: one of its faces, or a folded pair.
struct Unit {
  std::vector<int> faces;    // local faces (positions in the cell's face list): 1, or 2 for a folded pair
  std::vector<int> loop;     // its boundary, counter-clockwise seen from outside the cell
  std::vector<int> corners;  // positions in loop of its corners, increasing
};

// A geometric face of a cell: a unit, or the pieces a split neighbour made of one (units around
// one vertex inside, one corner each).
struct GeoFace {
  std::vector<int> loop;                 // its boundary, vertex ids, counter-clockwise seen from outside the cell
  std::vector<int> corners;              // positions in loop of its corners, increasing
  std::vector<int> units;                // the units it is made of
  int centre = -1;                       // made of pieces: the vertex they share inside it; else -1
  std::vector<int> piece;                // made of pieces: per corner, the unit that holds it
  std::vector<std::vector<int>> spokes;  // made of pieces: per side, the path from its midpoint to centre
  bool pieces() const { return centre >= 0; }
};

// A geometric side of a cell, between two of its geometric faces.
struct Side {
  std::vector<int> path;        // vertex ids, from corner to corner
  int out = -1, out_side = -1;  // the geometric face (and its side) along which it runs front to back
  int in = -1, in_side = -1;    // the one along which it runs back to front
  Midpoint mid;
};

struct CellPlan {
  std::vector<char> flipped;  // per local face: stored the other way round
  std::vector<Unit> units;
  std::vector<GeoFace> faces;
  std::vector<int> corners;  // vertex ids, increasing
  std::vector<Side> sides;
  std::string defect;  // why the cell cannot be split; empty when it can
};

// The member owning each directed edge of the loops of the units `members`.
class EdgeOwners {
 public:
  EdgeOwners(const std::vector<Unit>& units, const std::vector<int>& members) {
    for (int k : members) {
      const auto& l = units[at(k)].loop;
      for (std::size_t i = 0; i < l.size(); ++i) directed_.push_back({key(l[i], l[(i + 1) % l.size()]), k});
    }
    std::sort(directed_.begin(), directed_.end(), [](const Directed& a, const Directed& b) { return a.key < b.key; });
  }
  /// The member whose loop runs from a to b, or -1.
  int owner(int a, int b) const {
    const std::uint64_t k = key(a, b);
    const auto it = std::lower_bound(directed_.begin(), directed_.end(), k,
                                     [](const Directed& d, std::uint64_t x) { return d.key < x; });
    return it != directed_.end() && it->key == k ? it->member : -1;
  }

 private:
  struct Directed {
    std::uint64_t key;
    int member;
  };
  static std::uint64_t key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  }
  std::vector<Directed> directed_;
};

// The one loop around the units `members`: their directed edges whose reverse is in no member.
// False when they do not make one loop.
bool boundary_loop(const std::vector<Unit>& units, const std::vector<int>& members, const EdgeOwners& owners,
                   std::vector<int>& loop) {
  std::unordered_map<int, int> next;
  int start = -1;
  for (int k : members) {
    const auto& l = units[at(k)].loop;
    for (std::size_t i = 0; i < l.size(); ++i) {
      const int a = l[i], b = l[(i + 1) % l.size()];
      if (owners.owner(b, a) >= 0) continue;
      if (!next.emplace(a, b).second) return false;
      if (start < 0) start = a;
    }
  }
  if (start < 0) return false;
  loop = {start};
  for (int v = next.at(start); v != start; v = next.at(v)) {
    if (loop.size() > next.size() || next.find(v) == next.end()) return false;
    loop.push_back(v);
  }
  return loop.size() == next.size();
}

// The one vertex inside the loop (not on `on_loop`, sorted) shared by every member, or -1.
int shared_centre(const std::vector<Unit>& units, const std::vector<int>& members, const std::vector<int>& on_loop) {
  std::unordered_map<int, int> count;
  for (int k : members)
    for (int v : units[at(k)].loop) ++count[v];
  int centre = -1;
  for (int k : members)
    for (int v : units[at(k)].loop) {
      if (std::binary_search(on_loop.begin(), on_loop.end(), v) || count[v] != static_cast<int>(members.size())) continue;
      if (centre >= 0 && centre != v) return -1;
      centre = v;
    }
  return centre;
}

// The member holding each corner of the loop, each member one corner: false otherwise.
bool assign_pieces(const std::vector<Unit>& units, const std::vector<int>& members, const std::vector<int>& loop,
                   const std::vector<int>& corners, std::vector<int>& piece) {
  const int r = static_cast<int>(corners.size());
  if (r != static_cast<int>(members.size())) return false;
  piece.assign(at(r), -1);
  for (int s = 0; s < r; ++s) {
    const int v = loop[at(corners[at(s)])];
    for (int k : members)
      if (position_in(units[at(k)].loop, v) >= 0) {
        if (piece[at(s)] >= 0) return false;
        piece[at(s)] = k;
      }
    if (piece[at(s)] < 0) return false;
  }
  std::vector<int> sorted = piece;
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
}

// The spoke of side s of the loop (from corner s to corner s + 1): the side's midpoint must be a
// vertex of the loop, piece s must own the loop up to it and the next piece the rest, and the
// spoke runs along piece s's loop from the midpoint to the centre. False when it does not.
bool side_spoke(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<Unit>& units, const EdgeOwners& owners,
                const std::vector<int>& loop, const std::vector<int>& on_loop, const std::vector<int>& corners,
                const std::vector<int>& piece, int centre, int s, std::vector<int>& spoke) {
  const int r = static_cast<int>(corners.size());
  const int n = static_cast<int>(loop.size());
  const int c0 = corners[at(s)], c1 = corners[at((s + 1) % r)];
  const Midpoint mid = plan_midpoint(mesh, edges, loop_path(loop, c0, c1));
  if (mid.reuse < 0) return false;
  const int at_mid = position_in(loop, mid.reuse);
  const int next_piece = piece[at((s + 1) % r)];
  bool reached = false;
  for (int i = c0; i != c1; i = (i + 1) % n) {
    if (i == at_mid) reached = true;
    if (owners.owner(loop[at(i)], loop[at((i + 1) % n)]) != (reached ? next_piece : piece[at(s)])) return false;
  }
  if (!reached) return false;
  // piece s's loop from the midpoint to the centre, the next piece's the other way
  const auto& l = units[at(piece[at(s)])].loop;
  const int m = static_cast<int>(l.size());
  spoke = {mid.reuse};
  for (int i = (position_in(l, mid.reuse) + 1) % m; spoke.back() != centre; i = (i + 1) % m) {
    const int v = l[at(i)];
    if (v != centre && (std::binary_search(on_loop.begin(), on_loop.end(), v) || spoke.size() > l.size())) return false;
    spoke.push_back(v);
  }
  for (std::size_t i = 0; i + 1 < spoke.size(); ++i)
    if (owners.owner(spoke[i + 1], spoke[i]) != next_piece) return false;
  return true;
}

// Makes g the geometric face of the units `members` of a cell when they are the pieces of a
// split: one loop around them, one vertex inside shared by all, one corner of the loop in each,
// meeting at the midpoints of the loop's sides along paths to the shared vertex. False when
// they are not.
bool make_pieces(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<Unit>& units,
                 const std::vector<int>& members, GeoFace& g) {
  if (members.size() < 3) return false;
  const EdgeOwners owners(units, members);
  std::vector<int> loop;
  if (!boundary_loop(units, members, owners, loop)) return false;
  std::vector<int> on_loop = loop;
  std::sort(on_loop.begin(), on_loop.end());
  const int centre = shared_centre(units, members, on_loop);
  if (centre < 0) return false;
  const LocalPoints p = local_points(mesh, loop);
  const std::vector<int> corners = loop_corners(p.q, p.diameter);
  std::vector<int> piece;
  if (!assign_pieces(units, members, loop, corners, piece)) return false;
  const int r = static_cast<int>(corners.size());
  std::vector<std::vector<int>> spokes(at(r));
  for (int s = 0; s < r; ++s)
    if (!side_spoke(mesh, edges, units, owners, loop, on_loop, corners, piece, centre, s, spokes[at(s)])) return false;
  g.loop = std::move(loop);
  g.corners = corners;
  g.units = members;
  g.centre = centre;
  g.piece = std::move(piece);
  g.spokes = std::move(spokes);
  return true;
}

// The faces of cell c as loops oriented out of it, with their outward normals (plan.flipped
// marks those reversed).
void outward_loops(const Mesh3D& mesh, int c, CellPlan& plan, std::vector<std::vector<int>>& loops,
                   std::vector<Vec3>& normal) {
  const auto& ids = mesh.cell_faces(c);
  const int nf = static_cast<int>(ids.size());
  loops.assign(at(nf), {});
  normal.assign(at(nf), Vec3::Zero());
  plan.flipped.assign(at(nf), 0);
  for (int k = 0; k < nf; ++k) {
    const MeshFace& f = mesh.face(ids[at(k)]);
    loops[at(k)] = f.vertices;
    normal[at(k)] = mesh.face_normal(ids[at(k)]);
    if (f.inner != c) {
      std::reverse(loops[at(k)].begin(), loops[at(k)].end());
      plan.flipped[at(k)] = 1;
      normal[at(k)] = -normal[at(k)];
    }
  }
}

// The units of cell c (each face, a folded pair joined) into plan.units; unit_of[k] the unit of
// the cell's face k.
void make_units(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<std::vector<int>>& face_corners,
                const FoldedPairs& folded, int c, const std::vector<std::vector<int>>& loops, CellPlan& plan,
                std::vector<int>& unit_of) {
  const auto& ids = mesh.cell_faces(c);
  const int nf = static_cast<int>(ids.size());
  unit_of.assign(at(nf), -1);
  for (int k = 0; k < nf; ++k) {
    if (unit_of[at(k)] >= 0) continue;
    const int f = ids[at(k)];
    Unit u;
    u.faces = {k};
    if (folded.partner[at(f)] >= 0) {
      const int kp = static_cast<int>(std::find(ids.begin(), ids.end(), folded.partner[at(f)]) - ids.begin());
      const auto& e = edges.ends[at(folded.diagonal[at(f)])];
      u.faces.push_back(kp);
      u.loop = joined_loop(loops[at(k)], loops[at(kp)], e[0], e[1]);
      const auto& fc = folded.corners[at(f)];
      for (std::size_t i = 0; i < u.loop.size(); ++i)
        if (std::binary_search(fc.begin(), fc.end(), u.loop[i])) u.corners.push_back(static_cast<int>(i));
    } else {
      u.loop = loops[at(k)];
      const int n = static_cast<int>(u.loop.size());
      for (int p : face_corners[at(f)]) u.corners.push_back(plan.flipped[at(k)] ? n - 1 - p : p);
      std::sort(u.corners.begin(), u.corners.end());
    }
    for (int j : u.faces) unit_of[at(j)] = static_cast<int>(plan.units.size());
    plan.units.push_back(std::move(u));
  }
}

// The geometric faces of the cell into plan.faces: units with coplanar faces sharing an edge
// grouped (union-find), a group the pieces of a split one face, any other unit a face alone.
void make_geometric_faces(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<std::vector<int>>& loops,
                          const std::vector<Vec3>& normal, const std::vector<int>& unit_of, CellPlan& plan) {
  const int nf = static_cast<int>(loops.size());
  const int nu = static_cast<int>(plan.units.size());
  std::vector<int> group(at(nu));
  std::iota(group.begin(), group.end(), 0);
  auto root = [&](int k) {
    while (group[at(k)] != k) k = group[at(k)] = group[at(group[at(k)])];
    return k;
  };
  std::vector<std::pair<std::uint64_t, int>> undirected;
  for (int k = 0; k < nf; ++k) {
    const auto& l = loops[at(k)];
    for (std::size_t i = 0; i < l.size(); ++i) undirected.emplace_back(edge_key(l[i], l[(i + 1) % l.size()]), k);
  }
  std::sort(undirected.begin(), undirected.end());
  for (std::size_t i = 0; i + 1 < undirected.size(); ++i) {
    if (undirected[i].first != undirected[i + 1].first) continue;
    const int a = undirected[i].second, b = undirected[i + 1].second;
    if (unit_of[at(a)] != unit_of[at(b)] && (normal[at(a)] - normal[at(b)]).norm() <= coplanar_tolerance) {
      const int ra = root(unit_of[at(a)]), rb = root(unit_of[at(b)]);
      group[at(std::max(ra, rb))] = std::min(ra, rb);
    }
  }
  for (int u = 0; u < nu; ++u) {
    if (root(u) != u) continue;
    std::vector<int> members;
    for (int j = u; j < nu; ++j)
      if (root(j) == u) members.push_back(j);
    GeoFace g;
    if (members.size() > 1 && make_pieces(mesh, edges, plan.units, members, g)) {
      plan.faces.push_back(std::move(g));
      continue;
    }
    for (int j : members) {
      GeoFace single;
      single.loop = plan.units[at(j)].loop;
      single.corners = plan.units[at(j)].corners;
      single.units = {j};
      plan.faces.push_back(std::move(single));
    }
  }
}

// The corners of the cell: those of its geometric faces. False (with plan.defect) when a corner
// of one face lies inside a side of another.
bool find_corners(CellPlan& plan) {
  for (const GeoFace& g : plan.faces)
    for (int p : g.corners) plan.corners.push_back(g.loop[at(p)]);
  std::sort(plan.corners.begin(), plan.corners.end());
  plan.corners.erase(std::unique(plan.corners.begin(), plan.corners.end()), plan.corners.end());
  for (const GeoFace& g : plan.faces)
    for (std::size_t i = 0; i < g.loop.size(); ++i)
      if (std::binary_search(plan.corners.begin(), plan.corners.end(), g.loop[i]) &&
          !std::binary_search(g.corners.begin(), g.corners.end(), static_cast<int>(i))) {
        plan.defect = "its vertex " + std::to_string(g.loop[i]) +
                      " is a corner of one of its faces but lies inside a side of another (its faces do not meet "
                      "along whole sides)";
        return false;
      }
  return true;
}

// The sides of the cell: each path between consecutive corners of a geometric face, paired with
// the reverse path of the neighbouring geometric face. False (with plan.defect) for a path in one
// face only.
bool pair_sides(const Mesh3D& mesh, const EdgeTable& edges, CellPlan& plan) {
  struct Run {
    std::vector<int> path;
    int face, side;
    bool paired = false;
  };
  std::vector<Run> runs;
  for (int gi = 0; gi < static_cast<int>(plan.faces.size()); ++gi) {
    const GeoFace& g = plan.faces[at(gi)];
    const int r = static_cast<int>(g.corners.size());
    for (int s = 0; s < r; ++s)
      runs.push_back({loop_path(g.loop, g.corners[at(s)], g.corners[at((s + 1) % r)]), gi, s});
  }
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].paired) continue;
    const auto& p = runs[i].path;
    std::size_t twin = runs.size();
    for (std::size_t j = i + 1; j < runs.size() && twin == runs.size(); ++j)
      if (!runs[j].paired && std::equal(p.begin(), p.end(), runs[j].path.rbegin(), runs[j].path.rend())) twin = j;
    if (twin == runs.size()) {
      plan.defect = "its faces do not meet along whole sides (the side from vertex " + std::to_string(p.front()) +
                    " to vertex " + std::to_string(p.back()) + " is in one of its faces only)";
      return false;
    }
    runs[i].paired = runs[twin].paired = true;
    Side s;
    s.path = p;
    s.out = runs[i].face;
    s.out_side = runs[i].side;
    s.in = runs[twin].face;
    s.in_side = runs[twin].side;
    s.mid = plan_midpoint(mesh, edges, p);
    plan.sides.push_back(std::move(s));
  }
  return true;
}

// The units, geometric faces, corners and sides of cell c, and whether it can be split.
CellPlan plan_cell(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<std::vector<int>>& face_corners,
                   const FoldedPairs& folded, int c) {
  CellPlan plan;
  std::vector<std::vector<int>> loops;
  std::vector<Vec3> normal;
  outward_loops(mesh, c, plan, loops, normal);
  std::vector<int> unit_of;
  make_units(mesh, edges, face_corners, folded, c, loops, plan, unit_of);
  make_geometric_faces(mesh, edges, loops, normal, unit_of, plan);
  if (find_corners(plan)) pair_sides(mesh, edges, plan);
  return plan;
}

// The paths a cell's rule counts vertices on: its sides and the spokes of its faces made of pieces.
template <class F>
void for_each_counted_path(const CellPlan& plan, F&& f) {
  for (const Side& s : plan.sides) f(s.path);
  for (const GeoFace& g : plan.faces)
    for (const auto& spoke : g.spokes) f(spoke);
}

// The one-hanging-vertex closure of the marked set: marks every cell one of whose sides (or
// spokes) would receive a new vertex and then carry more than one vertex inside it.
std::vector<char> close_marked_set(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<CellPlan>& plans,
                                   std::span<const int> marked) {
  std::vector<char> is_marked(at(mesh.num_cells()), 0);
  std::vector<std::vector<double>> pending(edges.ends.size());  // new points per edge (t)
  std::vector<int> to_check, around;
  auto mark = [&](int c) {
    is_marked[at(c)] = 1;
    for (const Side& s : plans[at(c)].sides) {
      if (s.mid.reuse >= 0) continue;
      auto& on_edge = pending[at(s.mid.edge)];
      if (std::any_of(on_edge.begin(), on_edge.end(),
                      [&](double t) { return std::abs(t - s.mid.t) <= midpoint_tolerance; }))
        continue;
      on_edge.push_back(s.mid.t);
      cells_of_edge(mesh, edges, s.mid.edge, around);
      for (int e : around)
        if (!is_marked[at(e)]) to_check.push_back(e);
    }
  };
  for (int c : marked)
    if (!is_marked[at(c)]) mark(c);
  while (!to_check.empty()) {
    const int c = to_check.back();
    to_check.pop_back();
    if (is_marked[at(c)]) continue;
    bool split = false;
    for_each_counted_path(plans[at(c)], [&](const std::vector<int>& path) {
      if (split) return;
      std::size_t added = 0;
      for (std::size_t i = 0; i + 1 < path.size(); ++i) added += pending[at(edges.find(path[i], path[i + 1]))].size();
      if (added >= 1 && (path.size() - 2) + added > 1) split = true;
    });
    if (split) mark(c);
  }
  return is_marked;
}

// A point of a face (global coordinates) and its weights on the face's vertices.
struct WeightedPoint {
  Vec3 point;
  std::vector<double> weights;
};

// The point face f is cut around: its centroid when that lies strictly inside the kernel of the
// polygon of its corners, else the kernel's centroid; with its mean value coordinates.
WeightedPoint face_point(const Mesh3D& mesh, int f, const std::vector<int>& corners) {
  const auto& loop = mesh.face(f).vertices;
  const LocalPoints p = local_points(mesh, loop);
  const Vec3 n = mesh.face_normal(f);
  const Vec3 u = (p.q[at(corners[1])] - p.q[at(corners[0])]).normalized();
  const Vec3 v = n.cross(u);
  auto flat = [&](const Vec3& x) { return Point2(x.dot(u), x.dot(v)); };
  std::vector<Point2> q, chords;
  for (const Vec3& x : p.q) q.push_back(flat(x));
  for (int c : corners) chords.push_back(q[at(c)]);
  const std::size_t k = chords.size();
  auto strictly_inside = [&](const Point2& c) {
    for (std::size_t i = 0; i < k; ++i) {
      const Point2 d = chords[(i + 1) % k] - chords[i];
      if (!(cross2(d, c - chords[i]) > kernel_margin * d.norm() * p.diameter)) return false;
    }
    return true;
  };
  Point2 c = flat(p.frame.local(mesh.face_centroid(f)));
  if (!strictly_inside(c)) {
    Point2 lo = chords[0], hi = chords[0];
    for (const Point2& x : chords) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    std::vector<Point2> kernel{lo, Point2(hi.x(), lo.y()), hi, Point2(lo.x(), hi.y())};
    for (std::size_t i = 0; i < k && !kernel.empty(); ++i) kernel = clip_left(kernel, chords[i], chords[(i + 1) % k]);
    const auto [kernel_area, kernel_centroid] = area_centroid(kernel);
    const std::string name =
        "face " + std::to_string(f) + " is not star-shaped: it cannot be cut around a point inside it";
    if (kernel.empty()) throw InputError(name + " (no point of it sees its whole boundary: its kernel is empty)");
    if (!(kernel_area > 0.0) || !strictly_inside(kernel_centroid))
      throw InputError(name + " (the points that see its whole boundary form a degenerate region, of relative area " +
                       fmt_number(kernel_area / area_centroid(q).first) + ")");
    c = kernel_centroid;
  }
  return {p.frame.global(c.x() * u + c.y() * v), mean_value_coordinates(q, c)};
}

// A convex polytope as its faces, each a convex polygon counter-clockwise seen from outside.
using Polytope = std::vector<std::vector<Vec3>>;

Polytope box_polytope(const Vec3& lo, const Vec3& hi) {
  auto corner = [&](int b) { return Vec3(b & 1 ? hi.x() : lo.x(), b & 2 ? hi.y() : lo.y(), b & 4 ? hi.z() : lo.z()); };
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  Polytope p;
  for (const auto& f : faces) p.push_back({corner(f[0]), corner(f[1]), corner(f[2]), corner(f[3])});
  return p;
}

// The polytope clipped to the half-space n . (x - a) <= 0, with the cap the plane cuts.
Polytope clip_below(const Polytope& poly, const Vec3& n, const Vec3& a, double scale) {
  const bool cuts = std::any_of(poly.begin(), poly.end(), [&](const std::vector<Vec3>& face) {
    return std::any_of(face.begin(), face.end(), [&](const Vec3& p) { return n.dot(p - a) > 0.0; });
  });
  if (!cuts) return poly;  // nothing outside (the plane may hold a face: no cap)
  Polytope out;
  std::vector<Vec3> cap;
  for (const auto& face : poly) {
    std::vector<Vec3> kept;
    const std::size_t m = face.size();
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3& p = face[i];
      const Vec3& r = face[(i + 1) % m];
      const double sp = n.dot(p - a), sr = n.dot(r - a);
      if (sp <= 0.0) kept.push_back(p);
      if (sp == 0.0) cap.push_back(p);
      if ((sp > 0.0 && sr < 0.0) || (sp < 0.0 && sr > 0.0)) {
        kept.push_back(p + (sp / (sp - sr)) * (r - p));
        cap.push_back(kept.back());
      }
    }
    if (kept.size() >= 3) out.push_back(std::move(kept));
  }
  // the cap: its distinct points, in order around their mean (counter-clockwise seen along n)
  std::vector<Vec3> distinct;
  for (const Vec3& p : cap)
    if (std::none_of(distinct.begin(), distinct.end(), [&](const Vec3& q) { return (p - q).norm() <= 1e-13 * scale; }))
      distinct.push_back(p);
  if (distinct.size() >= 3) {
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : distinct) mean += p;
    mean /= static_cast<double>(distinct.size());
    const Vec3 u = n.unitOrthogonal();
    const Vec3 v = n.normalized().cross(u);
    std::sort(distinct.begin(), distinct.end(), [&](const Vec3& p, const Vec3& q) {
      return std::atan2((p - mean).dot(v), (p - mean).dot(u)) < std::atan2((q - mean).dot(v), (q - mean).dot(u));
    });
    out.push_back(std::move(distinct));
  }
  return out;
}

// Volume and centroid of a closed polytope (cones from its vertex mean).
std::pair<double, Vec3> volume_centroid(const Polytope& poly) {
  Vec3 o = Vec3::Zero();
  std::size_t count = 0;
  for (const auto& face : poly)
    for (const Vec3& p : face) {
      o += p;
      ++count;
    }
  if (count == 0) return {0.0, Vec3::Zero()};
  o /= static_cast<double>(count);
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (const auto& face : poly)
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const Vec3 a = face[0] - o, b = face[i] - o, c = face[i + 1] - o;
      const double v = a.cross(b).dot(c) / 6.0;
      volume += v;
      moment += v * (a + b + c) / 4.0;
    }
  if (!(volume > 0.0)) return {0.0, o};
  return {volume, o + moment / volume};
}

// The point cell c is split around: its centroid when that lies strictly inside the cell's
// kernel, else the kernel's centroid; with the least-norm affine weights on its vertices.
WeightedPoint cell_point(const Mesh3D& mesh, int c, bool added_by_rule) {
  const auto& cv = mesh.cell_vertices(c);
  const LocalPoints p = local_points(mesh, cv);
  const auto& ids = mesh.cell_faces(c);
  std::vector<Vec3> normals, points;  // outward unit normal and a point of each face
  for (int f : ids) {
    normals.push_back(mesh.face(f).inner == c ? mesh.face_normal(f) : Vec3(-mesh.face_normal(f)));
    points.push_back(p.frame.local(mesh.vertex(mesh.face(f).vertices.front())));
  }
  auto strictly_inside = [&](const Vec3& x) {
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (!(normals[k].dot(x - points[k]) < -kernel_margin * p.diameter)) return false;
    return true;
  };
  Vec3 x = p.frame.local(mesh.centroid(c));
  if (!strictly_inside(x)) {
    Vec3 lo = p.q.front(), hi = lo;
    for (const Vec3& q : p.q) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    Polytope kernel = box_polytope(lo, hi);
    for (std::size_t k = 0; k < ids.size() && !kernel.empty(); ++k)
      kernel = clip_below(kernel, normals[k], points[k], p.diameter);
    const auto [kernel_volume, kernel_centroid] = volume_centroid(kernel);
    const std::string name =
        "cell " + std::to_string(c) + " is not star-shaped: it cannot be split around an interior point";
    const std::string why = added_by_rule ? " (it is split because the one-hanging-vertex rule requires it)" : "";
    if (kernel.empty() || !(kernel_volume > 0.0))
      throw InputError(name + " (no point of it sees its whole boundary: its kernel is empty)" + why);
    if (!strictly_inside(kernel_centroid))
      throw InputError(name + " (the points that see its whole boundary form a degenerate region, of relative volume " +
                       fmt_number(kernel_volume / std::ldexp(mesh.volume(c), -3 * p.frame.exponent)) + ")" + why);
    x = kernel_centroid;
  }
  // least-norm affine weights: w_i = 1/n + (q_i - qbar)^T M^-1 (x - qbar)
  const std::size_t n = p.q.size();
  Vec3 mean = Vec3::Zero();
  for (const Vec3& q : p.q) mean += q;
  mean /= static_cast<double>(n);
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (const Vec3& q : p.q) M += (q - mean) * (q - mean).transpose();
  const Vec3 y = M.ldlt().solve(x - mean);
  std::vector<double> weights(n);
  for (std::size_t i = 0; i < n; ++i) weights[i] = 1.0 / static_cast<double>(n) + (p.q[i] - mean).dot(y);
  return {p.frame.global(x), std::move(weights)};
}

// The vertices of a refinement: the old ones, then per split cell its side midpoints not made
// before, its face points not made before and its interior point; with the prolongation's rows.
struct NewVertices {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Triplet<double>> rows;
  std::vector<std::vector<std::pair<double, int>>> cut;  // per edge: (t from its lower end, vertex), sorted by t
  std::vector<int> face_point;                           // per parent face: the point it is cut around, or -1
  std::vector<int> cell_point;                           // per parent cell: its interior point, or -1

  int add(const Vec3& p) {
    vertices.push_back(p);
    return static_cast<int>(vertices.size()) - 1;
  }
  // the vertex cut on edge g at t (made already)
  int on_edge(int g, double t) const {
    for (const auto& [s, v] : cut[at(g)])
      if (std::abs(s - t) <= midpoint_tolerance) return v;
    throw InternalError("refine_mesh: a point cut on an edge was not made");
  }
  // the vertex a midpoint plan names
  int midpoint(const Midpoint& m) const { return m.reuse >= 0 ? m.reuse : on_edge(m.edge, m.t); }
  // the vertex cut on edge g at t: the one there, or a new one
  int cut_edge(const Mesh3D& mesh, const EdgeTable& edges, int g, double t) {
    auto& on = cut[at(g)];
    for (const auto& [s, v] : on)
      if (std::abs(s - t) <= midpoint_tolerance) return v;
    const auto& e = edges.ends[at(g)];
    const int id = add((1.0 - t) * mesh.vertex(e[0]) + t * mesh.vertex(e[1]));
    rows.emplace_back(id, e[0], 1.0 - t);
    rows.emplace_back(id, e[1], t);
    on.emplace_back(t, id);
    return id;
  }
};

NewVertices new_vertices(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<CellPlan>& plans,
                         const std::vector<std::vector<int>>& face_corners, const FoldedPairs& folded,
                         const std::vector<char>& is_marked, const std::vector<char>& asked) {
  const int nv = mesh.num_vertices();
  NewVertices out;
  out.vertices = mesh.vertices();
  out.rows.reserve(at(nv) + 16 * at(mesh.num_cells()));
  for (int v = 0; v < nv; ++v) out.rows.emplace_back(v, v, 1.0);
  out.cut.resize(edges.ends.size());
  out.face_point.assign(at(mesh.num_faces()), -1);
  out.cell_point.assign(at(mesh.num_cells()), -1);
  for (int c = 0; c < mesh.num_cells(); ++c) {
    if (!is_marked[at(c)]) continue;
    const CellPlan& plan = plans[at(c)];
    for (const Side& s : plan.sides)
      if (s.mid.reuse < 0) out.cut_edge(mesh, edges, s.mid.edge, s.mid.t);
    const WeightedPoint centre = cell_point(mesh, c, !asked[at(c)]);
    for (const GeoFace& g : plan.faces) {
      if (g.pieces()) continue;
      const int f = mesh.cell_faces(c)[at(plan.units[at(g.units.front())].faces.front())];
      if (out.face_point[at(f)] >= 0) continue;
      if (folded.partner[at(f)] >= 0) {
        // a folded pair: the midpoint of its diagonal
        const int id = out.cut_edge(mesh, edges, folded.diagonal[at(f)], 0.5);
        out.face_point[at(f)] = out.face_point[at(folded.partner[at(f)])] = id;
        continue;
      }
      const WeightedPoint p = face_point(mesh, f, face_corners[at(f)]);
      const int id = out.add(p.point);
      const auto& loop = mesh.face(f).vertices;
      for (std::size_t i = 0; i < loop.size(); ++i) out.rows.emplace_back(id, loop[i], p.weights[i]);
      out.face_point[at(f)] = id;
    }
    const int id = out.add(centre.point);
    const auto& cv = mesh.cell_vertices(c);
    for (std::size_t i = 0; i < cv.size(); ++i) out.rows.emplace_back(id, cv[i], centre.weights[i]);
    out.cell_point[at(c)] = id;
  }
  for (auto& on_edge : out.cut) std::sort(on_edge.begin(), on_edge.end());
  return out;
}

// Appends to `out` the vertices of `path` (open) or `loop` (closed) with the points cut on its
// edges spliced in; `positions` (when given) receives where each of its vertices went.
void splice(const EdgeTable& edges, const NewVertices& made, const std::vector<int>& vertices, bool closed,
            std::vector<int>& out, std::vector<int>* positions = nullptr) {
  const std::size_t n = vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (positions != nullptr) positions->push_back(static_cast<int>(out.size()));
    out.push_back(vertices[i]);
    if (!closed && i + 1 == n) break;
    const int a = vertices[i], b = vertices[(i + 1) % n];
    const int g = edges.find(a, b);
    if (g < 0) continue;
    const auto& on_edge = made.cut[at(g)];
    if (edges.ends[at(g)][0] == a) {
      for (const auto& p : on_edge) out.push_back(p.second);
    } else {
      for (auto it = on_edge.rbegin(); it != on_edge.rend(); ++it) out.push_back(it->second);
    }
  }
}

// The polygons a parent face becomes, in its own orientation: the face with the points cut on
// its edges, or, when it has a face point, its pieces, one per corner (`corner` the vertex of
// each). The pieces of a folded pair are cut from the pair's loop; the piece of a corner at an
// end of the diagonal lies on both faces and is cut along the segment from the corner to the
// face point, each face keeping its part.
struct FacePolygons {
  std::vector<std::vector<int>> polygons;
  std::vector<int> corner;
};

FacePolygons face_polygons(const Mesh3D& mesh, const EdgeTable& edges, const NewVertices& made,
                           const std::vector<std::vector<int>>& face_corners, const FoldedPairs& folded, int f) {
  const auto& face_loop = mesh.face(f).vertices;
  FacePolygons out;
  const int centre = made.face_point[at(f)];
  if (centre < 0) {
    out.polygons.emplace_back();
    splice(edges, made, face_loop, true, out.polygons.back());
    return out;
  }
  // the loop cut into pieces, and its corners (positions)
  std::vector<int> loop;
  std::vector<int> corners;
  const int other = folded.partner[at(f)];
  if (other < 0) {
    loop = face_loop;
    corners = face_corners[at(f)];
  } else {
    std::vector<int> second = mesh.face(other).vertices;
    if (mesh.face(other).inner != mesh.face(f).inner) std::reverse(second.begin(), second.end());
    const auto& e = edges.ends[at(folded.diagonal[at(f)])];
    loop = joined_loop(face_loop, second, e[0], e[1]);
    const auto& fc = folded.corners[at(f)];
    for (std::size_t i = 0; i < loop.size(); ++i)
      if (std::binary_search(fc.begin(), fc.end(), loop[i])) corners.push_back(static_cast<int>(i));
  }
  std::vector<int> polygon, position;
  splice(edges, made, loop, true, polygon, &position);
  const int m = static_cast<int>(polygon.size());
  const std::size_t k = corners.size();
  std::vector<int> corner_at(k), mid_at(k);
  std::vector<char> in_face(k, 1);  // per side: whether it lies on face f
  for (std::size_t s = 0; s < k; ++s) {
    const int c0 = corners[s], c1 = corners[(s + 1) % k];
    const int mid = made.midpoint(plan_midpoint(mesh, edges, loop_path(loop, c0, c1)));
    corner_at[s] = position[at(c0)];
    int i = corner_at[s], steps = 0;
    while (polygon[at(i)] != mid && ++steps < m) i = (i + 1) % m;
    if (steps == m)
      throw InternalError("refine_mesh: the midpoint of a side of face " + std::to_string(f) + " is not on it");
    mid_at[s] = i;
    if (other >= 0) {
      const int a = loop[at(c0)], b = loop[at((c0 + 1) % static_cast<int>(loop.size()))];
      const int pa = position_in(face_loop, a);
      in_face[s] = pa >= 0 && face_loop[at((pa + 1) % static_cast<int>(face_loop.size()))] == b;
    }
  }
  for (std::size_t s = 0; s < k; ++s) {
    const std::size_t before = (s + k - 1) % k;
    std::vector<int> ahead, behind;  // corner ... side midpoint, and previous side midpoint ... before the corner
    for (int i = corner_at[s];; i = (i + 1) % m) {
      ahead.push_back(polygon[at(i)]);
      if (i == mid_at[s]) break;
    }
    for (int i = mid_at[before]; i != corner_at[s]; i = (i + 1) % m) behind.push_back(polygon[at(i)]);
    const int corner = loop[at(corners[s])];
    if (in_face[s] && in_face[before]) {
      std::vector<int> piece = ahead;
      piece.push_back(centre);
      piece.insert(piece.end(), behind.begin(), behind.end());
      out.polygons.push_back(std::move(piece));
      out.corner.push_back(corner);
    } else if (in_face[s]) {
      ahead.push_back(centre);
      out.polygons.push_back(std::move(ahead));
      out.corner.push_back(corner);
    } else if (in_face[before]) {
      std::vector<int> part{centre};
      part.insert(part.end(), behind.begin(), behind.end());
      part.push_back(corner);
      out.polygons.push_back(std::move(part));
      out.corner.push_back(corner);
    }
  }
  return out;
}

// The cells of a refinement with their regions and parents, and the parent face of each of
// their face loops (-1 inside a split cell).
struct ChildCells {
  std::vector<CellFaces> cells;
  std::vector<std::vector<int>> loop_parent;
  std::vector<int> regions, parent_cell;
};

// True when the points lie on one plane within fold_tolerance of their diameter.
bool coplanar(const std::vector<Vec3>& points) {
  std::vector<Vec3> p;
  for (const Vec3& x : points) p.push_back(x - points.front());
  const double d = diameter_of(p);
  const int e = d > 0.0 ? std::ilogb(d) : 0;
  for (Vec3& x : p) x = Vec3(std::ldexp(x.x(), -e), std::ldexp(x.y(), -e), std::ldexp(x.z(), -e));
  const Vec3 area = polygon_area_vector(p);
  const double a = area.norm();
  if (!(a > 0.0)) return false;
  const Vec3 n = area / a;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& x : p) mean += x;
  mean /= static_cast<double>(p.size());
  const double scale = std::ldexp(d, -e);
  return std::all_of(p.begin(), p.end(),
                     [&](const Vec3& x) { return std::abs(n.dot(x - mean)) <= fold_tolerance * scale; });
}

// The children of split cell c, one per corner in increasing vertex id: the pieces of its faces
// at the corner and the interior faces of the sides at the corner.
void split_cell(const Mesh3D& mesh, const EdgeTable& edges, int c, const CellPlan& plan, const NewVertices& made,
                const std::vector<FacePolygons>& polygons, ChildCells& out) {
  const auto& ids = mesh.cell_faces(c);
  const std::size_t first = out.cells.size();
  const std::size_t k = plan.corners.size();
  out.cells.resize(first + k);
  out.loop_parent.resize(first + k);
  for (std::size_t i = 0; i < k; ++i) {
    out.regions.push_back(mesh.region(c));
    out.parent_cell.push_back(c);
  }
  auto child = [&](int corner) {
    const auto it = std::lower_bound(plan.corners.begin(), plan.corners.end(), corner);
    if (it == plan.corners.end() || *it != corner)
      throw InternalError("refine_mesh: vertex " + std::to_string(corner) + " is not a corner of cell " +
                          std::to_string(c));
    return first + static_cast<std::size_t>(it - plan.corners.begin());
  };
  auto add = [&](std::size_t to, std::vector<int> loop, bool reversed, int parent) {
    if (reversed) std::reverse(loop.begin(), loop.end());
    out.cells[to].push_back(std::move(loop));
    out.loop_parent[to].push_back(parent);
  };
  // the pieces of the cell's faces, each to the child of the corner it holds
  for (const GeoFace& g : plan.faces) {
    if (!g.pieces()) {
      for (int local : plan.units[at(g.units.front())].faces) {
        const int f = ids[at(local)];
        const FacePolygons& fp = polygons[at(f)];
        for (std::size_t s = 0; s < fp.polygons.size(); ++s)
          add(child(fp.corner[s]), fp.polygons[s], plan.flipped[at(local)], f);
      }
      continue;
    }
    for (std::size_t s = 0; s < g.corners.size(); ++s)
      for (int local : plan.units[at(g.piece[s])].faces) {
        const int f = ids[at(local)];
        for (const auto& polygon : polygons[at(f)].polygons)
          add(child(g.loop[at(g.corners[s])]), polygon, plan.flipped[at(local)], f);
      }
  }
  // the interior faces, one per side, outward from the child of the side's first corner: the
  // side's midpoint, one face point, the interior point, the other face point; two triangles
  // along the segment from the midpoint to the interior point when these are not coplanar
  const int x = made.cell_point[at(c)];
  auto face_centre = [&](const GeoFace& g) {
    return g.pieces() ? g.centre : made.face_point[at(ids[at(plan.units[at(g.units.front())].faces.front())])];
  };
  for (const Side& s : plan.sides) {
    const int mid = made.midpoint(s.mid);
    const GeoFace& g_out = plan.faces[at(s.out)];
    const GeoFace& g_in = plan.faces[at(s.in)];
    const int c_out = face_centre(g_out), c_in = face_centre(g_in);
    std::vector<int> to_in = g_in.pieces() ? g_in.spokes[at(s.in_side)] : std::vector<int>{mid, c_in};
    std::vector<int> from_out = g_out.pieces() ? g_out.spokes[at(s.out_side)] : std::vector<int>{mid, c_out};
    std::reverse(from_out.begin(), from_out.end());
    std::vector<int> half_in, half_out;  // mid ... c_in and c_out ... mid, with the cut points
    splice(edges, made, to_in, false, half_in);
    splice(edges, made, from_out, false, half_out);
    const std::size_t a = child(s.path.front()), b = child(s.path.back());
    if (coplanar({made.vertices[at(mid)], made.vertices[at(c_in)], made.vertices[at(x)], made.vertices[at(c_out)]})) {
      std::vector<int> loop = half_in;
      loop.push_back(x);
      loop.insert(loop.end(), half_out.begin(), half_out.end() - 1);
      add(a, loop, false, -1);
      add(b, loop, true, -1);
    } else {
      std::vector<int> first = half_in;
      first.push_back(x);
      std::vector<int> second{x};
      second.insert(second.end(), half_out.begin(), half_out.end());
      add(a, first, false, -1);
      add(b, first, true, -1);
      add(a, second, false, -1);
      add(b, second, true, -1);
    }
  }
}

// The cells of the refinement in the parent's order: a cell that is not split with the
// polygons its faces became, a split one replaced by its children.
ChildCells child_cells(const Mesh3D& mesh, const EdgeTable& edges, const std::vector<CellPlan>& plans,
                       const std::vector<char>& is_marked, const NewVertices& made,
                       const std::vector<FacePolygons>& polygons) {
  ChildCells out;
  out.cells.reserve(at(mesh.num_cells()));
  for (int c = 0; c < mesh.num_cells(); ++c) {
    if (is_marked[at(c)]) {
      split_cell(mesh, edges, c, plans[at(c)], made, polygons, out);
      continue;
    }
    CellFaces cell;
    std::vector<int> parents;
    for (int f : mesh.cell_faces(c)) {
      const bool reversed = mesh.face(f).inner != c;
      for (std::vector<int> polygon : polygons[at(f)].polygons) {
        if (reversed) std::reverse(polygon.begin(), polygon.end());
        cell.push_back(std::move(polygon));
        parents.push_back(f);
      }
    }
    out.cells.push_back(std::move(cell));
    out.loop_parent.push_back(std::move(parents));
    out.regions.push_back(mesh.region(c));
    out.parent_cell.push_back(c);
  }
  return out;
}

}  // namespace

RefinedMesh3D refine_mesh(const Mesh3D& mesh, std::span<const int> marked) {
  const int nc = mesh.num_cells();
  const int nv = mesh.num_vertices();
  for (int c : marked)
    if (c < 0 || c >= nc)
      throw InputError("marked cell id " + std::to_string(c) + " is out of range [0, " + std::to_string(nc) + ")");

  // the new vertices and the children's faces, made from the corners of every face, the
  // geometric faces and sides of every cell and the closure; what they are made from is given
  // back before the refined mesh is built, whose construction is the refinement's peak
  std::vector<char> is_marked;
  NewVertices made;
  ChildCells children;
  {
    const EdgeTable edges = edge_table(mesh);
    std::vector<std::vector<int>> face_corners(at(mesh.num_faces()));
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const LocalPoints p = local_points(mesh, mesh.face(f).vertices);
      face_corners[at(f)] = loop_corners(p.q, p.diameter);
    }
    const FoldedPairs folded = folded_pairs(mesh, edges, face_corners);
    std::vector<CellPlan> plans;
    plans.reserve(at(nc));
    for (int c = 0; c < nc; ++c) plans.push_back(plan_cell(mesh, edges, face_corners, folded, c));
    is_marked = close_marked_set(mesh, edges, plans, marked);
    std::vector<char> asked(at(nc), 0);
    for (int c : marked) asked[at(c)] = 1;
    for (int c = 0; c < nc; ++c)
      if (is_marked[at(c)] && !plans[at(c)].defect.empty())
        throw InputError("cell " + std::to_string(c) + " cannot be split: " + plans[at(c)].defect +
                         (asked[at(c)] ? "" : " (it is split because the one-hanging-vertex rule requires it)"));

    made = new_vertices(mesh, edges, plans, face_corners, folded, is_marked, asked);
    std::vector<FacePolygons> polygons;
    polygons.reserve(at(mesh.num_faces()));
    for (int f = 0; f < mesh.num_faces(); ++f)
      polygons.push_back(face_polygons(mesh, edges, made, face_corners, folded, f));
    children = child_cells(mesh, edges, plans, is_marked, made, polygons);
  }
  decltype(made.cut)().swap(made.cut);  // of the new vertices, their rows alone are read below

  RefinedMesh3D out;
  try {
    out.mesh = Mesh3D(std::move(made.vertices), std::move(children.cells), std::move(children.regions));
  } catch (const MeshError& error) {
    const int parent = error.element() >= 0 ? children.parent_cell[at(error.element())] : -1;
    throw MeshError((parent >= 0 ? "refining cell " + std::to_string(parent) : std::string("refining the mesh")) +
                        " gives an invalid mesh: " + error.what(),
                    parent);
  }

  // the parent face of each face, and the face groups
  out.parent_face.assign(at(out.mesh.num_faces()), -1);
  for (int c = 0; c < out.mesh.num_cells(); ++c) {
    const auto& faces = out.mesh.cell_faces(c);
    for (std::size_t l = 0; l < faces.size(); ++l) out.parent_face[at(faces[l])] = children.loop_parent[at(c)][l];
  }
  if (!mesh.face_groups().empty()) {
    std::vector<int> start(at(mesh.num_faces()) + 1, 0), pieces(out.parent_face.size());
    for (int p : out.parent_face)
      if (p >= 0) ++start[at(p) + 1];
    for (std::size_t f = 0; f < at(mesh.num_faces()); ++f) start[f + 1] += start[f];
    std::vector<int> next(start.begin(), start.end() - 1);
    for (int f = 0; f < out.mesh.num_faces(); ++f)
      if (out.parent_face[at(f)] >= 0) pieces[at(next[at(out.parent_face[at(f)])]++)] = f;
    for (const auto& [name, group] : mesh.face_groups()) {
      std::vector<int> children_faces;
      for (int f : group)
        children_faces.insert(children_faces.end(), pieces.begin() + start[at(f)], pieces.begin() + start[at(f) + 1]);
      out.mesh.set_face_group(name, std::move(children_faces));
    }
  }
  out.parent_cell = std::move(children.parent_cell);
  out.prolongation.resize(out.mesh.num_vertices(), nv);
  out.prolongation.setFromTriplets(made.rows.begin(), made.rows.end());
  for (int c = 0; c < nc; ++c)
    if (is_marked[at(c)]) out.refined.push_back(c);
  return out;
}

RefinedMesh3D refine_uniformly(const Mesh3D& mesh) {
  std::vector<int> all(at(mesh.num_cells()));
  std::iota(all.begin(), all.end(), 0);
  return refine_mesh(mesh, all);
}

Eigen::VectorXd prolongate(const RefinedMesh3D& refined, const Eigen::VectorXd& parent_values) {
  const Eigen::Index parent_vertices = refined.prolongation.cols();
  if (parent_values.size() != 3 * parent_vertices)
    throw InputError("the parent nodal vector has " + std::to_string(parent_values.size()) +
                     " entries; the parent mesh has " + std::to_string(parent_vertices) + " vertices, so it needs " +
                     std::to_string(3 * parent_vertices));
  using Nodal = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  const Eigen::Map<const Nodal> parent(parent_values.data(), parent_vertices, 3);
  Eigen::VectorXd out(3 * refined.prolongation.rows());
  Eigen::Map<Nodal>(out.data(), refined.prolongation.rows(), 3) = refined.prolongation * parent;
  return out;
}

}  // namespace hemivem
