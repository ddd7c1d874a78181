// Two deformable bodies in contact (docs/two-bodies.md): the bodies' meshes matched along their
// interface (match_interface) and joined (join_meshes), the contact parts meeting the other
// body (BasicContactPart::against), the condensation on relative displacements (Joining).
#include <hemivem/contact/joining.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/bodies.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/interface.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/error.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace hemivem;

namespace {

/// The boundary edges of `mesh` with both end points on the line y = level (x in [0, 1]).
std::vector<int> edges_at_y(const Mesh& mesh, double level) {
  return select_boundary_edges(mesh, [&](const Vec2& a, const Vec2& b) {
    return std::abs(a.y() - level) < 1e-12 && std::abs(b.y() - level) < 1e-12;
  });
}
std::vector<int> edges_at_x(const Mesh& mesh, double level) {
  return select_boundary_edges(mesh, [&](const Vec2& a, const Vec2& b) {
    return std::abs(a.x() - level) < 1e-12 && std::abs(b.x() - level) < 1e-12;
  });
}

/// Two blocks stacked: `upper` on [0, 1] x [0.5, 1] and `lower` on [0, 1] x [0, 0.5], their
/// meshes matched along y = 0.5 and joined.
struct Stack {
  JoinedMeshes joined;
  std::vector<int> upper_bottom, lower_top;
};

Stack stack(const Mesh& upper, const Mesh& lower) {
  const MatchedInterface m = match_interface(upper, edges_at_y(upper, 0.5), lower, edges_at_y(lower, 0.5), 1e-6);
  Stack s;
  s.joined = join_meshes({&m.first, &m.second}, {"upper", "lower"});
  for (int e : m.first_edges) s.upper_bottom.push_back(s.joined.facet_of[0][static_cast<std::size_t>(e)]);
  for (int e : m.second_edges) s.lower_top.push_back(s.joined.facet_of[1][static_cast<std::size_t>(e)]);
  return s;
}

/// The contact part of the upper block's bottom against the lower block's top: Signorini
/// contact (gap 0, zero law, one-sided), with the friction law `friction` when given.
ContactPart interface_part(const Stack& s, std::shared_ptr<const ContactLaw> friction = nullptr) {
  ContactPart part;
  part.name = "interface";
  part.facets = s.upper_bottom;
  part.against = s.lower_top;
  part.gap = [](const Vec2&) { return 0.0; };
  part.law = zero_law();
  part.constraint = ConstraintKind::one_sided;
  part.friction = std::move(friction);
  return part;
}

struct Patch {
  double p = 2.0;                       // the pressure on the upper block's top
  Material upper{10.0, 0.3}, lower{4.0, 0.1};
};

/// The contact patch test: the lower block on rollers (u_y = 0 on its bottom, u_x = 0 on its
/// left side), the upper one held in x by its left side only (its vertical motion held by the
/// contact alone), a uniform pressure on top, frictionless Signorini contact between them.
ContactProblem patch_problem(const Stack& s, const Patch& patch) {
  const Mesh& mesh = s.joined.mesh;
  ContactProblem problem;
  problem.elasticity.mesh = &mesh;
  std::vector<Material> by_region(static_cast<std::size_t>(s.joined.first_region[1] + 1));
  for (int r = 0; r < s.joined.first_region[1]; ++r) by_region[static_cast<std::size_t>(r)] = patch.upper;
  by_region.back() = patch.lower;
  problem.elasticity.materials = MaterialTable(by_region, PlaneModel::strain);
  std::vector<int> left_upper, left_lower, bottom, top;
  for (int e : select_boundary_edges(mesh, [](const Vec2& a, const Vec2& b) { return a.x() == 0.0 && b.x() == 0.0; })) {
    const MeshEdge& edge = mesh.edge(e);
    (edge.v0 < s.joined.first_vertex[1] ? left_upper : left_lower).push_back(e);
  }
  bottom = edges_at_y(mesh, 0.0);
  top = edges_at_y(mesh, 1.0);
  const auto zero = [](const Vec2&) { return Vec2(0.0, 0.0); };
  problem.elasticity.dirichlet.push_back({left_upper, zero, {true, false}, "upper.left", {}});
  problem.elasticity.dirichlet.push_back({left_lower, zero, {true, false}, "lower.left", {}});
  problem.elasticity.dirichlet.push_back({bottom, zero, {false, true}, "lower.bottom", {}});
  TractionLoad load;
  load.facets = top;
  const double p = patch.p;
  load.pressure = [p](const Vec2&) { return p; };
  problem.elasticity.tractions.push_back(load);
  problem.parts.push_back(interface_part(s));
  return problem;
}

ContactSolution solve(const ContactProblem& problem, const std::string& minimizer = "ssn") {
  FactorizationOptions f;
  f.engine = "auto";
  MinimizerOptions o;
  o.tolerance = 1e-12;
  return solve_contact(problem, make_factorization(f), *make_minimizer(minimizer), o);
}

/// The exact field of the patch test: sigma_yy = -p and sigma_xx = 0 in both blocks (plane
/// strain), u_x = eps_xx x, u_y continuous across y = 0.5 and 0 at y = 0.
Vec2 exact(const Vec2& x, bool upper, const Patch& patch) {
  const auto strains = [&](const Material& m) {
    return Vec2(patch.p * m.poisson * (1.0 + m.poisson) / m.young, -patch.p * (1.0 - m.poisson * m.poisson) / m.young);
  };
  const Vec2 lo = strains(patch.lower), up = strains(patch.upper);
  if (!upper) return Vec2(lo.x() * x.x(), lo.y() * x.y());
  return Vec2(up.x() * x.x(), lo.y() * 0.5 + up.y() * (x.y() - 0.5));
}

void expect_patch_passed(const Stack& s, const Patch& patch, const ContactSolution& sol) {
  ASSERT_TRUE(sol.converged()) << sol.message;
  ASSERT_FALSE(sol.held_by_contact.empty());  // the upper block's vertical motion
  const Mesh& mesh = s.joined.mesh;
  double worst = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec2 u(sol.u(2 * v), sol.u(2 * v + 1));
    worst = std::max(worst, (u - exact(mesh.vertex(v), v < s.joined.first_vertex[1], patch)).norm());
  }
  EXPECT_LT(worst, 1e-10);
  ASSERT_FALSE(sol.contact.empty());
  double width = 0.0;
  for (const ContactNode& n : sol.contact) {
    ASSERT_GE(n.partner, 0);
    EXPECT_NEAR(n.force() / n.weight, patch.p, 1e-10 * patch.p) << "node at x = " << n.x.x();
    EXPECT_NEAR(n.u_nu, 0.0, 1e-12);
    EXPECT_EQ(mesh.vertex(n.partner), n.x);
    width += n.weight;
  }
  EXPECT_NEAR(width, 1.0, 1e-12);
  // the interface's forces are internal: the supports carry the load
  EXPECT_LT(sol.forces.residual(), 1e-10);
  EXPECT_NEAR(sol.contact_force().y(), patch.p, 1e-10);
}

}  // namespace

