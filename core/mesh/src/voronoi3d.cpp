// Voronoi cells of random seeds in a box (make_voronoi3d, generators3d.hpp).
//
// Each cell starts as the box and is clipped by the bisector planes of its seed's Delaunay
// neighbours (CGAL's Delaunay_triangulation_3; every seed when there are few), nearest first.
// Every plane is a "generator": a side of the box or a neighbouring seed. A vertex is named by
// the four generators it is equidistant from or lies on (its key: the cell's own seed, and
// three planes), and its position is computed from its key alone, so every cell around a
// vertex computes the same position, bit for bit. Whether a vertex lies on the kept side of a
// plane is decided exactly: interval arithmetic, and exact rational arithmetic when the
// interval cannot tell. So the cells agree on their shared vertices and faces (in general
// position the clipped Voronoi diagram has exactly four generators per vertex); vertices
// closer than the merge tolerance are then merged, which also handles exactly degenerate seed
// sets (five seeds on a sphere).
#include <hemivem/mesh/generators3d.hpp>

#include "box_grid.hpp"
#include "cell_topology.hpp"
#include "hilbert.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/FPU.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <functional>
#include <memory>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace hemivem {

namespace {

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

double box_magnitude(const Box& d) {
  return std::max({std::abs(d.x0), std::abs(d.x1), std::abs(d.y0), std::abs(d.y1), std::abs(d.z0), std::abs(d.z1)});
}

double box_largest_side(const Box& d) { return std::max({d.size(0), d.size(1), d.size(2)}); }

void check_input(GridSize3 n, const Box& d, const VoronoiOptions& options) {
  const char* g = "voronoi mesh";
  detail::check_box_grid(g, n, d);
  if (options.max_lloyd_iterations < 0)
    throw InputError(std::string(g) + ": max_lloyd_iterations must be >= 0 (got " +
                     std::to_string(options.max_lloyd_iterations) + ")");
  if (!(options.lloyd_tolerance >= 0.0) || !std::isfinite(options.lloyd_tolerance))
    throw InputError(std::string(g) + ": lloyd_tolerance must be finite and >= 0 (got " + fmt(options.lloyd_tolerance) +
                     ")");
}

/// A double in the open interval (a, b) from one 64-bit draw (portable, unlike
/// std::uniform_real_distribution).
double open_draw(std::mt19937_64& rng, double a, double b) {
  const double u = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;  // in (0, 1)
  const double x = a + (b - a) * u;
  if (x <= a) return std::nextafter(a, b);
  if (x >= b) return std::nextafter(b, a);
  return x;
}

// ---- points in lexicographic order ------------------------------------------------------

bool lex_less(const Vec3& a, const Vec3& b) {
  return a.x() < b.x() || (a.x() == b.x() && (a.y() < b.y() || (a.y() == b.y() && a.z() < b.z())));
}


// ---- neighbours -----------------------------------------------------------------------

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;

/// The candidate neighbours of each seed first, ..., end - 1: its Delaunay neighbours, or every
/// other seed when there are few seeds or they do not span space. Each list is sorted nearest
/// first (ties by index); the other seeds' lists are empty.
std::vector<std::vector<int>> neighbours(const std::vector<Vec3>& seeds, int first, int end) {
  const int ns = static_cast<int>(seeds.size());
  std::vector<std::vector<int>> nb(seeds.size());
  bool all = ns <= 16;
  if (!all) {
    Delaunay dt;
    std::vector<Delaunay::Vertex_handle> handle(seeds.size());
    Delaunay::Cell_handle hint;
    for (int i = 0; i < ns; ++i) {
      const Vec3& p = seeds[static_cast<std::size_t>(i)];
      const auto v = dt.insert(Kernel::Point_3(p.x(), p.y(), p.z()), hint);
      v->info() = i;
      hint = v->cell();
      handle[static_cast<std::size_t>(i)] = v;
    }
    if (dt.number_of_vertices() != seeds.size())
      throw NumericalError("voronoi mesh: two seeds coincide; the Voronoi diagram is undefined");
    if (dt.dimension() < 3) {
      all = true;
    } else {
      std::vector<Delaunay::Vertex_handle> adjacent;
      for (int i = first; i < end; ++i) {
        adjacent.clear();
        dt.finite_adjacent_vertices(handle[static_cast<std::size_t>(i)], std::back_inserter(adjacent));
        auto& list = nb[static_cast<std::size_t>(i)];
        for (const auto& v : adjacent) list.push_back(v->info());
      }
    }
  }
  if (all) {
    for (int i = first; i < end; ++i)
      for (int j = 0; j < ns; ++j)
        if (j != i) nb[static_cast<std::size_t>(i)].push_back(j);
  }
  for (int i = first; i < end; ++i) {
    const Vec3& p = seeds[static_cast<std::size_t>(i)];
    auto& list = nb[static_cast<std::size_t>(i)];
    for (int j : list)
      if (seeds[static_cast<std::size_t>(j)] == p)
        throw NumericalError("voronoi mesh: two seeds coincide; the Voronoi diagram is undefined");
    std::sort(list.begin(), list.end(), [&](int a, int b) {
      const double da = (seeds[static_cast<std::size_t>(a)] - p).squaredNorm();
      const double db = (seeds[static_cast<std::size_t>(b)] - p).squaredNorm();
      return da < db || (da == db && a < b);
    });
  }
  return nb;
}

// ---- vertices from their generators ---------------------------------------------------

/// A generator: a seed (its index, >= 0) or a side of the box (-1 - side, side 0 ... 5 for
/// x0, x1, y0, y1, z0, z1).
constexpr int side_generator(int side) { return -1 - side; }
constexpr int side_of(int generator) { return -1 - generator; }

/// The four generators of a vertex, sorted (sides first).
using Key = std::array<int, 4>;

struct KeyHash {
  std::size_t operator()(const Key& k) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (int x : k) h = (h ^ static_cast<std::uint32_t>(x)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

Key make_key(int a, int b, int c, int d) {
  Key k{a, b, c, d};
  std::sort(k.begin(), k.end());
  return k;
}

using Interval = CGAL::Interval_nt<false>;
using Rational = CGAL::Exact_rational;

double side_coordinate(const Box& box, int side) { return side % 2 == 0 ? box.lower(side / 2) : box.upper(side / 2); }

/// The point of a key: on the sides of its side generators, equidistant from its seeds. With
/// a the first seed and y = x - a, every other seed t gives 2 (t - a).y = |t - a|^2. Returns
/// false when the system is (or may be, for intervals) singular.
template <class NT>
bool solve_key(const Key& key, const std::vector<Vec3>& seeds, const Box& box, std::array<NT, 3>& x) {
  bool fixed[3] = {false, false, false};
  std::size_t s = 0;
  for (; s < 4 && key[s] < 0; ++s) {
    const int side = side_of(key[s]);
    fixed[side / 2] = true;
    x[static_cast<std::size_t>(side / 2)] = NT(side_coordinate(box, side));
  }
  if (s == 4) return false;  // no seed: not a vertex of a cell
  const Vec3& a = seeds[static_cast<std::size_t>(key[s])];
  int freeaxis[3];
  int nf = 0;
  for (int k = 0; k < 3; ++k)
    if (!fixed[k]) freeaxis[nf++] = k;
  if (nf != 3 - static_cast<int>(s)) return false;  // two sides on one axis
  // rows: 2 d_free . y_free = |d|^2 - 2 d_fixed . y_fixed
  NT m[3][3], r[3];
  for (int row = 0; row < nf; ++row) {
    const Vec3& t = seeds[static_cast<std::size_t>(key[s + 1 + static_cast<std::size_t>(row)])];
    NT d[3];
    NT rhs(0);
    for (int k = 0; k < 3; ++k) {
      d[k] = NT(t[k]) - NT(a[k]);
      rhs += d[k] * d[k];
    }
    for (int k = 0; k < 3; ++k)
      if (fixed[k]) rhs -= NT(2) * d[k] * (x[static_cast<std::size_t>(k)] - NT(a[k]));
    for (int c = 0; c < nf; ++c) m[row][c] = NT(2) * d[freeaxis[c]];
    r[row] = rhs;
  }
  auto nonzero = [](const NT& v) {
    if constexpr (std::is_same_v<NT, Interval>) {
      return v.inf() > 0 || v.sup() < 0;
    } else {
      return !CGAL::is_zero(v);
    }
  };
  NT y[3];
  if (nf == 1) {
    if (!nonzero(m[0][0])) return false;
    y[0] = r[0] / m[0][0];
  } else if (nf == 2) {
    const NT det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if (!nonzero(det)) return false;
    y[0] = (r[0] * m[1][1] - m[0][1] * r[1]) / det;
    y[1] = (m[0][0] * r[1] - r[0] * m[1][0]) / det;
  } else if (nf == 3) {
    const NT c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    const NT c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    const NT c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const NT det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if (!nonzero(det)) return false;
    // Cramer: replace column c by r
    auto det3 = [](const NT (&q)[3][3]) -> NT {
      return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
             q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
    };
    for (int c = 0; c < 3; ++c) {
      NT q[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) q[i][j] = j == c ? r[i] : m[i][j];
      y[c] = det3(q) / det;
    }
  }
  for (int c = 0; c < nf; ++c) x[static_cast<std::size_t>(freeaxis[c])] = NT(a[freeaxis[c]]) + y[c];
  return true;
}

/// A vertex of a cell being clipped: its key, its position (rounded) and an enclosing
/// interval of its exact position (valid when `interval_ok`).
struct Vertex {
  Key key{};
  Vec3 pos = Vec3::Zero();
  std::array<Interval, 3> box;
  double error = 0.0;  // bound of |pos - exact position| per coordinate
  bool interval_ok = false;
};

struct Face {
  int generator = 0;
  std::vector<int> loop;  // vertex indices, counter-clockwise seen from outside the cell
};

/// Rounds and filters the vertices of keys. Positions are computed in interval arithmetic
/// (the caller holds the rounding mode upward) and taken as the interval's midpoint when it
/// is narrower than `accuracy`, else computed exactly and rounded.
class VertexMaker {
 public:
  VertexMaker(const std::vector<Vec3>& seeds, const Box& box, double accuracy)
      : seeds_(seeds), box_(box), accuracy_(accuracy) {}

  Vertex make(const Key& key) const {
    Vertex v;
    v.key = key;
    v.interval_ok = solve_key(key, seeds_, box_, v.box);
    bool narrow = v.interval_ok;
    if (narrow)
      for (const Interval& c : v.box) narrow = narrow && c.sup() - c.inf() <= accuracy_;
    if (narrow) {
      for (int k = 0; k < 3; ++k) {
        const Interval& c = v.box[static_cast<std::size_t>(k)];
        // within [inf, sup]: |pos - exact| <= sup - inf
        v.pos[k] = c.inf() == c.sup() ? c.inf() : 0.5 * c.inf() + 0.5 * c.sup();
        v.error = std::max(v.error, c.sup() - c.inf());
      }
    } else {
      std::array<Rational, 3> x;
      if (!solve_key(key, seeds_, box_, x))
        throw NumericalError("voronoi mesh: a cell vertex is undefined (its planes do not meet in one point)");
      for (int k = 0; k < 3; ++k) {
        v.pos[k] = CGAL::to_double(x[static_cast<std::size_t>(k)]);
        v.error = std::max(v.error, 4.0 * std::numeric_limits<double>::epsilon() * std::abs(v.pos[k]));
      }
      v.error += std::numeric_limits<double>::denorm_min();
    }
    return v;
  }

  /// The sign of |v - e|^2 - |v - a|^2 (positive: v is closer to seed a than to seed e).
  int side(const Vertex& v, int a, int e) const {
    const Vec3& A = seeds_[static_cast<std::size_t>(a)];
    const Vec3& E = seeds_[static_cast<std::size_t>(e)];
    {
      // in doubles, with a bound of the error of pos and of the rounding (each operation
      // off by at most 2 eps, relative, in any rounding mode)
      constexpr double eps = std::numeric_limits<double>::epsilon();
      double g = 0.0, bound = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double d = A[k] - E[k];
        g += d * (2.0 * v.pos[k] - A[k] - E[k]);
        bound += std::abs(d) * (2.0 * v.error + 16.0 * eps * (2.0 * std::abs(v.pos[k]) + std::abs(A[k]) + std::abs(E[k])));
      }
      bound *= 1.0 + 1e-6;
      if (g > bound) return 1;
      if (g < -bound) return -1;
    }
    if (v.interval_ok) {
      Interval g(0);
      for (int k = 0; k < 3; ++k)
        g += (Interval(A[k]) - Interval(E[k])) * (Interval(2) * v.box[static_cast<std::size_t>(k)] - Interval(A[k]) -
                                                  Interval(E[k]));
      if (g.inf() > 0) return 1;
      if (g.sup() < 0) return -1;
    }
    std::array<Rational, 3> x;
    if (!solve_key(v.key, seeds_, box_, x))
      throw NumericalError("voronoi mesh: a cell vertex is undefined (its planes do not meet in one point)");
    Rational g(0);
    for (int k = 0; k < 3; ++k) {
      const Rational ak(A[k]), ek(E[k]);
      g += (ak - ek) * (Rational(2) * x[static_cast<std::size_t>(k)] - ak - ek);
    }
    return CGAL::sign(g);
  }

 private:
  const std::vector<Vec3>& seeds_;
  const Box& box_;
  double accuracy_;
};

/// A convex cell: vertices and outward faces, and the work space of clip() (kept between the
/// cells one Cell is made into, so that their vectors keep their capacity).
struct Cell {
  std::vector<Vertex> vertices;
  std::vector<Face> faces;
  std::vector<Face> next;  // the faces clip() makes, taking the loops' storage in turns with `faces`
  std::vector<int> signs, number;
  std::vector<std::pair<std::pair<int, int>, int>> crossing;
  std::vector<std::pair<int, int>> cap;
};

/// `c` becomes the box, as the cell of `seed` before any clipping.
void make_box_cell(Cell& c, int seed, const VertexMaker& maker) {
  c.vertices.clear();
  for (int i = 0; i < 8; ++i)
    c.vertices.push_back(maker.make(make_key(seed, side_generator(i & 1), side_generator(2 + ((i >> 1) & 1)),
                                             side_generator(4 + ((i >> 2) & 1)))));
  static constexpr int loops[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  c.faces.resize(6);
  for (int f = 0; f < 6; ++f) {
    c.faces[static_cast<std::size_t>(f)].generator = side_generator(f);
    c.faces[static_cast<std::size_t>(f)].loop.assign(std::begin(loops[f]), std::end(loops[f]));
  }
}

[[noreturn]] void degenerate(int seed) {
  throw NumericalError("voronoi mesh: clipping the cell of seed " + std::to_string(seed) +
                       " met a degenerate configuration of seeds");
}

/// The generator other than a and f shared by the keys of u and w (the plane of the face
/// across the edge u-w of face f), or INT_MIN when there is not exactly one.
int shared_generator(const Key& u, const Key& w, int a, int f) {
  int found = std::numeric_limits<int>::min(), count = 0;
  for (int x : u)
    if (x != a && x != f && std::find(w.begin(), w.end(), x) != w.end()) {
      found = x;
      ++count;
    }
  return count == 1 ? found : std::numeric_limits<int>::min();
}

/// The cap of cell a on a bisector: its directed edges chained into one loop, into `loop`.
void chain_cap(const std::vector<std::pair<int, int>>& cap, int a, std::vector<int>& loop) {
  const int start = cap.front().first;
  int v = start;
  for (std::size_t k = 0; k < cap.size(); ++k) {
    loop.push_back(v);
    int next = -1;
    for (const auto& [p, q] : cap)
      if (p == v) {
        if (next >= 0) degenerate(a);
        next = q;
      }
    if (next < 0) degenerate(a);
    v = next;
  }
  if (v != start) degenerate(a);
}

/// The first `count` faces of c.next become the faces of cell `c`, which keeps the vertices
/// they use, in their order.
void keep_used_vertices(Cell& c, std::size_t count) {
  c.next.resize(count);
  std::vector<Face>& faces = c.next;
  std::vector<int>& number = c.number;
  number.assign(c.vertices.size(), -1);
  for (const Face& f : faces)
    for (int v : f.loop) number[static_cast<std::size_t>(v)] = 0;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < c.vertices.size(); ++i)
    if (number[i] == 0) {
      number[i] = static_cast<int>(kept);
      if (kept != i) c.vertices[kept] = c.vertices[i];
      ++kept;
    }
  c.vertices.resize(kept);
  for (Face& f : faces)
    for (int& v : f.loop) v = number[static_cast<std::size_t>(v)];
  c.faces.swap(c.next);
}

/// The face of cell `c` (of seed a) across its directed edge u -> w: the face holding w -> u.
int face_across(const Cell& c, int u, int w, int a) {
  for (std::size_t f = 0; f < c.faces.size(); ++f) {
    const auto& L = c.faces[f].loop;
    for (std::size_t k = 0; k < L.size(); ++k)
      if (L[k] == w && L[(k + 1) % L.size()] == u) return static_cast<int>(f);
  }
  degenerate(a);
}

/// The reversed edges that no face of faces[0, count) matches, into `cap`: the cap of a cell
/// whose clipping plane holds some of its vertices.
void unmatched_edges(const std::vector<Face>& faces, std::size_t count, std::vector<std::pair<int, int>>& cap) {
  std::vector<std::pair<int, int>> edges;
  for (std::size_t m = 0; m < count; ++m) {
    const Face& f = faces[m];
    for (std::size_t k = 0; k < f.loop.size(); ++k) edges.emplace_back(f.loop[k], f.loop[(k + 1) % f.loop.size()]);
  }
  std::sort(edges.begin(), edges.end());
  for (const auto& [u, w] : edges)
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(w, u))) cap.emplace_back(w, u);
}

