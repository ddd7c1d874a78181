// Two deformable solids in contact (docs/two-bodies.md): the bodies' meshes matched along their
// interface (match_interface_3d) and joined (join_meshes), the contact part meeting the other
// body (BasicContactPart::against), the condensation on relative displacements (Joining).
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/bodies.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/interface3d.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace hemivem;

namespace {

const Box upper_box{0.0, 1.0, 0.0, 1.0, 0.5, 1.0}, lower_box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};

/// The boundary faces of `mesh` whose vertices all have coordinate `axis` equal to `level`.
std::vector<int> faces_at(const Mesh3D& mesh, int axis, double level) {
  return select_boundary_faces(mesh, [&](const Vec3& x) { return std::abs(x(axis) - level) < 1e-12; });
}

/// The faces of `faces` that belong to the upper body (vertex ids below `first_lower`), or to
/// the lower one.
std::vector<int> of_body(const Mesh3D& mesh, const std::vector<int>& faces, int first_lower, bool upper) {
  std::vector<int> out;
  for (int f : faces)
    if ((mesh.face(f).vertices.front() < first_lower) == upper) out.push_back(f);
  return out;
}

/// Two blocks stacked: `upper` on [0, 1]^2 x [0.5, 1] and `lower` on [0, 1]^2 x [0, 0.5], their
/// meshes matched along z = 0.5 (unless `match` is false) and joined.
struct Stack {
  JoinedMeshes3D joined;
  std::vector<int> upper_bottom, lower_top;
  bool upper_vertex(int v) const { return v < joined.first_vertex[1]; }
};

Stack stack(const Mesh3D& upper, const Mesh3D& lower, bool match = true) {
  const std::vector<int> bottom = faces_at(upper, 2, 0.5), top = faces_at(lower, 2, 0.5);
  Stack s;
  if (!match) {
    s.joined = join_meshes({&upper, &lower}, {"upper", "lower"});
    for (int f : bottom) s.upper_bottom.push_back(s.joined.facet_of[0][static_cast<std::size_t>(f)]);
    for (int f : top) s.lower_top.push_back(s.joined.facet_of[1][static_cast<std::size_t>(f)]);
    return s;
  }
  const MatchedInterface3D m = match_interface_3d(upper, bottom, lower, top, 1e-6);
  s.joined = join_meshes({&m.first, &m.second}, {"upper", "lower"});
  for (int f : m.first_faces) s.upper_bottom.push_back(s.joined.facet_of[0][static_cast<std::size_t>(f)]);
  for (int f : m.second_faces) s.lower_top.push_back(s.joined.facet_of[1][static_cast<std::size_t>(f)]);
  return s;
}

/// The materials of the joined mesh's regions: the upper body's, then the lower one's.
MaterialTable materials(const Stack& s, const Material& upper, const Material& lower) {
  std::vector<Material> by_region(static_cast<std::size_t>(s.joined.first_region[1] + 1), upper);
  by_region.back() = lower;
  return MaterialTable(by_region, PlaneModel::strain);
}

ContactPart3D interface_part(const Stack& s) {
  ContactPart3D part;
  part.name = "interface";
  part.facets = s.upper_bottom;
  part.against = s.lower_top;
  part.gap = [](const Vec3&) { return 0.0; };
  part.law = zero_law();
  part.constraint = ConstraintKind::one_sided;
  return part;
}

ContactSolution3D solve(const ContactProblem3D& problem, const std::string& minimizer) {
  FactorizationOptions f;
  f.engine = "auto";
  MinimizerOptions o;
  o.tolerance = 1e-12;
  return solve_contact(problem, make_factorization(f), *make_minimizer(minimizer), o);
}

struct Patch {
  double p = 2.0;  // the pressure on the upper block's top
  Material upper{10.0, 0.3}, lower{4.0, 0.1};
  /// The exact field: uniaxial stress sigma_zz = -p in both blocks, free lateral expansion,
  /// u = 0 on the planes x = 0, y = 0 (the normal component) and z = 0, u_z continuous at z = 0.5.
  Vec3 exact(const Vec3& x, bool up) const {
    const Material& m = up ? upper : lower;
    const double lateral = p * m.poisson / m.young;
    const double uz = up ? -p / lower.young * 0.5 - p / upper.young * (x.z() - 0.5) : -p / lower.young * x.z();
    return Vec3(lateral * x.x(), lateral * x.y(), uz);
  }
};

