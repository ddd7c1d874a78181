// make_voronoi3d: valid conforming meshes tiling the box, boundary faces exactly on its sides,
// determinism, Lloyd iterations (also split among processes) and input checks.
#include <hemivem/mesh/generators3d.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "thread_rows.hpp"

#include <algorithm>
#include <array>
#include <barrier>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <thread>
#include <limits>
#include <string>
#include <vector>

using hemivem::Box;
using hemivem::GridSize3;
using hemivem::Mesh3D;
using hemivem::Vec3;
using hemivem::VoronoiOptions;
using hemivem::test::input_error_of;

namespace {

const Box kBox{-1.0, 2.0, 0.5, 1.5, -0.25, 0.5};  // not a cube, not at the origin

VoronoiOptions seeded(std::uint64_t seed, int lloyd = 100) {
  VoronoiOptions o;
  o.seed = seed;
  o.max_lloyd_iterations = lloyd;
  return o;
}

double box_volume(const Box& b) { return b.size(0) * b.size(1) * b.size(2); }

std::vector<hemivem::CellFaces> cells_of(const Mesh3D& m) {
  std::vector<hemivem::CellFaces> cells;
  for (int c = 0; c < m.num_cells(); ++c) cells.push_back(m.cell(c));
  return cells;
}

/// The axes (bit a) on whose lower or upper side of the box a point lies exactly.
unsigned sides_of(const Vec3& p, const Box& b) {
  unsigned s = 0;
  for (int a = 0; a < 3; ++a) {
    if (p[a] == b.lower(a)) s |= 1u << (2 * a);
    if (p[a] == b.upper(a)) s |= 1u << (2 * a + 1);
  }
  return s;
}

/// The mesh tiles the box: valid by the rules of Mesh3D, its volume the box's, every vertex
/// inside, every boundary face exactly on one side and every face on a side on the boundary.
void expect_tiles_box(const Mesh3D& m, const Box& b, int cells) {
  EXPECT_EQ(m.num_cells(), cells);
  EXPECT_TRUE(hemivem::find_mesh3d_defects(m.vertices(), cells_of(m)).empty());
  const double volume = box_volume(b);
  EXPECT_NEAR(m.total_volume(), volume, 1e-12 * volume);
  for (int c = 0; c < m.num_cells(); ++c) EXPECT_GT(m.volume(c), 0.0);
  for (const Vec3& p : m.vertices())
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(p[a], b.lower(a));
      EXPECT_LE(p[a], b.upper(a));
    }
  double boundary_area = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) {
    unsigned common = ~0u;
    for (int v : m.face(f).vertices) common &= sides_of(m.vertex(v), b);
    EXPECT_EQ(m.face(f).on_boundary(), common != 0u) << "face " << f;
    if (m.face(f).on_boundary()) boundary_area += m.face_area(f);
  }
  const double area = 2.0 * (b.size(0) * b.size(1) + b.size(1) * b.size(2) + b.size(2) * b.size(0));
  EXPECT_NEAR(boundary_area, area, 1e-12 * area);
  // the boundary faces on each side cover it
  for (const char* side : {"x0", "x1", "y0", "y1", "z0", "z1"}) {
    double on_side = 0.0;
    for (int f : hemivem::select_box_side(m, b, side, 0.0)) on_side += m.face_area(f);
    const int axis = side[0] - 'x';
    const double expected = box_volume(b) / b.size(axis);
    EXPECT_NEAR(on_side, expected, 1e-12 * expected) << side;
  }
}

bool identical(const Mesh3D& a, const Mesh3D& b) {
  if (a.num_vertices() != b.num_vertices() || a.num_cells() != b.num_cells()) return false;
  for (int i = 0; i < a.num_vertices(); ++i)
    if (a.vertex(i).x() != b.vertex(i).x() || a.vertex(i).y() != b.vertex(i).y() || a.vertex(i).z() != b.vertex(i).z())
      return false;
  for (int c = 0; c < a.num_cells(); ++c)
    if (a.cell(c) != b.cell(c)) return false;
  return true;
}