/// Clips cell `c` of seed a by the bisector of seeds a and e (keeping the side of a).
///
/// A vertex strictly on the far side goes; the faces with such vertices are cut where their
/// edges cross the plane, and the cap (the new face on the plane) is made of the cuts. A vertex
/// exactly on the plane (a degenerate configuration: five seeds on a sphere) is kept, and the
/// cap is then found as the edges that no remaining face matches.
void clip(Cell& c, int a, int e, const VertexMaker& maker) {
  const std::size_t nv = c.vertices.size();
  std::vector<int>& s = c.signs;
  s.resize(nv);
  bool cut = false, zero = false;
  for (std::size_t i = 0; i < nv; ++i) {
    s[i] = maker.side(c.vertices[i], a, e);
    cut = cut || s[i] < 0;
    zero = zero || s[i] == 0;
  }
  if (!cut) return;

  auto& crossing = c.crossing;  // edge (min, max) -> new vertex
  crossing.clear();
  auto crossing_vertex = [&](int u, int w, int generator) {
    const std::pair<int, int> edge(std::min(u, w), std::max(u, w));
    for (const auto& [ed, id] : crossing)
      if (ed == edge) return id;
    int other = shared_generator(c.vertices[static_cast<std::size_t>(u)].key,
                                 c.vertices[static_cast<std::size_t>(w)].key, a, generator);
    if (other == std::numeric_limits<int>::min()) other = c.faces[static_cast<std::size_t>(face_across(c, u, w, a))].generator;
    const int id = static_cast<int>(c.vertices.size());
    c.vertices.push_back(maker.make(make_key(a, generator, other, e)));
    s.push_back(0);
    crossing.emplace_back(edge, id);
    return id;
  };

  auto& cap = c.cap;  // directed edges of the cap
  cap.clear();
  // the faces made, c.next[0, made): each takes a Face of c.next and its loop's storage
  std::vector<Face>& faces = c.next;
  std::size_t made = 0;
  const auto take = [&](int generator) -> Face& {
    if (made == faces.size()) faces.emplace_back();
    Face& g = faces[made++];
    g.generator = generator;
    g.loop.clear();
    return g;
  };
  for (Face& f : c.faces) {
    const auto& L = f.loop;
    bool has_negative = false, has_positive = false;
    for (int v : L) {
      has_negative = has_negative || s[static_cast<std::size_t>(v)] < 0;
      has_positive = has_positive || s[static_cast<std::size_t>(v)] > 0;
    }
    if (!has_negative) {
      take(f.generator).loop.swap(f.loop);
      continue;
    }
    if (!has_positive) continue;
    Face& g = take(f.generator);
    int exit = -1, entry = -1;
    for (std::size_t k = 0; k < L.size(); ++k) {
      const int u = L[k], w = L[(k + 1) % L.size()];
      const int su = s[static_cast<std::size_t>(u)], sw = s[static_cast<std::size_t>(w)];
      if (su >= 0) g.loop.push_back(u);
      if ((su > 0 && sw < 0) || (su < 0 && sw > 0)) g.loop.push_back(crossing_vertex(u, w, f.generator));
      if (su >= 0 && sw < 0) exit = g.loop.back();
      if (su < 0 && sw >= 0) entry = sw == 0 ? w : g.loop.back();
    }
    if (!zero) cap.emplace_back(entry, exit);
    if (g.loop.size() < 3) --made;
  }

  if (zero) unmatched_edges(faces, made, cap);
  if (!cap.empty()) {  // the new face, where it has three vertices or more
    Face& g = take(e);
    chain_cap(cap, a, g.loop);
    if (g.loop.size() < 3) --made;
  }
  keep_used_vertices(c, made);
}

