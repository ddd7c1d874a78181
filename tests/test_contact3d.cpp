// Contact of a three-dimensional body: a block pressed onto a rigid plane (an exact linear
// solution), every minimizer and linear engine on it, obstacles, and what is refused.
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <gtest/gtest.h>

#include "pressed_block3d.hpp"

#include <cmath>

using namespace hemivem;

namespace {

using test::pressed_block;

std::unique_ptr<SparseFactorization> engine(const std::string& name = "eigen") {
  FactorizationOptions o;
  o.engine = name;
  return make_factorization(o);
}

constexpr double young = test::pressed_block_young, poisson = test::pressed_block_poisson,
                 depth = test::pressed_block_depth;

}  // namespace

TEST(Contact3D, BlockPressedOnAPlaneIsUniaxialStress) {
  const Box box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  for (const auto& kind : {"cubes", "tetrahedra"}) {
    const Mesh3D mesh = make_mesh3d(kind, {3, 3, 2}, box);
    const ContactProblem3D p = pressed_block(mesh, box);
    const ContactSolution3D s = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    ASSERT_TRUE(s.converged()) << kind << ": " << s.message;
    // every bottom node (the corner on both symmetry planes included) is in contact
    EXPECT_EQ(s.contact.size(), 16u) << kind;
    const double strain = depth / 0.5, stress = young * strain;
    double area = 0.0;
    for (const ContactNode3D& n : s.contact) {
      EXPECT_EQ(n.state, ContactState::at_gap) << kind;
      EXPECT_NEAR(n.u_nu, 0.0, 1e-14);
      EXPECT_TRUE(n.normal.isApprox(Vec3(0, 0, -1), 1e-15));
      EXPECT_NEAR(n.pressure(), stress, 1e-9 * stress) << kind << " at " << n.x.transpose();
      area += n.weight;
    }
    EXPECT_NEAR(area, 1.0, 1e-14);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const Vec3 x = mesh.vertex(v);
      const Vec3 expected(poisson * strain * x.x(), poisson * strain * x.y(), -strain * x.z());
      EXPECT_LT((s.u.segment<3>(3 * v) - expected).norm(), 1e-11) << kind;
    }
    EXPECT_TRUE(s.contact_force().isApprox(Vec3(0, 0, stress), 1e-9));
    EXPECT_LT(s.forces.residual(), 1e-10);
  }
}

TEST(Contact3D, EveryMinimizerAndLinearEngineAgree) {
  const Box box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  const Mesh3D mesh = make_cubes({3, 3, 2}, box);
  ContactProblem3D p = pressed_block(mesh, box);
  // a stiff nonmonotone foundation instead of the rigid plane: some nodes on the law, none at a bound
  p.parts[0].obstacle.reset();
  p.parts[0].gap = [](const Vec3& x) { return 0.002 + 0.004 * x.x() * x.y(); };
  p.parts[0].law = paper_law();
  std::vector<Eigen::VectorXd> answers;
  for (const std::string& m : available_minimizers()) {
    if (m == "global-search") continue;
    for (const std::string& e : available_factorizations()) {
      if (e == "mumps-mpi") continue;
      const ContactSolution3D s = solve_contact(p, engine(e), *make_minimizer(m), MinimizerOptions{});
      ASSERT_TRUE(s.converged()) << m << " with " << e << ": " << s.message;
      answers.push_back(s.u);
    }
  }
  ASSERT_GE(answers.size(), 2u);
  for (const auto& u : answers) EXPECT_LT((u - answers.front()).cwiseAbs().maxCoeff(), 1e-6 * answers.front().cwiseAbs().maxCoeff());
}

TEST(Contact3D, SphereAndCylinderGapsAlongTheNormal) {
  Obstacle3D sphere;
  sphere.shape = Obstacle3D::Shape::sphere;
  sphere.center = Vec3(0, 0, 2);
  sphere.radius = 1.0;
  // from below, straight up: the sphere's bottom at z = 1
  EXPECT_DOUBLE_EQ(sphere.gap(Vec3(0, 0, 0), Vec3(0, 0, 1)), 1.0);
  EXPECT_NEAR(sphere.gap(Vec3(0.6, 0, 0.5), Vec3(0, 0, 1)), 1.5 - 0.8, 1e-15);
  EXPECT_TRUE(std::isinf(sphere.gap(Vec3(1.5, 0, 0), Vec3(0, 0, 1))));
  // inside: a negative gap
  EXPECT_NEAR(sphere.gap(Vec3(0, 0, 1.5), Vec3(0, 0, 1)), -0.5, 1e-15);
  Obstacle3D cylinder;
  cylinder.shape = Obstacle3D::Shape::cylinder;
  cylinder.center = Vec3(0, 0, 2);
  cylinder.axis = Vec3(1, 0, 0);
  cylinder.radius = 1.0;
  EXPECT_NEAR(cylinder.gap(Vec3(5, 0, 0), Vec3(0, 0, 1)), 1.0, 1e-15);
  EXPECT_NEAR(cylinder.gap(Vec3(-3, 0.6, 0), Vec3(0, 0, 1)), 2.0 - 0.8, 1e-15);
  EXPECT_TRUE(std::isinf(cylinder.gap(Vec3(0, 0, 0), Vec3(1, 0, 0))));
  EXPECT_TRUE(cylinder.defect().empty());
  cylinder.axis = Vec3::Zero();
  EXPECT_NE(cylinder.defect().find("axis"), std::string::npos);
  EXPECT_THROW(obstacle3d_shape_from_string("circle"), InputError);
}

