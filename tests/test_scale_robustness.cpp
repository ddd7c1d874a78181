// Mesh and scale robustness: boundary parts selected with tolerances relative to the domain,
// the same problem at scales 1e-100 ... 1e100, CGAL meshing far from unit size, polygons with
// features too thin to mesh, and the memory estimate of large elements.
#include <gtest/gtest.h>

#include <hemivem/error.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

using namespace hemivem;
using hemivem::test::run_command;
using hemivem::test::run_hemivem;
using hemivem::test::scratch;
using hemivem::test::scenes_dir;
using hemivem::test::slurp;

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// Example 4.1 on n x n squares of the square [0, L]^2.
Scene example_at_scale(double L, int n) {
  Scene s = parse_scene_string(slurp(scenes_dir() / "paper-example-4.1.toml"), "paper-example-4.1.toml");
  s.mesh.n = n;
  s.mesh.domain = {0.0, L, 0.0, L};
  return s;
}

/// Distinct vertices of the contact edges of a built problem.
std::set<int> contact_nodes(const BuiltProblem& b) {
  std::set<int> out;
  for (int e : b.problem.parts[0].facets) out.insert({b.mesh.edge(e).v0, b.mesh.edge(e).v1});
  return out;
}

// ---- boundary parts ---------------------------------------------------------------------

TEST(ScaleRobustness, SegmentContainsPointsOnALongSideDespiteRoundOff) {
  // x = k * 1e12 / 16 is rounded; the old distance through the clamped projection exceeded 1e-8
  const Segment bottom{Vec2(0.0, 0.0), Vec2(1e12, 0.0), 1e-8};
  for (int k = 0; k <= 16; ++k) EXPECT_TRUE(bottom.contains(Vec2(k * (1e12 / 16), 0.0))) << k;
  EXPECT_FALSE(bottom.contains(Vec2(0.5e12, 1.0)));
  EXPECT_FALSE(bottom.contains(Vec2(1e12 + 1.0, 0.0)));
}

TEST(ScaleRobustness, RectangleSideToleranceIsRelativeToTheRectangle) {
  const Rectangle tiny{0.0, 1e-100, 0.0, 1e-100};
  const Segment bottom = rectangle_side(tiny, "bottom");
  EXPECT_DOUBLE_EQ(bottom.tolerance, 1e-108);
  EXPECT_TRUE(bottom.contains(Vec2(0.5e-100, 0.0)));
  EXPECT_FALSE(bottom.contains(Vec2(0.5e-100, 1e-101)));  // a tenth of the side above it
  EXPECT_FALSE(bottom.contains(Vec2(0.0, 1e-100)));       // the top-left corner
}

TEST(ScaleRobustness, SquareOfSide1e12KeepsEveryBottomNodeOnGammaThree) {
  const auto built = build_problem(example_at_scale(1e12, 16));
  EXPECT_EQ(built->problem.parts[0].facets.size(), 16u);
  const std::set<int> nodes = contact_nodes(*built);
  EXPECT_EQ(nodes.size(), 17u);
  int clamped_corners = 0;
  for (const auto& d : built->problem.elasticity.dirichlet)
    for (int e : d.facets) clamped_corners += built->mesh.edge(e).v0 == 0 || built->mesh.edge(e).v1 == 0;
  EXPECT_GT(clamped_corners, 0);
  for (int v : nodes) EXPECT_EQ(built->mesh.vertex(v).y(), 0.0) << v;
}

TEST(ScaleRobustness, ContactPartAt1e150IsNotMistakenForTheClampedSides) {
  // The generators refuse cells of area below 1e-250; a mesh given by arrays is legal down to
  // areas that are normal doubles.
  const Mesh unit = make_squares(4);
  std::vector<Vec2> v = unit.vertices();
  for (auto& p : v) p *= 1e-150;
  const Mesh mesh(v, unit.elements());
  const Scene scene = example_at_scale(1.0, 4);
  ContactProblem p;
  ASSERT_NO_THROW(p = make_contact_problem(scene, mesh));
  EXPECT_EQ(p.parts[0].facets.size(), 4u);
  ASSERT_EQ(p.elasticity.dirichlet.size(), 1u);
  EXPECT_EQ(p.elasticity.dirichlet[0].facets.size(), 8u);  // left and right sides only
}

