// The certificate of DESIGN §3 (certify(), interfaces/certificate.hpp) and the scaffolding every
// minimizer shares (MinimizerRun): invariance under changes of units, points the earlier
// natural residual certified wrongly, the problem with c = 0, and every engine's converged
// results checked against a recomputation written here from the reduced problem alone.
#include <hemivem/certificate.hpp>
#include <hemivem/minimizer_run.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "test_support.hpp"

using namespace hemivem;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// j in other units: lengths multiplied by L, forces by F (j~(r) = F L j(r / L)).
class ScaledLaw final : public ContactLaw {
 public:
  ScaledLaw(std::shared_ptr<const ContactLaw> base, double force, double length)
      : base_(std::move(base)), F_(force), L_(length) {}
  std::string name() const override { return "scaled " + base_->name(); }
  double value(LawPart part, double r) const override { return F_ * L_ * base_->value(part, r / L_); }
  double derivative(LawPart part, double r, int side) const override { return F_ * base_->derivative(part, r / L_, side); }
  double second_derivative(LawPart part, double r, int side) const override {
    return F_ / L_ * base_->second_derivative(part, r / L_, side);
  }
  std::vector<double> breakpoints() const override {
    std::vector<double> b = base_->breakpoints();
    for (double& x : b) x *= L_;
    return b;
  }
  double alpha() const override { return F_ / L_ * base_->alpha(); }

 private:
  std::shared_ptr<const ContactLaw> base_;
  double F_, L_;
};

ReducedProblem random_problem(int n, std::shared_ptr<const ContactLaw> law, ConstraintKind kind, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = u(gen);
  Eigen::VectorXd c(n), w(n), g(n);
  for (int i = 0; i < n; ++i) {
    c(i) = 3.0 * u(gen);
    w(i) = 0.05 + 0.01 * u(gen);
    g(i) = 0.02 + 0.005 * u(gen);
  }
  return ReducedProblem::uniform(B * B.transpose() + 100.0 * Eigen::MatrixXd::Identity(n, n), c, w, std::move(law), kind, g);
}

// The problem in other units: forces x F, lengths x L.
ReducedProblem rescaled(const ReducedProblem& p, double F, double L) {
  const UniformForm u = *p.uniform_form();
  ReducedProblem q = ReducedProblem::uniform((F / L) * p.S, F * p.c, p.w, std::make_shared<ScaledLaw>(u.law, F, L),
                                             u.constraint, L * u.g);
  q.uniqueness_margin = p.uniqueness_margin;
  return q;
}

// A point with coordinates at bounds, at kinks, inside pieces and one slightly outside C.
Eigen::VectorXd mixed_point(const ReducedProblem& p) {
  Eigen::VectorXd a(p.size());
  const std::vector<double> kinks = p.law_by_number(0).kinks();
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    switch (i % 4) {
      case 0: a(i) = p.upper(i) < kInf ? p.upper(i) : 0.013; break;
      case 1: a(i) = kinks.empty() ? 0.004 : kinks.front(); break;
      case 2: a(i) = 0.0071 * ((i % 3) - 1.0); break;
      default: a(i) = 0.5 * p.c(i) / p.S(i, i); break;
    }
  }
  if (p.upper(0) < kInf) a(0) = p.upper(0) * (1.0 + 1e-3);  // outside C
  return a;
}

