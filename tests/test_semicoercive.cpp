// Bodies held by their contact: the rigid motions the Dirichlet conditions leave free are found
// before anything is factorized (hemivem/vem/rigid_motions.hpp, hemivem/contact/supports.hpp);
// a motion only the contact holds is solved (the condensation of a singular A), a motion that
// nothing holds is refused by name, and a contact node with a tangential prescribed component (a
// roller meeting the contact) is allowed.
#include <hemivem/contact/solver.hpp>
#include <hemivem/contact/supports.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace hemivem {
namespace {

// A block of width 4 and height 1 between two rollers (ux = 0 on the sides, corners
// included), a traction (0, -p) on its top, on a linear foundation of stiffness k and no gap:
// nothing but the foundation holds it vertically.
std::string block_scene(const std::string& mesh, double E, double p, double k, const std::string& sides = "") {
  return R"(
schema_version = 1
[mesh]
)" + mesh + R"(
domain = [0, 4, 0, 1]
[material]
E = )" + std::to_string(E) +
         R"(
nu = 0.3
[[dirichlet]]
)" + (sides.empty() ? "side = \"left\"" : sides) +
         R"(
ux = 0.0
[[dirichlet]]
side = "right"
ux = 0.0
[loads]
[[loads.traction]]
side = "top"
value = [0.0, )" + std::to_string(-p) +
         R"(]
[contact]
side = "bottom"
law = "linear"
constraint = "none"
[contact.parameters]
stiffness = )" + std::to_string(k) +
         "\n";
}

ContactSolution solve_scene_text(const std::string& text, const std::string& linear = "auto",
                                 const std::string& minimizer = "ssn") {
  const Scene scene = parse_scene_string(text, "block.toml");
  const auto built = build_problem(scene);
  FactorizationOptions f;
  f.engine = linear;
  MinimizerOptions o;
  o.tolerance = 1e-10;
  return solve_contact(built->problem, make_factorization(f), *make_minimizer(minimizer), o);
}

TEST(RigidMotions, TheFreeMotionsOfTheSupportsAreNamed) {
  const Mesh mesh = make_squares(4);
  // nothing prescribed: two translations and a rotation
  const RigidMotions all(mesh, make_dof_map(mesh, {}));
  ASSERT_EQ(all.size(), 3);
  EXPECT_EQ(all.describe(0), "translation along (1, 0) of the body");
  EXPECT_EQ(all.describe(1), "translation along (0, 1) of the body");
  EXPECT_EQ(all.describe(2), "rotation about (0.5, 0.5) of the body");
  // ux = 0 on the left side: the vertical translation is left
  DirichletCondition roller;
  roller.facets = select_boundary_edges(mesh, [](const Vec2& a, const Vec2& b) { return a.x() == 0.0 && b.x() == 0.0; });
  roller.value = [](const Vec2&) { return Vec2::Zero(); };
  roller.fix = {true, false};
  const RigidMotions one(mesh, make_dof_map(mesh, {roller}));
  ASSERT_EQ(one.size(), 1);
  EXPECT_EQ(one.describe(0), "translation along (0, 1) of the body");
  // uy = 0 at the bottom as well: held
  DirichletCondition bottom = roller;
  bottom.facets = select_boundary_edges(mesh, [](const Vec2& a, const Vec2& b) { return a.y() == 0.0 && b.y() == 0.0; });
  bottom.fix = {false, true};
  EXPECT_TRUE(RigidMotions(mesh, make_dof_map(mesh, {roller, bottom})).empty());
}

TEST(RigidMotions, TheDecisionDoesNotDependOnTheUnits) {
  for (const double scale : {1e-100, 1e-8, 1.0, 1e8, 1e100}) {
    SCOPED_TRACE(scale);
    const Mesh mesh = make_squares(3, Rectangle{0, scale, 0, scale});
    DirichletCondition pin;  // ux = 0 on the left side only: vertical translation left
    pin.facets = select_boundary_edges(mesh, [](const Vec2& a, const Vec2& b) { return a.x() == 0.0 && b.x() == 0.0; });
    pin.value = [](const Vec2&) { return Vec2::Zero(); };
    pin.fix = {true, false};
    const RigidMotions m(mesh, make_dof_map(mesh, {pin}));
    ASSERT_EQ(m.size(), 1);
    EXPECT_EQ(m.describe(0), "translation along (0, 1) of the body");
  }
}