/// `c` becomes the cell of seed a: the box clipped by the bisectors with its candidate
/// neighbours (nearest first; a neighbour farther than twice the cell's radius cannot cut it).
void make_voronoi_cell(Cell& c, int a, const std::vector<Vec3>& seeds, const std::vector<int>& nb,
                       const VertexMaker& maker, double margin) {
  make_box_cell(c, a, maker);
  const Vec3& p = seeds[static_cast<std::size_t>(a)];
  double radius = 0.0;
  auto update_radius = [&] {  // sqrt is monotone and correctly rounded: the largest norm, to the bit
    double largest = 0.0;
    for (const Vertex& v : c.vertices) largest = std::max(largest, (v.pos - p).squaredNorm());
    radius = std::sqrt(largest);
  };
  update_radius();
  for (int e : nb) {
    // |v - a| < |e - a| / 2 for every vertex v: the bisector misses the cell, and so do
    // the bisectors of every farther neighbour.
    if (0.5 * (seeds[static_cast<std::size_t>(e)] - p).norm() > radius + margin) break;
    clip(c, a, e, maker);
    update_radius();
  }
}

/// Volume and centroid of a cell (tetrahedra from its seed, which lies inside it).
std::pair<double, Vec3> volume_centroid(const Cell& c, const Vec3& apex) {
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (const Face& f : c.faces) {
    const Vec3 p0 = c.vertices[static_cast<std::size_t>(f.loop[0])].pos - apex;
    for (std::size_t k = 1; k + 1 < f.loop.size(); ++k) {
      const Vec3 p1 = c.vertices[static_cast<std::size_t>(f.loop[k])].pos - apex;
      const Vec3 p2 = c.vertices[static_cast<std::size_t>(f.loop[k + 1])].pos - apex;
      const double v = p0.dot(p1.cross(p2)) / 6.0;
      volume += v;
      moment += v * (p0 + p1 + p2) / 4.0;
    }
  }
  return {volume, apex + moment / volume};
}

