// Two deformable bodies whose surfaces do not coincide (docs/two-bodies.md, "Curved bodies"):
// each node paired with the point of the other body's surface along its normal
// (BodyPairing::projection), its gap the distance to it. Against closed forms: Lame's
// interference fit of two rings and Hertz's two cylinders.
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/bodies.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/error.hpp>

#include <gtest/gtest.h>

#include "projected_part.hpp"

#include "lame_rings.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <string>

using namespace hemivem;

namespace {

constexpr double pi = std::numbers::pi;

std::vector<double> uniform(double from, double to, int n) {
  std::vector<double> v(static_cast<std::size_t>(n) + 1);
  for (int k = 0; k <= n; ++k) v[static_cast<std::size_t>(k)] = from + (to - from) * k / n;
  v.back() = to;
  return v;
}

/// Points from `from` towards `to`: steps of h up to `flat` away, then growing by `ratio`, the
/// last step shortened or merged so that the last point is `to`.
std::vector<double> graded(double from, double to, double h, double flat, double ratio) {
  const double sign = to > from ? 1.0 : -1.0, length = std::abs(to - from);
  std::vector<double> d{0.0};
  double step = h;
  while (d.back() + step < length) {
    d.push_back(d.back() + step);
    if (d.back() >= flat) step *= ratio;
  }
  if (length - d.back() < 0.5 * step && d.size() > 1)
    d.back() = length;
  else
    d.push_back(length);
  std::vector<double> out;
  for (double x : d) out.push_back(from + sign * x);
  out.back() = to;
  return out;
}

/// Angles from a to b, finest (spacing h) within `flat` of `focus`.
std::vector<double> graded_around(double a, double focus, double b, double h, double flat, double ratio) {
  std::vector<double> left = graded(focus, a, h, flat, ratio), right = graded(focus, b, h, flat, ratio);
  std::reverse(left.begin(), left.end());
  left.insert(left.end(), right.begin() + 1, right.end());
  return left;
}

MaterialTable two_materials(const JoinedMeshes& joined, const Material& first, const Material& second) {
  std::vector<Material> by_region(static_cast<std::size_t>(joined.first_region[1] + 1), first);
  by_region.back() = second;
  return MaterialTable(by_region, PlaneModel::strain);
}

std::vector<int> in_body(const JoinedMeshes& joined, int body, const std::vector<int>& facets) {
  std::vector<int> out;
  for (int f : facets) out.push_back(joined.facet_of[static_cast<std::size_t>(body)][static_cast<std::size_t>(f)]);
  return out;
}

ContactSolution solve(const ContactProblem& problem) {
  FactorizationOptions f;
  f.engine = "auto";
  MinimizerOptions o;
  o.tolerance = 1e-12;
  return solve_contact(problem, make_factorization(f), *make_minimizer("ssn"), o);
}

}  // namespace