TEST(Contact3D, RefusesWhatItCannotSolve) {
  const Box box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  const Mesh3D mesh = make_cubes(2, box);
  // a body that neither its supports nor its frictionless contact hold (the rollers leave the
  // sliding along y free)
  ContactProblem3D loose = pressed_block(mesh, box);
  loose.elasticity.dirichlet.erase(loose.elasticity.dirichlet.begin() + 1);
  try {
    (void)solve_contact(loose, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("translation along y"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot hold"), std::string::npos) << e.what();
  }
  // a prescribed normal component takes a contact node out of the contact (the support holds
  // it); on every contact node it leaves the part nothing to touch
  ContactProblem3D normal_fixed = pressed_block(mesh, box);
  const ContactSolution3D all = solve_contact(normal_fixed, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  normal_fixed.elasticity.dirichlet.push_back({select_box_side(mesh, box, "x1"), {}, {false, false, true}, "x1"});
  const ContactSolution3D fewer = solve_contact(normal_fixed, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(fewer.converged()) << fewer.message;
  EXPECT_EQ(fewer.contact.size(), all.contact.size() - 3);  // the three bottom nodes on x = 1
  for (const auto& n : fewer.contact) EXPECT_LT(n.x.x(), 1.0);
  EXPECT_LT(fewer.forces.sum().norm(), 1e-10 * fewer.forces.contact.norm());  // driven by a displacement: no load
  normal_fixed.elasticity.dirichlet.push_back({select_box_side(mesh, box, "bottom"), {}, {false, false, true}, "z0"});
  try {
    (void)solve_contact(normal_fixed, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no contact node left"), std::string::npos) << e.what();
  }
  // friction on a 3D boundary: two tangentials per node (one where a symmetry plane holds the
  // other, none on the corner held by both), each pair a group
  const LinearSystem sys = assemble(pressed_block(mesh, box).elasticity);
  const ContactBoundary b = make_contact_boundary(mesh, select_box_side(mesh, box, "bottom"), sys.dofs, {});
  EXPECT_EQ(b.dimension, 3);
  const Condensation friction(sys, b, engine(), zero_law(), ConstraintKind::box, tresca_law(0.1));
  int pairs = 0, singles = 0, none = 0;
  for (int i = 0; i < b.size(); ++i) {
    const Vec3 x = mesh.vertex(b.nodes[static_cast<std::size_t>(i)]);
    const int held = (x.x() == 0.0) + (x.y() == 0.0);
    const bool first = friction.tangential_coordinate(i) >= 0, second = friction.second_tangential_coordinate(i) >= 0;
    EXPECT_EQ(first, held < 2) << x.transpose();
    EXPECT_EQ(second, held == 0) << x.transpose();
    pairs += second, singles += first && !second, none += !first;
  }
  EXPECT_EQ(static_cast<int>(friction.reduced().groups.size()), pairs);
  EXPECT_EQ(pairs, 4);
  EXPECT_EQ(singles, 4);
  EXPECT_EQ(none, 1);
}

TEST(Contact3D, WeightsAreAreaSharesAndNormalsAreAreaWeighted) {
  // the contact faces of two sides meeting at an edge: the nodes on the edge get both normals
  const Box box{0.0, 2.0, 0.0, 1.0, 0.0, 1.0};
  const Mesh3D mesh = make_cubes({2, 1, 1}, box);
  ElasticityProblem3D e;
  e.mesh = &mesh;
  e.materials = MaterialTable(Material{1.0, 0.0}, PlaneModel::strain);
  e.dirichlet.push_back({select_box_side(mesh, box, "x0"), {}, {true, true, true}, "x0"});
  const LinearSystem sys = assemble(e);
  std::vector<int> faces = select_box_side(mesh, box, "top");
  for (int f : select_box_side(mesh, box, "x1")) faces.push_back(f);
  const ContactBoundary b = make_contact_boundary(mesh, faces, sys.dofs, {});
  // nodes off x0: the top's 4 at x = 1, 2 and the x1 side's 4 (two shared)
  ASSERT_EQ(b.size(), 6);
  double total = 0.0;
  for (int i = 0; i < b.size(); ++i) {
    total += b.weights(i);
    const Vec3 x = mesh.vertex(b.nodes[static_cast<std::size_t>(i)]);
    if (x.x() == 2.0 && x.z() == 1.0) {
      EXPECT_NEAR(b.weights(i), 0.25 + 0.25, 1e-15);
      EXPECT_TRUE(b.normals3d[static_cast<std::size_t>(i)].isApprox(Vec3(1, 0, 1).normalized(), 1e-15));
    }
  }
  EXPECT_NEAR(total, 3.0 - 0.5, 1e-14);  // the areas of the faces (2 + 1) less the shares of the clamped nodes
}

// On Voronoi faces (polygons whose vertex mean is not their centroid) the weights are the face
// integrals of the basis functions, the weights of the load: a uniform pressure gives every
// node its exact pressure.
TEST(Contact3D, PressuresAreExactOnVoronoiFaces) {
  const Box box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  const Mesh3D mesh = make_mesh3d("voronoi", {4, 4, 2}, box);
  const ContactProblem3D p = pressed_block(mesh, box);
  const ContactSolution3D s = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(s.converged()) << s.message;
  const double stress = young * depth / 0.5;
  double area = 0.0;
  for (const ContactNode3D& n : s.contact) {
    EXPECT_NEAR(n.pressure(), stress, 1e-9 * stress) << "at " << n.x.transpose();
    area += n.weight;
  }
  EXPECT_NEAR(area, 1.0, 1e-13);
}
