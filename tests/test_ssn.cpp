// Engine-specific checks of the semismooth Newton / active-set minimizer "ssn": local
// quadratic convergence, iteration counts on Example 4.1, exact recognition of kinks, the
// gradient fallback, nonconvex problems, every status it can return and its input errors.
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/ssn_minimizer.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

using test::Example;
using test::example;

// A dense SPD matrix with a dominant diagonal and random coupling, like a small Schur complement.
ReducedProblem random_problem(int n, std::shared_ptr<const ContactLaw> law, ConstraintKind kind, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = u(gen);
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) c(i) = 2.0 * u(gen) + 1.0;
  const double alpha = law->alpha();
  ReducedProblem p = ReducedProblem::uniform(10.0 * B * B.transpose() / n + 100.0 * Eigen::MatrixXd::Identity(n, n), c,
                                             Eigen::VectorXd::Constant(n, 0.05), std::move(law), kind,
                                             Eigen::VectorXd::Constant(n, 0.02));
  p.uniqueness_margin = uniqueness_margin(p.S, p.w, alpha);
  return p;
}

// j = k r^3 / 3 for r > 0, 0 otherwise: convex, C^2, not piecewise quadratic.
std::shared_ptr<const ContactLaw> cubic_law(double k = 2000.0) {
  return std::make_shared<PiecewisePolynomialLaw>("cubic", std::vector<double>{0.0},
                                                  std::vector<Polynomial>{{0.0}, {0.0, 0.0, 0.0, k / 3.0}},
                                                  std::vector<Polynomial>{{0.0}, {0.0}});
}

int count_in_message(const std::string& message, const std::string& what) {
  const auto pos = message.find(" " + what);
  if (pos == std::string::npos) return -1;
  auto start = message.rfind(' ', pos - 1);
  start = start == std::string::npos ? 0 : start + 1;
  return std::stoi(message.substr(start, pos - start));
}

void expect_monotone(const MinimizerResult& r) {
  for (std::size_t k = 1; k < r.history.size(); ++k)
    EXPECT_LE(r.history[k].objective, r.history[k - 1].objective + 1e-12 * std::abs(r.history[k - 1].objective)) << "step " << k;
}

struct TimedRun {
  MinimizerResult result;
  Eigen::Index size = 0;  // N1
  double seconds = 0.0;
};

/// ssn to certificate 1e-10 on Example 4.1 on N x N squares, timed.
TimedRun ssn_on_squares(int n) {
  auto ex = example("squares", n);
  const ReducedProblem& p = ex->condensation->reduced();
  MinimizerOptions o;
  o.tolerance = 1e-10;
  const auto t0 = std::chrono::steady_clock::now();
  TimedRun run;
  run.result = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.size = p.size();
  return run;
}

TEST(Ssn, NameAndFactory) {
  EXPECT_EQ(SsnMinimizer().name(), "ssn");
}

TEST(Ssn, QuadraticConvergenceOnASmoothProblem) {
  const ReducedProblem p = random_problem(60, cubic_law(), ConstraintKind::none, 7);
  MinimizerOptions o;
  o.tolerance = 1e-14;
  const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
  ASSERT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
  std::cout << "residuals:";
  for (const auto& h : r.history) std::cout << " " << h.dual;
  std::cout << "\n";
  EXPECT_LE(r.iterations, 12);
  expect_monotone(r);
  // once the residual is small the Newton steps square it (up to a modest constant)
  int quadratic_steps = 0;
  for (std::size_t k = 1; k < r.history.size(); ++k) {
    const double prev = r.history[k - 1].dual, cur = r.history[k].dual;
    if (prev < 1e-2 && cur > 1e-15) {
      EXPECT_LE(cur, 100.0 * prev * prev) << "step " << k;
      ++quadratic_steps;
    }
  }
  EXPECT_GE(quadratic_steps, 1);
}

