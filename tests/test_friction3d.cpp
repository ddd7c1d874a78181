// Friction on a solid's surface (docs/friction.md): the law acts on the norm of the tangential
// displacement, the node's two tangential coordinates a group of the reduced problem. A block
// sheared over a Tresca foundation has an exact linear solution (every node slipping); with a
// bound that is never reached it is the block clamped at its bottom; every engine that takes
// groups agrees with them.
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace hemivem;

namespace {

constexpr double young = 100.0, poisson = 0.3, shift = 0.01, bound = 0.1, height = 0.5;
const double shear_modulus = young / (2.0 * (1.0 + poisson));
const Box block{0.0, 1.0, 0.0, 1.0, 0.0, height};

std::unique_ptr<SparseFactorization> engine(const std::string& name = "eigen") {
  FactorizationOptions o;
  o.engine = name;
  return make_factorization(o);
}

// The block on a bilateral Tresca foundation of bound g (u_z = 0 at the bottom), its top moved
// by (shift, 0, 0), the shear traction g on its x-sides that simple shear needs there: the
// exact solution is u = (shift - (h - z) g / G, 0, 0), the stress sigma_xz = g, and every bottom
// node slips along x with the friction force g w_i.
ContactProblem3D sheared_block(const Mesh3D& mesh, double g) {
  ContactProblem3D p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{young, poisson}, PlaneModel::strain);
  p.elasticity.dirichlet.push_back(
      {select_box_side(mesh, block, "top"), [](const Vec3&) { return Vec3(shift, 0, 0); }, {true, true, true}, "top"});
  for (const auto& [side, sign] : {std::pair{"x0", -1.0}, std::pair{"x1", 1.0}}) {
    TractionLoad3D t;
    t.facets = select_box_side(mesh, block, side);
    t.traction = [g, s = sign](const Vec3&) { return Vec3(0, 0, s * g); };
    p.elasticity.tractions.push_back(t);
  }
  ContactPart3D contact;
  contact.name = "foundation";
  contact.facets = select_box_side(mesh, block, "bottom");
  contact.law = zero_law();
  contact.constraint = ConstraintKind::bilateral;
  contact.friction = tresca_law(g);
  p.parts.push_back(std::move(contact));
  return p;
}

Vec3 simple_shear(const Vec3& x, double g) { return Vec3(shift - (height - x.z()) * g / shear_modulus, 0, 0); }

}  // namespace

TEST(Friction3D, ASolidsNodeHasTwoTangentialCoordinatesInAGroup) {
  const Mesh3D mesh = make_cubes({2, 2, 1}, block);
  const ContactProblem3D p = sheared_block(mesh, bound);
  const LinearSystem sys = assemble(p.elasticity);
  const ContactBoundary b = contact_boundary(p, sys.dofs);
  const Condensation cond(sys, b, engine(), part_conditions(p.parts));
  const ReducedProblem& rp = cond.reduced();
  // bilateral: no normal unknowns; two tangentials per node, each pair a group
  ASSERT_EQ(rp.size(), 2 * b.size());
  ASSERT_EQ(static_cast<int>(rp.groups.size()), b.size());
  for (int i = 0; i < b.size(); ++i) {
    EXPECT_EQ(cond.normal_coordinate(i), -1);
    const int k1 = cond.tangential_coordinate(i), k2 = cond.second_tangential_coordinate(i);
    ASSERT_GE(k1, 0);
    ASSERT_GE(k2, 0);
    EXPECT_EQ(rp.groups[static_cast<std::size_t>(i)].first, k1);
    EXPECT_EQ(rp.groups[static_cast<std::size_t>(i)].second, k2);
    // the two tangential directions and the normal are an orthonormal frame
    const Vec3 nu = cond.slot_direction(i, 0), t1 = cond.slot_direction(i, 1), t2 = cond.slot_direction(i, 2);
    EXPECT_NEAR(nu.dot(t1), 0.0, 1e-15);
    EXPECT_NEAR(nu.dot(t2), 0.0, 1e-15);
    EXPECT_NEAR(t1.dot(t2), 0.0, 1e-15);
    EXPECT_NEAR(t1.norm(), 1.0, 1e-15);
  }
}