TEST(CurvedBodies, ProjectionPairsEachNodeWithThePointAlongItsNormal) {
  // a 2 x 1 block above a 3 x 1 block, 0.1 apart: each upper node meets the lower top at the
  // point below it, on the edge of the lower mesh that holds it, at the distance 0.1
  const Mesh upper = make_squares({2, 1}, {0.0, 1.0, 0.6, 1.0}), lower = make_squares({3, 1}, {0.0, 1.0, 0.0, 0.5});
  const JoinedMeshes joined = join_meshes({&upper, &lower}, {"upper", "lower"});
  const auto at_y = [&](const Mesh& m, double y) {
    return select_boundary_edges(m, [y](const Vec2& a, const Vec2& b) { return a.y() == y && b.y() == y; });
  };
  ContactProblem problem;
  problem.elasticity.mesh = &joined.mesh;
  problem.parts.push_back(
      test::projected_part<2>(in_body(joined, 0, at_y(upper, 0.6)), in_body(joined, 1, at_y(lower, 0.5))));
  problem.parts.back().gap = [](const Vec2& x) { return 0.01 * x.x(); };  // added to the distance
  const DofMap dofs = make_dof_map(joined.mesh, {});
  const ContactBoundary b = make_contact_boundary(joined.mesh, problem.parts, dofs);
  ASSERT_EQ(b.size(), 3);
  ASSERT_EQ(b.across.size(), 3u);
  for (int i = 0; i < b.size(); ++i) {
    const Vec2 x = joined.mesh.vertex(b.nodes[static_cast<std::size_t>(i)]);
    EXPECT_NEAR(b.gaps(i), 0.1 + 0.01 * x.x(), 1e-15);
    const Across& a = b.across[static_cast<std::size_t>(i)];
    Vec2 point = Vec2::Zero();
    double sum = 0.0;
    for (int k = 0; k < a.size(); ++k) {
      EXPECT_GE(a.vertex[static_cast<std::size_t>(k)], joined.first_vertex[1]);
      point += a.weight[static_cast<std::size_t>(k)] * joined.mesh.vertex(a.vertex[static_cast<std::size_t>(k)]);
      sum += a.weight[static_cast<std::size_t>(k)];
    }
    EXPECT_NEAR(sum, 1.0, 1e-15);
    EXPECT_NEAR((point - Vec2(x.x(), 0.5)).norm(), 0.0, 1e-15) << "node at x = " << x.x();
    // x = 0.5 lies inside the lower edge [1/3, 2/3], between its two ends; x = 0 and 1 on a vertex
    EXPECT_EQ(a.size(), x.x() == 0.5 ? 2 : 1);
    EXPECT_EQ(b.partner_of(i), a.vertex[0]);  // the one vertex, or the edge's first end
  }
  // overlapping bodies: a negative gap; a surface the normals miss: no pair, an infinite gap
  const Mesh deep = make_squares({2, 1}, {0.0, 1.0, 0.45, 1.0});
  const JoinedMeshes overlap = join_meshes({&deep, &lower}, {"upper", "lower"});
  problem.elasticity.mesh = &overlap.mesh;
  problem.parts = {
      test::projected_part<2>(in_body(overlap, 0, at_y(deep, 0.45)), in_body(overlap, 1, at_y(lower, 0.5)))};
  const ContactBoundary o = make_contact_boundary(overlap.mesh, problem.parts, make_dof_map(overlap.mesh, {}));
  for (int i = 0; i < o.size(); ++i) EXPECT_NEAR(o.gaps(i), -0.05, 1e-15);
  const Mesh aside = make_squares({2, 1}, {2.0, 3.0, 0.6, 1.0});
  const JoinedMeshes apart = join_meshes({&aside, &lower}, {"upper", "lower"});
  problem.elasticity.mesh = &apart.mesh;
  problem.parts = {test::projected_part<2>(in_body(apart, 0, at_y(aside, 0.6)), in_body(apart, 1, at_y(lower, 0.5)))};
  const ContactBoundary m = make_contact_boundary(apart.mesh, problem.parts, make_dof_map(apart.mesh, {}));
  for (int i = 0; i < m.size(); ++i) {
    EXPECT_TRUE(std::isinf(m.gaps(i)));
    EXPECT_EQ(m.partner_of(i), -1);
  }
}

