// Engine-specific checks of the smoothing-based minimizers nlopt-mma and ceres-active-set
// (the shared cross-validation is tests/test_minimizers.cpp).
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <hemivem/certificate.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "test_support.hpp"

using namespace hemivem;

namespace {

bool built(const std::string& name) {
  const auto names = available_minimizers();
  return std::find(names.begin(), names.end(), name) != names.end();
}

using test::Example;
using test::example;

class SmoothEngine : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (!built(GetParam())) GTEST_SKIP() << GetParam() << " not built";
  }
  std::unique_ptr<NonsmoothMinimizer> engine(const std::map<std::string, double>& parameters = {}) const {
    return make_minimizer(GetParam(), parameters);
  }
};

// one node per entry: S = diag(100 + i), w = 0.05, kinked law (sigma = 0.3, so w sigma = 0.015):
// c in (0, 0.015) puts the exact minimizer on the kink a = 0
ReducedProblem kink_problem(Eigen::VectorXd* exact) {
  const std::vector<double> cs{-1.0, 0.004, 0.01, 0.014, 2.0};
  const int n = static_cast<int>(cs.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) S(i, i) = 100.0 + i;
  ReducedProblem p = ReducedProblem::uniform(S, Eigen::Map<const Eigen::VectorXd>(cs.data(), n),
                                             Eigen::VectorXd::Constant(n, 0.05), kinked_law(), ConstraintKind::none,
                                             Eigen::VectorXd::Constant(n, 0.02));
  exact->resize(n);
  for (int i = 0; i < n; ++i) {
    const double c = cs[static_cast<std::size_t>(i)];
    // a < 0: j = 0, a = c / s; a > 0: (s + w k) a = c - w sigma
    (*exact)(i) = c < 0 ? c / p.S(i, i) : (c > 0.015 ? (c - 0.015) / (p.S(i, i) + 0.05 * 100.0) : 0.0);
  }
  p.uniqueness_margin = 100.0;
  return p;
}

TEST_P(SmoothEngine, ErrorAtAKinkIsOfTheOrderOfEpsilon) {
  Eigen::VectorXd exact;
  const ReducedProblem p = kink_problem(&exact);
  double previous = 1.0;
  for (double eps : {1e-3, 1e-4, 1e-5, 1e-6, 1e-8}) {
    const MinimizerResult r = engine({{"epsilon", eps}})->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    const double e = (r.a - exact).cwiseAbs().maxCoeff();
    EXPECT_LE(e, 2.0 * eps) << eps << ": " << r.message;
    if (r.converged()) {
      // the final try with the nodes inside a kink's rounding stuck on the kink was certified:
      // then the point is the exact one, not an O(eps) approximation
      EXPECT_TRUE(certificate(p, r.a, MinimizerOptions{}.tolerance).converged());
      EXPECT_LE(e, 1e-9 * exact.cwiseAbs().maxCoeff()) << eps;
      continue;
    }
    EXPECT_LT(e, previous) << eps;
    previous = e;
    // otherwise nodes at a kink are certified only in the limit: the run says so
    EXPECT_NE(r.message.find("smoothing scale"), std::string::npos) << r.message;
  }
}

TEST_P(SmoothEngine, OneStagePerSmoothingScale) {
  Eigen::VectorXd exact;
  const ReducedProblem p = kink_problem(&exact);
  const MinimizerOptions o;
  std::map<std::string, double> continuation{{"epsilon0", 1e-2}, {"epsilon", 1e-6}, {"reduction", 0.1}};
  const MinimizerResult r = engine(continuation)->minimize(p, Eigen::VectorXd(), o);
  EXPECT_GE(r.history.size(), 5u);  // eps = 1e-2, ..., 1e-6
  EXPECT_EQ(r.iterations, static_cast<int>(r.history.size()));
  for (std::size_t k = 1; k < r.history.size(); ++k) {
    EXPECT_EQ(r.history[k].iteration, static_cast<int>(k) + 1);
    EXPECT_GE(r.history[k].seconds, r.history[k - 1].seconds);
  }
  // epsilon = 0: down to 1e-12, then the law itself
  continuation["epsilon"] = 0.0;
  const MinimizerResult z = engine(continuation)->minimize(p, Eigen::VectorXd(), o);
  EXPECT_LE(z.history.size(), 30u);
  EXPECT_LE((z.a - exact).cwiseAbs().maxCoeff(), 1e-10) << z.message;
  // a law without kinks needs no continuation
  auto ex = example("squares", 8);
  const MinimizerResult q = engine()->minimize(ex->condensation->reduced(), Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(q.converged()) << q.message;
  EXPECT_LE(q.history.size(), 4u);
}

TEST_P(SmoothEngine, InputErrors) {
  auto ex = example("squares", 8);
  const ReducedProblem& p = ex->condensation->reduced();
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"epsilom", 1e-6}, {"reduction", 1.5}, {"epsilon", -1.0}, {"epsilon0", 0.0}, {"snap", 2.0}}) {
    EXPECT_THROW(engine({{name, value}}), InputError) << name;
  }
  const std::string integer = GetParam() == "nlopt-mma" ? "stage_evaluations" : "lbfgs_rank";
  EXPECT_THROW(engine({{integer, 1e20}}), InputError) << "an integer field out of int's range";
  EXPECT_THROW(engine({{integer, 10.5}}), InputError) << "an integer field given a fraction";
  MinimizerOptions o;
  o.tolerance = 0.0;
  EXPECT_THROW(engine()->minimize(p, Eigen::VectorXd(), o), InputError);
  EXPECT_THROW(engine()->minimize(p, Eigen::VectorXd::Zero(p.size() - 1), MinimizerOptions{}), InputError);
  try {
    engine({{"nonsense", 1.0}});
    ADD_FAILURE() << "an unknown parameter was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("epsilon0"), std::string::npos) << "lists the known names: " << e.what();
  }
}

