#include <hemivem/mesh/interface3d.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace hemivem {

namespace {

using Vec2d = Eigen::Vector2d;

constexpr double largest_tolerance = 0.1;
// How far (relative to an edge's length or a face's size) a point inserted into it may lie off
// it and keep its coordinates; farther, it is projected onto it.
constexpr double straight_tolerance = 1e-11;
constexpr double no_distance = std::numeric_limits<double>::infinity();

// x with the fewest of 15, 16 or 17 significant digits that read back as x.
std::string number_text(double x) {
  std::string text;
  for (int digits = 15; digits <= 17; ++digits) {
    std::ostringstream out;
    out.precision(digits);
    out << x;
    text = out.str();
    if (!std::isfinite(x) || std::strtod(text.c_str(), nullptr) == x) break;
  }
  return text;
}

std::string point_text(const Vec3& p) {
  return "(" + number_text(p.x()) + ", " + number_text(p.y()) + ", " + number_text(p.z()) + ")";
}

std::uint64_t pair_key(int lo, int hi) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(lo)) << 32) | static_cast<std::uint32_t>(hi);
}

double cross2(const Vec2d& a, const Vec2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// The distance from p to segment [a, b] and the parameter of its nearest point (0 at a, 1 at b).
std::pair<double, double> segment_distance(const Vec2d& p, const Vec2d& a, const Vec2d& b) {
  const Vec2d along = b - a;
  const double length2 = along.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp(along.dot(p - a) / length2, 0.0, 1.0) : 0.0;
  const Vec2d foot = a + t * along;
  return {(p - foot).norm(), t};
}

// The signed distance of p from the line through a and b, positive on its left.
double signed_distance(const Vec2d& p, const Vec2d& a, const Vec2d& b) {
  const double length = (b - a).norm();
  return length > 0.0 ? cross2(b - a, p - a) / length : (p - a).norm();
}

// An axis-aligned rectangle of the interface's plane.
struct Box2 {
  Vec2d lo{no_distance, no_distance}, hi{-no_distance, -no_distance};
  void add(const Vec2d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool meets(const Box2& o) const {
    return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y();
  }
};

// Items given by their boxes, bucketed on a uniform grid over the union of the boxes, about one
// item per bucket.
class Grid {
 public:
  Grid() = default;
  explicit Grid(std::vector<Box2> boxes) : boxes_(std::move(boxes)) {
    for (const Box2& b : boxes_) {
      region_.add(b.lo);
      region_.add(b.hi);
    }
    const Vec2d size = region_.hi - region_.lo;
    const double count = static_cast<double>(std::max<std::size_t>(boxes_.size(), 1));
    cell_ = std::max(std::sqrt(size.x() * size.y() / count), size.maxCoeff() / max_cells);
    if (!(cell_ > 0.0) || !std::isfinite(cell_)) cell_ = 1.0;
    nx_ = static_cast<int>(std::clamp(std::ceil(size.x() / cell_), 1.0, max_cells));
    ny_ = static_cast<int>(std::clamp(std::ceil(size.y() / cell_), 1.0, max_cells));
    buckets_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), {});
    for (std::size_t k = 0; k < boxes_.size(); ++k) {
      const auto [x0, y0, x1, y1] = cells(boxes_[k]);
      for (int j = y0; j <= y1; ++j)
        for (int i = x0; i <= x1; ++i) buckets_[bucket(i, j)].push_back(static_cast<int>(k));
    }
  }
  // The items whose boxes meet `query`, increasing.
  std::vector<int> near(const Box2& query) const {
    std::vector<int> out;
    if (boxes_.empty() || !query.meets(region_)) return out;
    const auto [x0, y0, x1, y1] = cells(query);
    for (int j = y0; j <= y1; ++j)
      for (int i = x0; i <= x1; ++i)
        for (int k : buckets_[bucket(i, j)])
          if (boxes_[static_cast<std::size_t>(k)].meets(query)) out.push_back(k);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  static constexpr double max_cells = 4096.0;
  std::size_t bucket(int i, int j) const { return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i); }
  int index(double x, double origin, int n) const {
    const double k = std::floor((x - origin) / cell_);
    return static_cast<int>(std::clamp(k, 0.0, static_cast<double>(n - 1)));
  }
  std::array<int, 4> cells(const Box2& b) const {
    return {index(b.lo.x(), region_.lo.x(), nx_), index(b.lo.y(), region_.lo.y(), ny_),
            index(b.hi.x(), region_.lo.x(), nx_), index(b.hi.y(), region_.lo.y(), ny_)};
  }
  std::vector<Box2> boxes_;
  Box2 region_;
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> buckets_;
};

// An orthonormal frame of the interface's plane: coordinates (u, v) in it, and the distance off
// it along the normal (u x v = normal).
struct Frame {
  Vec3 origin = Vec3::Zero(), normal = Vec3::UnitZ(), u = Vec3::UnitX(), v = Vec3::UnitY();
  Vec2d at(const Vec3& x) const { return {(x - origin).dot(u), (x - origin).dot(v)}; }
  double off(const Vec3& x) const { return (x - origin).dot(normal); }
};

// The boundary faces `ids` of `mesh`, sorted, each once.
std::vector<int> checked_faces(const Mesh3D& mesh, std::vector<int> ids, const std::string& side) {
  const std::string of = " of the " + side + " mesh";
  if (ids.empty()) throw InputError("the interface" + of + " has no faces; give the ids of its boundary faces");
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (int f : ids) {
    if (f < 0 || f >= mesh.num_faces())
      throw InputError("interface face id " + std::to_string(f) + of + " is out of range [0, " +
                       std::to_string(mesh.num_faces()) + ")");
    const MeshFace& face = mesh.face(f);
    if (!face.on_boundary())
      throw InputError("interface face " + std::to_string(f) + of + " is not a boundary face (it lies between cells " +
                       std::to_string(face.inner) + " and " + std::to_string(face.outer) +
                       "); an interface is made of boundary faces");
  }
  return ids;
}

