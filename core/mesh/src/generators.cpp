#include <hemivem/mesh/generators.hpp>

#include <hemivem/mesh/boundary.hpp>

#include "box_grid.hpp"
#include "cell_topology.hpp"
#include "hilbert.hpp"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <span>
#include <sstream>
#include <utility>

namespace hemivem {

namespace {

/// Largest accepted n: keeps every vertex count of every generator well inside int.
constexpr int kMaxCellsPerSide = 20000;

/// Longest edge of a triangle in a polygon domain, in units of sqrt(area)/n.
constexpr double kTriangleEdgeFactor = 1.5;

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

void check_n(const char* generator, int n) {
  if (n < 1 || n > kMaxCellsPerSide)
    throw InputError(std::string(generator) + ": the number of cells per side n must be between 1 and " +
                     std::to_string(kMaxCellsPerSide) + " (got " + std::to_string(n) + ")");
}

void check_n(const char* generator, GridSize n) {
  if (n.nx == n.ny) return check_n(generator, n.nx);
  for (const int k : {n.nx, n.ny})
    if (k < 1 || k > kMaxCellsPerSide)
      throw InputError(std::string(generator) + ": the numbers of cells along x and y must be between 1 and " +
                       std::to_string(kMaxCellsPerSide) + " (got " + n.text() + ")");
}

void check_domain(const char* generator, const Rectangle& d, GridSize n) {
  const bool finite = std::isfinite(d.x0) && std::isfinite(d.x1) && std::isfinite(d.y0) && std::isfinite(d.y1) &&
                      std::isfinite(d.width()) && std::isfinite(d.height());
  const std::string got = " (got [" + fmt(d.x0) + ", " + fmt(d.x1) + "] x [" + fmt(d.y0) + ", " + fmt(d.y1) + "])";
  if (!finite || !(d.x1 > d.x0) || !(d.y1 > d.y0))
    throw InputError(std::string(generator) +
                     ": the domain must be a rectangle [x0,x1] x [y0,y1] with finite x0 < x1 and y0 < y1" + got);
  const double scale = std::max({std::abs(d.x0), std::abs(d.x1), std::abs(d.y0), std::abs(d.y1)});
  if (scale > max_mesh_coordinate)
    throw InputError(std::string(generator) + ": the domain's coordinates must be at most 1e150 in magnitude" + got);
  // Cells must be resolvable: a cell side well above the spacing of doubles at the domain's
  // coordinates, and a cell area that is a normal double.
  const double cw = d.width() / n.nx, ch = d.height() / n.ny;
  if (!(std::min(cw, ch) >= 1e-9 * scale) || !(cw * ch >= 1e-250))
    throw InputError(std::string(generator) + ": the cells of the domain with n = " + n.text() +
                     " are too small for double precision (cell sides must be at least 1e-9 of the largest |coordinate|"
                     " and the cell area at least 1e-250)" + got);
}

/// The point i/n of the way from a to b: a + (b - a) * i / n, and exactly b for i == n.
double grid_coordinate(double a, double b, long i, long n) {
  if (i == n) return b;
  return a + (b - a) * static_cast<double>(i) / static_cast<double>(n);
}

/// A double in [0, 1) from the top 53 bits of one 64-bit draw (portable, unlike
/// std::uniform_real_distribution).
double unit_draw(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// A double in the open interval (a, b).
double open_draw(std::mt19937_64& rng, double a, double b) {
  const double u = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;  // in (0, 1)
  const double x = a + (b - a) * u;
  if (x <= a) return std::nextafter(a, b);
  if (x >= b) return std::nextafter(b, a);
  return x;
}

/// (nx+1)(ny+1) grid points, vertex (i, j) at index j*(nx+1) + i.
std::vector<Vec2> grid_vertices(GridSize n, const Rectangle& d) {
  std::vector<Vec2> v;
  v.reserve(static_cast<std::size_t>(n.nx + 1) * static_cast<std::size_t>(n.ny + 1));
  for (int j = 0; j <= n.ny; ++j) {
    const double y = grid_coordinate(d.y0, d.y1, j, n.ny);
    for (int i = 0; i <= n.nx; ++i) v.emplace_back(grid_coordinate(d.x0, d.x1, i, n.nx), y);
  }
  return v;
}

/// The fraction of a box's sides by which the distorted generator moves each vertex inside.
constexpr double distorted_fraction = 0.2;

/// The grid points of grid_vertices, each inside the domain moved by up to `fraction` of a box's
/// sides along each axis, drawn from `seed` vertex by vertex (a distorted mesh's vertices).
std::vector<Vec2> distorted_vertices(GridSize n, double fraction, const Rectangle& domain, std::uint64_t seed) {
  if (!(fraction >= 0.0 && fraction < 0.5))
    throw InputError("distorted mesh: fraction must be in [0, 0.5) (got " + fmt(fraction) + ")");
  std::vector<Vec2> v = grid_vertices(n, domain);
  const double ax = fraction * (domain.width() / n.nx), ay = fraction * (domain.height() / n.ny);
  std::mt19937_64 rng(seed);
  for (int j = 1; j < n.ny; ++j)
    for (int i = 1; i < n.nx; ++i) {
      Vec2& p = v[static_cast<std::size_t>(j) * static_cast<std::size_t>(n.nx + 1) + static_cast<std::size_t>(i)];
      const double dx = ax * (2.0 * unit_draw(rng) - 1.0);
      const double dy = ay * (2.0 * unit_draw(rng) - 1.0);
      p += Vec2(dx, dy);
    }
  return v;
}

/// The nonconvex generator's grid: the points of the grid twice as fine as n, but the boxes'
/// centres and the mid-points of the boundary's boxes' sides, numbered as BoxGridVertices numbers
/// them, each mid-point moved a quarter of a box's side along each axis; each box an octagon of the
/// points around it (a nonconvex hexagon along the boundary, a nonconvex octagon inside).
struct NonconvexGrid {
  BoxGridVertices numbering;
  std::vector<Vec2> vertices;

  NonconvexGrid(GridSize n, const Rectangle& domain) : numbering("nonconvex", 2, {n.nx, n.ny, 1}) {
    const int mx = 2 * n.nx, my = 2 * n.ny;  // fine grid: points (i, j), 0 <= i <= mx, 0 <= j <= my
    vertices.reserve(static_cast<std::size_t>(numbering.count()));
    for (long long v = 0; v < numbering.count(); ++v) {
      const auto [i, j] = numbering.fine_point(v);
      if ((i + j) % 2 == 0) {
        vertices.emplace_back(grid_coordinate(domain.x0, domain.x1, static_cast<int>(i), mx),
                              grid_coordinate(domain.y0, domain.y1, static_cast<int>(j), my));
      } else {
        // i/(2N) plus a quarter macro cell 1/(4N): (2i+1)/(4N), never the far side
        vertices.emplace_back(grid_coordinate(domain.x0, domain.x1, static_cast<int>(2 * i + 1), 2 * mx),
                              grid_coordinate(domain.y0, domain.y1, static_cast<int>(2 * j + 1), 2 * my));
      }
    }
  }

  /// The cells of the boxes `keep` makes, box by box (x fastest).
  std::vector<std::vector<int>> cells(GridSize n, const detail::PieceBoxes& keep = {}) const {
    std::vector<std::vector<int>> elements;
    for (int J = 0; J < n.ny; ++J)
      for (int I = 0; I < n.nx; ++I) {
        if (!keep(I, J, 0)) continue;
        const long long i = 2 * I, j = 2 * J;
        const long long ring[8][2] = {{i, j},         {i + 1, j},     {i + 2, j}, {i + 2, j + 1},
                                      {i + 2, j + 2}, {i + 1, j + 2}, {i, j + 2}, {i, j + 1}};
        std::vector<int> el;
        el.reserve(8);
        for (const auto& p : ring)
          if (const long long v = numbering.fine_vertex(p[0], p[1]); v >= 0) el.push_back(static_cast<int>(v));
        elements.push_back(std::move(el));
      }
    return elements;
  }
};

std::vector<std::vector<int>> grid_squares(GridSize n, const detail::PieceBoxes& keep = {}) {
  std::vector<std::vector<int>> e;
  e.reserve(static_cast<std::size_t>(n.nx) * static_cast<std::size_t>(n.ny));
  for (int j = 0; j < n.ny; ++j)
    for (int i = 0; i < n.nx; ++i) {
      if (!keep(i, j, 0)) continue;
      const int a = j * (n.nx + 1) + i;
      e.push_back({a, a + 1, a + n.nx + 2, a + n.nx + 1});
    }
  return e;
}

/// Each rectangle of the grid split by its lower-left -> upper-right diagonal (make_triangles).
std::vector<std::vector<int>> grid_triangles(GridSize n, const detail::PieceBoxes& keep = {}) {
  std::vector<std::vector<int>> e;
  e.reserve(2 * static_cast<std::size_t>(n.nx) * static_cast<std::size_t>(n.ny));
  for (int j = 0; j < n.ny; ++j)
    for (int i = 0; i < n.nx; ++i) {
      if (!keep(i, j, 0)) continue;
      const int a = j * (n.nx + 1) + i;
      e.push_back({a, a + 1, a + n.nx + 2});         // below the diagonal
      e.push_back({a, a + n.nx + 2, a + n.nx + 1});  // above the diagonal
    }
  return e;
}

// ---- Voronoi ------------------------------------------------------------------------

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int id = -1;  // index of the face's circumcentre, -1 until computed
};
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;  // seed index, -1 for mirrors
using FaceBase = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

bool lex_less(const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); }

/// Exact circumcentre of a triangle (rational arithmetic), rounded to doubles.
Vec2 exact_circumcentre(const Vec2& a, const Vec2& b, const Vec2& c) {
  using Q = CGAL::Exact_rational;
  const Q ax(a.x()), ay(a.y());
  const Q ux = Q(b.x()) - ax, uy = Q(b.y()) - ay, vx = Q(c.x()) - ax, vy = Q(c.y()) - ay;
  Q den = ux * vy - uy * vx;
  den += den;
  const Q uu = ux * ux + uy * uy, vv = vx * vx + vy * vy;
  const Q x = ax + (vy * uu - uy * vv) / den, y = ay + (ux * vv - vx * uu) / den;
  return {CGAL::to_double(x), CGAL::to_double(y)};
}

/// Circumcentre of a triangle, computed from its vertices in lexicographic order so
/// the result does not depend on how the triangulation happens to store the face.
/// Falls back to exact arithmetic when the round-off bound of the floating-point formula
/// exceeds `accuracy` (skinny triangles: seeds very close to a side or to each other).
Vec2 circumcentre(Vec2 a, Vec2 b, Vec2 c, double accuracy) {
  if (lex_less(b, a)) std::swap(a, b);
  if (lex_less(c, b)) std::swap(b, c);
  if (lex_less(b, a)) std::swap(a, b);
  const double ux = b.x() - a.x(), uy = b.y() - a.y();
  const double vx = c.x() - a.x(), vy = c.y() - a.y();
  const double cross = ux * vy - uy * vx;
  const double den = 2.0 * cross;
  const double uu = ux * ux + uy * uy, vv = vx * vx + vy * vy;
  const double nx = vy * uu - uy * vv, ny = ux * vv - vx * uu;
  // first-order round-off bound of nx/den and ny/den (u = unit round-off)
  constexpr double u = 0.5 * std::numeric_limits<double>::epsilon();
  const double cond = (std::abs(ux * vy) + std::abs(uy * vx)) / std::abs(cross);
  const double ex = (8.0 * u * (std::abs(vy) * uu + std::abs(uy) * vv) + 6.0 * u * cond * std::abs(nx)) / std::abs(den);
  const double ey = (8.0 * u * (std::abs(ux) * vv + std::abs(vx) * uu) + 6.0 * u * cond * std::abs(ny)) / std::abs(den);
  if (!(ex <= accuracy && ey <= accuracy)) return exact_circumcentre(a, b, c);  // also catches 0/0
  return {a.x() + nx / den, a.y() + ny / den};
}

/// The index in `points` of the circumcentre of a face, computed and appended the first
/// time the face is asked (the face remembers it), so that all cells around it share it.
int circumcentre_id(Delaunay::Face_handle f, std::vector<Vec2>& points, double accuracy) {
  int& id = f->info().id;
  if (id < 0) {
    const auto& p0 = f->vertex(0)->point();
    const auto& p1 = f->vertex(1)->point();
    const auto& p2 = f->vertex(2)->point();
    id = static_cast<int>(points.size());
    points.push_back(circumcentre({p0.x(), p0.y()}, {p1.x(), p1.y()}, {p2.x(), p2.y()}, accuracy));
  }
  return id;
}

/// Voronoi cells of the seeds, clipped to the rectangle: cell i is the counter-clockwise
/// ring of circumcentres ids[offsets[i]] .. ids[offsets[i+1]-1].
struct VoronoiCells {
  std::vector<Vec2> points;
  std::vector<int> offsets;
  std::vector<int> ids;
};

/// The seeds a process's Voronoi cells are computed from (voronoi_cells of a range): the seeds
/// of the buckets (squares of side `h` over the rectangle) within `layers` buckets, along each
/// axis, of a bucket holding one of its own, and the distance `clearance` = layers h within which
/// of each of its own seeds every seed is among them.
struct SeedHalo {
  std::vector<char> included;  ///< one flag per seed
  double clearance = std::numeric_limits<double>::infinity();
};

SeedHalo seed_halo(const std::vector<Vec2>& seeds, const Rectangle& d, double h, std::size_t first, std::size_t end,
                   int layers) {
  const auto buckets_along = [&](double length) { return std::max(1, static_cast<int>(std::ceil(length / h))); };
  const int nx = buckets_along(d.width()), ny = buckets_along(d.height());
  const auto bucket = [&](const Vec2& p) {
    const int i = std::clamp(static_cast<int>(std::floor((p.x() - d.x0) / h)), 0, nx - 1);
    const int j = std::clamp(static_cast<int>(std::floor((p.y() - d.y0) / h)), 0, ny - 1);
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
  };
  std::vector<char> near(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
  for (std::size_t i = first; i < end; ++i) near[bucket(seeds[i])] = 1;
  // widened by `layers` along x, then along y
  const auto widen = [&](int count, int other, auto at) {
    std::vector<char> line(static_cast<std::size_t>(count));
    for (int o = 0; o < other; ++o) {
      int last = -1 - layers;  // the last marked position
      for (int c = 0; c < count; ++c) {
        if (at(c, o)) last = c;
        line[static_cast<std::size_t>(c)] = c - last <= layers;
      }
      last = count + layers;
      for (int c = count - 1; c >= 0; --c) {
        if (at(c, o)) last = c;
        if (last - c <= layers) line[static_cast<std::size_t>(c)] = 1;
      }
      for (int c = 0; c < count; ++c) at(c, o) = line[static_cast<std::size_t>(c)];
    }
  };
  widen(nx, ny, [&](int c, int o) -> char& { return near[static_cast<std::size_t>(o) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(c)]; });
  widen(ny, nx, [&](int c, int o) -> char& { return near[static_cast<std::size_t>(c) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(o)]; });
  SeedHalo halo;
  halo.included.resize(seeds.size());
  for (std::size_t i = 0; i < seeds.size(); ++i) halo.included[i] = near[bucket(seeds[i])];
  halo.clearance = layers * h;
  return halo;
}

/// Computes the cells of the seeds first, ..., end - 1 (out's cell k the seed first + k) using
/// the seeds `halo` includes (all when its flags are empty) and the reflections of those lying
/// closer than `reach` to a side (across that side). Returns false when that set of seeds and
/// reflections may be too small, i.e. when a cell is unbounded, leaves the rectangle, comes within
/// `tol` of a side across which its seed was not reflected, or reaches farther from its seed than
/// half the halo's clearance. When every seed whose true cell touches a side is reflected across
/// it, every Delaunay neighbour of a seed is present and the cells are exact; a cell of a seed
/// missing a needed reflection is a strict superset of the true cell and reaches the side, so the
/// check catches every wrong result. A cell whose points lie within r of its seed is exact when
/// every seed within 2 r of it is present (a seed nearer a point of the cell than its own lies
/// so), the same cell as of every seed: the cell's points are the circumcentres of the same
/// faces, computed from their vertices alone (circumcentre), the same to the bit.
bool try_voronoi_cells(const std::vector<Vec2>& seeds, const Rectangle& d, double reach, double tol, std::size_t first,
                       std::size_t end, const SeedHalo& halo, VoronoiCells& out) {
  const std::size_t ns = seeds.size();
  const auto in = [&](std::size_t i) { return halo.included.empty() || halo.included[i] != 0; };
  std::vector<std::pair<Kernel::Point_2, int>> pts;
  pts.reserve(ns + ns / 4);
  std::vector<unsigned char> mirrored(ns, 0);  // bit 0: x0, 1: x1, 2: y0, 3: y1
  for (std::size_t i = 0; i < ns; ++i)
    if (in(i)) pts.emplace_back(Kernel::Point_2(seeds[i].x(), seeds[i].y()), static_cast<int>(i));
  // side s: 0 x = x0, 1 x = x1, 2 y = y0, 3 y = y1; one side after the other, so that
  // consecutive insertions stay close
  for (unsigned s = 0; s < 4; ++s) {
    const double side = s == 0 ? d.x0 : s == 1 ? d.x1 : s == 2 ? d.y0 : d.y1;
    for (std::size_t i = 0; i < ns; ++i) {
      if (!in(i)) continue;
      const double x = seeds[i].x(), y = seeds[i].y();
      const double t = s < 2 ? x : y;
      if (std::abs(t - side) >= reach) continue;
      const double r = 2.0 * side - t;
      pts.emplace_back(s < 2 ? Kernel::Point_2(r, y) : Kernel::Point_2(x, r), -1);
      mirrored[i] |= static_cast<unsigned char>(1u << s);
    }
  }
  // The seeds are in Hilbert order (and so are the reflections of each side), so inserting
  // them one by one, each located from the previous one, is fast.
  Delaunay dt;
  std::vector<Delaunay::Vertex_handle> handle(ns);
  Delaunay::Face_handle hint;
  for (const auto& [p, info] : pts) {
    const auto v = dt.insert(p, hint);
    v->info() = info;
    hint = v->face();
    if (info >= 0) handle[static_cast<std::size_t>(info)] = v;
  }
  if (dt.number_of_vertices() != pts.size())
    throw NumericalError("voronoi mesh: two seeds coincide; the Voronoi diagram is undefined");
  if (dt.dimension() < 2) return false;  // all points on a line: no bounded cell

  out.points.clear();
  out.ids.clear();
  out.offsets.assign(1, 0);
  out.points.reserve(2 * (end - first) + 64);
  out.ids.reserve(6 * (end - first) + 64);
  for (std::size_t i = first; i < end; ++i) {
    auto fc = dt.incident_faces(handle[i]);
    const auto done = fc;
    do {
      if (dt.is_infinite(fc)) return false;
      out.ids.push_back(circumcentre_id(fc, out.points, tol / 64));
    } while (++fc != done);
    out.offsets.push_back(static_cast<int>(out.ids.size()));

    const std::size_t k0 = static_cast<std::size_t>(out.offsets[i - first]), k1 = static_cast<std::size_t>(out.offsets[i - first + 1]);
    for (std::size_t k = k0; k < k1; ++k) {
      const Vec2& p = out.points[static_cast<std::size_t>(out.ids[k])];
      if (!(2.0 * (p - seeds[i]).norm() <= halo.clearance)) return false;
      const double gap[4] = {p.x() - d.x0, d.x1 - p.x(), p.y() - d.y0, d.y1 - p.y()};
      for (int s = 0; s < 4; ++s) {
        if (gap[s] < -tol) return false;
        if (!(mirrored[i] & (1u << s)) && gap[s] <= tol) return false;
      }
    }
  }
  return true;
}

/// The cells of the seeds first, ..., end - 1 (all by default; out's cell k the seed first + k),
/// the same to the bit whichever range holds them: a range's are computed from the seeds around
/// it alone (seed_halo), widened until every cell is exact.
VoronoiCells voronoi_cells(const std::vector<Vec2>& seeds, const Rectangle& d, double spacing, double tol,
                           std::size_t first = 0, std::size_t end = std::numeric_limits<std::size_t>::max()) {
  end = std::min(end, seeds.size());
  VoronoiCells cells;
  const double everything = std::max(d.width(), d.height());
  const bool whole = first == 0 && end == seeds.size();
  for (double reach = 4.0 * spacing, layers = 8;; reach *= 2.0, layers *= 2) {
    const bool all = reach > everything;
    const bool around = whole || layers * spacing > 2.0 * everything;
    const SeedHalo halo = around ? SeedHalo{} : seed_halo(seeds, d, spacing, first, end, static_cast<int>(layers));
    if (try_voronoi_cells(seeds, d, all ? std::numeric_limits<double>::infinity() : reach, tol, first, end, halo, cells))
      return cells;
    if (all && around)
      throw NumericalError("voronoi mesh: a Voronoi cell leaves the rectangle even with every seed reflected");
  }
}

/// Centroid of the polygon pts[ids[0]], ..., pts[ids[m-1]], summed from its
/// lexicographically smallest vertex so that the result does not depend on where the
/// ring starts.
Vec2 polygon_centroid(const std::vector<Vec2>& pts, const int* ids, int m) {
  auto at = [&](int k) -> const Vec2& { return pts[static_cast<std::size_t>(ids[k % m])]; };
  int s = 0;
  for (int k = 1; k < m; ++k)
    if (lex_less(at(k), at(s))) s = k;
  const Vec2 o = at(s);
  double twice = 0.0;
  Vec2 moment = Vec2::Zero();
  for (int k = 1; k + 1 < m; ++k) {
    const Vec2 a = at(s + k) - o, b = at(s + k + 1) - o;
    const double cr = a.x() * b.y() - a.y() * b.x();
    twice += cr;
    moment += cr * (a + b);
  }
  return o + moment / (3.0 * twice);
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

/// Turns the cells into a mesh: merges circumcentres of adjacent faces closer than tol
/// (mirror symmetry makes cocircular quadruples, so one Voronoi vertex can come out as two
/// almost equal circumcentres), moves each merged vertex to snap(position) (exactly onto
/// the domain's sides or corners), drops cells that collapse to fewer than three vertices
/// when drop_collapsed (else throws),
/// numbers vertices in order of first appearance, each cell starting at its
/// lexicographically smallest vertex: the mesh's vertices and elements.
template <class Snap>
detail::PlaneCells voronoi_lists(const VoronoiCells& c, double tol, Snap snap, bool drop_collapsed) {
  const std::size_t np = c.points.size();
  const std::size_t ncell = c.offsets.size() - 1;
  const double tol2 = tol * tol;
  UnionFind uf(np);
  for (std::size_t i = 0; i < ncell; ++i) {
    const int b = c.offsets[i], m = c.offsets[i + 1] - b;
    for (int k = 0; k < m; ++k) {
      const int p = c.ids[static_cast<std::size_t>(b + k)], q = c.ids[static_cast<std::size_t>(b + (k + 1) % m)];
      if ((c.points[static_cast<std::size_t>(p)] - c.points[static_cast<std::size_t>(q)]).squaredNorm() < tol2)
        uf.unite(p, q);
    }
  }
  // One position per class: its lexicographically smallest member, snapped onto the sides.
  std::vector<Vec2> pos(np);
  std::vector<char> seen(np, 0);
  for (std::size_t p = 0; p < np; ++p) {
    const auto r = static_cast<std::size_t>(uf.find(static_cast<int>(p)));
    if (!seen[r] || lex_less(c.points[p], pos[r])) pos[r] = c.points[p];
    seen[r] = 1;
  }
  for (std::size_t r = 0; r < np; ++r) {
    if (!seen[r] || uf.parent[r] != static_cast<int>(r)) continue;
    pos[r] = snap(pos[r]);
  }
  // Classes that landed on the same position (e.g. two near-corner points) are one vertex.
  std::map<std::pair<double, double>, int> at;
  std::vector<int> key(np, -1);
  for (std::size_t r = 0; r < np; ++r) {
    if (!seen[r] || uf.parent[r] != static_cast<int>(r)) continue;
    key[r] = at.try_emplace({pos[r].x(), pos[r].y()}, static_cast<int>(r)).first->second;
  }

  std::vector<int> number(np, -1);
  std::vector<Vec2> vertices;
  std::vector<std::vector<int>> elements(ncell);
  std::vector<int> ring;
  for (std::size_t i = 0; i < ncell; ++i) {
    ring.clear();
    for (int k = c.offsets[i]; k < c.offsets[i + 1]; ++k) {
      const int v = key[static_cast<std::size_t>(uf.find(c.ids[static_cast<std::size_t>(k)]))];
      if (ring.empty() || ring.back() != v) ring.push_back(v);
    }
    while (ring.size() > 1 && ring.back() == ring.front()) ring.pop_back();
    if (ring.size() < 3 && drop_collapsed) continue;
    if (ring.size() < 3)
      throw NumericalError("voronoi mesh: the cell of seed " + std::to_string(i) + " collapsed to " +
                           std::to_string(ring.size()) + " vertices");
    const auto first = std::min_element(ring.begin(), ring.end(), [&](int a, int b) {
      return lex_less(pos[static_cast<std::size_t>(a)], pos[static_cast<std::size_t>(b)]);
    });
    std::rotate(ring.begin(), first, ring.end());
    auto& el = elements[i];
    el.reserve(ring.size());
    for (int v : ring) {
      int& num = number[static_cast<std::size_t>(v)];
      if (num < 0) {
        num = static_cast<int>(vertices.size());
        vertices.push_back(pos[static_cast<std::size_t>(v)]);
      }
      el.push_back(num);
    }
  }
  if (drop_collapsed)
    elements.erase(std::remove_if(elements.begin(), elements.end(), [](const auto& el) { return el.empty(); }),
                   elements.end());
  return {std::move(vertices), std::move(elements)};
}

void check_voronoi_options(const VoronoiOptions& options) {
  if (options.max_lloyd_iterations < 0)
    throw InputError("voronoi mesh: max_lloyd_iterations must be >= 0 (got " +
                     std::to_string(options.max_lloyd_iterations) + ")");
  if (!(options.lloyd_tolerance >= 0.0) || !std::isfinite(options.lloyd_tolerance))
    throw InputError("voronoi mesh: lloyd_tolerance must be finite and >= 0 (got " + fmt(options.lloyd_tolerance) +
                     ")");
}

}  // namespace

namespace {

/// The power of two k such that a domain of this size, divided by 2^k, is about unit size;
/// 0 when CGAL meshes the domain as it is. Delaunay predicates and constructions raise
/// coordinates to the fourth power: beyond about 1e70 they overflow, below about 1e-70 they
/// underflow. Scaling by a power of two is exact, so the mesh in scaled coordinates maps back
/// to the one the generator would make in exact range, sides and corners exactly in place.
int unit_scale_exponent(double size, double magnitude) {
  if (size >= 1e-30 && magnitude <= 1e30) return 0;
  return std::ilogb(size);
}

}  // namespace

std::string GridSize::text() const {
  return nx == ny ? std::to_string(nx) : "[" + std::to_string(nx) + ", " + std::to_string(ny) + "]";
}

Mesh make_squares(GridSize n, const Rectangle& domain) {
  check_n("squares mesh", n);
  check_domain("squares mesh", domain, n);
  return Mesh(grid_vertices(n, domain), grid_squares(n));
}



Mesh make_triangles(GridSize n, const Rectangle& domain) {
  check_n("triangles mesh", n);
  check_domain("triangles mesh", domain, n);
  return Mesh(grid_vertices(n, domain), grid_triangles(n));
}

Mesh make_mesh_piece(std::string_view generator, GridSize n, const Rectangle& domain, const BoxPiece& piece,
                     std::uint64_t seed) {
  detail::require_piece_generator(generator, 2);
  const std::string what = std::string(generator) + " mesh";
  check_n(what.c_str(), n);
  check_domain(what.c_str(), domain, n);
  const detail::PieceBoxes keep(generator, 2, {n.nx, n.ny, 1}, piece);
  if (generator == "distorted") return Mesh(distorted_vertices(n, distorted_fraction, domain, seed), grid_squares(n, keep));
  if (generator == "nonconvex") {
    NonconvexGrid grid(n, domain);
    std::vector<std::vector<int>> cells = grid.cells(n, keep);
    return Mesh(std::move(grid.vertices), std::move(cells));
  }
  return Mesh(grid_vertices(n, domain), generator == "squares" ? grid_squares(n, keep) : grid_triangles(n, keep));
}

namespace {

/// voronoi_cells of the seeds first, ..., end - 1 on one of `processes` (or in one process): a
/// process's cells, computed from the seeds around its own, may meet two coincident seeds that
/// another's do not, so every process learns of it before the next collective call and stops
/// with an error.
VoronoiCells shared_voronoi_cells(const std::vector<Vec2>& seeds, const Rectangle& d, double spacing, double tol,
                                  std::size_t first, std::size_t end, const RowDistribution* processes) {
  if (!processes) return voronoi_cells(seeds, d, spacing, tol, first, end);
  VoronoiCells out;
  std::string error;
  try {
    out = voronoi_cells(seeds, d, spacing, tol, first, end);
  } catch (const NumericalError& e) {
    error = e.what();
  }
  if (processes->max(error.empty() ? 0.0 : 1.0) > 0.0)
    throw NumericalError(error.empty() ? "voronoi mesh: the seeds' Voronoi cells failed on another process" : error);
  return out;
}

/// The centroid of each of the cells, (x, y) one after the other, strictly inside the rectangle
/// (as a cell's centroid lies inside it, but for round-off).
Eigen::VectorXd cell_centroids(const VoronoiCells& cells, const Rectangle& d) {
  const Eigen::Index count = static_cast<Eigen::Index>(cells.offsets.size()) - 1;
  Eigen::VectorXd centroids(2 * count);
  for (Eigen::Index k = 0; k < count; ++k) {
    const int b = cells.offsets[static_cast<std::size_t>(k)];
    Vec2 g = polygon_centroid(cells.points, cells.ids.data() + b, cells.offsets[static_cast<std::size_t>(k) + 1] - b);
    g.x() = std::clamp(g.x(), std::nextafter(d.x0, d.x1), std::nextafter(d.x1, d.x0));
    g.y() = std::clamp(g.y(), std::nextafter(d.y0, d.y1), std::nextafter(d.y1, d.y0));
    centroids.segment<2>(2 * k) = g;
  }
  return centroids;
}

}  // namespace

namespace {

/// make_voronoi's Lloyd iterations (collective over options.processes), then what makes its
/// vertices and elements of the seeds they end with, before its mesh is made (every seed's
/// cell: one process's work, called by any number of them).
std::function<detail::PlaneCells()> voronoi_rectangle_seeds(GridSize n, const Rectangle& domain,
                                                            const VoronoiOptions& options) {
  check_n("voronoi mesh", n);
  check_domain("voronoi mesh", domain, n);
  check_voronoi_options(options);
  if (const int k = unit_scale_exponent(std::max(domain.width(), domain.height()),
                                        std::max({std::abs(domain.x0), std::abs(domain.x1), std::abs(domain.y0),
                                                  std::abs(domain.y1)}))) {
    const Rectangle unit{std::ldexp(domain.x0, -k), std::ldexp(domain.x1, -k), std::ldexp(domain.y0, -k),
                         std::ldexp(domain.y1, -k)};
    return [unit_lists = voronoi_rectangle_seeds(n, unit, options), k] {
      detail::PlaneCells lists = unit_lists();
      for (auto& v : lists.vertices) v = Vec2(std::ldexp(v.x(), k), std::ldexp(v.y(), k));
      return lists;
    };
  }

  const std::size_t ns = static_cast<std::size_t>(n.nx) * static_cast<std::size_t>(n.ny);
  const double spacing = std::sqrt(domain.width() * domain.height() / static_cast<double>(ns));
  // Merge / snap tolerance: above the round-off of a circumcentre (relative to the
  // domain size and to the magnitude of the coordinates), and 1e-7 of the seed spacing so
  // that no edge is shorter than that (near-cocircular seeds are common after Lloyd).
  const double magnitude = std::max({std::abs(domain.x0), std::abs(domain.x1), std::abs(domain.y0), std::abs(domain.y1)});
  const double tol = std::max({1e-10 * std::max(domain.width(), domain.height()), 1e-7 * spacing,
                               64.0 * std::numeric_limits<double>::epsilon() * magnitude});

  std::mt19937_64 rng(options.seed);
  std::vector<Vec2> seeds(ns);
  for (auto& s : seeds) {
    const double x = open_draw(rng, domain.x0, domain.x1);
    s = Vec2(x, open_draw(rng, domain.y0, domain.y1));
  }

  // Number the seeds along a Hilbert curve: fast insertion, and nearby cells get nearby
  // element (and vertex) numbers. Lloyd moves seeds little, so the order stays good.
  detail::sort_along_hilbert_curve(seeds, domain);
  // the seeds whose cells this process computes in the Lloyd iterations (all in one process)
  const std::pair<std::size_t, std::size_t> share = share_of(ns, options.processes);
  const std::size_t first = share.first, end = share.second;
  const int iterations = options.max_lloyd_iterations;
  const auto cells_of = [&](std::size_t from, std::size_t to) {
    return shared_voronoi_cells(seeds, domain, spacing, tol, from, to, options.processes);
  };
  VoronoiCells cells = iterations > 0 ? cells_of(first, end) : VoronoiCells{};
  const double stop = options.lloyd_tolerance * spacing;
  for (int it = 0; it < iterations; ++it) {
    const Eigen::VectorXd centroids = cell_centroids(cells, domain);
    const Eigen::VectorXd all = options.processes ? options.processes->all_gather(centroids) : centroids;
    if (all.size() != 2 * static_cast<Eigen::Index>(ns)) throw InternalError("voronoi mesh: the processes' centroids");
    double moved = 0.0;
    for (std::size_t i = 0; i < ns; ++i) {
      const Vec2 g = all.segment<2>(2 * static_cast<Eigen::Index>(i));
      moved = std::max(moved, (g - seeds[i]).norm());
      seeds[i] = g;
    }
    if (moved <= stop || it + 1 == iterations) break;  // the cells of every seed make the mesh
    cells = cells_of(first, end);
  }
  return [seeds = std::move(seeds), domain, spacing, tol] {
    const auto snap_to_sides = [&](Vec2 p) {
      if (std::abs(p.x() - domain.x0) <= tol) p.x() = domain.x0;
      if (std::abs(p.x() - domain.x1) <= tol) p.x() = domain.x1;
      if (std::abs(p.y() - domain.y0) <= tol) p.y() = domain.y0;
      if (std::abs(p.y() - domain.y1) <= tol) p.y() = domain.y1;
      return p;
    };
    return voronoi_lists(voronoi_cells(seeds, domain, spacing, tol), tol, snap_to_sides, false);
  };
}

/// make_voronoi's vertices and elements, before its mesh is made.
detail::PlaneCells voronoi_rectangle_lists(GridSize n, const Rectangle& domain, const VoronoiOptions& options) {
  return voronoi_rectangle_seeds(n, domain, options)();
}

}  // namespace

Mesh make_voronoi(GridSize n, const Rectangle& domain, const VoronoiOptions& options) {
  detail::PlaneCells lists = voronoi_rectangle_lists(n, domain, options);
  return Mesh(std::move(lists.vertices), std::move(lists.elements));
}

MeshPieceRead<Mesh> make_voronoi_piece(GridSize n, const Rectangle& domain, const VoronoiOptions& options, int rank,
                                       int size, HeldPoints held) {
  const detail::PlaneCells lists = voronoi_rectangle_lists(n, domain, options);
  MeshPieceRead<Mesh> out;
  detail::make_plane_piece(lists, held, rank, size, out);
  return out;
}

namespace {

/// Throws the first defect of the plane mesh of `cells`, as its constructor names it.
void name_plane_defect(detail::PlaneCells&& cells) { (void)Mesh(std::move(cells.vertices), std::move(cells.elements)); }

}  // namespace

MeshPieceRead<Mesh> make_voronoi_piece(GridSize n, const Rectangle& domain, const RowDistribution& processes,
                                       VoronoiOptions options, HeldPoints held, const BoundaryPick<Mesh>& pick) {
  options.processes = &processes;
  const std::function<detail::PlaneCells()> lists = voronoi_rectangle_seeds(n, domain, options);
  return detail::lists_piece_by_first<Mesh, detail::PlaneCells>(processes, lists, held, pick, name_plane_defect);
}

MeshLists<Mesh> voronoi_lists(GridSize n, const Rectangle& domain, const VoronoiOptions& options) {
  return detail::plane_lists(std::make_shared<const detail::PlaneCells>(voronoi_rectangle_lists(n, domain, options)));
}

ListsOfFirst<Mesh> voronoi_lists_of_first(GridSize n, const Rectangle& domain, const RowDistribution& processes,
                                          VoronoiOptions options) {
  options.processes = &processes;
  std::function<detail::PlaneCells()> cells = voronoi_rectangle_seeds(n, domain, options);
  return {[cells = std::move(cells)] { return detail::plane_lists(std::make_shared<const detail::PlaneCells>(cells())); }, {}};
}

Mesh make_nonconvex(GridSize n, const Rectangle& domain) {
  check_n("nonconvex mesh", n);
  check_domain("nonconvex mesh", domain, n);
  NonconvexGrid grid(n, domain);
  std::vector<std::vector<int>> cells = grid.cells(n);
  return Mesh(std::move(grid.vertices), std::move(cells));
}

Mesh make_distorted(GridSize n, double fraction, const Rectangle& domain, std::uint64_t seed) {
  check_n("distorted mesh", n);
  check_domain("distorted mesh", domain, n);
  return Mesh(distorted_vertices(n, fraction, domain, seed), grid_squares(n));
}

const std::vector<std::string>& mesh_generator_names() {
  static const std::vector<std::string> names{"squares", "triangles", "voronoi", "nonconvex", "distorted"};
  return names;
}

Mesh make_mesh(std::string_view generator, GridSize n, const Rectangle& domain, std::uint64_t seed,
               const RowDistribution* processes) {
  if (generator == "squares") return make_squares(n, domain);
  if (generator == "triangles") return make_triangles(n, domain);
  if (generator == "voronoi") {
    VoronoiOptions options;
    options.seed = seed;
    options.processes = processes;
    return make_voronoi(n, domain, options);
  }
  if (generator == "nonconvex") return make_nonconvex(n, domain);
  if (generator == "distorted") return make_distorted(n, distorted_fraction, domain, seed);
  std::string valid;
  for (const auto& name : mesh_generator_names()) valid += (valid.empty() ? "" : ", ") + name;
  throw InputError("unknown mesh generator '" + std::string(generator) + "'; valid names: " + valid);
}


// ---- Polygon domains ----------------------------------------------------------------

namespace {

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactPolygon = CGAL::Polygon_2<ExactKernel>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<ExactKernel>;

/// A checked polygon domain: its corners counter-clockwise, the bounding box, the area and
/// the generator's length tolerance.
struct CheckedPolygon {
  std::vector<Vec2> corners;  ///< counter-clockwise
  Rectangle box;
  double area = 0.0;
  double tol = 0.0;
};

std::string point_text(const Vec2& p) { return "(" + fmt(p.x()) + ", " + fmt(p.y()) + ")"; }

/// The bounding box of position(*it) over [first, last) (not empty).
template <class It, class Position>
Rectangle bounding_box_of(It first, It last, Position position) {
  const Vec2& p0 = position(*first);
  Rectangle box{p0.x(), p0.x(), p0.y(), p0.y()};
  for (; first != last; ++first) {
    const Vec2& p = position(*first);
    box.x0 = std::min(box.x0, p.x());
    box.x1 = std::max(box.x1, p.x());
    box.y0 = std::min(box.y0, p.y());
    box.y1 = std::max(box.y1, p.y());
  }
  return box;
}

CheckedPolygon check_polygon(const char* generator, const PolygonDomain& d, int n) {
  const std::string defect = polygon_domain_defect(d);
  if (!defect.empty()) throw InputError(std::string(generator) + ": the polygon domain " + defect);
  const auto& c = d.corners;
  double magnitude = 0.0;
  for (const auto& p : c) magnitude = std::max({magnitude, std::abs(p.x()), std::abs(p.y())});
  CheckedPolygon out;
  out.corners = c;
  out.area = std::abs(signed_area(c));
  if (signed_area(c) < 0.0) std::reverse(out.corners.begin(), out.corners.end());
  out.box = bounding_box_of(c.begin(), c.end(), [](const Vec2& p) -> const Vec2& { return p; });
  const double spacing = std::sqrt(out.area) / n;
  if (!(out.area > 0.0) || !(spacing >= 1e-9 * magnitude) || !(spacing * spacing >= 1e-250))
    throw InputError(std::string(generator) + ": the cells of the polygon domain with n = " + std::to_string(n) +
                     " are too small for double precision (the cell size sqrt(area)/n must be at least 1e-9 of the "
                     "largest |coordinate| and its square at least 1e-250)");
  out.tol = std::max({1e-10 * std::max(out.box.width(), out.box.height()), 1e-7 * spacing,
                      64.0 * std::numeric_limits<double>::epsilon() * magnitude});
  return out;
}

/// Names the boundary edges on edge k of the polygon (corner k to corner k+1, in the order
/// given) "edge<k>", but for the edges `cut` (increasing: a piece's edges inside the whole
/// mesh).
void name_polygon_edges(Mesh& mesh, const std::vector<Vec2>& corners, double tol, std::span<const int> cut = {}) {
  const std::size_t m = corners.size();
  for (std::size_t k = 0; k < m; ++k) {
    std::vector<int> edges =
        select_boundary_edges(mesh, std::vector<Segment>{Segment{corners[k], corners[(k + 1) % m], tol}});
    std::erase_if(edges, [&](int e) { return std::binary_search(cut.begin(), cut.end(), e); });
    mesh.set_edge_group("edge" + std::to_string(k), std::move(edges));
  }
}

double to_plain_double(const ExactKernel::FT& x) { return CGAL::to_double(CGAL::exact(x)); }

/// The Voronoi cells of seeds inside the polygon, one counter-clockwise ring of
/// circumcentres per seed (a circumcentre has one id for all its cells), and whether the
/// polygon's boundary comes near each (otherwise the cell, which holds its seed, lies inside
/// the polygon). Four far sites make every cell bounded without changing it inside the
/// polygon.
struct RawCells {
  VoronoiCells cells;
  std::vector<char> cut;
};

RawCells raw_voronoi_cells(const std::vector<Vec2>& seeds, const CheckedPolygon& dom) {
  const std::size_t ns = seeds.size();
  const Rectangle& b = dom.box;
  const double far = 16.0 * std::max(b.width(), b.height());
  const double cx = 0.5 * (b.x0 + b.x1), cy = 0.5 * (b.y0 + b.y1);
  Delaunay dt;
  std::vector<Delaunay::Vertex_handle> handle(ns);
  Delaunay::Face_handle hint;
  for (std::size_t i = 0; i < ns; ++i) {
    handle[i] = dt.insert(Kernel::Point_2(seeds[i].x(), seeds[i].y()), hint);
    handle[i]->info() = static_cast<int>(i);
    hint = handle[i]->face();
  }
  for (const auto& [sx, sy] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}})
    dt.insert(Kernel::Point_2(cx + sx * far, cy + sy * far))->info() = -1;
  if (dt.number_of_vertices() != ns + 4)
    throw NumericalError("voronoi mesh: two seeds coincide; the Voronoi diagram is undefined");

  RawCells raw;
  VoronoiCells& out = raw.cells;
  out.offsets.assign(1, 0);
  raw.cut.assign(ns, 0);
  const std::size_t m = dom.corners.size();
  auto at = [&](int id) -> const Vec2& { return out.points[static_cast<std::size_t>(id)]; };
  for (std::size_t i = 0; i < ns; ++i) {
    const std::size_t first = out.ids.size();
    auto fc = dt.incident_faces(handle[i]);
    const auto done = fc;
    do {
      if (dt.is_infinite(fc)) throw NumericalError("voronoi mesh: a seed's Voronoi cell is unbounded");
      const int id = circumcentre_id(fc, out.points, dom.tol / 64);
      if (out.ids.size() == first || at(out.ids.back()) != at(id)) out.ids.push_back(id);
    } while (++fc != done);
    while (out.ids.size() > first + 1 && at(out.ids.back()) == at(out.ids[first])) out.ids.pop_back();
    out.offsets.push_back(static_cast<int>(out.ids.size()));
    const Rectangle cb = bounding_box_of(out.ids.begin() + static_cast<std::ptrdiff_t>(first), out.ids.end(), at);
    for (std::size_t k = 0; k < m && !raw.cut[i]; ++k) {
      const Vec2& p = dom.corners[k];
      const Vec2& q = dom.corners[(k + 1) % m];
      raw.cut[i] = std::max(p.x(), q.x()) >= cb.x0 - dom.tol && std::min(p.x(), q.x()) <= cb.x1 + dom.tol &&
                   std::max(p.y(), q.y()) >= cb.y0 - dom.tol && std::min(p.y(), q.y()) <= cb.y1 + dom.tol;
    }
  }
  return raw;
}

/// Centroid of each seed's cell within the polygon. A cut cell is clipped by Sutherland and
/// Hodgman's method: the polygon clipped by the half-planes of the convex cell. Where the
/// cell meets the polygon in several pieces the result joins them by edges of zero width,
/// which add nothing to its area and moments. NaN where the intersection has no area.
std::vector<Vec2> cell_centroids(const RawCells& raw, const CheckedPolygon& dom) {
  const VoronoiCells& c = raw.cells;
  const std::size_t ns = c.offsets.size() - 1;
  std::vector<Vec2> out(ns);
  std::vector<Vec2> poly, next;
  for (std::size_t i = 0; i < ns; ++i) {
    const int b = c.offsets[i], m = c.offsets[i + 1] - b;
    if (!raw.cut[i]) {
      out[i] = polygon_centroid(c.points, c.ids.data() + b, m);
      continue;
    }
    poly = dom.corners;
    for (int k = 0; k < m && !poly.empty(); ++k) {
      const Vec2& a = c.points[static_cast<std::size_t>(c.ids[static_cast<std::size_t>(b + k)])];
      const Vec2& e = c.points[static_cast<std::size_t>(c.ids[static_cast<std::size_t>(b + (k + 1) % m)])];
      const Vec2 d = e - a;
      auto side = [&](const Vec2& p) { return d.x() * (p.y() - a.y()) - d.y() * (p.x() - a.x()); };
      next.clear();
      for (std::size_t j = 0; j < poly.size(); ++j) {
        const Vec2& p = poly[j];
        const Vec2& q = poly[(j + 1) % poly.size()];
        const double sp = side(p), sq = side(q);
        if (sp >= 0.0) next.push_back(p);
        if ((sp >= 0.0) != (sq >= 0.0)) next.push_back(p + (sp / (sp - sq)) * (q - p));
      }
      poly.swap(next);
    }
    double twice = 0.0;
    Vec2 moment = Vec2::Zero();
    for (std::size_t j = 0; j < poly.size(); ++j) {
      const Vec2 p = poly[j] - dom.corners[0], q = poly[(j + 1) % poly.size()] - dom.corners[0];
      const double cr = p.x() * q.y() - p.y() * q.x();
      twice += cr;
      moment += cr * (p + q);
    }
    out[i] = twice > 0.0 ? Vec2(dom.corners[0] + moment / (3.0 * twice))
                         : Vec2(std::numeric_limits<double>::quiet_NaN(), 0.0);
  }
  return out;
}

/// The cells clipped to the polygon exactly (CGAL's Boolean operations): a cell that the
/// polygon's boundary cuts into several pieces gives one ring per piece, owner[k] is the seed
/// of ring k. Circumcentres keep their ids; a point made by clipping has one id per value.
VoronoiCells clip_cells(const RawCells& raw, const ExactPolygon& domain, std::vector<int>& owner) {
  const VoronoiCells& in = raw.cells;
  const std::size_t ns = in.offsets.size() - 1;
  VoronoiCells out;
  out.points = in.points;
  out.offsets.assign(1, 0);
  owner.clear();
  std::map<std::pair<double, double>, int> made;
  std::vector<ExactPolygonWithHoles> pieces;
  for (std::size_t i = 0; i < ns; ++i) {
    const auto first = in.ids.begin() + in.offsets[i], last = in.ids.begin() + in.offsets[i + 1];
    if (!raw.cut[i]) {
      out.ids.insert(out.ids.end(), first, last);
      out.offsets.push_back(static_cast<int>(out.ids.size()));
      owner.push_back(static_cast<int>(i));
      continue;
    }
    auto at = [&](int id) -> const Vec2& { return in.points[static_cast<std::size_t>(id)]; };
    ExactPolygon cell;
    for (auto it = first; it != last; ++it) cell.push_back(ExactKernel::Point_2(at(*it).x(), at(*it).y()));
    if (!cell.is_simple()) {  // round-off folded a tiny edge of the convex cell
      std::vector<ExactKernel::Point_2> hull;
      CGAL::convex_hull_2(cell.vertices_begin(), cell.vertices_end(), std::back_inserter(hull));
      cell = ExactPolygon(hull.begin(), hull.end());
    }
    if (cell.orientation() != CGAL::COUNTERCLOCKWISE) cell.reverse_orientation();
    pieces.clear();
    CGAL::intersection(cell, domain, std::back_inserter(pieces));
    for (const auto& piece : pieces) {
      if (piece.number_of_holes() != 0) throw NumericalError("voronoi mesh: a clipped Voronoi cell has a hole");
      for (auto v = piece.outer_boundary().vertices_begin(); v != piece.outer_boundary().vertices_end(); ++v) {
        const Vec2 p(to_plain_double(v->x()), to_plain_double(v->y()));
        const auto kept = std::find_if(first, last, [&](int id) { return at(id) == p; });
        if (kept != last) {
          out.ids.push_back(*kept);
          continue;
        }
        const auto [it, added] = made.try_emplace({p.x(), p.y()}, static_cast<int>(out.points.size()));
        if (added) out.points.push_back(p);
        out.ids.push_back(it->second);
      }
      out.offsets.push_back(static_cast<int>(out.ids.size()));
      owner.push_back(static_cast<int>(i));
    }
  }
  return out;
}

bool strictly_inside(const CGAL::Polygon_2<Kernel>& poly, const Vec2& p) {
  return poly.bounded_side(Kernel::Point_2(p.x(), p.y())) == CGAL::ON_BOUNDED_SIDE;
}

/// The polygon divided by 2^k (exact): corners, box, area and tolerance.
CheckedPolygon scaled_polygon(const CheckedPolygon& d, int k) {
  CheckedPolygon out = d;
  for (auto& p : out.corners) p = Vec2(std::ldexp(p.x(), -k), std::ldexp(p.y(), -k));
  out.box = Rectangle{std::ldexp(d.box.x0, -k), std::ldexp(d.box.x1, -k), std::ldexp(d.box.y0, -k),
                      std::ldexp(d.box.y1, -k)};
  out.area = std::ldexp(d.area, -2 * k);
  out.tol = std::ldexp(d.tol, -k);
  return out;
}

/// A polygon's mesh not made: the checked polygon and the cells' lists.
struct PolygonLists {
  CheckedPolygon dom;
  detail::PlaneCells cells;
};

/// A polygon generator's lists, run in coordinates where CGAL is exact in range
/// (unit_scale_exponent) and mapped back (every coordinate multiplied by 2^k: exact).
template <class Generate>
PolygonLists in_unit_coordinates(CheckedPolygon dom, Generate generate) {
  const Rectangle& b = dom.box;
  const int k = unit_scale_exponent(std::max(b.width(), b.height()),
                                    std::max({std::abs(b.x0), std::abs(b.x1), std::abs(b.y0), std::abs(b.y1)}));
  detail::PlaneCells cells = k == 0 ? generate(dom, 0) : generate(scaled_polygon(dom, k), k);
  if (k != 0)
    for (auto& v : cells.vertices) v = Vec2(std::ldexp(v.x(), k), std::ldexp(v.y(), k));
  return {std::move(dom), std::move(cells)};
}

/// The mesh of a polygon's lists, its boundary edges named after the polygon's edges.
Mesh polygon_mesh(const PolygonDomain& domain, PolygonLists lists) {
  Mesh mesh(std::move(lists.cells.vertices), std::move(lists.cells.elements));
  name_polygon_edges(mesh, domain.corners, lists.dom.tol);
  return mesh;
}

/// The narrowest feature of a polygon as its constrained triangulation sees it: the shortest
/// distance from a vertex of a face to the face's opposite edge where that edge is a polygon
/// edge (a corner close to an edge it does not end on: a thin spike, slit or neck).
struct Feature {
  double width = std::numeric_limits<double>::infinity();
  Vec2 corner = Vec2::Zero(), a = Vec2::Zero(), b = Vec2::Zero();  ///< the corner, the edge a-b
};

template <class Cdt>
Feature narrowest_feature(const Cdt& cdt) {
  auto at = [](const auto& v) { return Vec2(v->point().x(), v->point().y()); };
  Feature out;
  for (auto f : cdt.finite_face_handles())
    for (int i = 0; i < 3; ++i) {
      if (!f->is_constrained(i)) continue;
      const Vec2 p = at(f->vertex(i)), a = at(f->vertex(Cdt::ccw(i))), b = at(f->vertex(Cdt::cw(i)));
      const Vec2 d = b - a;
      const double t = (p - a).dot(d) / d.squaredNorm();
      const double w = t <= 0.0   ? (p - a).norm()
                       : t >= 1.0 ? (p - b).norm()
                                  : std::abs(d.x() * (p - a).y() - d.y() * (p - a).x()) / d.norm();
      if (w < out.width) out = Feature{w, p, a, b};
    }
  return out;
}

/// Narrowest feature accepted, in units of the triangles' size bound: below it a Delaunay
/// refiner needs about (length of the feature) / (its width) triangles to keep its angles.
constexpr double kMinFeatureFraction = 1e-3;
/// Triangles the refiner may make for n: 16 n^2 + 4096 (a polygon gives about 2 n^2).
std::size_t triangle_budget(int n) { return 16 * static_cast<std::size_t>(n) * static_cast<std::size_t>(n) + 4096; }

std::string feature_text(const Feature& f, int k) {
  auto back = [k](const Vec2& p) { return Vec2(std::ldexp(p.x(), k), std::ldexp(p.y(), k)); };
  return "a feature of width " + fmt(std::ldexp(f.width, k)) + " at " + point_text(back(f.corner)) +
         " (that corner is this close to the polygon edge from " + point_text(back(f.a)) + " to " +
         point_text(back(f.b)) + ")";
}

}  // namespace