TEST(TwoBodies, ContactPatchTestWithNonMatchingSquares) {
  const Patch patch;
  const Stack s = stack(make_squares({4, 3}, {0.0, 1.0, 0.5, 1.0}), make_squares({3, 2}, {0.0, 1.0, 0.0, 0.5}));
  expect_patch_passed(s, patch, solve(patch_problem(s, patch)));
}

TEST(TwoBodies, ContactPatchTestWithVoronoiOnOneSide) {
  const Patch patch;
  const Stack s = stack(make_voronoi({5, 3}, {0.0, 1.0, 0.5, 1.0}), make_squares({7, 3}, {0.0, 1.0, 0.0, 0.5}));
  for (const std::string minimizer : {"ssn", "bundle-dca"}) {
    SCOPED_TRACE(minimizer);
    expect_patch_passed(s, patch, solve(patch_problem(s, patch), minimizer));
  }
}

TEST(TwoBodies, JoiningIsTheChangeOfCoordinatesItSays) {
  // one pair (vertex 0 with vertex 1) of two free vertices and a third held
  const DofMap dofs(6, 2, {4, 5}, Eigen::Vector2d(0.5, 0.0));
  Joining j(dofs, {{0, Across::vertex_at(1)}}, 2);
  const Eigen::VectorXd u = (Eigen::VectorXd(6) << 1.0, 2.0, 0.25, -1.0, 0.5, 0.0).finished();
  const Eigen::VectorXd v = j.relative(u);
  EXPECT_EQ(v(0), 0.75);
  EXPECT_EQ(v(1), 3.0);
  EXPECT_EQ(v(2), 0.25);
  EXPECT_TRUE(j.displacement(v) == u);
  // T^T A T of a diagonal A: the relative coordinate couples to its partner
  LinearSystem s;
  s.dofs = dofs;
  s.A.resize(4, 4);
  for (int k = 0; k < 4; ++k) s.A.insert(k, k) = k + 1.0;
  s.b = Eigen::VectorXd::Ones(4);
  const LinearSystem joined = j.join(s);
  const Eigen::MatrixXd A = Eigen::MatrixXd(joined.A);
  EXPECT_EQ(A(0, 0), 1.0);
  EXPECT_EQ(A(0, 2), 1.0);
  EXPECT_EQ(A(2, 2), 4.0);
  EXPECT_EQ(joined.b(2), 2.0);
  // a component prescribed on one side only, against a free one, is refused by name
  const DofMap held(6, 2, {0, 5}, Eigen::Vector2d(0.0, 0.0));
  EXPECT_THROW(Joining(held, {{0, Across::vertex_at(1)}}, 2), InputError);
  EXPECT_THROW(Joining(dofs, {{0, Across::vertex_at(1)}, {1, Across::vertex_at(2)}}, 2), InputError);
}

