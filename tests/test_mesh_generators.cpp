#include <hemivem/mesh/generators.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "thread_rows.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

using hemivem::Mesh;
using hemivem::Rectangle;
using hemivem::Vec2;
using hemivem::test::identical;
using hemivem::test::input_error_of;

namespace {

const Rectangle kRect{-1.0, 2.0, 0.5, 1.5};  // a non-unit rectangle

Mesh make(const std::string& name, int n, const Rectangle& d = kRect, std::uint64_t seed = 1) {
  return hemivem::make_mesh(name, n, d, seed);
}

// Which sides of the rectangle a point lies on exactly (bit 0: x0, 1: x1, 2: y0, 3: y1).
unsigned sides_of(const Vec2& p, const Rectangle& d) {
  return (p.x() == d.x0 ? 1u : 0u) | (p.x() == d.x1 ? 2u : 0u) | (p.y() == d.y0 ? 4u : 0u) | (p.y() == d.y1 ? 8u : 0u);
}

// The mesh tiles the rectangle: every vertex inside it, total area equal to its area,
// every element counter-clockwise, boundary vertices exactly on the sides, and the
// boundary edges exactly the edges lying on a side.
void expect_tiles_rectangle(const Mesh& m, const Rectangle& d) {
  const double area = d.width() * d.height();
  EXPECT_NEAR(m.total_area(), area, 1e-12 * area);
  for (const Vec2& p : m.vertices()) {
    EXPECT_TRUE(p.x() >= d.x0 && p.x() <= d.x1 && p.y() >= d.y0 && p.y() <= d.y1)
        << "vertex (" << p.x() << ", " << p.y() << ") outside the rectangle";
  }
  std::vector<Vec2> poly;
  for (int e = 0; e < m.num_elements(); ++e) {
    poly.clear();
    for (int v : m.element(e)) poly.push_back(m.vertex(v));
    EXPECT_GT(hemivem::signed_area(poly), 0.0) << "element " << e << " is not counter-clockwise";
  }
  for (int v : m.boundary_vertices())
    EXPECT_NE(sides_of(m.vertex(v), d), 0u) << "boundary vertex " << v << " is not exactly on a side";
  int on_sides = 0;
  for (int i = 0; i < m.num_edges(); ++i) {
    const auto& ed = m.edge(i);
    const bool on_side = (sides_of(m.vertex(ed.v0), d) & sides_of(m.vertex(ed.v1), d)) != 0;
    on_sides += on_side ? 1 : 0;
    EXPECT_EQ(ed.on_boundary(), on_side) << "edge " << i << " (" << ed.v0 << "-" << ed.v1 << ")";
  }
  EXPECT_EQ(on_sides, static_cast<int>(m.boundary_edges().size()));
  // the boundary is closed and its length is the perimeter
  double perimeter = 0.0;
  for (int i : m.boundary_edges()) perimeter += m.edge_length(i);
  EXPECT_NEAR(perimeter, 2.0 * (d.width() + d.height()), 1e-12 * (d.width() + d.height()));
}


double max_over_min_area(const Mesh& m) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (int e = 0; e < m.num_elements(); ++e) {
    lo = std::min(lo, m.area(e));
    hi = std::max(hi, m.area(e));
  }
  return hi / lo;
}

// Some interior angle exceeds 180 degrees (a right turn in a counter-clockwise ring).
bool has_reflex_angle(const Mesh& m, int e) {
  const auto el = m.element(e);
  const std::size_t k = el.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vec2 a = m.vertex(el[(i + k - 1) % k]), b = m.vertex(el[i]), c = m.vertex(el[(i + 1) % k]);
    const Vec2 u = b - a, w = c - b;
    if (u.x() * w.y() - u.y() * w.x() < 0.0) return true;
  }
  return false;
}


}  // namespace

// ---- squares and triangles ------------------------------------------------------------

