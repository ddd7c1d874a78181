// Loading paths on the full-space route (docs/full-space.md, docs/paths.md): every step of a path
// solved in the whole space by Krylov solves is the step the condensed route finds (its contact
// unknowns and displacement within 1e-8), with friction and Coulomb's fixed point, in the plane
// and in solids (a moving obstacle there); a minimizer other than the route's own is refused by
// name. tests/test_path.cpp runs a moving obstacle against static solves, a failed step and a load
// that vanishes on both routes.
#include <hemivem/app/run.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

std::unique_ptr<SparseFactorization> factorization() { return make_factorization(FactorizationOptions{}); }

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

MinimizerOptions tight() {
  MinimizerOptions o;
  o.tolerance = 1e-12;
  return o;
}

// Example 4.1 with the top traction (tx, -8).
ContactProblem example(const Mesh& mesh, double tx) {
  ContactProblem problem = example_4_1(mesh);
  for (auto& t : problem.elasticity.tractions) t.traction = [tx](const Vec2&) { return Vec2(tx, -8.0); };
  return problem;
}

// Coulomb's law of coefficient mu on the contact: Tresca's law of bound 1 scaled node by node.
ContactProblem with_coulomb(ContactProblem p, double mu) {
  p.parts[0].friction = tresca_law(1.0);
  p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, mu, {}};
  return p;
}

// Each step of `full` is the step of `condensed`: converged both, the contact unknowns, the
// displacement (where both have it) and the energy within `rel`, the same friction bound.
template <int dim>
void expect_same_steps(const BasicPathSolution<dim>& condensed, const BasicPathSolution<dim>& full, double rel) {
  ASSERT_EQ(full.steps.size(), condensed.steps.size());
  EXPECT_EQ(full.last.stages, (std::vector<std::string>{"assembly", "posing", "path"}));
  EXPECT_EQ(full.condensed_loads, 0);
  // the route's counts: the Newton iterations are the steps' (each summed over its fixed point)
  EXPECT_FALSE(condensed.last.full_space.has_value()) << "no Krylov engine ran";
  ASSERT_TRUE(full.last.full_space.has_value());
  int newton = 0;
  for (const auto& f : full.steps) newton += f.iterations;
  EXPECT_EQ(full.last.full_space->newton_iterations, newton);
  EXPECT_GE(full.last.full_space->krylov_iterations, newton);
  EXPECT_GE(full.last.full_space->preconditioner_setups, static_cast<int>(full.steps.size()));
  for (std::size_t k = 0; k < full.steps.size(); ++k) {
    const auto& c = condensed.steps[k];
    const auto& f = full.steps[k];
    SCOPED_TRACE("step " + std::to_string(k + 1));
    ASSERT_TRUE(c.converged()) << c.message;
    ASSERT_TRUE(f.converged()) << f.message;
    EXPECT_LE(max_abs(f.a - c.a), rel * max_abs(c.a));
    if (c.u.size() > 0) {
      ASSERT_EQ(f.u.size(), c.u.size());
      EXPECT_LE(max_abs(f.u - c.u), rel * max_abs(c.u));
      ASSERT_TRUE(f.forces.has_value());
      EXPECT_LE(f.forces->residual(), 1e-8);
    }
    EXPECT_NEAR(f.energy, c.energy, rel * std::abs(c.energy));
    EXPECT_EQ(f.fixed_point.used, c.fixed_point.used);
    if (c.friction_bound.size() > 0) {
      for (Eigen::Index i = 0; i < c.friction_bound.size(); ++i)
        if (std::isfinite(c.friction_bound(i)))
          EXPECT_NEAR(f.friction_bound(i), c.friction_bound(i), 1e-7 * (1.0 + max_abs(c.friction_bound))) << i;
    }
  }
}

}  // namespace

// Tresca friction along a path whose load is rebuilt at every step (the history matters: the
// friction acts on the slip of each step), with every Krylov engine built.
TEST(FullSpacePath, EveryStepIsTheCondensedRoutesWithEveryKrylovEngine) {
  const Mesh mesh = make_squares(10);
  const auto ssn = make_minimizer("ssn");
  ContactProblem p = example(mesh, 3.0);
  p.parts[0].friction = tresca_law(0.5);
  const PathLoading loading{{0.25, 0.5, 1.0}, [at_one = p](double t, ContactProblem& q) {
                              q.elasticity.tractions[0].traction = [f = at_one.elasticity.tractions[0].traction,
                                                                    t](const Vec2& x) -> Vec2 { return t * f(x); };
                            }};
  PathOptions options;
  options.minimizer = tight();
  options.frame = [](int) { return true; };
  ContactProblem q = p;
  const PathSolution condensed = solve_path(q, factorization(), *ssn, loading, options);
  for (const std::string& engine : available_krylov_solvers()) {
    SCOPED_TRACE(engine);
    for (const bool proportional : {true, false}) {
      SCOPED_TRACE(proportional ? "proportional" : "rebuilt at every step");
      ContactProblem r = p;
      const PathSolution full = solve_path(r, make_krylov_solver(engine), *ssn,
                                           proportional ? PathLoading{loading.t, {}} : loading, options);
      expect_same_steps(condensed, full, 1e-8);
      EXPECT_TRUE(full.converged());
      EXPECT_TRUE(std::isnan(full.last.uniqueness_margin)) << "not measured on this route";
    }
  }
}

