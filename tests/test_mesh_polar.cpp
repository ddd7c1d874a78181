// make_polar (hemivem/mesh/generators.hpp): rings, disks and sectors on a polar grid.
#include <hemivem/mesh/generators.hpp>
#include <hemivem/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace hemivem;

namespace {
constexpr double pi = std::numbers::pi;

double length_of(const Mesh& mesh, const std::vector<int>& edges) {
  double sum = 0.0;
  for (int e : edges) sum += mesh.edge_length(e);
  return sum;
}
}  // namespace

TEST(Polar, QuarterRingHasItsCellsVerticesAndSides) {
  const Mesh m = make_polar({1.0, 2.0}, {1.0, 1.5, 2.0}, {0.0, pi / 6, pi / 3, pi / 2});
  EXPECT_EQ(m.num_elements(), 6);
  EXPECT_EQ(m.num_vertices(), 12);
  // the vertices on the axes through the centre lie on them exactly
  for (int v = 0; v < m.num_vertices(); ++v) {
    const Vec2 d = m.vertex(v) - Vec2(1.0, 2.0);
    EXPECT_TRUE(std::abs(d.norm() - 1.0) < 1e-15 || std::abs(d.norm() - 1.5) < 1e-15 ||
                std::abs(d.norm() - 2.0) < 1e-15);
    if (std::abs(d.x()) < 1e-12) EXPECT_EQ(m.vertex(v).x(), 1.0);
    if (std::abs(d.y()) < 1e-12) EXPECT_EQ(m.vertex(v).y(), 2.0);
  }
  // the inscribed polygons' areas: (1/2) r^2 sin(dtheta) per sector
  EXPECT_NEAR(m.total_area(), 3 * 0.5 * (4.0 - 1.0) * std::sin(pi / 6), 1e-14);
  EXPECT_EQ(m.edge_group("outer").size(), 3u);
  EXPECT_EQ(m.edge_group("inner").size(), 3u);
  EXPECT_NEAR(length_of(m, m.edge_group("start")), 1.0, 1e-15);
  EXPECT_NEAR(length_of(m, m.edge_group("end")), 1.0, 1e-15);
  EXPECT_NEAR(length_of(m, m.edge_group("outer")), 3 * 2 * 2.0 * std::sin(pi / 12), 1e-14);
  EXPECT_EQ(m.boundary_edges().size(), 10u);
}

TEST(Polar, DiskAndFullRingClose) {
  const Mesh disk = make_polar({0.0, 0.0}, {0.0, 0.5, 1.0}, {0.0, pi / 2, pi, 1.5 * pi, 2 * pi});
  EXPECT_EQ(disk.num_vertices(), 1 + 2 * 4);
  EXPECT_EQ(disk.num_elements(), 8);           // 4 triangles at the centre, 4 quadrilaterals
  EXPECT_NEAR(disk.total_area(), 2.0, 1e-15);  // the square inscribed in the unit circle
  EXPECT_EQ(disk.boundary_edges().size(), 4u);
  EXPECT_EQ(disk.edge_group("outer").size(), 4u);
  EXPECT_THROW(disk.edge_group("start"), InputError);  // a full turn has no sides
  EXPECT_THROW(disk.edge_group("inner"), InputError);
  const Mesh half = make_polar({0.0, 1.0}, {0.0, 1.0}, {pi, 1.5 * pi, 2 * pi});  // a half disk: triangles
  EXPECT_EQ(half.num_elements(), 2);
  EXPECT_EQ(half.edge_group("start").size(), 1u);
  EXPECT_EQ(half.edge_group("end").size(), 1u);
  EXPECT_EQ(half.vertex(half.edge(half.edge_group("end")[0]).v1).y(), 1.0);
}

TEST(Polar, RefusesWhatIsNoGrid) {
  EXPECT_THROW(make_polar({0, 0}, {1.0}, {0.0, 1.0}), InputError);
  EXPECT_THROW(make_polar({0, 0}, {1.0, 2.0}, {0.0}), InputError);
  EXPECT_THROW(make_polar({0, 0}, {2.0, 1.0}, {0.0, 1.0}), InputError);
  EXPECT_THROW(make_polar({0, 0}, {-1.0, 1.0}, {0.0, 1.0}), InputError);
  EXPECT_THROW(make_polar({0, 0}, {1.0, 2.0}, {0.0, 7.0}), InputError);
  EXPECT_THROW(make_polar({0, 0}, {1.0, NAN}, {0.0, 1.0}), InputError);
  EXPECT_THROW(make_polar({NAN, 0}, {1.0, 2.0}, {0.0, 1.0}), InputError);
}