// The plane through the area-weighted centroid of the first side's faces, normal to the sum of
// their area vectors; its frame's first axis is the coordinate axis least aligned with the
// normal (the first on a tie), made orthogonal to it.
Frame interface_frame(const Mesh3D& mesh, const std::vector<int>& faces) {
  Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
  double total = 0.0;
  for (int f : faces) {
    sum += mesh.face_area(f) * mesh.face_normal(f);
    moment += mesh.face_area(f) * mesh.face_centroid(f);
    total += mesh.face_area(f);
  }
  const double length = scale_free_norm(sum);
  if (!(length > 1e-12 * total))
    throw InputError("the interface faces of the first mesh do not lie in a plane: their area vectors cancel (the "
                     "faces enclose a volume or face opposite ways); the interface must be planar");
  Frame frame;
  frame.normal = sum / length;
  frame.origin = moment / total;
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(frame.normal[k]) < std::abs(frame.normal[axis])) axis = k;
  const Vec3 e = Vec3::Unit(axis);
  frame.u = (e - frame.normal.dot(e) * frame.normal).normalized();
  frame.v = frame.normal.cross(frame.u);
  return frame;
}

// The bounding box diagonal of the faces' vertices and their largest coordinate magnitude.
std::pair<double, double> extent(const Mesh3D& mesh, const std::vector<int>& faces) {
  Vec3 lo = Vec3::Constant(no_distance), hi = Vec3::Constant(-no_distance);
  double magnitude = 0.0;
  for (int f : faces)
    for (int v : mesh.face(f).vertices) {
      lo = lo.cwiseMin(mesh.vertex(v));
      hi = hi.cwiseMax(mesh.vertex(v));
      magnitude = std::max(magnitude, mesh.vertex(v).cwiseAbs().maxCoeff());
    }
  return {scale_free_norm(hi - lo), magnitude};
}

// The tolerance and how it came: `relative` times the interface's `size`, at least the round-off.
struct Tolerance {
  double distance = 0.0, relative = 0.0, size = 0.0;
  std::string text() const {
    return "the tolerance " + number_text(distance) + " (" + number_text(relative) + " of the interface's size " +
           number_text(size) + ")";
  }
};

void check_planar(const Mesh3D& mesh, const std::vector<int>& faces, const std::string& side, const Frame& frame,
                  const Tolerance& tol) {
  for (int f : faces)
    for (int v : mesh.face(f).vertices) {
      const double off = std::abs(frame.off(mesh.vertex(v)));
      if (off > tol.distance)
        throw InputError("interface vertex " + std::to_string(v) + " " + point_text(mesh.vertex(v)) + " of the " + side +
                         " mesh (in face " + std::to_string(f) + ") is " + number_text(off) +
                         " off the plane of the interface (through " + point_text(frame.origin) + ", normal " +
                         point_text(frame.normal) + "), more than " + tol.text() +
                         ": the interface must be planar (piecewise-planar interfaces are not supported)");
    }
}

// The first side's faces face along the normal, the second side's against it.
void check_orientation(const Mesh3D& first, const std::vector<int>& first_faces, const Mesh3D& second,
                       const std::vector<int>& second_faces, const Frame& frame) {
  for (int f : first_faces)
    if (!(first.face_normal(f).dot(frame.normal) > 0.0))
      throw InputError("interface face " + std::to_string(f) + " of the first mesh faces the other way (outward normal " +
                       point_text(first.face_normal(f)) + ") from the rest of its interface (normal " +
                       point_text(frame.normal) + "); the faces of one side must all face the other body");
  for (int f : second_faces)
    if (!(second.face_normal(f).dot(frame.normal) < 0.0))
      throw InputError("interface face " + std::to_string(f) + " of the second mesh has the same orientation as the "
                       "interface of the first mesh (outward normal " + point_text(second.face_normal(f)) +
                       ", the first's " + point_text(frame.normal) +
                       "): the two bodies lie on the same side of the interface (they overlap); the outward normals "
                       "of the two sides must be opposite");
}

// One side's interface in the plane: its faces (sorted ids) with their vertex loops (positions
// in `vertices`) counter-clockwise in the frame, its vertices (sorted ids) with their
// coordinates in the frame, its edges (positions of the ends, smaller first, sorted), the faces
// around each vertex and each edge, each face's edges (along its loop) and area, and a grid of
// the faces' boxes (grown by the tolerance).
struct Surface {
  const Mesh3D* mesh = nullptr;
  std::string side;
  std::vector<int> faces;
  std::vector<std::vector<int>> loops, face_edges;
  std::vector<int> vertices;
  std::vector<Vec2d> xy;
  std::vector<std::array<int, 2>> edges;
  std::vector<std::vector<int>> edge_faces, vertex_faces;
  std::vector<double> face_area, face_perimeter;
  Grid grid;
  double tol = 0.0;
};

void add_topology(Surface& s) {
  std::vector<std::uint64_t> keys;
  for (const auto& loop : s.loops)
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      keys.push_back(pair_key(std::min(a, b), std::max(a, b)));
    }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::unordered_map<std::uint64_t, int> edge_of;
  for (const std::uint64_t key : keys) {
    edge_of.emplace(key, static_cast<int>(s.edges.size()));
    s.edges.push_back({static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu)});
  }
  s.edge_faces.assign(s.edges.size(), {});
  s.vertex_faces.assign(s.vertices.size(), {});
  s.face_edges.assign(s.loops.size(), {});
  for (std::size_t f = 0; f < s.loops.size(); ++f) {
    const auto& loop = s.loops[f];
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      const int e = edge_of.at(pair_key(std::min(a, b), std::max(a, b)));
      s.face_edges[f].push_back(e);
      s.edge_faces[static_cast<std::size_t>(e)].push_back(static_cast<int>(f));
      s.vertex_faces[static_cast<std::size_t>(a)].push_back(static_cast<int>(f));
    }
  }
}

