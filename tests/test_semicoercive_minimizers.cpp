// Reduced problems whose S is only positive semidefinite (a body whose rigid motion is left
// free by its supports and held by its contact only): every engine reaches the certificate
// when a minimizer exists, and says at once that there is no solution when the load pushes
// the body away from its support (hemivem/existence.hpp).
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/existence.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

using namespace hemivem;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double k_spring = 50.0;
constexpr double k_foundation = 20.0;

/// k times the graph Laplacian of a chain of n nodes: null space the constants.
Eigen::MatrixXd chain_laplacian(int n, double k) {
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i + 1 < n; ++i) {
    S(i, i) += k;
    S(i + 1, i + 1) += k;
    S(i, i + 1) -= k;
    S(i + 1, i) -= k;
  }
  return S;
}

/// k D^T D with D the second differences of n nodes (a beam's bending): null space the
/// affine functions of the node number (a translation and a rotation).
Eigen::MatrixXd bending(int n, double k) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n - 2, n);
  for (int i = 0; i + 2 < n; ++i) D(i, i) = 1.0, D(i, i + 1) = -2.0, D(i, i + 2) = 1.0;
  return k * D.transpose() * D;
}

/// j = k_f (r^+)^2 / 2: a linear foundation that resists penetration (r > 0) only.
std::shared_ptr<const ContactLaw> foundation() {
  return std::make_shared<PiecewisePolynomialLaw>(
      PiecewisePolynomialLaw::from_j("foundation", {0.0}, {{0.0}, {0.0, 0.0, 0.5 * k_foundation}}));
}

Eigen::VectorXd weights(int n) {
  Eigen::VectorXd w(n);
  for (int i = 0; i < n; ++i) w(i) = (i == 0 || i == n - 1) ? 0.5 : 1.0;
  return w;
}

MinimizerOptions options() {
  MinimizerOptions o;
  o.tolerance = 1e-10;
  return o;
}

/// Every built engine and the global search over them.
std::vector<std::pair<std::string, std::shared_ptr<const NonsmoothMinimizer>>> engines() {
  std::vector<std::pair<std::string, std::shared_ptr<const NonsmoothMinimizer>>> out;
  for (const auto& name : available_minimizers()) out.emplace_back(name, make_minimizer(name));
  out.emplace_back("global", make_global_search("ssn"));
  return out;
}

/// sum_i c_i = sum_i (w_i j'(a_i) + lambda_i): S's null vector 1 balances the forces.
void expect_balance(const ReducedProblem& p, const MinimizerResult& r, const std::string& who) {
  const double total = p.c.sum(), contact = (r.law_force + r.reaction).sum();
  EXPECT_NEAR(contact, total, 1e-8 * p.c.cwiseAbs().sum()) << who;
}

TEST(SemicoerciveExistence, AsymptoticSlopesOfTheShippedLaws) {
  EXPECT_EQ(asymptotic_slope(*foundation(), +1), kInf);
  EXPECT_EQ(asymptotic_slope(*foundation(), -1), 0.0);
  EXPECT_EQ(asymptotic_slope(*linear_law(3.0), -1), -kInf);
  EXPECT_EQ(asymptotic_slope(*zero_law(), +1), 0.0);
  EXPECT_DOUBLE_EQ(asymptotic_slope(*tresca_law(0.25), +1), 0.25);
  EXPECT_DOUBLE_EQ(asymptotic_slope(*tresca_law(0.25), -1), -0.25);
  EXPECT_DOUBLE_EQ(asymptotic_slope(*slip_weakening_law(0.1, 0.05, 0.01), +1), 0.05);
}

TEST(SemicoerciveExistence, NullSpacesOfTheChainAndTheBeam) {
  const Eigen::MatrixXd N1 = null_space(chain_laplacian(20, k_spring));
  ASSERT_EQ(N1.cols(), 1);
  EXPECT_NEAR(std::abs(N1.col(0).sum()), std::sqrt(20.0), 1e-10);
  EXPECT_EQ(null_space(bending(20, k_spring)).cols(), 2);
  EXPECT_EQ(null_space(Eigen::MatrixXd::Identity(5, 5)).cols(), 0);
  // a definite S: no null space, bounded whatever the load
  const ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd::Identity(4, 4), -Eigen::VectorXd::Ones(4),
                                                   Eigen::VectorXd::Ones(4), zero_law(), ConstraintKind::none);
  const Existence e = check_existence(p);
  EXPECT_TRUE(e.bounded && e.coercive);
  EXPECT_EQ(e.null_dimension, 0);
}

