// Frictional contact (docs/friction.md): the coordinate-wise reduced problem, the friction
// laws, and the solve on Example 4.1's geometry, each checked against something independent:
// a closed form for one node on a spring, Dirichlet problems for the limits of the friction
// bound, the frictionless problem for a zero bound, and every engine against ssn.
#include <hemivem/certificate.hpp>
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/example.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "test_support.hpp"

using namespace hemivem;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// One tangential coordinate on a spring: F(a) = k a^2 / 2 - c a + w g |a|.
ReducedProblem spring(double k, double c, double w, std::shared_ptr<const ContactLaw> law) {
  ReducedProblem p;
  p.S = Eigen::MatrixXd::Constant(1, 1, k);
  p.c = Eigen::VectorXd::Constant(1, c);
  p.w = Eigen::VectorXd::Constant(1, w);
  p.laws = {law};
  p.law_index = Eigen::VectorXi::Zero(1);
  p.lo = Eigen::VectorXd::Constant(1, -kInf);
  p.hi = Eigen::VectorXd::Constant(1, kInf);
  p.uniqueness_margin = uniqueness_margin(p.S, p.w, p.alphas());
  return p;
}

class Friction : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<NonsmoothMinimizer> engine() const { return make_minimizer(GetParam()); }
};

// stick when |c| <= w g, slip by (|c| - w g) / k otherwise
TEST_P(Friction, OneNodeOnASpringSticksOrSlipsByTheClosedForm) {
  const double k = 4.0, g = 0.5;
  for (const double w : {1.0, 0.25}) {
    for (const double c : {0.3, -0.45, 0.5 * w, 1.7, -3.0, 0.0}) {
      SCOPED_TRACE("w " + std::to_string(w) + ", c " + std::to_string(c));
      const ReducedProblem p = spring(k, c, w, tresca_law(g));
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
      ASSERT_TRUE(r.converged()) << r.message;
      const double exact = std::abs(c) <= w * g ? 0.0 : std::copysign((std::abs(c) - w * g) / k, c);
      EXPECT_NEAR(r.a(0), exact, 1e-9 * std::max(1.0, std::abs(exact)));
      if (std::abs(c) <= w * g) {
        EXPECT_EQ(r.a(0), 0.0) << "a stuck node is put exactly on the kink";
        EXPECT_EQ(friction_state(p.law_by_number(0), r.a(0)), FrictionState::stick);
        EXPECT_NEAR(r.law_force(0), c, 1e-12) << "the friction force balances the load while stuck";
      } else {
        EXPECT_EQ(friction_state(p.law_by_number(0), r.a(0)), FrictionState::slip);
        EXPECT_NEAR(std::abs(r.law_force(0)), w * g, 1e-12) << "a slipping node carries the friction bound";
      }
    }
  }
}

// A normal and a tangential coordinate coupled by S: every engine reaches the point of ssn.
TEST_P(Friction, NormalAndTangentialCoordinatesAgreeWithSsn) {
  ReducedProblem p;
  p.S.resize(4, 4);
  p.S << 4, 1, 0.5, 0, 1, 3, 0, 0.4, 0.5, 0, 5, 1, 0, 0.4, 1, 4;
  p.c = Eigen::Vector4d(0.2, 0.05, 1.0, -0.6);
  p.w = Eigen::Vector4d(0.05, 0.05, 0.05, 0.05);
  p.laws = {paper_law(), tresca_law(0.3)};
  p.law_index = Eigen::Vector4i(0, 0, 1, 1);
  p.lo = Eigen::Vector4d(-0.02, -0.02, -kInf, -kInf);
  p.hi = Eigen::Vector4d(0.02, 0.02, kInf, kInf);
  p.uniqueness_margin = uniqueness_margin(p.S, p.w, p.alphas());
  ASSERT_GT(p.uniqueness_margin, 0.0);
  const MinimizerResult ref = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(ref.converged()) << ref.message;
  const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LT((r.a - ref.a).cwiseAbs().maxCoeff(), 1e-8 * ref.a.cwiseAbs().maxCoeff());
  // the certificate judges every coordinate by its own law and bounds
  EXPECT_TRUE(certificate(p, r.a, 1e-10).converged());
  Eigen::VectorXd off = r.a;
  off(2) += 1e-3;
  EXPECT_FALSE(certificate(p, off, 1e-10).converged());
}

