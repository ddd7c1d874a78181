// The clamped block of shared/meshes/README.md on Sutton's unmerged Voronoi mesh, compared
// with what mVEM (an independent MATLAB/Octave VEM code using the same stabilization)
// reports there: E = 65, nu = 0.29, u = 0 on the 71 vertices with |x| < 1e-8 or
// |x - 1| < 1e-8, traction (0, -8) on y = 1, no body force. Vertices 107 and 108 are
// 1.2e-11 apart on the loaded side (joined by a tiny edge); their displacements differ
// by 3.1e-3, 4 % of the largest displacement, and the trace-scaled stabilization moves
// vertex 108 by 5.4e-3.
#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/poly2d.hpp>

#include <gtest/gtest.h>

#include <iostream>

#include "test_support.hpp"

using namespace hemivem;

namespace {

Eigen::VectorXd clamped_block(const Mesh& mesh, Stabilization stab) {
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{65.0, 0.29});
  p.stabilization = stab;
  p.dirichlet.push_back({select_boundary_edges(mesh,
                                               [](const Vec2& a, const Vec2& b) {
                                                 return (std::abs(a.x()) < 1e-8 && std::abs(b.x()) < 1e-8) ||
                                                        (std::abs(a.x() - 1) < 1e-8 && std::abs(b.x() - 1) < 1e-8);
                                               }),
                         {},
                         {true, true}});
  p.tractions.push_back({select_boundary_edges(mesh,
                                               [](const Vec2& a, const Vec2& b) {
                                                 return std::abs(a.y() - 1) < 1e-8 && std::abs(b.y() - 1) < 1e-8;
                                               }),
                         [](const Vec2&) { return Vec2(0, -8); }});
  const LinearSystem sys = assemble(p);
  EXPECT_EQ(sys.dofs.num_dofs() - sys.dofs.num_free(), 2 * 71) << "clamped vertices";
  return test::solve(sys);
}

TEST(MvemReference, TwinVerticesOnSuttonVoronoi) {
  const auto dir = test::shared_dir();
  if (dir.empty()) GTEST_SKIP() << "shared/meshes not found next to the project: mVEM comparison skipped";
  const Mesh mesh = read_poly2d(dir / "meshes" / "sutton-voronoi.poly2d").mesh;
  ASSERT_LT((mesh.vertex(107) - mesh.vertex(108)).norm(), 1e-10);
  const Eigen::VectorXd u = clamped_block(mesh, Stabilization::two_mu);
  double umax = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) umax = std::max(umax, u.segment<2>(2 * v).norm());
  const double twin = (u.segment<2>(2 * 107) - u.segment<2>(2 * 108)).norm();
  const Eigen::VectorXd ut = clamped_block(mesh, Stabilization::trace_scaled);
  const double moved = (ut.segment<2>(2 * 108) - u.segment<2>(2 * 108)).norm();
  std::cout << "max |u| = " << umax << ", |u(107) - u(108)| = " << twin << " (" << 100 * twin / umax
            << " % of max), vertex 108 moves by " << moved << " with the trace-scaled stabilization\n";
  EXPECT_NEAR(twin, 3.1e-3, 0.05e-3);
  EXPECT_NEAR(twin / umax, 0.04, 0.005);
  EXPECT_NEAR(moved, 5.4e-3, 0.05e-3);
}

}  // namespace