TEST_P(SmoothEngine, LimitsAreStatuses) {
  auto ex = example("squares", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  MinimizerOptions o;
  o.max_evaluations = 5;
  MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
  EXPECT_EQ(r.status, MinimizerStatus::evaluation_limit) << r.message;
  EXPECT_LE(r.function_evaluations + r.subgradient_evaluations, 12);
  EXPECT_LE(r.certificate.primal, 1e-12);
  Eigen::VectorXd exact;
  const ReducedProblem k = kink_problem(&exact);
  MinimizerOptions oi;
  oi.max_iterations = 1;
  r = engine()->minimize(k, Eigen::VectorXd(), oi);
  EXPECT_EQ(r.status, MinimizerStatus::iteration_limit) << r.message;
  EXPECT_EQ(r.iterations, 1);
}

TEST_P(SmoothEngine, WarmStartAtTheSolutionIsCheap) {
  auto ex = example("voronoi", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  const MinimizerResult cold = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(cold.converged()) << cold.message;
  const MinimizerResult warm = engine()->minimize(p, cold.a, MinimizerOptions{});
  EXPECT_TRUE(warm.converged()) << warm.message;
  EXPECT_LT(warm.function_evaluations, cold.function_evaluations);
}

TEST_P(SmoothEngine, PrintsNothing) {
  auto ex = example("squares", 16, [](ContactProblem& p) { p.parts[0].law = make_contact_law("sawtooth"); });
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  MinimizerOptions o;
  o.max_evaluations = 50;  // also the early exits
  engine()->minimize(ex->condensation->reduced(), Eigen::VectorXd(), o);
  engine()->minimize(ex->condensation->reduced(), Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST_P(SmoothEngine, EmptyProblem) {
  const ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd(0, 0), Eigen::VectorXd(), Eigen::VectorXd(), kinked_law(),
                                                   ConstraintKind::box, Eigen::VectorXd());
  const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(r.converged());
  EXPECT_EQ(r.a.size(), 0);
}

// Evaluation counts and times on Example 4.1 (printed; the assertions are the contract's).
TEST_P(SmoothEngine, Example41Counts) {
  for (const std::string kind : {"squares", "triangles", "voronoi", "nonconvex"})
    for (int n : {8, 16, 32, 64}) {
      auto ex = example(kind, n);
      const ReducedProblem& p = ex->condensation->reduced();
      MinimizerOptions o;
      o.tolerance = 1e-9;
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
      EXPECT_TRUE(r.converged()) << kind << " " << n << ": " << r.message;
      EXPECT_GT(r.timings.at("total"), 0.0);
      std::printf("%s %-9s N=%-3d nodes %-3ld: %-9s residual %.1e iterations %d f %d g %d time %.4f s\n", GetParam().c_str(),
                  kind.c_str(), n, static_cast<long>(p.size()), to_string(r.status).c_str(), r.certificate.dual,
                  r.iterations, r.function_evaluations, r.subgradient_evaluations, r.timings.at("total"));
    }
}

INSTANTIATE_TEST_SUITE_P(Engines, SmoothEngine, ::testing::Values("nlopt-mma", "ceres-active-set"), [](const auto& info) {
  std::string s = info.param;
  for (auto& c : s)
    if (c == '-') c = '_';
  return s;
});

}  // namespace