TEST(Certificate, UnchangedByTheUnitsOfForceAndLength) {
  for (const std::string law : {"paper", "kinked", "sawtooth", "linear"}) {
    for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided, ConstraintKind::none}) {
      SCOPED_TRACE(law + " / " + to_string(kind));
      const ReducedProblem p = random_problem(12, make_contact_law(law), kind, 7);
      const Eigen::VectorXd a = mixed_point(p);
      const CertifiedPoint base = certify(p, a, 1e-10);
      ASSERT_GT(base.certificate.dual, 1e-6) << "a point that is not a solution";
      for (const auto& [F, L] : std::vector<std::pair<double, double>>{{1e6, 1.0}, {1.0, 1e-4}, {3e-3, 250.0}}) {
        const ReducedProblem q = rescaled(p, F, L);
        const CertifiedPoint s = certify(q, L * a, 1e-10);
        EXPECT_NEAR(s.certificate.primal, base.certificate.primal, 1e-12 * (1.0 + base.certificate.primal)) << F << " " << L;
        EXPECT_NEAR(s.certificate.dual, base.certificate.dual, 1e-12 * base.certificate.dual) << F << " " << L;
        EXPECT_NEAR(s.certificate.length_scale, L * base.certificate.length_scale, 1e-12 * L * base.certificate.length_scale);
        EXPECT_NEAR(s.certificate.force_scale, F * base.certificate.force_scale, 1e-12 * F * base.certificate.force_scale);
        EXPECT_TRUE(((s.a - L * base.a).array().abs() <= 1e-14 * L).all()) << "the same coordinates are snapped";
        EXPECT_TRUE(((s.reaction - F * base.reaction).array().abs() <= 1e-9 * F).all());
      }
    }
  }
}

TEST(Certificate, SolutionsStayCertifiedInOtherUnits) {
  const ReducedProblem p = random_problem(10, paper_law(), ConstraintKind::box, 3);
  const MinimizerResult r = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(r.converged()) << r.message;
  for (const auto& [F, L] : std::vector<std::pair<double, double>>{{1e8, 1e-6}, {1e-5, 1e3}}) {
    const Certificate c = certificate(rescaled(p, F, L), L * r.a, 1e-10);
    EXPECT_TRUE(c.converged()) << c.primal << " " << c.dual;
    EXPECT_NEAR(c.dual, r.certificate.dual, 1e-3 * r.certificate.dual + 1e-15);
  }
}

// One node pushed by c against a box of width 2e-10 around 0: the solution is the upper bound.
ReducedProblem tiny_box(double gap = 1e-10, std::shared_ptr<const ContactLaw> law = paper_law()) {
  ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd::Constant(1, 1, 100.0), Eigen::VectorXd::Constant(1, 2.0),
                                             Eigen::VectorXd::Constant(1, 0.05), std::move(law), ConstraintKind::box,
                                             Eigen::VectorXd::Constant(1, gap));
  p.uniqueness_margin = 99.0;
  return p;
}

TEST(Certificate, AFeasiblePointInsideATinyBoxWithUnbalancedForcesIsNotASolution) {
  const ReducedProblem p = tiny_box();
  const Eigen::VectorXd inside = Eigen::VectorXd::Constant(1, 0.3e-10);
  const CertifiedPoint c = certify(p, inside, 1e-10);
  EXPECT_EQ(c.certificate.primal, 0.0);
  EXPECT_GT(c.certificate.dual, 0.5) << "S a - c = -2 is balanced by nothing";
  EXPECT_FALSE(c.certificate.converged());
  EXPECT_EQ(c.a(0), inside(0)) << "2e-11 away from a bound is not within tol * l = 2e-12";
  EXPECT_EQ(c.reaction(0), 0.0);
  // the bound itself: the reaction takes the force
  const CertifiedPoint at = certify(p, Eigen::VectorXd::Constant(1, 1e-10), 1e-10);
  EXPECT_TRUE(at.certificate.converged());
  EXPECT_NEAR(at.reaction(0), 2.0 - 100.0 * 1e-10 - 0.05 * 60.0 * 1e-10, 1e-15);
  // an engine stopped at once there reports it unconverged; allowed to run it converges
  for (const std::string& name : available_minimizers()) {
    MinimizerOptions o;
    o.max_iterations = 0;
    const MinimizerResult r = make_minimizer(name)->minimize(p, inside, o);
    EXPECT_FALSE(r.converged()) << name;
    EXPECT_EQ(r.status, MinimizerStatus::iteration_limit) << name;
    EXPECT_EQ(r.a(0), inside(0)) << name;
    const MinimizerResult full = make_minimizer(name)->minimize(p, inside, MinimizerOptions{});
    EXPECT_TRUE(full.converged()) << name << ": " << full.message;
    EXPECT_EQ(full.a(0), 1e-10) << name;
  }
}