// Refuses a face with a vertex farther than the tolerance outside the line of one of its edges.
void check_convex(const Surface& s, std::size_t f, double tol) {
  const auto& loop = s.loops[f];
  const auto& ids = s.vertices;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int a = loop[i], b = loop[(i + 1) % loop.size()];
    for (const int c : loop) {
      const double inside = signed_distance(s.xy[static_cast<std::size_t>(c)], s.xy[static_cast<std::size_t>(a)],
                                            s.xy[static_cast<std::size_t>(b)]);
      if (inside < -tol)
        throw InputError("interface face " + std::to_string(s.faces[f]) + " of the " + s.side +
                         " mesh is not convex: its vertex " + std::to_string(ids[static_cast<std::size_t>(c)]) +
                         " lies " + number_text(-inside) + " outside the line of its edge " +
                         std::to_string(ids[static_cast<std::size_t>(a)]) + " - " +
                         std::to_string(ids[static_cast<std::size_t>(b)]) +
                         "; interface faces must be convex (split the face into convex ones)");
    }
  }
}

// The interface `faces` of `mesh` in the plane; the second side's loops are reversed, so that
// both sides' loops run counter-clockwise in the frame.
Surface make_surface(const Mesh3D& mesh, std::vector<int> faces, const std::string& side, const Frame& frame, double tol) {
  Surface s;
  s.mesh = &mesh;
  s.side = side;
  s.tol = tol;
  s.faces = std::move(faces);
  for (int f : s.faces) s.vertices.insert(s.vertices.end(), mesh.face(f).vertices.begin(), mesh.face(f).vertices.end());
  std::sort(s.vertices.begin(), s.vertices.end());
  s.vertices.erase(std::unique(s.vertices.begin(), s.vertices.end()), s.vertices.end());
  std::unordered_map<int, int> position;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    position.emplace(s.vertices[i], static_cast<int>(i));
    s.xy.push_back(frame.at(mesh.vertex(s.vertices[i])));
  }
  std::vector<Box2> boxes;
  for (int f : s.faces) {
    std::vector<int> loop;
    for (int v : mesh.face(f).vertices) loop.push_back(position.at(v));
    if (side == "second") std::reverse(loop.begin(), loop.end());
    double area = 0.0, perimeter = 0.0;
    Box2 box;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Vec2d& a = s.xy[static_cast<std::size_t>(loop[i])];
      const Vec2d& b = s.xy[static_cast<std::size_t>(loop[(i + 1) % loop.size()])];
      area += 0.5 * cross2(a - s.xy[static_cast<std::size_t>(loop[0])], b - s.xy[static_cast<std::size_t>(loop[0])]);
      perimeter += (b - a).norm();
      box.add(a);
    }
    box.lo -= Vec2d::Constant(tol);
    box.hi += Vec2d::Constant(tol);
    boxes.push_back(box);
    s.loops.push_back(std::move(loop));
    s.face_area.push_back(area);
    s.face_perimeter.push_back(perimeter);
    check_convex(s, s.loops.size() - 1, tol);
  }
  s.grid = Grid(std::move(boxes));
  add_topology(s);
  return s;
}

// Where a point lies on one side's interface: at a vertex, inside an edge (at parameter t from
// its smaller end) or inside a face (positions in the Surface).
enum class Kind { vertex, edge, face };
struct Place {
  Kind kind = Kind::face;
  int index = -1;
  double t = 0.0;
};

// A point of the overlay: its coordinates in the plane, its place on each side, the coordinates
// of a vertex made for it, and its vertex id in each matched mesh.
struct Point {
  Vec2d xy;
  Vec3 x;
  std::array<Place, 2> place;
  std::array<int, 2> id{-1, -1};
};

// The distance from p to the interface of s (to its nearest edge), for the message of a point
// outside it.
double distance_to(const Surface& s, const Vec2d& p) {
  double best = no_distance;
  for (const auto& e : s.edges)
    best = std::min(best, segment_distance(p, s.xy[static_cast<std::size_t>(e[0])], s.xy[static_cast<std::size_t>(e[1])]).first);
  return best;
}

// The vertex of s within the tolerance of p (-1 when none); InputError naming `what` when two are.
int nearby_vertex(const Surface& s, const std::vector<int>& near, const Vec2d& p, double tol, const std::string& what) {
  std::vector<int> found;
  for (int f : near)
    for (int v : s.loops[static_cast<std::size_t>(f)])
      if ((s.xy[static_cast<std::size_t>(v)] - p).norm() <= tol) found.push_back(v);
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  if (found.size() > 1)
    throw InputError(what + " is within the tolerance " + number_text(tol) + " of two interface vertices of the " + s.side +
                     " mesh (" + std::to_string(s.vertices[static_cast<std::size_t>(found[0])]) + " and " +
                     std::to_string(s.vertices[static_cast<std::size_t>(found[1])]) +
                     "); each vertex can pair with one only: use a smaller tolerance");
  return found.empty() ? -1 : found.front();
}

// The edges of s within the tolerance of p: (distance, edge, parameter), nearest first.
std::vector<std::tuple<double, int, double>> nearby_edges(const Surface& s, const std::vector<int>& near, const Vec2d& p,
                                                          double tol) {
  std::vector<std::tuple<double, int, double>> found;
  for (int f : near)
    for (int e : s.face_edges[static_cast<std::size_t>(f)]) {
      const auto& ends = s.edges[static_cast<std::size_t>(e)];
      const auto [d, t] = segment_distance(p, s.xy[static_cast<std::size_t>(ends[0])], s.xy[static_cast<std::size_t>(ends[1])]);
      if (d <= tol) found.emplace_back(d, e, t);
    }
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  return found;
}

