// The smoothing-based engines nlopt-mma and ceres-active-set on problems with groups of
// coordinates (a solid's isotropic friction: a law of the norm of a node's tangential pair).
#include <hemivem/certificate.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/uniqueness.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "test_support.hpp"

using namespace hemivem;

namespace {

bool built(const std::string& name) {
  const auto names = available_minimizers();
  return std::find(names.begin(), names.end(), name) != names.end();
}

class SmoothEngineGroups : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (!built(GetParam())) GTEST_SKIP() << GetParam() << " not built";
  }
  std::unique_ptr<NonsmoothMinimizer> engine() const { return make_minimizer(GetParam(), {}); }
};

TEST_P(SmoothEngineGroups, TakesGroups) { EXPECT_TRUE(engine()->takes_groups()); }

// Uncoupled groups on springs under Tresca friction: the closed form, stuck groups exactly at 0.
TEST_P(SmoothEngineGroups, TrescaSpringsMatchTheirClosedForm) {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const double bound = 1.0;
    const ReducedProblem p = test::tresca_springs(12, bound, seed);
    const Eigen::VectorXd exact = test::tresca_springs_solution(p, bound);
    const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    ASSERT_TRUE(r.converged()) << "seed " << seed << ": " << r.message;
    const double scale = std::max(exact.cwiseAbs().maxCoeff(), p.c.cwiseAbs().maxCoeff() / p.S.diagonal().minCoeff());
    EXPECT_LE((r.a - exact).cwiseAbs().maxCoeff(), 1e-9 * scale) << "seed " << seed;
    int stuck = 0, slipping = 0;
    for (const CoordinateGroup& g : p.groups) {
      if (exact(g.first) == 0.0 && exact(g.second) == 0.0) {
        ++stuck;
        EXPECT_EQ(r.a(g.first), 0.0) << "seed " << seed;
        EXPECT_EQ(r.a(g.second), 0.0) << "seed " << seed;
      } else {
        ++slipping;
      }
    }
    EXPECT_GT(stuck, 0) << "seed " << seed;
    EXPECT_GT(slipping, 0) << "seed " << seed;
  }
}

// A convex law of a solid's contact node, with the proximal map of t w j (plus the bound for a
// normal coordinate) written out independently of the engines.
struct ConvexLaw {
  std::string name;
  std::shared_ptr<const ContactLaw> law;
  // prox of t w j on a normal coordinate (then clipped to its upper bound by the caller)
  std::function<double(double y, double tw)> prox;
  // the radius of the prox of t w j(|v|) at a pair of norm rho
  std::function<double(double rho, double tw)> prox_radius;
};

ConvexLaw linear(double k) {
  return {"linear", linear_law(k), [k](double y, double tw) { return y / (1.0 + tw * k); },
          [k](double rho, double tw) { return rho / (1.0 + tw * k); }};
}
// j = 0 for r <= 0, sigma r + k r^2 / 2 for r > 0: not even (its smoothing at 0 is not symmetric)
ConvexLaw kinked(double sigma, double k) {
  return {"kinked", kinked_law(sigma, k),
          [sigma, k](double y, double tw) {
            if (y <= 0.0) return y;
            return y <= tw * sigma ? 0.0 : (y - tw * sigma) / (1.0 + tw * k);
          },
          [sigma, k](double rho, double tw) { return std::max(0.0, rho - tw * sigma) / (1.0 + tw * k); }};
}
ConvexLaw tresca(double bound) {
  return {"tresca", tresca_law(bound),
          [bound](double y, double tw) { return std::copysign(std::max(0.0, std::abs(y) - tw * bound), y); },
          [bound](double rho, double tw) { return std::max(0.0, rho - tw * bound); }};
}

// The minimizer of the strongly convex F by the proximal gradient method with step 1 / ||S||:
// the exact prox of each coordinate's law with its bound, of each group's law of the norm
// (block soft-thresholding for Tresca), iterated until the step stops changing the point.
Eigen::VectorXd proximal_gradient(const ReducedProblem& p, const ConvexLaw& normal, const ConvexLaw& friction,
                                  double* fixed_point_residual) {
  const double t = 1.0 / Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p.S).eigenvalues().maxCoeff();
  const Eigen::VectorXi group_of = p.group_of();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p.size());
  auto step = [&](const Eigen::VectorXd& a) {
    const Eigen::VectorXd y = a - t * (p.S * a - p.c);
    Eigen::VectorXd next = y;
    for (Eigen::Index i = 0; i < p.size(); ++i)
      if (group_of(i) < 0) next(i) = std::min(normal.prox(y(i), t * p.w(i)), p.upper(i));
    for (const CoordinateGroup& g : p.groups) {
      const double rho = std::hypot(y(g.first), y(g.second));
      const double radius = friction.prox_radius(rho, t * p.w(g.first));
      const double scale = rho > 0.0 ? radius / rho : 0.0;
      next(g.first) = scale * y(g.first);
      next(g.second) = scale * y(g.second);
    }
    return next;
  };
  for (int k = 0; k < 100000; ++k) {
    const Eigen::VectorXd next = step(x);
    const bool same = next == x;
    x = next;
    if (same) break;
  }
  *fixed_point_residual = (step(x) - x).cwiseAbs().maxCoeff();
  return x;
}