TEST(Certificate, ZeroLoadIsSolvedByZero) {
  for (const std::string law : contact_law_names()) {
    for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided, ConstraintKind::none}) {
      SCOPED_TRACE(law + " / " + to_string(kind));
      ReducedProblem p = random_problem(6, make_contact_law(law), kind, 11);
      p.c.setZero();
      const CertifiedPoint c = certify(p, Eigen::VectorXd::Zero(6), 1e-10);
      EXPECT_EQ(c.certificate.primal, 0.0);
      EXPECT_EQ(c.certificate.dual, 0.0);
      EXPECT_TRUE(c.certificate.converged());
      for (const std::string& name : available_minimizers()) {
        const MinimizerResult r = make_minimizer(name)->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
        EXPECT_TRUE(r.converged()) << name << ": " << r.message;
        EXPECT_EQ(r.a.cwiseAbs().maxCoeff(), 0.0) << name;
      }
    }
  }
}

TEST(Certificate, SnapsWithinTheToleranceOntoBoundsAndKinks) {
  const ReducedProblem p = tiny_box(0.02, kinked_law());  // kink at 0
  // l = max(|a|, g, c / S) = 0.02: the window is 2e-12
  const CertifiedPoint far = certify(p, Eigen::VectorXd::Constant(1, 0.02 - 1e-11), 1e-10);
  EXPECT_EQ(far.a(0), 0.02 - 1e-11);
  EXPECT_NEAR(far.certificate.dual, 0.05 * (0.3 + 100.0 * 0.02) / 2.0, 1e-9) << "the law force alone, unbalanced";
  const CertifiedPoint near = certify(p, Eigen::VectorXd::Constant(1, 0.02 - 1e-12), 1e-10);
  EXPECT_EQ(near.a(0), 0.02);
  const CertifiedPoint beyond = certify(p, Eigen::VectorXd::Constant(1, 0.02 + 1e-12), 1e-10);
  EXPECT_EQ(beyond.a(0), 0.02);
  EXPECT_EQ(beyond.certificate.primal, 0.0);
  const CertifiedPoint outside = certify(p, Eigen::VectorXd::Constant(1, 0.0201), 1e-10);
  EXPECT_NEAR(outside.certificate.primal, 1e-4 / 0.0201, 1e-12);
  const CertifiedPoint kink = certify(p, Eigen::VectorXd::Constant(1, -1e-12), 1e-10);
  EXPECT_EQ(kink.a(0), 0.0);
  EXPECT_EQ(kink.reaction(0), 0.0);
  // at the kink the law force is the point of w [0, sigma] nearest to -(S a - c) = 2: w sigma
  EXPECT_NEAR(kink.law_force(0), 0.05 * 0.3, 1e-15);
  EXPECT_EQ(certify(p, Eigen::VectorXd::Constant(1, std::nan("")), 1e-10).certificate.dual, kInf);
  EXPECT_EQ(certify(p, Eigen::VectorXd::Zero(2), 1e-10).certificate.primal, kInf);
}