/// Relative standard deviation of the cell volumes.
double volume_spread(const Mesh3D& m) {
  const double mean = m.total_volume() / m.num_cells();
  double s = 0.0;
  for (int c = 0; c < m.num_cells(); ++c) s += (m.volume(c) - mean) * (m.volume(c) - mean);
  return std::sqrt(s / m.num_cells()) / mean;
}

TEST(Voronoi3D, TilesTheBoxForSeveralSizesAndSeeds) {
  for (const GridSize3 n : {GridSize3(1), GridSize3(2), GridSize3(3), GridSize3(4, 3, 2), GridSize3(1, 1, 5)})
    for (const std::uint64_t seed : {1u, 2u, 7u}) {
      SCOPED_TRACE("n = " + n.text() + ", seed " + std::to_string(seed));
      expect_tiles_box(hemivem::make_voronoi3d(n, kBox, seeded(seed)), kBox, n.nx * n.ny * n.nz);
    }
  SCOPED_TRACE("n = 6");
  expect_tiles_box(hemivem::make_voronoi3d(6, kBox, seeded(3)), kBox, 216);
}

TEST(Voronoi3D, RawCellsOfManySeedsTileTheBox) {
  // without Lloyd iterations the cells are the least regular: small faces and short edges
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_tiles_box(hemivem::make_voronoi3d(GridSize3(3, 4, 2), kBox, seeded(seed, 0)), kBox, 24);
  }
  expect_tiles_box(hemivem::make_voronoi3d(8, Box{}, seeded(11, 0)), Box{}, 512);
}

TEST(Voronoi3D, SymmetricSeedsAfterLongLloydIterations) {
  // Lloyd iterations without a tolerance drive 2 x 2 x 2 seeds in a cube to the centres of its
  // octants, where eight cells meet at the centre: an exactly degenerate Voronoi diagram.
  VoronoiOptions o = seeded(1, 1000);
  o.lloyd_tolerance = 0.0;
  const Mesh3D m = hemivem::make_voronoi3d(2, Box{}, o);
  expect_tiles_box(m, Box{}, 8);
  for (int c = 0; c < 8; ++c) EXPECT_NEAR(m.volume(c), 0.125, 1e-6);
  o.seed = 5;
  expect_tiles_box(hemivem::make_voronoi3d(3, kBox, o), kBox, 27);
}

TEST(Voronoi3D, ScaledBoxes) {
  for (const double s : {1e-40, 1e-6, 1e6, 1e40}) {
    SCOPED_TRACE("scale " + std::to_string(s));
    const Box b{-s, 2 * s, 3 * s, 4 * s, 0.0, 0.5 * s};
    expect_tiles_box(hemivem::make_voronoi3d(3, b, seeded(4, 20)), b, 27);
  }
  const Box far{1e6, 1e6 + 1.0, -1e6 - 1.0, -1e6, 0.0, 1.0};  // far from the origin
  const Mesh3D m = hemivem::make_voronoi3d(3, far, seeded(4, 20));
  expect_tiles_box(m, far, 27);
  // the faces' centroids are computed relative to a vertex of theirs: those on the box's sides
  // lie on them, and the volume is the box's to round-off of its size, not of its distance
  // from the origin (1e6 times more)
  EXPECT_NEAR(m.total_volume(), 1.0, 1e-14);
}

using hemivem::test::ThreadRows;

