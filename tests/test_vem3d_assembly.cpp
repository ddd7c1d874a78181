// The 3D assembly against an independent P1 finite-element code on tetrahedra, and the patch
// test of whole meshes of every cell kind.
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <gtest/gtest.h>

#include <array>

#include "test_support.hpp"

using namespace hemivem;

namespace {

MaterialTable steel() { return MaterialTable(Material{210.0, 0.3}, PlaneModel::strain); }

Eigen::VectorXd solve_free(const LinearSystem& sys) {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(sys.A);
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  return sys.dofs.expand(ldlt.solve(sys.b));
}

// An independent P1 code: K = V B^T C B per tetrahedron (test::p1_tetrahedron_stiffness); a body
// force linear in x with the exact mass matrix V/20 (1 + delta_ij); a traction linear on each
// triangle with A/12 (1 + delta_ij); clamped dofs eliminated.
Eigen::VectorXd p1_solve(const Mesh3D& mesh, const Lame& lame, const VectorField3& f, const std::vector<int>& traction_faces,
                         const VectorField3& t, const std::vector<int>& clamped_faces) {
  const int n = 3 * mesh.num_vertices();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto& v = mesh.cell_vertices(c);
    double volume = 0.0;
    const Eigen::Matrix<double, 12, 12> Ke = test::p1_tetrahedron_stiffness(mesh, c, lame.lambda, lame.mu, &volume);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        K.block<3, 3>(3 * v[i], 3 * v[j]) += Ke.block<3, 3>(3 * i, 3 * j);
        b.segment<3>(3 * v[i]) += volume / 20.0 * (i == j ? 2.0 : 1.0) * f(mesh.vertex(v[j]));
      }
  }
  for (int id : traction_faces) {
    const auto& v = mesh.face(id).vertices;
    const double area = mesh.face_area(id);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) b.segment<3>(3 * v[i]) += area / 12.0 * (i == j ? 2.0 : 1.0) * t(mesh.vertex(v[j]));
  }
  std::vector<char> fixed(static_cast<std::size_t>(n), 0);
  for (int id : clamped_faces)
    for (int v : mesh.face(id).vertices)
      for (int c = 0; c < 3; ++c) fixed[static_cast<std::size_t>(3 * v + c)] = 1;
  std::vector<int> free;
  for (int d = 0; d < n; ++d)
    if (!fixed[static_cast<std::size_t>(d)]) free.push_back(d);
  Eigen::MatrixXd Kf(free.size(), free.size());
  Eigen::VectorXd bf(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) {
    bf(i) = b(free[i]);
    for (std::size_t j = 0; j < free.size(); ++j) Kf(i, j) = K(free[i], free[j]);
  }
  const Eigen::VectorXd uf = Kf.llt().solve(bf);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i < free.size(); ++i) u(free[i]) = uf(i);
  return u;
}

}  // namespace

TEST(Vem3DAssembly, TetrahedraEqualP1FiniteElements) {
  // a box that is not a cube, with its interior vertices moved: general tetrahedra
  const Box box{0.0, 1.0, 0.0, 0.6, 0.0, 0.8};
  const Mesh3D grid = make_tetrahedra({3, 2, 3}, box);
  std::vector<Vec3> vertices = grid.vertices();
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    Vec3& p = vertices[i];
    const bool inside = p.x() > 0 && p.x() < 1 && p.y() > 0 && p.y() < 0.6 && p.z() > 0 && p.z() < 0.8;
    if (inside) p += 0.04 * Vec3(std::sin(3.0 * i), std::cos(5.0 * i), std::sin(7.0 * i + 1));
  }
  std::vector<CellFaces> cells;
  for (int c = 0; c < grid.num_cells(); ++c) cells.push_back(grid.cell(c));
  const Mesh3D mesh(vertices, cells);
  ElasticityProblem3D p;
  p.mesh = &mesh;
  p.materials = steel();
  p.body_force = [](const Vec3& x) { return Vec3(1.0 + x.x(), 2.0 * x.y(), x.z() - 0.5); };
  const auto top = select_box_side(mesh, box, "top");
  const auto left = select_box_side(mesh, box, "x0");
  const VectorField3 traction = [](const Vec3& x) { return Vec3(3.0 * x.y(), -1.0 + x.x(), -2.0); };
  p.tractions.push_back({top, traction, {}});
  p.dirichlet.push_back({left, {}, {true, true, true}, "clamped"});
  const Eigen::VectorXd u = solve_free(assemble(p));
  const Eigen::VectorXd reference = p1_solve(mesh, steel().lame(0), p.body_force, top, traction, left);
  EXPECT_GT(reference.cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((u - reference).cwiseAbs().maxCoeff(), 1e-10 * reference.cwiseAbs().maxCoeff());
}

TEST(Vem3DAssembly, PatchTestOnEveryMesh) {
  // a linear displacement prescribed on the whole boundary is reproduced inside to round-off
  const Eigen::Vector3d a(0.1, -0.2, 0.05);
  Eigen::Matrix3d G;
  G << 0.01, 0.02, -0.03, 0.015, -0.01, 0.005, 0.02, 0.01, 0.012;
  const VectorField3 exact = [&](const Vec3& x) -> Vec3 { return a + G * x; };
  const Box box{-1.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  for (const auto& kind : {"cubes", "tetrahedra", "voronoi"}) {
    const Mesh3D mesh = make_mesh3d(kind, {4, 3, 3}, box);
    ElasticityProblem3D p;
    p.mesh = &mesh;
    p.materials = steel();
    p.dirichlet.push_back({mesh.boundary_faces(), exact, {true, true, true}, "all"});
    const Eigen::VectorXd u = solve_free(assemble(p));
    double err = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v) err = std::max(err, (u.segment<3>(3 * v) - exact(mesh.vertex(v))).norm());
    EXPECT_LT(err, 1e-13) << kind;
    // the projection of each cell is the field itself
    for (const LinearField3& f : project_solution(mesh, u)) EXPECT_LT((f.gradient - G).norm(), 1e-12) << kind;
  }
}

TEST(Vem3DAssembly, UniformPressureGivesUniformStress) {
  // a box on rollers (x0, y0, z0 normal components fixed) under a pressure p on its top: the
  // exact solution is linear, sigma_zz = -p, and every kind of mesh reproduces it
  const double p0 = 2.5;
  const Box box{0.0, 1.0, 0.0, 2.0, 0.0, 1.5};
  const Material m{100.0, 0.25};
  for (const auto& kind : {"cubes", "tetrahedra", "voronoi"}) {
    const Mesh3D mesh = make_mesh3d(kind, {2, 3, 2}, box);
    ElasticityProblem3D p;
    p.mesh = &mesh;
    p.materials = MaterialTable(m, PlaneModel::strain);
    p.dirichlet.push_back({select_box_side(mesh, box, "x0"), {}, {true, false, false}, "x0"});
    p.dirichlet.push_back({select_box_side(mesh, box, "y0"), {}, {false, true, false}, "y0"});
    p.dirichlet.push_back({select_box_side(mesh, box, "z0"), {}, {false, false, true}, "z0"});
    p.tractions.push_back({select_box_side(mesh, box, "top"), {}, [&](const Vec3&) { return p0; }});
    const Eigen::VectorXd u = solve_free(assemble(p));
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const Vec3 x = mesh.vertex(v);
      const Vec3 expected(m.poisson * p0 / m.young * x.x(), m.poisson * p0 / m.young * x.y(), -p0 / m.young * x.z());
      EXPECT_LT((u.segment<3>(3 * v) - expected).norm(), 1e-13) << kind;
    }
  }
}