// The vertex that two of `edges` share (-1 when none); InputError naming `what` when two such
// vertices are.
int shared_vertex(const Surface& s, const std::vector<std::tuple<double, int, double>>& edges, const std::string& what,
                  double tol) {
  std::vector<int> ends, shared;
  for (const auto& [d, e, t] : edges)
    for (int v : s.edges[static_cast<std::size_t>(e)]) ends.push_back(v);
  std::sort(ends.begin(), ends.end());
  for (std::size_t i = 0; i + 1 < ends.size(); ++i)
    if (ends[i] == ends[i + 1] && (shared.empty() || shared.back() != ends[i])) shared.push_back(ends[i]);
  if (shared.size() > 1)
    throw InputError(what + " is within the tolerance " + number_text(tol) + " of interface edges of the " + s.side +
                     " mesh around two of its vertices (" + std::to_string(s.vertices[static_cast<std::size_t>(shared[0])]) +
                     " and " + std::to_string(s.vertices[static_cast<std::size_t>(shared[1])]) +
                     "); each vertex can pair with one only: use a smaller tolerance");
  return shared.empty() ? -1 : shared.front();
}

// The place on s of point p (described by `what` in messages): a vertex within the tolerance,
// or the vertex that two edges within the tolerance share (a point in both edges' reach is at
// their common end); else the nearest edge within the tolerance (the first on a tie); else the
// face holding it.
Place locate(const Surface& s, const Vec2d& p, const Tolerance& tol, const std::string& what) {
  Box2 at;
  at.add(p);
  const std::vector<int> near = s.grid.near(at);
  int vertex = nearby_vertex(s, near, p, tol.distance, what);
  const auto edges = nearby_edges(s, near, p, tol.distance);
  if (vertex < 0 && edges.size() > 1) vertex = shared_vertex(s, edges, what, tol.distance);
  if (vertex >= 0) return {Kind::vertex, vertex, 0.0};
  if (!edges.empty()) return {Kind::edge, std::get<1>(edges.front()), std::get<2>(edges.front())};
  for (int f : near) {
    const auto& loop = s.loops[static_cast<std::size_t>(f)];
    double inside = no_distance;
    for (std::size_t i = 0; i < loop.size(); ++i)
      inside = std::min(inside, signed_distance(p, s.xy[static_cast<std::size_t>(loop[i])],
                                                s.xy[static_cast<std::size_t>(loop[(i + 1) % loop.size()])]));
    if (inside > 0.0) return {Kind::face, f, 0.0};
  }
  throw InputError(what + " is " + number_text(distance_to(s, p)) + " away from the interface of the " + s.side +
                   " mesh, more than " + tol.text() + ": the two interfaces must cover the same region");
}

std::string vertex_text(const Surface& s, int position) {
  const int v = s.vertices[static_cast<std::size_t>(position)];
  return "interface vertex " + std::to_string(v) + " " + point_text(s.mesh->vertex(v)) + " of the " + s.side + " mesh";
}

// Pairs of vertices (positions) that one side or the other placed at each other: per vertex of
// each side its partner on the other, or -1. InputError when a vertex would pair with two.
std::array<std::vector<int>, 2> pair_vertices(const Surface& a, const std::vector<Place>& a_on_b, const Surface& b,
                                              const std::vector<Place>& b_on_a, double tol) {
  std::array<std::vector<int>, 2> partner{std::vector<int>(a.vertices.size(), -1), std::vector<int>(b.vertices.size(), -1)};
  const auto join = [&](int i, int j) {
    const int had_i = partner[0][static_cast<std::size_t>(i)], had_j = partner[1][static_cast<std::size_t>(j)];
    if ((had_i >= 0 && had_i != j) || (had_j >= 0 && had_j != i))
      throw InputError(vertex_text(a, i) + " and " + vertex_text(b, j) + " are within the tolerance " + number_text(tol) +
                       " of each other, but " + (had_i >= 0 && had_i != j ? vertex_text(b, had_i) : vertex_text(a, had_j)) +
                       " is too; each vertex can pair with one only: use a smaller tolerance");
    partner[0][static_cast<std::size_t>(i)] = j;
    partner[1][static_cast<std::size_t>(j)] = i;
  };
  for (std::size_t i = 0; i < a_on_b.size(); ++i)
    if (a_on_b[i].kind == Kind::vertex) join(static_cast<int>(i), a_on_b[i].index);
  for (std::size_t j = 0; j < b_on_a.size(); ++j)
    if (b_on_a[j].kind == Kind::vertex) join(b_on_a[j].index, static_cast<int>(j));
  return partner;
}