TEST(Ssn, Example41IterationCounts) {
  for (int n : {16, 32, 64}) {
    const TimedRun run = ssn_on_squares(n);
    const MinimizerResult& r = run.result;
    std::cout << "squares N = " << n << ": N1 = " << run.size << ", " << r.iterations << " iterations, residual "
              << r.certificate.dual << ", " << run.seconds << " s (" << r.message << ")\n";
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_LE(r.iterations, 25);
    EXPECT_EQ(count_in_message(r.message, "gradient fallbacks"), 0) << r.message;
    EXPECT_FALSE(r.may_be_nonunique);
    expect_monotone(r);
    EXPECT_TRUE(r.timings.count("total") && r.timings.count("factorization") && r.timings.count("line_search"));
  }
}

// Timings for the benchmark sizes (slow to build: run with --gtest_also_run_disabled_tests).
TEST(Ssn, DISABLED_Example41Timings) {
  for (int n : {64, 128, 256}) {
    const TimedRun run = ssn_on_squares(n);
    const MinimizerResult& r = run.result;
    std::cout << "squares N = " << n << ": N1 = " << run.size << ", " << r.iterations << " iterations, residual "
              << r.certificate.dual << ", " << run.seconds << " s, factorization " << r.timings.at("factorization")
              << " s (" << r.message << ")\n";
    EXPECT_TRUE(r.converged()) << r.message;
  }
  for (int n : {500, 1000}) {
    const ReducedProblem p = random_problem(n, paper_law(), ConstraintKind::box, 2);
    const auto t0 = std::chrono::steady_clock::now();
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "random dense N1 = " << n << ": " << r.iterations << " iterations, residual " << r.certificate.dual
              << ", " << s << " s (" << r.message << ")\n";
    EXPECT_TRUE(r.converged()) << r.message;
  }
}

TEST(Ssn, ConvergesFromAnyStartWhenStronglyConvex) {
  auto ex = example("squares", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  ASSERT_GT(p.uniqueness_margin, 0.0);
  const MinimizerResult ref = SsnMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(ref.converged());
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (int k = 0; k < 10; ++k) {
    Eigen::VectorXd start(p.size());
    for (Eigen::Index i = 0; i < start.size(); ++i) start(i) = u(gen);
    const MinimizerResult r = SsnMinimizer().minimize(p, start, MinimizerOptions{});
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_LE((r.a - ref.a).cwiseAbs().maxCoeff(), 1e-8 * ref.a.cwiseAbs().maxCoeff());
    expect_monotone(r);
  }
}

TEST(Ssn, EveryLawEveryConstraintRandomStarts) {
  int worst = 0;
  for (const std::string law : {"paper", "linear", "zero", "kinked", "sawtooth"})
    for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided, ConstraintKind::none})
      for (unsigned seed = 1; seed <= 4; ++seed) {
        SCOPED_TRACE(law + " / " + to_string(kind) + " / seed " + std::to_string(seed));
        ReducedProblem p = random_problem(50, make_contact_law(law), kind, seed);
        p.c *= 0.5 * seed;  // from little contact to everything beyond the last breakpoint
        if (seed % 2 == 0) p.w *= 200.0;  // the law dominates S: S + W j'' indefinite (paper law)
        std::mt19937 gen(seed);
        std::uniform_real_distribution<double> u(-0.05, 0.05);
        Eigen::VectorXd start(p.size());
        for (Eigen::Index i = 0; i < start.size(); ++i) start(i) = u(gen);
        for (const Eigen::VectorXd& s0 : {Eigen::VectorXd(), start}) {
          MinimizerOptions o;
          o.tolerance = 1e-12;
          const MinimizerResult r = SsnMinimizer().minimize(p, s0, o);
          EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
          EXPECT_EQ(r.certificate.primal, 0.0);
          expect_monotone(r);
          worst = std::max(worst, r.iterations);
        }
      }
  std::cout << "most iterations: " << worst << "\n";
  EXPECT_LE(worst, 40);
}

