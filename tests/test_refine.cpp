// Adaptive refinement (hemivem/mesh/refine.hpp): the split of elements around an interior
// point, hanging nodes as vertices with at most one per side, what follows the refinement
// (regions, edge groups, boundary), the prolongation, Dörfler marking, and the patch test on
// refined meshes of every kind.
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/vem/assembly.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

const Rectangle kDomain{-1.0, 2.0, 0.5, 1.5};

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

std::vector<Vec2> polygon_of(const Mesh& mesh, int e) {
  std::vector<Vec2> p;
  for (int v : mesh.element(e)) p.push_back(mesh.vertex(v));
  return p;
}

// Point in polygon (crossing number), or within `tol` of its boundary.
bool touches(const std::vector<Vec2>& poly, const Vec2& p, double tol) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[j];
    const Vec2& b = poly[i];
    const Vec2 d = b - a;
    const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    if ((a + t * d - p).norm() <= tol) return true;
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x()))
      inside = !inside;
  }
  return inside;
}

// The elements whose closure holds p.
std::vector<int> elements_touching(const Mesh& mesh, const Vec2& p) {
  std::vector<int> out;
  for (int e = 0; e < mesh.num_elements(); ++e)
    if (touches(polygon_of(mesh, e), p, 1e-12 * mesh.diameter(e))) out.push_back(e);
  return out;
}

struct LinearCase {
  Vec2 a{0.3, -0.7};
  Eigen::Matrix2d G = (Eigen::Matrix2d() << 0.011, -0.027, 0.019, 0.005).finished();
  Vec2 operator()(const Vec2& x) const { return a + G * x; }
};

// The patch test of test_vem_patch.cpp: Dirichlet data of a linear field on the whole
// boundary; the largest error of the solution relative to the field's largest value.
double patch_dirichlet(const Mesh& mesh) {
  const LinearCase exact;
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{65.0, 0.29});
  p.dirichlet.push_back(test::dirichlet_everywhere(mesh, exact));
  return test::max_relative_nodal_error(mesh, test::solve(assemble(p)), exact);
}

