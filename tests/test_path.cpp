// Loading histories (docs/paths.md): each step checked against something independent — the
// static solve, the same path with its data rebuilt at every step, the frictionless problem,
// the balance of forces — and the fixed point of Coulomb's law against its coupled certificate.
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace hemivem;

namespace {

std::unique_ptr<SparseFactorization> engine(const std::string& name = "eigen") {
  FactorizationOptions fo;
  fo.engine = name;
  return make_factorization(fo);
}

// Example 4.1 with the top traction (tx, -8).
ContactProblem example(const Mesh& mesh, double tx = 0.0) {
  ContactProblem problem = example_4_1(mesh);
  for (auto& t : problem.elasticity.tractions) t.traction = [tx](const Vec2&) { return Vec2(tx, -8.0); };
  return problem;
}

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

// The path on the condensed route (eigen) or on the full-space route (eigen-cg).
PathSolution on_route(bool full_space, ContactProblem& problem, const NonsmoothMinimizer& minimizer,
                      const PathLoading& loading, const PathOptions& options = {},
                      const std::string& factorization = "eigen") {
  return full_space ? solve_path(problem, make_krylov_solver("eigen-cg"), minimizer, loading, options)
                    : solve_path(problem, engine(factorization), minimizer, loading, options);
}

std::vector<double> factors(int K) {
  std::vector<double> t;
  for (int k = 1; k <= K; ++k) t.push_back(static_cast<double>(k) / K);
  return t;
}

// The update of a proportional path written out: the problem's data at t from those at t = 1.
std::function<void(double, ContactProblem&)> rebuild(const ContactProblem& at_one) {
  return [at_one](double t, ContactProblem& p) {
    for (std::size_t i = 0; i < p.elasticity.tractions.size(); ++i)
      p.elasticity.tractions[i].traction = [f = at_one.elasticity.tractions[i].traction, t](const Vec2& x) -> Vec2 {
        return t * f(x);
      };
  };
}

}  // namespace

TEST(Path, OneStepIsTheStaticSolve) {
  const Mesh mesh = make_squares(12);
  for (const bool friction : {false, true}) {
    SCOPED_TRACE(friction ? "tresca" : "frictionless");
    ContactProblem problem = example(mesh, 3.0);
    if (friction) problem.parts[0].friction = tresca_law(0.8);
    const auto minimizer = make_minimizer("ssn");
    const ContactSolution s = solve_contact(problem, engine(), *minimizer, MinimizerOptions{});
    ASSERT_TRUE(s.converged()) << s.message;
    const PathSolution path = solve_path(problem, engine(), *minimizer, PathLoading{{1.0}, {}});
    ASSERT_EQ(path.steps.size(), 1u);
    ASSERT_TRUE(path.converged()) << path.steps[0].message;
    EXPECT_LE(max_abs(path.last.u - s.u), 1e-10 * max_abs(s.u));
    EXPECT_NEAR(path.steps[0].energy, s.energy, 1e-10 * std::abs(s.energy));
    ASSERT_EQ(path.last.contact.size(), s.contact.size());
    for (std::size_t i = 0; i < s.contact.size(); ++i) {
      EXPECT_NEAR(path.last.contact[i].force(), s.contact[i].force(), 1e-9 * std::abs(s.contact_force().y()));
      EXPECT_EQ(path.last.contact[i].friction_state, s.contact[i].friction_state);
    }
    EXPECT_LE(path.last.forces.residual(), 1e-9);
  }
}

// Proportional loading condenses once and scales c; rebuilding the data at every step (one
// interior solve per step for c and u, no load kept) must give the same path.
TEST(Path, ProportionalLoadingEqualsRebuildingTheDataAtEveryStep) {
  const Mesh mesh = make_squares(12);
  ContactProblem a = example(mesh, 3.0);
  a.parts[0].friction = tresca_law(0.5);
  ContactProblem b = a;
  const auto minimizer = make_minimizer("ssn");
  const PathSolution fast = solve_path(a, engine(), *minimizer, PathLoading{factors(6), {}});
  PathOptions every_step;
  every_step.solved_loads = 0;
  const PathSolution slow =
      solve_path(b, engine("cholmod"), *minimizer, PathLoading{factors(6), rebuild(a)}, every_step);
  EXPECT_TRUE(fast.proportional);
  EXPECT_FALSE(slow.proportional);
  EXPECT_EQ(fast.condensed_loads, 1);
  EXPECT_EQ(slow.condensed_loads, 6);
  ASSERT_EQ(fast.steps.size(), 6u);
  ASSERT_EQ(slow.steps.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    ASSERT_TRUE(fast.steps[k].converged()) << fast.steps[k].message;
    ASSERT_TRUE(slow.steps[k].converged()) << slow.steps[k].message;
    EXPECT_LE(max_abs(fast.steps[k].a - slow.steps[k].a), 1e-8 * max_abs(slow.steps[k].a));
    EXPECT_NEAR(fast.steps[k].energy, slow.steps[k].energy, 1e-8 * std::abs(slow.steps[k].energy));
    EXPECT_LE((fast.steps[k].applied - slow.steps[k].applied).norm(), 1e-12 * slow.steps[k].applied.norm());
    EXPECT_NEAR(fast.steps[k].t, static_cast<double>(k + 1) / 6.0, 1e-15);
  }
  EXPECT_LE(max_abs(fast.last.u - slow.last.u), 1e-8 * max_abs(slow.last.u));
}

