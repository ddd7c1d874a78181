// Coulomb friction on a solid against an independent solver of the same discrete problem. On
// tetrahedra the virtual element space is P1, so the problem hemivem solves is that of a P1
// finite-element code: written here from scratch (element stiffness from the inverse of
// [1 x y z], test_support's, nodal weights a third of each bottom triangle), condensed onto the bottom nodes by a
// dense Cholesky factorization and minimised by accelerated proximal gradients (the exact prox of
// w g |v| on each node's tangential pair, the projection onto u_z >= 0), Coulomb's bound g_i =
// mu p_i by a plain fixed point around it. A block pressed by a rigid platen and sheared, with
// stuck, slipping and separated nodes: hemivem's answer (the scene through the command's entry
// point) must be that one.
#include <gtest/gtest.h>

#include <hemivem/app/run.hpp>
#include <hemivem/mesh/generators3d.hpp>

#include <Eigen/Dense>

#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace hemivem::app {
namespace {

constexpr double young = 100.0, poisson = 0.3, mu = 0.6;
const Box block{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
const Vec3 top_motion(0.002, 0.001, -0.004);

// The scene: the bottom on the rigid plane z = 0 (one-sided, no normal law), Coulomb's law;
// the top moved by top_motion; a single static step.
std::string scene_text(const std::string& friction) {
  return "schema_version = 1\n[mesh]\ngenerator = \"tetrahedra\"\nn = [3, 3, 2]\ndomain = [0, 1, 0, 1, 0, 0.5]\n"
         "[material]\nE = 100.0\nnu = 0.3\n[[dirichlet]]\nside = \"top\"\nvalue = [0.002, 0.001, -0.004]\n"
         "[contact]\nside = \"bottom\"\nlaw = \"zero\"\ngap = \"0.006*x*y\"\nconstraint = \"one-sided\"\n"
         "[contact.friction]\n" +
         friction;
}

struct Reference {
  Eigen::VectorXd u;         // 3 per vertex
  std::vector<int> bottom;   // the contact nodes
  Eigen::VectorXd pressure;  // per contact node: its normal force over its weight
};

// The independent P1 code: the full stiffness, the dofs of the top prescribed, the bottom nodes'
// dofs condensed onto, and the frictional contact problem on them solved by FISTA with a Coulomb
// fixed point (bound = mu * the normal force of the previous Tresca solve, until it settles).
Reference p1_coulomb(const Mesh3D& mesh) {
  const int nv = mesh.num_vertices(), n = 3 * nv;
  const double lambda = young * poisson / ((1 + poisson) * (1 - 2 * poisson)), shear = young / (2 * (1 + poisson));
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto& v = mesh.cell_vertices(c);
    const Eigen::Matrix<double, 12, 12> Ke = test::p1_tetrahedron_stiffness(mesh, c, lambda, shear);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) K.block<3, 3>(3 * v[i], 3 * v[j]) += Ke.block<3, 3>(3 * i, 3 * j);
  }
  // the top's dofs prescribed, the bottom's (every vertex at z = 0) the contact unknowns
  Reference r;
  std::vector<int> kind(static_cast<std::size_t>(nv), 0);  // 0 interior, 1 top, 2 bottom
  for (int v = 0; v < nv; ++v) {
    const double z = mesh.vertex(v).z();
    kind[static_cast<std::size_t>(v)] = z == 0.5 ? 1 : (z == 0.0 ? 2 : 0);
    if (z == 0.0) r.bottom.push_back(v);
  }
  Eigen::VectorXd w = Eigen::VectorXd::Zero(nv);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& fv = mesh.face(f).vertices;
    if (fv.size() == 3 && std::all_of(fv.begin(), fv.end(), [&](int v) { return mesh.vertex(v).z() == 0.0; }))
      for (int v : fv) w(v) += mesh.face_area(f) / 3.0;
  }
  std::vector<int> one, two, top;  // bottom dofs, interior dofs, prescribed dofs
  for (int v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c) {
      const int k = kind[static_cast<std::size_t>(v)];
      (k == 2 ? one : k == 0 ? two : top).push_back(3 * v + c);
    }
  auto block = [&](const std::vector<int>& rows, const std::vector<int>& cols) {
    Eigen::MatrixXd M(rows.size(), cols.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (std::size_t j = 0; j < cols.size(); ++j) M(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = K(rows[i], cols[j]);
    return M;
  };
  Eigen::VectorXd up(top.size());
  for (std::size_t i = 0; i < top.size(); ++i) up(static_cast<Eigen::Index>(i)) = top_motion(top[i] % 3);
  const Eigen::LLT<Eigen::MatrixXd> K22(block(two, two));
  const Eigen::MatrixXd K21 = block(two, one), K2p = block(two, top);
  const Eigen::MatrixXd S = block(one, one) - K21.transpose() * K22.solve(K21);
  const Eigen::VectorXd c = -(block(one, top) * up - K21.transpose() * K22.solve(K2p * up));
  const int m = static_cast<int>(r.bottom.size());
  const double L = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S).eigenvalues().maxCoeff();
  // FISTA with restarts on F(a) = 1/2 a^T S a - c^T a + sum_i g_i w_i |(a_x, a_y)_i|, a_z,i >= -gap_i
  // (u_nu = -u_z <= gap)
  Eigen::VectorXd gap(m), g = Eigen::VectorXd::Zero(m), a = Eigen::VectorXd::Zero(3 * m);
  for (int i = 0; i < m; ++i) {
    const Vec3 x = mesh.vertex(r.bottom[static_cast<std::size_t>(i)]);
    gap(i) = 0.006 * x.x() * x.y();
  }
  auto prox = [&](Eigen::VectorXd y) {
    for (int i = 0; i < m; ++i) {
      const Eigen::Vector2d t(y(3 * i), y(3 * i + 1));
      const double len = t.norm(), cut = g(i) * w(r.bottom[static_cast<std::size_t>(i)]) / L;
      const Eigen::Vector2d kept = len > cut ? Eigen::Vector2d(t * (1.0 - cut / len)) : Eigen::Vector2d::Zero();
      y(3 * i) = kept.x(), y(3 * i + 1) = kept.y();
      y(3 * i + 2) = std::max(y(3 * i + 2), -gap(i));
    }
    return y;
  };
  for (int fixed_point = 0; fixed_point < 200; ++fixed_point) {
    Eigen::VectorXd x = a, y = a;
    double s = 1.0;
    for (int it = 0; it < 200000; ++it) {
      const Eigen::VectorXd next = prox(y - (S * y - c) / L);
      const double s_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * s * s));
      y = next + ((s - 1.0) / s_next) * (next - x);
      if ((next - x).dot(y - next) > 0.0) y = next, s = 1.0;  // restart where the momentum goes uphill
      else s = s_next;
      const double moved = (next - x).cwiseAbs().maxCoeff();
      x = next;
      if (moved <= 1e-17) break;
    }
    a = x;
    // the normal force of each node: the platen's reaction, (S a - c)_z at a node on it
    const Eigen::VectorXd r_force = S * a - c;
    Eigen::VectorXd g_new(m);
    for (int i = 0; i < m; ++i) {
      const double P = a(3 * i + 2) == -gap(i) ? std::max(r_force(3 * i + 2), 0.0) : 0.0;
      g_new(i) = mu * P / w(r.bottom[static_cast<std::size_t>(i)]);
    }
    const double change = (g_new - g).cwiseAbs().maxCoeff();
    g = g_new;
    if (fixed_point > 0 && change <= 1e-13 * std::max(1.0, g.cwiseAbs().maxCoeff())) break;
  }
  r.pressure = g / mu;
  // the whole displacement
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i < one.size(); ++i) u(one[i]) = a(static_cast<Eigen::Index>(i));
  for (std::size_t i = 0; i < top.size(); ++i) u(top[i]) = up(static_cast<Eigen::Index>(i));
  const Eigen::VectorXd u2 = -K22.solve(K21 * a + K2p * up);
  for (std::size_t i = 0; i < two.size(); ++i) u(two[i]) = u2(static_cast<Eigen::Index>(i));
  r.u = u;
  return r;
}