/// visit(i, cell) for the cells of the seeds first, ..., end - 1 in turn, each made into one
/// Cell (its storage reused from one cell to the next), in the rounding mode of the caller.
template <class Visit>
void for_each_voronoi_cell(const std::vector<Vec3>& seeds, const Box& box, double accuracy, double margin,
                           std::size_t first, std::size_t end, Visit&& visit) {
  const auto nb = neighbours(seeds, static_cast<int>(first), static_cast<int>(end));
  const VertexMaker maker(seeds, box, accuracy);
  Cell c;
  for (std::size_t i = first; i < end; ++i) {
    {
      const CGAL::Protect_FPU_rounding<true> upward;  // interval arithmetic
      make_voronoi_cell(c, static_cast<int>(i), seeds, nb[i], maker, margin);
    }
    visit(i, c);
  }
}

/// The cells of every seed (their vertices and faces).
std::vector<Cell> voronoi_cells(const std::vector<Vec3>& seeds, const Box& box, double accuracy, double margin) {
  std::vector<Cell> cells;
  cells.reserve(seeds.size());
  for_each_voronoi_cell(seeds, box, accuracy, margin, 0, seeds.size(), [&](std::size_t, const Cell& c) {
    cells.emplace_back();
    cells.back().vertices = c.vertices;
    cells.back().faces = c.faces;
  });
  return cells;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[static_cast<std::size_t>(a)] != a) {
      parent[static_cast<std::size_t>(a)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(a)])];
      a = parent[static_cast<std::size_t>(a)];
    }
    return a;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