INSTANTIATE_TEST_SUITE_P(Engines, Friction, ::testing::ValuesIn(available_minimizers()), [](const auto& info) {
  std::string s = info.param;
  for (auto& ch : s)
    if (ch == '-') ch = '_';
  return s;
});

TEST(FrictionLaws, TrescaAndSlipWeakeningAreTheirFormulas) {
  const auto t = tresca_law(0.4);
  EXPECT_DOUBLE_EQ(t->value(-0.5), 0.2);
  EXPECT_DOUBLE_EQ(t->value(0.25), 0.1);
  EXPECT_EQ(t->kinks(), std::vector<double>{0.0});
  EXPECT_EQ(t->alpha(), 0.0);
  EXPECT_DOUBLE_EQ(t->clarke(0.0).lo, -0.4);
  EXPECT_DOUBLE_EQ(t->clarke(0.0).hi, 0.4);

  const double gs = 0.3, gk = 0.1, d = 0.02;
  const auto s = slip_weakening_law(gs, gk, d);
  for (double r : {-0.05, -0.02, -0.01, 0.0, 0.005, 0.02, 0.3}) {
    const double a = std::abs(r);
    const double j = a <= d ? gs * a - (gs - gk) * a * a / (2 * d) : gk * a + (gs - gk) * d / 2;
    EXPECT_NEAR(s->value(r), j, 1e-15) << r;
    // both parts convex: one-sided derivatives increase across r
    for (LawPart part : {LawPart::j1, LawPart::j2})
      EXPECT_LE(s->derivative(part, r, -1), s->derivative(part, r, +1) + 1e-15);
  }
  EXPECT_NEAR(s->derivative(LawPart::j, 0.01, +1), gs - (gs - gk) * 0.5, 1e-15);
  EXPECT_NEAR(s->derivative(LawPart::j, -0.05, +1), -gk, 1e-15);
  EXPECT_EQ(s->kinks(), std::vector<double>{0.0});
  EXPECT_NEAR(s->alpha(), (gs - gk) / d, 1e-9);
  EXPECT_EQ(friction_state(*s, 0.0), FrictionState::stick);
  EXPECT_EQ(friction_state(*s, -0.01), FrictionState::slip_weakening);
  EXPECT_EQ(friction_state(*s, 0.03), FrictionState::slip_kinetic);
  EXPECT_NE(test::input_error_of([] { (void)slip_weakening_law(0.1, 0.2, 0.01); }), "");
  EXPECT_NE(test::input_error_of([] { (void)tresca_law(-1.0); }), "");
}

// ---- Example 4.1's geometry with a tangential component in the top traction ---------------

struct FrictionRun {
  ContactSolution solution;
  ReducedProblem reduced;
};

FrictionRun solve(const Mesh& mesh, const std::function<void(ContactProblem&)>& change, const std::string& minimizer = "ssn",
          const std::string& linear = "eigen") {
  ContactProblem problem = example_4_1(mesh);
  for (auto& t : problem.elasticity.tractions) t.traction = [](const Vec2&) { return Vec2(3.0, -8.0); };
  change(problem);
  FrictionRun run;
  FactorizationOptions fo;
  fo.engine = linear;
  run.solution = solve_contact(problem, make_factorization(fo), *make_minimizer(minimizer), MinimizerOptions{}, &run.reduced);
  return run;
}

double max_abs(const Eigen::VectorXd& v) { return v.cwiseAbs().maxCoeff(); }

void write_text(const std::filesystem::path& file, const std::string& text) { std::ofstream(file) << text; }