// Without friction the history does not matter: every step is the static problem at t_k.
TEST(Path, FrictionlessStepsAreStaticSolvesAtTheirLoad) {
  const Mesh mesh = make_squares(10);
  ContactProblem problem = example(mesh);
  const auto minimizer = make_minimizer("ssn");
  PathOptions options;
  options.frame = [](int) { return true; };
  const PathSolution path = solve_path(problem, engine(), *minimizer, PathLoading{{0.25, 0.5, 1.0}, {}}, options);
  for (const PathStep& s : path.steps) {
    SCOPED_TRACE("t " + std::to_string(s.t));
    ContactProblem at_t = example(mesh);
    at_t.elasticity.tractions[0].traction = [t = s.t](const Vec2&) { return Vec2(0.0, -8.0 * t); };
    const ContactSolution st = solve_contact(at_t, engine(), *minimizer, MinimizerOptions{});
    ASSERT_TRUE(s.converged());
    EXPECT_LE(max_abs(s.u - st.u), 1e-9 * max_abs(st.u));
    EXPECT_NEAR(s.energy, st.energy, 1e-9 * std::abs(st.energy));
    ASSERT_TRUE(s.forces.has_value());
    EXPECT_LE(s.forces->residual(), 1e-9);
  }
}

// A zero Tresca bound: the slip of each step is free, so the path ends where the frictionless
// static solve is (the shift of the tangential unknowns by the previous slip is exact).
TEST(Path, ZeroTrescaBoundEndsAtTheFrictionlessSolution) {
  const Mesh mesh = make_squares(12);
  ContactProblem problem = example(mesh, 3.0);
  const auto minimizer = make_minimizer("ssn");
  const ContactSolution frictionless = solve_contact(problem, engine(), *minimizer, MinimizerOptions{});
  problem.parts[0].friction = tresca_law(0.0);
  const PathSolution path = solve_path(problem, engine(), *minimizer, PathLoading{factors(4), {}});
  ASSERT_TRUE(path.converged());
  EXPECT_LE(max_abs(path.last.u - frictionless.u), 1e-9 * max_abs(frictionless.u));
}

// Coulomb with mu = 0 is frictionless; a huge mu after a normal load sticks every node in
// contact while a shear load grows; every step balances its forces.
TEST(Path, CoulombLimitsAndBalance) {
  const Mesh mesh = make_squares(12);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem frictionless = example(mesh, 3.0);
  const ContactSolution reference = solve_contact(frictionless, engine(), *minimizer, MinimizerOptions{});
  {
    ContactProblem p = example(mesh, 3.0);
    p.parts[0].friction = tresca_law(1.0);
    p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.0, {}};
    const PathSolution path = solve_path(p, engine(), *minimizer, PathLoading{{1.0}, {}});
    ASSERT_TRUE(path.converged()) << path.steps[0].message;
    EXPECT_TRUE(path.steps[0].fixed_point.used);
    EXPECT_LE(max_abs(path.last.u - reference.u), 1e-9 * max_abs(reference.u));
  }
  // normal load to t = 1, then the shear grows with t - 1
  ContactProblem p = example(mesh);
  p.parts[0].friction = tresca_law(1.0);
  p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 1e6, {}};
  PathLoading loading{{0.5, 1.0, 1.5, 2.0}, [](double t, ContactProblem& q) {
                        q.elasticity.tractions[0].traction = [t](const Vec2&) {
                          return Vec2(3.0 * std::max(t - 1.0, 0.0), -8.0 * std::min(t, 1.0));
                        };
                      }};
  PathOptions options;
  options.frame = [](int) { return true; };
  const PathSolution path = solve_path(p, engine(), *minimizer, loading, options);
  ASSERT_EQ(path.steps.size(), 4u);
  for (const PathStep& s : path.steps) {
    SCOPED_TRACE("t " + std::to_string(s.t));
    ASSERT_TRUE(s.converged()) << s.message;
    ASSERT_TRUE(s.forces.has_value());
    EXPECT_LE(s.forces->residual(), 1e-8);
    EXPECT_LE((s.forces->contact - s.contact_force).norm(), 1e-14 * (1.0 + s.contact_force.norm()));
    if (s.t <= 1.0) continue;
    int pressed = 0;
    for (std::size_t i = 0; i < s.contact.size(); ++i) {
      if (!(s.contact[i].force() > 0.0)) continue;
      ++pressed;
      EXPECT_EQ(s.slip(static_cast<Eigen::Index>(i)), 0.0) << "node " << s.contact[i].vertex;
      EXPECT_EQ(s.contact[i].friction_state, FrictionState::stick);
    }
    EXPECT_GT(pressed, 0);
  }
}