std::string polygon_domain_defect(const PolygonDomain& d) {
  const auto& c = d.corners;
  if (c.size() < 3) return "needs at least 3 corners (got " + std::to_string(c.size()) + ")";
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(c[i].x()) || !std::isfinite(c[i].y()))
      return "has a corner that is not finite: corner " + std::to_string(i) + " " + point_text(c[i]);
    if (std::max(std::abs(c[i].x()), std::abs(c[i].y())) > max_mesh_coordinate)
      return "has a corner above 1e150 in magnitude: corner " + std::to_string(i);
  }
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c[i] == c[(i + 1) % c.size()])
      return "repeats corner " + std::to_string(i) + " " + point_text(c[i]) + " as corner " +
             std::to_string((i + 1) % c.size());
  CGAL::Polygon_2<Kernel> poly;
  for (const auto& p : c) poly.push_back(Kernel::Point_2(p.x(), p.y()));
  if (!poly.is_simple())
    return "is not simple: two of its edges cross or touch (corners go in order around the boundary, the last "
           "joined to the first)";
  return {};
}

namespace {

/// Triangles in a checked polygon, as lists; k: the power of two its coordinates were divided
/// by, for messages.
detail::PlaneCells triangle_lists(int n, const CheckedPolygon& dom, int k) {
  using MeshVertexBase = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
  using MeshFaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
  using MeshTds = CGAL::Triangulation_data_structure_2<MeshVertexBase, MeshFaceBase>;
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, MeshTds>;
  using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> corner;
  for (const auto& p : dom.corners) corner.push_back(cdt.insert(Cdt::Point(p.x(), p.y())));
  for (std::size_t k = 0; k < corner.size(); ++k) cdt.insert_constraint(corner[k], corner[(k + 1) % corner.size()]);
  // Longest edges at most 1.5 sqrt(area)/n: about 2 n^2 triangles, as on a rectangle.
  const double size = kTriangleEdgeFactor * std::sqrt(dom.area) / n;
  const Feature narrowest = narrowest_feature(cdt);
  if (narrowest.width < kMinFeatureFraction * size) {
    throw InputError("triangles mesh: the polygon domain has " + feature_text(narrowest, k) + ", narrower than " +
                     fmt(kMinFeatureFraction) + " of the triangles' size " + fmt(std::ldexp(size, k)) +
                     " at n = " + std::to_string(n) + "; widen it");
  }
  CGAL::Delaunay_mesher_2<Cdt, Criteria> mesher(cdt, Criteria(0.125, size));
  mesher.init();
  const std::size_t budget = triangle_budget(n);
  for (std::size_t steps = 0; !mesher.is_refinement_done(); ++steps) {
    mesher.try_one_step_refine_mesh();
    if (cdt.number_of_faces() > budget || steps > 4 * budget)
      throw InputError("triangles mesh: the polygon domain needs more than " + std::to_string(budget) +
                       " triangles at n = " + std::to_string(n) + " (16 n^2 + 4096) to keep their angles; its "
                       "narrowest part is " + feature_text(narrowest, k) + "; widen it");
  }

  std::vector<std::array<Vec2, 3>> faces;
  std::vector<Vec2> centroids;
  for (auto f : cdt.finite_face_handles()) {
    if (!f->is_in_domain()) continue;
    std::array<Vec2, 3> t;
    for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(k)] = Vec2(f->vertex(k)->point().x(), f->vertex(k)->point().y());
    faces.push_back(t);
    centroids.push_back((t[0] + t[1] + t[2]) / 3.0);
  }
  std::map<std::pair<double, double>, int> number;
  std::vector<Vec2> vertices;
  std::vector<std::vector<int>> elements;
  elements.reserve(faces.size());
  for (std::size_t f : detail::hilbert_order(centroids, dom.box)) {
    auto t = faces[f];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end(), lex_less), t.end());
    std::vector<int> el;
    for (const auto& p : t) {
      const auto [it, added] = number.try_emplace({p.x(), p.y()}, static_cast<int>(vertices.size()));
      if (added) vertices.push_back(p);
      el.push_back(it->second);
    }
    elements.push_back(std::move(el));
  }
  return {std::move(vertices), std::move(elements)};
}

