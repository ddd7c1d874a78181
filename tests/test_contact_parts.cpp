// Several contact parts (docs/contact-parts.md): the contact boundary, the condensation with
// conditions per node, the solve, the path and the scene's [[contact]], each checked against
// something independent: one part of the same edges, the condensation of one part reduced by
// hand (a Schur complement, a restriction, laws and bounds set per coordinate) and solved by
// another engine, the balance of forces, Tresca's law against a constant bound table.
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/estimate/error_estimate.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Cholesky>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "test_support.hpp"

using namespace hemivem;
namespace fs = std::filesystem;

namespace {

std::unique_ptr<SparseFactorization> engine(const std::string& name = "eigen") {
  FactorizationOptions fo;
  fo.engine = name;
  return make_factorization(fo);
}

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

// Example 4.1 with the top traction (tx, -8).
ContactProblem example(const Mesh& mesh, double tx = 0.0) {
  ContactProblem problem = example_4_1(mesh);
  for (auto& t : problem.elasticity.tractions) t.traction = [tx](const Vec2&) { return Vec2(tx, -8.0); };
  return problem;
}

// The problem's one contact part, its edges split at x = 0.5 into "left" and "right" (in
// that order unless `right_first`), each with the first part's data; `change` edits them.
void split_bottom(ContactProblem& p, const std::function<void(ContactPart& left, ContactPart& right)>& change = {},
                  bool right_first = false) {
  std::vector<ContactPart> parts = contact_parts(p);
  ContactPart left = parts.front(), right = parts.front();
  left.name = "left";
  right.name = "right";
  left.facets.clear();
  right.facets.clear();
  const Mesh& mesh = *p.elasticity.mesh;
  for (int id : parts.front().facets) {
    const MeshEdge& e = mesh.edge(id);
    (0.5 * (mesh.vertex(e.v0).x() + mesh.vertex(e.v1).x()) < 0.5 ? left : right).facets.push_back(id);
  }
  if (change) change(left, right);
  p.parts = right_first ? std::vector<ContactPart>{right, left} : std::vector<ContactPart>{left, right};
}

struct Solved {
  ContactSolution solution;
  ReducedProblem reduced;
};

Solved solve(const ContactProblem& p, const std::string& minimizer = "ssn") {
  Solved r;
  r.solution = solve_contact(p, engine(), *make_minimizer(minimizer), MinimizerOptions{}, &r.reduced);
  return r;
}

// The rows and columns `keep` of S, the others (`drop`) eliminated: S_kk - S_kd S_dd^-1 S_dk,
// and c the same way.
void eliminate(const ReducedProblem& full, const std::vector<int>& keep, const std::vector<int>& drop,
               Eigen::MatrixXd* S, Eigen::VectorXd* c) {
  auto block = [&](const std::vector<int>& r, const std::vector<int>& q) {
    Eigen::MatrixXd B(r.size(), q.size());
    for (std::size_t i = 0; i < r.size(); ++i)
      for (std::size_t j = 0; j < q.size(); ++j) B(i, j) = full.S(r[i], q[j]);
    return B;
  };
  auto part = [&](const std::vector<int>& r) {
    Eigen::VectorXd v(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) v(i) = full.c(r[i]);
    return v;
  };
  *S = block(keep, keep);
  *c = part(keep);
  if (drop.empty()) return;
  const Eigen::LLT<Eigen::MatrixXd> dd(block(drop, drop));
  *S -= block(keep, drop) * dd.solve(block(drop, keep));
  *c -= block(keep, drop) * dd.solve(part(drop));
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
}

}  // namespace

// ---- the contact boundary ---------------------------------------------------------------

TEST(ContactParts, OnePartIsTheSingleContactOfTheProblem) {
  const Mesh mesh = make_squares(8);
  ContactProblem p = example(mesh);
  const std::vector<ContactPart> parts = contact_parts(p);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].name, "contact");
  EXPECT_EQ(parts[0].facets, p.parts[0].facets);
  EXPECT_EQ(parts[0].law, p.parts[0].law);
  ContactProblem none = example(mesh);
  none.parts.clear();
  EXPECT_TRUE(contact_parts(none).empty());
  EXPECT_TRUE(none.parts.empty());
  // the boundary of one part is make_contact_boundary's of its edges
  const LinearSystem system = assemble(p.elasticity);
  const ContactBoundary a = contact_boundary(p, system.dofs);
  const ContactBoundary b = make_contact_boundary(mesh, p.parts[0].facets, system.dofs, p.parts[0].gap);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_EQ(a.gaps, b.gaps);
  EXPECT_EQ(a.part, std::vector<int>(a.nodes.size(), 0));
}