/// The cells' vertices of distinct keys, in order of first appearance walking the cells in
/// seed order, and each cell's faces by generator as (generator, vertex ids).
struct DistinctVertices {
  std::vector<Vec3> pos;
  std::vector<std::vector<std::pair<int, std::vector<int>>>> cell_faces;
};

DistinctVertices distinct_vertices(const std::vector<Cell>& cells) {
  std::unordered_map<Key, int, KeyHash> id_of;
  DistinctVertices out;
  std::vector<Vec3>& pos = out.pos;
  auto& cell_faces = out.cell_faces;
  cell_faces.resize(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    std::vector<Face> faces = cells[c].faces;
    std::sort(faces.begin(), faces.end(), [](const Face& x, const Face& y) { return x.generator < y.generator; });
    for (const Face& f : faces) {
      std::vector<int> ids;
      for (int v : f.loop) {
        const Vertex& vx = cells[c].vertices[static_cast<std::size_t>(v)];
        const auto [it, fresh] = id_of.try_emplace(vx.key, static_cast<int>(pos.size()));
        if (fresh) pos.push_back(vx.pos);
        ids.push_back(it->second);
      }
      cell_faces[c].emplace_back(f.generator, std::move(ids));
    }
  }
  return out;
}

/// Unites in `uf` the vertices closer than tol (neighbouring buckets of a grid of spacing tol);
/// returns each representative's position snapped onto the sides within tol.
std::vector<Vec3> merge_close_vertices(const std::vector<Vec3>& pos, const Box& box, double tol, UnionFind& uf) {
  const std::size_t np = pos.size();
  struct Bucket {
    std::int64_t i, j, k;
    bool operator==(const Bucket&) const = default;
  };
  struct BucketHash {
    std::size_t operator()(const Bucket& b) const noexcept {
      return static_cast<std::size_t>((static_cast<std::uint64_t>(b.i) * 73856093u) ^
                                      (static_cast<std::uint64_t>(b.j) * 19349663u) ^
                                      (static_cast<std::uint64_t>(b.k) * 83492791u));
    }
  };
  auto bucket_of = [&](const Vec3& p) {
    return Bucket{static_cast<std::int64_t>(std::floor((p.x() - box.x0) / tol)),
                  static_cast<std::int64_t>(std::floor((p.y() - box.y0) / tol)),
                  static_cast<std::int64_t>(std::floor((p.z() - box.z0) / tol))};
  };
  std::unordered_map<Bucket, std::vector<int>, BucketHash> grid;
  for (std::size_t p = 0; p < np; ++p) grid[bucket_of(pos[p])].push_back(static_cast<int>(p));
  for (std::size_t p = 0; p < np; ++p) {
    const Bucket b = bucket_of(pos[p]);
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
        for (std::int64_t dk = -1; dk <= 1; ++dk) {
          const auto it = grid.find(Bucket{b.i + di, b.j + dj, b.k + dk});
          if (it == grid.end()) continue;
          for (int q : it->second)
            if (q > static_cast<int>(p) && (pos[static_cast<std::size_t>(q)] - pos[p]).norm() < tol)
              uf.unite(static_cast<int>(p), q);
        }
  }
  std::vector<Vec3> merged(np);
  for (std::size_t p = 0; p < np; ++p) {
    if (uf.find(static_cast<int>(p)) != static_cast<int>(p)) continue;
    Vec3 x = pos[p];
    for (int a = 0; a < 3; ++a) {
      if (std::abs(x[a] - box.lower(a)) <= tol) x[a] = box.lower(a);
      if (std::abs(x[a] - box.upper(a)) <= tol) x[a] = box.upper(a);
    }
    merged[p] = x;
  }
  return merged;
}

