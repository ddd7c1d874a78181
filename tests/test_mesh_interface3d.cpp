// Matching two solids' meshes along their plane contact interface (hemivem/mesh/interface3d.hpp):
// both interfaces replaced by their common refinement, the same polygons with the same vertices at
// the same points, paired one to one; what the match keeps (volumes, areas, conformity, face
// groups); idempotence; refusals of interfaces that are not one plane region covered from both
// sides.
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/interface3d.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

constexpr double kTolerance = 1e-8;

const Box kLower{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
const Box kUpper{0.0, 1.0, 0.0, 1.0, 0.5, 1.0};

std::vector<int> top(const Mesh3D& mesh) { return select_box_side(mesh, kLower, "top"); }
std::vector<int> bottom(const Mesh3D& mesh) { return select_box_side(mesh, kUpper, "bottom"); }

// The vertices of a set of faces, sorted.
std::vector<int> vertices_of(const Mesh3D& mesh, const std::vector<int>& faces) {
  std::set<int> out;
  for (int f : faces) out.insert(mesh.face(f).vertices.begin(), mesh.face(f).vertices.end());
  return {out.begin(), out.end()};
}

double area_of(const Mesh3D& mesh, const std::vector<int>& faces) {
  double sum = 0.0;
  for (int f : faces) sum += mesh.face_area(f);
  return sum;
}

std::vector<CellFaces> cells_of(const Mesh3D& mesh) {
  std::vector<CellFaces> cells;
  for (int c = 0; c < mesh.num_cells(); ++c) cells.push_back(mesh.cell(c));
  return cells;
}

// The same vertices bit for bit, the same cells (face loops), regions and face groups.
bool identical(const Mesh3D& a, const Mesh3D& b) {
  if (a.num_vertices() != b.num_vertices()) return false;
  for (int v = 0; v < a.num_vertices(); ++v)
    if (!(a.vertex(v).array() == b.vertex(v).array()).all()) return false;
  return cells_of(a) == cells_of(b) && a.regions() == b.regions() && a.face_groups() == b.face_groups();
}

// True when loop b runs through the vertices of loop a backwards (from any start).
bool reversed_loop(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size() || a.empty()) return false;
  const auto at = std::find(b.begin(), b.end(), a[0]);
  if (at == b.end()) return false;
  const std::size_t n = a.size(), s = static_cast<std::size_t>(at - b.begin());
  for (std::size_t i = 0; i < n; ++i)
    if (a[i] != b[(s + n - i) % n]) return false;
  return true;
}

// Everything the match must keep on one side: `given` with interface `faces` became `matched`
// with interface `matched_faces`, its interface vertices in pairs[k][side].
void expect_side_kept(const Mesh3D& given, const std::vector<int>& faces, const Mesh3D& matched,
                      const std::vector<int>& matched_faces, const MatchedInterface3D& r, int side) {
  SCOPED_TRACE(side == 0 ? "first" : "second");
  // The constructor's checks (conformity, closed cells, no hanging vertex on the boundary), once more.
  EXPECT_TRUE(find_mesh3d_defects(matched.vertices(), cells_of(matched)).empty());
  // Old vertices keep their ids and positions.
  ASSERT_GE(matched.num_vertices(), given.num_vertices());
  for (int v = 0; v < given.num_vertices(); ++v) EXPECT_TRUE(matched.vertex(v) == given.vertex(v)) << "vertex " << v;
  // Cells: same count, regions and volumes (to round-off); the total volume too.
  ASSERT_EQ(matched.num_cells(), given.num_cells());
  EXPECT_EQ(matched.regions(), given.regions());
  for (int c = 0; c < given.num_cells(); ++c)
    EXPECT_NEAR(matched.volume(c), given.volume(c), 1e-13 * given.volume(c)) << "cell " << c;
  EXPECT_NEAR(matched.total_volume(), given.total_volume(), 1e-13 * given.total_volume());
  // The interface: boundary faces of the same total area; the whole boundary too.
  for (int f : matched_faces) EXPECT_TRUE(matched.face(f).on_boundary()) << "face " << f;
  EXPECT_NEAR(area_of(matched, matched_faces), area_of(given, faces), 1e-13 * area_of(given, faces));
  EXPECT_NEAR(area_of(matched, matched.boundary_faces()), area_of(given, given.boundary_faces()),
              1e-13 * area_of(given, given.boundary_faces()));
  // The vertices of the interface are the paired ones, each once, and every old one is paired.
  std::vector<int> paired;
  for (const auto& pr : r.pairs) paired.push_back(pr[static_cast<std::size_t>(side)]);
  std::sort(paired.begin(), paired.end());
  EXPECT_TRUE(std::adjacent_find(paired.begin(), paired.end()) == paired.end());
  EXPECT_EQ(paired, vertices_of(matched, matched_faces));
  for (int v : vertices_of(given, faces)) EXPECT_TRUE(std::binary_search(paired.begin(), paired.end(), v)) << "vertex " << v;
  // Face groups cover the same surface.
  for (const auto& [name, group] : given.face_groups())
    EXPECT_NEAR(area_of(matched, matched.face_group(name)), area_of(given, group), 1e-13 * area_of(given, group))
        << "group " << name;
}