// The points of both sides' vertices: the first side's, each placed on the second side, then
// the second side's that are not paired with one of them (a pair is made when either vertex is
// placed at the other). Returns per side the point of each vertex.
std::array<std::vector<int>, 2> add_vertices(const Surface& a, const Surface& b, const Tolerance& tol,
                                             std::vector<Point>& points) {
  std::vector<Place> a_on_b, b_on_a;
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    a_on_b.push_back(locate(b, a.xy[i], tol, vertex_text(a, static_cast<int>(i))));
  for (std::size_t j = 0; j < b.vertices.size(); ++j)
    b_on_a.push_back(locate(a, b.xy[j], tol, vertex_text(b, static_cast<int>(j))));
  const auto partner = pair_vertices(a, a_on_b, b, b_on_a, tol.distance);
  std::array<std::vector<int>, 2> point_of{std::vector<int>(a.vertices.size(), -1), std::vector<int>(b.vertices.size(), -1)};
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    const int j = partner[0][i];
    const Place on_b = j >= 0 ? Place{Kind::vertex, j, 0.0} : a_on_b[i];
    point_of[0][i] = static_cast<int>(points.size());
    points.push_back(Point{a.xy[i], a.mesh->vertex(a.vertices[i]), {Place{Kind::vertex, static_cast<int>(i), 0.0}, on_b}, {-1, -1}});
  }
  for (std::size_t j = 0; j < b.vertices.size(); ++j) {
    const int i = partner[1][j];
    if (i >= 0) {
      point_of[1][j] = point_of[0][static_cast<std::size_t>(i)];
      continue;
    }
    point_of[1][j] = static_cast<int>(points.size());
    points.push_back(Point{b.xy[j], b.mesh->vertex(b.vertices[j]), {b_on_a[j], Place{Kind::vertex, static_cast<int>(j), 0.0}}, {-1, -1}});
  }
  return point_of;
}

// The crossing of first edge k with second edge m, when the ends of each lie on either side of
// the other's line, each farther than the tolerance: (parameter along k, parameter along m).
bool crossing(const Surface& a, int k, const Surface& b, int m, double tol, double& s, double& t) {
  const auto& ea = a.edges[static_cast<std::size_t>(k)];
  const auto& eb = b.edges[static_cast<std::size_t>(m)];
  const Vec2d& p0 = a.xy[static_cast<std::size_t>(ea[0])];
  const Vec2d& p1 = a.xy[static_cast<std::size_t>(ea[1])];
  const Vec2d& q0 = b.xy[static_cast<std::size_t>(eb[0])];
  const Vec2d& q1 = b.xy[static_cast<std::size_t>(eb[1])];
  const double dq0 = signed_distance(q0, p0, p1), dq1 = signed_distance(q1, p0, p1);
  const double dp0 = signed_distance(p0, q0, q1), dp1 = signed_distance(p1, q0, q1);
  const auto apart = [tol](double x, double y) {
    return std::abs(x) > tol && std::abs(y) > tol && ((x > 0.0) != (y > 0.0));
  };
  if (!apart(dq0, dq1) || !apart(dp0, dp1)) return false;
  s = dp0 / (dp0 - dp1);
  t = dq0 / (dq0 - dq1);
  return true;
}

// The crossings of the two sides' edges, along the first side's edges in order, each from its
// smaller end.
void add_crossings(const Surface& a, const Surface& b, double tol, std::vector<Point>& points) {
  for (std::size_t k = 0; k < a.edges.size(); ++k) {
    const auto& ends = a.edges[k];
    const Vec2d& p0 = a.xy[static_cast<std::size_t>(ends[0])];
    const Vec2d& p1 = a.xy[static_cast<std::size_t>(ends[1])];
    Box2 box;
    box.add(p0);
    box.add(p1);
    std::vector<int> edges;
    for (int f : b.grid.near(box)) {
      const auto& fe = b.face_edges[static_cast<std::size_t>(f)];
      edges.insert(edges.end(), fe.begin(), fe.end());
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<std::tuple<double, int, double>> found;
    for (int m : edges) {
      double s = 0.0, t = 0.0;
      if (crossing(a, static_cast<int>(k), b, m, tol, s, t)) found.emplace_back(s, m, t);
    }
    std::sort(found.begin(), found.end());
    const Vec3& x0 = a.mesh->vertex(a.vertices[static_cast<std::size_t>(ends[0])]);
    const Vec3& x1 = a.mesh->vertex(a.vertices[static_cast<std::size_t>(ends[1])]);
    for (const auto& [s, m, t] : found) {
      Point p;
      p.xy = p0 + s * (p1 - p0);
      p.x = x0 + s * (x1 - x0);
      p.place = {Place{Kind::edge, static_cast<int>(k), s}, Place{Kind::edge, m, t}};
      points.push_back(p);
    }
  }
}

// The points of each side's edges (sorted along the edge) and faces.
struct Incidence {
  std::vector<std::vector<std::pair<double, int>>> on_edge;
  std::vector<std::vector<int>> in_face;
};

Incidence incidence(const Surface& s, const std::vector<Point>& points, int side) {
  Incidence out;
  out.on_edge.assign(s.edges.size(), {});
  out.in_face.assign(s.faces.size(), {});
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Place& pl = points[k].place[static_cast<std::size_t>(side)];
    if (pl.kind == Kind::edge) out.on_edge[static_cast<std::size_t>(pl.index)].emplace_back(pl.t, static_cast<int>(k));
    if (pl.kind == Kind::face) out.in_face[static_cast<std::size_t>(pl.index)].push_back(static_cast<int>(k));
  }
  for (auto& list : out.on_edge) std::sort(list.begin(), list.end());
  return out;
}

// A piece of the overlay: the first and the second face holding it (positions in the Surfaces)
// and its points counter-clockwise in the frame.
struct Piece {
  std::array<int, 2> face{-1, -1};
  std::vector<int> loop;
  double area = 0.0;
};

// Orders `loop` (points on the boundary of a convex polygon) counter-clockwise around their mean
// and returns the area it encloses; `diameter` receives the largest distance between two of them.
double order_piece(const std::vector<Point>& points, std::vector<int>& loop, double& diameter) {
  Vec2d mean = Vec2d::Zero();
  for (int k : loop) mean += points[static_cast<std::size_t>(k)].xy;
  mean /= static_cast<double>(loop.size());
  std::vector<std::pair<double, int>> angle;
  for (int k : loop) {
    const Vec2d d = points[static_cast<std::size_t>(k)].xy - mean;
    angle.emplace_back(std::atan2(d.y(), d.x()), k);
  }
  std::sort(angle.begin(), angle.end());
  double area = 0.0;
  diameter = 0.0;
  for (std::size_t i = 0; i < angle.size(); ++i) {
    loop[i] = angle[i].second;
    const Vec2d& a = points[static_cast<std::size_t>(angle[i].second)].xy;
    const Vec2d& b = points[static_cast<std::size_t>(angle[(i + 1) % angle.size()].second)].xy;
    area += 0.5 * cross2(a - mean, b - mean);
    for (const auto& other : angle) diameter = std::max(diameter, (points[static_cast<std::size_t>(other.second)].xy - a).norm());
  }
  return area;
}