// Coulomb (mu = 0.3) along 200 small steps, pressed to t = 1/2 then sheared: each step's first
// bound is extrapolated from the last two steps' and the fixed point is accelerated (Anderson),
// so that it takes at most two Tresca problems a step on average; every step is certified, and
// the path is the one the plain relaxed iteration finds.
TEST(Path, CoulombAlongSmallStepsTakesAtMostTwoTrescaSolvesAStep) {
  const Mesh mesh = make_squares(16);
  const auto minimizer = make_minimizer("ssn");
  auto run = [&](int depth) {
    ContactProblem p = example(mesh);
    p.parts[0].friction = tresca_law(1.0);
    p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.3, {}};
    PathLoading loading{factors(200), [](double t, ContactProblem& q) {
                          q.elasticity.tractions[0].traction = [t](const Vec2&) {
                            return Vec2(4.0 * std::max(2.0 * t - 1.0, 0.0), -8.0 * std::min(2.0 * t, 1.0));
                          };
                        }};
    PathOptions options;
    options.fixed_point.anderson_depth = depth;
    return solve_path(p, engine(), *minimizer, loading, options);
  };
  const PathSolution fast = run(3), plain = run(0);
  ASSERT_TRUE(fast.converged()) << fast.last.message;
  ASSERT_TRUE(plain.converged()) << plain.last.message;
  int solves = 0;
  for (const PathStep& s : fast.steps) solves += s.fixed_point.iterations;
  EXPECT_LE(solves, 2 * 200);
  for (std::size_t k = 0; k < fast.steps.size(); k += 20)
    EXPECT_LE(max_abs(fast.steps[k].a - plain.steps[k].a), 1e-7 * max_abs(plain.steps[k].a)) << "step " << k + 1;
  EXPECT_LE(max_abs(fast.last.u - plain.last.u), 1e-7 * max_abs(plain.last.u));
}

// A moderate mu: the fixed point converges and its certificate holds; the friction force of every
// node lies within mu times its normal force, with equality where it slips.
TEST(Path, CoulombFixedPointMeetsTheCoupledConditions) {
  const Mesh mesh = make_squares(12);
  const auto minimizer = make_minimizer("ssn");
  const double mu = 0.3;
  ContactProblem p = example(mesh, 3.0);
  p.parts[0].friction = tresca_law(1.0);
  p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, mu, {}};
  const PathSolution path = solve_path(p, engine(), *minimizer, PathLoading{factors(3), {}});
  int slipping = 0, sticking = 0;
  for (const PathStep& s : path.steps) {
    ASSERT_TRUE(s.converged()) << s.message;
    EXPECT_TRUE(s.fixed_point.converged);
    EXPECT_GE(s.fixed_point.iterations, 2);
    const double f = s.certificate.force_scale;
    for (const ContactNode& n : s.contact) {
      const double limit = mu * std::max(n.force(), 0.0);
      EXPECT_LE(std::abs(n.friction_force), limit + 1e-9 * f);
      if (n.friction_state == FrictionState::slip) {
        ++slipping;
        EXPECT_NEAR(std::abs(n.friction_force), limit, 1e-9 * f);
      } else {
        ++sticking;
      }
    }
  }
  EXPECT_GT(slipping, 0);
  EXPECT_GT(sticking, 0);
}