// The checks of a match of two interfaces; the pairs' points are bitwise the same for these
// meshes (whose common points are exact).
MatchedInterface3D expect_good_match(const Mesh3D& first, const std::vector<int>& first_faces, const Mesh3D& second,
                                     const std::vector<int>& second_faces) {
  const MatchedInterface3D r = match_interface_3d(first, first_faces, second, second_faces, kTolerance);
  std::map<int, int> partner;
  for (const auto& [p, q] : r.pairs) {
    EXPECT_TRUE((r.first.vertex(p).array() == r.second.vertex(q).array()).all()) << "pair " << p << ", " << q;
    partner[p] = q;
  }
  EXPECT_TRUE(std::is_sorted(r.pairs.begin(), r.pairs.end()));
  // Face k of both sides: the same polygon, opposite orientations.
  EXPECT_EQ(r.first_faces.size(), r.second_faces.size());
  EXPECT_TRUE(std::is_sorted(r.first_faces.begin(), r.first_faces.end()));
  for (std::size_t k = 0; k < std::min(r.first_faces.size(), r.second_faces.size()); ++k) {
    std::vector<int> mapped;
    for (int v : r.first.face(r.first_faces[k]).vertices) mapped.push_back(partner.count(v) ? partner.at(v) : -1);
    EXPECT_TRUE(reversed_loop(mapped, r.second.face(r.second_faces[k]).vertices)) << "face pair " << k;
    EXPECT_NEAR(r.first.face_area(r.first_faces[k]), r.second.face_area(r.second_faces[k]), 1e-14);
    EXPECT_NEAR(r.first.face_normal(r.first_faces[k]).dot(r.second.face_normal(r.second_faces[k])), -1.0, 1e-14);
  }
  std::set<int> distinct_second(r.second_faces.begin(), r.second_faces.end());
  EXPECT_EQ(distinct_second.size(), r.second_faces.size());
  expect_side_kept(first, first_faces, r.first, r.first_faces, r, 0);
  expect_side_kept(second, second_faces, r.second, r.second_faces, r, 1);
  // Matching again changes nothing.
  const MatchedInterface3D again = match_interface_3d(r.first, r.first_faces, r.second, r.second_faces, kTolerance);
  EXPECT_TRUE(identical(again.first, r.first));
  EXPECT_TRUE(identical(again.second, r.second));
  EXPECT_EQ(again.pairs, r.pairs);
  EXPECT_EQ(again.first_faces, r.first_faces);
  EXPECT_EQ(again.second_faces, r.second_faces);
  return r;
}

// One prism cell over the polygon `base` (counter-clockwise in the xy plane) from z0 to z1; face
// 0 is its bottom.
Mesh3D prism(const std::vector<Eigen::Vector2d>& base, double z0, double z1) {
  std::vector<Vec3> x;
  for (const auto& p : base) x.emplace_back(p.x(), p.y(), z0);
  for (const auto& p : base) x.emplace_back(p.x(), p.y(), z1);
  const int n = static_cast<int>(base.size());
  CellFaces cell(2);
  for (int i = n - 1; i >= 0; --i) cell[0].push_back(i);
  for (int i = 0; i < n; ++i) cell[1].push_back(n + i);
  for (int i = 0; i < n; ++i) cell.push_back({i, (i + 1) % n, (i + 1) % n + n, i + n});
  return Mesh3D(x, {cell});
}

