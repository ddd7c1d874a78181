// Matching two bodies' meshes along their contact interface (hemivem/mesh/interface.hpp): the
// interface vertices of each side inserted into the other's edges, one to one at the same points;
// what the match keeps (areas, boundary, interior edges, edge groups); idempotence and symmetry;
// the patch test on matched meshes; refusals of interfaces that do not cover the same curve.
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/interface.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/material.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

constexpr double kTolerance = 1e-8;

const Rectangle kLower{0.0, 1.0, 0.0, 1.0};
const Rectangle kUpper{0.0, 1.0, 1.0, 2.0};

std::vector<int> side_edges(const Mesh& mesh, const Rectangle& r, const std::string& side) {
  return select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(r, side)});
}

// The vertices of a set of edges, sorted.
std::vector<int> vertices_of(const Mesh& mesh, const std::vector<int>& edges) {
  std::set<int> out;
  for (int g : edges) {
    out.insert(mesh.edge(g).v0);
    out.insert(mesh.edge(g).v1);
  }
  return {out.begin(), out.end()};
}

double length_of(const Mesh& mesh, const std::vector<int>& edges) {
  double sum = 0.0;
  for (int g : edges) sum += mesh.edge_length(g);
  return sum;
}

// The vertex pairs of the interior edges.
std::set<std::pair<int, int>> interior_edges(const Mesh& mesh) {
  std::set<std::pair<int, int>> out;
  for (const MeshEdge& e : mesh.edges())
    if (!e.on_boundary()) out.emplace(std::min(e.v0, e.v1), std::max(e.v0, e.v1));
  return out;
}

// Everything the match must give and keep on one side: `given` with interface `edges` became
// `matched` with interface `matched_edges`, its vertices in pairs[k][side].
void expect_side_kept(const Mesh& given, const std::vector<int>& edges, const Mesh& matched,
                      const std::vector<int>& matched_edges, const MatchedInterface& r, int side,
                      const std::vector<int>& vertex_of) {
  SCOPED_TRACE(side == 0 ? "first" : "second");
  // The constructor's checks, once more.
  EXPECT_TRUE(find_mesh_defects(matched.vertices(), matched.elements()).empty());
  // Old vertices keep their ids and positions; only vertices were added, one per interface
  // point the side did not have.
  ASSERT_EQ(vertex_of.size(), static_cast<std::size_t>(given.num_vertices()));
  for (int v = 0; v < given.num_vertices(); ++v) {
    EXPECT_EQ(vertex_of[static_cast<std::size_t>(v)], v);
    EXPECT_TRUE(matched.vertex(v) == given.vertex(v)) << "vertex " << v;
  }
  const std::vector<int> old_interface = vertices_of(given, edges);
  EXPECT_EQ(matched.num_vertices(), given.num_vertices() + static_cast<int>(r.pairs.size() - old_interface.size()));
  // Elements: same count, regions and areas (to round-off); the total area too.
  ASSERT_EQ(matched.num_elements(), given.num_elements());
  EXPECT_EQ(matched.regions(), given.regions());
  for (int e = 0; e < given.num_elements(); ++e)
    EXPECT_NEAR(matched.area(e), given.area(e), 1e-13 * given.area(e)) << "element " << e;
  EXPECT_NEAR(matched.total_area(), given.total_area(), 1e-13 * given.total_area());
  // No interior edge became a boundary edge or was made: the interior edges are the same.
  EXPECT_EQ(interior_edges(matched), interior_edges(given));
  // The boundary: same total length, and the interface the same length.
  EXPECT_NEAR(length_of(matched, matched.boundary_edges()), length_of(given, given.boundary_edges()),
              1e-13 * length_of(given, given.boundary_edges()));
  EXPECT_NEAR(length_of(matched, matched_edges), length_of(given, edges), 1e-13 * length_of(given, edges));
  // The interface edges join consecutive pairs and are boundary edges.
  ASSERT_EQ(matched_edges.size() + 1, r.pairs.size());
  for (std::size_t k = 0; k < matched_edges.size(); ++k) {
    const MeshEdge& e = matched.edge(matched_edges[k]);
    EXPECT_TRUE(e.on_boundary());
    const int p = r.pairs[k][static_cast<std::size_t>(side)], q = r.pairs[k + 1][static_cast<std::size_t>(side)];
    EXPECT_TRUE((e.v0 == p && e.v1 == q) || (e.v0 == q && e.v1 == p)) << "interface edge " << k;
  }
  // Every vertex of the interface is in one pair, and every old one is.
  std::vector<int> paired;
  for (const auto& pr : r.pairs) paired.push_back(pr[static_cast<std::size_t>(side)]);
  std::sort(paired.begin(), paired.end());
  EXPECT_TRUE(std::adjacent_find(paired.begin(), paired.end()) == paired.end());
  EXPECT_EQ(paired, vertices_of(matched, matched_edges));
  for (int v : old_interface) EXPECT_TRUE(std::binary_search(paired.begin(), paired.end(), v)) << "vertex " << v;
}

