// Cross-validation of every built nonsmooth minimizer (DESIGN §3, §5): closed forms, the
// paper's Example 4.1 on four mesh types against ssn, kinked laws, edge cases and a law
// concave enough to lose uniqueness.
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "test_support.hpp"

using namespace hemivem;

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Minimizer);

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- closed forms: diagonal S, every node a 1D problem --------------------------------

// All local minimizers of f(a) = s a^2 / 2 - c a + w j(a) on [lo, hi], for laws whose pieces
// have degree <= 2: stationary points inside pieces, breakpoints and bounds.
std::vector<double> local_minimizers_1d(const ContactLaw& law, double s, double c, double w, double lo, double hi) {
  auto d = [&](double a, int side) { return s * a - c + w * law.derivative(LawPart::j, a, side); };
  std::vector<double> knots{lo};
  for (double b : law.breakpoints())
    if (b > lo && b < hi) knots.push_back(b);
  knots.push_back(hi);
  std::vector<double> out;
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    const double a0 = knots[k], a1 = knots[k + 1];
    // on (a0, a1) f' is affine: f'(a) = d0 + q (a - x) with q = s + w j''
    const double xm = std::isinf(a0) ? (std::isinf(a1) ? 0.0 : a1 - 1.0) : (std::isinf(a1) ? a0 + 1.0 : 0.5 * (a0 + a1));
    const double q = s + w * law.second_derivative(LawPart::j, xm, +1);
    const double dm = d(xm, +1);
    if (q > 0) {
      const double a = xm - dm / q;
      if (a > a0 && a < a1) out.push_back(a);
    }
  }
  for (std::size_t k = 0; k < knots.size(); ++k) {
    const double a = knots[k];
    if (std::isinf(a)) continue;
    const double left = k == 0 ? -kInf : d(a, -1);   // at the lower bound nothing to the left
    const double right = k + 1 == knots.size() ? kInf : d(a, +1);
    if (left <= 0.0 && right >= 0.0) out.push_back(a);
  }
  return out;
}

struct ClosedForm {
  std::string law;
  ConstraintKind constraint;
};

ReducedProblem diagonal_problem(const ClosedForm& cf, Eigen::VectorXd* exact) {
  const std::vector<double> cs{-3.0, -0.5, 0.2, 0.5, 0.8, 0.95, 1.2, 1.6, 2.4, 3.0, 6.0};
  const int n = static_cast<int>(cs.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) {
    S(i, i) = 100.0 + i;  // distinct diagonal entries
    c(i) = cs[static_cast<std::size_t>(i)];
  }
  ReducedProblem p = ReducedProblem::uniform(S, c, Eigen::VectorXd::Constant(n, 0.05), make_contact_law(cf.law),
                                             cf.constraint, Eigen::VectorXd::Constant(n, 0.02));
  const ContactLaw& law = p.law_by_number(0);
  exact->resize(n);
  for (int i = 0; i < n; ++i) {
    const auto mins = local_minimizers_1d(law, p.S(i, i), p.c(i), p.w(i), p.lower(i), p.upper(i));
    EXPECT_EQ(mins.size(), 1u) << "node " << i << " of the closed form must have a unique local minimizer";
    (*exact)(i) = mins.empty() ? 0.0 : mins[0];
  }
  p.uniqueness_margin = uniqueness_margin(p.S, p.w, law.alpha());
  return p;
}

class Minimizer : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<NonsmoothMinimizer> engine(const std::map<std::string, double>& parameters = {}) const {
    return make_minimizer(GetParam(), parameters);
  }
  bool smoothing_based() const { return GetParam() == "nlopt-mma" || GetParam() == "ceres-active-set"; }
};

