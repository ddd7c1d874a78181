// The three-dimensional Hertz problem (docs/three-dimensions.md): a rigid sphere pressed into a
// block, against a = sqrt(R d) and p0 = 3P/(2 pi a^2), on a graded mesh with more than 100
// contact nodes inside the contact disk.
#include "bench/hertz3d.hpp"

#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <gtest/gtest.h>

using namespace hemivem;

TEST(Hertz3D, ContactRadiusAndPeakPressureWithinFivePercent) {
  hertz3d::Setup s;
  s.h_over_a = 1.0 / 6;
  const Mesh3D mesh = hertz3d::mesh(s);
  FactorizationOptions o;
  o.engine = "cholmod";
  const auto available = available_factorizations();
  if (std::find(available.begin(), available.end(), "cholmod") == available.end()) o.engine = "eigen";
  const ContactSolution3D sol =
      solve_contact(hertz3d::problem(s, mesh), make_factorization(o), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(sol.converged()) << sol.message;
  const hertz3d::Measured m = hertz3d::measure(s, sol);
  EXPECT_GE(m.full_disk, 100);
  EXPECT_NEAR(m.a / s.a(), 1.0, 0.05);
  EXPECT_NEAR(m.p0 / s.p0(), 1.0, 0.05);
  // the nodes pressed are those inside the disk, up to one mesh size
  for (const ContactNode3D& n : sol.contact) {
    const double r = n.x.head<2>().norm();
    if (r < s.a() - s.h_over_a * s.a()) EXPECT_GT(n.force(), 0.0) << "r = " << r;
    if (r > s.a() + s.h_over_a * s.a()) EXPECT_EQ(n.force(), 0.0) << "r = " << r;
  }
  EXPECT_LT(sol.forces.residual(), 1e-8);
}