TEST(MeshGenerators, SquaresCountsNumberingAndTiling) {
  for (int n : {1, 2, 5}) {
    const Mesh m = hemivem::make_squares(n, kRect);
    EXPECT_EQ(m.num_vertices(), (n + 1) * (n + 1));
    EXPECT_EQ(m.num_elements(), n * n);
    EXPECT_EQ(static_cast<int>(m.boundary_edges().size()), 4 * n);
    expect_tiles_rectangle(m, kRect);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const Vec2& p = m.vertex(j * (n + 1) + i);
        EXPECT_NEAR(p.x(), kRect.x0 + kRect.width() * i / n, 1e-15);
        EXPECT_NEAR(p.y(), kRect.y0 + kRect.height() * j / n, 1e-15);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto el = m.element(j * n + i);
        const int a = j * (n + 1) + i;
        ASSERT_EQ(el.size(), 4u);
        EXPECT_EQ(el[0], a);
        EXPECT_EQ(el[1], a + 1);
        EXPECT_EQ(el[2], a + n + 2);
        EXPECT_EQ(el[3], a + n + 1);
        EXPECT_NEAR(m.area(j * n + i), kRect.width() * kRect.height() / (n * n), 1e-14);
      }
  }
}

// nx cells along x and ny along y: counts, numbering, tiling, and cells of equal shape
// when the domain's aspect ratio is nx : ny.
TEST(MeshGenerators, DifferentCellCountsAlongXAndY) {
  const hemivem::GridSize g(6, 2);
  const Rectangle wide{0.0, 3.0, 0.0, 1.0};
  const Mesh sq = hemivem::make_squares(g, wide);
  EXPECT_EQ(sq.num_vertices(), 7 * 3);
  EXPECT_EQ(sq.num_elements(), 12);
  expect_tiles_rectangle(sq, wide);
  for (int e = 0; e < sq.num_elements(); ++e) EXPECT_NEAR(sq.area(e), 0.25, 1e-15);  // 0.5 x 0.5 squares
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 6; ++i) {
      EXPECT_EQ(sq.vertex(j * 7 + i).x(), 0.5 * i);
      EXPECT_EQ(sq.vertex(j * 7 + i).y(), 0.5 * j);
    }
  const auto el = sq.element(1 * 6 + 4);  // element (4, 1)
  EXPECT_EQ(std::vector<int>(el.begin(), el.end()), (std::vector<int>{11, 12, 19, 18}));
  EXPECT_EQ(hemivem::make_triangles(g, wide).num_elements(), 24);
  EXPECT_EQ(hemivem::make_nonconvex(g, wide).num_elements(), 12);
  EXPECT_EQ(hemivem::make_distorted(g, 0.2, wide).num_elements(), 12);
  EXPECT_EQ(hemivem::make_voronoi(g, wide).num_elements(), 12);
  for (const std::string name : hemivem::mesh_generator_names()) {
    SCOPED_TRACE(name);
    const Mesh m = hemivem::make_mesh(name, g, wide, 3);
    expect_tiles_rectangle(m, wide);
    EXPECT_EQ(m.num_vertices() - m.num_edges() + m.num_elements(), 1);  // Euler, one face outside
  }
  // n x n is the int form, bit for bit
  EXPECT_TRUE(identical(hemivem::make_voronoi(hemivem::GridSize(5, 5), wide), hemivem::make_voronoi(5, wide)));
  EXPECT_EQ(hemivem::GridSize(5).text(), "5");
  EXPECT_EQ(g.text(), "[6, 2]");
  EXPECT_THROW((void)hemivem::make_squares(hemivem::GridSize(4, 0)), hemivem::InputError);
  EXPECT_NE(input_error_of([&] { (void)hemivem::make_squares(hemivem::GridSize(4, 0)); }).find("(got [4, 0])"),
            std::string::npos);
}

TEST(MeshGenerators, GridEndsExactlyOnAwkwardRectangle) {
  // 0.1 + (0.3 - 0.1) is not 0.3 in floating point: the last vertex must still be x1
  const Rectangle d{0.1, 0.3, 0.7, 0.9};
  const Mesh m = hemivem::make_squares(3, d);
  EXPECT_EQ(m.vertex(3).x(), 0.3);
  EXPECT_EQ(m.vertex(15).y(), 0.9);
  expect_tiles_rectangle(m, d);
}