// Tetrahedra on kUpper with the vertices of their bottom inside the square moved in the plane
// z = 0.5 by up to `amount` along x and y (the triangles stay planar).
Mesh3D jiggled_tetrahedra(GridSize3 n, double amount, unsigned seed) {
  const Mesh3D tets = make_tetrahedra(n, kUpper);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> x = tets.vertices();
  for (Vec3& p : x)
    if (p.z() == 0.5 && p.x() > 0.0 && p.x() < 1.0 && p.y() > 0.0 && p.y() < 1.0) {
      p.x() += amount * u(gen);
      p.y() += amount * u(gen);
    }
  return Mesh3D(x, cells_of(tets), tets.regions());
}

// The number of distinct points among the interface vertices of both sides.
std::size_t distinct_points(const Mesh3D& a, const std::vector<int>& fa, const Mesh3D& b, const std::vector<int>& fb) {
  std::set<std::tuple<double, double, double>> points;
  for (int v : vertices_of(a, fa)) points.emplace(a.vertex(v).x(), a.vertex(v).y(), a.vertex(v).z());
  for (int v : vertices_of(b, fb)) points.emplace(b.vertex(v).x(), b.vertex(v).y(), b.vertex(v).z());
  return points.size();
}

}  // namespace

// ---- hand-checkable ------------------------------------------------------------------------

TEST(MatchInterface3D, OneCubeOnFourCubes) {
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower), upper = make_cubes(1, kUpper);
  const MatchedInterface3D r = expect_good_match(lower, top(lower), upper, bottom(upper));
  // 4 interface faces and 9 interface vertices each side; the lower block is unchanged.
  EXPECT_EQ(r.first_faces.size(), 4u);
  EXPECT_EQ(r.pairs.size(), 9u);
  EXPECT_TRUE(identical(r.first, lower));
  // The cube got the 4 edge midpoints and the centre of its bottom (13 vertices), its bottom is
  // split in 4 quadrilaterals and its 4 side faces each gained the midpoint of its bottom edge.
  EXPECT_EQ(r.second.num_vertices(), 13);
  const CellFaces cube = r.second.cell(0);
  ASSERT_EQ(cube.size(), 9u);
  int quadrilaterals_below = 0, pentagons = 0, top_quadrilaterals = 0;
  for (int f : r.second.cell_faces(0)) {
    const auto& loop = r.second.face(f).vertices;
    const Vec3 n = r.second.face_normal(f);
    if (n.z() < -0.5 && loop.size() == 4) ++quadrilaterals_below;
    if (std::abs(n.z()) < 1e-12 && loop.size() == 5) ++pentagons;
    if (n.z() > 0.5 && loop.size() == 4) ++top_quadrilaterals;
  }
  EXPECT_EQ(quadrilaterals_below, 4);
  EXPECT_EQ(pentagons, 4);
  EXPECT_EQ(top_quadrilaterals, 1);
  for (int f : r.second_faces) EXPECT_NEAR(r.second.face_area(f), 0.25, 1e-15);
  // Every midpoint and the centre are copies of the lower block's vertices.
  for (const auto& [p, q] : r.pairs)
    if (q >= upper.num_vertices()) {
      EXPECT_LT(p, lower.num_vertices());
    }
  // Sides swapped: the same, the other way round.
  const MatchedInterface3D s = expect_good_match(upper, bottom(upper), lower, top(lower));
  EXPECT_TRUE(identical(s.first, r.second));
  EXPECT_TRUE(identical(s.second, lower));
}

TEST(MatchInterface3D, CubesThreeByThreeOnFourByFour) {
  // The overlay of two tensor grids is the tensor grid of the union of their lines: 0, 1/4, 1/3,
  // 1/2, 2/3, 3/4, 1, so 7 x 7 points and 6 x 6 faces.
  const Mesh3D lower = make_cubes(GridSize3(3, 3, 2), kLower), upper = make_cubes(GridSize3(4, 4, 1), kUpper);
  const MatchedInterface3D r = expect_good_match(lower, top(lower), upper, bottom(upper));
  EXPECT_EQ(r.pairs.size(), 49u);
  EXPECT_EQ(r.first_faces.size(), 36u);
  // 12 crossings of interior lines, new on both sides: 21 + 12 new below, 12 + 12 above.
  EXPECT_EQ(r.first.num_vertices(), lower.num_vertices() + 33);
  EXPECT_EQ(r.second.num_vertices(), upper.num_vertices() + 24);
  // A crossing: (1/3, 1/4) lies on the lower block's edge x = 1/3, at the same bits on both sides.
  int crossings = 0;
  for (const auto& [p, q] : r.pairs)
    if (p >= lower.num_vertices() && q >= upper.num_vertices()) {
      ++crossings;
      const Vec3& x = r.first.vertex(p);
      EXPECT_EQ(x.z(), 0.5);
      EXPECT_TRUE(x.x() == 1.0 / 3.0 || x.x() == 2.0 / 3.0 || x.y() == 1.0 / 3.0 || x.y() == 2.0 / 3.0) << x.transpose();
    }
  EXPECT_EQ(crossings, 12);
}