TEST(SemiCoercive, BlockBetweenRollersConvergesForEveryStiffnessAndMesh) {
  const double p = 2.0, k = 50.0;
  for (const std::string mesh : {"generator = \"squares\"\nn = [16, 4]", "generator = \"squares\"\nn = [32, 8]",
                                 "generator = \"squares\"\nn = [64, 16]", "generator = \"voronoi\"\nn = [24, 6]",
                                 "generator = \"triangles\"\nn = [16, 4]"})
    for (const double E : {50.0, 65.0, 100.0, 1e3, 1e4, 1e5}) {
      SCOPED_TRACE(mesh + ", E = " + std::to_string(E));
      const ContactSolution s = solve_scene_text(block_scene(mesh, E, p, k));
      ASSERT_TRUE(s.converged()) << s.message;
      ASSERT_EQ(s.held_by_contact.size(), 1u);
      EXPECT_EQ(s.held_by_contact[0], "translation along (0, 1) of the body");
      // one-dimensional: a uniform compression, the settlement is the load over the stiffness
      for (const ContactNode& n : s.contact) EXPECT_NEAR(n.u_nu, p / k, 1e-10 * p / k) << "vertex " << n.vertex;
    }
}

TEST(SemiCoercive, EveryEngineSolvesTheBlockWithRollersAwayFromTheCorners) {
  // the left roller only on the upper half of the side: the problem is two-dimensional
  const std::string text = block_scene("generator = \"squares\"\nn = [16, 4]", 100.0, 2.0, 50.0,
                                       "segments = [[0, 0.5, 0, 1]]");
  ContactSolution reference;
  for (const std::string& linear : available_factorizations())
    for (const std::string minimizer : {"ssn", "bundle-dca", "nlopt-mma", "ceres-active-set"}) {
      SCOPED_TRACE(linear + " " + minimizer);
      if (linear == "mumps-mpi") continue;
      const ContactSolution s = solve_scene_text(text, linear, minimizer);
      ASSERT_TRUE(s.converged()) << s.message;
      Vec2 load(0.0, -2.0 * 4.0);
      // the foundation carries the whole vertical load (the rollers are vertical)
      EXPECT_NEAR(s.contact_force().y(), -load.y(), 1e-8 * 8.0);
      if (reference.u.size() == 0) reference = s;
      else EXPECT_LT((s.u - reference.u).cwiseAbs().maxCoeff(), 1e-6 * reference.u.cwiseAbs().maxCoeff());
    }
}

TEST(SemiCoercive, AMotionTheContactCannotHoldIsRefusedByName) {
  // uy = 0 on both sides: the horizontal translation is free, and frictionless contact on the
  // bottom (away from the corners) does not resist it
  std::string text = block_scene("generator = \"squares\"\nn = [8, 2]", 100.0, 2.0, 50.0);
  text.replace(text.find("ux = 0.0"), 8, "uy = 0.0");
  text.replace(text.find("ux = 0.0"), 8, "uy = 0.0");
  text.replace(text.find("side = \"bottom\""), 15, "segments = [[0.5, 0, 3.5, 0]]");
  try {
    (void)solve_scene_text(text);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("translation along (1, 0) of the body"), std::string::npos) << what;
    EXPECT_NE(what.find("frictionless"), std::string::npos) << what;
  }
}

// Three separate 4 x 4 squares side by side, x in [0, 1], [2, 3], [4, 5].
std::filesystem::path three_squares() {
  const auto path = std::filesystem::temp_directory_path() / "hemivem-three-squares.poly2d";
  std::ofstream out(path);
  out << "vertices " << 3 * 25 << "\n";
  for (int b = 0; b < 3; ++b)
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i) out << 2 * b + i / 4.0 << " " << j / 4.0 << "\n";
  out << "elements " << 3 * 16 << "\n";
  for (int b = 0; b < 3; ++b)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const int v = 25 * b + 5 * j + i;
        out << "4 " << v << " " << v + 1 << " " << v + 6 << " " << v + 5 << "\n";
      }
  return path;
}

// The pieces counted are those the rigid motions move one by one: three squares side by side,
// one mesh of squares, one of cubes.
TEST(RigidMotions, ThePiecesCountedAreThoseTheMotionsMove) {
  const Mesh squares = read_poly2d(three_squares()).mesh;
  EXPECT_EQ(count_pieces(squares), 3);
  EXPECT_EQ(count_pieces(squares), RigidMotions(squares, make_dof_map(squares, {})).num_pieces());
  EXPECT_EQ(count_pieces(make_squares(4)), 1);
  const Mesh3D cubes = make_cubes(2);
  EXPECT_EQ(count_pieces(cubes), 1);
  EXPECT_EQ(BasicRigidMotions<3>(cubes, make_dof_map(cubes, {})).num_pieces(), 1);
}