TEST(MeshGenerators, TrianglesSplitEachSquareAlongItsDiagonal) {
  const int n = 4;
  const Mesh m = hemivem::make_triangles(n, kRect);
  const Mesh sq = hemivem::make_squares(n, kRect);
  EXPECT_EQ(m.num_vertices(), (n + 1) * (n + 1));
  EXPECT_EQ(m.num_elements(), 2 * n * n);
  EXPECT_EQ(m.vertices(), sq.vertices());
  EXPECT_EQ(m.num_edges(), 3 * n * n + 2 * n);
  expect_tiles_rectangle(m, kRect);
  for (int s = 0; s < n * n; ++s) {
    const auto lo = m.element(2 * s), hi = m.element(2 * s + 1), q = sq.element(s);
    ASSERT_EQ(lo.size(), 3u);
    ASSERT_EQ(hi.size(), 3u);
    // lower-left -> upper-right diagonal, shared by both triangles
    EXPECT_EQ(std::vector<int>(lo.begin(), lo.end()), (std::vector<int>{q[0], q[1], q[2]}));
    EXPECT_EQ(std::vector<int>(hi.begin(), hi.end()), (std::vector<int>{q[0], q[2], q[3]}));
    EXPECT_NEAR(m.area(2 * s), 0.5 * sq.area(s), 1e-15);
  }
}

// ---- nonconvex -------------------------------------------------------------------------

TEST(MeshGenerators, NonconvexCountsAndDegrees) {
  for (int n : {2, 3, 5}) {
    const Mesh m = hemivem::make_nonconvex(n, kRect);
    EXPECT_EQ(m.num_vertices(), (n + 1) * (n + 1) + 2 * n * (n - 1));
    EXPECT_EQ(m.num_elements(), n * n);
    expect_tiles_rectangle(m, kRect);
    std::map<int, int> degrees;
    for (int J = 0; J < n; ++J)
      for (int I = 0; I < n; ++I) {
        const int boundary_sides = (I == 0) + (I == n - 1) + (J == 0) + (J == n - 1);
        EXPECT_EQ(m.element_size(J * n + I), 8 - boundary_sides) << "macro cell " << I << ", " << J;
        ++degrees[m.element_size(J * n + I)];
      }
    EXPECT_EQ(degrees[8], (n - 2) * (n - 2));
    EXPECT_EQ(degrees[7], 4 * (n - 2));
    EXPECT_EQ(degrees[6], 4);
  }
  EXPECT_EQ(hemivem::make_nonconvex(1, kRect).element_size(0), 4);
}

TEST(MeshGenerators, NonconvexInteriorElementsAreNotConvex) {
  const int n = 5;
  const Mesh m = hemivem::make_nonconvex(n, kRect);
  for (int J = 1; J + 1 < n; ++J)
    for (int I = 1; I + 1 < n; ++I) EXPECT_TRUE(has_reflex_angle(m, J * n + I)) << "macro cell " << I << ", " << J;
  // an interior macro cell loses two triangles (bottom, left) and gains two (right, top)
  // of equal area: it keeps the area of the macro square
  EXPECT_NEAR(m.area(2 * n + 2), kRect.width() * kRect.height() / (n * n), 1e-14);
}