namespace {

/// Two rings pressed into each other (test::LameRings): the inner one inside the outer one,
/// whole rings held against rigid motions at three vertices each, the inner ring's outer surface
/// (n_inner angles) paired by projection with the outer ring's inner surface (n_outer angles):
/// the meshes do not match.
struct Rings : test::LameRings {
  int n_inner = 512, n_outer = 448, radial = 8;
};

struct RingResult {
  double worst = 0.0;      // the largest |p_i / p - 1| over the contact nodes
  double mean = 0.0;       // |the mean pressure (force over length) / p - 1|
  double expansion = 0.0;  // |u_r / u_r(Lame) - 1| on the outer ring's outer circle, the largest
  int nodes = 0;
};

RingResult press_rings(const Rings& r) {
  const double s = r.b + r.delta;
  const Mesh inner = make_polar({0, 0}, uniform(r.a, s, r.radial), uniform(0.0, 2 * pi, r.n_inner));
  const Mesh outer = make_polar({0, 0}, uniform(r.b, r.c, r.radial), uniform(0.0, 2 * pi, r.n_outer));
  const JoinedMeshes joined = join_meshes({&inner, &outer}, {"inner", "outer"});
  ContactProblem problem;
  problem.elasticity.mesh = &joined.mesh;
  problem.elasticity.materials = two_materials(joined, r.inner, r.outer);
  // each ring held at the points of its inner circle on the axes: u_y = 0 at (+-a, 0), u_x = 0
  // at (0, a): what the exact, axisymmetric solution does there
  const auto held = [&](int body, double radius) {
    std::vector<int> on_x, on_y;
    const int first = joined.first_vertex[static_cast<std::size_t>(body)];
    const int last = body == 0 ? joined.first_vertex[1] : joined.mesh.num_vertices();
    for (int v = first; v < last; ++v) {
      const Vec2 x = joined.mesh.vertex(v);
      if (std::abs(x.norm() - radius) > 1e-12) continue;
      if (x.y() == 0.0) on_x.push_back(v);
      if (x.x() == 0.0 && x.y() > 0.0) on_y.push_back(v);
    }
    const auto zero = [](const Vec2&) { return Vec2(0.0, 0.0); };
    problem.elasticity.dirichlet.push_back({{}, zero, {false, true}, "on x", on_x});
    problem.elasticity.dirichlet.push_back({{}, zero, {true, false}, "on y", on_y});
  };
  held(0, r.a);
  held(1, r.b);
  problem.parts.push_back(test::projected_part<2>(in_body(joined, 0, inner.edge_group("outer")),
                                                  in_body(joined, 1, outer.edge_group("inner"))));
  const ContactSolution sol = solve(problem);
  EXPECT_TRUE(sol.converged()) << sol.message;
  const auto [outer_pressure, expansion] = test::lame_interference(r);
  const double p = outer_pressure * r.b / s;  // on the inner ring's surface
  RingResult out;
  double force = 0.0, length = 0.0;
  for (const ContactNode& n : sol.contact) {
    out.worst = std::max(out.worst, std::abs(n.pressure() / p - 1.0));
    force += n.force();
    length += n.weight;
    ++out.nodes;
  }
  out.mean = std::abs(force / length / p - 1.0);
  for (int v = joined.first_vertex[1]; v < joined.mesh.num_vertices(); ++v) {
    const Vec2 x = joined.mesh.vertex(v);
    if (std::abs(x.norm() - r.c) > 1e-12) continue;
    const double ur = (sol.u(2 * v) * x.x() + sol.u(2 * v + 1) * x.y()) / x.norm();
    out.expansion = std::max(out.expansion, std::abs(ur / expansion - 1.0));
  }
  return out;
}

}  // namespace

TEST(CurvedBodies, InterferenceFitOfTwoRingsGivesLamesPressure) {
  // the same angles on both sides: each node meets a vertex at the distance -delta, and every
  // node's pressure is Lame's
  Rings same;
  same.n_outer = same.n_inner;
  const RingResult m = press_rings(same);
  EXPECT_EQ(m.nodes, same.n_inner);
  EXPECT_LT(m.worst, 2e-3);
  EXPECT_LT(m.expansion, 2e-3);
  // other angles: the outer ring's inner polygon puts the points across from the nodes on its
  // chords, whose gaps vary by up to b (1 - cos(pi / n_outer)) about the mean; the pressure is
  // Lame's on the whole, and the fields converge
  Rings coarse;
  const RingResult c = press_rings(coarse);
  EXPECT_LT(c.mean, 0.025);
  EXPECT_LT(c.expansion, 0.025);
  Rings fine = coarse;
  fine.n_inner *= 2;
  fine.n_outer *= 2;
  fine.radial *= 2;
  const RingResult f = press_rings(fine);
  EXPECT_LT(f.mean, c.mean / 3);  // second order: 4 times smaller
  EXPECT_LT(f.expansion, c.expansion / 3);
}

