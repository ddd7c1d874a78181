// The whole pipeline: assembly, condensation, minimization, back-substitution.
#include <hemivem/contact/solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/scene/example.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

TEST(ContactSolver, EveryDisplacementPrescribedIsAnInputError) {
  const Mesh mesh = make_squares(1);
  ContactProblem p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{65.0, 0.29}, PlaneModel::strain);
  std::vector<int> all;
  for (int e : mesh.boundary_edges()) all.push_back(e);
  p.elasticity.dirichlet.push_back({all, {}, {true, true}});
  try {
    (void)solve_contact(p, eigen_engine(), *make_minimizer(available_minimizers().front()), MinimizerOptions{});
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to solve"), std::string::npos) << e.what();
  }
}

TEST(ContactSolver, Example41RunsEveryStage) {
  if (!have_ssn()) GTEST_SKIP() << "the ssn minimizer was not built";
  const Mesh mesh = make_squares(16);
  const ContactProblem p = example_4_1(mesh);
  MinimizerOptions o;
  o.tolerance = 1e-10;
  const ContactSolution s = solve_contact(p, eigen_engine(), *make_minimizer("ssn"), o);
  EXPECT_TRUE(s.converged()) << s.message;
  EXPECT_EQ(s.stages, (std::vector<std::string>{"assembly", "condensation", "minimize", "back_substitution"}));
  EXPECT_GT(s.uniqueness_margin, 0.0);
  ASSERT_EQ(s.contact.size(), 15u);
  for (const auto& node : s.contact) {
    // u_nu is the normal component of the displacement (normal (0, -1) on the bottom)
    EXPECT_NEAR(node.u_nu, -s.u(2 * node.vertex + 1), 1e-12);
    EXPECT_LE(std::abs(node.u_nu), 0.02 + 1e-15);
    if (node.state == ContactState::at_gap) EXPECT_GE(node.reaction, 0.0);
    if (!at_a_bound(node.state)) EXPECT_EQ(node.reaction, 0.0);
  }
  for (const char* stage : {"assembly", "condensation", "minimize", "back_substitution", "total"})
    EXPECT_TRUE(s.timings.count(stage)) << stage;
}

// the options are the solver's own copy: a temporary given to the constructor is gone before run()
TEST(ContactSolver, OptionsGivenAsATemporaryAreKept) {
  if (!have_ssn()) GTEST_SKIP() << "the ssn minimizer was not built";
  const Mesh mesh = make_squares(8);
  const ContactProblem p = example_4_1(mesh);
  ContactSolver solver(p, eigen_engine(), [] {
    MinimizerOptions o;
    o.tolerance = 1e-11;
    o.max_iterations = 50;
    return o;
  }());
  const auto ssn = make_minimizer("ssn");
  const NonsmoothMinimizer* one[] = {ssn.get()};
  const ContactSolution s = std::move(solver.run(one).front());
  EXPECT_TRUE(s.converged()) << s.message;
  EXPECT_LE(s.certificate.worst(), 1e-11);
}