// ---- other meshes ----------------------------------------------------------------------------

TEST(MatchInterface3D, CubesAgainstTetrahedra) {
  const Mesh3D lower = make_cubes(GridSize3(3, 3, 1), kLower), upper = make_tetrahedra(GridSize3(4, 4, 1), kUpper);
  const MatchedInterface3D r = expect_good_match(lower, top(lower), upper, bottom(upper));
  EXPECT_GT(r.pairs.size(), distinct_points(lower, top(lower), upper, bottom(upper)));
  expect_good_match(upper, bottom(upper), lower, top(lower));
  const Mesh3D tets = make_tetrahedra(GridSize3(5, 3, 2), kLower);
  expect_good_match(tets, top(tets), upper, bottom(upper));
}

TEST(MatchInterface3D, CubesAgainstVoronoi) {
  const Mesh3D lower = make_cubes(GridSize3(4, 4, 2), kLower), upper = make_voronoi3d(GridSize3(3, 3, 2), kUpper);
  expect_good_match(lower, top(lower), upper, bottom(upper));
  const Mesh3D voronoi_lower = make_voronoi3d(GridSize3(4, 3, 2), kLower, VoronoiOptions{7});
  expect_good_match(voronoi_lower, top(voronoi_lower), upper, bottom(upper));
}

TEST(MatchInterface3D, VoronoiAgainstVoronoi) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const Mesh3D a = make_voronoi3d(GridSize3(4, 5, 1), kLower, VoronoiOptions{seed});
    const Mesh3D b = make_voronoi3d(GridSize3(5, 3, 1), kUpper, VoronoiOptions{seed + 100});
    expect_good_match(a, top(a), b, bottom(b));
  }
}

TEST(MatchInterface3D, CubesAgainstTrianglesInGeneralPosition) {
  // The upper bottom's inner vertices moved by up to 0.05: no line of one side along a line of
  // the other, crossings everywhere.
  for (unsigned seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const Mesh3D lower = make_cubes(GridSize3(4, 4, 1), kLower), upper = jiggled_tetrahedra(GridSize3(5, 4, 1), 0.05, seed);
    const MatchedInterface3D r = expect_good_match(lower, top(lower), upper, bottom(upper));
    EXPECT_GT(r.pairs.size(), distinct_points(lower, top(lower), upper, bottom(upper)));
  }
}

TEST(MatchInterface3D, VerticesWithinTheToleranceArePairedAndKeepTheirCoordinates) {
  // The same 4 x 4 grid on both sides, the upper's inner vertices moved by up to 3e-9 (the
  // distance tolerance is 1e-8 sqrt 2): every vertex pairs, nothing is inserted, and only the
  // lower squares are cut along the triangles' diagonals.
  for (unsigned seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const Mesh3D lower = make_cubes(GridSize3(4, 4, 1), kLower), upper = jiggled_tetrahedra(GridSize3(4, 4, 1), 3e-9, seed);
    const MatchedInterface3D r = match_interface_3d(lower, top(lower), upper, bottom(upper), kTolerance);
    EXPECT_EQ(r.pairs.size(), 25u);
    EXPECT_EQ(r.first_faces.size(), 32u);
    EXPECT_EQ(r.first.num_vertices(), lower.num_vertices());
    EXPECT_TRUE(identical(r.second, upper));
    for (const auto& [p, q] : r.pairs) EXPECT_LE((r.first.vertex(p) - r.second.vertex(q)).norm(), 3e-9 * std::sqrt(2.0));
    expect_side_kept(lower, top(lower), r.first, r.first_faces, r, 0);
    const MatchedInterface3D again = match_interface_3d(r.first, r.first_faces, r.second, r.second_faces, kTolerance);
    EXPECT_TRUE(identical(again.first, r.first));
    EXPECT_TRUE(identical(again.second, r.second));
    EXPECT_EQ(again.pairs, r.pairs);
  }
}