TEST(Friction3D, ABlockShearedOverATrescaFoundationIsSimpleShearOnEveryMesh) {
  for (const char* kind : {"cubes", "tetrahedra", "voronoi"}) {
    SCOPED_TRACE(kind);
    const Mesh3D mesh = make_mesh3d(kind, {3, 3, 2}, block);
    const ContactProblem3D p = sheared_block(mesh, bound);
    const ContactSolution3D s = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    ASSERT_TRUE(s.converged()) << s.message;
    double area = 0.0;
    for (const ContactNode3D& n : s.contact) {
      EXPECT_EQ(n.friction_state, FrictionState::slip);
      EXPECT_NEAR((n.u_tangential - simple_shear(n.x, bound)).norm(), 0.0, 1e-11);
      EXPECT_NEAR((n.friction_vector - Vec3(bound * n.weight, 0, 0)).norm(), 0.0, 1e-11 * bound * n.weight);
      EXPECT_NEAR(n.u_tau, n.u_tangential.norm(), 0.0);
      EXPECT_NEAR(n.friction_force, bound * n.weight, 1e-11 * bound * n.weight);
      area += n.weight;
    }
    EXPECT_NEAR(area, 1.0, 1e-13);
    for (int v = 0; v < mesh.num_vertices(); ++v)
      EXPECT_LT((s.u.segment<3>(3 * v) - simple_shear(mesh.vertex(v), bound)).norm(), 1e-11) << "vertex " << v;
    // the foundation pulls the body back by g times the area; the balance closes
    EXPECT_TRUE(s.contact_force().isApprox(Vec3(-bound, 0, 0), 1e-11)) << s.contact_force().transpose();
    EXPECT_LT(s.forces.residual(), 1e-10);
  }
}

TEST(Friction3D, ABoundThatIsNeverReachedClampsTheBottom) {
  const Mesh3D mesh = make_tetrahedra({2, 2, 2}, block);
  const ContactProblem3D p = sheared_block(mesh, 1e6);
  const ContactSolution3D s = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(s.converged()) << s.message;
  for (const ContactNode3D& n : s.contact) {
    EXPECT_EQ(n.friction_state, FrictionState::stick);
    EXPECT_EQ(n.u_tangential, Vec3::Zero());
  }
  // the same block clamped at its bottom: one linear solve
  ElasticityProblem3D clamped = p.elasticity;
  clamped.dirichlet.push_back({select_box_side(mesh, block, "bottom"), {}, {true, true, true}, "bottom"});
  ContactProblem3D linear;
  linear.elasticity = clamped;
  const ContactSolution3D c = solve_contact(linear, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(c.converged()) << c.message;
  EXPECT_LT((s.u - c.u).cwiseAbs().maxCoeff(), 1e-10 * c.u.cwiseAbs().maxCoeff());
  // the friction forces are the clamp's reactions, inside the (never reached) bound
  ASSERT_EQ(c.forces.reactions.back().name, "bottom");
  const Vec3 clamp = c.forces.reactions.back().force;
  EXPECT_LT((s.contact_force() - clamp).norm(), 1e-8 * clamp.norm())
      << s.contact_force().transpose() << " against " << clamp.transpose();
}

TEST(Friction3D, EveryMinimizerThatTakesGroupsAgreesAndTheOthersRefuseByName) {
  const Mesh3D mesh = make_cubes({3, 3, 2}, block);
  ContactProblem3D p = sheared_block(mesh, bound);
  // a foundation that lets go of part of the bottom: a one-sided contact with gap, slip and stick
  p.parts[0].constraint = ConstraintKind::one_sided;
  p.parts[0].gap = [](const Vec3& x) { return 0.0005 * x.x(); };
  p.parts[0].law = linear_law(2000.0);
  p.parts[0].friction = tresca_law(0.8);
  p.elasticity.dirichlet[0].value = [](const Vec3&) { return Vec3(shift, 0.3 * shift, -0.004); };
  const ContactSolution3D reference = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(reference.converged()) << reference.message;
  int stuck = 0, slipping = 0;
  for (const ContactNode3D& n : reference.contact) {
    stuck += n.friction_state == FrictionState::stick;
    slipping += n.friction_state == FrictionState::slip;
  }
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slipping, 0);
  int agreeing = 0;
  for (const std::string& m : available_minimizers()) {
    SCOPED_TRACE(m);
    if (m == "ssn" || m == "global-search") continue;
    const auto minimizer = make_minimizer(m);
    if (!minimizer->takes_groups()) {
      try {
        (void)solve_contact(p, engine(), *minimizer, MinimizerOptions{});
        ADD_FAILURE() << m << " solved a problem with groups it does not take";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(m + " does not take groups"), std::string::npos) << e.what();
      }
      continue;
    }
    const ContactSolution3D s = solve_contact(p, engine(), *minimizer, MinimizerOptions{});
    ASSERT_TRUE(s.converged()) << s.message;
    EXPECT_LT((s.u - reference.u).cwiseAbs().maxCoeff(), 1e-7 * reference.u.cwiseAbs().maxCoeff());
    ++agreeing;
  }
  RecordProperty("engines_agreeing_with_ssn", agreeing);
}