TEST(TwoBodies, UnmatchedMeshesAreRefusedByName) {
  const Patch patch;
  const Mesh upper = make_squares({4, 3}, {0.0, 1.0, 0.5, 1.0}), lower = make_squares({3, 2}, {0.0, 1.0, 0.0, 0.5});
  Stack s;
  s.joined = join_meshes({&upper, &lower}, {"upper", "lower"});
  for (int e : edges_at_y(upper, 0.5)) s.upper_bottom.push_back(s.joined.facet_of[0][static_cast<std::size_t>(e)]);
  for (int e : edges_at_y(lower, 0.5)) s.lower_top.push_back(s.joined.facet_of[1][static_cast<std::size_t>(e)]);
  try {
    solve(patch_problem(s, patch));
    FAIL() << "unmatched meshes were solved";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no vertex of the other body"), std::string::npos) << e.what();
  }
}

namespace {

/// The upper block pressed by 1 + 2x on its top, held in x on its left side, with Signorini
/// contact on its bottom: against the lower block (clamped at its bottom, on rollers on its
/// left side, Young's modulus `stiff`) when `against` is not empty, else against a rigid
/// foundation (`mesh` the upper block's alone).
ContactProblem pressed_upper(const Mesh& mesh, const std::vector<int>& bottom, const std::vector<int>& against,
                             int lower_first_vertex, double stiff) {
  ContactProblem problem;
  problem.elasticity.mesh = &mesh;
  const int regions = 1 + *std::max_element(mesh.regions().begin(), mesh.regions().end());
  std::vector<Material> by_region(static_cast<std::size_t>(regions), Material{10.0, 0.3});
  if (!against.empty()) by_region.back() = Material{stiff, 0.3};
  problem.elasticity.materials = MaterialTable(by_region, PlaneModel::strain);
  // the left sides of both blocks on rollers (the vertices at one point of the contact take the
  // same supports)
  std::vector<int> left;
  for (int e : edges_at_x(mesh, 0.0))
    if (mesh.edge(e).v0 < lower_first_vertex || !against.empty()) left.push_back(e);
  const auto zero = [](const Vec2&) { return Vec2(0.0, 0.0); };
  problem.elasticity.dirichlet.push_back({left, zero, {true, false}, "left", {}});
  if (!against.empty()) problem.elasticity.dirichlet.push_back({edges_at_y(mesh, 0.0), zero, {true, true}, "lower.bottom", {}});
  TractionLoad load;
  load.facets = edges_at_y(mesh, 1.0);
  load.pressure = [](const Vec2& x) { return 1.0 + 2.0 * x.x(); };
  problem.elasticity.tractions.push_back(load);
  ContactPart part;
  part.facets = bottom;
  part.against = against;
  part.gap = [](const Vec2&) { return 0.0; };
  part.law = zero_law();
  part.constraint = ConstraintKind::one_sided;
  problem.parts.push_back(part);
  return problem;
}

}  // namespace