TEST(MatchInterface3D, FeaturesAFewTolerancesApartMatchWithAnotherTolerance) {
  // Vertices moved by up to 1e-7, about 7 distance tolerances of 1e-8 (relative): the sides'
  // features are a few tolerances apart (see the limits). With 1e-10 they are far apart, with
  // 1e-6 they pair; with 1e-8 the match is good or refused, never an invalid mesh.
  int refused = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const Mesh3D lower = make_cubes(GridSize3(4, 4, 1), kLower), upper = jiggled_tetrahedra(GridSize3(4, 4, 1), 1e-7, seed);
    for (const double tolerance : {1e-10, 1e-6}) {
      const MatchedInterface3D r = match_interface_3d(lower, top(lower), upper, bottom(upper), tolerance);
      expect_side_kept(lower, top(lower), r.first, r.first_faces, r, 0);
      expect_side_kept(upper, bottom(upper), r.second, r.second_faces, r, 1);
      if (tolerance == 1e-6) {
        EXPECT_EQ(r.pairs.size(), 25u);
      }
    }
    try {
      const MatchedInterface3D r = match_interface_3d(lower, top(lower), upper, bottom(upper), kTolerance);
      expect_side_kept(lower, top(lower), r.first, r.first_faces, r, 0);
      expect_side_kept(upper, bottom(upper), r.second, r.second_faces, r, 1);
    } catch (const InputError&) {  // MeshError is an InputError
      ++refused;
    }
  }
  EXPECT_LE(refused, 5);
}

TEST(MatchInterface3D, SameMatchAtEveryScale) {
  const Mesh3D lower = make_cubes(GridSize3(3, 3, 1), kLower), upper = make_tetrahedra(GridSize3(4, 5, 1), kUpper);
  const MatchedInterface3D r = match_interface_3d(lower, top(lower), upper, bottom(upper), kTolerance);
  for (const double scale : {1e-6, 1e6}) {
    SCOPED_TRACE(testing::Message() << "scale " << scale);
    const auto scaled = [scale](const Mesh3D& m) {
      std::vector<Vec3> x;
      for (const Vec3& p : m.vertices()) x.push_back(scale * p + Vec3(7.0, 3.0, -2.0) * scale);
      return Mesh3D(x, cells_of(m), m.regions());
    };
    const MatchedInterface3D s = match_interface_3d(scaled(lower), top(lower), scaled(upper), bottom(upper), kTolerance);
    EXPECT_EQ(s.pairs, r.pairs);
    EXPECT_EQ(s.first_faces, r.first_faces);
    EXPECT_EQ(s.second_faces, r.second_faces);
    EXPECT_EQ(cells_of(s.first), cells_of(r.first));
    EXPECT_EQ(cells_of(s.second), cells_of(r.second));
  }
}

TEST(MatchInterface3D, ZeroToleranceOnExactMeshes) {
  // Common points of these grids are bitwise equal: the round-off tolerance alone gives the same match.
  const Mesh3D lower = make_cubes(GridSize3(2, 4, 1), kLower), upper = make_tetrahedra(GridSize3(4, 3, 1), kUpper);
  const MatchedInterface3D r = match_interface_3d(lower, top(lower), upper, bottom(upper), kTolerance);
  const MatchedInterface3D z = match_interface_3d(lower, top(lower), upper, bottom(upper), 0.0);
  EXPECT_TRUE(identical(z.first, r.first));
  EXPECT_TRUE(identical(z.second, r.second));
  EXPECT_EQ(z.pairs, r.pairs);
  EXPECT_EQ(z.first_faces, r.first_faces);
  EXPECT_EQ(z.second_faces, r.second_faces);
}

TEST(MatchInterface3D, NeverCrashesOnRandomFaceSets) {
  // Random sets of boundary faces (any side of the blocks) and random parts of the contact sides:
  // each is matched into valid meshes or refused with an InputError.
  const Mesh3D lower = make_cubes(GridSize3(3, 3, 2), kLower), upper = make_tetrahedra(GridSize3(2, 3, 1), kUpper);
  std::mt19937 gen(11);
  int matched = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const bool contact_sides = trial % 2 == 0;
    const std::vector<int> from_a = contact_sides ? top(lower) : lower.boundary_faces();
    const std::vector<int> from_b = contact_sides ? bottom(upper) : upper.boundary_faces();
    const double keep = std::uniform_real_distribution<double>(0.3, 1.2)(gen);
    std::vector<int> fa, fb;
    for (int f : from_a)
      if (std::uniform_real_distribution<double>(0.0, 1.0)(gen) < keep) fa.push_back(f);
    for (int f : from_b)
      if (std::uniform_real_distribution<double>(0.0, 1.0)(gen) < keep) fb.push_back(f);
    try {
      const MatchedInterface3D r = match_interface_3d(lower, fa, upper, fb, kTolerance);
      ++matched;
      SCOPED_TRACE(testing::Message() << "trial " << trial);
      expect_side_kept(lower, fa, r.first, r.first_faces, r, 0);
      expect_side_kept(upper, fb, r.second, r.second_faces, r, 1);
    } catch (const InputError& e) {
      EXPECT_FALSE(std::string(e.what()).empty());
    }
  }
  EXPECT_GT(matched, 0);
}