// The same problem at every scale L: coordinates times L, Young's modulus times L, tractions,
// gap and contact law unchanged. Stresses and the displacement are then the same at every
// scale (the stiffness of a plane element does not change with its size, its load grows with
// L), the contact forces (integrals over edges) and the energy grow with L.
TEST(ScaleRobustness, SameProblemAtEveryScaleGivesTheSameDisplacement) {
  nlohmann::json reference;
  for (double L : {1.0, 1e-100, 1e-50, 1e-12, 1e12, 1e50, 1e100}) {
    SCOPED_TRACE("L = " + num(L));
    const auto out = scratch("scale-" + num(L));
    const auto r = run_hemivem("solve --linear eigen --n 16 --json -q --out " + out.string() +
                               " --set 'mesh.domain=[0," + num(L) + ",0," + num(L) + "]' --set material.E=" +
                               num(65.0 * L));
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["status"], "converged");
    if (L == 1.0) {
      reference = j;
      ASSERT_EQ(j["contact"].size(), 15u);
      continue;
    }
    EXPECT_EQ(j["contact_zone"]["nodes"], reference["contact_zone"]["nodes"]);
    EXPECT_NEAR(j["contact_zone"]["length"].get<double>() / L, reference["contact_zone"]["length"].get<double>(), 1e-12);
    EXPECT_NEAR(j["potential_energy"].get<double>() / L, reference["potential_energy"].get<double>(), 1e-9);
    ASSERT_EQ(j["contact"].size(), reference["contact"].size());
    for (std::size_t k = 0; k < j["contact"].size(); ++k) {
      const auto& a = j["contact"][k];
      const auto& b = reference["contact"][k];
      EXPECT_EQ(a["state"], b["state"]) << k;
      EXPECT_NEAR(a["x"].get<double>() / L, b["x"].get<double>(), 1e-14) << k;
      EXPECT_NEAR(a["u_nu"].get<double>(), b["u_nu"].get<double>(), 1e-9 * 0.02) << k;
      EXPECT_NEAR(a["pressure"].get<double>(), b["pressure"].get<double>(), 1e-8) << k;
    }
  }
}

// ---- CGAL far from unit size ------------------------------------------------------------

void expect_tiles(const Mesh& m, const Rectangle& r) {
  EXPECT_NEAR(m.total_area(), r.width() * r.height(), 1e-12 * r.width() * r.height());
  const Rectangle box = m.bounding_box();
  EXPECT_EQ(box.x0, r.x0);
  EXPECT_EQ(box.x1, r.x1);
  EXPECT_EQ(box.y0, r.y0);
  EXPECT_EQ(box.y1, r.y1);
  int on_sides = 0;
  for (int v : m.boundary_vertices()) {
    const Vec2& p = m.vertex(v);
    on_sides += p.x() == r.x0 || p.x() == r.x1 || p.y() == r.y0 || p.y() == r.y1;
  }
  EXPECT_EQ(on_sides, static_cast<int>(m.boundary_vertices().size()));
}

PolygonDomain square_polygon(double L) { return PolygonDomain{{Vec2(0, 0), Vec2(L, 0), Vec2(L, L), Vec2(0, L)}}; }