// The edges of face f of s (positions) that hold a point placed at `pl` on s.
std::vector<int> edges_at(const Surface& s, int f, const Place& pl) {
  if (pl.kind == Kind::edge) return {pl.index};
  std::vector<int> out;
  if (pl.kind == Kind::vertex)
    for (int e : s.face_edges[static_cast<std::size_t>(f)]) {
      const auto& ends = s.edges[static_cast<std::size_t>(e)];
      if (ends[0] == pl.index || ends[1] == pl.index) out.push_back(e);
    }
  return out;
}

// Whether two of `group`'s points on a common edge of face `faces[side]` of `s` are not both
// within the tolerance of the line of one edge of face `faces[1 - side]` of `o`: the segment
// between them is then a chord through the other face (a convex polygon holding both on its
// boundary), and the two faces overlap along it.
bool has_chord(const std::vector<Point>& points, const std::vector<int>& group, const Surface& s, const Surface& o,
               const std::array<int, 2>& faces, int side) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  const auto& other_loop = o.loops[at(faces[at(1 - side)])];
  for (std::size_t i = 0; i < group.size(); ++i)
    for (std::size_t j = i + 1; j < group.size(); ++j) {
      const Point& p = points[at(group[i])];
      const Point& q = points[at(group[j])];
      std::vector<int> ep = edges_at(s, faces[at(side)], p.place[at(side)]);
      std::vector<int> eq = edges_at(s, faces[at(side)], q.place[at(side)]);
      if (std::none_of(ep.begin(), ep.end(), [&](int e) { return std::find(eq.begin(), eq.end(), e) != eq.end(); }))
        continue;
      bool along_a_side = false;
      for (std::size_t k = 0; k < other_loop.size() && !along_a_side; ++k) {
        const Vec2d& u = o.xy[at(other_loop[k])];
        const Vec2d& v = o.xy[at(other_loop[(k + 1) % other_loop.size()])];
        along_a_side = std::abs(signed_distance(p.xy, u, v)) <= o.tol && std::abs(signed_distance(q.xy, u, v)) <= o.tol;
      }
      if (!along_a_side) return true;
    }
  return false;
}

// Whether first face fa and second face fb (positions) overlap in an area, given the points in
// both closures: when those points include an edge crossing or a point inside either face (the
// faces overlap near it), or two points on an edge of one face forming a chord of the other
// (has_chord), or else span more than the tolerance times their diameter (faces that only touch
// along an edge or at a vertex give points along a line).
bool spans_area(const std::vector<Point>& points, const std::vector<int>& group, const Surface& a, const Surface& b,
                const std::array<int, 2>& faces, double area, double diameter) {
  for (int k : group) {
    const auto& [on_a, on_b] = points[static_cast<std::size_t>(k)].place;
    if (on_a.kind == Kind::face || on_b.kind == Kind::face || (on_a.kind == Kind::edge && on_b.kind == Kind::edge))
      return true;
  }
  return has_chord(points, group, b, a, faces, 1) || has_chord(points, group, a, b, faces, 0) || area > a.tol * diameter;
}

// The second faces whose closure holds a point placed at `pl` on the second side.
const std::vector<int>& faces_at(const Surface& b, const Place& pl, std::vector<int>& one) {
  if (pl.kind == Kind::vertex) return b.vertex_faces[static_cast<std::size_t>(pl.index)];
  if (pl.kind == Kind::edge) return b.edge_faces[static_cast<std::size_t>(pl.index)];
  one.assign(1, pl.index);
  return one;
}

// The pieces of the overlay, by first face, then by second face. The points of first face f
// (its vertices, the points on its edges and inside it) are grouped by the second faces whose
// closure holds them; a group spanning an area (spans_area) is the piece of f and that face.
std::vector<Piece> make_pieces(const Surface& a, const Surface& b, const std::vector<Point>& points,
                               const std::vector<int>& point_of_a_vertex, const Incidence& on_a) {
  std::vector<Piece> pieces;
  std::vector<int> one;
  for (std::size_t f = 0; f < a.faces.size(); ++f) {
    std::vector<int> held(on_a.in_face[f]);
    const auto& loop = a.loops[f];
    for (std::size_t i = 0; i < loop.size(); ++i) {
      held.push_back(point_of_a_vertex[static_cast<std::size_t>(loop[i])]);
      for (const auto& [t, k] : on_a.on_edge[static_cast<std::size_t>(a.face_edges[f][i])]) held.push_back(k);
    }
    std::map<int, std::vector<int>> groups;
    for (int k : held)
      for (int g : faces_at(b, points[static_cast<std::size_t>(k)].place[1], one)) groups[g].push_back(k);
    for (auto& [g, group] : groups) {
      if (group.size() < 3) continue;
      double diameter = 0.0;
      const double area = order_piece(points, group, diameter);
      const std::array<int, 2> faces{static_cast<int>(f), g};
      if (spans_area(points, group, a, b, faces, area, diameter)) pieces.push_back(Piece{faces, std::move(group), area});
    }
  }
  return pieces;
}

