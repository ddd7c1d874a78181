// The global search on problems with groups of coordinates (ReducedProblem::groups: a law of a
// pair's norm, a solid's friction): certified critical points lowest first under slip-weakening
// friction, one run for a convex problem whose uniqueness margin is positive, starts that put a
// group's norm at its law's radii, and the refusal of an engine list with an engine that does
// not take groups.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <hemivem/bundle_dca_minimizer.hpp>
#include <hemivem/certificate.hpp>
#include <hemivem/error.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/minimizer_run.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/uniqueness.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "test_support.hpp"

namespace hemivem {
namespace {

// An engine that does not take groups (the default of NonsmoothMinimizer).
class NoGroups final : public NonsmoothMinimizer {
 public:
  std::string name() const override { return "no-groups"; }

 protected:
  MinimizerResult run(MinimizerRun& run) const override { return run.finish(MinimizerStatus::failed, "never runs"); }
};

std::unique_ptr<GlobalSearch> bundle_dca_search(GlobalSearchOptions options = {}) {
  return std::make_unique<GlobalSearch>(
      std::vector<std::shared_ptr<const NonsmoothMinimizer>>{std::make_shared<BundleDcaMinimizer>()}, options);
}

// Slip-weakening friction on 3 nodes whose curvature bound alpha = (1.5 - 0.5) / 0.005 = 200
// exceeds the stiffness: F is not convex and may have several critical points.
ReducedProblem slip_weakening_solid(unsigned seed) {
  ReducedProblem p = test::frictional_solid_problem(3, linear_law(100.0), slip_weakening_law(1.5, 0.5, 0.005), seed);
  set_uniqueness_margin(p);
  return p;
}

TEST(GlobalSearchGroups, SlipWeakeningFrictionGivesCertifiedCriticalPointsLowestFirst) {
  for (unsigned seed : {1u, 2u}) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const ReducedProblem p = slip_weakening_solid(seed);
    ASSERT_LT(p.uniqueness_margin, 0.0);
    GlobalSearchOptions so;
    so.max_starts = 30;
    so.random_starts = 4;
    const auto search = bundle_dca_search(so);
    ASSERT_TRUE(search->takes_groups());
    const MinimizerOptions o;
    const MinimizerResult r = search->minimize(p, Eigen::VectorXd(), o);
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_TRUE(r.may_be_nonunique);
    ASSERT_FALSE(r.critical_points.empty());
    EXPECT_EQ(r.a, r.critical_points.front().a);
    for (std::size_t k = 0; k < r.critical_points.size(); ++k) {
      const CriticalPoint& c = r.critical_points[k];
      const CertifiedPoint cp = certify(p, c.a, o.tolerance);
      EXPECT_TRUE(cp.certificate.converged()) << k << ": " << cp.certificate.primal << " " << cp.certificate.dual;
      EXPECT_EQ(cp.a, c.a) << "a critical point is its certified (snapped) point";
      EXPECT_DOUBLE_EQ(c.objective, p.energy(c.a));
      if (k > 0) EXPECT_LE(r.critical_points[k - 1].objective, c.objective);
      for (std::size_t l = 0; l < k; ++l)
        EXPECT_GT((r.critical_points[l].a - c.a).cwiseAbs().maxCoeff(), so.agree * cp.certificate.length_scale);
    }
    // the lowest is no higher than a local run from the origin
    const MinimizerResult local = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), o);
    if (local.converged()) EXPECT_LE(r.objective, local.objective + 1e-12 * std::abs(local.objective));
  }
}

TEST(GlobalSearchGroups, AConvexProblemWithGroupsIsSolvedOnce) {
  ReducedProblem p = test::frictional_solid_problem(4, linear_law(100.0), tresca_law(1.0), 7);
  set_uniqueness_margin(p);
  ASSERT_GT(p.uniqueness_margin, 0.0);
  const MinimizerResult r = bundle_dca_search()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_FALSE(r.may_be_nonunique);
  EXPECT_NE(r.message.find("uniqueness margin is positive"), std::string::npos) << r.message;
  EXPECT_EQ(r.history.size(), 1u) << "one local run";
  ASSERT_EQ(r.critical_points.size(), 1u);
  EXPECT_TRUE(certify(p, r.a, MinimizerOptions{}.tolerance).certificate.converged());
}

TEST(GlobalSearchGroups, AGroupsBreakpointStartsAreRadiiOfItsLaw) {
  const double delta = 0.005;
  const ReducedProblem p = slip_weakening_solid(3);
  const auto search = bundle_dca_search();
  const std::vector<SearchStart> starts = search->starts(p, Eigen::VectorXd());
  const Eigen::VectorXd quadratic = starts.at(1).a;
  ASSERT_EQ(starts.at(1).name, "quadratic minimizer");
  int checked = 0;
  for (const SearchStart& s : starts) {
    const bool at_breakpoints = s.name.rfind("breakpoint", 0) == 0 || s.name.rfind("middle", 0) == 0;
    if (!at_breakpoints) continue;
    for (const CoordinateGroup& g : p.groups) {
      const double r = group_norm(s.a, g);
      const bool radius = r == 0.0 || std::abs(r - delta) <= 1e-15 || std::abs(r - 0.5 * delta) <= 1e-15 ||
                          r == group_norm(quadratic, g);
      EXPECT_TRUE(radius) << s.name << ": group norm " << r;
      // along the quadratic minimizer's pair
      const Eigen::Vector2d v(s.a(g.first), s.a(g.second)), q(quadratic(g.first), quadratic(g.second));
      if (r > 0.0) EXPECT_NEAR(v.normalized().dot(q.normalized()), 1.0, 1e-12) << s.name;
      ++checked;
    }
  }
  EXPECT_GE(checked, 3 * static_cast<int>(p.groups.size())) << "0, delta / 2 and delta";
}

TEST(GlobalSearchGroups, AnEngineListWithAnEngineWithoutGroupsIsRefusedByName) {
  const std::vector<std::shared_ptr<const NonsmoothMinimizer>> engines{std::make_shared<BundleDcaMinimizer>(),
                                                                       std::make_shared<NoGroups>()};
  const GlobalSearch search(engines);
  EXPECT_FALSE(search.takes_groups());
  EXPECT_EQ(search.engines_without_groups(), std::vector<std::string>{"no-groups"});
  const ReducedProblem p = slip_weakening_solid(1);
  try {
    search.minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    ADD_FAILURE() << "a problem with groups was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not take groups"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("with the engine(s) no-groups"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hemivem
