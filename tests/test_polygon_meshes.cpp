// Meshes of polygon domains (triangles and voronoi generators): they tile the polygon,
// keep its corners, name its edges, agree with the rectangle generator on a rectangle, and
// are deterministic; bad polygons are refused with the defect named.
#include <hemivem/mesh/generators.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

using hemivem::Mesh;
using hemivem::PolygonDomain;
using hemivem::Vec2;
using hemivem::test::identical;
using hemivem::test::input_error_of;

namespace {

// An L: the unit square without its upper right quarter, given clockwise on purpose.
const PolygonDomain kL{{{0.0, 0.0}, {0.0, 1.0}, {0.5, 1.0}, {0.5, 0.5}, {1.0, 0.5}, {1.0, 0.0}}};
// A trapezoid, counter-clockwise, away from the origin.
const PolygonDomain kTrapezoid{{{10.0, -2.0}, {14.0, -2.0}, {13.0, 0.0}, {11.0, 0.0}}};

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

double distance_to_boundary(const Vec2& p, const PolygonDomain& d) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < d.corners.size(); ++k)
    best = std::min(best, distance_to_segment(p, d.corners[k], d.corners[(k + 1) % d.corners.size()]));
  return best;
}

// The mesh tiles the polygon: its area, boundary vertices on the polygon's edges, every
// corner a vertex exactly, the boundary's length the perimeter, edge group k exactly the
// boundary edges on edge k with the edge's length, and Euler's formula for a disk.
void expect_tiles_polygon(const Mesh& m, const PolygonDomain& d) {
  const double area = std::abs(hemivem::signed_area(d.corners));
  EXPECT_NEAR(m.total_area(), area, 1e-12 * area);
  const double size = std::sqrt(area);
  for (int v : m.boundary_vertices())
    EXPECT_LE(distance_to_boundary(m.vertex(v), d), 1e-12 * size) << "boundary vertex " << v;
  for (const Vec2& c : d.corners)
    EXPECT_NE(std::find(m.vertices().begin(), m.vertices().end(), c), m.vertices().end())
        << "corner (" << c.x() << ", " << c.y() << ") is not a vertex";
  double perimeter = 0.0, boundary = 0.0;
  std::size_t grouped = 0;
  for (std::size_t k = 0; k < d.corners.size(); ++k) {
    const Vec2 a = d.corners[k], b = d.corners[(k + 1) % d.corners.size()];
    perimeter += (b - a).norm();
    double length = 0.0;
    for (int e : m.edge_group("edge" + std::to_string(k))) {
      EXPECT_TRUE(m.edge(e).on_boundary());
      EXPECT_LE(distance_to_segment(m.vertex(m.edge(e).v0), a, b), 1e-12 * size);
      EXPECT_LE(distance_to_segment(m.vertex(m.edge(e).v1), a, b), 1e-12 * size);
      length += m.edge_length(e);
    }
    EXPECT_NEAR(length, (b - a).norm(), 1e-12 * size) << "edge" << k;
    grouped += m.edge_group("edge" + std::to_string(k)).size();
  }
  for (int e : m.boundary_edges()) boundary += m.edge_length(e);
  EXPECT_NEAR(boundary, perimeter, 1e-12 * perimeter);
  EXPECT_EQ(grouped, m.boundary_edges().size());
  EXPECT_EQ(m.num_vertices() - m.num_edges() + m.num_elements(), 1);
}



}  // namespace

TEST(PolygonMeshes, TrianglesTileThePolygon) {
  for (const PolygonDomain& d : {kL, kTrapezoid}) {
    for (int n : {1, 4, 16}) {
      const Mesh m = hemivem::make_triangles(n, d);
      expect_tiles_polygon(m, d);
      for (int e = 0; e < m.num_elements(); ++e) EXPECT_EQ(m.element_size(e), 3);
      if (n == 16) {  // about 2 n^2 triangles, as on a rectangle
        EXPECT_GT(m.num_elements(), n * n);
        EXPECT_LT(m.num_elements(), 4 * n * n);
      }
    }
  }
}

TEST(PolygonMeshes, TrianglesHaveNoSmallAngles) {
  // the mesher's bound: no angle below about 20.7 degrees (the L's corners are 90 and 270)
  const Mesh m = hemivem::make_triangles(12, kL);
  double smallest = 180.0;
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto el = m.element(e);
    for (int i = 0; i < 3; ++i) {
      const Vec2 a = m.vertex(el[i]), b = m.vertex(el[(i + 1) % 3]), c = m.vertex(el[(i + 2) % 3]);
      const double cosine = (b - a).dot(c - a) / ((b - a).norm() * (c - a).norm());
      smallest = std::min(smallest, std::acos(cosine) * 180.0 / M_PI);
    }
  }
  EXPECT_GE(smallest, 20.0);
}