// (a) a chain on a foundation, pushed into it: a_i = c_i / (w_i k_f) for a uniform load
TEST(Semicoercive, ChainOnAFoundationSettlesByTheLoadOverTheFoundationStiffness) {
  for (int n : {10, 30, 50}) {
    const Eigen::VectorXd w = weights(n);
    const Eigen::VectorXd c = 0.3 * w;  // a uniform pressure
    const ReducedProblem p = ReducedProblem::uniform(chain_laplacian(n, k_spring), c, w, foundation(), ConstraintKind::none);
    const Existence e = check_existence(p);
    EXPECT_TRUE(e.bounded && e.coercive) << n;
    EXPECT_EQ(e.null_dimension, 1);
    for (const auto& [name, engine] : engines()) {
      const std::string who = name + " n=" + std::to_string(n);
      const MinimizerResult r = engine->minimize(p, {}, options());
      ASSERT_TRUE(r.converged()) << who << ": " << r.message;
      EXPECT_LE((r.a - Eigen::VectorXd::Constant(n, 0.3 / k_foundation)).lpNorm<Eigen::Infinity>(), 1e-8 * 0.3 / k_foundation)
          << who;
      expect_balance(p, r, who);
    }
  }
}

// (a') a load that varies along the chain (some nodes pulled, the total pushing in)
TEST(Semicoercive, ChainOnAFoundationUnderAVaryingLoadBalancesIt) {
  const int n = 40;
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) c(i) = 0.2 + 0.5 * std::sin(0.7 * i);
  ASSERT_GT(c.sum(), 0.0);
  const ReducedProblem p = ReducedProblem::uniform(chain_laplacian(n, k_spring), c, weights(n), foundation(), ConstraintKind::none);
  EXPECT_TRUE(check_existence(p).bounded);
  Eigen::VectorXd reference;
  for (const auto& [name, engine] : engines()) {
    const MinimizerResult r = engine->minimize(p, {}, options());
    ASSERT_TRUE(r.converged()) << name << ": " << r.message;
    expect_balance(p, r, name);
    if (reference.size() == 0) reference = r.a;  // F is strictly convex here: one minimizer
    EXPECT_LE((r.a - reference).lpNorm<Eigen::Infinity>(), 1e-7 * reference.lpNorm<Eigen::Infinity>()) << name;
  }
}

// (a'') from starts lifted off the foundation (where the Newton matrix is S alone: singular)
// and from one pressed 70 times deeper than the solution
TEST(Semicoercive, ChainOnAFoundationFromLiftedStarts) {
  const int n = 30;
  const Eigen::VectorXd w = weights(n);
  const ReducedProblem p = ReducedProblem::uniform(chain_laplacian(n, k_spring), 0.3 * w, w, foundation(), ConstraintKind::none);
  Eigen::VectorXd tilted(n);
  for (int i = 0; i < n; ++i) tilted(i) = -0.05 + 0.002 * i;
  for (const Eigen::VectorXd& start : {Eigen::VectorXd(Eigen::VectorXd::Constant(n, -0.05)), tilted,
                                       Eigen::VectorXd(Eigen::VectorXd::Constant(n, 1.0))}) {
    for (const auto& [name, engine] : engines()) {
      const MinimizerResult r = engine->minimize(p, start, options());
      ASSERT_TRUE(r.converged()) << name << " from " << start(0) << ": " << r.message;
      EXPECT_LE((r.a - Eigen::VectorXd::Constant(n, 0.3 / k_foundation)).lpNorm<Eigen::Infinity>(), 1e-8 * 0.3 / k_foundation)
          << name;
    }
  }
}

// the global search's starts stay at the scale of the problem where S^-1 c does not exist
TEST(Semicoercive, TheGlobalSearchStartsAtTheScaleOfTheProblem) {
  const int n = 30;
  const Eigen::VectorXd w = weights(n);
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) c(i) = 0.2 + 0.5 * std::sin(0.7 * i);
  const ReducedProblem p = ReducedProblem::uniform(chain_laplacian(n, k_spring), c, w, foundation(), ConstraintKind::none);
  // |S^+ c| <= |c| / lambda_2(S) (lambda_2 = 4 k sin^2(pi / 2n) of the chain) and the random
  // starts lie in a box a few times larger
  const double lambda2 = 4.0 * k_spring * std::pow(std::sin(M_PI / (2.0 * n)), 2);
  const double scale = c.norm() / lambda2;
  const auto starts = make_global_search("ssn")->starts(p, {});
  ASSERT_GE(starts.size(), 2u);
  for (const SearchStart& s : starts) {
    ASSERT_TRUE(s.a.allFinite()) << s.name;
    EXPECT_LE(s.a.lpNorm<Eigen::Infinity>(), 4.0 * scale) << s.name;
  }
  EXPECT_EQ(starts[1].name, "quadratic minimizer");
  // S^+ c: orthogonal to the null space, S a = c minus its mean
  const Eigen::VectorXd& q = starts[1].a;
  EXPECT_NEAR(q.sum(), 0.0, 1e-10 * scale);
  EXPECT_LE((p.S * q - (c.array() - c.mean()).matrix()).lpNorm<Eigen::Infinity>(), 1e-10 * c.lpNorm<Eigen::Infinity>());
}