/// The contact patch test: the lower block on rollers (u_z = 0 on its bottom, u_x = 0 on its
/// side x0, u_y = 0 on its side y0), the upper one held on its sides x0 and y0 only (its
/// vertical motion held by the contact alone), a uniform pressure on top, frictionless
/// Signorini contact between them.
ContactProblem3D patch_problem(const Stack& s, const Patch& patch) {
  const Mesh3D& mesh = s.joined.mesh;
  const int first_lower = s.joined.first_vertex[1];
  ContactProblem3D problem;
  problem.elasticity.mesh = &mesh;
  problem.elasticity.materials = materials(s, patch.upper, patch.lower);
  const std::vector<int> x0 = faces_at(mesh, 0, 0.0), y0 = faces_at(mesh, 1, 0.0);
  problem.elasticity.dirichlet.push_back({of_body(mesh, x0, first_lower, true), {}, {true, false, false}, "upper.x0"});
  problem.elasticity.dirichlet.push_back({of_body(mesh, y0, first_lower, true), {}, {false, true, false}, "upper.y0"});
  problem.elasticity.dirichlet.push_back({of_body(mesh, x0, first_lower, false), {}, {true, false, false}, "lower.x0"});
  problem.elasticity.dirichlet.push_back({of_body(mesh, y0, first_lower, false), {}, {false, true, false}, "lower.y0"});
  problem.elasticity.dirichlet.push_back({faces_at(mesh, 2, 0.0), {}, {false, false, true}, "lower.bottom"});
  TractionLoad3D load;
  load.facets = faces_at(mesh, 2, 1.0);
  const double p = patch.p;
  load.pressure = [p](const Vec3&) { return p; };
  problem.elasticity.tractions.push_back(load);
  problem.parts.push_back(interface_part(s));
  return problem;
}

void expect_patch_passed(const Stack& s, const Patch& patch, const ContactSolution3D& sol) {
  ASSERT_TRUE(sol.converged()) << sol.message;
  ASSERT_EQ(sol.held_by_contact.size(), 1u);  // the upper block's translation along z
  const Mesh3D& mesh = s.joined.mesh;
  double worst = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    worst = std::max(worst, (sol.u.segment<3>(3 * v) - patch.exact(mesh.vertex(v), s.upper_vertex(v))).norm());
  EXPECT_LT(worst, 1e-10);
  ASSERT_FALSE(sol.contact.empty());
  double area = 0.0;
  for (const ContactNode3D& n : sol.contact) {
    ASSERT_GE(n.partner, 0);
    EXPECT_TRUE(s.upper_vertex(n.vertex));
    EXPECT_FALSE(s.upper_vertex(n.partner));
    EXPECT_NEAR(n.force() / n.weight, patch.p, 1e-10 * patch.p) << "node at " << n.x.transpose();
    EXPECT_NEAR(n.u_nu, 0.0, 1e-12);
    EXPECT_EQ(mesh.vertex(n.partner), n.x);
    area += n.weight;
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
  // the interface's forces are internal: the supports carry the load
  EXPECT_LT(sol.forces.residual(), 1e-10);
  EXPECT_NEAR(sol.contact_force().z(), patch.p, 1e-10);
}

void expect_patch_passed_by_both_minimizers(const Stack& s) {
  const Patch patch;
  const ContactProblem3D problem = patch_problem(s, patch);
  for (const std::string minimizer : {"ssn", "bundle-dca"}) {
    SCOPED_TRACE(minimizer);
    expect_patch_passed(s, patch, solve(problem, minimizer));
  }
}

}  // namespace