TEST(PolygonMeshes, VoronoiTilesThePolygon) {
  for (const PolygonDomain& d : {kL, kTrapezoid}) {
    for (int n : {1, 3, 12}) {
      for (int iterations : {0, 100}) {
        hemivem::VoronoiOptions o;
        o.max_lloyd_iterations = iterations;
        const Mesh m = hemivem::make_voronoi(n, d, o);
        expect_tiles_polygon(m, d);
        // a cell cut in two by the re-entrant corner gives two elements
        EXPECT_GE(m.num_elements(), n * n);
        EXPECT_LE(m.num_elements(), n * n + 4);
        EXPECT_GE(m.min_edge_length(), 1e-8 * m.h());
      }
    }
  }
}

TEST(PolygonMeshes, VoronoiOnARectangleIsTheRectangleGenerator) {
  // Same seeds (every draw lands inside), cells clipped instead of mirrored: the same mesh to
  // round-off, computed another way.
  const hemivem::Rectangle r{-1.0, 2.0, 0.5, 1.5};
  const PolygonDomain p{{{-1.0, 0.5}, {2.0, 0.5}, {2.0, 1.5}, {-1.0, 1.5}}};
  for (int iterations : {0, 100}) {
    hemivem::VoronoiOptions o;
    o.seed = 4;
    o.max_lloyd_iterations = iterations;
    const Mesh a = hemivem::make_voronoi(9, r, o), b = hemivem::make_voronoi(9, p, o);
    ASSERT_EQ(a.num_elements(), b.num_elements());
    ASSERT_EQ(a.num_vertices(), b.num_vertices());
    EXPECT_EQ(a.elements(), b.elements());
    double worst = 0.0;
    for (int v = 0; v < a.num_vertices(); ++v) worst = std::max(worst, (a.vertex(v) - b.vertex(v)).norm());
    EXPECT_LE(worst, 1e-12);
  }
}

TEST(PolygonMeshes, SameArgumentsSameMesh) {
  EXPECT_TRUE(identical(hemivem::make_triangles(9, kL), hemivem::make_triangles(9, kL)));
  hemivem::VoronoiOptions o;
  o.seed = 7;
  EXPECT_TRUE(identical(hemivem::make_voronoi(9, kL, o), hemivem::make_voronoi(9, kL, o)));
  o.seed = 8;
  EXPECT_FALSE(identical(hemivem::make_voronoi(9, kL, {}), hemivem::make_voronoi(9, kL, o)));
  EXPECT_TRUE(identical(hemivem::make_mesh("voronoi", 5, kL, 8), hemivem::make_voronoi(5, kL, [] {
                          hemivem::VoronoiOptions v;
                          v.seed = 8;
                          return v;
                        }())));
  EXPECT_TRUE(identical(hemivem::make_mesh("triangles", 5, kL), hemivem::make_triangles(5, kL)));
}

TEST(PolygonMeshes, BadPolygonsAreRefusedWithTheDefect) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<PolygonDomain, std::string>> bad{
      {{{{0, 0}, {1, 0}}}, "at least 3 corners"},
      {{{{0, 0}, {1, 0}, {1, inf}}}, "not finite"},
      {{{{0, 0}, {1, 0}, {1, 0}, {0, 1}}}, "repeats corner 1"},
      {{{{0, 0}, {1, 1}, {1, 0}, {0, 1}}}, "not simple"},       // a bow tie
      {{{{0, 0}, {1, 0}, {2, 0}}}, "not simple"},               // no area
      {{{{0, 0}, {2, 0}, {1, 0}, {1, 1}}}, "not simple"},       // an edge folds back on the previous
  };
  for (const auto& [poly, fragment] : bad) {
    EXPECT_NE(hemivem::polygon_domain_defect(poly).find(fragment), std::string::npos) << fragment;
    for (const std::string name : {"triangles", "voronoi"}) {
      const std::string msg = input_error_of([&, name = name] { hemivem::make_mesh(name, 3, poly); });
      EXPECT_NE(msg.find(fragment), std::string::npos) << name << ": " << msg;
    }
  }
  EXPECT_EQ(hemivem::polygon_domain_defect(kL), "");
  // cells too small for double precision
  const PolygonDomain far{{{1e6, 1e6}, {1e6 + 1e-8, 1e6}, {1e6, 1e6 + 1e-8}}};
  EXPECT_NE(input_error_of([&] { hemivem::make_triangles(20, far); }).find("too small"), std::string::npos);
  // the other generators need a rectangle
  for (const std::string name : {"squares", "nonconvex", "distorted"}) {
    const std::string msg = input_error_of([&, name = name] { hemivem::make_mesh(name, 3, kL); });
    EXPECT_NE(msg.find("needs a rectangular domain"), std::string::npos) << msg;
  }
  EXPECT_NE(input_error_of([] { hemivem::make_mesh("hexagons", 3, kL); }).find("unknown mesh generator"), std::string::npos);
}