/// Throws unless the face between two cells is one loop, reversed. `by_neighbour`: per cell,
/// its faces by the neighbour across them.
void check_shared_faces(const std::vector<std::map<int, std::vector<int>>>& by_neighbour) {
  const std::size_t cells = by_neighbour.size();
  for (std::size_t c = 0; c < cells; ++c)
    for (const auto& [d, loop] : by_neighbour[c]) {
      const auto& other = by_neighbour[static_cast<std::size_t>(d)];
      const auto it = other.find(static_cast<int>(c));
      bool same = it != other.end() && it->second.size() == loop.size();
      if (same) {
        std::vector<int> rev(loop.rbegin(), loop.rend());
        const auto at = std::find(rev.begin(), rev.end(), it->second.front());
        same = at != rev.end();
        if (same) {
          std::rotate(rev.begin(), at, rev.end());
          same = rev == it->second;
        }
      }
      if (!same)
        throw NumericalError("voronoi mesh: the cells of seeds " + std::to_string(c) + " and " + std::to_string(d) +
                             " disagree on their common face (a degenerate configuration of seeds)");
    }
}

/// The mesh of the cells: vertices of equal keys are one; vertices closer than tol are
/// merged (to the position of the first one met) and then snapped onto the sides within tol;
/// repeated consecutive vertices of a face are dropped and so are faces left with fewer than
/// three. Vertices are numbered in order of first appearance walking the cells in seed order,
/// their faces by generator (sides, then neighbours by index), each face from its
/// lexicographically smallest vertex: the mesh's vertices and cells (voronoi_mesh makes it).
detail::SolidCells voronoi_lists(const std::vector<Cell>& cells, const Box& box, double tol) {
  const DistinctVertices distinct = distinct_vertices(cells);
  const std::vector<Vec3>& pos = distinct.pos;
  const auto& cell_faces = distinct.cell_faces;
  const std::size_t np = pos.size();
  UnionFind uf(np);
  const std::vector<Vec3> merged = merge_close_vertices(pos, box, tol, uf);

  // faces of merged vertices; number the vertices
  std::vector<int> number(np, -1);
  std::vector<Vec3> vertices;
  std::vector<CellFaces> out(cells.size());
  std::vector<std::map<int, std::vector<int>>> by_neighbour(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (const auto& [generator, ids] : cell_faces[c]) {
      std::vector<int> loop;
      for (int id : ids) {
        const int r = uf.find(id);
        if (loop.empty() || loop.back() != r) loop.push_back(r);
      }
      while (loop.size() > 1 && loop.back() == loop.front()) loop.pop_back();
      if (loop.size() < 3) continue;
      const auto first = std::min_element(loop.begin(), loop.end(), [&](int x, int y) {
        return lex_less(merged[static_cast<std::size_t>(x)], merged[static_cast<std::size_t>(y)]);
      });
      std::rotate(loop.begin(), first, loop.end());
      for (int& v : loop) {
        int& n = number[static_cast<std::size_t>(v)];
        if (n < 0) {
          n = static_cast<int>(vertices.size());
          vertices.push_back(merged[static_cast<std::size_t>(v)]);
        }
        v = n;
      }
      if (generator >= 0) by_neighbour[c][generator] = loop;
      out[c].push_back(std::move(loop));
    }
  }
  check_shared_faces(by_neighbour);
  return {std::move(vertices), std::move(out)};
}