TEST(ContactParts, ANodeWherePartsMeetBelongsToThePartListedFirst) {
  const Mesh mesh = make_squares(8);
  const ContactProblem one = example(mesh);
  const LinearSystem system = assemble(one.elasticity);
  const ContactBoundary whole = contact_boundary(one, system.dofs);
  for (const bool right_first : {false, true}) {
    SCOPED_TRACE(right_first ? "right listed first" : "left listed first");
    ContactProblem p = example(mesh);
    split_bottom(p, {}, right_first);
    const ContactBoundary b = contact_boundary(p, system.dofs);
    ASSERT_EQ(b.nodes, whole.nodes);
    EXPECT_EQ(b.weights, whole.weights) << "a node's weight comes from all its contact edges";
    for (std::size_t i = 0; i < b.nodes.size(); ++i) {
      EXPECT_EQ(b.normals[i], whole.normals[i]);
      const double x = mesh.vertex(b.nodes[i]).x();
      const std::string name = contact_parts(p)[static_cast<std::size_t>(b.part[i])].name;
      if (x < 0.5) EXPECT_EQ(name, "left");
      else if (x > 0.5) EXPECT_EQ(name, "right");
      else EXPECT_EQ(name, right_first ? "right" : "left") << "the node at x = 0.5";
    }
  }
}

TEST(ContactParts, AnEdgeInTwoPartsOrAPartWithoutNameOrEdgesIsRefused) {
  const Mesh mesh = make_squares(8);
  ContactProblem p = example(mesh);
  split_bottom(p, [](ContactPart& left, ContactPart& right) { right.facets.push_back(left.facets.back()); });
  const LinearSystem system = assemble(p.elasticity);
  const std::string m = test::input_error_of([&] { (void)contact_boundary(p, system.dofs); });
  EXPECT_NE(m.find("'left' and 'right'"), std::string::npos) << m;
  ContactProblem q = example(mesh);
  split_bottom(q, [](ContactPart&, ContactPart& right) { right.name = "left"; });
  EXPECT_NE(test::input_error_of([&] { (void)contact_parts(q); }).find("two contact parts are named 'left'"),
            std::string::npos);
  ContactProblem r = example(mesh);
  split_bottom(r, [](ContactPart&, ContactPart& right) { right.facets.clear(); });
  EXPECT_NE(test::input_error_of([&] { (void)contact_parts(r); }).find("'right' has no edges"), std::string::npos);
}

// ---- the condensation and the solve -----------------------------------------------------

// The same law on both halves: the reduced problem and the solution of one part, to the bit.
TEST(ContactParts, TwoPartsSplittingOneSideAreThatSide) {
  const Mesh mesh = make_squares(16);
  const Solved one = solve(example(mesh));
  for (const bool own_laws : {false, true}) {
    SCOPED_TRACE(own_laws ? "a law of each part's own" : "one law shared");
    ContactProblem p = example(mesh);
    split_bottom(p, [own_laws](ContactPart& left, ContactPart& right) {
      if (!own_laws) return;
      left.law = paper_law();
      right.law = paper_law();
    });
    const Solved two = solve(p);
    ASSERT_TRUE(two.solution.converged()) << two.solution.message;
    EXPECT_EQ(two.reduced.laws.size(), own_laws ? 2u : 1u) << "each distinct law once";
    EXPECT_EQ(two.reduced.S, one.reduced.S);
    EXPECT_EQ(two.reduced.c, one.reduced.c);
    EXPECT_EQ(two.reduced.lo, one.reduced.lo);
    EXPECT_EQ(two.reduced.hi, one.reduced.hi);
    EXPECT_EQ(two.reduced.w, one.reduced.w);
    EXPECT_LE(max_abs(two.solution.u - one.solution.u), 1e-13 * max_abs(one.solution.u));
    EXPECT_EQ(two.solution.contact_parts, (std::vector<std::string>{"left", "right"}));
    ASSERT_EQ(two.solution.contact.size(), one.solution.contact.size());
    for (std::size_t i = 0; i < one.solution.contact.size(); ++i) {
      const ContactNode& n = two.solution.contact[i];
      EXPECT_EQ(n.vertex, one.solution.contact[i].vertex);
      EXPECT_EQ(n.part, n.x.x() <= 0.5 ? 0 : 1);
      EXPECT_NEAR(n.force(), one.solution.contact[i].force(), 1e-12 * one.solution.certificate.force_scale);
    }
  }
  EXPECT_EQ(one.solution.contact_parts, std::vector<std::string>{"contact"});
}