// Everything a refinement must keep, checked on any parent and refined mesh: parent vertices
// in place, areas (per parent and in total), children inside their parent, regions, the
// bounding box, boundary length, the prolongation (rows summing to 1, linear fields exact),
// parent edges, and determinism.
void expect_sound_refinement(const Mesh& parent, const RefinedMesh& r, std::span<const int> marked) {
  const Mesh& m = r.mesh;
  ASSERT_EQ(static_cast<int>(r.parent_element.size()), m.num_elements());
  ASSERT_EQ(static_cast<int>(r.parent_edge.size()), m.num_edges());
  ASSERT_EQ(r.prolongation.rows(), m.num_vertices());
  ASSERT_EQ(r.prolongation.cols(), parent.num_vertices());
  for (int v = 0; v < parent.num_vertices(); ++v) EXPECT_TRUE(m.vertex(v) == parent.vertex(v)) << "vertex " << v << " moved";

  EXPECT_NEAR(m.total_area(), parent.total_area(), 1e-13 * parent.total_area());
  std::vector<double> child_area(static_cast<std::size_t>(parent.num_elements()), 0.0);
  for (int e = 0; e < m.num_elements(); ++e) {
    const int p = r.parent_element[static_cast<std::size_t>(e)];
    EXPECT_GT(m.area(e), 0.0);
    EXPECT_EQ(m.region(e), parent.region(p));
    child_area[static_cast<std::size_t>(p)] += m.area(e);
    EXPECT_TRUE(touches(polygon_of(parent, p), m.centroid(e), 1e-12 * parent.diameter(p)))
        << "element " << e << " is not inside its parent " << p;
  }
  for (int p = 0; p < parent.num_elements(); ++p)
    EXPECT_NEAR(child_area[static_cast<std::size_t>(p)], parent.area(p), 1e-12 * parent.area(p)) << "parent " << p;

  // the refined set holds the marked elements; its elements are replaced by children
  std::vector<int> count(static_cast<std::size_t>(parent.num_elements()), 0);
  for (int p : r.parent_element) ++count[static_cast<std::size_t>(p)];
  for (int e : marked) EXPECT_TRUE(std::binary_search(r.refined.begin(), r.refined.end(), e)) << e;
  for (int p = 0; p < parent.num_elements(); ++p) {
    const bool split = std::binary_search(r.refined.begin(), r.refined.end(), p);
    if (split) {
      EXPECT_EQ(count[static_cast<std::size_t>(p)], static_cast<int>(element_corners(parent, p).size()));
    } else {
      EXPECT_EQ(count[static_cast<std::size_t>(p)], 1);
    }
  }

  const Rectangle a = parent.bounding_box(), b = m.bounding_box();
  EXPECT_TRUE(a.x0 == b.x0 && a.x1 == b.x1 && a.y0 == b.y0 && a.y1 == b.y1) << "bounding box changed";
  double la = 0.0, lb = 0.0;
  for (int i : parent.boundary_edges()) la += parent.edge_length(i);
  for (int i : m.boundary_edges()) {
    lb += m.edge_length(i);
    const int g = r.parent_edge[static_cast<std::size_t>(i)];
    ASSERT_GE(g, 0) << "boundary edge " << i << " has no parent edge";
    EXPECT_TRUE(parent.edge(g).on_boundary());
  }
  EXPECT_NEAR(la, lb, 1e-12 * la);

  // prolongation: rows sum to 1, linear fields exact at every vertex
  const LinearCase field;
  Eigen::VectorXd u(2 * parent.num_vertices());
  for (int v = 0; v < parent.num_vertices(); ++v) u.segment<2>(2 * v) = field(parent.vertex(v));
  const Eigen::VectorXd uf = prolongate(r, u);
  double err = 0.0, ref = 0.0;
  for (int v = 0; v < m.num_vertices(); ++v) {
    EXPECT_NEAR(r.prolongation.row(v).sum(), 1.0, 1e-14) << "row " << v;
    const Vec2 e = field(m.vertex(v));
    err = std::max(err, (uf.segment<2>(2 * v) - e).cwiseAbs().maxCoeff());
    ref = std::max(ref, e.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(err, 1e-12 * ref) << "prolongation of a linear field";

  EXPECT_TRUE(test::identical(m, refine_mesh(parent, marked).mesh)) << "not deterministic";
}

std::vector<int> every_third(const Mesh& mesh, int offset = 0) {
  std::vector<int> out;
  for (int e = offset; e < mesh.num_elements(); e += 3) out.push_back(e);
  return out;
}

// Uniform refinement, local refinement of every third element and a second level on that:
// sound, and the patch test exact on each.
void expect_refinements_pass_patch_test(const Mesh& mesh) {
  {
    SCOPED_TRACE("uniform");
    const RefinedMesh r = refine_uniformly(mesh);
    std::vector<int> all(static_cast<std::size_t>(mesh.num_elements()));
    std::iota(all.begin(), all.end(), 0);
    expect_sound_refinement(mesh, r, all);
    EXPECT_EQ(r.refined, all);
    EXPECT_LE(patch_dirichlet(r.mesh), 1e-10);
  }
  SCOPED_TRACE("local");
  const std::vector<int> marked = every_third(mesh);
  const RefinedMesh r1 = refine_mesh(mesh, marked);
  expect_sound_refinement(mesh, r1, marked);
  EXPECT_LE(patch_dirichlet(r1.mesh), 1e-10);
  SCOPED_TRACE("second level");
  const std::vector<int> marked2 = every_third(r1.mesh, 1);
  const RefinedMesh r2 = refine_mesh(r1.mesh, marked2);
  expect_sound_refinement(r1.mesh, r2, marked2);
  EXPECT_LE(patch_dirichlet(r2.mesh), 1e-10);
}

// ---- the split --------------------------------------------------------------------------

// A point set and a set of element vertex sets, up to numbering (coordinates rounded to 1e-12).
using Point = std::array<long long, 2>;
Point key(const Vec2& p) { return {std::llround(p.x() * 1e12), std::llround(p.y() * 1e12)}; }
std::set<Point> vertex_set(const Mesh& m) {
  std::set<Point> out;
  for (const Vec2& p : m.vertices()) out.insert(key(p));
  return out;
}
std::set<std::vector<Point>> element_set(const Mesh& m) {
  std::set<std::vector<Point>> out;
  for (int e = 0; e < m.num_elements(); ++e) {
    std::vector<Point> el;
    for (int v : m.element(e)) el.push_back(key(m.vertex(v)));
    std::sort(el.begin(), el.end());
    out.insert(el);
  }
  return out;
}
std::set<std::array<Point, 2>> segment_set(const Mesh& m, const std::vector<int>& edges) {
  std::set<std::array<Point, 2>> out;
  for (int i : edges) {
    std::array<Point, 2> s{key(m.vertex(m.edge(i).v0)), key(m.vertex(m.edge(i).v1))};
    std::sort(s.begin(), s.end());
    out.insert(s);
  }
  return out;
}

TEST(RefineSplit, UniformRefinementOfSquaresIsTheFinerSquares) {
  const Mesh coarse = make_squares(8);
  const Mesh fine = make_squares(16);
  const RefinedMesh r = refine_uniformly(coarse);
  EXPECT_EQ(r.mesh.num_vertices(), fine.num_vertices());
  EXPECT_EQ(r.mesh.num_elements(), fine.num_elements());
  EXPECT_EQ(vertex_set(r.mesh), vertex_set(fine));
  EXPECT_EQ(element_set(r.mesh), element_set(fine));
  for (const std::string side : {"left", "right", "bottom", "top"}) {
    SCOPED_TRACE(side);
    const std::vector<Segment> seg{rectangle_side(r.mesh.bounding_box(), side)};
    const auto selected = select_boundary_edges(r.mesh, seg);
    EXPECT_EQ(selected.size(), 16u);
    EXPECT_EQ(segment_set(r.mesh, selected), segment_set(fine, select_boundary_edges(fine, seg)));
  }
  expect_sound_refinement(coarse, r, r.refined);
}

TEST(RefineSplit, TrianglesSplitIntoThreeQuadrilaterals) {
  const Mesh mesh = make_triangles(3, kDomain);
  const RefinedMesh r = refine_mesh(mesh, std::vector<int>{4});
  int children = 0;
  for (int e = 0; e < r.mesh.num_elements(); ++e) {
    if (r.parent_element[static_cast<std::size_t>(e)] != 4) continue;
    ++children;
    EXPECT_EQ(r.mesh.element_size(e), 4);
    // the interior point is the triangle's centroid, shared by the three children
    EXPECT_TRUE(std::ranges::count(r.mesh.element(e), r.mesh.num_vertices() - 1) == 1);
  }
  EXPECT_EQ(children, 3);
  EXPECT_LT((r.mesh.vertex(r.mesh.num_vertices() - 1) - mesh.centroid(4)).norm(), 1e-14 * mesh.diameter(4));
  // 3 new midpoints, one interior point
  EXPECT_EQ(r.mesh.num_vertices(), mesh.num_vertices() + 4);
  expect_sound_refinement(mesh, r, std::vector<int>{4});
}

TEST(RefineSplit, VoronoiCellsSplitIntoQuadrilateralsAndNeighboursGainHangingNodes) {
  const Mesh mesh = make_voronoi(5, kDomain);
  const int e = 12;
  const RefinedMesh r = refine_mesh(mesh, std::vector<int>{e});
  EXPECT_EQ(r.refined, std::vector<int>{e});
  const int k = mesh.element_size(e);
  EXPECT_EQ(r.mesh.num_elements(), mesh.num_elements() - 1 + k);
  EXPECT_EQ(r.mesh.num_vertices(), mesh.num_vertices() + k + 1);
  for (int c = 0; c < r.mesh.num_elements(); ++c) {
    const int p = r.parent_element[static_cast<std::size_t>(c)];
    if (p == e) {
      EXPECT_EQ(element_corners(r.mesh, c).size(), 4u) << "child " << c;
    } else {
      // a neighbour across a side of e gains that side's midpoint, and keeps its corners
      bool neighbour = false;
      for (int g : mesh.element_edges(p)) neighbour |= mesh.edge(g).left == e || mesh.edge(g).right == e;
      EXPECT_EQ(r.mesh.element_size(c), mesh.element_size(p) + (neighbour ? 1 : 0)) << "element " << c;
      EXPECT_EQ(element_corners(r.mesh, c).size(), static_cast<std::size_t>(mesh.element_size(p)));
    }
  }
  expect_sound_refinement(mesh, r, std::vector<int>{e});
}

TEST(RefineSplit, ASquareWithAHangingNodeHasFourSidesAndReusesTheNode) {
  const Mesh mesh = make_squares(2);
  const RefinedMesh r1 = refine_mesh(mesh, std::vector<int>{0});
  // element 1 (right of 0) now has 5 vertices, 4 corners
  const int right = 4;  // children 0..3 of element 0, then element 1
  ASSERT_EQ(r1.parent_element[static_cast<std::size_t>(right)], 1);
  EXPECT_EQ(r1.mesh.element_size(right), 5);
  EXPECT_EQ(element_corners(r1.mesh, right).size(), 4u);
  // splitting it reuses the hanging node (0.5, 0.25): one new midpoint fewer
  const RefinedMesh r2 = refine_mesh(r1.mesh, std::vector<int>{right});
  EXPECT_EQ(r2.mesh.num_vertices(), r1.mesh.num_vertices() + 3 + 1);
  for (int c = 0; c < r2.mesh.num_elements(); ++c)
    if (r2.parent_element[static_cast<std::size_t>(c)] == right) EXPECT_EQ(r2.mesh.element_size(c), 4);
  expect_sound_refinement(r1.mesh, r2, std::vector<int>{right});
}

TEST(RefineSplit, MarkedIdsAreCheckedAndDuplicatesAllowed) {
  const Mesh mesh = make_squares(3);
  EXPECT_NE(test::input_error_of([&] { refine_mesh(mesh, std::vector<int>{9}); }).find("out of range"), std::string::npos);
  EXPECT_NE(test::input_error_of([&] { refine_mesh(mesh, std::vector<int>{-1}); }).find("out of range"), std::string::npos);
  EXPECT_TRUE(test::identical(refine_mesh(mesh, std::vector<int>{4, 4, 4}).mesh, refine_mesh(mesh, std::vector<int>{4}).mesh));
  const RefinedMesh none = refine_mesh(mesh, std::vector<int>{});
  EXPECT_TRUE(test::identical(none.mesh, mesh));
  EXPECT_TRUE(none.refined.empty());
}

// ---- every mesh kind: patch test, areas, prolongation ------------------------------------

class RefineGenerated : public ::testing::TestWithParam<std::string> {};

TEST_P(RefineGenerated, RefinedMeshesPassThePatchTest) {
  const Mesh mesh = make_mesh(GetParam(), 6, kDomain, 7);
  expect_refinements_pass_patch_test(mesh);
}

INSTANTIATE_TEST_SUITE_P(Generators, RefineGenerated,
                         ::testing::Values("squares", "triangles", "voronoi", "distorted", "nonconvex"));

// Meshes of an L-shaped polygon: Voronoi cells cut by the re-entrant corner are non-convex.
TEST(RefinePolygon, RefinedPolygonMeshesPassThePatchTest) {
  const PolygonDomain l{{{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.4}, {0.4, 0.4}, {0.4, 1.0}, {0.0, 1.0}}};
  for (const std::string name : {"triangles", "voronoi"}) {
    SCOPED_TRACE(name);
    expect_refinements_pass_patch_test(make_mesh(name, 7, l, 3));
  }
}

TEST(RefineShared, RefinedSharedMeshesPassThePatchTest) {
  const auto files = test::shared_meshes();
  if (files.empty()) GTEST_SKIP() << "shared/meshes not found next to the project";
  for (const auto& f : files) {
    SCOPED_TRACE(f.filename().string());
    try {
      expect_refinements_pass_patch_test(read_poly2d(f).mesh);
    } catch (const Error& e) {
      ADD_FAILURE() << e.what();
    }
  }
}

TEST(RefineShared, NonConvexStarShapedElementsRefine) {
  const auto dir = test::shared_dir();
  if (dir.empty()) GTEST_SKIP() << "shared/meshes not found next to the project";
  const Mesh mesh = read_poly2d(dir / "meshes" / "sutton-non-convex.poly2d").mesh;
  // it has non-convex elements
  int non_convex = 0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto p = polygon_of(mesh, e);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (cross(p[(i + 1) % p.size()] - p[i], p[(i + 2) % p.size()] - p[(i + 1) % p.size()]) < 0.0) {
        ++non_convex;
        break;
      }
  }
  EXPECT_GT(non_convex, 0);
  const RefinedMesh r = refine_uniformly(mesh);
  EXPECT_EQ(static_cast<int>(r.refined.size()), mesh.num_elements());
}

TEST(RefineRegions, ChildrenInheritTheRegion) {
  Mesh mesh = make_voronoi(4, kDomain);
  std::vector<int> regions(static_cast<std::size_t>(mesh.num_elements()));
  for (std::size_t e = 0; e < regions.size(); ++e) regions[e] = static_cast<int>(e % 3) + 1;
  mesh.set_regions(regions);
  const RefinedMesh r = refine_mesh(mesh, every_third(mesh));
  for (int e = 0; e < r.mesh.num_elements(); ++e)
    EXPECT_EQ(r.mesh.region(e), regions[static_cast<std::size_t>(r.parent_element[static_cast<std::size_t>(e)])]);
}

// ---- star-shapedness ----------------------------------------------------------------------

// A square below a U (whose kernel is empty), or below an L (whose centroid is outside its kernel).
Mesh square_below(const std::vector<Vec2>& top, int squares_below) {
  std::vector<Vec2> v{{0, -1}, {3, -1}};
  std::vector<std::vector<int>> el;
  if (squares_below == 1) {
    el.push_back({0, 1});
  } else {
    v.push_back({1.5, -1});
    el.push_back({0, 2});
    el.push_back({2, 1});
  }
  const int base = static_cast<int>(v.size());
  for (const Vec2& p : top) v.push_back(p);
  // top[0] = (0, 0), top[1] = (3, 0) (or (1.5, 0), (3, 0) with two squares)
  if (squares_below == 1) {
    el[0].insert(el[0].end(), {base + 1, base});
  } else {
    el[0].insert(el[0].end(), {base + 1, base});
    el[1].insert(el[1].end(), {base + 2, base + 1});
  }
  std::vector<int> upper(top.size());
  std::iota(upper.begin(), upper.end(), base);
  el.push_back(upper);
  return Mesh(v, el);
}

TEST(RefineStarShaped, AnElementWithAnEmptyKernelIsRefusedByName) {
  const std::vector<Vec2> u{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  const Mesh mesh = square_below(u, 1);
  const std::string what = test::input_error_of([&] { refine_mesh(mesh, std::vector<int>{1}); });
  EXPECT_NE(what.find("element 1 is not star-shaped"), std::string::npos) << what;
  EXPECT_NE(what.find("kernel is empty"), std::string::npos) << what;
  EXPECT_NE(test::input_error_of([&] { refine_uniformly(mesh); }).find("element 1 is not star-shaped"), std::string::npos);
  // splitting the square below gives the U one hanging node: it is not split
  const RefinedMesh r = refine_mesh(mesh, std::vector<int>{0});
  EXPECT_EQ(r.refined, std::vector<int>{0});
  EXPECT_EQ(r.mesh.element_size(r.mesh.num_elements() - 1), 9);

  // with a hanging node on the U's bottom already, splitting one square below would give it a
  // second: the one-hanging-node rule marks it, and the message says so
  const std::vector<Vec2> u2{{0, 0}, {1.5, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  const Mesh mesh2 = square_below(u2, 2);
  const std::string what2 = test::input_error_of([&] { refine_mesh(mesh2, std::vector<int>{0}); });
  EXPECT_NE(what2.find("element 2 is not star-shaped"), std::string::npos) << what2;
  EXPECT_NE(what2.find("one-hanging-node rule"), std::string::npos) << what2;
}

TEST(RefineStarShaped, AnElementWhoseKernelIsASegmentIsRefused) {
  // two blocks meeting along [0, 1] x {1}: only the points of that segment see everything
  const std::vector<Vec2> v{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {-1, 2}, {-1, 1}, {0, 1}};
  const Mesh mesh(v, {{0, 1, 2, 3, 4, 5, 6, 7}});
  const std::string what = test::input_error_of([&] { refine_uniformly(mesh); });
  EXPECT_NE(what.find("element 0 is not star-shaped"), std::string::npos) << what;
  EXPECT_NE(what.find("degenerate"), std::string::npos) << what;
}

TEST(RefineStarShaped, AnElementWhoseCentroidIsOutsideItsKernelIsSplitAroundTheKernelsCentroid) {
  // an L: centroid (1.1, 1.1), kernel [0, 1] x [0, 1]
  const std::vector<Vec2> l{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};
  const Mesh mesh = square_below(l, 1);
  const RefinedMesh r = refine_mesh(mesh, std::vector<int>{1});
  const Vec2 c = r.mesh.vertex(r.mesh.num_vertices() - 1);
  EXPECT_NEAR(c.x(), 0.5, 1e-14);
  EXPECT_NEAR(c.y(), 0.5, 1e-14);
  EXPECT_EQ(r.mesh.num_elements(), 1 + 6);
  expect_sound_refinement(mesh, r, std::vector<int>{1});
  EXPECT_LE(patch_dirichlet(r.mesh), 1e-10);
}

// ---- one hanging node per side, no degeneration -------------------------------------------

// Sides of an element found independently of element_corners: on a mesh of dyadic
// coordinates, a vertex is hanging when the cross product with its neighbours is exactly 0.
std::vector<int> exact_corners(const Mesh& m, int e) {
  const auto p = polygon_of(m, e);
  const std::size_t n = p.size();
  std::vector<int> out;
  for (std::size_t i = 0; i < n; ++i)
    if (cross(p[(i + 1) % n] - p[(i + n - 1) % n], p[i] - p[(i + n - 1) % n]) != 0.0) out.push_back(static_cast<int>(i));
  return out;
}

// Refines the element touching `point` of a 4 x 4 squares mesh of the unit square ten times;
// every side carries at most one hanging vertex at every level. Returns how many elements the
// one-hanging-node rule added.
int refine_towards(const Vec2& point) {
  Mesh mesh = make_squares(4);
  int closure_added = 0;
  for (int level = 0; level < 10; ++level) {
    const std::vector<int> marked = elements_touching(mesh, point);
    EXPECT_EQ(marked.size(), 1u);
    RefinedMesh r = refine_mesh(mesh, marked);
    expect_sound_refinement(mesh, r, marked);
    closure_added += static_cast<int>(r.refined.size()) - 1;
    mesh = std::move(r.mesh);
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const std::vector<int> corners = exact_corners(mesh, e);
      EXPECT_EQ(corners, element_corners(mesh, e)) << "level " << level << " element " << e;
      EXPECT_EQ(corners.size(), 4u);
      if (corners.size() != 4u) continue;
      const int n = mesh.element_size(e);
      EXPECT_LE(n, 8);
      for (std::size_t s = 0; s < 4; ++s) {
        const int inside = (corners[(s + 1) % 4] - corners[s] + n) % n - 1;
        EXPECT_LE(inside, 1) << "level " << level << " element " << e << " side " << s;
      }
    }
  }
  EXPECT_NEAR(mesh.total_area(), 1.0, 1e-14);
  return closure_added;
}

TEST(RefineHangingNodes, AtMostOneHangingNodePerSideRefiningACorner) {
  // the element at a corner: its neighbours are its siblings, the rule has nothing to add
  EXPECT_EQ(refine_towards(Vec2(0.0, 0.0)), 0);
}

TEST(RefineHangingNodes, AtMostOneHangingNodePerSideRefiningTowardsAnInteriorPoint) {
  // 1/3 is on no mesh line: the element holding it has coarser neighbours with a hanging node
  // on the side they share, so the rule acts
  EXPECT_GT(refine_towards(Vec2(1.0 / 3.0, 1.0 / 3.0)), 5);
}

double worst_shape(const Mesh& m) {
  double worst = 0.0;
  for (int e = 0; e < m.num_elements(); ++e) worst = std::max(worst, m.diameter(e) * m.diameter(e) / m.area(e));
  return worst;
}

TEST(RefineShape, NoDegenerationOverTenLevels) {
  const Vec2 point(0.3, 0.8);
  for (const std::string name : {"squares", "triangles", "voronoi"}) {
    SCOPED_TRACE(name);
    Mesh mesh = make_mesh(name, 5, kDomain, 3);
    double level1 = 0.0;
    bool at_most_twice = true;  // vertices per element at most twice its corners
    for (int level = 1; level <= 10; ++level) {
      const std::vector<int> marked = elements_touching(mesh, point);
      ASSERT_FALSE(marked.empty());
      mesh = refine_mesh(mesh, marked).mesh;
      if (level == 1) level1 = worst_shape(mesh);
      for (int e = 0; e < mesh.num_elements(); ++e)
        at_most_twice &= static_cast<std::size_t>(mesh.element_size(e)) <= 2 * element_corners(mesh, e).size();
    }
    const double level10 = worst_shape(mesh);
    RecordProperty(name + "_worst_shape_level1", std::to_string(level1));
    RecordProperty(name + "_worst_shape_level10", std::to_string(level10));
    EXPECT_LE(level10, 2.0 * level1) << "level 1: " << level1 << ", level 10: " << level10;
    EXPECT_TRUE(at_most_twice);
    // the elements at the point are about 2^-10 of the first ones
    EXPECT_LT(mesh.diameter(elements_touching(mesh, point).front()), 2e-3 * kDomain.width());
    EXPECT_LE(patch_dirichlet(mesh), 1e-10);
  }
}

// ---- edge groups, scale ------------------------------------------------------------------

TEST(RefineEdgeGroups, GroupsCoverTheSameSegments) {
  const PolygonDomain pentagon{{{0.0, 0.0}, {2.0, 0.0}, {2.5, 1.2}, {1.0, 2.0}, {-0.4, 1.0}}};
  Mesh mesh = make_triangles(4, pentagon);
  auto group_length = [](const Mesh& m, const std::string& name) {
    double l = 0.0;
    for (int i : m.edge_group(name)) l += m.edge_length(i);
    return l;
  };
  std::vector<double> lengths;
  for (int k = 0; k < 5; ++k) lengths.push_back(group_length(mesh, "edge" + std::to_string(k)));
  for (int level = 0; level < 3; ++level) {
    std::vector<int> marked;
    for (int g : mesh.edge_group("edge1")) marked.push_back(mesh.edge(g).left);
    const std::size_t before = mesh.edge_group("edge1").size();
    mesh = refine_mesh(mesh, marked).mesh;
    EXPECT_GT(mesh.edge_group("edge1").size(), before);
    for (int k = 0; k < 5; ++k) {
      const std::string name = "edge" + std::to_string(k);
      SCOPED_TRACE(name);
      EXPECT_NEAR(group_length(mesh, name), lengths[static_cast<std::size_t>(k)], 1e-12);
      EXPECT_EQ(select_boundary_edges(mesh, name).size(), mesh.edge_group(name).size());
      const Vec2 a = pentagon.corners[static_cast<std::size_t>(k)], b = pentagon.corners[static_cast<std::size_t>((k + 1) % 5)];
      const Segment side{a, b, 1e-12};
      for (int i : mesh.edge_group(name)) {
        EXPECT_TRUE(side.contains(mesh.vertex(mesh.edge(i).v0)));
        EXPECT_TRUE(side.contains(mesh.vertex(mesh.edge(i).v1)));
      }
    }
  }
}

// A Gmsh body with a curved boundary (a half disk, "arc" and "top"): refined along its straight
// edges, the groups keep their length (the arc's polygon, not the circle's), region 3 is kept.
TEST(RefineEdgeGroups, GmshGroupsFollowAndTheArcStaysItsPolygon) {
  const Mesh disk = read_gmsh(test::scenes_dir() / "meshes" / "half-disk.msh");
  std::vector<int> marked;
  for (int g : disk.edge_group("arc")) marked.push_back(disk.edge(g).left);
  const RefinedMesh r = refine_mesh(disk, marked);
  expect_sound_refinement(disk, r, marked);
  for (const std::string name : {"arc", "top"}) {
    double before = 0.0, after = 0.0;
    for (int g : disk.edge_group(name)) before += disk.edge_length(g);
    for (int g : r.mesh.edge_group(name)) after += r.mesh.edge_length(g);
    EXPECT_NEAR(after, before, 1e-13 * before) << name;
  }
  EXPECT_EQ(r.mesh.edge_group("arc").size(), 2 * disk.edge_group("arc").size());
  for (int e = 0; e < r.mesh.num_elements(); ++e) EXPECT_EQ(r.mesh.region(e), 3);
  EXPECT_LE(patch_dirichlet(r.mesh), 1e-10);
}

TEST(RefineScale, TheSameTopologyAtEveryScale) {
  for (const std::string name : {"squares", "triangles", "voronoi", "nonconvex"}) {
    SCOPED_TRACE(name);
    const Mesh unit = make_mesh(name, 5, kDomain, 3);
    auto two_levels = [](const Mesh& m) {
      std::vector<RefinedMesh> out{refine_mesh(m, every_third(m))};
      out.push_back(refine_mesh(out[0].mesh, every_third(out[0].mesh, 2)));
      return out;
    };
    const auto reference = two_levels(unit);
    for (const double s : {1e-100, 1e100}) {
      SCOPED_TRACE(s);
      std::vector<Vec2> v = unit.vertices();
      for (Vec2& p : v) p *= s;
      const auto scaled = two_levels(Mesh(v, unit.elements()));
      for (std::size_t l = 0; l < 2; ++l) {
        EXPECT_EQ(scaled[l].mesh.elements(), reference[l].mesh.elements());
        EXPECT_EQ(scaled[l].refined, reference[l].refined);
        ASSERT_EQ(scaled[l].mesh.num_vertices(), reference[l].mesh.num_vertices());
        double err = 0.0;
        for (int i = 0; i < reference[l].mesh.num_vertices(); ++i)
          err = std::max(err, (scaled[l].mesh.vertex(i) / s - reference[l].mesh.vertex(i)).norm());
        EXPECT_LE(err, 1e-14);
      }
    }
  }
}

// ---- Dörfler marking -------------------------------------------------------------------

TEST(Dorfler, HandComputedExamples) {
  // eta^2 = 1, 9, 4, 0.25 (sum 14.25)
  const std::vector<double> eta{1.0, 3.0, 2.0, 0.5};
  EXPECT_EQ(dorfler_marking(eta, 0.5), (std::vector<int>{1}));     // 9 >= 7.125
  EXPECT_EQ(dorfler_marking(eta, 0.7), (std::vector<int>{1, 2}));  // 9 < 9.975 <= 13
  EXPECT_EQ(dorfler_marking(eta, 0.95), (std::vector<int>{0, 1, 2}));  // 13 < 13.5375 <= 14
  EXPECT_EQ(dorfler_marking(eta, 1.0), (std::vector<int>{0, 1, 2, 3}));
  // ties are marked together: eta^2 = 4, 1, 4, 1
  const std::vector<double> tied{2.0, 1.0, 2.0, 1.0};
  EXPECT_EQ(dorfler_marking(tied, 0.3), (std::vector<int>{0, 2}));
  EXPECT_EQ(dorfler_marking(tied, 0.5), (std::vector<int>{0, 2}));
  EXPECT_EQ(dorfler_marking(tied, 0.85), (std::vector<int>{0, 1, 2, 3}));
  // ... to round-off (within 1e-6 of the largest), whichever of them is the larger
  const std::vector<double> mirrored{2.0 * (1.0 + 1e-15), 1.0, 2.0, 0.5};
  const std::vector<double> other_way{2.0, 1.0, 2.0 * (1.0 + 1e-15), 0.5};
  EXPECT_EQ(dorfler_marking(mirrored, 0.3), (std::vector<int>{0, 2}));
  EXPECT_EQ(dorfler_marking(other_way, 0.3), (std::vector<int>{0, 2}));
  // and no further: 2 - 1e-5 is not 2
  EXPECT_EQ(dorfler_marking(std::vector<double>{2.0, 2.0 - 1e-5, 1.0}, 0.3), (std::vector<int>{0}));
  // no overflow for huge indicators
  const std::vector<double> huge{1e300, 3e300, 2e300, 5e299};
  EXPECT_EQ(dorfler_marking(huge, 0.7), (std::vector<int>{1, 2}));
}

TEST(Dorfler, ThetaOneMarksEveryNonzeroIndicator) {
  const std::vector<double> eta{0.0, 1.0, 1e-10, 0.0, 3.0};
  EXPECT_EQ(dorfler_marking(eta, 1.0), (std::vector<int>{1, 2, 4}));
  EXPECT_TRUE(dorfler_marking(std::vector<double>{0.0, 0.0}, 0.5).empty());
  EXPECT_TRUE(dorfler_marking(std::vector<double>{}, 0.5).empty());
}

TEST(Dorfler, InvalidInputThrows) {
  const std::vector<double> eta{1.0, 2.0};
  for (const double theta : {0.0, -0.1, 1.0000001, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_NE(test::input_error_of([&] { dorfler_marking(eta, theta); }).find("theta"), std::string::npos) << theta;
  EXPECT_NE(test::input_error_of([&] { dorfler_marking(std::vector<double>{1.0, -1.0}, 0.5); }).find("indicator 1"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([&] {
              dorfler_marking(std::vector<double>{std::numeric_limits<double>::infinity()}, 0.5);
            }).find("indicator 0"),
            std::string::npos);
}

TEST(Prolongate, InterpolatesComponentwiseAndChecksTheSize) {
  const Mesh mesh = make_voronoi(4, kDomain);
  const RefinedMesh r = refine_mesh(mesh, every_third(mesh));
  EXPECT_FALSE(test::input_error_of([&] { prolongate(r, Eigen::VectorXd::Zero(2 * mesh.num_vertices() + 1)); }).empty());
  // a field that is not linear: each component is the prolongation applied to that component
  Eigen::VectorXd u(2 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<2>(2 * v) = Vec2(std::sin(3 * mesh.vertex(v).x()), std::cos(mesh.vertex(v).y()));
  const Eigen::VectorXd uf = prolongate(r, u);
  Eigen::VectorXd ux(mesh.num_vertices()), uy(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    ux(v) = u(2 * v);
    uy(v) = u(2 * v + 1);
  }
  const Eigen::VectorXd fx = r.prolongation * ux, fy = r.prolongation * uy;
  for (int v = 0; v < r.mesh.num_vertices(); ++v) {
    EXPECT_EQ(uf(2 * v), fx(v));
    EXPECT_EQ(uf(2 * v + 1), fy(v));
  }
  // edge midpoints are the mean of the edge's ends
  for (int v = mesh.num_vertices(); v < r.mesh.num_vertices(); ++v) {
    if (r.prolongation.row(v).nonZeros() != 2) continue;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(r.prolongation, v); it; ++it)
      EXPECT_EQ(it.value(), 0.5);
  }
}

}  // namespace