TEST(MeshGenerators, NonconvexOctagonCoordinatesByHand) {
  // N = 3 on the unit square: macro cells of 1/3, quarter shift 1/12. Centre cell (1, 1):
  const Mesh m = hemivem::make_nonconvex(3);
  const auto el = m.element(4);
  ASSERT_EQ(el.size(), 8u);
  const double expected[8][2] = {{1.0 / 3, 1.0 / 3},  {7.0 / 12, 5.0 / 12}, {2.0 / 3, 1.0 / 3}, {3.0 / 4, 7.0 / 12},
                                 {2.0 / 3, 2.0 / 3},  {7.0 / 12, 3.0 / 4},  {1.0 / 3, 2.0 / 3}, {5.0 / 12, 7.0 / 12}};
  for (int k = 0; k < 8; ++k) {
    EXPECT_NEAR(m.vertex(el[k]).x(), expected[k][0], 1e-15) << "vertex " << k;
    EXPECT_NEAR(m.vertex(el[k]).y(), expected[k][1], 1e-15) << "vertex " << k;
  }
  // the reflex angles are at the bottom and left mid-points, which are pushed inwards
  EXPECT_NEAR(m.area(4), 1.0 / 9, 1e-15);
  // corner cell (2, 2) has lost its right and top mid-points: 6 vertices
  const auto c = m.element(8);
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(m.vertex(c[2]), Vec2(1.0, 2.0 / 3));
  EXPECT_EQ(m.vertex(c[3]), Vec2(1.0, 1.0));
}

// ---- distorted -------------------------------------------------------------------------

TEST(MeshGenerators, DistortedMovesOnlyInteriorVerticesWithinBounds) {
  const int n = 6;
  const double f = 0.3;
  const Mesh m = hemivem::make_distorted(n, f, kRect, 7);
  const Mesh sq = hemivem::make_squares(n, kRect);
  EXPECT_EQ(m.num_vertices(), sq.num_vertices());
  EXPECT_EQ(m.elements(), sq.elements());
  expect_tiles_rectangle(m, kRect);
  const double hx = kRect.width() / n, hy = kRect.height() / n;
  int moved = 0;
  double largest_x = 0.0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const int v = j * (n + 1) + i;
      const Vec2 d = m.vertex(v) - sq.vertex(v);
      if (i == 0 || j == 0 || i == n || j == n) {
        EXPECT_EQ(m.vertex(v), sq.vertex(v)) << "boundary vertex " << v << " moved";
        continue;
      }
      EXPECT_LE(std::abs(d.x()), f * hx * (1 + 1e-12));
      EXPECT_LE(std::abs(d.y()), f * hy * (1 + 1e-12));
      moved += (d.x() != 0.0 && d.y() != 0.0) ? 1 : 0;
      largest_x = std::max(largest_x, std::abs(d.x()));
    }
  EXPECT_EQ(moved, (n - 1) * (n - 1));
  EXPECT_GT(largest_x, 0.5 * f * hx);  // the moves use the range, not a sliver of it
  EXPECT_TRUE(identical(hemivem::make_distorted(n, 0.0, kRect, 7), sq));
}

TEST(MeshGenerators, DistortedRejectsBadFraction) {
  for (double f : {-0.1, 0.5, 0.7, std::numeric_limits<double>::quiet_NaN()}) {
    const std::string msg = input_error_of([&] { hemivem::make_distorted(4, f, kRect); });
    EXPECT_NE(msg.find("fraction"), std::string::npos) << f << ": " << msg;
  }
  EXPECT_NO_THROW(hemivem::make_distorted(4, 0.49, kRect, 3));
}

// ---- voronoi ---------------------------------------------------------------------------

TEST(MeshGenerators, VoronoiTilesTheRectangle) {
  for (int n : {1, 2, 7, 12}) {
    for (int iterations : {0, 100}) {
      hemivem::VoronoiOptions o;
      o.max_lloyd_iterations = iterations;
      o.seed = 3;
      const Mesh m = hemivem::make_voronoi(n, kRect, o);
      EXPECT_EQ(m.num_elements(), n * n);
      expect_tiles_rectangle(m, kRect);
      // Euler for a disk: V - E + F = 1
      EXPECT_EQ(m.num_vertices() - m.num_edges() + m.num_elements(), 1);
    }
  }
  // one seed: its cell is the rectangle
  const Mesh one = hemivem::make_voronoi(1, kRect);
  ASSERT_EQ(one.element_size(0), 4);
  EXPECT_EQ(one.vertex(one.element(0)[0]), Vec2(kRect.x0, kRect.y0));
  EXPECT_EQ(one.vertex(one.element(0)[2]), Vec2(kRect.x1, kRect.y1));
}