// The solution of a linear problem whose bottom has the Dirichlet condition `fix` (u = 0 in
// the components fixed) instead of contact.
Eigen::VectorXd dirichlet_bottom(const Mesh& mesh, std::array<bool, 2> fix) {
  ContactProblem problem = example_4_1(mesh);
  for (auto& t : problem.elasticity.tractions) t.traction = [](const Vec2&) { return Vec2(3.0, -8.0); };
  problem.elasticity.dirichlet.push_back({problem.parts[0].facets, {}, fix});
  return test::solve(assemble(problem.elasticity));
}

TEST(FrictionExample, BilateralWithoutFrictionIsARollerSupport) {
  const Mesh mesh = make_squares(12);
  const FrictionRun r = solve(mesh, [](ContactProblem& p) { p.parts[0].constraint = ConstraintKind::bilateral; });
  ASSERT_TRUE(r.solution.converged()) << r.solution.message;
  EXPECT_EQ(r.reduced.size(), static_cast<Eigen::Index>(r.solution.contact.size())) << "tangential unknowns only";
  const Eigen::VectorXd roller = dirichlet_bottom(mesh, {false, true});
  EXPECT_LT(max_abs(r.solution.u - roller), 1e-10 * max_abs(roller));
  for (const auto& n : r.solution.contact) {
    EXPECT_EQ(n.state, ContactState::tied);
    EXPECT_EQ(n.friction_force, 0.0);
  }
}

TEST(FrictionExample, BilateralWithAHugeTrescaBoundSticksEverywhereLikeAClampedBottom) {
  const Mesh mesh = make_squares(12);
  const FrictionRun r = solve(mesh, [](ContactProblem& p) {
    p.parts[0].constraint = ConstraintKind::bilateral;
    p.parts[0].friction = tresca_law(1e6);
  });
  ASSERT_TRUE(r.solution.converged()) << r.solution.message;
  const Eigen::VectorXd clamped = dirichlet_bottom(mesh, {true, true});
  EXPECT_LT(max_abs(r.solution.u - clamped), 1e-10 * max_abs(clamped));
  // the forces that hold the bottom: the reactions K u - f of the clamped problem, from the
  // global stiffness and load (no condensation): normal (nu = (0, -1)) and tangential (tau = (1, 0))
  ContactProblem problem = example_4_1(mesh);
  for (auto& t : problem.elasticity.tractions) t.traction = [](const Vec2&) { return Vec2(3.0, -8.0); };
  const Eigen::VectorXd reaction =
      assemble_stiffness(mesh, problem.elasticity.materials, problem.elasticity.stabilization) * clamped -
      assemble_load(mesh, problem.elasticity.body_force, problem.elasticity.tractions);
  const double scale = max_abs(reaction);
  for (const auto& n : r.solution.contact) {
    EXPECT_EQ(n.u_tau, 0.0);
    EXPECT_EQ(n.friction_state, FrictionState::stick);
    EXPECT_NEAR(n.force(), -reaction.segment<2>(2 * n.vertex).dot(n.normal), 1e-8 * scale) << n.vertex;
    EXPECT_NEAR(n.friction_force, -reaction(2 * n.vertex), 1e-8 * scale) << n.vertex;
  }
  // and the resultant balances the load with the side clamps' reactions
  Vec2 bottom = Vec2::Zero();
  for (const auto& n : r.solution.contact) bottom += reaction.segment<2>(2 * n.vertex);
  EXPECT_LT((r.solution.contact_force() - bottom).norm(), 1e-8 * scale);
}

TEST(FrictionExample, ZeroFrictionBoundGivesTheFrictionlessSolution) {
  const Mesh mesh = make_squares(16);
  const FrictionRun plain = solve(mesh, [](ContactProblem&) {});
  const FrictionRun zero = solve(mesh, [](ContactProblem& p) { p.parts[0].friction = tresca_law(0.0); });
  ASSERT_TRUE(plain.solution.converged() && zero.solution.converged());
  EXPECT_EQ(zero.reduced.size(), 2 * plain.reduced.size());
  EXPECT_LT(max_abs(zero.solution.u - plain.solution.u), 1e-9 * max_abs(plain.solution.u));
  for (const auto& n : zero.solution.contact) EXPECT_EQ(n.friction_force, 0.0);
}

