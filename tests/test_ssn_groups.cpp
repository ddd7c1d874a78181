// The engine "ssn" on groups of coordinates (ReducedProblem::groups: a law of a pair's norm, a
// solid's isotropic friction): Tresca springs against their closed form, a solid's frictional
// contact under Tresca's law against an independent proximal-gradient solution, stuck and
// slipping groups together, exact landing on 0, slip-weakening (nonconvex) friction, a law
// with a kink at a positive radius, and the iteration count of the Newton steps.
#include <hemivem/certificate.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/ssn_minimizer.hpp>
#include <hemivem/uniqueness.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

constexpr double bound = 0.7;  // Tresca's bound on the springs

Eigen::VectorXd random_start(Eigen::Index n, double size, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd a(n);
  for (Eigen::Index i = 0; i < n; ++i) a(i) = size * unit(gen);
  return a;
}

MinimizerResult ssn(const ReducedProblem& p, const Eigen::VectorXd& start = {}, double tolerance = 1e-12) {
  MinimizerOptions o;
  o.tolerance = tolerance;
  return SsnMinimizer().minimize(p, start, o);
}

double relative_error(const Eigen::VectorXd& a, const Eigen::VectorXd& exact) {
  const double scale = exact.cwiseAbs().maxCoeff();
  const double error = (a - exact).cwiseAbs().maxCoeff();
  return scale > 0.0 ? error / scale : error;
}

// The frictional solid of test_support with linear springs (stiffness k per unit weight, k = 0:
// the one-sided bound only) on the normals and Tresca's law of bound g on the groups, solved
// without the engine: proximal gradient on F = f + h, f = 1/2 a^T (S + diag(w k on the normals))
// a - c^T a smooth, h = sum_G w g |a_G| + the bounds a_i <= g_i, whose prox is exact (block
// soft-thresholding of each group, the clamp of each normal). Step 1/L, L = lambda_max of f's
// Hessian; run until the step vanishes in round-off.
Eigen::VectorXd proximal_gradient(const ReducedProblem& p, int nodes, double k, double g) {
  Eigen::MatrixXd H = p.S;
  for (int i = 0; i < nodes; ++i) H(i, i) += k * p.w(i);
  const double L = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  Eigen::VectorXd a = Eigen::VectorXd::Zero(p.size());
  for (int it = 0; it < 100000; ++it) {
    Eigen::VectorXd x = a - (H * a - p.c) / L;
    for (int i = 0; i < nodes; ++i) x(i) = std::min(x(i), p.hi(i));
    for (const CoordinateGroup& grp : p.groups) {
      const double m = group_norm(x, grp), threshold = p.w(grp.first) * g / L;
      const double factor = m > threshold ? 1.0 - threshold / m : 0.0;
      x(grp.first) *= factor;
      x(grp.second) *= factor;
    }
    const double step = (x - a).cwiseAbs().maxCoeff();
    a.swap(x);
    if (step <= 1e-17 * std::max(1.0, a.cwiseAbs().maxCoeff())) break;
  }
  return a;
}

// j' = 0.5 on (0, 0.01) and 1.5 beyond (even): convex, with a kink at the radius 0.01.
std::shared_ptr<const ContactLaw> two_slope_law() {
  return std::make_shared<PiecewisePolynomialLaw>(PiecewisePolynomialLaw::from_j(
      "two-slope", {-0.01, 0.0, 0.01}, {{-0.01, -1.5}, {0.0, -0.5}, {0.0, 0.5}, {-0.01, 1.5}}));
}

}  // namespace

TEST(SsnGroups, TakesGroups) {
  EXPECT_TRUE(SsnMinimizer().takes_groups());
  EXPECT_NO_THROW(ssn(test::tresca_springs(2, bound, 1)));
}

