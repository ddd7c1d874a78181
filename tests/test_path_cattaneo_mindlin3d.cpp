// Cattaneo and Mindlin in three dimensions: a rigid sphere (R = 1) pressed into a block, then the
// block's bottom moved sideways while the sphere stays, Coulomb friction mu = 0.3, nu = 0.49
// (where the normal and the tangential problems of a rigid indenter uncouple). For the normal
// force P and the tangential force Q of each step, Hertz's contact radius is
// a = (3 P R / (4 E*))^(1/3), E* = E / (1 - nu^2), and the stick zone is the disc of radius
// c = a (1 - Q / (mu P))^(1/3). Half the problem is solved (the plane y = 0 is one of symmetry
// under a shear along x) on boxes graded towards the contact, cells of h = 1/64 under the sphere.
//
// Measured: the nodes in contact that stick, the largest distance from the axis of the sphere
// (widened by h/2, the edge lying between the last node that sticks and the first that slips)
// against c; the test allows one cell h. Measured: Hertz's radius within 0.24 h, the stick zone
// within 0.67 h at every step, Q / (mu P) from 0.11 to 0.74.
#include <gtest/gtest.h>

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hemivem {
namespace {

constexpr double E = 65.0, nu = 0.49, mu = 0.3, R = 1.0, h = 1.0 / 64.0, depth = 0.01, shear = 0.0035;

// Coordinates from 0: `fine` cells of h, then cells growing by 1.5 up to `length`.
std::vector<double> graded(int fine, double length) {
  std::vector<double> x{0.0};
  for (int i = 1; i <= fine; ++i) x.push_back(i * h);
  double step = h;
  while (x.back() < length) x.push_back(x.back() + (step *= 1.5));
  return x;
}

std::vector<double> mirrored(const std::vector<double>& x) {
  std::vector<double> out;
  for (auto it = x.rbegin(); it != x.rend(); ++it) out.push_back(-*it);
  out.insert(out.end(), x.begin() + 1, x.end());
  return out;
}

TEST(CattaneoMindlin3D, TheStickZoneShrinksAsTheCubeRootOfTheSparedFriction) {
  const std::vector<double> along = graded(10, 1.0), down = graded(8, 1.0);
  std::vector<double> z;
  for (auto it = down.rbegin(); it != down.rend(); ++it) z.push_back(-*it);
  const Mesh3D mesh = make_cubes(mirrored(along), along, z);
  const Box box = mesh.bounding_box();
  ContactProblem3D p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{E, nu}, PlaneModel::strain);
  p.elasticity.dirichlet.push_back({select_box_side(mesh, box, "bottom"), {}, {true, true, true}, "bottom"});
  p.elasticity.dirichlet.push_back({select_box_side(mesh, box, "y0"), {}, {false, true, false}, "y0"});
  ContactPart3D contact;
  contact.name = "top";
  for (int f : select_box_side(mesh, box, "top"))  // the fine part of the top, under the sphere
    if (const Vec3 c = mesh.face_centroid(f); std::hypot(c.x(), c.y()) < 10 * h) contact.facets.push_back(f);
  Obstacle3D sphere;
  sphere.shape = Obstacle3D::Shape::sphere;
  sphere.center = Vec3(0, 0, R);
  sphere.radius = R;
  contact.obstacle = sphere;
  contact.law = zero_law();
  contact.constraint = ConstraintKind::one_sided;
  contact.friction = tresca_law(1.0);
  contact.friction_bound = FrictionBound{FrictionBound::Kind::coulomb, mu, {}};
  p.parts.push_back(std::move(contact));
  // pressed in 4 steps (t <= 1), then sheared in 8
  BasicPathLoading<3> loading;
  for (int k = 1; k <= 12; ++k) loading.t.push_back(k <= 4 ? 0.25 * k : 1.0 + 0.1 * (k - 4));
  loading.update = [](double t, ContactProblem3D& q) {
    q.elasticity.dirichlet[0].value = [t](const Vec3&) {
      return Vec3(shear * std::max(t - 1.0, 0.0), 0.0, depth * std::min(t, 1.0));
    };
  };
  loading.updates_gaps = false;
  FactorizationOptions fo;
  fo.engine = "cholmod";
  const auto ssn = make_minimizer("ssn");
  const BasicPathSolution<3> path = solve_path(p, make_factorization(fo), *ssn, loading);
  ASSERT_TRUE(path.converged());
  const double Estar = E / (1.0 - nu * nu);
  int compared = 0;
  for (const BasicPathStep<3>& s : path.steps) {
    SCOPED_TRACE(testing::Message() << "t = " << s.t);
    const double P = -2.0 * s.contact_force.z(), Q = 2.0 * std::abs(s.contact_force.x());  // both halves
    ASSERT_GT(P, 0.0);
    const double a = std::cbrt(3.0 * P * R / (4.0 * Estar));
    double reach = 0.0, stuck = 0.0;
    for (const auto& n : s.contact) {
      if (!(n.force() > 0.0)) continue;
      const double r = std::hypot(n.x.x(), n.x.y());
      reach = std::max(reach, r);
      if (n.friction_state == FrictionState::stick) stuck = std::max(stuck, r);
    }
    EXPECT_NEAR(reach + 0.5 * h, a, h) << "Hertz's contact radius";
    if (s.t <= 1.0 || !(Q < mu * P)) continue;
    const double c = a * std::cbrt(1.0 - Q / (mu * P));
    EXPECT_NEAR(stuck + 0.5 * h, c, h) << "Q / (mu P) = " << Q / (mu * P);
    ++compared;
  }
  EXPECT_GE(compared, 4);
}

}  // namespace
}  // namespace hemivem