// One iteration cannot resolve the bound: the step says so, never "converged".
TEST(Path, AFixedPointThatDoesNotConvergeIsReported) {
  const Mesh mesh = make_squares(8);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem p = example(mesh, 3.0);
  p.parts[0].friction = tresca_law(1.0);
  p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.3, {}};
  PathOptions options;
  options.fixed_point.max_iterations = 1;
  const PathSolution path = solve_path(p, engine(), *minimizer, PathLoading{{1.0}, {}}, options);
  const PathStep& s = path.steps[0];
  EXPECT_FALSE(s.converged());
  EXPECT_FALSE(s.fixed_point.converged);
  EXPECT_FALSE(path.last.converged());
  EXPECT_NE(s.message.find("fixed point"), std::string::npos) << s.message;
}

// A failed step in the middle of a path makes the path fail: its last solution carries the
// failed step's status and names it, though every later step converged.
TEST(Path, AFailedStepBeforeConvergedOnesFailsThePath) {
  const Mesh mesh = make_squares(8);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem p = example(mesh);
  PathOptions options;
  int finished = 0;
  options.on_step = [&finished](const PathStep&) {
    ++finished;
    return true;
  };
  // step 2 jumps from t = 0.05 to t = 1 (a new contact zone); its first iteration is stopped
  options.minimizer.callback = [&finished](const IterationRecord&) { return finished != 1; };
  const PathSolution path = solve_path(p, engine(), *minimizer, PathLoading{{0.05, 1.0, 1.05, 1.1}, {}}, options);
  ASSERT_EQ(path.steps.size(), 4u);
  EXPECT_TRUE(path.steps[0].converged());
  EXPECT_EQ(path.steps[1].status, MinimizerStatus::stopped_by_callback);
  EXPECT_TRUE(path.steps[2].converged());
  EXPECT_TRUE(path.steps[3].converged());
  EXPECT_FALSE(path.converged());
  EXPECT_EQ(path.last.status, MinimizerStatus::stopped_by_callback);
  EXPECT_NE(path.last.message.find("step 2 (t = 1) did not converge"), std::string::npos) << path.last.message;
  EXPECT_NE(path.last.message.find("the 2 steps after it"), std::string::npos) << path.last.message;
  // the last step's own numbers are kept: its displacement is the last step's
  EXPECT_EQ(path.last.u, path.steps[3].u);
}

// The bound h(u_nu) of a table: a constant table is Tresca's law with that bound.
TEST(Path, AConstantBoundTableIsTresca) {
  const Mesh mesh = make_squares(10);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem tresca = example(mesh, 3.0);
  tresca.parts[0].friction = tresca_law(0.8);
  const PathSolution a = solve_path(tresca, engine(), *minimizer, PathLoading{factors(2), {}});
  ContactProblem table = example(mesh, 3.0);
  table.parts[0].friction = tresca_law(1.0);
  table.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::normal_displacement, 0.0, {{{-1.0, 0.8}}, {{1.0, 0.8}}}};
  const PathSolution b = solve_path(table, engine(), *minimizer, PathLoading{factors(2), {}});
  ASSERT_TRUE(a.converged());
  ASSERT_TRUE(b.converged()) << b.steps.back().message;
  EXPECT_LE(max_abs(a.last.u - b.last.u), 1e-9 * max_abs(a.last.u));
  EXPECT_EQ(b.steps[0].fixed_point.iterations, 2);  // g = 0, then g = 0.8 exactly
}

TEST(Path, FrictionBoundTableInterpolates) {
  FrictionBound h{FrictionBound::Kind::normal_displacement, 0.0, {{{0.0, 1.0}}, {{0.01, 3.0}}}};
  EXPECT_EQ(h.of_normal_displacement(-1.0), 1.0);
  EXPECT_DOUBLE_EQ(h.of_normal_displacement(0.005), 2.0);
  EXPECT_EQ(h.of_normal_displacement(1.0), 3.0);
  FrictionBound c{FrictionBound::Kind::coulomb, 0.5, {}};
  EXPECT_EQ(c.bound(0.0, 4.0), 2.0);
  EXPECT_EQ(c.bound(0.0, -4.0), 0.0);
  EXPECT_THROW(check_friction_bound(FrictionBound{FrictionBound::Kind::coulomb, -1.0, {}}), InputError);
  EXPECT_THROW(check_friction_bound(FrictionBound{FrictionBound::Kind::normal_displacement, 0.0, {{{1.0, 1.0}}, {{0.0, 1.0}}}}),
               InputError);
}