TEST(Certificate, NoConstraintNeverReportsAReaction) {
  ReducedProblem p = random_problem(8, paper_law(), ConstraintKind::none, 5);
  const MinimizerResult r = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(r.converged());
  EXPECT_EQ(r.reaction.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(count_at_bound(p, r.a), 0);
}

// ---- every engine, every shipped law: the converged results, recomputed here ---------------

// The KKT residual of a from the reduced problem alone: per coordinate the distance of
// -(S a - c)_i to the set of forces w_i [j'(a-), j'(a+)] + N_C(a_i); divided by the largest of
// |c|, |S a| and the law forces used. Returns max(that, infeasibility / l).
double recomputed_residual(const ReducedProblem& p, const Eigen::VectorXd& a) {
  const Eigen::VectorXd r = p.S * a - p.c;
  double worst = 0.0, force = std::max(p.c.cwiseAbs().maxCoeff(), (p.S * a).cwiseAbs().maxCoeff());
  double ell = a.cwiseAbs().maxCoeff(), infeasible = 0.0;
  const UniformForm u = *p.uniform_form();
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    ell = std::max(ell, std::abs(p.c(i)) / p.S(i, i));
    if (u.constraint != ConstraintKind::none) ell = std::max(ell, u.g(i));
    const double lo = u.constraint == ConstraintKind::box ? -u.g(i) : -kInf;
    const double hi = u.constraint == ConstraintKind::none ? kInf : u.g(i);
    infeasible = std::max({infeasible, lo - a(i), a(i) - hi});
    const double d1 = p.w(i) * u.law->derivative(LawPart::j, a(i), -1);
    const double d2 = p.w(i) * u.law->derivative(LawPart::j, a(i), +1);
    const double f_lo = std::min(d1, d2) + (a(i) == lo ? -kInf : 0.0);
    const double f_hi = std::max(d1, d2) + (a(i) == hi ? kInf : 0.0);
    const double target = -r(i);
    const double dist = target < f_lo ? f_lo - target : (target > f_hi ? target - f_hi : 0.0);
    worst = std::max(worst, dist);
    force = std::max(force, std::abs(std::clamp(target, std::min(d1, d2), std::max(d1, d2))));
  }
  return std::max(worst / force, infeasible / ell);
}

class EveryEngine : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryEngine, ConvergedResultsPassAnIndependentRecomputation) {
  int converged = 0;
  for (const std::string& law : contact_law_names()) {
    for (ConstraintKind kind : {ConstraintKind::box, ConstraintKind::one_sided, ConstraintKind::none}) {
      SCOPED_TRACE(law + " / " + to_string(kind));
      auto ex = test::example("squares", 16, [&](ContactProblem& cp) {
        cp.parts[0].law = make_contact_law(law);
        cp.parts[0].constraint = kind;
      });
      const ReducedProblem& p = ex->condensation->reduced();
      const MinimizerResult r = make_minimizer(GetParam())->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
      if (!r.converged()) continue;
      ++converged;
      EXPECT_LE(recomputed_residual(p, r.a), 1e-10) << r.message;
      EXPECT_EQ(r.objective, p.energy(r.a));
    }
  }
  EXPECT_GE(converged, 9) << "at least the laws without kinks converge with every constraint";
}

INSTANTIATE_TEST_SUITE_P(Engines, EveryEngine, ::testing::ValuesIn(available_minimizers()),
                         [](const auto& info) {
                           std::string s = info.param;
                           std::replace(s.begin(), s.end(), '-', '_');
                           return s;
                         });

// ---- the two energies --------------------------------------------------------------------------

TEST(Energies, PotentialEnergyAndReducedObjectiveDifferByAConstant) {
  // Phi(u(a)) - F(a) must not depend on a (docs/reference/outputs.md, "Energies"): u(a) is the
  // back-substitution, Phi the potential energy over the free dofs
  auto ex = test::example("squares", 8);
  const ReducedProblem& p = ex->condensation->reduced();
  auto potential = [&](const Eigen::VectorXd& a) {
    const Eigen::VectorXd u = ex->condensation->back_substitute(a);
    Eigen::VectorXd uf(ex->system.dofs.num_free());
    for (int k = 0; k < uf.size(); ++k) uf(k) = u(ex->system.dofs.free_dof(k));
    double phi = 0.5 * uf.dot(ex->system.A * uf) - uf.dot(ex->system.b);
    for (Eigen::Index i = 0; i < a.size(); ++i) phi += p.w(i) * p.law_of(i).value(a(i));
    return phi;
  };
  const MinimizerResult r = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(r.converged());
  const double constant = potential(r.a) - r.objective;
  EXPECT_LT(constant, 0.0) << "-1/2 b2^T A22^-1 b2";
  for (double s : {0.0, 0.5, -0.7}) {
    const Eigen::VectorXd a = s * r.a + Eigen::VectorXd::Constant(r.a.size(), 0.001 * s);
    EXPECT_NEAR(potential(a) - p.energy(a), constant, 1e-12 * std::abs(constant)) << s;
  }
}

// ---- the scaffolding ------------------------------------------------------------------------