TEST_P(Minimizer, ClosedFormsNodeByNode) {
  for (const std::string law : {"paper", "linear", "zero", "kinked", "sawtooth"}) {
    for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided, ConstraintKind::none}) {
      SCOPED_TRACE(law + " / " + to_string(kind));
      Eigen::VectorXd exact;
      const ReducedProblem p = diagonal_problem({law, kind}, &exact);
      MinimizerOptions o;
      o.tolerance = 1e-10;
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
      const bool kink = law == "kinked" || law == "sawtooth";
      if (smoothing_based() && kink) {
        // smoothing engines approach kinks only as epsilon -> 0 (see KinkedLaws)
        EXPECT_LE((r.a - exact).cwiseAbs().maxCoeff(), 1e-3) << r.message;
        continue;
      }
      EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message << " residual " << r.certificate.dual;
      EXPECT_LE((r.a - exact).cwiseAbs().maxCoeff(), 1e-8) << "got " << r.a.transpose() << "\nexact " << exact.transpose();
    }
  }
}

// ---- Example 4.1 ---------------------------------------------------------------------------

using test::Example;
using test::example;

std::vector<int> at_bound(const ReducedProblem& p, const Eigen::VectorXd& a) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if ((std::isfinite(p.upper(i)) && std::abs(a(i) - p.upper(i)) <= 1e-9 * (1 + std::abs(p.upper(i)))) ||
        (std::isfinite(p.lower(i)) && std::abs(a(i) - p.lower(i)) <= 1e-9 * (1 + std::abs(p.lower(i)))))
      out.push_back(static_cast<int>(i));
  return out;
}

TEST_P(Minimizer, Example41AgreesWithSsnOnFourMeshTypes) {
  const auto ssn = make_minimizer("ssn");
  for (const std::string kind : {"squares", "triangles", "voronoi", "nonconvex"}) {
    for (int n : {8, 16, 32}) {
      SCOPED_TRACE(kind + " N = " + std::to_string(n));
      auto ex = example(kind, n);
      const ReducedProblem& p = ex->condensation->reduced();
      MinimizerOptions o;
      o.tolerance = 1e-9;
      const MinimizerResult ref = ssn->minimize(p, Eigen::VectorXd(), o);
      ASSERT_TRUE(ref.converged()) << ref.message;
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
      EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
      EXPECT_LE(r.certificate.dual, 1e-8);
      EXPECT_LE(r.certificate.primal, 1e-12);
      EXPECT_LE((r.a - ref.a).cwiseAbs().maxCoeff(), 1e-6 * ref.a.cwiseAbs().maxCoeff());
      EXPECT_EQ(at_bound(p, r.a), at_bound(p, ref.a));
      EXPECT_FALSE(r.may_be_nonunique);  // lambda_min(S - 20 W) > 0 here
      EXPECT_GT(r.iterations, 0);
      EXPECT_GT(r.function_evaluations + r.subgradient_evaluations, 0);
      EXPECT_FALSE(r.history.empty());
      EXPECT_TRUE(r.timings.count("total"));
    }
  }
}