// The condensation of one part with the old constructor and with the conditions of one part.
TEST(ContactParts, TheConditionsOfOnePartCondenseAsBefore) {
  const Mesh mesh = make_squares(12);
  for (const int kind : {0, 1, 2}) {
    SCOPED_TRACE(kind);
    ContactProblem p = example(mesh, 3.0);
    if (kind == 1) p.parts[0].friction = tresca_law(0.5);
    if (kind == 2) p.parts[0].constraint = ConstraintKind::bilateral;
    const LinearSystem system = assemble(p.elasticity);
    const ContactBoundary boundary = contact_boundary(p, system.dofs);
    const Condensation a(system, boundary, engine(), p.parts[0].law, constraint_in_effect(p.parts[0]), p.parts[0].friction);
    const Condensation b(system, boundary, engine(), part_conditions(contact_parts(p)));
    EXPECT_EQ(a.reduced().S, b.reduced().S);
    EXPECT_EQ(a.reduced().c, b.reduced().c);
    EXPECT_EQ(a.reduced().lo, b.reduced().lo);
    EXPECT_EQ(a.reduced().hi, b.reduced().hi);
    EXPECT_EQ(a.reduced().w, b.reduced().w);
    EXPECT_EQ(a.reduced().law_index, b.reduced().law_index);
    EXPECT_EQ(a.reduced().laws.size(), b.reduced().laws.size());
    for (int i = 0; i < boundary.size(); ++i) {
      EXPECT_EQ(a.normal_coordinate(i), kind == 2 ? -1 : i);
      EXPECT_EQ(a.tangential_coordinate(i), kind == 0 ? -1 : (kind == 1 ? boundary.size() : 0) + i);
    }
  }
}

