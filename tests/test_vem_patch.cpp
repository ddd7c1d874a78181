// Patch test: a linear displacement field is reproduced to round-off on every mesh the
// generators make and on every mesh in shared/meshes, with Dirichlet data on the whole
// boundary and with tractions on part of it; the load of a linear body force is exact on
// linear fields. The right-hand side of a loading path's steps equals the assembled one.
#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

using namespace hemivem;

namespace {

struct LinearCase {
  Vec2 a{0.3, -0.7};
  Eigen::Matrix2d G = (Eigen::Matrix2d() << 0.011, -0.027, 0.019, 0.005).finished();
  Vec2 operator()(const Vec2& x) const { return a + G * x; }
};

double max_relative_error(const Mesh& mesh, const Eigen::VectorXd& u, const LinearCase& exact) {
  return test::max_relative_nodal_error(mesh, u, exact);
}

// Dirichlet data everywhere.
double patch_dirichlet(const Mesh& mesh, Stabilization stab) {
  const LinearCase exact;
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{65.0, 0.29});
  p.stabilization = stab;
  p.dirichlet.push_back(test::dirichlet_everywhere(mesh, exact));
  return max_relative_error(mesh, test::solve(assemble(p)), exact);
}

// Dirichlet data on the left side of the bounding box, the exact traction sigma n on
// every other boundary edge (constant stress, so the traction is constant per edge).
// Returns the relative residual ||A u_exact - b|| / ||b|| of the exact linear field in the
// discrete equations: the patch test proper, free of the round-off amplification of a
// solve (a clamped 3:1 block is a cantilever whose condition number grows like N^2).
double patch_traction(const Mesh& mesh) {
  const LinearCase exact;
  const Material mat{65.0, 0.29};
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(mat, PlaneModel::stress);
  const Lame l = lame(mat, PlaneModel::stress);
  const Eigen::Matrix2d eps = 0.5 * (exact.G + exact.G.transpose());
  const Eigen::Matrix2d sigma = l.lambda * eps.trace() * Eigen::Matrix2d::Identity() + 2 * l.mu * eps;
  const Rectangle box = mesh.bounding_box();
  const Segment left = rectangle_side(box, "left", 1e-8 * box.width());
  p.dirichlet.push_back({select_boundary_edges(mesh, std::vector<Segment>{left}), exact, {true, true}});
  EXPECT_FALSE(p.dirichlet.back().facets.empty());
  for (int id : mesh.boundary_edges()) {
    const auto& e = mesh.edge(id);
    if (left.contains(mesh.vertex(e.v0)) && left.contains(mesh.vertex(e.v1))) continue;
    const Vec2 d = mesh.vertex(e.v1) - mesh.vertex(e.v0);
    const Vec2 n = Vec2(d.y(), -d.x()).normalized();  // outward: the edge runs counter-clockwise
    const Vec2 t = sigma * n;
    p.tractions.push_back({{id}, [t](const Vec2&) { return t; }});
  }
  const LinearSystem sys = assemble(p);
  Eigen::VectorXd ue(sys.dofs.num_free());
  for (int i = 0; i < sys.dofs.num_free(); ++i) {
    const int d = sys.dofs.free_dof(i);
    ue(i) = exact(mesh.vertex(d / 2))(d % 2);
  }
  return (sys.A * ue - sys.b).norm() / sys.b.norm();
}

struct GeneratedCase {
  std::string name;
  int n;
};

class PatchGenerated : public ::testing::TestWithParam<GeneratedCase> {};

TEST_P(PatchGenerated, LinearFieldIsReproduced) {
  const Rectangle domain{-1.0, 2.0, 0.5, 1.5};
  const Mesh mesh = make_mesh(GetParam().name, GetParam().n, domain, 7);
  EXPECT_LE(patch_dirichlet(mesh, Stabilization::two_mu), 1e-12);
  EXPECT_LE(patch_dirichlet(mesh, Stabilization::trace_scaled), 1e-12);
  EXPECT_LE(patch_traction(mesh), 1e-12);
}

// The load of a linear body force f0 paired with a linear field v is int f0 . v over the
// domain: the projection of the load reproduces linear fields and the quadrature is exact.
TEST_P(PatchGenerated, BodyForceLoadIsExactOnLinearFields) {
  const Rectangle d{-1.0, 2.0, 0.5, 1.5};
  const Mesh mesh = make_mesh(GetParam().name, GetParam().n, d, 7);
  const LinearCase v;
  const Vec2 b(0.4, -1.3);
  const Eigen::Matrix2d B = (Eigen::Matrix2d() << 0.7, -0.2, 0.5, 1.1).finished();
  const Eigen::VectorXd f = assemble_load(mesh, [&](const Vec2& x) -> Vec2 { return b + B * x; }, {});
  Eigen::VectorXd nodal(2 * mesh.num_vertices());
  for (int i = 0; i < mesh.num_vertices(); ++i) nodal.segment<2>(2 * i) = v(mesh.vertex(i));
  // Moments of the rectangle: area, int x, int x x^T.
  const double w = d.x1 - d.x0, h = d.y1 - d.y0;
  const Vec2 first(0.5 * (d.x1 * d.x1 - d.x0 * d.x0) * h, 0.5 * (d.y1 * d.y1 - d.y0 * d.y0) * w);
  const double xy = 0.25 * (d.x1 * d.x1 - d.x0 * d.x0) * (d.y1 * d.y1 - d.y0 * d.y0);
  const Eigen::Matrix2d second = (Eigen::Matrix2d() << (std::pow(d.x1, 3) - std::pow(d.x0, 3)) / 3.0 * h, xy, xy,
                                  (std::pow(d.y1, 3) - std::pow(d.y0, 3)) / 3.0 * w)
                                     .finished();
  // int (b + B x) . (a + G x) = |D| b.a + b.G first + (B first).a + trace(B^T G second)
  const double exact = w * h * b.dot(v.a) + b.dot(v.G * first) + (B * first).dot(v.a) + (B.transpose() * v.G * second).trace();
  EXPECT_NEAR(f.dot(nodal), exact, 1e-12 * std::abs(exact));
}

