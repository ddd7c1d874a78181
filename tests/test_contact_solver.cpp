// The whole pipeline: assembly, condensation, minimization, back-substitution.
#include <hemivem/contact_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/piecewise_law.hpp>

#include <gtest/gtest.h>

using namespace hemivem;

namespace {

std::unique_ptr<SparseFactorization> eigen_engine() {
  FactorizationOptions o;
  o.engine = "eigen";
  return make_factorization(o);
}

bool have_ssn() {
  const auto m = available_minimizers();
  return std::find(m.begin(), m.end(), "ssn") != m.end();
}

TEST(ContactSolver, Example41RunsEveryStage) {
  if (!have_ssn()) GTEST_SKIP() << "the ssn minimizer was not built";
  const Mesh mesh = make_squares(16);
  const ContactProblem p = example_4_1(mesh);
  MinimizerOptions o;
  o.tolerance = 1e-10;
  const ContactSolution s = solve_contact(p, eigen_engine(), *make_minimizer("ssn"), o);
  EXPECT_TRUE(s.converged()) << s.minimizer.message;
  EXPECT_EQ(s.stages, (std::vector<std::string>{"assembly", "condensation", "minimize", "back_substitution"}));
  EXPECT_GT(s.uniqueness_margin, 0.0);
  ASSERT_EQ(s.contact.size(), 15u);
  for (const auto& node : s.contact) {
    // u_nu is the normal component of the displacement (normal (0, -1) on the bottom)
    EXPECT_NEAR(node.u_nu, -s.u(2 * node.vertex + 1), 1e-12);
    EXPECT_LE(std::abs(node.u_nu), 0.02 + 1e-15);
    if (node.state == "upper") EXPECT_GE(node.multiplier, 0.0);
    if (node.state == "free") EXPECT_EQ(node.multiplier, 0.0);
  }
  for (const char* stage : {"assembly", "condensation", "minimize", "back_substitution", "total"})
    EXPECT_TRUE(s.timings.count(stage)) << stage;
}

TEST(ContactSolver, NoContactBoundaryIsOneLinearSolve) {
  const Mesh mesh = make_squares(8);
  ContactProblem p = example_4_1(mesh);
  p.contact_edges.clear();
  // any minimizer object will do: it is not called
  struct Unused final : NonsmoothMinimizer {
    std::string name() const override { return "unused"; }
    MinimizerResult minimize(const ReducedProblem&, const Eigen::VectorXd&, const MinimizerOptions&) const override {
      ADD_FAILURE() << "the minimizer must not run without a contact boundary";
      return {};
    }
  } unused;
  const ContactSolution s = solve_contact(p, eigen_engine(), unused, MinimizerOptions{});
  EXPECT_EQ(s.stages, (std::vector<std::string>{"assembly", "linear_solve"}));
  EXPECT_TRUE(s.converged());
  EXPECT_TRUE(s.contact.empty());
  EXPECT_LT(s.u.minCoeff(), 0.0);
}

}  // namespace