// The checks of a match of two interfaces.
MatchedInterface expect_good_match(const Mesh& first, const std::vector<int>& first_edges, const Mesh& second,
                                   const std::vector<int>& second_edges) {
  const MatchedInterface r = match_interface(first, first_edges, second, second_edges, kTolerance);
  // Pairs at the same point, bit for bit, for these meshes (whose shared points are exact).
  for (const auto& [p, q] : r.pairs) {
    EXPECT_EQ(r.first.vertex(p).x(), r.second.vertex(q).x()) << "pair " << p << ", " << q;
    EXPECT_EQ(r.first.vertex(p).y(), r.second.vertex(q).y()) << "pair " << p << ", " << q;
  }
  // As many pairs as distinct points in the union of both interfaces.
  std::set<std::pair<double, double>> points;
  for (int v : vertices_of(first, first_edges)) points.emplace(first.vertex(v).x(), first.vertex(v).y());
  for (int v : vertices_of(second, second_edges)) points.emplace(second.vertex(v).x(), second.vertex(v).y());
  EXPECT_EQ(r.pairs.size(), points.size());
  // Ordered along the interface: the path through the pairs is as long as the interface.
  double path = 0.0;
  for (std::size_t k = 0; k + 1 < r.pairs.size(); ++k)
    path += (r.first.vertex(r.pairs[k + 1][0]) - r.first.vertex(r.pairs[k][0])).norm();
  EXPECT_NEAR(path, length_of(first, first_edges), 1e-13 * path);
  expect_side_kept(first, first_edges, r.first, r.first_edges, r, 0, r.first_vertex_of);
  expect_side_kept(second, second_edges, r.second, r.second_edges, r, 1, r.second_vertex_of);
  return r;
}

// Matching again changes nothing; swapping the sides swaps everything.
void expect_idempotent_and_symmetric(const Mesh& first, const std::vector<int>& first_edges, const Mesh& second,
                                     const std::vector<int>& second_edges) {
  const MatchedInterface r = match_interface(first, first_edges, second, second_edges, kTolerance);
  const MatchedInterface again = match_interface(r.first, r.first_edges, r.second, r.second_edges, kTolerance);
  EXPECT_TRUE(test::identical(again.first, r.first));
  EXPECT_TRUE(test::identical(again.second, r.second));
  EXPECT_EQ(again.pairs, r.pairs);
  EXPECT_EQ(again.first_edges, r.first_edges);
  EXPECT_EQ(again.second_edges, r.second_edges);

  const MatchedInterface s = match_interface(second, second_edges, first, first_edges, kTolerance);
  EXPECT_TRUE(test::identical(s.first, r.second));
  EXPECT_TRUE(test::identical(s.second, r.first));
  ASSERT_EQ(s.pairs.size(), r.pairs.size());
  const std::size_t m = r.pairs.size();
  for (std::size_t k = 0; k < m; ++k) {
    EXPECT_EQ(s.pairs[k][0], r.pairs[m - 1 - k][1]) << "pair " << k;
    EXPECT_EQ(s.pairs[k][1], r.pairs[m - 1 - k][0]) << "pair " << k;
  }
  std::vector<int> reversed_first(r.first_edges.rbegin(), r.first_edges.rend());
  std::vector<int> reversed_second(r.second_edges.rbegin(), r.second_edges.rend());
  EXPECT_EQ(s.first_edges, reversed_second);
  EXPECT_EQ(s.second_edges, reversed_first);
}

// ---- patch test ---------------------------------------------------------------------------