// Friction on the left half, none on the right: the reduced problem is the one of friction
// everywhere with the right half's tangential displacements eliminated (a Schur complement
// by dense algebra), and every engine solves it to ssn's point.
TEST(ContactParts, FrictionOnOnePartBesideAFrictionlessPart) {
  const Mesh mesh = make_squares(16);
  const double bound = 0.8;
  ContactProblem everywhere = example(mesh, 3.0);
  everywhere.parts[0].friction = tresca_law(bound);
  const Solved full = solve(everywhere);
  ContactProblem p = example(mesh, 3.0);
  split_bottom(p, [bound](ContactPart& left, ContactPart&) { left.friction = tresca_law(bound); });
  const Solved mixed = solve(p);
  ASSERT_TRUE(mixed.solution.converged()) << mixed.solution.message;

  const LinearSystem system = assemble(p.elasticity);
  const ContactBoundary boundary = contact_boundary(p, system.dofs);
  const Condensation cond(system, boundary, engine(), part_conditions(contact_parts(p)));
  const int n = boundary.size();
  std::vector<int> keep, drop;
  int left = 0;
  for (int i = 0; i < n; ++i) keep.push_back(i);
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(cond.normal_coordinate(i), i);
    if (boundary.part[static_cast<std::size_t>(i)] == 0) {
      EXPECT_EQ(cond.tangential_coordinate(i), n + left++) << "all normals, then the tangentials of the left";
      keep.push_back(n + i);
    } else {
      EXPECT_EQ(cond.tangential_coordinate(i), -1);
      drop.push_back(n + i);
    }
  }
  ASSERT_EQ(mixed.reduced.size(), n + left);
  Eigen::MatrixXd S;
  Eigen::VectorXd c;
  eliminate(full.reduced, keep, drop, &S, &c);
  EXPECT_LT(relative(mixed.reduced.S, S), 1e-10);
  EXPECT_LT(relative(mixed.reduced.c, c), 1e-10);
  EXPECT_EQ(mixed.reduced.laws.size(), 2u);
  for (Eigen::Index k = n; k < mixed.reduced.size(); ++k) EXPECT_EQ(mixed.reduced.law_of(k).name(), "tresca");

  int stick = 0, slip = 0;
  for (const ContactNode& node : mixed.solution.contact) {
    if (node.part == 1) {
      EXPECT_TRUE(node.friction_state == FrictionState::none);
      EXPECT_EQ(node.friction_force, 0.0);
      continue;
    }
    EXPECT_LE(std::abs(node.friction_force), bound * node.weight * (1.0 + 1e-12));
    (node.friction_state == FrictionState::stick ? stick : slip) += 1;
  }
  EXPECT_GT(stick + slip, 0);
  for (const std::string& m : available_minimizers()) {
    SCOPED_TRACE(m);
    const MinimizerResult other = make_minimizer(m)->minimize(mixed.reduced, Eigen::VectorXd(), MinimizerOptions{});
    ASSERT_TRUE(other.converged()) << other.message;
    EXPECT_LT(max_abs(other.a - mixed.solution.minimizer->a), 1e-7 * max_abs(mixed.solution.minimizer->a));
  }
  EXPECT_LT(mixed.solution.forces.residual(), 1e-10);
}

// A bilateral left half (u_nu = 0, sliding freely) beside the paper's law on the right: the
// left normals are removed from the problem of friction everywhere (with j = 0 on every
// tangential) and the right tangentials eliminated.
TEST(ContactParts, ABilateralPartBesideAPartWithALaw) {
  const Mesh mesh = make_squares(12);
  ContactProblem everywhere = example(mesh, 3.0);
  everywhere.parts[0].friction = zero_law();
  const Solved full = solve(everywhere);
  ContactProblem p = example(mesh, 3.0);
  split_bottom(p, [](ContactPart& left, ContactPart&) { left.constraint = ConstraintKind::bilateral; });
  const Solved mixed = solve(p);
  ASSERT_TRUE(mixed.solution.converged()) << mixed.solution.message;
  std::vector<int> keep, keep_tangential, drop;
  const auto& nodes = mixed.solution.contact;
  const int n = static_cast<int>(nodes.size());
  for (int i = 0; i < n; ++i)
    if (nodes[static_cast<std::size_t>(i)].part == 1) keep.push_back(i);
  for (int i = 0; i < n; ++i) (nodes[static_cast<std::size_t>(i)].part == 0 ? keep : drop).push_back(n + i);
  Eigen::MatrixXd S;
  Eigen::VectorXd c;
  eliminate(full.reduced, keep, drop, &S, &c);
  ASSERT_EQ(mixed.reduced.size(), static_cast<Eigen::Index>(keep.size()));
  EXPECT_LT(relative(mixed.reduced.S, S), 1e-10);
  EXPECT_LT(relative(mixed.reduced.c, c), 1e-10);
  for (const ContactNode& node : nodes) {
    EXPECT_EQ(node.state == ContactState::tied, node.part == 0) << node.vertex;
    if (node.part == 0) EXPECT_EQ(node.u_nu, 0.0);
    if (node.part == 0) EXPECT_EQ(node.friction_force, 0.0);
  }
  EXPECT_LT(mixed.solution.forces.residual(), 1e-10);
}