// A solid's frictional contact with convex laws has a positive uniqueness margin: the engine's
// certified point is THE solution, which the proximal gradient method computes independently.
TEST_P(SmoothEngineGroups, ConvexFrictionalSolidIsTheProximalGradientSolution) {
  struct Case {
    ConvexLaw normal, friction;
  };
  for (const Case& c : {Case{linear(100.0), tresca(1.0)}, Case{kinked(0.3, 100.0), tresca(1.0)},
                        Case{linear(100.0), kinked(1.0, 50.0)}})
    for (unsigned seed : {1u, 2u, 3u}) {
      const std::string what = c.normal.name + " / " + c.friction.name + " seed " + std::to_string(seed);
      const ReducedProblem p = test::frictional_solid_problem(8, c.normal.law, c.friction.law, seed);
      ASSERT_TRUE(measure_uniqueness(p).proves_uniqueness()) << what;
      double residual = 0.0;
      const Eigen::VectorXd exact = proximal_gradient(p, c.normal, c.friction, &residual);
      ASSERT_LE(residual, 1e-15 * exact.cwiseAbs().maxCoeff()) << what;
      ASSERT_TRUE(certificate(p, exact, 1e-12).converged()) << what;
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
      ASSERT_TRUE(r.converged()) << what << ": " << r.message;
      EXPECT_LE((r.a - exact).cwiseAbs().maxCoeff(), 1e-7 * exact.cwiseAbs().maxCoeff()) << what;
      int stuck = 0, slipping = 0;
      for (const CoordinateGroup& g : p.groups) {
        if (exact(g.first) == 0.0 && exact(g.second) == 0.0) {
          ++stuck;
          EXPECT_EQ(group_norm(r.a, g), 0.0) << what;
        } else {
          ++slipping;
        }
      }
      EXPECT_GT(stuck, 0) << what;
      EXPECT_GT(slipping, 0) << what;
    }
}

// Slip-weakening friction (nonconvex, several critical points possible): whenever an engine
// reports converged, its point satisfies the stationarity conditions checked here directly.
TEST_P(SmoothEngineGroups, SlipWeakeningConvergedPointsAreCritical) {
  const double gs = 1.0, gk = 0.4, k = 100.0;
  int converged = 0, runs = 0;
  for (double slip : {0.02, 0.004})
    for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
      const std::string what = "slip " + std::to_string(slip) + " seed " + std::to_string(seed);
      const ReducedProblem p = test::frictional_solid_problem(8, linear_law(k), slip_weakening_law(gs, gk, slip), seed);
      const MinimizerOptions o;
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
      ++runs;
      if (!r.converged()) continue;
      ++converged;
      ASSERT_TRUE(certificate(p, r.a, o.tolerance).converged()) << what;
      // the residual of each condition, relative to the largest force
      const Eigen::VectorXd force = p.c - p.S * r.a;
      const double scale = std::max(p.c.cwiseAbs().maxCoeff(), (p.S * r.a).cwiseAbs().maxCoeff());
      const double allowed = 10.0 * o.tolerance * scale;
      const int nodes = static_cast<int>(p.groups.size());
      for (int i = 0; i < nodes; ++i) {
        const double law_force = p.w(i) * k * r.a(i);
        if (r.a(i) < p.upper(i)) EXPECT_NEAR(force(i), law_force, allowed) << what << " node " << i;
        else EXPECT_GE(force(i) - law_force, -allowed) << what << " node " << i << " (reaction >= 0)";
      }
      for (const CoordinateGroup& g : p.groups) {
        const Eigen::Vector2d f(force(g.first), force(g.second));
        const double rho = group_norm(r.a, g), w = p.w(g.first);
        if (rho == 0.0) {
          EXPECT_LE(f.norm(), w * gs + allowed) << what << " stuck group " << g.first;
          continue;
        }
        const Eigen::Vector2d e = Eigen::Vector2d(r.a(g.first), r.a(g.second)) / rho;
        const double bound = rho >= slip ? gk : gs - (gs - gk) * rho / slip;
        EXPECT_LE((f - w * bound * e).norm(), allowed) << what << " slipping group " << g.first;
      }
    }
  EXPECT_GT(converged, runs / 2) << GetParam() << " converged on " << converged << " of " << runs;
}

INSTANTIATE_TEST_SUITE_P(Engines, SmoothEngineGroups, ::testing::Values("nlopt-mma", "ceres-active-set"),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (auto& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

}  // namespace