// (b) a chain pushed towards a unilateral constraint a <= g, no law: it comes to rest on it
TEST(Semicoercive, ChainPushedAgainstAGapRestsOnIt) {
  for (int n : {10, 30, 50}) {
    const Eigen::VectorXd w = weights(n);
    const Eigen::VectorXd g = Eigen::VectorXd::Constant(n, 0.01);
    const ReducedProblem p =
        ReducedProblem::uniform(chain_laplacian(n, k_spring), 0.3 * w, w, zero_law(), ConstraintKind::one_sided, g);
    EXPECT_TRUE(check_existence(p).bounded);
    for (const auto& [name, engine] : engines()) {
      const std::string who = name + " n=" + std::to_string(n);
      const MinimizerResult r = engine->minimize(p, {}, options());
      ASSERT_TRUE(r.converged()) << who << ": " << r.message;
      EXPECT_LE((r.a - g).lpNorm<Eigen::Infinity>(), 1e-10 * 0.01) << who;
      EXPECT_LE((r.reaction - 0.3 * w).lpNorm<Eigen::Infinity>(), 1e-8 * 0.3) << who;
    }
  }
}

// (c) a load that pulls the chain off its foundation or away from the gap: no solution, said at once
TEST(Semicoercive, ALoadPullingTheBodyAwayIsReportedUnbounded) {
  const int n = 20;
  const Eigen::VectorXd w = weights(n);
  const ReducedProblem on_foundation =
      ReducedProblem::uniform(chain_laplacian(n, k_spring), -0.3 * w, w, foundation(), ConstraintKind::none);
  const ReducedProblem at_gap = ReducedProblem::uniform(chain_laplacian(n, k_spring), -0.3 * w, w, zero_law(),
                                                        ConstraintKind::one_sided, Eigen::VectorXd::Constant(n, 0.01));
  for (const ReducedProblem* p : {&on_foundation, &at_gap}) {
    const Existence e = check_existence(*p);
    ASSERT_FALSE(e.bounded);
    EXPECT_FALSE(e.coercive);
    // the direction is the rigid motion away from the support, -1 scaled to ||d||_inf = 1
    EXPECT_LE((e.direction + Eigen::VectorXd::Ones(n)).lpNorm<Eigen::Infinity>(), 1e-10);
    EXPECT_NEAR(e.slope, -0.3 * w.sum(), 1e-10);
    for (const auto& [name, engine] : engines()) {
      const MinimizerResult r = engine->minimize(*p, {}, options());
      EXPECT_EQ(r.status, MinimizerStatus::unbounded) << name << ": " << r.message;
      EXPECT_EQ(r.iterations, 0) << name;
      EXPECT_NE(r.message.find("unbounded below"), std::string::npos) << r.message;
      EXPECT_NE(r.message.find("there is no solution"), std::string::npos) << r.message;
    }
  }
  EXPECT_EQ(to_string(MinimizerStatus::unbounded), "unbounded");
  EXPECT_EQ(minimizer_status_from_string("Unbounded"), MinimizerStatus::unbounded);
}