TEST(TwoBodies, AFoundationPosedAsAStiffBodyGivesTheOneBodyAnswer) {
  const Stack s = stack(make_voronoi({6, 3}, {0.0, 1.0, 0.5, 1.0}), make_squares({5, 3}, {0.0, 1.0, 0.0, 0.5}));
  // the upper block alone (its matched mesh, the same vertices) on a rigid foundation
  const Mesh upper = [&] {
    std::vector<Vec2> v(s.joined.mesh.vertices().begin(), s.joined.mesh.vertices().begin() + s.joined.first_vertex[1]);
    std::vector<std::vector<int>> elements;
    for (int e = 0; e < s.joined.first_cell[1]; ++e)
      elements.emplace_back(s.joined.mesh.element(e).begin(), s.joined.mesh.element(e).end());
    return Mesh(v, elements);
  }();
  const ContactSolution alone = solve(pressed_upper(upper, edges_at_y(upper, 0.5), {}, upper.num_vertices(), 0.0));
  ASSERT_TRUE(alone.converged()) << alone.message;
  const Eigen::Index n = 2 * upper.num_vertices();
  double previous = 0.0;
  for (const double stiff : {1e2, 1e4, 1e6}) {
    SCOPED_TRACE(stiff);
    const ContactSolution two =
        solve(pressed_upper(s.joined.mesh, s.upper_bottom, s.lower_top, s.joined.first_vertex[1], stiff));
    ASSERT_TRUE(two.converged()) << two.message;
    const double difference = (two.u.head(n) - alone.u).cwiseAbs().maxCoeff() / alone.u.cwiseAbs().maxCoeff();
    // the foundation's compliance is that of the stiff body: 1/stiff
    EXPECT_LT(difference, 300.0 / stiff);
    if (previous > 0.0) EXPECT_LT(difference, 0.02 * previous);
    previous = difference;
  }
}

// Tresca friction between the bodies, on the relative tangential displacement: the upper block,
// held by the contact alone (normal and tangential), is pressed by p and sheared by tau < g on
// its top, with the complementary shear on both blocks' sides; the lower block is clamped at its
// bottom. With nu = 0 the exact field is linear in each block (sigma_yy = -p, sigma_xy = tau),
// the interface stuck: the relative displacement 0 and the friction force tau at every node.
namespace {

struct Sheared {
  double p = 2.0, tau = 0.7, g = 1.0;
  Material upper{10.0, 0.0}, lower{4.0, 0.0};
  /// The exact displacement at vertex x of the upper (or lower) block.
  Vec2 exact(const Vec2& x, bool up) const {
    const double y0 = up ? 0.5 : 0.0;
    const Material& m = up ? upper : lower;
    // below: u = (tau/mu_l y, -p/E_l y); above: continuous at y = 0.5 (mu = E/2 with nu = 0)
    const Vec2 base = up ? Vec2(tau / (lower.young / 2.0) * 0.5, -p / lower.young * 0.5) : Vec2(0.0, 0.0);
    return base + Vec2(tau / (m.young / 2.0) * (x.y() - y0), -p / m.young * (x.y() - y0));
  }
};

/// The sheared stack's problem; `load` is read when the tractions are evaluated.
ContactProblem sheared_problem(const Stack& s, const Sheared& load) {
  const Mesh& mesh = s.joined.mesh;
  ContactProblem problem;
  problem.elasticity.mesh = &mesh;
  std::vector<Material> by_region(static_cast<std::size_t>(s.joined.first_region[1] + 1), load.upper);
  by_region.back() = load.lower;
  problem.elasticity.materials = MaterialTable(by_region, PlaneModel::strain);
  const auto zero = [](const Vec2&) { return Vec2(0.0, 0.0); };
  problem.elasticity.dirichlet.push_back({edges_at_y(mesh, 0.0), zero, {true, true}, "lower.bottom", {}});
  TractionLoad top, left, right;
  top.facets = edges_at_y(mesh, 1.0);
  top.traction = [&load](const Vec2&) { return Vec2(load.tau, -load.p); };
  left.facets = edges_at_x(mesh, 0.0);
  left.traction = [&load](const Vec2&) { return Vec2(0.0, -load.tau); };
  right.facets = edges_at_x(mesh, 1.0);
  right.traction = [&load](const Vec2&) { return Vec2(0.0, load.tau); };
  problem.elasticity.tractions = {top, left, right};
  problem.parts.push_back(interface_part(s, tresca_law(load.g)));
  return problem;
}

double worst_error(const Stack& s, const Sheared& load, const Eigen::VectorXd& u) {
  double worst = 0.0;
  for (int v = 0; v < s.joined.mesh.num_vertices(); ++v)
    worst = std::max(worst, (Vec2(u(2 * v), u(2 * v + 1)) - load.exact(s.joined.mesh.vertex(v), v < s.joined.first_vertex[1])).norm());
  return worst;
}

}  // namespace