struct LinearCase {
  Vec2 a{0.3, -0.7};
  Eigen::Matrix2d G = (Eigen::Matrix2d() << 0.011, -0.027, 0.019, 0.005).finished();
  Vec2 operator()(const Vec2& x) const { return a + G * x; }
};

const Material kMaterial{65.0, 0.29};

// The largest nodal error, relative to the field's largest value, of the VEM solution with the
// linear field's values on the boundary edges `held` and its traction sigma n on `loaded`
// (outward normal `normal`); and the same over the vertices `watched` alone into *watched_error.
double patch_error(const Mesh& mesh, const std::vector<int>& held, const std::vector<int>& loaded, const Vec2& normal,
                   const std::vector<int>& watched, double* watched_error) {
  const LinearCase exact;
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(kMaterial);
  p.dirichlet.push_back(DirichletCondition{held, exact, {true, true}});
  if (!loaded.empty()) {
    const Lame l = lame(kMaterial, PlaneModel::strain);
    const Eigen::Matrix2d eps = 0.5 * (exact.G + exact.G.transpose());
    const Eigen::Matrix2d sigma = l.lambda * eps.trace() * Eigen::Matrix2d::Identity() + 2.0 * l.mu * eps;
    const Vec2 t = sigma * normal;
    p.tractions.push_back(TractionLoad{loaded, [t](const Vec2&) { return t; }, {}});
  }
  const Eigen::VectorXd u = test::solve(assemble(p));
  double scale = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) scale = std::max(scale, exact(mesh.vertex(v)).cwiseAbs().maxCoeff());
  double worst = 0.0, worst_watched = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double err = (u.segment<2>(2 * v) - exact(mesh.vertex(v))).cwiseAbs().maxCoeff() / scale;
    worst = std::max(worst, err);
    if (std::find(watched.begin(), watched.end(), v) != watched.end()) worst_watched = std::max(worst_watched, err);
  }
  if (watched_error) *watched_error = worst_watched;
  return worst;
}

// The patch test on a matched side: Dirichlet data of the linear field everywhere; then held on
// the boundary but the interface, the interface loaded by the field's traction (so that the
// inserted vertices are unknowns).
void expect_patch_test(const Mesh& given, const Mesh& matched, const std::vector<int>& matched_edges, const Vec2& normal) {
  std::vector<int> inserted;
  for (int v = given.num_vertices(); v < matched.num_vertices(); ++v) inserted.push_back(v);
  ASSERT_FALSE(inserted.empty());
  double at_inserted = 1.0;
  EXPECT_LE(patch_error(matched, matched.boundary_edges(), {}, normal, inserted, &at_inserted), 1e-12);
  EXPECT_LE(at_inserted, 1e-12);
  std::vector<int> held;
  for (int g : matched.boundary_edges())
    if (std::find(matched_edges.begin(), matched_edges.end(), g) == matched_edges.end()) held.push_back(g);
  at_inserted = 1.0;
  EXPECT_LE(patch_error(matched, held, matched_edges, normal, inserted, &at_inserted), 1e-12);
  EXPECT_LE(at_inserted, 1e-12);
}

}  // namespace

// ---- stacked blocks -----------------------------------------------------------------------

TEST(MatchInterface, StackedSquaresOfDifferentSizes) {
  const Mesh lower = make_squares(3, kLower), upper = make_squares(5, kUpper);
  const auto lower_top = side_edges(lower, kLower, "top"), upper_bottom = side_edges(upper, kUpper, "bottom");
  const MatchedInterface r = expect_good_match(lower, lower_top, upper, upper_bottom);
  // 4 + 6 points, the two corners shared: 8 pairs; 4 inserted below, 2 above.
  EXPECT_EQ(r.pairs.size(), 8u);
  EXPECT_EQ(r.first.num_vertices(), lower.num_vertices() + 4);
  EXPECT_EQ(r.second.num_vertices(), upper.num_vertices() + 2);
  // Counter-clockwise around the lower block: its top runs from x = 1 to x = 0.
  for (std::size_t k = 0; k + 1 < r.pairs.size(); ++k)
    EXPECT_GT(r.first.vertex(r.pairs[k][0]).x(), r.first.vertex(r.pairs[k + 1][0]).x());
  // The top cells of the lower block got the points 0.2 (cell 6), 0.4, 0.6 (cell 7), 0.8 (cell 8).
  EXPECT_EQ(r.first.element_size(6), 5);
  EXPECT_EQ(r.first.element_size(7), 6);
  EXPECT_EQ(r.first.element_size(8), 5);
  EXPECT_EQ(r.first.element_size(3), 4);
}