/// make(), the mesh of Voronoi cells (or a piece of it), its MeshError a NumericalError.
template <class Make>
auto valid_voronoi(const Make& make) {
  try {
    return make();
  } catch (const MeshError& err) {
    throw NumericalError("voronoi mesh: the Voronoi cells do not make a valid mesh (a degenerate configuration of "
                         "seeds): " +
                         err.detail());
  }
}

/// The power of two k such that a box of this size, divided by 2^k, is about unit size; 0
/// when the box is used as it is (as the 2D generator: scaling by 2^k is exact).
int unit_scale_exponent(double size, double magnitude) {
  if (size >= 1e-30 && magnitude <= 1e30) return 0;
  return std::ilogb(size);
}

/// make_voronoi3d's Lloyd iterations (collective over options.processes), then what makes its
/// vertices and cells of the seeds they end with, before its mesh is made (every seed's cell:
/// one process's work, called by any number of them).
std::function<detail::SolidCells()> voronoi_box_seeds(GridSize3 n, const Box& domain, const VoronoiOptions& options) {
  check_input(n, domain, options);
  if (const int k = unit_scale_exponent(box_largest_side(domain), box_magnitude(domain))) {
    const Box unit{std::ldexp(domain.x0, -k), std::ldexp(domain.x1, -k), std::ldexp(domain.y0, -k),
                   std::ldexp(domain.y1, -k), std::ldexp(domain.z0, -k), std::ldexp(domain.z1, -k)};
    return [unit_lists = voronoi_box_seeds(n, unit, options), k] {
      detail::SolidCells lists = unit_lists();
      for (auto& v : lists.vertices) v = Vec3(std::ldexp(v.x(), k), std::ldexp(v.y(), k), std::ldexp(v.z(), k));
      return lists;
    };
  }

  const std::size_t ns = static_cast<std::size_t>(n.nx) * static_cast<std::size_t>(n.ny) * static_cast<std::size_t>(n.nz);
  const double volume = domain.size(0) * domain.size(1) * domain.size(2);
  const double spacing = std::cbrt(volume / static_cast<double>(ns));
  const double magnitude = box_magnitude(domain);
  // Merge / snap tolerance: 1e-10 of the seed spacing, and above the round-off of the
  // coordinates. Moving a vertex by tol moves it off the plane of a face of diameter D by
  // about tol / D of D: well inside the planarity tolerance 1e-8 for every face but those
  // smaller than about 1e-2 of the spacing that touch a merged vertex.
  const double tol = std::max(1e-10 * spacing, 64.0 * std::numeric_limits<double>::epsilon() * magnitude);
  const double accuracy = tol / 64.0;  // of the rounded vertex positions
  const double margin = 2.0 * accuracy + 4.0 * std::numeric_limits<double>::epsilon() * (magnitude + box_largest_side(domain));

  std::mt19937_64 rng(options.seed);
  std::vector<Vec3> seeds(ns);
  for (auto& s : seeds) {
    const double x = open_draw(rng, domain.x0, domain.x1);
    const double y = open_draw(rng, domain.y0, domain.y1);
    s = Vec3(x, y, open_draw(rng, domain.z0, domain.z1));
  }
  // Seeds along a Hilbert curve: nearby cells get nearby numbers (Lloyd moves seeds little).
  detail::sort_along_hilbert_curve(seeds, domain);
  // the seeds whose cells this process computes in the Lloyd iterations (all in one process)
  const std::pair<std::size_t, std::size_t> share = share_of(ns, options.processes);
  const std::size_t first = share.first, end = share.second;
  const double stop = options.lloyd_tolerance * spacing;
  for (int it = 0; it < options.max_lloyd_iterations; ++it) {
    Eigen::VectorXd centroids(3 * static_cast<Eigen::Index>(end - first));
    for_each_voronoi_cell(seeds, domain, accuracy, margin, first, end, [&](std::size_t i, const Cell& cell) {
      Vec3 g = volume_centroid(cell, seeds[i]).second;
      // the centroid of a cell lies inside it; keep it strictly inside the box anyway
      for (int a = 0; a < 3; ++a)
        g[a] = std::clamp(g[a], std::nextafter(domain.lower(a), domain.upper(a)),
                          std::nextafter(domain.upper(a), domain.lower(a)));
      centroids.segment<3>(3 * static_cast<Eigen::Index>(i - first)) = g;
    });
    const Eigen::VectorXd all = options.processes ? options.processes->all_gather(centroids) : centroids;
    if (all.size() != 3 * static_cast<Eigen::Index>(ns)) throw InternalError("voronoi mesh: the processes' centroids");
    double moved = 0.0;
    for (std::size_t i = 0; i < ns; ++i) {
      const Vec3 g = all.segment<3>(3 * static_cast<Eigen::Index>(i));
      moved = std::max(moved, (g - seeds[i]).norm());
      seeds[i] = g;
    }
    if (moved <= stop) break;
  }
  return [seeds = std::move(seeds), domain, accuracy, margin, tol] {
    return voronoi_lists(voronoi_cells(seeds, domain, accuracy, margin), domain, tol);
  };
}