TEST(Path, CoupledCertificateCountsTheBoundMismatchAsAForce) {
  Certificate tresca;
  tresca.primal = 0.0;
  tresca.dual = 1e-12;
  tresca.force_scale = 10.0;
  tresca.tolerance = 1e-10;
  const Eigen::VectorXd w = Eigen::VectorXd::Constant(2, 0.5);
  const Eigen::VectorXd g = Eigen::VectorXd::Constant(2, 1.0);
  EXPECT_TRUE(friction_bound_certificate(tresca, w, g, g).converged());
  Eigen::VectorXd off = g;
  off(1) += 1e-6;
  const Certificate c = friction_bound_certificate(tresca, w, g, off);
  EXPECT_FALSE(c.converged());
  EXPECT_DOUBLE_EQ(c.dual, 0.5 * (off(1) - g(1)) / 10.0);
}

TEST(Path, StopsWhenAskedAndRefusesBadFactors) {
  const Mesh mesh = make_squares(8);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem p = example(mesh);
  PathOptions options;
  options.on_step = [](const PathStep& s) { return s.index < 2; };
  const PathSolution path = solve_path(p, engine(), *minimizer, PathLoading{factors(5), {}}, options);
  ASSERT_EQ(path.steps.size(), 2u);
  EXPECT_EQ(path.last.u.size(), 2 * mesh.num_vertices());
  EXPECT_LE(path.last.forces.residual(), 1e-9);
  EXPECT_THROW(solve_path(p, engine(), *minimizer, PathLoading{{0.5, 0.5}, {}}), InputError);
  EXPECT_THROW(solve_path(p, engine(), *minimizer, PathLoading{{0.0, 1.0}, {}}), InputError);
  EXPECT_THROW(solve_path(p, engine(), *minimizer, PathLoading{{}, {}}), InputError);
}

// Every linear engine condenses the new load of each step (a split interior solve keeps the
// forward substitution of the load it last saw) and back-substitutes it.
TEST(Path, EveryLinearEngineFollowsTheSameGeneralPath) {
  const Mesh mesh = make_squares(8);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem reference_problem = example(mesh, 3.0);
  reference_problem.parts[0].friction = tresca_law(0.5);
  const PathSolution reference =
      solve_path(reference_problem, engine("eigen"), *minimizer, PathLoading{factors(3), {}});
  for (const std::string& name : available_factorizations()) {
    SCOPED_TRACE(name);
    ContactProblem p = example(mesh, 3.0);
    p.parts[0].friction = tresca_law(0.5);
    for (const int kept : {0, 6}) {  // every step's load condensed; or each a multiple of the first
      SCOPED_TRACE("loads kept " + std::to_string(kept));
      ContactProblem q = p;
      PathOptions options;
      options.frame = [](int) { return true; };
      options.solved_loads = kept;
      const PathSolution path = solve_path(q, engine(name), *minimizer, PathLoading{factors(3), rebuild(p)}, options);
      ASSERT_EQ(path.steps.size(), 3u);
      EXPECT_EQ(path.condensed_loads, kept == 0 ? 3 : 1);
      for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_TRUE(path.steps[k].converged()) << path.steps[k].message;
        EXPECT_LE(max_abs(path.steps[k].a - reference.steps[k].a), 1e-8 * max_abs(reference.steps[k].a));
        EXPECT_LE(path.steps[k].forces->residual(), 1e-9);
      }
    }
  }
}

// Each step of the path against the static solve of the problem that `at` makes at its t: the
// contact coordinates and the energy to 1e-9, and `more` for the further checks of a step.
template <class At, class More>
void expect_static_solves(const PathSolution& path, const Mesh& mesh, const At& at, const NonsmoothMinimizer& minimizer,
                          const More& more) {
  for (const PathStep& s : path.steps) {
    SCOPED_TRACE("t " + std::to_string(s.t));
    ContactProblem at_t = example(mesh);
    at(s.t, at_t);
    const ContactSolution st = solve_contact(at_t, engine(), minimizer, MinimizerOptions{});
    ASSERT_TRUE(s.converged()) << s.message;
    ASSERT_TRUE(st.converged());
    EXPECT_LE(max_abs(s.a - st.minimizer->a), 1e-9 * max_abs(st.minimizer->a));
    EXPECT_NEAR(s.energy, st.energy, 1e-9 * std::abs(st.energy));
    more(s, st);
  }
}

