// The bundle-dca engine on its own: the proximal bundle method on a convex nonsmooth problem,
// monotone decrease of the DC iteration, the bundle-size limit, every status and input errors.
#include <hemivem/bundle_dca_minimizer.hpp>
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <iostream>
#include <regex>

#include "test_support.hpp"

using namespace hemivem;

namespace {

using test::Example;
using test::example;

int largest_bundle(const MinimizerResult& r) {
  std::smatch m;
  const std::regex re("largest bundle ([0-9]+) cuts");
  if (!std::regex_search(r.message, m, re)) return -1;
  return std::stoi(m[1]);
}

// f(a) = 1/2 s a^2 - c a + w j(a), kinked law j = 0 (a <= 0), sigma a + k a^2 / 2 (a > 0)
double kinked_1d(double s, double c, double w, double sigma, double k) {
  if (c <= 0.0) return c / s;                 // left of the kink
  if (c <= w * sigma) return 0.0;             // at the kink: c in [0, w sigma]
  return (c - w * sigma) / (s + w * k);       // right of the kink
}

TEST(BundleDca, NameAndFactory) {
  EXPECT_EQ(BundleDcaMinimizer().name(), "bundle-dca");
  EXPECT_EQ(make_minimizer("bundle-dca")->name(), "bundle-dca");
  EXPECT_EQ(make_minimizer("bundle_dca")->name(), "bundle-dca");
}

TEST(BundleDca, ConvexKinkedProblemSolvedByTheBundleAlone) {
  // coupled S (tridiagonal, SPD), kinked law: F is convex and nonsmooth, F2 = 0, so the DC
  // loop makes one step and the proximal bundle method alone solves the problem
  const int n = 12;
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    S(i, i) = 120.0;
    if (i + 1 < n) S(i, i + 1) = S(i + 1, i) = -40.0;
  }
  // w sigma = 0.25: a wide range of loads keeps a node at the kink
  const ReducedProblem p = ReducedProblem::uniform(S, Eigen::VectorXd::LinSpaced(n, -1.0, 2.0),
                                                   Eigen::VectorXd::Constant(n, 0.05), kinked_law(5.0, 100.0),
                                                   ConstraintKind::none, Eigen::VectorXd::Constant(n, 0.02));
  MinimizerOptions o;
  o.tolerance = 1e-11;
  const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), o);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_EQ(r.iterations, 1) << r.message;
  EXPECT_LE(r.certificate.dual, 1e-11);
  // some nodes sit exactly at the kink a = 0, where F is not differentiable
  int at_kink = 0;
  for (int i = 0; i < n; ++i) at_kink += r.a(i) == 0.0;
  EXPECT_GT(at_kink, 0) << r.a.transpose();
  // and the solution agrees with ssn
  const MinimizerResult ref = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), o);
  ASSERT_TRUE(ref.converged()) << ref.message;
  EXPECT_LE((r.a - ref.a).cwiseAbs().maxCoeff(), 1e-10 * ref.a.cwiseAbs().maxCoeff());
  std::cout << r.message << "\n";
}

TEST(BundleDca, ConvexKinkedClosedFormOneNodeAtATime) {
  for (double c : {-2.0, 0.0, 0.01, 0.015, 0.5, 3.0}) {
    const ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd::Constant(1, 1, 100.0), Eigen::VectorXd::Constant(1, c),
                                                     Eigen::VectorXd::Constant(1, 0.05), kinked_law(0.3, 100.0),
                                                     ConstraintKind::box, Eigen::VectorXd::Constant(1, 1.0));
    const double exact = kinked_1d(100.0, c, 0.05, 0.3, 100.0);
    const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_TRUE(r.converged() || c == 0.0) << c << ": " << r.message;
    EXPECT_NEAR(r.a(0), exact, 1e-12) << c;
  }
}

TEST(BundleDca, DcIterationDecreasesTheEnergyMonotonically) {
  for (const std::string law : {"paper", "sawtooth"}) {
    SCOPED_TRACE(law);
    auto ex = example("voronoi", 16, [&](ContactProblem& p) { p.parts[0].law = make_contact_law(law); });
    const ReducedProblem& p = ex->condensation->reduced();
    MinimizerOptions o;
    o.tolerance = 1e-10;
    const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), o);
    ASSERT_TRUE(r.converged()) << r.message;
    ASSERT_GE(r.history.size(), 2u);
    double previous = p.energy(p.project(Eigen::VectorXd::Zero(p.size())));
    for (const auto& h : r.history) {
      EXPECT_LE(h.objective, previous + 1e-13 * std::abs(previous)) << "DC iteration " << h.iteration;
      previous = h.objective;
    }
  }
}

TEST(BundleDca, BundleSizeLimitIsRespected) {
  auto ex = example("squares", 32);
  const ReducedProblem& p = ex->condensation->reduced();
  for (int size : {4, 6, 30}) {
    MinimizerOptions o;
    o.tolerance = 1e-9;
    BundleDcaOptions bo;
    bo.bundle_size = size;
    const MinimizerResult r = BundleDcaMinimizer(bo).minimize(p, Eigen::VectorXd(), o);
    EXPECT_TRUE(r.converged()) << size << ": " << r.message;
    const int largest = largest_bundle(r);
    ASSERT_GT(largest, 0) << r.message;
    EXPECT_LE(largest, size) << r.message;
  }
}