TEST(MatchInterface, SquaresAgainstVoronoi) {
  const Mesh lower = make_squares(3, kLower), upper = make_voronoi(5, kUpper);
  const auto lower_top = side_edges(lower, kLower, "top"), upper_bottom = side_edges(upper, kUpper, "bottom");
  expect_good_match(lower, lower_top, upper, upper_bottom);
  expect_good_match(upper, upper_bottom, lower, lower_top);
  const Mesh lower_voronoi = make_voronoi(4, kLower, {7});
  expect_good_match(lower_voronoi, side_edges(lower_voronoi, kLower, "top"), upper, upper_bottom);
}

TEST(MatchInterface, TrianglesAndNonconvexBlocks) {
  const Mesh lower = make_triangles(4, kLower), upper = make_nonconvex(3, kUpper);
  expect_good_match(lower, side_edges(lower, kLower, "top"), upper, side_edges(upper, kUpper, "bottom"));
}

TEST(MatchInterface, SideBySideBlocks) {
  // A vertical interface: the right side of [0,1]^2 and the left side of [1,3]x[0,1].
  const Rectangle right{1.0, 3.0, 0.0, 1.0};
  const Mesh a = make_squares(GridSize(2, 4), kLower), b = make_voronoi(GridSize(6, 3), right);
  expect_good_match(a, side_edges(a, kLower, "right"), b, side_edges(b, right, "left"));
}

TEST(MatchInterface, CoincidentVerticesArePairedWithoutInsertion) {
  // Squares 2 and 4: the points 0, 0.5, 1 are on both sides (exactly); only 0.25 and 0.75 are inserted.
  const Mesh lower = make_squares(2, kLower), upper = make_squares(4, kUpper);
  const MatchedInterface r =
      expect_good_match(lower, side_edges(lower, kLower, "top"), upper, side_edges(upper, kUpper, "bottom"));
  EXPECT_EQ(r.pairs.size(), 5u);
  EXPECT_EQ(r.first.num_vertices(), lower.num_vertices() + 2);
  EXPECT_EQ(r.second.num_vertices(), upper.num_vertices());
  EXPECT_TRUE(test::identical(r.second, upper));
}

TEST(MatchInterface, VerticesWithinTheToleranceArePairedAndKeepTheirCoordinates) {
  // Two cells each, split at x = 0.5 below and at 0.5 + 1e-12 above.
  const Mesh lower({{0, 0}, {0.5, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}}, {{0, 1, 4, 5}, {1, 2, 3, 4}});
  const double x = 0.5 + 1e-12;
  const Mesh upper({{0, 1}, {x, 1}, {1, 1}, {1, 2}, {x, 2}, {0, 2}}, {{0, 1, 4, 5}, {1, 2, 3, 4}});
  const MatchedInterface r = match_interface(lower, side_edges(lower, kLower, "top"), upper,
                                             side_edges(upper, kUpper, "bottom"), kTolerance);
  EXPECT_TRUE(test::identical(r.first, lower));
  EXPECT_TRUE(test::identical(r.second, upper));
  ASSERT_EQ(r.pairs.size(), 3u);
  EXPECT_EQ(r.pairs[1], (std::array<int, 2>{4, 1}));
  EXPECT_EQ(r.second.vertex(1).x(), x);
  // With a tolerance below the gap, the two points are distinct: each is inserted into the other.
  const MatchedInterface strict = match_interface(lower, side_edges(lower, kLower, "top"), upper,
                                                  side_edges(upper, kUpper, "bottom"), 1e-13);
  EXPECT_EQ(strict.pairs.size(), 4u);
  EXPECT_EQ(strict.first.num_vertices(), 7);
  EXPECT_EQ(strict.second.num_vertices(), 7);
}