// Every face of s is covered by its pieces: their areas add up to its own, to the tolerance
// times its perimeter (and round-off).
void check_coverage(const Surface& s, const Surface& other, const std::vector<Piece>& pieces, int side, double tol) {
  std::vector<double> covered(s.faces.size(), 0.0);
  for (const Piece& p : pieces) covered[static_cast<std::size_t>(p.face[static_cast<std::size_t>(side)])] += p.area;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const double area = s.face_area[f];
    if (std::abs(covered[f] - area) > tol * s.face_perimeter[f] + 1e-12 * area)
      throw InputError("interface face " + std::to_string(s.faces[f]) + " of the " + s.side + " mesh (area " +
                       number_text(area) + ") is covered by the faces of the " + other.side + " mesh over an area of " +
                       number_text(covered[f]) + ": the two interfaces must cover the same region");
  }
}

// The vertex ids of the points in the matched mesh of `side`: the vertex itself, else a new one,
// in the order of the points.
void number_points(std::vector<Point>& points, const Surface& s, int side) {
  int next = s.mesh->num_vertices();
  for (Point& p : points) {
    const Place& pl = p.place[static_cast<std::size_t>(side)];
    p.id[static_cast<std::size_t>(side)] = pl.kind == Kind::vertex ? s.vertices[static_cast<std::size_t>(pl.index)] : next++;
  }
}

// A piece's vertex loop in the mesh of `side` (reversed on the second side: counter-clockwise
// seen from outside its body): the face's own loop when the piece has the face's vertices, else
// started at its smallest id.
std::vector<int> piece_loop(const Piece& piece, const std::vector<Point>& points, const Surface& s, int side) {
  std::vector<int> loop;
  for (int k : piece.loop) loop.push_back(points[static_cast<std::size_t>(k)].id[static_cast<std::size_t>(side)]);
  if (side == 1) std::reverse(loop.begin(), loop.end());
  const std::vector<int>& own = s.mesh->face(s.faces[static_cast<std::size_t>(piece.face[static_cast<std::size_t>(side)])]).vertices;
  std::vector<int> mine(loop), theirs(own);
  std::sort(mine.begin(), mine.end());
  std::sort(theirs.begin(), theirs.end());
  if (mine == theirs) return own;
  std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
  return loop;
}

// Per interface edge of s with points inside it (key: its end ids, smaller first): their ids in
// the matched mesh, from the smaller end.
std::unordered_map<std::uint64_t, std::vector<int>> edge_cuts(const Surface& s, const Incidence& inc,
                                                              const std::vector<Point>& points, int side) {
  std::unordered_map<std::uint64_t, std::vector<int>> cuts;
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    if (inc.on_edge[e].empty()) continue;
    auto& ids = cuts[pair_key(s.vertices[static_cast<std::size_t>(s.edges[e][0])], s.vertices[static_cast<std::size_t>(s.edges[e][1])])];
    for (const auto& [t, k] : inc.on_edge[e]) ids.push_back(points[static_cast<std::size_t>(k)].id[static_cast<std::size_t>(side)]);
  }
  return cuts;
}

std::vector<int> spliced(const std::vector<int>& loop, const std::unordered_map<std::uint64_t, std::vector<int>>& cuts) {
  std::vector<int> out;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int a = loop[i], b = loop[(i + 1) % loop.size()];
    out.push_back(a);
    const auto it = cuts.find(pair_key(std::min(a, b), std::max(a, b)));
    if (it == cuts.end()) continue;
    if (a < b)
      out.insert(out.end(), it->second.begin(), it->second.end());
    else
      out.insert(out.end(), it->second.rbegin(), it->second.rend());
  }
  return out;
}

// The coordinates of the vertex made for point p in the mesh of `side`: p's own, unless they lie
// off the edge or the plane of the face of that side that holds p by more than
// straight_tolerance of its size (a point of the other side placed there within the tolerance),
// then their projection onto it, so that the faces along the edge stay straight and planar.
Vec3 copy_on(const Surface& s, const Point& p, int side) {
  const Place& pl = p.place[static_cast<std::size_t>(side)];
  const Mesh3D& mesh = *s.mesh;
  if (pl.kind == Kind::edge) {
    const auto& ends = s.edges[static_cast<std::size_t>(pl.index)];
    const Vec3& x0 = mesh.vertex(s.vertices[static_cast<std::size_t>(ends[0])]);
    const Vec3 along = mesh.vertex(s.vertices[static_cast<std::size_t>(ends[1])]) - x0;
    const Vec3 foot = x0 + (p.x - x0).dot(along) / along.squaredNorm() * along;
    return (p.x - foot).norm() <= straight_tolerance * along.norm() ? p.x : foot;
  }
  const int f = s.faces[static_cast<std::size_t>(pl.index)];
  const double off = (p.x - mesh.face_centroid(f)).dot(mesh.face_normal(f));
  return std::abs(off) <= straight_tolerance * std::sqrt(mesh.face_area(f)) ? p.x : Vec3(p.x - off * mesh.face_normal(f));
}

// A matched side: its mesh, the face id of each piece in it, and per given face its faces now.
struct Built {
  Mesh3D mesh;
  std::vector<int> piece_face;
};