namespace {

/// Hertz's two cylinders in plane strain: the upper one (radius r1, centre (0, r1)) pressed
/// down by a prescribed displacement of its flat side onto the lower one (radius r2, centre
/// (0, -r2), its flat side clamped), each a half disk graded towards the point where they
/// touch, frictionless: the contact half-width a = sqrt(4 P R / (pi E)) and the peak pressure
/// p0 = 2 P / (pi a), R = r1 r2 / (r1 + r2) and 1/E = (1 - nu1^2)/E1 + (1 - nu2^2)/E2, P the
/// force pressing them (per unit length).
struct Cylinders {
  double r1 = 1.0, r2 = 1.5, push = 0.004;
  Material upper{1.0, 0.3}, lower{2.0, 0.2};
  double h = 0.004;  // the mesh size at the contact
};

struct HertzResult {
  double a = 0.0, p0 = 0.0;                // Hertz's, of the force measured
  double fitted_a = 0.0, fitted_p0 = 0.0;  // p^2 = p0^2 (1 - x^2 / a^2) fitted to the nodes
  double peak = 0.0;
  int pressed = 0;
};

/// The cylinders of `c`, or with `half` their halves x >= 0 (the same cells), held on x = 0 by
/// symmetry (u_x = 0): the node where the upper surface meets that line then has its normal
/// along the line, as its mirror image makes it.
ContactSolution solve_cylinders(const Cylinders& c, bool half) {
  const double ratio = 1.12;
  const auto half_disk = [&](double radius, double focus, double from, double to, double cy) {
    const std::vector<double> radii = graded(radius, 0.0, c.h, 0.05, ratio);
    std::vector<double> r(radii.rbegin(), radii.rend());
    // the half: from the focus to the end on the right (x > 0)
    const double right = std::cos(from) > 0.0 ? from : to;
    std::vector<double> angles = half ? graded(focus, right, c.h / radius, 0.08 / radius, ratio)
                                      : graded_around(from, focus, to, c.h / radius, 0.08 / radius, ratio);
    if (half && right < focus) std::reverse(angles.begin(), angles.end());
    return make_polar({0.0, cy}, r, angles);
  };
  const Mesh upper = half_disk(c.r1, 1.5 * pi, pi, 2 * pi, c.r1), lower = half_disk(c.r2, 0.5 * pi, 0.0, pi, -c.r2);
  const JoinedMeshes joined = join_meshes({&upper, &lower}, {"upper", "lower"});
  ContactProblem problem;
  problem.elasticity.mesh = &joined.mesh;
  problem.elasticity.materials = two_materials(joined, c.upper, c.lower);
  // the flat sides: the upper one's "end" (and "start" of the whole), the lower one's "start" (and "end")
  std::vector<int> top = in_body(joined, 0, upper.edge_group("end")), bottom = in_body(joined, 1, lower.edge_group("start"));
  const std::vector<int> upper_start = in_body(joined, 0, upper.edge_group("start")),
                         lower_end = in_body(joined, 1, lower.edge_group("end"));
  const double push = c.push;
  const auto zero = [](const Vec2&) { return Vec2(0.0, 0.0); };
  if (half) {
    problem.elasticity.dirichlet.push_back({upper_start, zero, {true, false}, "upper symmetry", {}});
    problem.elasticity.dirichlet.push_back({lower_end, zero, {true, false}, "lower symmetry", {}});
  } else {
    top.insert(top.end(), upper_start.begin(), upper_start.end());
    bottom.insert(bottom.end(), lower_end.begin(), lower_end.end());
  }
  problem.elasticity.dirichlet.push_back({top, [push](const Vec2&) { return Vec2(0.0, -push); }, {true, true}, "top", {}});
  problem.elasticity.dirichlet.push_back({bottom, zero, {true, true}, "bottom", {}});
  problem.parts.push_back(test::projected_part<2>(in_body(joined, 0, upper.edge_group("outer")),
                                                  in_body(joined, 1, lower.edge_group("outer"))));
  const ContactSolution sol = solve(problem);
  EXPECT_TRUE(sol.converged()) << sol.message;
  EXPECT_LT(sol.forces.residual(), 1e-9);
  return sol;
}

HertzResult press_cylinders(const Cylinders& c) {
  const ContactSolution sol = solve_cylinders(c, false);
  HertzResult out;
  double force = 0.0;
  for (const ContactNode& n : sol.contact) force += n.force_on_body().y();
  const double radius = c.r1 * c.r2 / (c.r1 + c.r2);
  const double modulus = 1.0 / ((1.0 - c.upper.poisson * c.upper.poisson) / c.upper.young +
                                (1.0 - c.lower.poisson * c.lower.poisson) / c.lower.young);
  out.a = std::sqrt(4.0 * force * radius / (pi * modulus));
  out.p0 = 2.0 * force / (pi * out.a);
  // least squares of p^2 = alpha + beta x^2 over the nodes well inside the contact
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const ContactNode& n : sol.contact) {
    const double p = n.pressure();
    out.peak = std::max(out.peak, p);
    if (p > 0.0) ++out.pressed;
    if (std::abs(n.x.x()) > 0.8 * out.a) continue;
    const Eigen::Vector2d row(1.0, n.x.x() * n.x.x());
    m += row * row.transpose();
    rhs += row * p * p;
  }
  const Eigen::Vector2d fit = m.ldlt().solve(rhs);
  out.fitted_p0 = std::sqrt(fit(0));
  out.fitted_a = std::sqrt(-fit(0) / fit(1));
  return out;
}

}  // namespace