TEST(TwoBodies3D, JoinedSolidsTouchingStayTwoPieces) {
  Mesh3D upper = make_cubes({3, 3, 2}, upper_box);
  upper.set_face_group("bottom", faces_at(upper, 2, 0.5));
  const Mesh3D lower = make_tetrahedra({2, 2, 2}, lower_box);
  const MatchedInterface3D m = match_interface_3d(upper, faces_at(upper, 2, 0.5), lower, faces_at(lower, 2, 0.5), 1e-6);
  const JoinedMeshes3D j = join_meshes({&m.first, &m.second}, {"upper", "lower"});
  const Mesh3D& mesh = j.mesh;
  EXPECT_EQ(mesh.num_vertices(), m.first.num_vertices() + m.second.num_vertices());
  EXPECT_EQ(mesh.num_cells(), m.first.num_cells() + m.second.num_cells());
  // the faces at one place of the interface stay two boundary faces, one per body
  EXPECT_EQ(mesh.num_faces(), m.first.num_faces() + m.second.num_faces());
  EXPECT_EQ(mesh.boundary_faces().size(), m.first.boundary_faces().size() + m.second.boundary_faces().size());
  EXPECT_EQ(j.first_vertex, (std::vector<int>{0, m.first.num_vertices()}));
  EXPECT_EQ(j.first_cell, (std::vector<int>{0, m.first.num_cells()}));
  EXPECT_EQ(j.first_region, (std::vector<int>{0, 1}));
  EXPECT_EQ(mesh.region(mesh.num_cells() - 1), 1);
  EXPECT_NEAR(mesh.total_volume(), 1.0, 1e-14);
  for (int b = 0; b < 2; ++b) {
    const Mesh3D& own = b == 0 ? m.first : m.second;
    ASSERT_EQ(j.facet_of[static_cast<std::size_t>(b)].size(), static_cast<std::size_t>(own.num_faces()));
    for (int f = 0; f < own.num_faces(); ++f) {
      const MeshFace& face = mesh.face(j.facet_of[static_cast<std::size_t>(b)][static_cast<std::size_t>(f)]);
      std::vector<int> shifted = own.face(f).vertices;
      for (int& v : shifted) v += j.first_vertex[static_cast<std::size_t>(b)];
      EXPECT_EQ(face.vertices, shifted);
      EXPECT_EQ(face.on_boundary(), own.face(f).on_boundary());
    }
  }
  // the interface vertices of the two bodies coincide, pair by pair
  for (const auto& [a, b] : m.pairs) EXPECT_EQ(mesh.vertex(a), mesh.vertex(j.first_vertex[1] + b));
  std::vector<int> bottom;
  for (int f : m.first.face_group("bottom")) bottom.push_back(j.facet_of[0][static_cast<std::size_t>(f)]);
  EXPECT_EQ(mesh.face_group("upper.bottom"), bottom);
  EXPECT_EQ(mesh.face_groups().size(), 1u);
  // a body joined with itself: every vertex and face doubled at its place, every face of one
  // copy a face of that copy only (no face is taken for an interior face of both)
  const JoinedMeshes3D twice = join_meshes({&lower, &lower}, {"a", "b"});
  EXPECT_EQ(twice.mesh.num_vertices(), 2 * lower.num_vertices());
  EXPECT_EQ(twice.mesh.num_faces(), 2 * lower.num_faces());
  EXPECT_EQ(twice.mesh.boundary_faces().size(), 2 * lower.boundary_faces().size());
  for (int f = 0; f < twice.mesh.num_faces(); ++f) {
    const MeshFace& face = twice.mesh.face(f);
    EXPECT_EQ(face.inner < lower.num_cells(), face.vertices.front() < lower.num_vertices());
    if (!face.on_boundary()) EXPECT_EQ(face.inner < lower.num_cells(), face.outer < lower.num_cells());
  }
  EXPECT_THROW(join_meshes(std::vector<const Mesh3D*>{}, {}), InputError);
  EXPECT_THROW(join_meshes({&m.first, nullptr}, {"a", "b"}), InputError);
  EXPECT_THROW(join_meshes({&m.first, &m.second}, {"a", "a"}), InputError);
  EXPECT_THROW(join_meshes({&m.first, &m.second}, {"a"}), InputError);
}

TEST(TwoBodies3D, ContactPatchTestWithNonMatchingCubes) {
  expect_patch_passed_by_both_minimizers(stack(make_cubes({3, 3, 2}, upper_box), make_cubes({2, 2, 2}, lower_box)));
}

TEST(TwoBodies3D, ContactPatchTestWithCubesOnTetrahedra) {
  expect_patch_passed_by_both_minimizers(stack(make_cubes({3, 3, 2}, upper_box), make_tetrahedra({2, 2, 2}, lower_box)));
}

TEST(TwoBodies3D, ContactPatchTestWithVoronoiOnOneSide) {
  expect_patch_passed_by_both_minimizers(stack(make_voronoi3d({3, 3, 2}, upper_box), make_cubes({2, 2, 2}, lower_box)));
}

TEST(TwoBodies3D, UnmatchedMeshesAreRefusedByName) {
  const Patch patch;
  const Stack s = stack(make_cubes({3, 3, 2}, upper_box), make_cubes({2, 2, 2}, lower_box), false);
  try {
    (void)solve(patch_problem(s, patch), "ssn");
    FAIL() << "unmatched meshes were solved";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no vertex of the other body"), std::string::npos) << e.what();
  }
}