TEST(Ssn, KinkIsRecognisedExactly) {
  // two nodes, kinked law (j' jumps from 0 to 0.3 at 0): node 0 rests exactly on the kink
  // with 0 inside its Clarke interval; node 1 is inside the smooth piece r > 0.
  Eigen::Matrix2d S;
  S << 2.0, -0.5, -0.5, 2.0;
  for (ConstraintKind kind : {ConstraintKind::none, ConstraintKind::one_sided, ConstraintKind::box}) {
    const ReducedProblem p = ReducedProblem::uniform(S, Eigen::Vector2d(0.1, 1.0), Eigen::Vector2d(1.0, 1.0),
                                                     kinked_law(0.3, 100.0), kind, Eigen::Vector2d(1.0, 1.0));
    for (const Eigen::Vector2d start : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.5, -0.3), Eigen::Vector2d(-0.7, 0.9)}) {
      MinimizerOptions o;
      o.tolerance = 1e-14;
      const MinimizerResult r = SsnMinimizer().minimize(p, start, o);
      ASSERT_TRUE(r.converged()) << r.message;
      EXPECT_EQ(r.a(0), 0.0);
      EXPECT_NEAR(r.a(1), 0.7 / 102.0, 1e-15);
      EXPECT_LE(r.certificate.dual, 1e-14);
      EXPECT_LE(r.iterations, 6);
    }
  }
}

TEST(Ssn, KinkedLawsOnExample41ReachTheCertificate) {
  for (const std::string law : {"kinked", "sawtooth"}) {
    auto ex = example("squares", 32, [&](ContactProblem& q) {
      q.parts[0].law = make_contact_law(law);
      q.parts[0].constraint = ConstraintKind::one_sided;
    });
    const ReducedProblem& p = ex->condensation->reduced();
    MinimizerOptions o;
    o.tolerance = 1e-12;
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_TRUE(r.converged()) << law << ": " << r.message << " residual " << r.certificate.dual;
    int at_kink = 0;
    for (Eigen::Index i = 0; i < r.a.size(); ++i)
      for (double b : p.law_of(i).breakpoints()) at_kink += r.a(i) == b ? 1 : 0;
    std::cout << law << ": " << r.iterations << " iterations, " << at_kink << " nodes exactly at a breakpoint, residual "
              << r.certificate.dual << "\n";
    expect_monotone(r);
  }
}

// The paper's law (4.7) scaled by `factor` (alpha_j = 20 factor).
std::shared_ptr<const ContactLaw> scaled_paper_law(double factor) {
  const auto base = std::dynamic_pointer_cast<const PiecewisePolynomialLaw>(paper_law());
  auto scale = [&](std::vector<Polynomial> ps) {
    for (auto& q : ps)
      for (auto& c : q) c *= factor;
    return ps;
  };
  return std::make_shared<PiecewisePolynomialLaw>("paper-scaled", base->breakpoints(), scale(base->pieces(LawPart::j1)),
                                                  scale(base->pieces(LawPart::j2)));
}

TEST(Ssn, ArmijoFallbackKeepsConverging) {
  // a single backtracking step with a demanding Armijo constant, from a start where the law's
  // curvature vanishes (the full Newton step overshoots a stiff cubic law): the Newton path is
  // rejected and the projected-gradient fallback must carry the run
  const ReducedProblem p = random_problem(40, cubic_law(1e7), ConstraintKind::none, 5);
  MinimizerOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 5000;
  SsnOptions so;
  so.max_backtracks = 1;
  so.armijo = 0.49;
  const MinimizerResult r = SsnMinimizer(so).minimize(p, Eigen::VectorXd(), o);
  std::cout << r.message << "\n";
  EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
  EXPECT_GT(count_in_message(r.message, "gradient fallbacks"), 0) << r.message;
  expect_monotone(r);
}