// The cells of the matched mesh of `side`: interface faces replaced by their pieces, other faces
// with the edge cuts spliced in. `where` receives per cell, per given face, the range of its
// faces now (first position, count) and per piece its (cell, position).
std::vector<CellFaces> matched_cells(const Surface& s, const std::vector<Piece>& pieces, const std::vector<Point>& points,
                                     const Incidence& inc, int side, std::vector<std::vector<std::array<int, 2>>>& where,
                                     std::vector<std::array<int, 2>>& piece_at) {
  const Mesh3D& mesh = *s.mesh;
  std::unordered_map<int, std::vector<int>> pieces_of;  // interface face id -> pieces
  for (std::size_t k = 0; k < pieces.size(); ++k)
    pieces_of[s.faces[static_cast<std::size_t>(pieces[k].face[static_cast<std::size_t>(side)])]].push_back(static_cast<int>(k));
  const auto cuts = edge_cuts(s, inc, points, side);
  std::vector<CellFaces> cells(static_cast<std::size_t>(mesh.num_cells()));
  where.assign(cells.size(), {});
  piece_at.assign(pieces.size(), {-1, -1});
  for (int c = 0; c < mesh.num_cells(); ++c) {
    auto& out = cells[static_cast<std::size_t>(c)];
    const CellFaces given = mesh.cell(c);
    for (std::size_t j = 0; j < given.size(); ++j) {
      const int start = static_cast<int>(out.size());
      const auto it = pieces_of.find(mesh.cell_faces(c)[j]);
      if (it == pieces_of.end()) {
        out.push_back(spliced(given[j], cuts));
      } else {
        for (int k : it->second) {
          piece_at[static_cast<std::size_t>(k)] = {c, static_cast<int>(out.size())};
          out.push_back(piece_loop(pieces[static_cast<std::size_t>(k)], points, s, side));
        }
      }
      where[static_cast<std::size_t>(c)].push_back({start, static_cast<int>(out.size()) - start});
    }
  }
  return cells;
}

// The matched mesh of `side`, with the face groups carried over to the faces each face became.
Built build_side(const Surface& s, const std::vector<Piece>& pieces, const std::vector<Point>& points, const Incidence& inc,
                 int side) {
  const Mesh3D& mesh = *s.mesh;
  std::vector<std::vector<std::array<int, 2>>> where;
  std::vector<std::array<int, 2>> piece_at;
  std::vector<CellFaces> cells = matched_cells(s, pieces, points, inc, side, where, piece_at);
  std::vector<Vec3> vertices = mesh.vertices();
  for (const Point& p : points)
    if (p.id[static_cast<std::size_t>(side)] >= mesh.num_vertices()) vertices.push_back(copy_on(s, p, side));
  Built out;
  try {
    out.mesh = Mesh3D(std::move(vertices), std::move(cells), mesh.regions());
  } catch (const MeshError& error) {
    throw MeshError("matching the interface makes cell " + std::to_string(error.element()) + " of the " + s.side +
                        " mesh invalid: " + error.what(),
                    error.element());
  }
  for (const auto& [c, j] : piece_at) out.piece_face.push_back(out.mesh.cell_faces(c)[static_cast<std::size_t>(j)]);
  for (const auto& [name, group] : mesh.face_groups()) {
    std::vector<int> faces;
    for (int f : group) {
      const int c = mesh.face(f).inner;
      const auto& given = mesh.cell_faces(c);
      const auto j = static_cast<std::size_t>(std::find(given.begin(), given.end(), f) - given.begin());
      const auto [start, count] = where[static_cast<std::size_t>(c)][j];
      for (int k = start; k < start + count; ++k) faces.push_back(out.mesh.cell_faces(c)[static_cast<std::size_t>(k)]);
    }
    out.mesh.set_face_group(name, std::move(faces));
  }
  return out;
}

}  // namespace

MatchedInterface3D match_interface_3d(const Mesh3D& first, const std::vector<int>& first_faces, const Mesh3D& second,
                                      const std::vector<int>& second_faces, double tolerance) {
  if (!(tolerance >= 0.0 && tolerance <= largest_tolerance))
    throw InputError("the interface tolerance is " + number_text(tolerance) + "; it must be in [0, " +
                     number_text(largest_tolerance) + "] (a fraction of the interface's size)");
  const std::vector<int> fa = checked_faces(first, first_faces, "first");
  const std::vector<int> fb = checked_faces(second, second_faces, "second");

  const auto [size_a, magnitude_a] = extent(first, fa);
  const auto [size_b, magnitude_b] = extent(second, fb);
  Tolerance tol{0.0, tolerance, std::max(size_a, size_b)};
  tol.distance = std::max(tolerance * tol.size,
                          16.0 * std::numeric_limits<double>::epsilon() * std::max(magnitude_a, magnitude_b));
  const Frame frame = interface_frame(first, fa);
  check_planar(first, fa, "first", frame, tol);
  check_planar(second, fb, "second", frame, tol);
  check_orientation(first, fa, second, fb, frame);

  const Surface a = make_surface(first, fa, "first", frame, tol.distance);
  const Surface b = make_surface(second, fb, "second", frame, tol.distance);
  std::vector<Point> points;
  const auto point_of = add_vertices(a, b, tol, points);
  add_crossings(a, b, tol.distance, points);
  const Incidence on_a = incidence(a, points, 0), on_b = incidence(b, points, 1);
  const std::vector<Piece> pieces = make_pieces(a, b, points, point_of[0], on_a);
  check_coverage(a, b, pieces, 0, tol.distance);
  check_coverage(b, a, pieces, 1, tol.distance);
  number_points(points, a, 0);
  number_points(points, b, 1);

  Built built_a = build_side(a, pieces, points, on_a, 0);
  Built built_b = build_side(b, pieces, points, on_b, 1);
  MatchedInterface3D out;
  std::vector<std::array<int, 2>> faces;
  for (std::size_t k = 0; k < pieces.size(); ++k) faces.push_back({built_a.piece_face[k], built_b.piece_face[k]});
  std::sort(faces.begin(), faces.end());
  for (const auto& [f, g] : faces) {
    out.first_faces.push_back(f);
    out.second_faces.push_back(g);
  }
  for (const Point& p : points) out.pairs.push_back(p.id);
  std::sort(out.pairs.begin(), out.pairs.end());
  out.first = std::move(built_a.mesh);
  out.second = std::move(built_b.mesh);
  return out;
}

}  // namespace hemivem