// Different laws and constraints per part: the solver's reduced problem is the one of a single
// part with each coordinate's law and bounds set by hand, and a second engine solves that one
// to the solver's point.
TEST(ContactParts, TwoLawsAreTheirCoordinatesLawsSolvedByASecondEngine) {
  const Mesh mesh = make_squares(16);
  const auto kinked = kinked_law(0.3, 100.0);
  ContactProblem p = example(mesh);
  split_bottom(p, [&](ContactPart&, ContactPart& right) {
    right.law = kinked;
    right.constraint = ConstraintKind::one_sided;
    right.gap = [](const Vec2&) { return 0.01; };
  });
  const Solved two = solve(p);
  ASSERT_TRUE(two.solution.converged()) << two.solution.message;
  const Solved one = solve(example(mesh));
  ReducedProblem hand = one.reduced;
  hand.laws = {one.reduced.laws.front(), kinked};
  for (std::size_t i = 0; i < two.solution.contact.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    if (two.solution.contact[i].part == 0) continue;
    hand.law_index(k) = 1;
    hand.lo(k) = -std::numeric_limits<double>::infinity();
    hand.hi(k) = 0.01;
  }
  EXPECT_EQ(two.reduced.S, hand.S);
  EXPECT_EQ(two.reduced.c, hand.c);
  EXPECT_EQ(two.reduced.lo, hand.lo);
  EXPECT_EQ(two.reduced.hi, hand.hi);
  EXPECT_EQ(two.reduced.law_index, hand.law_index);
  EXPECT_TRUE(two.reduced.coordinatewise());
  int solved_by_others = 0;
  for (const std::string& m : available_minimizers()) {
    if (m == "ssn") continue;
    SCOPED_TRACE(m);
    const MinimizerResult other = make_minimizer(m)->minimize(hand, Eigen::VectorXd(), MinimizerOptions{});
    ASSERT_TRUE(other.converged()) << other.message;
    EXPECT_LT(max_abs(other.a - two.solution.minimizer->a), 1e-7 * max_abs(two.solution.minimizer->a));
    ++solved_by_others;
  }
  EXPECT_GT(solved_by_others, 0) << "no second engine is built";
  // the right half is bounded by its own gap, and its nodes at the bound are "at-gap"
  for (const ContactNode& n : two.solution.contact) {
    if (n.part == 1) EXPECT_LE(n.u_nu, 0.01);
    if (n.part == 1 && n.u_nu == 0.01) EXPECT_EQ(n.state, ContactState::at_gap);
  }
}

// The error estimate of two parts splitting one side is the estimate of that side.
TEST(ContactParts, TheErrorEstimateOfASplitSideIsTheSidesOwn) {
  const Mesh mesh = make_squares(12);
  for (const bool friction : {false, true}) {
    SCOPED_TRACE(friction ? "tresca" : "frictionless");
    ContactProblem one = example(mesh, 3.0);
    if (friction) one.parts[0].friction = tresca_law(0.8);
    ContactProblem two = example(mesh, 3.0);
    if (friction) two.parts[0].friction = tresca_law(0.8);
    split_bottom(two);
    const ErrorEstimate a = estimate_error(one, solve(one).solution);
    const ErrorEstimate b = estimate_error(two, solve(two).solution);
    EXPECT_NEAR(b.energy, a.energy, 1e-12 * a.energy);
    EXPECT_EQ(b.parts.at("friction") > 0.0, friction);
  }
  // friction on the left half only: the right half's tangential residual counts as contact
  ContactProblem p = example(mesh, 3.0);
  split_bottom(p, [](ContactPart& left, ContactPart&) { left.friction = tresca_law(0.8); });
  const ErrorEstimate e = estimate_error(p, solve(p).solution);
  EXPECT_GT(e.parts.at("friction"), 0.0);
  EXPECT_GT(e.parts.at("contact"), 0.0);
}

// ---- loading paths ---------------------------------------------------------------------