TEST(SsnGroups, TrescaSpringsMatchTheirClosedForm) {
  for (const unsigned seed : {1u, 2u, 3u})
    for (const int groups : {1, 7, 60})
      for (const bool from_zero : {true, false}) {
        SCOPED_TRACE(testing::Message() << "seed " << seed << ", " << groups << " groups, start "
                                        << (from_zero ? "0" : "random"));
        const ReducedProblem p = test::tresca_springs(groups, bound, seed);
        const Eigen::VectorXd exact = test::tresca_springs_solution(p, bound);
        const MinimizerResult r = ssn(p, from_zero ? Eigen::VectorXd() : random_start(p.size(), 0.5, seed));
        ASSERT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
        EXPECT_TRUE(certificate(p, r.a, 1e-12).converged());
        EXPECT_LE(relative_error(r.a, exact), 1e-10);
        for (const CoordinateGroup& g : p.groups)
          if (group_norm(exact, g) == 0.0) EXPECT_EQ(group_norm(r.a, g), 0.0) << "a stuck group is exactly 0";
      }
}

TEST(SsnGroups, FewNewtonIterationsOnTheSprings) {
  // from a random start every group must find its state (stuck groups travel to 0, slipping
  // ones turn onto the direction of their load); Newton's steps on the norm do it in a few
  // iterations, a step with a wrong curvature would converge linearly at best
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    const ReducedProblem p = test::tresca_springs(40, bound, seed);
    const MinimizerResult r = ssn(p, random_start(p.size(), 0.5, seed + 10));
    ASSERT_TRUE(r.converged()) << "seed " << seed << ": " << r.message;
    EXPECT_LE(r.iterations, 10) << "seed " << seed << ": " << r.message;
    EXPECT_LE(relative_error(r.a, test::tresca_springs_solution(p, bound)), 1e-10) << "seed " << seed;
  }
}

TEST(SsnGroups, StuckGroupsLandExactlyOnZeroWithoutTheCertificatesSnap) {
  // at tolerance 1e-300 the certificate snaps nothing (its window is 1e-300 of the length
  // scale) and does not converge (round-off stays): the point returned is the engine's own
  for (const unsigned seed : {1u, 2u, 3u}) {
    const ReducedProblem p = test::tresca_springs(30, bound, seed);
    const Eigen::VectorXd exact = test::tresca_springs_solution(p, bound);
    const MinimizerResult r = ssn(p, random_start(p.size(), 0.5, seed), 1e-300);
    EXPECT_LE(relative_error(r.a, exact), 1e-12) << "seed " << seed;
    int stuck = 0;
    for (const CoordinateGroup& g : p.groups) {
      if (group_norm(exact, g) > 0.0) continue;
      ++stuck;
      EXPECT_EQ(r.a(g.first), 0.0) << "seed " << seed;
      EXPECT_EQ(r.a(g.second), 0.0) << "seed " << seed;
    }
    EXPECT_GT(stuck, 0) << "seed " << seed;
  }
}

TEST(SsnGroups, TrescaFrictionOnASolidIsTheUniqueSolution) {
  const double g = 1.0;
  for (const double k : {100.0, 0.0})  // linear springs on the normals; the one-sided bound only
    for (const int nodes : {4, 12, 30})
      for (const unsigned seed : {1u, 2u, 3u}) {
        SCOPED_TRACE(testing::Message() << "normal stiffness " << k << ", " << nodes << " nodes, seed " << seed);
        const ReducedProblem p = test::frictional_solid_problem(
            nodes, k > 0.0 ? linear_law(k) : zero_law(), tresca_law(g), seed);
        EXPECT_TRUE(measure_uniqueness(p).proves_uniqueness());
        for (const bool from_zero : {true, false}) {
          const MinimizerResult r = ssn(p, from_zero ? Eigen::VectorXd() : random_start(p.size(), 0.05, seed));
          ASSERT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
          EXPECT_LE(relative_error(r.a, proximal_gradient(p, nodes, k, g)), 1e-7);
        }
      }
}