TEST(FrictionExample, StickZoneGrowsWithTheBoundAndEveryEngineAgrees) {
  const Mesh mesh = make_squares(16);
  int previous_stick = -1;
  double previous_slip = kInf;
  for (const double g : {0.0, 0.2, 0.8, 1.5, 5.0}) {
    SCOPED_TRACE("g_F " + std::to_string(g));
    const FrictionRun r = solve(mesh, [g](ContactProblem& p) { p.parts[0].friction = tresca_law(g); });
    ASSERT_TRUE(r.solution.converged()) << r.solution.message;
    int stick = 0;
    double slip = 0.0;
    for (const auto& n : r.solution.contact) {
      stick += n.friction_state == FrictionState::stick;
      slip = std::max(slip, std::abs(n.u_tau));
      EXPECT_LE(std::abs(n.friction_force), g * n.weight * (1.0 + 1e-12));
    }
    EXPECT_GE(stick, previous_stick);
    EXPECT_LE(slip, previous_slip * (1.0 + 1e-12));
    previous_stick = stick;
    previous_slip = slip;
    if (g == 0.8) {
      EXPECT_GT(stick, 0);
      EXPECT_LT(stick, static_cast<int>(r.solution.contact.size())) << "a mixed stick/slip state";
      for (const std::string& m : available_minimizers()) {
        SCOPED_TRACE(m);
        const MinimizerResult other = make_minimizer(m)->minimize(r.reduced, Eigen::VectorXd(), MinimizerOptions{});
        ASSERT_TRUE(other.converged()) << other.message;
        EXPECT_LT(max_abs(other.a - r.solution.minimizer->a), 1e-7 * max_abs(r.solution.minimizer->a));
      }
    }
  }
  EXPECT_EQ(previous_slip, 0.0) << "a bound far above the load sticks everywhere";
}

TEST(FrictionExample, EnginesAcrossLinearBackendsAgree) {
  const Mesh mesh = make_squares(12);
  const auto change = [](ContactProblem& p) { p.parts[0].friction = tresca_law(0.2); };
  const FrictionRun ref = solve(mesh, change);
  for (const std::string& linear : available_factorizations()) {
    if (linear == "mumps-mpi") continue;
    SCOPED_TRACE(linear);
    const FrictionRun r = solve(mesh, change, "ssn", linear);
    EXPECT_LT((r.reduced.S - ref.reduced.S).cwiseAbs().maxCoeff(), 1e-10 * ref.reduced.S.cwiseAbs().maxCoeff());
    EXPECT_LT(max_abs(r.solution.u - ref.solution.u), 1e-9 * max_abs(ref.solution.u));
  }
}