TEST(MatchInterface3D, FaceGroupsFollowThePieces) {
  Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower);
  const Mesh3D upper = make_cubes(GridSize3(3, 3, 1), kUpper);
  lower.set_face_group("contact", top(lower));
  lower.set_face_group("side", select_box_side(lower, kLower, "x0"));
  const MatchedInterface3D r = expect_good_match(lower, top(lower), upper, bottom(upper));
  // The contact group is the interface after the match; the side faces gained vertices.
  std::vector<int> group = r.first.face_group("contact");
  std::sort(group.begin(), group.end());
  EXPECT_EQ(group, r.first_faces);
  for (int f : r.first.face_group("side")) EXPECT_EQ(r.first.face(f).vertices.size(), 5u) << "face " << f;
}

TEST(MatchInterface3D, LargerGrids) {
  const Mesh3D lower = make_cubes(GridSize3(12, 12, 1), kLower), upper = make_cubes(GridSize3(17, 17, 1), kUpper);
  const MatchedInterface3D r = expect_good_match(lower, top(lower), upper, bottom(upper));
  // 13 + 18 - 2 distinct lines each way.
  EXPECT_EQ(r.pairs.size(), 29u * 29u);
  EXPECT_EQ(r.first_faces.size(), 28u * 28u);
  const Mesh3D tets = make_tetrahedra(GridSize3(11, 13, 1), kUpper);
  expect_good_match(lower, top(lower), tets, bottom(tets));
  // A few thousand faces a side.
  const Mesh3D many = make_cubes(GridSize3(60, 60, 1), kLower), others = make_tetrahedra(GridSize3(41, 43, 1), kUpper);
  const MatchedInterface3D big = expect_good_match(many, top(many), others, bottom(others));
  EXPECT_GT(big.first_faces.size(), top(many).size() + bottom(others).size());
}

TEST(MatchInterface3D, InclinedInterface) {
  // The 2 x 2 and 3 x 3 blocks turned about a diagonal axis and moved off the origin: the plane is
  // no coordinate plane, and no coordinate is exact.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  const Vec3 shift(3.0, -2.0, 5.0);
  const auto moved = [&](const Mesh3D& m) {
    std::vector<Vec3> x;
    for (const Vec3& p : m.vertices()) x.push_back(turn * p + shift);
    return Mesh3D(x, cells_of(m), m.regions());
  };
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower), upper = make_cubes(GridSize3(3, 3, 1), kUpper);
  const Mesh3D a = moved(lower), b = moved(upper);
  const MatchedInterface3D r = match_interface_3d(a, top(lower), b, bottom(upper), kTolerance);
  EXPECT_EQ(r.pairs.size(), 25u);  // lines 0, 1/3, 1/2, 2/3, 1 each way
  EXPECT_EQ(r.first_faces.size(), 16u);
  expect_side_kept(a, top(lower), r.first, r.first_faces, r, 0);
  expect_side_kept(b, bottom(upper), r.second, r.second_faces, r, 1);
  for (const auto& [p, q] : r.pairs) EXPECT_LE((r.first.vertex(p) - r.second.vertex(q)).norm(), 1e-14);
  const MatchedInterface3D again = match_interface_3d(r.first, r.first_faces, r.second, r.second_faces, kTolerance);
  EXPECT_TRUE(identical(again.first, r.first));
  EXPECT_TRUE(identical(again.second, r.second));
  EXPECT_EQ(again.pairs, r.pairs);
}

// ---- refusals ----------------------------------------------------------------------------------