TEST(CurvedBodies, TwoCylindersGiveHertzsHalfWidthAndPeakPressure) {
  // the mesh size at the contact: a / 2, a / 4 and a / 8 (a = 0.034)
  std::vector<HertzResult> r;
  for (double h : {0.016, 0.008, 0.004}) {
    Cylinders c;
    c.h = h;
    r.push_back(press_cylinders(c));
  }
  const auto a_error = [](const HertzResult& x) { return std::abs(x.fitted_a / x.a - 1.0); };
  const auto p0_error = [](const HertzResult& x) { return std::abs(x.fitted_p0 / x.p0 - 1.0); };
  EXPECT_LT(a_error(r[0]), 0.05);
  EXPECT_LT(p0_error(r[0]), 0.05);
  for (std::size_t k = 1; k < r.size(); ++k) {
    EXPECT_LT(a_error(r[k]), 0.5 * a_error(r[k - 1])) << "h halved " << k << " times";
    EXPECT_LT(p0_error(r[k]), p0_error(r[k - 1])) << "h halved " << k << " times";
  }
  const HertzResult& fine = r.back();
  EXPECT_GE(fine.pressed, 15);
  EXPECT_LT(a_error(fine), 0.005);
  EXPECT_LT(p0_error(fine), 0.005);
  EXPECT_NEAR(fine.peak / fine.p0, 1.0, 0.005);
}

TEST(CurvedBodies, TheHalfModelOnItsSymmetryLineIsTheWholeModel) {
  // the node where the upper surface meets x = 0 (its one contact edge on one side of the line)
  // takes the normal (0, -1): the half model is the whole model's right half
  const Cylinders c;
  const ContactSolution whole = solve_cylinders(c, false), half = solve_cylinders(c, true);
  std::map<std::pair<double, double>, const ContactNode*> by_point;
  for (const ContactNode& n : whole.contact) by_point[{n.x.x(), n.x.y()}] = &n;
  double peak = 0.0, force = 0.0, half_force = 0.0;
  for (const ContactNode& n : whole.contact) {
    peak = std::max(peak, n.pressure());
    force += n.force_on_body().y();
  }
  int compared = 0;
  for (const ContactNode& n : half.contact) {
    half_force += n.force_on_body().y();
    const auto at = by_point.find({n.x.x(), n.x.y()});
    ASSERT_NE(at, by_point.end()) << "node at " << n.x.transpose();
    EXPECT_NEAR(n.pressure(), at->second->pressure(), 1e-8 * peak) << "node at " << n.x.transpose();
    if (n.x.x() == 0.0) {
      EXPECT_EQ(n.normal, Vec2(0.0, -1.0));
      EXPECT_NEAR(n.weight, 0.5 * at->second->weight, 1e-15);
      EXPECT_GT(n.pressure(), 0.0);
    }
    ++compared;
  }
  EXPECT_GT(compared, 20);
  EXPECT_NEAR(2.0 * half_force, force, 1e-8 * force);  // the node on the line stands for half its share
}