// Loads that combine two fields with coefficients in t, (3t, -8t) on the top and (0, -20 t^2) in
// the body: two loads are condensed, every other step's is their combination, and each step is
// still the static problem at its load (no friction: the history does not matter).
TEST(Path, ALoadCombiningFieldsWithCoefficientsInTCondensesEachFieldOnce) {
  const Mesh mesh = make_squares(10);
  const auto minimizer = make_minimizer("ssn");
  auto at = [](double t, ContactProblem& q) {
    q.elasticity.tractions[0].traction = [t](const Vec2&) { return Vec2(3.0 * t, -8.0 * t); };
    q.elasticity.body_force = [t](const Vec2&) { return Vec2(0.0, -20.0 * t * t); };
  };
  ContactProblem problem = example(mesh);
  PathOptions options;
  options.frame = [](int k) { return k % 2 == 0; };
  const PathSolution path = solve_path(problem, engine("cholmod"), *minimizer, PathLoading{factors(6), at}, options);
  ASSERT_EQ(path.steps.size(), 6u);
  EXPECT_EQ(path.condensed_loads, 2);
  expect_static_solves(path, mesh, at, *minimizer, [](const PathStep& s, const ContactSolution& st) {
    EXPECT_LE((s.applied - Vec2(3.0 * s.t, -8.0 * s.t - 20.0 * s.t * s.t)).norm(), 1e-12 * s.applied.norm());
    if (s.u.size() > 0) {
      EXPECT_LE(max_abs(s.u - st.u), 1e-9 * max_abs(st.u));
      EXPECT_LE(s.forces->residual(), 1e-9);
    }
  });
}

// A load on the top, then from t = 1/2 on also in the body's lowest quarter (the contact side):
// the first load is zero in the rows of that quarter, and the second is zero where the first is
// not (the top's rows), so the later steps' loads are no combination of the first, measured in
// rows where it is zero. Each is condensed at its step until the second field is kept. Every
// step is the static problem at its load.
TEST(Path, ALoadThatSpreadsBeyondTheRowsOfThoseKeptIsNotTheirCombination) {
  const Mesh mesh = make_squares(64);  // 8 450 unknowns: several blocks of rows
  const auto minimizer = make_minimizer("ssn");
  auto at = [](double t, ContactProblem& q) {
    q.elasticity.tractions[0].traction = [t](const Vec2&) { return Vec2(0.0, -8.0 * t); };
    q.elasticity.body_force = [t](const Vec2& x) { return Vec2(0.0, t > 0.5 && x.y() < 0.25 ? -20.0 * (t - 0.5) : 0.0); };
  };
  ContactProblem problem = example(mesh);
  const PathSolution path = solve_path(problem, engine("cholmod"), *minimizer, PathLoading{factors(6), at});
  ASSERT_EQ(path.steps.size(), 6u);
  // the top's load (step 1), the first step with the body's load (t = 2/3); t = 5/6 and 1 are
  // combinations of the two
  EXPECT_EQ(path.condensed_loads, 2);
  expect_static_solves(path, mesh, at, *minimizer, [](const PathStep&, const ContactSolution&) {});
}

// A load that is no combination of a few fields (sin(pi t x) on the top): each step condenses
// its own, the first six are kept and the later ones are not in their span; the path is the one
// that keeps none.
TEST(Path, ALoadOutsideTheSpanOfThoseKeptIsCondensedAtItsStep) {
  const Mesh mesh = make_squares(16);
  const auto minimizer = make_minimizer("ssn");
  auto at = [](double t, ContactProblem& q) {
    q.elasticity.tractions[0].traction = [t](const Vec2& x) { return Vec2(0.0, -8.0 * (1.0 + std::sin(M_PI * t * x.x()))); };
  };
  ContactProblem a = example(mesh), b = example(mesh);
  PathOptions none;
  none.solved_loads = 0;
  const PathSolution kept = solve_path(a, engine(), *minimizer, PathLoading{factors(8), at});
  const PathSolution every = solve_path(b, engine(), *minimizer, PathLoading{factors(8), at}, none);
  EXPECT_EQ(kept.condensed_loads, 8);
  EXPECT_EQ(every.condensed_loads, 8);
  ASSERT_EQ(kept.steps.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    ASSERT_TRUE(kept.steps[k].converged()) << kept.steps[k].message;
    EXPECT_LE(max_abs(kept.steps[k].a - every.steps[k].a), 1e-10 * max_abs(every.steps[k].a));
    EXPECT_NEAR(kept.steps[k].energy, every.steps[k].energy, 1e-10 * std::abs(every.steps[k].energy));
  }
  EXPECT_LE(max_abs(kept.last.u - every.last.u), 1e-10 * max_abs(every.last.u));
}