/// make_voronoi3d's vertices and cells, before its mesh is made.
detail::SolidCells voronoi_box_lists(GridSize3 n, const Box& domain, const VoronoiOptions& options) {
  return voronoi_box_seeds(n, domain, options)();
}

}  // namespace

Mesh3D make_voronoi3d(GridSize3 n, const Box& domain, const VoronoiOptions& options) {
  detail::SolidCells lists = voronoi_box_lists(n, domain, options);
  return valid_voronoi([&] { return Mesh3D(std::move(lists.vertices), std::move(lists.cells)); });
}

MeshPieceRead<Mesh3D> make_voronoi3d_piece(GridSize3 n, const Box& domain, const VoronoiOptions& options, int rank,
                                           int size, HeldPoints held) {
  const detail::SolidCells lists = voronoi_box_lists(n, domain, options);
  MeshPieceRead<Mesh3D> out;
  valid_voronoi([&] {
    detail::make_solid_piece(lists, held, rank, size, out);
    return 0;
  });
  return out;
}

MeshPieceRead<Mesh3D> make_voronoi3d_piece(GridSize3 n, const Box& domain, const RowDistribution& processes,
                                           VoronoiOptions options, HeldPoints held, const BoundaryPick<Mesh3D>& pick) {
  options.processes = &processes;
  const std::function<detail::SolidCells()> lists = voronoi_box_seeds(n, domain, options);
  return valid_voronoi([&] {
    return detail::lists_piece_by_first<Mesh3D, detail::SolidCells>(
        processes, lists, held, pick, [](detail::SolidCells&& cells) {
          valid_voronoi([&] { return Mesh3D(std::move(cells.vertices), std::move(cells.cells)); });
        });
  });
}

namespace {

/// MeshLists of the Voronoi cells `lists`, their defects named by valid_voronoi.
MeshLists<Mesh3D> voronoi_mesh_lists(std::shared_ptr<const detail::SolidCells> lists) {
  return {static_cast<int>(lists->vertices.size()),
          [lists](const std::vector<char>& owned, HeldPoints held) {
            MeshPieceRead<Mesh3D> out;
            valid_voronoi([&] {
              detail::make_solid_piece(*lists, owned, held, out);
              return 0;
            });
            return out;
          },
          [lists](int size, const std::function<std::vector<char>(int)>& owned, HeldPoints held,
                  const PieceDelivery<Mesh3D>& deliver) {
            detail::make_solid_pieces(*lists, held, detail::pieces_around<Mesh3D>(size, owned, deliver));
          },
          [lists] { valid_voronoi([&] { return Mesh3D(lists->vertices, lists->cells); }); }};
}

}  // namespace

MeshLists<Mesh3D> voronoi3d_lists(GridSize3 n, const Box& domain, const VoronoiOptions& options) {
  return voronoi_mesh_lists(std::make_shared<const detail::SolidCells>(voronoi_box_lists(n, domain, options)));
}

ListsOfFirst<Mesh3D> voronoi3d_lists_of_first(GridSize3 n, const Box& domain, const RowDistribution& processes,
                                              VoronoiOptions options) {
  options.processes = &processes;
  std::function<detail::SolidCells()> cells = voronoi_box_seeds(n, domain, options);
  return {[cells = std::move(cells)] { return voronoi_mesh_lists(std::make_shared<const detail::SolidCells>(cells())); }, {}};
}

}  // namespace hemivem