TEST(ScaleRobustness, CgalGeneratorsMeshFarFromUnitSize) {
  const std::size_t unit_triangles = static_cast<std::size_t>(make_triangles(4, square_polygon(1.0)).num_elements());
  for (double L : {1e110, 1e-110, 1e150, 1e-120}) {
    SCOPED_TRACE("L = " + num(L));
    const Rectangle r{0.0, L, 0.0, L};
    const Mesh v = make_voronoi(GridSize(4), r);
    EXPECT_EQ(v.num_elements(), 16);
    expect_tiles(v, r);
    const Mesh t = make_triangles(4, square_polygon(L));
    // the scaled square is not the unit square: the count follows n, not bit for bit
    EXPECT_GE(static_cast<std::size_t>(t.num_elements()), unit_triangles / 2);
    EXPECT_LE(static_cast<std::size_t>(t.num_elements()), unit_triangles * 2);
    expect_tiles(t, r);
    EXPECT_FALSE(t.edge_group("edge0").empty());
    EXPECT_FALSE(t.edge_group("edge2").empty());
    const Mesh pv = make_voronoi(4, square_polygon(L));
    expect_tiles(pv, r);
    EXPECT_FALSE(pv.edge_group("edge1").empty());
  }
}

TEST(ScaleRobustness, CgalGeneratorsMeshFarFromUnitSizeFromTheCommand) {
  const auto out = scratch("far.poly2d");
  for (const std::string args : {"triangles --n 4 --polygon 0 0 1e110 0 1e110 1e110 0 1e110",
                                 "voronoi --n 4 --domain 0 1e110 0 1e110", "voronoi --n 4 --domain 0 1e-110 0 1e-110",
                                 "triangles --n 4 --polygon 0 0 1e-110 0 1e-110 1e-110 0 1e-110"}) {
    const auto r = run_command("timeout -k 5 60 " + std::string(HEMIVEM_BINARY) + " mesh " + args + " -o " +
                               out.string());
    EXPECT_EQ(r.code, 0) << args << "\n" << r.out << r.err;
  }
}

// ---- thin features ----------------------------------------------------------------------

PolygonDomain spike(double half_width) {
  return PolygonDomain{{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0.5, 1), Vec2(0.5 + half_width, 100),
                        Vec2(0.5 - half_width, 1), Vec2(0, 1)}};
}

TEST(ScaleRobustness, ThinSpikeIsRefusedWithItsLocation) {
  for (double w : {1e-13, 5e-7}) {
    SCOPED_TRACE(w);
    const auto start = std::chrono::steady_clock::now();
    const std::string msg = hemivem::test::input_error_of([&] { make_triangles(4, spike(w)); });
    EXPECT_NE(msg.find("feature of width"), std::string::npos) << msg;
    EXPECT_NE(msg.find("(0.5, 1)"), std::string::npos) << msg;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  }
}

