// On triangles the virtual element space is P1 and the stabilization vanishes: the VEM
// stiffness must equal a P1 finite-element stiffness, written here independently from
// the shape-function gradients of each triangle.
#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace hemivem;

namespace {

// Constant-strain triangle: K = A * B^T D B with B from the barycentric gradients
// grad(l_i) = (y_j - y_k, x_k - x_j) / (2A), D the plane-strain matrix written out.
Eigen::MatrixXd p1_stiffness(const Mesh& mesh, double E, double nu) {
  const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  Eigen::Matrix3d D;
  D << lam + 2 * mu, lam, 0, lam, lam + 2 * mu, 0, 0, 0, mu;
  const int n = 2 * mesh.num_vertices();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto v = mesh.element(e);
    const Vec2 p[3] = {mesh.vertex(v[0]), mesh.vertex(v[1]), mesh.vertex(v[2])};
    const double twoA = (p[1].x() - p[0].x()) * (p[2].y() - p[0].y()) - (p[2].x() - p[0].x()) * (p[1].y() - p[0].y());
    Eigen::Matrix<double, 3, 6> B = Eigen::Matrix<double, 3, 6>::Zero();
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const double bx = (p[j].y() - p[k].y()) / twoA, by = (p[k].x() - p[j].x()) / twoA;
      B(0, 2 * i) = bx;
      B(1, 2 * i + 1) = by;
      B(2, 2 * i) = by;
      B(2, 2 * i + 1) = bx;
    }
    const Eigen::Matrix<double, 6, 6> Ke = 0.5 * twoA * B.transpose() * D * B;
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) K(2 * v[a / 2] + a % 2, 2 * v[b / 2] + b % 2) += Ke(a, b);
  }
  return K;
}

void expect_equal_stiffness(const Mesh& mesh) {
  const double E = 65.0, nu = 0.29;
  const Eigen::MatrixXd Kvem = Eigen::MatrixXd(assemble_stiffness(mesh, MaterialTable(Material{E, nu})));
  const Eigen::MatrixXd Kfem = p1_stiffness(mesh, E, nu);
  EXPECT_LE((Kvem - Kfem).cwiseAbs().maxCoeff(), 1e-13 * Kfem.cwiseAbs().maxCoeff());
}

TEST(VemOnTriangles, EqualsP1FiniteElements) {
  expect_equal_stiffness(make_triangles(12, Rectangle{-1.0, 2.0, 0.5, 1.5}));
}

TEST(VemOnTriangles, EqualsP1FiniteElementsOnSuttonTriangles) {
  const auto dir = test::shared_dir();
  if (dir.empty()) GTEST_SKIP() << "shared/meshes not found next to the project: Sutton's triangle mesh skipped";
  expect_equal_stiffness(read_poly2d(dir / "meshes" / "sutton-triangles.poly2d").mesh);
}

}  // namespace