// Tresca friction between the solids, on the relative tangential displacement: the upper block,
// held by the contact alone (normal and tangential), is pressed by p and sheared by tau < g
// along x on its top, with the complementary shear on both blocks' sides x0 and x1; the lower
// block is clamped at its bottom. With nu = 0 the exact field is linear in each block
// (sigma_zz = -p, sigma_xz = tau), the interface stuck: the relative displacement 0, the
// friction force tau and the pressure p at every node.
namespace {

struct Sheared {
  double p = 2.0, tau = 0.7, g = 1.0;
  Material upper{10.0, 0.0}, lower{4.0, 0.0};
  /// The exact displacement at vertex x of the upper (or lower) block: below
  /// u = (tau/mu_l z, 0, -p/E_l z), above continuous at z = 0.5 (mu = E/2 with nu = 0).
  Vec3 exact(const Vec3& x, bool up) const {
    const double z0 = up ? 0.5 : 0.0;
    const Material& m = up ? upper : lower;
    const Vec3 base = up ? Vec3(tau / (lower.young / 2.0) * 0.5, 0.0, -p / lower.young * 0.5) : Vec3::Zero();
    return base + Vec3(tau / (m.young / 2.0) * (x.z() - z0), 0.0, -p / m.young * (x.z() - z0));
  }
};

ContactProblem3D sheared_problem(const Stack& s, const Sheared& load) {
  const Mesh3D& mesh = s.joined.mesh;
  ContactProblem3D problem;
  problem.elasticity.mesh = &mesh;
  problem.elasticity.materials = materials(s, load.upper, load.lower);
  problem.elasticity.dirichlet.push_back({faces_at(mesh, 2, 0.0), {}, {true, true, true}, "lower.bottom"});
  TractionLoad3D top, x0, x1;
  top.facets = faces_at(mesh, 2, 1.0);
  top.traction = [&load](const Vec3&) { return Vec3(load.tau, 0.0, -load.p); };
  x0.facets = faces_at(mesh, 0, 0.0);
  x0.traction = [&load](const Vec3&) { return Vec3(0.0, 0.0, -load.tau); };
  x1.facets = faces_at(mesh, 0, 1.0);
  x1.traction = [&load](const Vec3&) { return Vec3(0.0, 0.0, load.tau); };
  problem.elasticity.tractions = {top, x0, x1};
  ContactPart3D part = interface_part(s);
  part.friction = tresca_law(load.g);
  problem.parts.push_back(part);
  return problem;
}

}  // namespace

TEST(TwoBodies3D, TrescaFrictionHoldsAStuckInterfaceExactly) {
  const Stack s = stack(make_cubes({3, 3, 2}, upper_box), make_tetrahedra({2, 2, 2}, lower_box));
  const Sheared load;
  const ContactProblem3D problem = sheared_problem(s, load);
  const Mesh3D& mesh = s.joined.mesh;
  for (const std::string minimizer : {"ssn", "bundle-dca"}) {
    SCOPED_TRACE(minimizer);
    const ContactSolution3D sol = solve(problem, minimizer);
    ASSERT_TRUE(sol.converged()) << sol.message;
    // the upper block's six rigid motions: the normal contact holds the translation along z
    // and the rotations about x and y, the friction the translations along x and y and the
    // rotation about z
    EXPECT_EQ(sol.held_by_contact.size(), 6u);
    double worst = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      worst = std::max(worst, (sol.u.segment<3>(3 * v) - load.exact(mesh.vertex(v), s.upper_vertex(v))).norm());
    EXPECT_LT(worst, 1e-10);
    double area = 0.0;
    for (const ContactNode3D& n : sol.contact) {
      ASSERT_GE(n.partner, 0);
      EXPECT_NEAR(n.u_tau, 0.0, 1e-12);
      EXPECT_EQ(n.friction_state, FrictionState::stick);
      EXPECT_NEAR(n.friction_force / n.weight, load.tau, 1e-9) << "node at " << n.x.transpose();
      // the lower body pushes the upper one by -zeta_t: along -x, against the shear on its top
      EXPECT_NEAR(n.friction_vector.x() / n.weight, load.tau, 1e-9);
      EXPECT_NEAR(n.force() / n.weight, load.p, 1e-9);
      area += n.weight;
    }
    EXPECT_NEAR(area, 1.0, 1e-12);
    EXPECT_LT(sol.forces.residual(), 1e-10);
  }
}