TEST(SemiCoercive, APieceHeldByNothingIsRefusedNamingIt) {
  const std::string mesh = "file = \"" + three_squares().string() + "\"";
  const std::string common = R"(
schema_version = 1
[mesh]
)" + mesh + R"(
[material]
E = 65.0
nu = 0.29
[clamped]
side = ["left", "right"]
[loads]
[[loads.traction]]
side = "top"
value = [1.0, -8.0]
)";
  for (const bool contact : {true, false}) {
    SCOPED_TRACE(contact);
    try {
      (void)solve_scene_text(common + (contact ? "[contact]\nside = \"bottom\"\n" : ""));
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("translation along (1, 0) of the piece of 16 elements around (2.5, 0.5)"), std::string::npos)
          << what;
      if (!contact) EXPECT_NE(what.find("rotation about (2.5, 0.5)"), std::string::npos) << what;
    }
  }
}

TEST(SemiCoercive, ARollerMeetingTheContactIsAllowedAPrescribedNormalTakesTheNodeOut) {
  // the block's bottom corners carry the rollers (ux = 0): tangential to the bottom's normal
  const ContactSolution s = solve_scene_text(block_scene("generator = \"squares\"\nn = [8, 2]", 100.0, 2.0, 50.0));
  ASSERT_TRUE(s.converged());
  bool corner = false;
  for (const ContactNode& n : s.contact) corner = corner || (n.x.x() == 0.0 && n.x.y() == 0.0);
  EXPECT_TRUE(corner) << "the corner node under the roller is a contact node";
  // uy prescribed on the left side: at the corner (0, 0) it is the contact's normal component,
  // so the support holds that node and the contact keeps the others
  std::string text = block_scene("generator = \"squares\"\nn = [8, 2]", 100.0, 2.0, 50.0);
  text.replace(text.find("ux = 0.0"), 8, "uy = 0.0");
  const ContactSolution held = solve_scene_text(text);
  ASSERT_TRUE(held.converged()) << held.message;
  EXPECT_EQ(held.contact.size(), s.contact.size() - 1);
  for (const ContactNode& n : held.contact) EXPECT_FALSE(n.x.x() == 0.0 && n.x.y() == 0.0) << "the pinned corner left the contact";
  // the support's reaction takes the corner's share: load, reactions and contact balance
  EXPECT_LT(held.forces.sum().norm(), 1e-10 * held.forces.applied.norm());
}

// A Gmsh body (the lower half of a disk) resting on a rigid plane, a roller on the inner part of
// its flat top (ux = 0) and a pressure on it: the vertical translation and a rotation are held by
// the plane alone. It solves, names both motions, and its margin is 0 (in exact arithmetic it is:
// the zero law adds no curvature along them), not a sign of round-off.
TEST(SemiCoercive, AGmshBodyRestingOnAPlaneSolvesAndItsMarginIsZero) {
  const std::string text = R"(
schema_version = 1
[mesh]
file = ")" + (test::scenes_dir() / "meshes" / "half-disk.msh").string() + R"("
[material]
E = 65.0
nu = 0.29
[[dirichlet]]
segments = [[-0.9, 1.0, 0.9, 1.0]]
ux = 0.0
[loads]
[[loads.traction]]
group = "top"
pressure = 1.0
[contact]
group = "arc"
law = "zero"
constraint = "one-sided"
[contact.obstacle]
shape = "plane"
point = [0.0, 0.0]
normal = [0.0, 1.0]
)";
  const Scene scene = parse_scene_string(text, "half-disk.toml");
  const auto built = build_problem(scene);
  for (const std::string minimizer : {"ssn", "bundle-dca"}) {
    SCOPED_TRACE(minimizer);
    FactorizationOptions f;
    f.engine = "auto";
    MinimizerOptions o;
    o.tolerance = 1e-10;
    const auto m = make_minimizer(minimizer);
    const NonsmoothMinimizer* one[] = {m.get()};
    const ContactSolution s = solve_contact(built->problem, make_factorization(f), one, o, nullptr, true).front();
    ASSERT_TRUE(s.converged()) << s.message;
    ASSERT_EQ(s.held_by_contact.size(), 2u);
    EXPECT_NE(s.held_by_contact[0].find("rotation about"), std::string::npos) << s.held_by_contact[0];
    EXPECT_EQ(s.held_by_contact[1], "translation along (0, 1) of the body");
    EXPECT_EQ(s.uniqueness_margin, 0.0) << "round-off bound " << s.uniqueness_roundoff;
    EXPECT_TRUE(s.may_be_nonunique);
    // the plane carries the whole load: the pressure 1 on the top of width 2
    EXPECT_NEAR(s.contact_force().y(), 2.0, 1e-8);
  }
}

}  // namespace
}  // namespace hemivem