TEST(MatchInterface, KinkedInterfaceBetweenPolygons) {
  // The lower body's top is the kinked line (2,1) - (1,1.5) - (0,1): its polygon edges 2 and 3;
  // the upper body's bottom is the same line: its edges 0 and 1.
  const PolygonDomain below{{{0, 0}, {2, 0}, {2, 1}, {1, 1.5}, {0, 1}}};
  const PolygonDomain above{{{0, 1}, {1, 1.5}, {2, 1}, {2, 3}, {0, 3}}};
  const Mesh lower = make_voronoi(5, below, {3}), upper = make_triangles(3, above);
  std::vector<int> lower_top = select_boundary_edges(lower, "edge2"), upper_bottom = select_boundary_edges(upper, "edge0");
  for (int g : select_boundary_edges(lower, "edge3")) lower_top.push_back(g);
  for (int g : select_boundary_edges(upper, "edge1")) upper_bottom.push_back(g);
  const MatchedInterface r = expect_good_match(lower, lower_top, upper, upper_bottom);
  // The kink is a vertex of both: paired, not inserted.
  const auto kink = std::find_if(r.pairs.begin(), r.pairs.end(),
                                 [&](const auto& p) { return r.first.vertex(p[0]) == Vec2(1, 1.5); });
  ASSERT_NE(kink, r.pairs.end());
  EXPECT_LT((*kink)[0], lower.num_vertices());
  EXPECT_LT((*kink)[1], upper.num_vertices());
  // Edge groups follow the split: each group covers the same length as before.
  for (const Mesh* m : {&r.first, &r.second}) {
    const Mesh& given = m == &r.first ? lower : upper;
    for (const auto& [name, group] : given.edge_groups())
      EXPECT_NEAR(length_of(*m, m->edge_group(name)), length_of(given, group), 1e-13) << name;
  }
  EXPECT_EQ(r.first.edge_group("edge2").size() + r.first.edge_group("edge3").size(), r.first_edges.size());
  expect_idempotent_and_symmetric(lower, lower_top, upper, upper_bottom);
}

TEST(MatchInterface, SameMatchAtEveryScale) {
  const MatchedInterface unit = match_interface(make_squares(3, kLower), side_edges(make_squares(3, kLower), kLower, "top"),
                                                make_voronoi(5, kUpper), side_edges(make_voronoi(5, kUpper), kUpper, "bottom"),
                                                kTolerance);
  for (double s : {std::ldexp(1.0, -30), 1e-7, 3.0, 1e9}) {
    const Rectangle lo{0, s, 0, s}, up{0, s, s, 2 * s};
    const Mesh lower = make_squares(3, lo), upper = make_voronoi(5, up);
    const MatchedInterface r =
        match_interface(lower, side_edges(lower, lo, "top"), upper, side_edges(upper, up, "bottom"), kTolerance);
    EXPECT_EQ(r.pairs, unit.pairs) << s;
    EXPECT_EQ(r.first.elements(), unit.first.elements()) << s;
  }
}

// ---- idempotence and symmetry -------------------------------------------------------------

TEST(MatchInterface, IdempotentAndSymmetric) {
  const Mesh lower = make_squares(3, kLower), upper = make_squares(5, kUpper), cells = make_voronoi(5, kUpper);
  const auto lower_top = side_edges(lower, kLower, "top");
  expect_idempotent_and_symmetric(lower, lower_top, upper, side_edges(upper, kUpper, "bottom"));
  expect_idempotent_and_symmetric(lower, lower_top, cells, side_edges(cells, kUpper, "bottom"));
  // The interface edges may be given in any order, repeated.
  std::vector<int> shuffled = lower_top;
  std::reverse(shuffled.begin(), shuffled.end());
  shuffled.push_back(shuffled.front());
  const MatchedInterface a = match_interface(lower, lower_top, cells, side_edges(cells, kUpper, "bottom"), kTolerance);
  const MatchedInterface b = match_interface(lower, shuffled, cells, side_edges(cells, kUpper, "bottom"), kTolerance);
  EXPECT_TRUE(test::identical(a.first, b.first));
  EXPECT_EQ(a.pairs, b.pairs);
}

// ---- the patch test -----------------------------------------------------------------------