PolygonLists triangles_in_polygon(int n, const PolygonDomain& domain) {
  check_n("triangles mesh", n);
  return in_unit_coordinates(check_polygon("triangles mesh", domain, n),
                             [n](const CheckedPolygon& dom, int k) { return triangle_lists(n, dom, k); });
}

}  // namespace

Mesh make_triangles(int n, const PolygonDomain& domain) { return polygon_mesh(domain, triangles_in_polygon(n, domain)); }

namespace {

/// Voronoi cells in a checked polygon (see make_voronoi), as lists.
detail::PlaneCells voronoi_polygon_lists(int n, const CheckedPolygon& dom, const VoronoiOptions& options) {
  const std::size_t ns = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  const double spacing = std::sqrt(dom.area / static_cast<double>(ns));
  CGAL::Polygon_2<Kernel> inexact;
  ExactPolygon exact;
  for (const auto& p : dom.corners) {
    inexact.push_back(Kernel::Point_2(p.x(), p.y()));
    exact.push_back(ExactKernel::Point_2(p.x(), p.y()));
  }

  // Seeds uniform in the polygon: uniform in its bounding box, kept when strictly inside.
  std::mt19937_64 rng(options.seed);
  std::vector<Vec2> seeds;
  seeds.reserve(ns);
  const std::size_t budget = 1000 * ns + 100000;
  for (std::size_t draws = 0; seeds.size() < ns; ++draws) {
    if (draws == budget)
      throw InputError("voronoi mesh: the polygon domain fills too little of its bounding box to place seeds in it");
    const double x = open_draw(rng, dom.box.x0, dom.box.x1);
    const Vec2 p(x, open_draw(rng, dom.box.y0, dom.box.y1));
    if (strictly_inside(inexact, p)) seeds.push_back(p);
  }
  detail::sort_along_hilbert_curve(seeds, dom.box);

  RawCells raw = raw_voronoi_cells(seeds, dom);
  const double stop = options.lloyd_tolerance * spacing;
  for (int it = 0; it < options.max_lloyd_iterations; ++it) {
    const std::vector<Vec2> centroid = cell_centroids(raw, dom);
    double moved = 0.0;
    for (std::size_t i = 0; i < ns; ++i) {
      const Vec2& g = centroid[i];
      // a cell cut in pieces: their joint centroid may lie outside the polygon
      if (!std::isfinite(g.x()) || !strictly_inside(inexact, g)) continue;
      moved = std::max(moved, (g - seeds[i]).norm());
      seeds[i] = g;
    }
    raw = raw_voronoi_cells(seeds, dom);
    if (moved <= stop) break;
  }
  std::vector<int> owner;
  const VoronoiCells cells = clip_cells(raw, exact, owner);
  const auto snap_to_corners = [&](const Vec2& p) {
    for (const auto& c : dom.corners)
      if ((p - c).norm() <= 4.0 * dom.tol) return c;
    return p;
  };
  return voronoi_lists(cells, dom.tol, snap_to_corners, true);
}

PolygonLists voronoi_in_polygon(int n, const PolygonDomain& domain, const VoronoiOptions& options) {
  check_n("voronoi mesh", n);
  CheckedPolygon dom = check_polygon("voronoi mesh", domain, n);
  check_voronoi_options(options);
  return in_unit_coordinates(std::move(dom), [n, &options](const CheckedPolygon& d, int) {
    return voronoi_polygon_lists(n, d, options);
  });
}

/// The lists of the generator `generator` (triangles or voronoi) in a polygon (make_mesh).
PolygonLists polygon_lists(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed) {
  if (generator == "triangles") return triangles_in_polygon(n, domain);
  if (generator == "voronoi") {
    VoronoiOptions options;
    options.seed = seed;
    return voronoi_in_polygon(n, domain, options);
  }
  for (const auto& name : mesh_generator_names())
    if (generator == name)
      throw InputError("the mesh generator '" + name + "' needs a rectangular domain; a polygon domain needs "
                       "generator voronoi or triangles");
  make_mesh(generator, n, Rectangle{}, seed);  // unknown name: its message
  throw InputError("unknown mesh generator '" + std::string(generator) + "'");
}

}  // namespace