// the Lloyd iterations split among 2 and 3 processes (threads here; each computing the cells of
// its share of the seeds): every process makes the mesh one process makes, to the bit
TEST(Voronoi3D, LloydIterationsSplitAmongProcessesMakeOneProcesssMesh) {
  const GridSize3 n(5, 4, 3);
  const Mesh3D whole = hemivem::make_voronoi3d(n, kBox, seeded(4));
  for (const int size : {2, 3}) {
    SCOPED_TRACE(std::to_string(size) + " processes");
    const auto made = hemivem::test::on_threads(size, [&](const ThreadRows& rows) {
      VoronoiOptions o = seeded(4);
      o.processes = &rows;
      return hemivem::make_voronoi3d(n, kBox, o);
    });
    for (const Mesh3D& m : made) EXPECT_TRUE(identical(m, whole));
  }
  // with the iterations cut short the mesh differs: the comparison above can fail
  EXPECT_FALSE(identical(hemivem::make_voronoi3d(n, kBox, seeded(4, 3)), whole));
}

TEST(Voronoi3D, DeterministicPerSeed) {
  const Mesh3D a = hemivem::make_voronoi3d(GridSize3(4, 3, 2), kBox, seeded(9));
  const Mesh3D b = hemivem::make_voronoi3d(GridSize3(4, 3, 2), kBox, seeded(9));
  EXPECT_TRUE(identical(a, b));
  const Mesh3D c = hemivem::make_voronoi3d(GridSize3(4, 3, 2), kBox, seeded(10));
  EXPECT_FALSE(identical(a, c));
  EXPECT_NE(a.vertex(a.num_vertices() / 2), c.vertex(c.num_vertices() / 2));
}

TEST(Voronoi3D, LloydIterationsEvenOutTheCells) {
  const Mesh3D raw = hemivem::make_voronoi3d(5, Box{}, seeded(2, 0));
  const Mesh3D few = hemivem::make_voronoi3d(5, Box{}, seeded(2, 5));
  const Mesh3D many = hemivem::make_voronoi3d(5, Box{}, seeded(2, 100));
  EXPECT_LT(volume_spread(few), 0.5 * volume_spread(raw));
  EXPECT_LT(volume_spread(many), volume_spread(few));
  // the iterations stop once no seed moves by more than the tolerance
  VoronoiOptions loose = seeded(2, 100);
  loose.lloyd_tolerance = 0.5;
  const Mesh3D stopped = hemivem::make_voronoi3d(5, Box{}, loose);
  EXPECT_FALSE(identical(stopped, many));
  EXPECT_GT(volume_spread(stopped), volume_spread(many));
}

TEST(Voronoi3D, InputErrors) {
  auto make = [](GridSize3 n, const Box& b, const VoronoiOptions& o = {}) {
    return input_error_of([&] { hemivem::make_voronoi3d(n, b, o); });
  };
  for (const GridSize3 n : {GridSize3(0), GridSize3(-1), GridSize3(2, 0, 2), GridSize3(1001, 1, 1)})
    EXPECT_NE(make(n, Box{}).find("voronoi mesh"), std::string::npos) << n.text();
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  for (const Box& b : {Box{1, 0, 0, 1, 0, 1}, Box{0, 1, 0, 0, 0, 1}, Box{0, 1, 0, 1, 0, -1}, Box{0, inf, 0, 1, 0, 1},
                       Box{nan, 1, 0, 1, 0, 1}, Box{0, 1, 0, 1, 0, 1e300}, Box{1e9, 1e9 + 1e-3, 0, 1, 0, 1}})
    EXPECT_NE(make(2, b), "");
  VoronoiOptions o;
  o.max_lloyd_iterations = -1;
  EXPECT_NE(make(2, Box{}, o).find("max_lloyd_iterations"), std::string::npos);
  o.max_lloyd_iterations = 10;
  o.lloyd_tolerance = -1.0;
  EXPECT_NE(make(2, Box{}, o).find("lloyd_tolerance"), std::string::npos);
  o.lloyd_tolerance = nan;
  EXPECT_NE(make(2, Box{}, o).find("lloyd_tolerance"), std::string::npos);
  EXPECT_EQ(make(2, Box{}), "");
}

}  // namespace