TEST_P(Minimizer, KinkedLaws) {
  // kinked (sigma = 0.3) and sawtooth: no node of the solution sits on a kink; kinked with
  // sigma = 3: six of the 15 nodes sit exactly on the kink at r = 0.
  const auto ssn = make_minimizer("ssn");
  const std::vector<std::pair<std::string, std::shared_ptr<const ContactLaw>>> laws{
      {"kinked", kinked_law(0.3, 100.0)}, {"sawtooth", sawtooth_law()}, {"kinked-held", kinked_law(3.0, 100.0)}};
  for (const auto& [label, law] : laws) {
    SCOPED_TRACE(label);
    auto ex = example("squares", 16, [&](ContactProblem& p) {
      p.parts[0].law = law;
      p.parts[0].constraint = ConstraintKind::one_sided;
    });
    const ReducedProblem& p = ex->condensation->reduced();
    MinimizerOptions o;
    o.tolerance = 1e-9;
    const MinimizerResult ref = ssn->minimize(p, Eigen::VectorXd(), o);
    ASSERT_TRUE(ref.converged()) << ref.message;
    int on_kink = 0;
    for (Eigen::Index i = 0; i < ref.a.size(); ++i)
      for (double b : law->breakpoints())
        on_kink += ref.a(i) == b && law->derivative(LawPart::j, b, -1) != law->derivative(LawPart::j, b, +1);
    ASSERT_EQ(on_kink > 0, label == "kinked-held") << "the test needs its nodes on (or off) the kink";
    const double scale = std::max(ref.a.cwiseAbs().maxCoeff(), 1e-3);  // kinked-held: small a
    if (!smoothing_based()) {
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
      EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
      EXPECT_LE((r.a - ref.a).cwiseAbs().maxCoeff(), 1e-6 * scale);
      continue;
    }
    // smoothing engines: exact away from kinks; at a kink the error falls with the final
    // smoothing scale epsilon
    std::vector<double> errors;
    for (double eps : {1e-3, 1e-4, 1e-5, 1e-6}) {
      const MinimizerResult r = engine({{"epsilon", eps}})->minimize(p, Eigen::VectorXd(), o);
      errors.push_back((r.a - ref.a).cwiseAbs().maxCoeff() / scale);
      std::cout << GetParam() << " " << label << " epsilon " << eps << ": relative error against ssn " << errors.back()
                << ", certificate " << r.certificate.dual << "\n";
    }
    if (on_kink == 0) {
      for (double e : errors) EXPECT_LE(e, 1e-6);
    } else {
      for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_LT(errors[k], errors[k - 1]);
      EXPECT_LT(errors.back(), 1e-3);
    }
  }
}

TEST_P(Minimizer, NothingInContact) {
  // the load lifts the body: a < 0, j = 0 there, no bound active (one-sided a <= g)
  auto ex = example("squares", 16, [](ContactProblem& p) {
    p.elasticity.tractions[0].traction = [](const Vec2&) { return Vec2(0.0, 8.0); };
    p.parts[0].constraint = ConstraintKind::one_sided;
  });
  const ReducedProblem& p = ex->condensation->reduced();
  const Eigen::VectorXd linear = p.S.llt().solve(p.c);
  ASSERT_LT(linear.maxCoeff(), 0.0);
  const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(r.converged()) << r.message;
  EXPECT_LE((r.a - linear).cwiseAbs().maxCoeff(), 1e-8 * linear.cwiseAbs().maxCoeff());
  EXPECT_TRUE(at_bound(p, r.a).empty());
}

TEST_P(Minimizer, EverythingAtTheBound) {
  auto ex = example("squares", 16, [](ContactProblem& p) {
    p.elasticity.tractions[0].traction = [](const Vec2&) { return Vec2(0.0, -800.0); };
  });
  const ReducedProblem& p = ex->condensation->reduced();
  const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(r.converged()) << r.message;
  EXPECT_LE((r.a - p.uniform_form()->g).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(at_bound(p, r.a).size(), static_cast<std::size_t>(p.size()));
}

TEST_P(Minimizer, ZeroGap) {
  for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided}) {
    auto ex = example("squares", 16, [&](ContactProblem& p) {
      p.parts[0].gap = [](const Vec2&) { return 0.0; };
      p.parts[0].constraint = kind;
    });
    const ReducedProblem& p = ex->condensation->reduced();
    const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_TRUE(r.converged()) << r.message;
    EXPECT_LE(r.a.cwiseAbs().maxCoeff(), 1e-12) << "the load pushes down: a = 0 is the solution";
  }
}