TEST(ContactSolver, WithoutAConstraintNoNodeIsAtABoundAndNoReactionIsReported) {
  // constraint "none": the bounds are infinite, so every node is free and the contact force
  // is the law's alone (balancing S a - c to the tolerance)
  const Mesh mesh = make_squares(16);
  ContactProblem p = example_4_1(mesh);
  p.parts[0].constraint = ConstraintKind::none;
  const ContactSolution s = solve_contact(p, eigen_engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(s.converged()) << s.message;
  ASSERT_EQ(s.contact.size(), 15u);
  double largest = 0.0, deepest = 0.0;
  for (const auto& node : s.contact) {
    EXPECT_FALSE(at_a_bound(node.state)) << node.vertex;
    // off the bounds the state is the sign of the law's force: pressed in, or separated
    EXPECT_EQ(node.state, node.law_force > 0.0 ? ContactState::in_contact : ContactState::separated) << node.vertex;
    EXPECT_EQ(node.reaction, 0.0) << node.vertex;
    largest = std::max(largest, std::abs(node.law_force));
    deepest = std::max(deepest, node.u_nu);
  }
  EXPECT_GT(deepest, 0.02) << "without the gap the load presses the middle nodes past it";
  EXPECT_GT(largest, 0.0) << "the law carries the load";
}

TEST(ContactSolver, ContactForcesBalanceTheLoad) {
  // Example 4.1: the clamped sides and the contact nodes carry the traction (0, -8) on the top
  // (length 1); the contact forces are the certificate's zeta + lambda, each >= 0 here
  // (compression), and the pressure is the force per length w_i.
  const Mesh mesh = make_squares(16);
  const ContactSolution s = solve_contact(example_4_1(mesh), eigen_engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(s.converged());
  double total = 0.0;
  for (const auto& node : s.contact) {
    EXPECT_GE(node.force(), -1e-12) << node.vertex;
    EXPECT_DOUBLE_EQ(node.pressure(), node.force() / node.weight);
    if (node.state == ContactState::at_gap) EXPECT_GT(node.reaction, 0.0) << node.vertex;
    total += node.force();
  }
  EXPECT_GT(total, 0.0);
  EXPECT_LT(total, 8.0) << "the clamped sides carry the rest of the load";
}

TEST(ContactSolver, NoContactBoundaryIsOneLinearSolve) {
  const Mesh mesh = make_squares(8);
  ContactProblem p = example_4_1(mesh);
  p.parts.clear();
  // any minimizer object will do: it is not called
  struct Unused final : NonsmoothMinimizer {
    std::string name() const override { return "unused"; }
   protected:
    MinimizerResult run(MinimizerRun&) const override {
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

namespace hemivem {
namespace {

TEST(ContactStates, AreWordsBothWays) {
  for (ContactState s : {ContactState::separated, ContactState::in_contact, ContactState::in_tension,
                         ContactState::at_gap, ContactState::at_minus_gap, ContactState::tied})
    EXPECT_EQ(contact_state_from_string(to_string(s)), s);
  EXPECT_EQ(to_string(ContactState::at_gap), "at-gap");
  EXPECT_EQ(to_string(ContactState::in_contact), "in-contact");
  EXPECT_EQ(to_string(ContactState::tied), "tied");
  EXPECT_THROW(contact_state_from_string("in contact"), InputError);
  EXPECT_THROW(contact_state_from_string("upper"), InputError);
  // at a bound by position, off them by the sign of the law's force
  EXPECT_EQ(contact_state(0.02, -0.02, 0.02, 0.0), ContactState::at_gap);
  EXPECT_EQ(contact_state(-0.02, -0.02, 0.02, 5.0), ContactState::at_minus_gap);
  EXPECT_EQ(contact_state(0.01, -0.02, 0.02, 3.0), ContactState::in_contact);
  EXPECT_EQ(contact_state(-0.01, -0.02, 0.02, -3.0), ContactState::in_tension);
  EXPECT_EQ(contact_state(-0.01, -std::numeric_limits<double>::infinity(), 0.02, 0.0), ContactState::separated);
  EXPECT_TRUE(at_a_bound(ContactState::tied));
  EXPECT_FALSE(at_a_bound(ContactState::in_contact));
  for (FrictionState s : {FrictionState::none, FrictionState::stick, FrictionState::slip, FrictionState::slip_weakening,
                          FrictionState::slip_kinetic})
    EXPECT_EQ(friction_state_from_string(to_string(s)), s);
  EXPECT_EQ(to_string(FrictionState::none), "");
  EXPECT_EQ(to_string(FrictionState::slip_weakening), "slip-weakening");
  EXPECT_THROW(friction_state_from_string("sliding"), InputError);
}

}  // namespace
}  // namespace hemivem