TEST(MinimizerRun, ACertifiedPointBeatsABetterLookingOne) {
  const ReducedProblem p = tiny_box();
  MinimizerOptions o;
  MinimizerRun run("test", p, Eigen::VectorXd(), o);
  EXPECT_EQ(run.start()(0), 0.0);
  EXPECT_FALSE(run.offer(Eigen::VectorXd::Constant(1, 0.5e-10)));
  EXPECT_TRUE(run.offer(Eigen::VectorXd::Constant(1, 1e-10)));
  EXPECT_FALSE(run.offer(Eigen::VectorXd::Constant(1, 0.9e-10)));
  EXPECT_EQ(run.best()(0), 1e-10);
  // a converged result never carries the reason a stage stopped
  const MinimizerResult r = run.finish(MinimizerStatus::stalled, "stalled in stage 2", "3 stages");
  EXPECT_TRUE(r.converged());
  EXPECT_EQ(r.message, "3 stages");
  const MinimizerResult at = run.finish(MinimizerStatus::stalled, "stalled in stage 2", "3 stages", &run.start());
  EXPECT_EQ(at.status, MinimizerStatus::stalled);
  EXPECT_EQ(at.message, "stalled in stage 2; 3 stages");
}

TEST(MinimizerRun, CountsRecordsAndChecks) {
  const ReducedProblem p = tiny_box();
  MinimizerOptions o;
  o.max_evaluations = 3;
  int calls = 0;
  o.callback = [&](const IterationRecord& r) { return ++calls < 2 && r.iteration > 0; };
  MinimizerRun run("test", p, Eigen::VectorXd(), o);
  run.count_functions(2);
  EXPECT_TRUE(run.budget_left(1));
  EXPECT_FALSE(run.budget_left(2));
  EXPECT_TRUE(run.record(Eigen::VectorXd::Constant(1, 0.5e-10)));
  EXPECT_FALSE(run.record(Eigen::VectorXd::Constant(1, 1e-10)));
  const MinimizerResult r = run.finish(MinimizerStatus::stopped_by_callback);
  ASSERT_EQ(r.history.size(), 2u);
  EXPECT_EQ(r.history[1].iteration, 2);
  EXPECT_EQ(r.history[1].active, 1);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_EQ(r.function_evaluations, 2);
  EXPECT_TRUE(r.timings.count("total"));
  EXPECT_FALSE(r.may_be_nonunique);
  // bad input names the engine
  MinimizerOptions bad;
  bad.tolerance = 0.0;
  EXPECT_THROW(MinimizerRun("test", p, Eigen::VectorXd(), bad), InputError);
  EXPECT_THROW(MinimizerRun("test", p, Eigen::VectorXd::Zero(3), o), InputError);
  ReducedProblem broken = p;
  broken.w.resize(2);
  try {
    MinimizerRun("some-engine", broken, Eigen::VectorXd(), o);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("some-engine"), std::string::npos) << e.what();
  }
}

TEST(MinimizerRun, EveryEngineAnswersTheEmptyProblem) {
  const ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd(0, 0), Eigen::VectorXd(), Eigen::VectorXd(), paper_law(),
                                                   ConstraintKind::box, Eigen::VectorXd());
  for (const std::string& name : available_minimizers()) {
    const MinimizerResult r = make_minimizer(name)->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
    EXPECT_TRUE(r.converged()) << name;
    EXPECT_EQ(r.message, "empty problem");
    EXPECT_EQ(r.certificate.dual, 0.0);
  }
}

TEST(ContactLaw, OneDefinitionOfAKink) {
  EXPECT_EQ(paper_law()->kinks(), std::vector<double>{});
  EXPECT_EQ(kinked_law()->kinks(), std::vector<double>{0.0});
  EXPECT_EQ(sawtooth_law(100.0, 0.01, 0.2, 0.02)->kinks(), std::vector<double>{0.01}) << "j' is continuous at 0 and r2";
  EXPECT_EQ(ScaledLaw(kinked_law(), 1e9, 1e-9).kinks(), std::vector<double>{0.0});
}

}  // namespace