TEST(BundleDca, EveryStatus) {
  auto ex = example("squares", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  const BundleDcaMinimizer engine;
  {  // converged
    const MinimizerResult r = engine.minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_EQ(r.status, MinimizerStatus::converged) << r.message;
    EXPECT_TRUE(r.timings.count("total"));
    EXPECT_EQ(static_cast<int>(r.history.size()), r.iterations);
  }
  {  // iteration limit
    MinimizerOptions o;
    o.max_iterations = 1;
    const MinimizerResult r = engine.minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::iteration_limit) << r.message;
    EXPECT_EQ(r.iterations, 1);
  }
  {  // evaluation limit
    MinimizerOptions o;
    o.max_evaluations = 5;
    const MinimizerResult r = engine.minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::evaluation_limit) << r.message;
    EXPECT_LE(r.function_evaluations + r.subgradient_evaluations, 5);
    EXPECT_LE(r.certificate.primal, 1e-12);
  }
  for (int budget : {1, 2, 4, 7, 12}) {  // the budget is never exceeded
    MinimizerOptions o;
    o.max_evaluations = budget;
    const MinimizerResult r = engine.minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::evaluation_limit) << budget << ": " << r.message;
    EXPECT_LE(r.function_evaluations + r.subgradient_evaluations, budget);
  }
  {  // stalled: a tolerance below rounding
    MinimizerOptions o;
    o.tolerance = 1e-300;
    const MinimizerResult r = engine.minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::stalled) << r.message;
    EXPECT_LE(r.certificate.dual, 1e-12);
  }
  {  // stopped by the callback
    MinimizerOptions o;
    int calls = 0;
    o.callback = [&](const IterationRecord& rec) {
      EXPECT_EQ(rec.iteration, ++calls);
      return calls < 2;
    };
    const MinimizerResult r = engine.minimize(p, Eigen::VectorXd(), o);
    EXPECT_EQ(r.status, MinimizerStatus::stopped_by_callback) << r.message;
    EXPECT_EQ(calls, 2);
  }
  {  // failed: S not positive definite
    ReducedProblem bad = ReducedProblem::uniform(-p.S, p.c, p.w, p.laws.front(), ConstraintKind::none);
    const MinimizerResult r = engine.minimize(bad, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_EQ(r.status, MinimizerStatus::failed) << r.message;
    EXPECT_TRUE(r.a.allFinite());
  }
}

TEST(BundleDca, InputErrors) {
  auto ex = example("squares", 8);
  const ReducedProblem& p = ex->condensation->reduced();
  const BundleDcaMinimizer engine;
  EXPECT_THROW(engine.minimize(p, Eigen::VectorXd::Zero(p.size() + 2), MinimizerOptions{}), InputError);
  EXPECT_THROW(make_minimizer("bundle-dca", {{"epsilon", 1e-3}}), InputError);  // a smoothing engine's parameter
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"bundle_size", 2}, {"bundle_size", 1e20}, {"proximal_weight", -1}, {"descent", 1.0},
           {"inner_tolerance_factor", 0.0}, {"max_bundle_iterations", 0}, {"stall_iterations", 0},
           {"stall_iterations", 3.5}, {"two_sided_cuts", 0.5}}) {
    try {
      make_minimizer("bundle-dca", {{name, value}});
      ADD_FAILURE() << name << " = " << value << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << "the message names the field: " << e.what();
    }
  }
  std::map<std::string, double> defaults;
  for (const auto& [name, value] : parameter_values(BundleDcaOptions{})) defaults[name] = value;
  EXPECT_EQ(defaults.size(), 8u);
  EXPECT_TRUE(make_minimizer("bundle-dca", defaults)->minimize(p, Eigen::VectorXd(), MinimizerOptions{}).converged());
  MinimizerOptions invalid;
  invalid.tolerance = 0.0;
  EXPECT_THROW(engine.minimize(p, Eigen::VectorXd(), invalid), InputError);
}

TEST(BundleDca, Example41Counts) {
  // iteration and evaluation counts on Example 4.1 (printed; the cross-validation is in
  // test_minimizers). HEMIVEM_BUNDLE_DCA_SIZES="128 256" measures other mesh sizes.
  std::vector<int> sizes{8, 16, 32, 64};
  if (const char* env = std::getenv("HEMIVEM_BUNDLE_DCA_SIZES")) {
    sizes.clear();
    std::istringstream in(env);
    for (int n; in >> n;) sizes.push_back(n);
  }
  for (int n : sizes) {
    auto ex = example("squares", n);
    const ReducedProblem& p = ex->condensation->reduced();
    MinimizerOptions o;
    o.tolerance = 1e-10;
    const MinimizerResult r = BundleDcaMinimizer().minimize(p, Eigen::VectorXd(), o);
    EXPECT_TRUE(r.converged()) << r.message;
    std::cout << "N1 = " << p.size() << ": " << r.iterations << " DC iterations, " << r.function_evaluations
              << " function + " << r.subgradient_evaluations << " subgradient evaluations, residual "
              << r.certificate.dual << ", " << r.timings.at("total") << " s\n  " << r.message << "\n";
  }
}

}  // namespace