TEST_P(Minimizer, InfeasibleStartIsProjected) {
  auto ex = example("squares", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(p.size(), 1.0);  // 50 g: far outside
  const MinimizerResult r = engine()->minimize(p, start, MinimizerOptions{});
  const MinimizerResult ref = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(r.converged()) << r.message;
  EXPECT_LE((r.a - ref.a).cwiseAbs().maxCoeff(), 1e-6 * ref.a.cwiseAbs().maxCoeff());
  EXPECT_THROW(engine()->minimize(p, Eigen::VectorXd::Zero(p.size() + 1), MinimizerOptions{}), InputError);
}

TEST_P(Minimizer, ConcaveLawFlagsPossibleNonUniqueness) {
  // the paper's law scaled by 20: alpha_j = 400, lambda_min(S - alpha W) < 0
  const auto base = std::dynamic_pointer_cast<const PiecewisePolynomialLaw>(paper_law());
  ASSERT_TRUE(base);
  auto scale = [](std::vector<Polynomial> ps) {
    for (auto& p : ps)
      for (auto& c : p) c *= 20.0;
    return ps;
  };
  const auto law = std::make_shared<PiecewisePolynomialLaw>("paper-x20", base->breakpoints(), scale(base->pieces(LawPart::j1)),
                                                            scale(base->pieces(LawPart::j2)));
  auto ex = example("squares", 16, [&](ContactProblem& p) { p.parts[0].law = law; });
  const ReducedProblem& p = ex->condensation->reduced();
  ASSERT_LT(p.uniqueness_margin, 0.0);
  MinimizerOptions o;
  o.tolerance = 1e-8;
  const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
  EXPECT_TRUE(r.converged()) << to_string(r.status) << ": " << r.message;
  EXPECT_LE(r.certificate.dual, 1e-8);
  EXPECT_LE(r.certificate.primal, 1e-12);
  EXPECT_TRUE(r.may_be_nonunique);
}

TEST_P(Minimizer, CallbackCanStopTheRun) {
  auto ex = example("squares", 16);
  MinimizerOptions o;
  int calls = 0;
  o.callback = [&](const IterationRecord&) { return ++calls < 1; };
  const MinimizerResult r = engine()->minimize(ex->condensation->reduced(), Eigen::VectorXd(), o);
  EXPECT_EQ(calls, 1);
  if (!r.converged()) EXPECT_EQ(r.status, MinimizerStatus::stopped_by_callback);
  EXPECT_TRUE(r.a.allFinite());
  EXPECT_LE(r.certificate.primal, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Engines, Minimizer, ::testing::ValuesIn(available_minimizers()), [](const auto& info) {
  std::string s = info.param;
  for (auto& c : s)
    if (c == '-') c = '_';
  return s;
});

TEST(MinimizerFactory, UnknownNameListsTheBuiltOnes) {
  try {
    make_minimizer("newton-krylov");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown minimizer 'newton-krylov'; available:"), std::string::npos) << e.what();
  }
}

TEST(Certificate, ZeroExactlyAtAHandSolution) {
  // one node: S = 2, c = 1, w = 1, j = 0, box |a| <= 0.2: solution a = 0.2 (the bound)
  auto problem = [](ConstraintKind kind) {
    return ReducedProblem::uniform(Eigen::MatrixXd::Constant(1, 1, 2.0), Eigen::VectorXd::Constant(1, 1.0),
                                   Eigen::VectorXd::Constant(1, 1.0), zero_law(), kind, Eigen::VectorXd::Constant(1, 0.2));
  };
  ReducedProblem p = problem(ConstraintKind::box);
  Eigen::VectorXd a = Eigen::VectorXd::Constant(1, 0.2);
  const CertifiedPoint at = certify(p, a, 1e-10);
  EXPECT_EQ(at.certificate.dual, 0.0);
  EXPECT_EQ(at.certificate.primal, 0.0);
  EXPECT_DOUBLE_EQ(at.reaction(0), 0.6);  // S a - c = -0.6, taken by the bound
  a(0) = 0.1;  // free: S a - c = -0.8 against f = max(|c|, |S a|) = 1
  EXPECT_NEAR(certificate(p, a, 1e-10).dual, 0.8, 1e-15);
  a(0) = 0.3;  // 0.1 beyond the bound; l = max(|a|, g, c / S) = 0.5
  EXPECT_NEAR(certificate(p, a, 1e-10).primal, 0.2, 1e-15);
  p = problem(ConstraintKind::none);  // unconstrained: a = 0.5
  a(0) = 0.5;
  EXPECT_EQ(certificate(p, a, 1e-10).dual, 0.0);
}

}  // namespace