TEST(Ssn, NonconvexProblemGivesACriticalPoint) {
  // paper law x 200 on a random problem: S + W j'' is indefinite on the middle piece
  const auto law = scaled_paper_law(200.0);
  for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided, ConstraintKind::none}) {
    ReducedProblem p = random_problem(40, law, kind, 11);
    p.c *= 3.0;
    ASSERT_LT(p.uniqueness_margin, 0.0);
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    std::cout << to_string(kind) << ": " << r.message << "; residuals";
    for (const auto& h : r.history) std::cout << " " << h.dual;
    std::cout << "\n";
    EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
    EXPECT_TRUE(r.may_be_nonunique);
    expect_monotone(r);
    // a local minimizer: no small feasible coordinate move decreases F
    for (Eigen::Index i = 0; i < p.size(); ++i)
      for (double h : {-1e-6, 1e-6}) {
        Eigen::VectorXd b = r.a;
        b(i) += h;
        if (b(i) < p.lower(i) || b(i) > p.upper(i)) continue;
        EXPECT_GE(p.energy(b), r.objective - 1e-14 * std::abs(r.objective)) << "node " << i;
      }
  }
}

TEST(Ssn, StatusPaths) {
  auto ex = example("squares", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  {
    MinimizerOptions o;
    o.max_iterations = 1;
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::iteration_limit) << r.message;
    EXPECT_EQ(r.iterations, 1);
    EXPECT_EQ(r.history.size(), 2u);  // the start and one iteration
  }
  {
    MinimizerOptions o;
    o.max_evaluations = 3;
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::evaluation_limit) << r.message;
    EXPECT_LE(r.function_evaluations + r.subgradient_evaluations, 4);
  }
  {
    MinimizerOptions o;
    int calls = 0;
    o.callback = [&](const IterationRecord& rec) {
      EXPECT_EQ(rec.iteration, calls + 1);
      return ++calls < 2;
    };
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::stopped_by_callback);
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(r.iterations, 2);
  }
  {
    MinimizerOptions o;
    o.tolerance = 1e-300;  // below round-off: no descent step is left
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::stalled) << r.message;
    EXPECT_LE(r.certificate.dual, 1e-12);
    EXPECT_LT(r.iterations, 100);
  }
  {
    const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_EQ(r.status, MinimizerStatus::converged);
    EXPECT_EQ(r.certificate.primal, 0.0);
    EXPECT_GT(r.function_evaluations, 0);
    EXPECT_GT(r.subgradient_evaluations, 0);
    EXPECT_EQ(static_cast<int>(r.history.size()), r.iterations + 1);
    // a converged start needs no iteration
    const MinimizerResult again = SsnMinimizer().minimize(p, r.a, MinimizerOptions{});
    EXPECT_TRUE(again.converged());
    EXPECT_EQ(again.iterations, 0);
    EXPECT_EQ(again.a, r.a);
  }
}

TEST(Ssn, EmptyProblem) {
  const ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd(0, 0), Eigen::VectorXd(), Eigen::VectorXd(), zero_law(),
                                                   ConstraintKind::box, Eigen::VectorXd());
  const MinimizerResult r = SsnMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(r.converged());
  EXPECT_EQ(r.a.size(), 0);
}

TEST(Ssn, InputErrors) {
  const ReducedProblem p = random_problem(5, paper_law(), ConstraintKind::box, 1);
  const SsnMinimizer m;
  EXPECT_THROW(m.minimize(p, Eigen::VectorXd::Zero(4), MinimizerOptions{}), InputError);
  EXPECT_THROW(m.minimize(p, Eigen::VectorXd::Constant(5, std::nan("")), MinimizerOptions{}), InputError);
  EXPECT_THROW(make_minimizer("ssn", {{"newton_steps", 3}}), InputError);
  for (const auto& [name, bad] : std::vector<std::pair<std::string, double>>{
           {"armijo", 0.7}, {"backtrack", 1.0}, {"max_backtracks", 0.0}, {"max_backtracks", 1e20},
           {"max_backtracks", 2.5}, {"active_scale", -1.0}, {"shift", 0.0}}) {
    try {
      make_minimizer("ssn", {{name, bad}});
      ADD_FAILURE() << name << " = " << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << "the message names the field: " << e.what();
    }
  }
  MinimizerOptions oi;
  oi.tolerance = 0.0;
  EXPECT_THROW(m.minimize(p, Eigen::VectorXd(), oi), InputError);
  const auto ok = make_minimizer(
      "ssn", {{"armijo", 1e-3}, {"backtrack", 0.3}, {"max_backtracks", 50}, {"active_scale", 0.5}, {"shift", 1e-6}});
  EXPECT_TRUE(ok->minimize(p, Eigen::VectorXd(), MinimizerOptions{}).converged());
}

}  // namespace