TEST(MeshGenerators, VoronoiHasNoTinyEdges) {
  // Mirror symmetry makes every vertex on a side the circumcentre of two Delaunay
  // faces; those must come out as one vertex, not as an edge of ~1e-16.
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    for (int iterations : {0, 5, 100}) {
      hemivem::VoronoiOptions o;
      o.seed = seed;
      o.max_lloyd_iterations = iterations;
      const Mesh m = hemivem::make_voronoi(9, kRect, o);
      EXPECT_GE(m.min_edge_length(), 1e-8 * m.h()) << "seed " << seed << ", " << iterations << " iterations";
    }
  }
  // two cells side by side after Lloyd meet in a nearly 4-valent centre point
  const Mesh two = hemivem::make_voronoi(2, {0, 1, 0, 1});
  EXPECT_GE(two.min_edge_length(), 1e-8 * two.h());
}

TEST(MeshGenerators, VoronoiLloydEvensOutTheCells) {
  const int n = 16;
  hemivem::VoronoiOptions raw;
  raw.max_lloyd_iterations = 0;
  const Mesh m0 = hemivem::make_voronoi(n, {0, 1, 0, 1}, raw);
  const Mesh m1 = hemivem::make_voronoi(n, {0, 1, 0, 1});
  const double spread0 = max_over_min_area(m0), spread1 = max_over_min_area(m1);
  EXPECT_GT(spread0, 5.0);
  EXPECT_LT(spread1, 2.5);
  EXPECT_LT(m1.h(), m0.h());
  // h ~ 1/n: a cell of a relaxed mesh is about a hexagon of area 1/n^2
  EXPECT_GT(m1.h(), 1.0 / n);
  EXPECT_LT(m1.h(), 2.5 / n);
  for (int e = 0; e < m1.num_elements(); ++e) EXPECT_FALSE(has_reflex_angle(m1, e));
}

// the Lloyd iterations split among 2, 3 and 5 processes (threads here; each computing the cells of
// its share of the seeds from the seeds around them alone): every process makes the mesh one
// process makes, to the bit, on a rectangle whose cells are computed at its own scale and on one
// made unit first
TEST(MeshGenerators, VoronoiLloydIterationsSplitAmongProcessesMakeOneProcesssMesh) {
  const hemivem::GridSize n(48, 40);
  for (const Rectangle& d : {Rectangle{0, 1.2, 0, 1}, Rectangle{1e6, 1e6 + 1, -3, -2}}) {
    hemivem::VoronoiOptions one;
    one.seed = 5;
    const Mesh whole = hemivem::make_voronoi(n, d, one);
    for (const int size : {2, 3, 5}) {
      SCOPED_TRACE(std::to_string(size) + " processes");
      const auto made = hemivem::test::on_threads(size, [&](const hemivem::test::ThreadRows& rows) {
        hemivem::VoronoiOptions o = one;
        o.processes = &rows;
        return hemivem::make_voronoi(n, d, o);
      });
      for (const Mesh& m : made) EXPECT_TRUE(identical(m, whole));
    }
    // with the iterations cut short the mesh differs: the comparison above can fail
    hemivem::VoronoiOptions short_of = one;
    short_of.max_lloyd_iterations = 3;
    EXPECT_FALSE(identical(hemivem::make_voronoi(n, d, short_of), whole));
  }
}

TEST(MeshGenerators, VoronoiHandlesThinAndOffsetRectangles) {
  for (const Rectangle& d : {Rectangle{0, 1000, 0, 0.001}, Rectangle{1e6, 1e6 + 1, -3, -2}, Rectangle{0.1, 0.3, 0.7, 0.9}}) {
    const Mesh m = hemivem::make_voronoi(6, d);
    EXPECT_EQ(m.num_elements(), 36);
    expect_tiles_rectangle(m, d);
    EXPECT_GE(m.min_edge_length(), 1e-8 * m.h());
  }
}

// ---- determinism -----------------------------------------------------------------------