// Coulomb's law on the left half and a constant bound table on the right (the fixed point on
// some nodes only) is the path of Coulomb's law beside Tresca's with that bound.
TEST(ContactParts, APathWithABoundOnSomeNodes) {
  const Mesh mesh = make_squares(12);
  const auto minimizer = make_minimizer("ssn");
  const double mu = 0.3;
  auto with = [&](bool table) {
    ContactProblem p = example(mesh, 3.0);
    split_bottom(p, [&](ContactPart& left, ContactPart& right) {
      left.friction = tresca_law(1.0);
      left.friction_bound = FrictionBound{FrictionBound::Kind::coulomb, mu, {}};
      right.friction = tresca_law(table ? 1.0 : 0.8);
      if (table) right.friction_bound = FrictionBound{FrictionBound::Kind::normal_displacement, 0.0, {{{-1.0, 0.8}}, {{1.0, 0.8}}}};
    });
    return p;
  };
  ContactProblem a = with(false), b = with(true);
  const PathSolution tresca = solve_path(a, engine(), *minimizer, PathLoading{{0.5, 1.0}, {}});
  const PathSolution table = solve_path(b, engine(), *minimizer, PathLoading{{0.5, 1.0}, {}});
  ASSERT_TRUE(tresca.converged()) << tresca.steps.back().message;
  ASSERT_TRUE(table.converged()) << table.steps.back().message;
  EXPECT_LE(max_abs(tresca.last.u - table.last.u), 1e-8 * max_abs(tresca.last.u));
  EXPECT_EQ(tresca.last.contact_parts, (std::vector<std::string>{"left", "right"}));
  for (const PathStep& s : tresca.steps) {
    EXPECT_TRUE(s.fixed_point.converged);
    const double f = s.certificate.force_scale;
    for (std::size_t i = 0; i < s.contact.size(); ++i) {
      const ContactNode& n = s.contact[i];
      const double limit = n.part == 0 ? mu * std::max(n.force(), 0.0) : 0.8 * n.weight;
      EXPECT_LE(std::abs(n.friction_force), limit + 1e-9 * f) << n.vertex;
      if (n.part == 0) EXPECT_NEAR(s.friction_bound(static_cast<Eigen::Index>(i)) * n.weight, limit, 1e-9 * f);
    }
  }
}

// A frictionless part beside one with friction along a path: no slip there (NaN), the others'.
TEST(ContactParts, APathWithAFrictionlessPart) {
  const Mesh mesh = make_squares(10);
  const auto minimizer = make_minimizer("ssn");
  ContactProblem p = example(mesh, 3.0);
  split_bottom(p, [](ContactPart& left, ContactPart&) { left.friction = tresca_law(0.8); });
  const PathSolution path = solve_path(p, engine(), *minimizer, PathLoading{{0.5, 1.0}, {}});
  ASSERT_TRUE(path.converged()) << path.steps.back().message;
  const ContactSolution static_solve = solve(p).solution;
  EXPECT_LE(max_abs(path.last.u - static_solve.u), 1e-8 * max_abs(static_solve.u))
      << "a proportional path of Tresca's law with the stick of its first step";
  for (const PathStep& s : path.steps)
    for (std::size_t i = 0; i < s.contact.size(); ++i)
      EXPECT_EQ(std::isnan(s.slip(static_cast<Eigen::Index>(i))), s.contact[i].part == 1);
}

// ---- scenes ----------------------------------------------------------------------------

namespace {

const char* kTwoParts = R"(schema_version = 1
title = "two parts"

[mesh]
generator = "squares"
n = [16, 8]
domain = [0.0, 1.0, 0.0, 0.5]

[clamped]
side = "left"

[[contact]]
name = "support"
side = "bottom"
law = "paper"
gap = 0.02

[[contact]]
side = "top"
law = "zero"
constraint = "one-sided"

[contact.obstacle]
shape = "circle"
center = [0.7, 0.72]
radius = 0.25
)";

std::string with_line(const InputError& e) { return e.where() + ": " + e.detail(); }

}  // namespace