// A moving obstacle changes the gaps of every step (Condensation::set_gaps); each step must be
// the static problem with the obstacle where the step puts it, on either route. With the law's
// origin on the obstacle's surface the condensed load (the full-space route: the coordinates'
// origin) shifts with the gaps too.
TEST(Path, AMovingObstacleGivesTheStaticSolveAtEveryStep) {
  for (const std::string origin : {"body", "surface"}) {
    SCOPED_TRACE(origin);
    auto scene_text = [&](double cy, bool moving) {
      // the rays of the corner nodes meet the circle well inside it (at x = +-1 they would graze it)
      return std::string("schema_version = 1\n[mesh]\nn = 16\ndomain = [-0.5, 0.5, -1.0, 0.0]\n"
                         "[material]\nE = 65.0\nnu = 0.29\n[clamped]\nside = \"bottom\"\n"
                         "[contact]\nside = \"top\"\nlaw = \"") +
             (origin == "surface" ? "linear" : "zero") + "\"\nconstraint = \"one-sided\"\nlaw_origin = \"" + origin +
             "\"\n[contact.obstacle]\nshape = \"circle\"\ncenter = [0.0, " + std::to_string(cy) +
             "]\nradius = 1.0\n" + (moving ? "motion = [0.0, -0.02]\n" : "");
    };
    const Scene moving = parse_scene_string(scene_text(1.005, true), "moving.toml");
    ASSERT_FALSE(scene_is_proportional(moving));
    const auto minimizer = make_minimizer("ssn");
    PathLoading loading{{0.5, 0.75, 1.0}, [&moving](double t, ContactProblem& p) { set_load_factor(moving, t, p); }};
    PathOptions options;
    options.frame = [](int) { return true; };
    for (const bool full_space : {false, true}) {
      SCOPED_TRACE(full_space ? "the full-space route" : "the condensed route");
      auto built = build_problem(moving);
      const PathSolution path = on_route(full_space, built->problem, *minimizer, loading, options, "cholmod");
      for (const PathStep& s : path.steps) {
        SCOPED_TRACE("t " + std::to_string(s.t));
        ASSERT_TRUE(s.converged()) << s.message;
        const Scene at_t = parse_scene_string(scene_text(1.005 - 0.02 * s.t, false), "static.toml");
        auto b = build_problem(at_t);
        const ContactSolution st = solve_contact(b->problem, engine(), *minimizer, MinimizerOptions{});
        ASSERT_TRUE(st.converged());
        EXPECT_GT(contact_zone(st).nodes, 0);
        EXPECT_LE(max_abs(s.u - st.u), 1e-8 * max_abs(st.u));
        EXPECT_NEAR(s.energy, st.energy, 1e-8 * std::abs(st.energy));
      }
    }
  }
}

// A disk lowered through the top of the body: pressed in at the first step (the nodes under it
// start inside it), then below the surface, where the rays out of the nodes above it miss it and
// their gaps turn infinite. That step fails, naming the node, instead of dropping the contact, on
// either route.
TEST(Path, AnObstacleMovedThroughTheBodyFailsItsStep) {
  const std::string text =
      "schema_version = 1\n[mesh]\nn = 20\ndomain = [-0.5, 0.5, -1.0, 0.0]\n"
      "[material]\nE = 65.0\nnu = 0.29\n[clamped]\nside = \"bottom\"\n"
      "[contact]\nside = \"top\"\nlaw = \"zero\"\nconstraint = \"one-sided\"\n"
      "[contact.obstacle]\nshape = \"circle\"\ncenter = [0.0, 0.105]\nradius = 0.1\nmotion = [0.0, -0.5]\n";
  const Scene scene = parse_scene_string(text, "through.toml");
  const auto minimizer = make_minimizer("ssn");
  PathLoading loading{{0.02, 0.5, 1.0}, [&scene](double t, ContactProblem& p) { set_load_factor(scene, t, p); }};
  for (const bool full_space : {false, true}) {
    SCOPED_TRACE(full_space ? "the full-space route" : "the condensed route");
    auto built = build_problem(scene);
    const PathSolution path = on_route(full_space, built->problem, *minimizer, loading);
    ASSERT_EQ(path.steps.size(), 3u);
    EXPECT_TRUE(path.steps[0].converged()) << path.steps[0].message;
    EXPECT_GT(contact_zone(path.steps[0].contact).nodes, 0);
    EXPECT_FALSE(path.steps[1].converged());
    EXPECT_NE(path.steps[1].message.find("has moved through the body's surface at vertex"), std::string::npos)
        << path.steps[1].message;
    EXPECT_FALSE(path.converged());
    EXPECT_NE(path.last.message.find("step 2 (t = 0.5) did not converge"), std::string::npos) << path.last.message;
  }
}