Mesh make_voronoi(int n, const PolygonDomain& domain, const VoronoiOptions& options) {
  return polygon_mesh(domain, voronoi_in_polygon(n, domain, options));
}

Mesh make_mesh(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed) {
  return polygon_mesh(domain, polygon_lists(generator, n, domain, seed));
}

MeshPieceRead<Mesh> make_mesh_piece(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed,
                                    int rank, int size, HeldPoints held) {
  const PolygonLists lists = polygon_lists(generator, n, domain, seed);
  MeshPieceRead<Mesh> out;
  detail::make_plane_piece(lists.cells, held, rank, size, out);
  name_polygon_edges(out.mesh, domain.corners, lists.dom.tol, out.cut_facets);
  return out;
}

MeshLists<Mesh> mesh_lists(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed) {
  PolygonLists lists = polygon_lists(generator, n, domain, seed);
  return detail::plane_lists(std::make_shared<const detail::PlaneCells>(std::move(lists.cells)),
                             [corners = domain.corners, tol = lists.dom.tol](MeshPieceRead<Mesh>& piece) {
                               name_polygon_edges(piece.mesh, corners, tol, piece.cut_facets);
                             });
}

ListsOfFirst<Mesh> mesh_lists_of_first(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed) {
  return {[generator = std::string(generator), n, domain, seed] { return mesh_lists(generator, n, domain, seed); },
          [n, domain](MeshPieceRead<Mesh>& piece) {
            // where the first made the lists, the polygon (which it checked) gives the tolerance
            name_polygon_edges(piece.mesh, domain.corners, check_polygon("polygon mesh", domain, n).tol, piece.cut_facets);
          }};
}

MeshPieceRead<Mesh> make_mesh_piece(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed,
                                    const RowDistribution& processes, HeldPoints held, const BoundaryPick<Mesh>& pick) {
  const ListsOfFirst<Mesh> source = mesh_lists_of_first(generator, n, domain, seed);
  // the pieces' edges named after the polygon's edges, as the whole mesh's, before the pick reads them
  const BoundaryPick<Mesh> named_pick = !pick ? pick : [&](MeshPieceRead<Mesh>&& sides) {
    source.finish(sides);
    return pick(std::move(sides));
  };
  MeshPieceRead<Mesh> out = detail::lists_piece_by_first<Mesh, detail::PlaneCells>(
      processes, [&] { return polygon_lists(generator, n, domain, seed).cells; }, held, named_pick, name_plane_defect);
  source.finish(out);
  return out;
}

}  // namespace hemivem