// Started next to the solution, as a step of a loading path is: Example 4.1 with Tresca friction
// and a traction (3, -8), from the solution moved by 1e-6 to 1e-9 of its size in random
// directions. Near the solution the energy changes by less than its round-off, where Armijo's
// comparison of F is noise; every run must still reach the certificate (a step there is taken
// on the decrease of the residual). The path that showed the failure this guards against (ssn
// cycling between active sets until it stalled, two steps in a 1000-step Coulomb path on
// 256 x 256 squares) is measured in docs/paths.md.
TEST(Ssn, AStartNextToTheSolutionReachesTheCertificate) {
  auto ex = example("squares", 32, [](ContactProblem& p) {
    p.parts[0].friction = tresca_law(0.8);
    for (auto& t : p.elasticity.tractions) t.traction = [](const Vec2&) { return Vec2(3.0, -8.0); };
  });
  const ReducedProblem& p = ex->condensation->reduced();
  MinimizerOptions o;
  o.tolerance = 1e-10;
  const MinimizerResult cold = SsnMinimizer().minimize(p, Eigen::VectorXd(), o);
  ASSERT_TRUE(cold.converged()) << cold.message;
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double size = cold.a.cwiseAbs().maxCoeff();
  for (int run = 0; run < 40; ++run) {
    SCOPED_TRACE("run " + std::to_string(run));
    Eigen::VectorXd start = cold.a;
    for (Eigen::Index i = 0; i < start.size(); ++i) start(i) += std::pow(10.0, -6.0 - run % 4) * size * u(gen);
    o.check_existence = false;
    const MinimizerResult warm = SsnMinimizer().minimize(p, start, o);
    EXPECT_TRUE(warm.converged()) << to_string(warm.status) << ": " << warm.message;
    EXPECT_LE((warm.a - cold.a).cwiseAbs().maxCoeff(), 1e-8 * size);
  }
}

// One engine instance keeps the last Newton system's factor for the next system with the same
// matrix (a path's steps): its results are those of a fresh instance bit for bit, on the same
// matrix with another load (where the factor is reused) and on a matrix that differs.
TEST(Ssn, KeptFactorGivesTheFreshResultBitForBit) {
  // a spring j = k a^2 / 2 without kinks: every coordinate is free, the system S + k W each time
  const auto spring = std::make_shared<PiecewisePolynomialLaw>("spring", std::vector<double>{},
                                                               std::vector<Polynomial>{{0.0, 0.0, 500.0}},
                                                               std::vector<Polynomial>{{0.0}});
  const ReducedProblem p = random_problem(60, spring, ConstraintKind::none, 2);
  ReducedProblem other_load = p, other_matrix = p;
  other_load.c *= -1.5;
  other_matrix.S *= 1.001;
  const SsnMinimizer kept;
  for (const ReducedProblem* r : std::vector<const ReducedProblem*>{&p, &other_load, &other_matrix, &p}) {
    const MinimizerResult fresh = SsnMinimizer().minimize(*r, Eigen::VectorXd(), MinimizerOptions{});
    const MinimizerResult again = kept.minimize(*r, Eigen::VectorXd(), MinimizerOptions{});
    ASSERT_TRUE(fresh.converged()) << fresh.message;
    EXPECT_EQ(again.message, fresh.message);
    EXPECT_TRUE(again.a == fresh.a) << "max difference " << (again.a - fresh.a).cwiseAbs().maxCoeff();
  }
}