TEST(ContactPartScenes, AnArrayOfContactTablesIsParts) {
  const Scene s = parse_scene_string(kTwoParts, "two.toml");
  ASSERT_TRUE(s.contact.has_value());
  ASSERT_EQ(s.more_contact.size(), 1u);
  EXPECT_EQ(s.contact->name, "support");
  EXPECT_EQ(s.contact->constraint, ConstraintKind::box);
  EXPECT_TRUE(s.more_contact[0].obstacle.has_value());
  EXPECT_EQ(s.more_contact[0].constraint, ConstraintKind::one_sided);
  EXPECT_EQ(contact_parts(s).size(), 2u);
  EXPECT_EQ(contact_key(s, 1), "contact[1]");
  EXPECT_EQ(contact_part_name(s, 0), "support");
  EXPECT_EQ(contact_part_name(s, 1), "contact[1]");
  EXPECT_EQ(s.where("contact[1].constraint"), "two.toml:21");
  // written back as [[contact]] and read again, the same scene
  const std::string text = to_toml(s);
  EXPECT_NE(text.find("[[contact]]"), std::string::npos);
  EXPECT_EQ(text.find("\n[contact]\n"), std::string::npos);
  EXPECT_EQ(parse_scene_string(text, "again.toml"), s);
  // a [[contact]] of one table is [contact]
  const Scene a = parse_scene_string("schema_version = 1\n[[contact]]\nside = \"bottom\"\ngap = 0.01\n", "a.toml");
  const Scene b = parse_scene_string("schema_version = 1\n[contact]\nside = \"bottom\"\ngap = 0.01\n", "a.toml");
  EXPECT_EQ(a, b);
  EXPECT_TRUE(a.more_contact.empty());
  EXPECT_NE(to_toml(a).find("\n[contact]\n"), std::string::npos);
  EXPECT_EQ(contact_part_name(b, 0), "contact");
}

TEST(ContactPartScenes, BuiltIntoTheProblemsParts) {
  const Scene s = parse_scene_string(kTwoParts, "two.toml");
  const auto built = build_problem(s);
  const std::vector<ContactPart> parts = contact_parts(built->problem);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].name, "support");
  EXPECT_EQ(parts[1].name, "contact[1]");
  EXPECT_EQ(parts[0].facets.size(), 16u);
  EXPECT_EQ(parts[1].facets.size(), 16u);
  EXPECT_TRUE(parts[0].gap && !parts[0].obstacle);
  EXPECT_TRUE(parts[1].obstacle && !parts[1].gap);
  EXPECT_EQ(parts[1].law->name(), "zero");
  EXPECT_TRUE(scene_is_proportional(s));
  // the data at t per part: the second part's obstacle moves, the first part's gap mentions t
  Scene moving = s;
  apply_overrides(moving, {"contact[1].obstacle.motion=[0.0, \"-0.01*t\"]", "contact[0].gap=\"0.02*t\""});
  EXPECT_FALSE(scene_is_proportional(moving));
  auto mb = build_problem(moving);
  set_load_factor(moving, 0.5, mb->problem);
  EXPECT_DOUBLE_EQ(mb->problem.parts[0].gap(Vec2(0.5, 0.0)), 0.01);
  EXPECT_DOUBLE_EQ(mb->problem.parts[1].obstacle->center.y(), 0.72 - 0.005);
}

TEST(ContactPartScenes, OverridesNameTheirPart) {
  Scene s = parse_scene_string(kTwoParts, "two.toml");
  apply_override(s, "contact[1].constraint=none");
  EXPECT_EQ(s.more_contact[0].constraint, ConstraintKind::none);
  apply_override(s, "contact[0].name=floor");
  EXPECT_EQ(contact_part_name(s, 0), "floor");
  try {
    apply_override(s, "contact.gap=0.01");
    ADD_FAILURE() << "contact.gap names no part of two";
  } catch (const InputError& e) {
    EXPECT_NE(e.detail().find("contact[1].gap"), std::string::npos) << e.detail();
    EXPECT_EQ(e.where(), "--set contact.gap");
  }
  try {
    apply_override(s, "contact[0].gap=-1");
    ADD_FAILURE() << "a negative gap";
  } catch (const InputError& e) {
    EXPECT_NE(with_line(e).find("must be >= 0"), std::string::npos) << with_line(e);
  }
  // one [contact] table: "contact[0].x" is its key too
  Scene one = parse_scene_string("schema_version = 1\n[contact]\nside = \"bottom\"\ngap = 0.01\n", "one.toml");
  apply_override(one, "contact[0].gap=0.03");
  EXPECT_EQ(one.contact->gap.value, 0.03);
}

