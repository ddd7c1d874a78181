// contact.law_origin = "surface": the normal law acts on the distance u_nu - g to the obstacle's
// surface (normal compliance or adhesion against an obstacle), against a hand computation.
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace hemivem {
namespace {

ContactSolution solve_text(const std::string& text, const std::string& minimizer = "ssn") {
  const Scene scene = parse_scene_string(text, "indenter.toml");
  const auto built = build_problem(scene);
  FactorizationOptions f;
  f.engine = "auto";
  MinimizerOptions o;
  o.tolerance = 1e-10;
  return solve_contact(built->problem, make_factorization(f), *make_minimizer(minimizer), o);
}

// A unit column between rollers, its top pushed down by D, over a rigid plane g0 below its
// bottom, the contact a linear spring of stiffness k.
std::string column(const std::string& mesh, double D, double g0, double k, const std::string& origin) {
  return R"(
schema_version = 1
[mesh]
)" + mesh + R"(
[material]
E = 100.0
nu = 0.3
[[dirichlet]]
side = "left"
ux = 0.0
[[dirichlet]]
side = "right"
ux = 0.0
[[dirichlet]]
side = "top"
value = [0.0, )" + std::to_string(-D) +
         R"(]
[contact]
side = "bottom"
law = "linear"
constraint = "none"
law_origin = ")" + origin + R"("
[contact.parameters]
stiffness = )" + std::to_string(k) +
         R"(
[contact.obstacle]
shape = "plane"
point = [0.0, )" + std::to_string(-g0) +
         R"(]
normal = [0.0, 1.0]
)";
}

TEST(LawOrigin, ACompliantIndentersForcePenetrationCurveIsTheHandComputation) {
  const double E = 100.0, nu = 0.3, g0 = 0.01, k = 400.0;
  const double M = E * nu / ((1 + nu) * (1 - 2 * nu)) + E / (1 + nu);  // lambda + 2 mu (plane strain)
  for (const std::string mesh : {"generator = \"squares\"\nn = 4", "generator = \"voronoi\"\nn = 6"})
    for (const double D : {0.015, 0.02, 0.04}) {
      SCOPED_TRACE(mesh + ", D = " + std::to_string(D));
      // the column is compressed uniformly: M (D - s) = k (s - g0) at its bottom settlement s
      const double s = (M * D + k * g0) / (M + k);
      const ContactSolution sol = solve_text(column(mesh, D, g0, k, "surface"));
      ASSERT_TRUE(sol.converged()) << sol.message;
      double force = 0.0;
      for (const ContactNode& n : sol.contact) {
        EXPECT_NEAR(n.u_nu, s, 1e-10 * s) << "vertex " << n.vertex;
        EXPECT_NEAR(n.pressure(), k * (s - g0), 1e-9 * k * (s - g0)) << "vertex " << n.vertex;
        force += n.force();
      }
      EXPECT_NEAR(force, k * (s - g0), 1e-9 * k * (s - g0)) << "the force of a penetration s - g0";
      // measured from the body, the same spring would carry k s: the origin matters
      const ContactSolution body = solve_text(column(mesh, D, g0, k, "body"));
      ASSERT_TRUE(body.converged());
      EXPECT_NEAR(body.contact.front().u_nu, M * D / (M + k), 1e-10 * D);
    }
}

TEST(LawOrigin, EveryMinimizerAgreesAndNodesThatMissTheObstacleHaveNoLaw) {
  // a disk indenter over part of the bottom: the rays of the outer nodes miss it (g = +inf)
  const std::string text = R"(
schema_version = 1
[mesh]
generator = "squares"
n = 8
[material]
E = 100.0
nu = 0.3
[clamped]
side = "top"
[loads]
[[loads.traction]]
side = "top"
value = [0.0, -1.0]
[contact]
side = "bottom"
law = "linear"
constraint = "none"
law_origin = "surface"
[contact.parameters]
stiffness = 1000.0
[contact.obstacle]
shape = "circle"
center = [0.5, -0.3]
radius = 0.31
)";
  ContactSolution reference;
  for (const std::string m : {"ssn", "bundle-dca", "nlopt-mma", "ceres-active-set"}) {
    SCOPED_TRACE(m);
    const ContactSolution sol = solve_text(text, m);
    ASSERT_TRUE(sol.converged()) << sol.message;
    int missed = 0;
    for (const ContactNode& n : sol.contact)
      if (std::isinf(n.gap)) {
        ++missed;
        EXPECT_EQ(n.law_force, 0.0);
      } else {
        // a spring of the penetration u_nu - g: its force is k w (u_nu - g)
        EXPECT_NEAR(n.law_force, 1000.0 * n.weight * (n.u_nu - n.gap), 1e-8);
      }
    EXPECT_GT(missed, 0);
    if (reference.u.size() == 0) reference = sol;
    else EXPECT_LT((sol.u - reference.u).cwiseAbs().maxCoeff(), 1e-6 * reference.u.cwiseAbs().maxCoeff());
  }
}

TEST(LawOrigin, UnknownOriginsAndBilateralAreRefusedAtTheirKey) {
  for (const std::string bad : {"law_origin = \"obstacle\"", "constraint = \"bilateral\"\nlaw_origin = \"surface\""}) {
    SCOPED_TRACE(bad);
    try {
      (void)parse_scene_string("schema_version = 1\n[contact]\nside = \"bottom\"\n" + bad + "\n", "bad.toml");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("law_origin"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace hemivem