TEST(TwoBodies, TrescaFrictionHoldsAStuckInterfaceExactly) {
  const Stack s = stack(make_voronoi({5, 3}, {0.0, 1.0, 0.5, 1.0}), make_squares({3, 2}, {0.0, 1.0, 0.0, 0.5}));
  const Sheared load;
  const double p = load.p, tau = load.tau;
  const ContactProblem problem = sheared_problem(s, load);
  for (const std::string minimizer : {"ssn", "bundle-dca"}) {
    SCOPED_TRACE(minimizer);
    const ContactSolution sol = solve(problem, minimizer);
    ASSERT_TRUE(sol.converged()) << sol.message;
    EXPECT_EQ(sol.held_by_contact.size(), 3u);  // the upper block's rigid motions
    const double worst = worst_error(s, load, sol.u);
    EXPECT_LT(worst, 1e-10);
    for (const ContactNode& n : sol.contact) {
      EXPECT_NEAR(n.u_tau, 0.0, 1e-12);
      EXPECT_EQ(n.friction_state, FrictionState::stick);
      // the lower body pushes the upper one by -zeta along the tangent tau = (-nu_y, nu_x) = (1, 0)
      EXPECT_NEAR(n.friction_force / n.weight, tau, 1e-9) << "node at x = " << n.x.x();
      EXPECT_NEAR(n.force() / n.weight, p, 1e-9);
    }
  }
}

// The same stack along a loading path whose load is not proportional (p t^2 and tau t): each
// step condenses its load through the joining, and is the exact field at its t.
TEST(TwoBodies, APathOfTwoBodiesIsExactAtEveryStep) {
  const Stack s = stack(make_voronoi({5, 3}, {0.0, 1.0, 0.5, 1.0}), make_squares({3, 2}, {0.0, 1.0, 0.0, 0.5}));
  Sheared load;
  ContactProblem problem = sheared_problem(s, load);
  const Sheared full = load;
  PathLoading loading;
  loading.t = {0.25, 0.5, 0.75, 1.0};
  loading.update = [&](double t, ContactProblem&) {
    load.p = full.p * t * t;
    load.tau = full.tau * t;
  };
  loading.updates_prescribed = false;
  loading.updates_gaps = false;
  FactorizationOptions f;
  f.engine = "auto";
  PathOptions options;
  options.minimizer.tolerance = 1e-12;
  options.frame = [](int) { return true; };
  const PathSolution path = solve_path(problem, make_factorization(f), *make_minimizer("ssn"), loading, options);
  ASSERT_TRUE(path.converged());
  ASSERT_EQ(path.steps.size(), 4u);
  for (const PathStep& step : path.steps) {
    SCOPED_TRACE(step.t);
    Sheared at = full;
    at.p = full.p * step.t * step.t;
    at.tau = full.tau * step.t;
    ASSERT_EQ(step.u.size(), 2 * s.joined.mesh.num_vertices());
    EXPECT_LT(worst_error(s, at, step.u), 1e-10);
  }
}