TEST(MatchInterface3D, RefusesBadFaceLists) {
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 2), kLower), upper = make_cubes(2, kUpper);
  const auto lt = top(lower), ub = bottom(upper);
  EXPECT_NE(test::input_error_of([&] { match_interface_3d(lower, {}, upper, ub, kTolerance); })
                .find("the interface of the first mesh has no faces"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([&] { match_interface_3d(lower, lt, upper, {}, kTolerance); })
                .find("the interface of the second mesh has no faces"),
            std::string::npos);
  const std::string range = test::input_error_of([&] { match_interface_3d(lower, lt, upper, {-1}, kTolerance); });
  EXPECT_NE(range.find("interface face id -1 of the second mesh is out of range [0, " +
                       std::to_string(upper.num_faces()) + ")"),
            std::string::npos)
      << range;
  int inner = 0;
  while (lower.face(inner).on_boundary()) ++inner;
  const std::string interior = test::input_error_of([&] { match_interface_3d(lower, {inner}, upper, ub, kTolerance); });
  EXPECT_NE(interior.find("interface face " + std::to_string(inner) + " of the first mesh is not a boundary face"),
            std::string::npos)
      << interior;
  EXPECT_NE(test::input_error_of([&] { match_interface_3d(lower, lt, upper, ub, 0.2); }).find("must be in [0, 0.1]"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([&] { match_interface_3d(lower, lt, upper, ub, -1e-3); }).find("must be in [0, 0.1]"),
            std::string::npos);
}

TEST(MatchInterface3D, RefusesInterfacesThatDoNotCoverTheSameRegion) {
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower);
  // A block shifted by half its width: the lower block's corner (0, 0) is outside the upper's bottom.
  const Box shifted{0.5, 1.5, 0.0, 1.0, 0.5, 1.0};
  const Mesh3D upper = make_cubes(GridSize3(3, 3, 1), shifted);
  const auto ub = select_box_side(upper, shifted, "bottom");
  const std::string shift = test::input_error_of([&] { match_interface_3d(lower, top(lower), upper, ub, kTolerance); });
  EXPECT_NE(shift.find("interface vertex 9 (0, 0, 0.5) of the first mesh is 0.5 away from the interface of the second "
                       "mesh, more than the tolerance"),
            std::string::npos)
      << shift;
  EXPECT_NE(shift.find("must cover the same region"), std::string::npos) << shift;
  // Part of the lower block's top: the upper block's corner (1, 1) is outside it.
  std::vector<int> part;
  for (int f : top(lower))
    if (lower.face_centroid(f).x() < 0.5) part.push_back(f);
  const Mesh3D full = make_cubes(GridSize3(3, 3, 1), kUpper);
  const std::string partial = test::input_error_of([&] { match_interface_3d(lower, part, full, bottom(full), kTolerance); });
  EXPECT_NE(partial.find("of the second mesh is 0.16666666666666"), std::string::npos) << partial;
  EXPECT_NE(partial.find("away from the interface of the first mesh"), std::string::npos)
      << partial;
  // A vertex within the tolerance of two vertices of the other side.
  const Mesh3D fine = make_cubes(GridSize3(16, 16, 1), kUpper);
  const std::string two = test::input_error_of([&] { match_interface_3d(lower, top(lower), fine, bottom(fine), 0.05); });
  EXPECT_NE(two.find("of the first mesh is within the tolerance"), std::string::npos) << two;
  EXPECT_NE(two.find("of two interface vertices of the second mesh"), std::string::npos) << two;
}

TEST(MatchInterface3D, RefusesUncoveredFacesBetweenMatchingVertices) {
  // An L-shaped lower region (three unit squares of a 2 x 2 block) against a pentagon above, its
  // convex hull: every vertex of each side lies on the other's region, but the pentagon also
  // covers the triangle (1, 1), (2, 1), (1, 2) (area 1/2) that the L does not.
  const Box big{0.0, 2.0, 0.0, 2.0, 0.0, 0.5};
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), big);
  std::vector<int> ell;
  for (int f : select_box_side(lower, big, "top"))
    if (lower.face_centroid(f).x() < 1.0 || lower.face_centroid(f).y() < 1.0) ell.push_back(f);
  ASSERT_EQ(ell.size(), 3u);
  const Mesh3D upper = prism({{0, 0}, {2, 0}, {2, 1}, {1, 2}, {0, 2}}, 0.5, 1.0);
  const std::string message = test::input_error_of([&] { match_interface_3d(lower, ell, upper, {0}, kTolerance); });
  EXPECT_NE(message.find("interface face 0 of the second mesh (area 3.5) is covered by the faces of the first mesh over "
                         "an area of 3: the two interfaces must cover the same region"),
            std::string::npos)
      << message;
}