// Coulomb's law along a path, pressed to t = 1 then sheared: the fixed point on the friction
// bound runs on the full-space route as on the condensed one, to the same coupled certificate.
TEST(FullSpacePath, CoulombsFixedPointFindsTheCondensedRoutesSteps) {
  const Mesh mesh = make_squares(10);
  const ContactProblem p = with_coulomb(example(mesh, 0.0), 0.3);
  const auto ssn = make_minimizer("ssn");
  const PathLoading loading{{0.5, 1.0, 1.25, 1.5}, [](double t, ContactProblem& q) {
                              q.elasticity.tractions[0].traction = [t](const Vec2&) {
                                return Vec2(4.0 * std::max(t - 1.0, 0.0), -8.0 * std::min(t, 1.0));
                              };
                            }};
  PathOptions options;
  options.minimizer = tight();
  options.frame = [](int) { return true; };
  ContactProblem a = p, b = p;
  const PathSolution condensed = solve_path(a, factorization(), *ssn, loading, options);
  const PathSolution full = solve_path(b, make_krylov_solver("eigen-cg"), *ssn, loading, options);
  expect_same_steps(condensed, full, 1e-8);
  int slipping = 0;  // the shear makes some node slip: the bound is what limits its force
  for (const auto& n : full.steps.back().contact) slipping += n.friction_state == FrictionState::slip ? 1 : 0;
  EXPECT_GT(slipping, 0);
  for (const auto& s : full.steps) EXPECT_TRUE(s.fixed_point.converged) << s.index;
}

TEST(FullSpacePath, AnotherMinimizerIsRefusedByName) {
  const Mesh mesh = make_squares(6);
  ContactProblem p = example(mesh, 0.0);
  const auto dca = make_minimizer("bundle-dca");
  const std::string why = test::input_error_of(
      [&] { (void)solve_path(p, make_krylov_solver("eigen-cg"), *dca, PathLoading{{0.5, 1.0}, {}}); });
  EXPECT_NE(why.find("the minimizer ssn: minimizer bundle-dca needs a linear engine that factorizes"),
            std::string::npos)
      << why;
}

// Solids through the one entry point: the 3D Example 4.1 along a proportional path, a sphere
// lowered onto a block (a moving obstacle), and a block pressed and dragged with Coulomb's
// friction, each step on the full-space route the condensed route's.
TEST(FullSpacePath, ASolidsPathsAreTheCondensedRoutes) {
  struct Case {
    std::string scene;
    std::vector<std::string> overrides;
  };
  const std::vector<Case> cases = {
      {"example-4.1-3d.toml", {"mesh.n=[5, 5, 5]", "path.steps=3"}},
      {"hertz-sphere-3d.toml",
       {"mesh.n=5", "contact.obstacle.center=[0, 0, 1.0]", "contact.obstacle.motion=[0, 0, -0.01]", "path.steps=3"}},
      // Coulomb's law on a solid's surface (groups of two tangential coordinates): the block
      // pressed and dragged along a path
      {"friction-block-3d.toml",
       {"mesh.n=[6, 6, 3]", "contact.friction={law = \"coulomb\", coefficient = 0.3}",
        "path.t=[0.25, 0.5, 1.0]"}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene);
    Scene condensed = parse_scene(test::scenes_dir() / c.scene);
    apply_overrides(condensed, c.overrides);
    apply_overrides(condensed, {"solver.tolerance=1e-12"});
    Scene full = condensed;
    apply_overrides(full, {"solver.linear=\"eigen-cg\""});
    const app::SceneRun a = app::run_scene(condensed);
    const app::SceneRun b = app::run_scene(full);
    ASSERT_NE(a.solid_path(), nullptr);
    ASSERT_NE(b.solid_path(), nullptr);
    ASSERT_TRUE(b.converged()) << b.solid()->solution.message;
    expect_same_steps(*a.solid_path(), *b.solid_path(), 1e-8);
    const Eigen::VectorXd& u = a.solid()->solution.u;
    EXPECT_LE(max_abs(b.solid()->solution.u - u), 1e-8 * max_abs(u));
  }
}