TEST(ScaleRobustness, ElementCountFollowsN) {
  // a spike wide enough to pass the feature check still needs about length / width triangles
  const std::string msg = hemivem::test::input_error_of([&] { make_triangles(4, spike(5e-4)); });
  EXPECT_NE(msg.find("needs more than 4352 triangles"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(0.5, 1)"), std::string::npos) << msg;
  // an ordinary polygon stays near 2 n^2
  const PolygonDomain l_shape{{Vec2(0, 0), Vec2(2, 0), Vec2(2, 1), Vec2(1, 1), Vec2(1, 2), Vec2(0, 2)}};
  for (int n : {2, 8, 32}) EXPECT_LE(make_triangles(n, l_shape).num_elements(), 4 * n * n + 64) << n;
}

TEST(ScaleRobustness, ThinSpikeFromTheCommandEndsInTime) {
  const auto r = run_command("timeout -k 5 60 " + std::string(HEMIVEM_BINARY) +
                             " mesh triangles --n 4 --polygon 0 0 1 0 1 1 0.5 1 0.5000000000001 100 0.4999999999999 1 "
                             "0 1 -o " + scratch("spike.poly2d").string());
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("feature of width"), std::string::npos) << r.out << r.err;
}

// ---- memory of large elements -----------------------------------------------------------

/// One element: the unit square with k vertices per side.
std::filesystem::path one_polygon_file(int k) {
  const auto path = scratch("polygon-" + std::to_string(4 * k) + ".poly2d");
  std::ofstream f(path);
  f.precision(17);
  f << "vertices " << 4 * k << "\n";
  for (int i = 0; i < k; ++i) f << double(i) / k << " 0\n";
  for (int i = 0; i < k; ++i) f << "1 " << double(i) / k << "\n";
  for (int i = 0; i < k; ++i) f << 1.0 - double(i) / k << " 1\n";
  for (int i = 0; i < k; ++i) f << "0 " << 1.0 - double(i) / k << "\n";
  f << "elements 1\n" << 4 * k;
  for (int i = 0; i < 4 * k; ++i) f << " " << i;
  f << "\n";
  return path;
}

TEST(ScaleRobustness, MemoryEstimateCountsTheElementMatrices) {
  // measured: one element of 1000 vertices peaks at 0.26 GB, of 2000 at 0.99 GB, of 3003 at 2.4 GB
  Scene scene = example_at_scale(1.0, 4);
  scene.mesh.file = one_polygon_file(750);  // 3000 vertices
  const Mesh mesh = [&] {
    std::vector<Vec2> v;
    std::vector<int> el;
    for (int i = 0; i < 3000; ++i) {
      const double t = 2.0 * M_PI * i / 3000;
      v.emplace_back(std::cos(t), std::sin(t));
      el.push_back(i);
    }
    return Mesh(v, {el});
  }();
  EXPECT_GT(estimate_memory(mesh).solve_bytes, 2.4e9);
  EXPECT_LT(estimate_memory(mesh).solve_bytes, 1.3 * 2.4e9);
  // an ordinary mesh keeps about its estimate
  for (int n : {16, 64, 256}) {
    const double by_mesh = estimate_memory(make_squares(n)).solve_bytes, by_n = estimate_memory("squares", n).solve_bytes;
    EXPECT_GE(by_mesh, by_n) << n;
    EXPECT_LT(by_mesh, 1.2 * by_n) << n;
  }

  const char* saved = std::getenv("HEMIVEM_MEMORY_LIMIT");
  const std::string keep = saved ? saved : "";
  setenv("HEMIVEM_MEMORY_LIMIT", "100M", 1);
  const std::string msg = hemivem::test::input_error_of([&] { build_problem(scene); });
  if (saved) setenv("HEMIVEM_MEMORY_LIMIT", keep.c_str(), 1);
  else unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_NE(msg.find("elements of up to 3000 vertices"), std::string::npos) << msg;
  EXPECT_NE(msg.find("HEMIVEM_MEMORY_LIMIT"), std::string::npos) << msg;
}

TEST(ScaleRobustness, BenchRefusesASizeBeyondMemoryBeforeTheReference) {
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_command("HEMIVEM_MEMORY_LIMIT=1G timeout -k 5 60 " + std::string(HEMIVEM_BINARY) +
                             " bench --n 100000 --out " + scratch("bench").string());
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("squares n = 100000"), std::string::npos) << r.out << r.err;
  EXPECT_EQ((r.out + r.err).find("reference"), std::string::npos) << r.out << r.err;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
}

TEST(ScaleRobustness, LongTitleDoesNotHoldUpTheFigures) {
  std::string text = slurp(scenes_dir() / "paper-example-4.1.toml");
  const std::string title = "title = \"Example 4.1 (Feng, Han, Huang 2021)\"";
  ASSERT_NE(text.find(title), std::string::npos);
  text.replace(text.find(title), title.size(), "title = \"" + std::string(10'000'000, 'a') + "\"");
  const auto scene = scratch("long-title.toml");
  std::ofstream(scene) << text;
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_command("timeout -k 5 60 " + std::string(HEMIVEM_BINARY) + " solve " + scene.string() +
                             " --n 4 --linear eigen -q --out " + scratch("long-title").string());
  EXPECT_EQ(r.code, 0) << r.out.substr(0, 2000);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
}

}  // namespace