TEST(FrictionExample, SlipWeakeningLosesTheMarginAndSaysSo) {
  const Mesh mesh = make_squares(16);
  // alpha = (g_s - g_k) / slip = 3500 against S's tangential diagonal ~ 50-80 and w = 1/16: the
  // margin goes negative and the problem may have several critical points
  const auto weakening = [](ContactProblem& p) { p.parts[0].friction = slip_weakening_law(0.4, 0.05, 1e-4); };
  const FrictionRun r = solve(mesh, weakening, "ceres-active-set");
  EXPECT_LT(r.solution.uniqueness_margin, 0.0);
  EXPECT_TRUE(r.solution.may_be_nonunique);
  ASSERT_TRUE(r.solution.converged()) << r.solution.message;
  // every engine that claims convergence holds a certified critical point (ssn's Newton steps
  // find no curvature on the falling branch and may stop at its iteration limit, unconverged)
  for (const std::string& m : available_minimizers()) {
    SCOPED_TRACE(m);
    const MinimizerResult other = make_minimizer(m)->minimize(r.reduced, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_TRUE(other.may_be_nonunique);
    if (other.converged()) EXPECT_TRUE(certificate(r.reduced, other.a, 1e-10).converged());
  }
  // a gentle weakening keeps the margin positive
  const FrictionRun mild = solve(mesh, [](ContactProblem& p) { p.parts[0].friction = slip_weakening_law(0.4, 0.35, 1.0); });
  EXPECT_GT(mild.solution.uniqueness_margin, 0.0);
  EXPECT_FALSE(mild.solution.may_be_nonunique);
}

// Reduced-problem files in the coordinate-wise form: a normal and a tangential coordinate
// written and read back, and the same point reached from the file.
TEST(FrictionFiles, CoordinateWiseProblemsRoundTripThroughFiles) {
  const Mesh mesh = make_squares(8);
  const FrictionRun r = solve(mesh, [](ContactProblem& p) { p.parts[0].friction = slip_weakening_law(0.4, 0.1, 0.01); });
  ASSERT_TRUE(r.reduced.coordinatewise());
  const auto dir = test::scratch("friction-reduced");
  write_reduced_problem(dir, r.reduced);
  EXPECT_TRUE(std::filesystem::exists(dir / "law1.txt"));
  EXPECT_FALSE(std::filesystem::exists(dir / "g.txt"));
  const ReducedProblem q = read_reduced_problem(dir);
  ASSERT_TRUE(q.coordinatewise());
  EXPECT_EQ(q.S, r.reduced.S);
  EXPECT_EQ(q.c, r.reduced.c);
  EXPECT_EQ(q.w, r.reduced.w);
  EXPECT_EQ(q.law_index, r.reduced.law_index);
  EXPECT_EQ(q.lo, r.reduced.lo);
  EXPECT_EQ(q.hi, r.reduced.hi);
  EXPECT_EQ(q.uniqueness_margin, r.reduced.uniqueness_margin);
  ASSERT_EQ(q.num_laws(), 2);
  EXPECT_EQ(q.law_by_number(1).name(), "slip-weakening");
  for (double a : {-0.02, -0.005, 0.0, 0.003, 0.05})
    EXPECT_EQ(q.law_by_number(1).value(LawPart::j, a), r.reduced.law_by_number(1).value(LawPart::j, a));
  const MinimizerResult again = make_minimizer("ssn")->minimize(q, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(again.converged());
  EXPECT_LT(max_abs(again.a - r.solution.minimizer->a), 1e-12 * max_abs(r.solution.minimizer->a));
  // the uniform form written over it leaves no coordinate-wise file behind
  const FrictionRun plain = solve(mesh, [](ContactProblem&) {});
  write_reduced_problem(dir, plain.reduced);
  EXPECT_FALSE(std::filesystem::exists(dir / "coordinates.txt"));
  EXPECT_FALSE(std::filesystem::exists(dir / "law1.txt"));
  EXPECT_FALSE(read_reduced_problem(dir).coordinatewise());
}

TEST(FrictionFiles, DefectsNameTheFileAndLine) {
  const auto dir = test::scratch("friction-reduced-bad");
  write_reduced_problem(dir, spring(2.0, 0.5, 1.0, tresca_law(0.1)));
  // one law without bounds is written in the uniform form (constraint none); read it per coordinate
  write_text(dir / "problem.txt", "form coordinate-wise\nlaws 1\n");
  auto error_with = [&](const std::string& file, const std::string& text) {
    write_text(dir / file, text);
    return test::input_error_of([&] { (void)read_reduced_problem(dir); });
  };
  const std::string coordinates = (dir / "coordinates.txt").string();
  EXPECT_NE(error_with("coordinates.txt", "0 1 -1\n").find(coordinates + ":1"), std::string::npos);
  EXPECT_NE(error_with("coordinates.txt", "3 -inf inf\n").find("out of range"), std::string::npos);
  EXPECT_NE(error_with("coordinates.txt", "0 -inf\n").find("expected 'law lower upper'"), std::string::npos);
  write_text(dir / "coordinates.txt", "0 -inf inf\n");
  EXPECT_NE(error_with("problem.txt", "format 4\n").find("not one this program reads"), std::string::npos);
  const std::string mixed = error_with("problem.txt", "form coordinate-wise\nconstraint box\n");
  EXPECT_NE(mixed.find("not a constraint"), std::string::npos) << mixed;
}

}  // namespace