TEST(MeshGenerators, SameSeedSameMeshOtherSeedOtherMesh) {
  for (const auto& name : hemivem::mesh_generator_names()) {
    EXPECT_TRUE(identical(make(name, 6, kRect, 11), make(name, 6, kRect, 11))) << name;
  }
  for (const std::string name : {"voronoi", "distorted"}) {
    const Mesh a = make(name, 6, kRect, 11), b = make(name, 6, kRect, 12);
    EXPECT_FALSE(identical(a, b)) << name;
    EXPECT_NE(a.vertex(a.num_vertices() / 2), b.vertex(b.num_vertices() / 2)) << name;
  }
  hemivem::VoronoiOptions o;
  o.seed = 5;
  o.max_lloyd_iterations = 3;
  EXPECT_TRUE(identical(hemivem::make_voronoi(10, kRect, o), hemivem::make_voronoi(10, kRect, o)));
}

// ---- by name and argument checks ---------------------------------------------------------

TEST(MeshGenerators, MakeMeshByName) {
  const auto& names = hemivem::mesh_generator_names();
  EXPECT_EQ(names, (std::vector<std::string>{"squares", "triangles", "voronoi", "nonconvex", "distorted"}));
  const int n = 4;
  const std::map<std::string, int> elements{
      {"squares", n * n}, {"triangles", 2 * n * n}, {"voronoi", n * n}, {"nonconvex", n * n}, {"distorted", n * n}};
  for (const auto& name : names) {
    const Mesh m = make(name, n);
    EXPECT_EQ(m.num_elements(), elements.at(name)) << name;
    expect_tiles_rectangle(m, kRect);
  }
  EXPECT_TRUE(identical(make("squares", n), hemivem::make_squares(n, kRect)));
  EXPECT_TRUE(identical(make("nonconvex", n), hemivem::make_nonconvex(n, kRect)));
  EXPECT_TRUE(identical(make("distorted", n, kRect, 9), hemivem::make_distorted(n, 0.2, kRect, 9)));
  hemivem::VoronoiOptions o;
  o.seed = 9;
  EXPECT_TRUE(identical(make("voronoi", n, kRect, 9), hemivem::make_voronoi(n, kRect, o)));
}

TEST(MeshGenerators, UnknownNameListsTheValidOnes) {
  const std::string msg = input_error_of([] { hemivem::make_mesh("hexagons", 4); });
  EXPECT_NE(msg.find("hexagons"), std::string::npos) << msg;
  for (const auto& name : hemivem::mesh_generator_names()) EXPECT_NE(msg.find(name), std::string::npos) << msg;
}

TEST(MeshGenerators, RejectBadSizeAndDomain) {
  for (const auto& name : hemivem::mesh_generator_names()) {
    for (int n : {0, -3}) {
      const std::string msg = input_error_of([&] { make(name, n); });
      EXPECT_NE(msg.find("n must be"), std::string::npos) << name << ": " << msg;
      EXPECT_NE(msg.find("got " + std::to_string(n)), std::string::npos) << name << ": " << msg;
    }
    const double inf = std::numeric_limits<double>::infinity();
    for (const Rectangle& d : {Rectangle{1, 1, 0, 1}, Rectangle{0, 1, 2, 1}, Rectangle{0, inf, 0, 1},
                               Rectangle{0, 1, std::nan(""), 1}, Rectangle{-1e308, 1e308, 0, 1}}) {
      const std::string msg = input_error_of([&] { make(name, 2, d); });
      EXPECT_NE(msg.find("domain"), std::string::npos) << name << ": " << msg;
    }
  }
  hemivem::VoronoiOptions o;
  o.max_lloyd_iterations = -1;
  EXPECT_NE(input_error_of([&] { hemivem::make_voronoi(3, kRect, o); }).find("max_lloyd_iterations"), std::string::npos);
  o.max_lloyd_iterations = 10;
  o.lloyd_tolerance = -1.0;
  EXPECT_NE(input_error_of([&] { hemivem::make_voronoi(3, kRect, o); }).find("lloyd_tolerance"), std::string::npos);
}