INSTANTIATE_TEST_SUITE_P(Generators, PatchGenerated,
                         ::testing::Values(GeneratedCase{"squares", 5}, GeneratedCase{"squares", 16},
                                           GeneratedCase{"triangles", 7}, GeneratedCase{"voronoi", 6},
                                           GeneratedCase{"voronoi", 15}, GeneratedCase{"nonconvex", 4},
                                           GeneratedCase{"nonconvex", 9}, GeneratedCase{"distorted", 8}),
                         [](const auto& info) { return info.param.name + std::to_string(info.param.n); });

// Meshes of polygon domains (an L with a re-entrant corner, whose Voronoi cells are cut in
// pieces) and the curved body of scenes/meshes/half-disk.msh.
TEST(PatchPolygon, LinearFieldIsReproducedOnPolygonMeshes) {
  const PolygonDomain l{{{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.4}, {0.4, 0.4}, {0.4, 1.0}, {0.0, 1.0}}};
  for (const std::string name : {"triangles", "voronoi"}) {
    for (int n : {5, 14}) {
      SCOPED_TRACE(name + " " + std::to_string(n));
      const Mesh mesh = make_mesh(name, n, l, 3);
      EXPECT_LE(patch_dirichlet(mesh, Stabilization::two_mu), 1e-12);
      EXPECT_LE(patch_dirichlet(mesh, Stabilization::trace_scaled), 1e-12);
      EXPECT_LE(patch_traction(mesh), 1e-12);
    }
  }
  const Mesh disk = read_gmsh(test::scenes_dir() / "meshes" / "half-disk.msh");
  EXPECT_LE(patch_dirichlet(disk, Stabilization::two_mu), 1e-12);
}

// nx x ny cells on a rectangle whose aspect ratio is not nx : ny (stretched cells).
TEST(PatchGrid, LinearFieldIsReproducedWithDifferentCellCountsAlongXAndY) {
  for (const std::string& name : mesh_generator_names()) {
    SCOPED_TRACE(name);
    const Mesh mesh = make_mesh(name, GridSize(7, 3), Rectangle{0.0, 1.0, 0.0, 2.0}, 5);
    EXPECT_LE(patch_dirichlet(mesh, Stabilization::two_mu), 1e-12);
    EXPECT_LE(patch_traction(mesh), 1e-12);
  }
}

TEST(PatchShared, LinearFieldIsReproducedOnEverySharedMesh) {
  const auto files = test::shared_meshes();
  if (files.empty()) GTEST_SKIP() << "shared/meshes not found next to the project: patch test on Sutton's meshes skipped";
  for (const auto& f : files) {
    SCOPED_TRACE(f.filename().string());
    const Mesh mesh = read_poly2d(f).mesh;
    EXPECT_LE(patch_dirichlet(mesh, Stabilization::two_mu), 1e-12);
    EXPECT_LE(patch_traction(mesh), 1e-12);
  }
}

// The right-hand side a loading path assembles at each step (assemble_rhs, from a dof map
// already made) is the one of the whole assembly, with and without prescribed values to lift.
TEST(AssembleRhs, EqualsTheAssembledRightHandSide) {
  for (const std::string& name : {std::string("squares"), std::string("voronoi")}) {
    SCOPED_TRACE(name);
    const Mesh mesh = make_mesh(name, GridSize(6, 4), Rectangle{0.0, 1.0, 0.0, 2.0}, 5);
    const Rectangle box = mesh.bounding_box();
    const Segment left = rectangle_side(box, "left", 1e-8 * box.width());
    const Segment top = rectangle_side(box, "top", 1e-8 * box.height());
    for (const bool moved : {false, true}) {
      ElasticityProblem p;
      p.mesh = &mesh;
      p.materials = MaterialTable(Material{65.0, 0.29});
      p.body_force = [](const Vec2& x) { return Vec2(0.3 * x.y(), -1.0 - x.x()); };
      p.tractions.push_back({select_boundary_edges(mesh, std::vector<Segment>{top}),
                             [](const Vec2& x) { return Vec2(0.5, -8.0 * x.x()); }});
      const Vec2 shift = moved ? Vec2(0.01, -0.02) : Vec2(0.0, 0.0);
      p.dirichlet.push_back(
          {select_boundary_edges(mesh, std::vector<Segment>{left}), [shift](const Vec2& x) { return shift * (1.0 + x.y()); },
           {true, true}});
      const LinearSystem sys = assemble(p);
      EXPECT_EQ(moved, !sys.dofs.prescribed_values().isZero(0.0));
      const Eigen::VectorXd b = assemble_rhs(p, sys.dofs);
      ASSERT_EQ(b.size(), sys.b.size());
      EXPECT_LE((b - sys.b).norm(), 1e-14 * sys.b.norm()) << "moved " << moved;
      // written into a part of a larger vector, the rest untouched
      Eigen::VectorXd larger = Eigen::VectorXd::Constant(b.size() + 3, 7.0);
      assemble_rhs(p, sys.dofs, larger.segment(1, b.size()));
      EXPECT_EQ(larger.segment(1, b.size()), b);
      EXPECT_EQ(larger(0), 7.0);
      EXPECT_EQ(larger.tail(2), Eigen::Vector2d(7.0, 7.0));
      EXPECT_THROW(assemble_rhs(p, sys.dofs, larger.head(b.size() - 1)), InternalError);
    }
  }
}

}  // namespace