TEST(Friction3DP1, CoulombOnTetrahedraIsThatOfAnIndependentP1Code) {
  const Mesh3D mesh = make_tetrahedra({3, 3, 2}, block);
  const Reference ref = p1_coulomb(mesh);
  const SceneRun run = run_scene(parse_scene_string(scene_text("law = \"coulomb\"\ncoefficient = 0.6\n"), "p1.toml"));
  ASSERT_TRUE(run.converged());
  const ContactSolution3D& s = run.solid()->solution;
  ASSERT_EQ(s.u.size(), ref.u.size());
  const double scale = ref.u.cwiseAbs().maxCoeff();
  EXPECT_LT((s.u - ref.u).cwiseAbs().maxCoeff(), 1e-10 * scale) << "hemivem against the P1 code";
  // the mix the test is about: nodes stuck, slipping and separated
  int stuck = 0, slipping = 0, separated = 0;
  for (const ContactNode3D& n : s.contact) {
    const bool pressed = n.force() > 1e-9;
    separated += !pressed;
    stuck += pressed && n.friction_state == FrictionState::stick;
    slipping += pressed && n.friction_state == FrictionState::slip;
  }
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slipping, 0);
  EXPECT_GT(separated, 0);
  EXPECT_EQ(stuck + slipping + separated, static_cast<int>(ref.bottom.size()));
}

}  // namespace
}  // namespace hemivem::app
