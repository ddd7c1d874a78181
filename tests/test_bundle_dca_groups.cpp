// The bundle-dca engine on groups of coordinates (ReducedProblem::groups: a law of a pair's
// norm, a solid's isotropic friction): Tresca springs against their closed form, a convex
// frictional solid against an independent proximal-gradient solution (its uniqueness margin is
// positive, so that is THE solution), and slip-weakening friction, certified when converged.
#include <hemivem/bundle_dca_minimizer.hpp>
#include <hemivem/certificate.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/uniqueness.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "test_support.hpp"

using namespace hemivem;

namespace {

// The minimizer of F for a frictional solid problem with the linear normal law j = k r^2 / 2
// (one-sided bounds a_i <= g_i) and Tresca friction of bound g on the groups, by the proximal
// gradient method with step 1 / lambda_max(S): the exact prox of t w k r^2 / 2 on (-inf, g_i]
// (scale, then clamp) per normal coordinate and of t w g |v| (block soft-thresholding) per
// group, run until the iterates stop moving.
Eigen::VectorXd proximal_gradient(const ReducedProblem& p, double k, double g) {
  const double L = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p.S).eigenvalues().maxCoeff();
  const double t = 1.0 / L;
  const Eigen::VectorXi group_of = p.group_of();
  Eigen::VectorXd a = Eigen::VectorXd::Zero(p.size());
  for (int it = 0; it < 200000; ++it) {
    const Eigen::VectorXd u = a - t * (p.S * a - p.c);
    Eigen::VectorXd next(p.size());
    for (Eigen::Index i = 0; i < p.size(); ++i)
      if (group_of(i) < 0) next(i) = std::min(u(i) / (1.0 + t * p.w(i) * k), p.upper(i));
    for (const CoordinateGroup& G : p.groups) {
      const Eigen::Vector2d v(u(G.first), u(G.second));
      const double m = v.norm(), threshold = t * p.w(G.first) * g;
      const Eigen::Vector2d x = m <= threshold ? Eigen::Vector2d::Zero() : Eigen::Vector2d(v * (1.0 - threshold / m));
      next(G.first) = x(0);
      next(G.second) = x(1);
    }
    const double change = (next - a).cwiseAbs().maxCoeff();
    a = next;
    if (change <= 1e-18 * std::max(1.0, a.cwiseAbs().maxCoeff()) && it > 10) break;
  }
  return a;
}

}  // namespace

TEST(BundleDcaGroups, TakesGroups) {
  EXPECT_TRUE(BundleDcaMinimizer().takes_groups());
  EXPECT_TRUE(make_minimizer("bundle-dca")->takes_groups());
}

TEST(BundleDcaGroups, TrescaSpringsMatchTheirClosedFormWithStuckGroupsExactlyAtZero) {
  const double bound = 0.5;
  int stuck = 0, slipping = 0;
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const ReducedProblem p = test::tresca_springs(10, bound, seed);
    const Eigen::VectorXd exact = test::tresca_springs_solution(p, bound);
    const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_TRUE(certify(p, r.a, MinimizerOptions{}.tolerance).certificate.converged());
    EXPECT_LE((r.a - exact).cwiseAbs().maxCoeff(), 1e-9 * exact.cwiseAbs().maxCoeff()) << r.message;
    for (const CoordinateGroup& g : p.groups) {
      if (group_norm(exact, g) == 0.0) {
        ++stuck;
        EXPECT_EQ(r.a(g.first), 0.0);
        EXPECT_EQ(r.a(g.second), 0.0);
      } else {
        ++slipping;
      }
    }
  }
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slipping, 0);
}

TEST(BundleDcaGroups, ConvexFrictionalSolidIsTheProximalGradientSolution) {
  const double k = 100.0, g = 1.0;
  int stuck = 0, slipping = 0;
  for (unsigned seed : {11u, 12u, 13u}) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    ReducedProblem p = test::frictional_solid_problem(6, linear_law(k), tresca_law(g), seed);
    set_uniqueness_margin(p);
    ASSERT_GT(p.uniqueness_margin, 0.0) << "the test needs a problem with one critical point";
    const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_FALSE(r.may_be_nonunique);
    const Eigen::VectorXd reference = proximal_gradient(p, k, g);
    ASSERT_TRUE(certify(p, reference, 1e-10).certificate.converged()) << "the reference did not converge";
    EXPECT_LE((r.a - reference).cwiseAbs().maxCoeff(), 1e-7 * reference.cwiseAbs().maxCoeff()) << r.message;
    for (const CoordinateGroup& G : p.groups) {
      if (group_norm(reference, G) == 0.0) {
        ++stuck;
        EXPECT_EQ(group_norm(r.a, G), 0.0);
      } else {
        ++slipping;
      }
    }
  }
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slipping, 0);
}

TEST(BundleDcaGroups, SlipWeakeningFrictionConvergesToCertifiedCriticalPoints) {
  int converged = 0;
  for (unsigned seed : {21u, 22u, 23u, 24u}) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const ReducedProblem p =
        test::frictional_solid_problem(6, linear_law(100.0), slip_weakening_law(1.0, 0.5, 0.01), seed);
    const MinimizerOptions o;
    const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_LE(r.objective, p.energy(Eigen::VectorXd::Zero(p.size())) + 1e-15) << r.message;
    if (!r.converged()) continue;
    ++converged;
    const CertifiedPoint cp = certify(p, r.a, o.tolerance);
    EXPECT_TRUE(cp.certificate.converged()) << cp.certificate.primal << " " << cp.certificate.dual;
    EXPECT_EQ(cp.a, r.a) << "the point returned is the certified (snapped) one";
    EXPECT_DOUBLE_EQ(r.objective, p.energy(r.a));
  }
  EXPECT_GT(converged, 0) << "no run converged";
}