TEST(ContactPartScenes, DefectsNameTheFileLineAndPart) {
  auto error = [](const std::string& text) {
    try {
      Scene s = parse_scene_string(text, "bad.toml");
      (void)build_problem(s);
    } catch (const InputError& e) {
      return with_line(e);
    }
    return std::string();
  };
  const std::string two = "schema_version = 1\n[[contact]]\nname = \"a\"\nside = \"bottom\"\n[[contact]]\nname = \"a\"\nside = \"top\"\n";
  EXPECT_NE(error(two).find("bad.toml:6: contact[1].name: contact part 0 has the name 'a' already"), std::string::npos)
      << error(two);
  const std::string bad_name = "schema_version = 1\n[contact]\nname = \"a b\"\nside = \"bottom\"\n";
  EXPECT_NE(error(bad_name).find("bad.toml:3: contact.name:"), std::string::npos) << error(bad_name);
  const std::string overlap =
      "schema_version = 1\n[[contact]]\nside = \"bottom\"\n[[contact]]\nsegments = [[0.0, 0.0, 0.5, 0.0]]\n";
  const std::string m = error(overlap);
  EXPECT_NE(m.find("bad.toml:4: contact[1]: selects the boundary edge"), std::string::npos) << m;
  EXPECT_NE(m.find("contact[0] ('contact[0]') selects too"), std::string::npos) << m;
  const std::string wrong_key = "schema_version = 1\n[[contact]]\nside = \"bottom\"\n[[contact]]\nside = \"top\"\ngapp = 1\n";
  EXPECT_NE(error(wrong_key).find("bad.toml:6: unknown key 'gapp' in [contact[1]]"), std::string::npos) << error(wrong_key);
  const std::string empty = "schema_version = 1\ncontact = []\n";
  EXPECT_NE(error(empty).find("at least one"), std::string::npos) << error(empty);
}

// The shipped scene: both parts carry the indenter's push, the forces balance, and the outputs
// name each node's part.
TEST(ContactPartScenes, TheBracketBalancesAndItsOutputsNameTheParts) {
  Scene scene = parse_scene(test::scenes_dir() / "bracket-two-contacts.toml");
  apply_override(scene, "mesh.n=[32, 16]");
  const app::SceneSolve s = app::solve_scene(scene);
  ASSERT_TRUE(s.solution.converged()) << s.solution.message;
  EXPECT_LT(s.solution.forces.residual(), 1e-10);
  EXPECT_EQ(s.solution.contact_parts, (std::vector<std::string>{"support", "indenter"}));
  Vec2 support = Vec2::Zero(), indenter = Vec2::Zero();
  for (const ContactNode& n : s.solution.contact) {
    const Vec2 f = -n.force() * n.normal;
    (n.part == 0 ? support : indenter) += f;
    if (n.part == 1) EXPECT_GE(n.force(), -1e-12) << "the indenter only pushes";
  }
  EXPECT_LT(indenter.y(), 0.0) << "the indenter pushes the bracket down";
  EXPECT_GT(support.y(), 0.0) << "the support holds it up";
  EXPECT_LT((support + indenter - s.solution.contact_force()).norm(), 1e-12 * indenter.norm());

  const fs::path dir = test::scratch("contact_parts_outputs");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::vector<std::string> files{"result.json", "contact.csv", "solution.vtu"};
  app::write_results(dir, scene, s, &files);
  std::ifstream csv(dir / "contact.csv");
  std::string header, row;
  std::getline(csv, header);
  EXPECT_EQ(header, "vertex,x,y,u_nu,law_force,reaction,pressure,state,gap,nx,ny,part");
  int rows = 0, indenter_rows = 0;
  while (std::getline(csv, row)) {
    ++rows;
    const std::string part = row.substr(row.rfind(',') + 1);
    EXPECT_TRUE(part == "support" || part == "indenter") << row;
    indenter_rows += part == "indenter";
  }
  EXPECT_EQ(rows, static_cast<int>(s.solution.contact.size()));
  EXPECT_GT(indenter_rows, 0);
  const auto j = nlohmann::json::parse(test::slurp(dir / "result.json"));
  for (std::size_t i = 0; i < s.solution.contact.size(); ++i)
    EXPECT_EQ(j.at("contact")[i].at("part"), s.solution.contact_parts[static_cast<std::size_t>(s.solution.contact[i].part)]);
  EXPECT_NE(test::slurp(dir / "solution.vtu").find("Name=\"contact_part\""), std::string::npos);
  fs::remove_all(dir);
}