// Loaded and unloaded to exactly zero: the last step is the unloaded body, a = 0, certified, on
// either route.
TEST(Path, AStepWhoseLoadVanishesIsTheUnloadedBody) {
  const Mesh mesh = make_squares(8);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem p = example(mesh);
  p.parts[0].law = zero_law();
  PathLoading loading{{0.25, 0.5, 0.75, 1.0}, [](double t, ContactProblem& q) {
                        q.elasticity.tractions[0].traction = [t](const Vec2&) {
                          return Vec2(0.0, -8.0 * (1.0 - std::abs(2.0 * t - 1.0)));
                        };
                      }};
  for (const bool full_space : {false, true}) {
    SCOPED_TRACE(full_space ? "the full-space route" : "the condensed route");
    ContactProblem q = p;
    const PathSolution path = on_route(full_space, q, *minimizer, loading);
    ASSERT_EQ(path.steps.size(), 4u);
    for (const PathStep& s : path.steps) EXPECT_TRUE(s.converged()) << "t " << s.t << ": " << s.message;
    EXPECT_GT(max_abs(path.steps[1].a), 0.0);
    EXPECT_EQ(max_abs(path.steps.back().a), 0.0);
    EXPECT_EQ(max_abs(path.last.u), 0.0);
  }
}

// An obstacle moving sideways: nodes near its ends start and stop facing it (their gaps turn
// infinite and finite again), and with the law's origin on its surface they lose and regain
// their law. Every step is still the static problem with the obstacle where the step puts it.
TEST(Path, NodesThatStartOrStopFacingAMovingObstacle) {
  auto scene_text = [](double cx, bool moving) {
    return std::string("schema_version = 1\n[mesh]\nn = 16\ndomain = [-1.0, 1.0, -1.0, 0.0]\n"
                       "[material]\nE = 65.0\nnu = 0.29\n[clamped]\nside = \"bottom\"\n"
                       "[contact]\nside = \"top\"\nlaw = \"linear\"\nconstraint = \"one-sided\"\nlaw_origin = \"surface\"\n"
                       "[contact.obstacle]\nshape = \"circle\"\ncenter = [") +
           std::to_string(cx) + ", 0.905]\nradius = 0.9\n" + (moving ? "motion = [-0.2, 0.0]\n" : "");
  };
  const Scene moving = parse_scene_string(scene_text(0.0, true), "moving.toml");
  auto built = build_problem(moving);
  const auto minimizer = make_minimizer("ssn");
  PathLoading loading{{0.3, 0.6, 0.9}, [&moving](double t, ContactProblem& p) { set_load_factor(moving, t, p); }};
  PathOptions options;
  options.frame = [](int) { return true; };
  const PathSolution path = solve_path(built->problem, engine("cholmod"), *minimizer, loading, options);
  int facing_changes = 0;
  std::vector<bool> facing_before;
  for (const PathStep& s : path.steps) {
    SCOPED_TRACE("t " + std::to_string(s.t));
    ASSERT_TRUE(s.converged()) << s.message;
    std::vector<bool> facing;
    for (const ContactNode& n : s.contact) facing.push_back(std::isfinite(n.gap));
    if (!facing_before.empty())
      for (std::size_t i = 0; i < facing.size(); ++i) facing_changes += facing[i] != facing_before[i] ? 1 : 0;
    facing_before = facing;
    auto b = build_problem(parse_scene_string(scene_text(-0.2 * s.t, false), "static.toml"));
    const ContactSolution st = solve_contact(b->problem, engine(), *minimizer, MinimizerOptions{});
    ASSERT_TRUE(st.converged());
    EXPECT_LE(max_abs(s.u - st.u), 1e-8 * max_abs(st.u));
    EXPECT_NEAR(s.energy, st.energy, 1e-8 * std::abs(st.energy));
  }
  EXPECT_GE(facing_changes, 2);  // one node starts facing it, another stops
}