TEST(MatchInterface, PatchTestOnMatchedMeshes) {
  const Mesh lower = make_squares(3, kLower), upper = make_voronoi(5, kUpper);
  const MatchedInterface r = match_interface(lower, side_edges(lower, kLower, "top"), upper,
                                             side_edges(upper, kUpper, "bottom"), kTolerance);
  {
    SCOPED_TRACE("lower squares");
    expect_patch_test(lower, r.first, r.first_edges, Vec2(0, 1));
  }
  {
    SCOPED_TRACE("upper voronoi");
    expect_patch_test(upper, r.second, r.second_edges, Vec2(0, -1));
  }
  const Mesh squares5 = make_squares(5, kUpper);
  const MatchedInterface s = match_interface(lower, side_edges(lower, kLower, "top"), squares5,
                                             side_edges(squares5, kUpper, "bottom"), kTolerance);
  SCOPED_TRACE("upper squares");
  expect_patch_test(squares5, s.second, s.second_edges, Vec2(0, -1));
}

// ---- refusals -----------------------------------------------------------------------------

TEST(MatchInterface, RefusesInterfacesThatDoNotCoverTheSameCurve) {
  const Mesh lower = make_squares(3, kLower);
  const auto lower_top = side_edges(lower, kLower, "top");
  // A block shifted by half its width: the ends do not match.
  const Rectangle shifted{0.5, 1.5, 1.0, 2.0};
  const Mesh upper = make_squares(5, shifted);
  const std::string shift =
      test::input_error_of([&] { match_interface(lower, lower_top, upper, side_edges(upper, shifted, "bottom"), kTolerance); });
  EXPECT_NE(shift.find("end vertex 12 (0, 1) of the first mesh is 0.5 away from the interface of the second mesh"),
            std::string::npos)
      << shift;
  EXPECT_NE(shift.find("the same curve"), std::string::npos) << shift;
  // The same, sides swapped: the second's end (1.5, 1) is off.
  const std::string swapped =
      test::input_error_of([&] { match_interface(upper, side_edges(upper, shifted, "bottom"), lower, lower_top, kTolerance); });
  EXPECT_NE(swapped.find("of the first mesh is 0.5 away"), std::string::npos) << swapped;
  // A shorter interface: only part of the lower block's top.
  const std::vector<int> part = select_boundary_edges(lower, std::vector<Segment>{Segment{Vec2(0, 1), Vec2(0.7, 1)}});
  ASSERT_EQ(part.size(), 2u);
  const Mesh full = make_squares(5, kUpper);
  EXPECT_NE(test::input_error_of([&] { match_interface(lower, part, full, side_edges(full, kUpper, "bottom"), kTolerance); })
                .find("end vertex"),
            std::string::npos);
  // A vertex inside the chain off the other's curve: a bump of 0.05 in the upper body's bottom.
  const PolygonDomain bumped{{{0, 1}, {0.5, 1.05}, {1, 1}, {1, 2}, {0, 2}}};
  const Mesh bump = make_triangles(2, bumped);
  std::vector<int> bump_bottom = select_boundary_edges(bump, "edge0");
  for (int g : select_boundary_edges(bump, "edge1")) bump_bottom.push_back(g);
  const std::string off = test::input_error_of([&] { match_interface(lower, lower_top, bump, bump_bottom, kTolerance); });
  EXPECT_NE(off.find("interface vertex"), std::string::npos) << off;
  EXPECT_NE(off.find("of the first mesh is 0.0"), std::string::npos) << off;
  EXPECT_NE(off.find("away from the interface of the second mesh"), std::string::npos) << off;
  // The same bump is accepted with a tolerance above it (a tenth of the interface's length).
  EXPECT_NO_THROW(match_interface(lower, lower_top, bump, bump_bottom, 0.1));
  // A vertex within the tolerance of two of the other side: 0.5 below, 0.45 and 0.55 above.
  const Mesh two_squares = make_squares(2, kLower);
  const Mesh hexagon({{0, 1}, {0.45, 1}, {0.55, 1}, {1, 1}, {1, 2}, {0, 2}}, {{0, 1, 2, 3, 4, 5}});
  const std::string ambiguous = test::input_error_of([&] {
    match_interface(two_squares, side_edges(two_squares, kLower, "top"), hexagon, side_edges(hexagon, kUpper, "bottom"), 0.1);
  });
  EXPECT_NE(ambiguous.find("interface vertex 7 (0.5, 1) of the first mesh is within the tolerance 0.1 of two interface "
                           "vertices of the second mesh"),
            std::string::npos)
      << ambiguous;
  EXPECT_NO_THROW(match_interface(two_squares, side_edges(two_squares, kLower, "top"), hexagon,
                                  side_edges(hexagon, kUpper, "bottom"), 0.01));
  // Bodies on the same side: a block matched with itself.
  const std::string overlap = test::input_error_of([&] { match_interface(lower, lower_top, lower, lower_top, kTolerance); });
  EXPECT_NE(overlap.find("same side"), std::string::npos) << overlap;
}