// a law of linear growth (Tresca friction on a free sliding motion): it stops the motion while
// the load is below the friction bound, and cannot when it is above
TEST(Semicoercive, ChainHeldByFrictionSticksBelowTheBoundAndSlidesAwayAbove) {
  const int n = 20;
  const Eigen::VectorXd w = weights(n);
  Eigen::VectorXd start(n);
  for (int i = 0; i < n; ++i) start(i) = 0.01 * std::cos(0.5 * i);
  const ReducedProblem sticks = ReducedProblem::uniform(chain_laplacian(n, k_spring), 0.1 * w, w, tresca_law(0.25),
                                                        ConstraintKind::none);
  EXPECT_TRUE(check_existence(sticks).coercive);
  for (const auto& [name, engine] : engines()) {
    const MinimizerResult r = engine->minimize(sticks, start, options());
    ASSERT_TRUE(r.converged()) << name << ": " << r.message;
    EXPECT_EQ(r.a.lpNorm<Eigen::Infinity>(), 0.0) << name;  // every node on the kink: stuck
    EXPECT_LE((r.law_force - 0.1 * w).lpNorm<Eigen::Infinity>(), 1e-8) << name;
  }
  const ReducedProblem slides = ReducedProblem::uniform(chain_laplacian(n, k_spring), 0.3 * w, w, tresca_law(0.25),
                                                        ConstraintKind::none);
  const Existence e = check_existence(slides);
  ASSERT_FALSE(e.bounded);
  EXPECT_LE((e.direction - Eigen::VectorXd::Ones(n)).lpNorm<Eigen::Infinity>(), 1e-10);
  EXPECT_NEAR(e.slope, -(0.3 - 0.25) * w.sum(), 1e-10);
  for (const auto& [name, engine] : engines())
    EXPECT_EQ(engine->minimize(slides, start, options()).status, MinimizerStatus::unbounded) << name;
}

// (d) a rank-2 null space (translation and rotation of a beam on a foundation)
TEST(Semicoercive, BeamOnAFoundationWithARankTwoNullSpace) {
  const int n = 20;
  const Eigen::VectorXd w = weights(n);
  const ReducedProblem level = ReducedProblem::uniform(bending(n, k_spring), 0.3 * w, w, foundation(), ConstraintKind::none);
  const Existence e = check_existence(level);
  EXPECT_TRUE(e.bounded && e.coercive);
  EXPECT_EQ(e.null_dimension, 2);
  for (const auto& [name, engine] : engines()) {
    const MinimizerResult r = engine->minimize(level, {}, options());
    ASSERT_TRUE(r.converged()) << name << ": " << r.message;
    EXPECT_LE((r.a - Eigen::VectorXd::Constant(n, 0.3 / k_foundation)).lpNorm<Eigen::Infinity>(), 1e-8 * 0.3 / k_foundation)
        << name;
    expect_balance(level, r, name);
  }
  // pushed down in total but with a moment that lifts the right end off the foundation: the
  // beam tips over about its left end
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) c(i) = i < n / 2 ? 3.0 : -1.0;
  ASSERT_GT(c.sum(), 0.0);
  const ReducedProblem tipping = ReducedProblem::uniform(bending(n, k_spring), c, w, foundation(), ConstraintKind::none);
  const Existence t = check_existence(tipping);
  ASSERT_FALSE(t.bounded);
  // the rotation about node 0: d_i = -i / (n - 1), up to round-off in the null basis
  for (int i = 0; i < n; ++i) EXPECT_NEAR(t.direction(i), -i / double(n - 1), 1e-9) << i;
  for (const auto& [name, engine] : engines()) {
    const MinimizerResult r = engine->minimize(tipping, {}, options());
    EXPECT_EQ(r.status, MinimizerStatus::unbounded) << name << ": " << r.message;
  }
  // a moment the foundation can carry (c symmetric about the middle): bounded, solved
  for (int i = 0; i < n; ++i) c(i) = 1.0 + 0.5 * std::cos(2.0 * M_PI * i / (n - 1));
  const ReducedProblem carried = ReducedProblem::uniform(bending(n, k_spring), c, w, foundation(), ConstraintKind::none);
  EXPECT_TRUE(check_existence(carried).bounded);
  for (const auto& [name, engine] : engines()) {
    const MinimizerResult r = engine->minimize(carried, {}, options());
    ASSERT_TRUE(r.converged()) << name << ": " << r.message;
    expect_balance(carried, r, name);
  }
}

// a null direction on which nothing acts (c . d = 0, no law) is bounded but not coercive
TEST(SemicoerciveExistence, AFreeMotionThatCostsNothingIsBoundedNotCoercive) {
  const int n = 10;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
  c(0) = 1.0, c(n - 1) = -1.0;
  const ReducedProblem p = ReducedProblem::uniform(chain_laplacian(n, k_spring), c, weights(n), zero_law(), ConstraintKind::none);
  const Existence e = check_existence(p);
  EXPECT_TRUE(e.bounded);
  EXPECT_FALSE(e.coercive);
  EXPECT_EQ(e.direction.size(), 0);
}

}  // namespace