TEST(SsnGroups, StuckAndSlippingGroupsTogether) {
  const double g = 1.5;  // loads of about 2 per coordinate: some groups stick, others slip
  for (const unsigned seed : {1u, 2u, 3u}) {
    const ReducedProblem p = test::frictional_solid_problem(12, linear_law(100.0), tresca_law(g), seed);
    const MinimizerResult r = ssn(p, random_start(p.size(), 0.05, seed));
    ASSERT_TRUE(r.converged()) << "seed " << seed << ": " << r.message;
    const Eigen::VectorXd force = p.c - p.S * r.a;  // the law force balances it
    int stuck = 0, slipping = 0;
    for (const CoordinateGroup& grp : p.groups) {
      const double w = p.w(grp.first), m = std::hypot(force(grp.first), force(grp.second));
      if (group_norm(r.a, grp) == 0.0) {
        ++stuck;
        EXPECT_LE(m, w * g * (1.0 + 1e-12)) << "seed " << seed << ": a stuck group's force is in the disc";
      } else {
        ++slipping;
        EXPECT_NEAR(m, w * g, 1e-10) << "seed " << seed << ": a slipping group's force is on the circle";
        // and along its slip
        const Eigen::Vector2d v(r.a(grp.first), r.a(grp.second)), f(force(grp.first), force(grp.second));
        EXPECT_NEAR(v.normalized().dot(f.normalized()), 1.0, 1e-10) << "seed " << seed;
      }
    }
    EXPECT_GT(stuck, 0) << "seed " << seed;
    EXPECT_GT(slipping, 0) << "seed " << seed;
  }
}

TEST(SsnGroups, SlipWeakeningFrictionGivesCertifiedCriticalPoints) {
  // two laws: a mild one (uniqueness margin still positive: one critical point, reached from
  // every start) and a strong one (margin negative: several critical points may exist)
  struct Case {
    double g_static, g_kinetic, slip;
    bool unique;
  };
  for (const Case c : {Case{1.0, 0.5, 0.01, true}, Case{1.5, 0.2, 0.005, false}})
    for (const int nodes : {5, 20})
      for (const unsigned seed : {1u, 2u, 3u}) {
        SCOPED_TRACE(testing::Message() << "slip-weakening " << c.g_static << " " << c.g_kinetic << " " << c.slip
                                        << ", " << nodes << " nodes, seed " << seed);
        const ReducedProblem p = test::frictional_solid_problem(
            nodes, linear_law(100.0), slip_weakening_law(c.g_static, c.g_kinetic, c.slip), seed);
        EXPECT_EQ(measure_uniqueness(p).proves_uniqueness(), c.unique);
        const MinimizerResult from_zero = ssn(p);
        const MinimizerResult from_random = ssn(p, random_start(p.size(), 0.05, seed));
        for (const MinimizerResult* r : {&from_zero, &from_random}) {
          EXPECT_TRUE(r->converged()) << to_string(r->status) << ": " << r->message;
          if (!r->converged()) continue;
          EXPECT_TRUE(certificate(p, r->a, 1e-12).converged());
          for (std::size_t k = 1; k < r->history.size(); ++k)
            EXPECT_LE(r->history[k].objective,
                      r->history[k - 1].objective + 1e-12 * std::abs(r->history[k - 1].objective))
                << "F does not increase beyond its round-off (README.md), step " << k;
        }
        if (c.unique && from_zero.converged() && from_random.converged())
          EXPECT_LE(relative_error(from_random.a, from_zero.a), 1e-9);
      }
}

TEST(SsnGroups, AKinkAtAPositiveRadiusHoldsGroupsOnItsCircle) {
  const double kink = 0.01;
  int on_circle = 0;
  for (const unsigned seed : {1u, 2u, 3u, 4u}) {
    const ReducedProblem p = test::frictional_solid_problem(20, linear_law(100.0), two_slope_law(), seed);
    EXPECT_TRUE(measure_uniqueness(p).proves_uniqueness()) << "seed " << seed;
    const MinimizerResult from_zero = ssn(p);
    const MinimizerResult from_random = ssn(p, random_start(p.size(), 0.1, seed));
    ASSERT_TRUE(from_zero.converged()) << "seed " << seed << ": " << from_zero.message;
    ASSERT_TRUE(from_random.converged()) << "seed " << seed << ": " << from_random.message;
    EXPECT_LE(relative_error(from_random.a, from_zero.a), 1e-9) << "seed " << seed;
    for (const CoordinateGroup& g : p.groups) on_circle += group_norm(from_random.a, g) == kink ? 1 : 0;
  }
  EXPECT_GT(on_circle, 0) << "no group held on the kink's circle";
}