TEST(MatchInterface, RefusesEdgesThatAreNotOneBoundaryChain) {
  const Mesh lower = make_squares(3, kLower), upper = make_squares(5, kUpper);
  const auto lower_top = side_edges(lower, kLower, "top"), upper_bottom = side_edges(upper, kUpper, "bottom");
  auto error = [&](const std::vector<int>& first_edges, const std::vector<int>& second_edges, double tol = kTolerance) {
    return test::input_error_of([&] { match_interface(lower, first_edges, upper, second_edges, tol); });
  };
  // An interior edge.
  int interior = -1;
  for (int g = 0; g < lower.num_edges() && interior < 0; ++g)
    if (!lower.edge(g).on_boundary()) interior = g;
  std::vector<int> with_interior = lower_top;
  with_interior.push_back(interior);
  const std::string not_boundary = error(with_interior, upper_bottom);
  EXPECT_NE(not_boundary.find("interface edge " + std::to_string(interior) + " of the first mesh is not a boundary edge"),
            std::string::npos)
      << not_boundary;
  EXPECT_NE(error(lower_top, {interior}).find("of the second mesh is not a boundary edge"), std::string::npos);
  // Out of range, empty.
  EXPECT_NE(error(lower_top, {-1}).find("interface edge id -1 of the second mesh is out of range"), std::string::npos);
  EXPECT_NE(error({lower.num_edges()}, upper_bottom).find("out of range"), std::string::npos);
  EXPECT_NE(error({}, upper_bottom).find("the interface of the first mesh has no edges"), std::string::npos);
  // Two separate pieces: the top and the bottom.
  std::vector<int> pieces = lower_top;
  for (int g : side_edges(lower, kLower, "bottom")) pieces.push_back(g);
  EXPECT_NE(error(pieces, upper_bottom).find("do not form one chain"), std::string::npos);
  // A closed loop: the whole boundary.
  EXPECT_NE(error(lower.boundary_edges(), upper_bottom).find("closed loop"), std::string::npos);
  // Tolerances.
  for (double t : {-1e-8, 0.5, std::nan(""), HUGE_VAL})
    EXPECT_NE(error(lower_top, upper_bottom, t).find("tolerance"), std::string::npos) << t;
  // An empty mesh has no edges.
  EXPECT_NE(test::input_error_of([&] { match_interface(Mesh(), {0}, upper, upper_bottom, kTolerance); }).find("out of range"),
            std::string::npos);
}

TEST(MatchInterface, NeverCrashesOnRandomEdgeSets) {
  // Random sets of boundary edges of two blocks: a match or an InputError, nothing else.
  const Mesh lower = make_voronoi(4, kLower, {2}), upper = make_squares(3, kUpper);
  const auto lower_top = side_edges(lower, kLower, "top"), upper_bottom = side_edges(upper, kUpper, "bottom");
  std::mt19937 rng(11);
  int matched = 0;
  for (int trial = 0; trial < 300; ++trial) {
    auto pick = [&](const Mesh& m) {
      std::vector<int> edges;
      const auto& b = m.boundary_edges();
      const int start = static_cast<int>(rng() % b.size()), count = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < count; ++k) edges.push_back(b[(static_cast<std::size_t>(start + k)) % b.size()]);
      if (rng() % 3 == 0) edges.push_back(static_cast<int>(rng() % static_cast<unsigned>(m.num_edges() + 2)) - 1);
      return edges;
    };
    std::vector<int> ea = pick(lower), eb = pick(upper);
    if (trial % 10 == 0) {  // the true interfaces, and sometimes one more edge
      ea = lower_top;
      eb = upper_bottom;
    }
    try {
      const MatchedInterface r = match_interface(lower, ea, upper, eb, trial % 2 ? kTolerance : 0.05);
      ++matched;
      EXPECT_EQ(r.first_edges.size() + 1, r.pairs.size());
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << "trial " << trial << ": " << e.what();
    }
  }
  EXPECT_GE(matched, 30);
}