TEST(MatchInterface3D, RefusesNonPlanarInterfaces) {
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower), upper = make_cubes(2, kUpper);
  // The top and the side x = 1 of the lower block: an L-shaped (piecewise-planar) interface.
  std::vector<int> bent = top(lower);
  for (int f : select_box_side(lower, kLower, "x1")) bent.push_back(f);
  const std::string message = test::input_error_of([&] { match_interface_3d(lower, bent, upper, bottom(upper), kTolerance); });
  EXPECT_NE(message.find("of the first mesh"), std::string::npos) << message;
  EXPECT_NE(message.find("off the plane of the interface"), std::string::npos) << message;
  EXPECT_NE(message.find("must be planar"), std::string::npos) << message;
  // The second side off the plane: the upper block raised by 0.01.
  const Box raised{0.0, 1.0, 0.0, 1.0, 0.51, 1.0};
  const Mesh3D high = make_cubes(2, raised);
  const std::string off = test::input_error_of(
      [&] { match_interface_3d(lower, top(lower), high, select_box_side(high, raised, "bottom"), kTolerance); });
  EXPECT_NE(off.find("of the second mesh (in face"), std::string::npos) << off;
  EXPECT_NE(off.find("is 0.01"), std::string::npos) << off;
  EXPECT_NE(off.find("off the plane of the interface (through (0.5, 0.5, 0.5), normal (0, 0, 1))"), std::string::npos)
      << off;
  // Within a tolerance of 0.02 of the interface's size (sqrt 2), 0.01 is in the plane.
  EXPECT_NO_THROW(match_interface_3d(lower, top(lower), high, select_box_side(high, raised, "bottom"), 0.02));
}

TEST(MatchInterface3D, RefusesTheSameOrientationOnBothSides) {
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower), other = make_cubes(GridSize3(3, 3, 1), kLower);
  const std::string message = test::input_error_of([&] { match_interface_3d(lower, top(lower), other, top(other), kTolerance); });
  EXPECT_NE(message.find("of the second mesh has the same orientation as the interface of the first mesh"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("same side of the interface"), std::string::npos) << message;
  // One face of the first side facing the other way: the lower block's top with the upper's bottom.
  const Mesh3D upper = make_cubes(GridSize3(2, 2, 1), kUpper);
  const std::string folded = test::input_error_of([&] {
    // Two blocks in one mesh, touching along a line: the top of [0,1]^2 x [0,0.5] and the bottom of
    // [1,1.5] x [0,1] x [0.5,1], both at z = 0.5, facing opposite ways.
    const Box beside{1.0, 1.5, 0.0, 1.0, 0.5, 1.0};
    const Mesh3D b = make_cubes(1, beside);
    std::vector<Vec3> x = lower.vertices();
    std::vector<CellFaces> cells = cells_of(lower);
    const int n = static_cast<int>(x.size());
    for (const Vec3& p : b.vertices()) x.push_back(p);
    for (CellFaces c : cells_of(b)) {
      for (auto& loop : c)
        for (int& v : loop) v += n;
      cells.push_back(c);
    }
    const Mesh3D both(x, cells);
    std::vector<int> faces = top(both);
    for (int f : select_box_side(both, beside, "bottom")) faces.push_back(f);
    match_interface_3d(both, faces, upper, bottom(upper), kTolerance);
  });
  EXPECT_NE(folded.find("of the first mesh faces the other way"), std::string::npos) << folded;
}

TEST(MatchInterface3D, RefusesNonConvexFaces) {
  // An L-shaped prism above the lower block: its bottom is one non-convex hexagon.
  const Mesh3D upper = prism({{0, 0}, {1, 0}, {1, 0.5}, {0.5, 0.5}, {0.5, 1}, {0, 1}}, 0.5, 1.0);
  const Mesh3D lower = make_cubes(GridSize3(2, 2, 1), kLower);
  std::vector<int> ell_top;
  for (int f : top(lower))
    if (lower.face_centroid(f).x() < 0.5 || lower.face_centroid(f).y() < 0.5) ell_top.push_back(f);
  const std::string message = test::input_error_of([&] { match_interface_3d(lower, ell_top, upper, {0}, kTolerance); });
  EXPECT_NE(message.find("interface face 0 of the second mesh is not convex: its vertex"), std::string::npos) << message;
  EXPECT_NE(message.find("split the face into convex ones"), std::string::npos) << message;
}
