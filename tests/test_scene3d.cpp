// Three-dimensional scenes (docs/reference/scenes.md, "Three-dimensional scenes"): what makes a
// scene 3D, its keys as read, written back and refused, the problem build_problem<3> poses, and
// solves of small 3D scenes through hemivem::app with their stresses, forces and outputs.
#include <hemivem/app/solve3d.hpp>
#include <hemivem/app/vtu.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/scene/mesh_files3d.hpp>
#include <hemivem/scene/scene.hpp>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace hemivem;

namespace {

const std::string kHead = "schema_version = 1\n";
/// A small box of cubes.
const std::string kBox = kHead + "[mesh]\ngenerator = \"cubes\"\nn = 3\ndomain = [0, 1, 0, 1, 0, 1]\n";

std::string scene_error(const std::string& text) {
  return test::input_error_of([&] { (void)parse_scene_string(text, "solid.toml"); });
}

/// `text` holds every fragment.
::testing::AssertionResult holds(const std::string& text, std::initializer_list<std::string> fragments) {
  for (const auto& f : fragments)
    if (text.find(f) == std::string::npos) return ::testing::AssertionFailure() << "'" << f << "' not in: " << text;
  return ::testing::AssertionSuccess();
}

}  // namespace

TEST(Scene3D, WhatMakesASceneThreeDimensional) {
  EXPECT_EQ(parse_scene_string(kHead, "s.toml").dimension(), 2);
  EXPECT_EQ(parse_scene_string(kHead + "[mesh]\nn = 4\ndomain = [0, 1, 0, 1]\n", "s.toml").dimension(), 2);
  const Scene box = parse_scene_string(kHead + "[mesh]\ndomain = [0, 2, 0, 1, -1, 0]\n", "s.toml");
  EXPECT_EQ(box.dimension(), 3);
  EXPECT_EQ(box.mesh.generator, "cubes");  // the default generator of a box
  EXPECT_EQ(box.mesh.box, (std::array<double, 6>{0, 2, 0, 1, -1, 0}));
  const Scene counts = parse_scene_string(kHead + "[mesh]\nn = [4, 2, 3]\n", "s.toml");
  EXPECT_EQ(counts.dimension(), 3);
  EXPECT_EQ(counts.mesh.cells3(), GridSize3(4, 2, 3));
  EXPECT_EQ(counts.mesh.box, (std::array<double, 6>{0, 1, 0, 1, 0, 1}));
  const Scene tets = parse_scene_string(kHead + "[mesh]\ngenerator = \"tetrahedra\"\nn = 2\n", "s.toml");
  EXPECT_EQ(tets.dimension(), 3);
  EXPECT_EQ(tets.mesh.description(), "tetrahedra n=2");
  EXPECT_EQ(counts.mesh.description(), "cubes n=[4, 2, 3]");
}

TEST(Scene3D, AGmshFileOfVolumeElementsIsThreeDimensional) {
  const fs::path dir = test::scratch("gmsh-dimension");
  fs::create_directories(dir);
  const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Elements\n";
  {
    std::ofstream(dir / "solid.msh") << head << "2 2 1 2\n2 1 2 1\n1 1 2 3\n3 1 4 1\n2 1 2 3 4\n$EndElements\n";
    std::ofstream(dir / "plane.msh") << head << "1 2 1 2\n2 1 2 2\n1 1 2 3\n2 2 3 4\n$EndElements\n";
  }
  EXPECT_EQ(gmsh_file_dimension(dir / "solid.msh"), 3);
  EXPECT_EQ(gmsh_file_dimension(dir / "plane.msh"), 2);
  EXPECT_EQ(gmsh_file_dimension(dir / "absent.msh"), 2);  // the 2D reader says what is wrong
  EXPECT_EQ(gmsh_file_dimension(test::scenes_dir() / "meshes" / "half-disk.msh"), 2);
  const Scene solid = parse_scene_string(kHead + "[mesh]\nfile = \"solid.msh\"\n", (dir / "s.toml").string());
  EXPECT_EQ(solid.dimension(), 3);
  const Scene plane = parse_scene_string(kHead + "[mesh]\nfile = \"plane.msh\"\n", (dir / "s.toml").string());
  EXPECT_EQ(plane.dimension(), 2);
  // the solid's reader reads it: this one has no nodes
  EXPECT_TRUE(holds(test::input_error_of([&] { (void)build_problem<3>(solid); }), {"solid.msh"}));
  fs::remove_all(dir);
}

TEST(Scene3D, AGmshFileOfASolidSolvesAsItsGenerator) {
  const fs::path dir = test::scratch("gmsh-solid");
  fs::create_directories(dir);
  write_gmsh3d(make_cubes(GridSize3(3, 2, 2), Box{0, 1, 0, 0.5, 0, 0.5}), dir / "box.msh");
  const std::string rest = "[clamped]\nside = \"x0\"\n[loads]\n[[loads.traction]]\nside = \"x1\"\nvalue = [0, 0, -1]\n";
  const Scene file = parse_scene_string(kHead + "[mesh]\nfile = \"box.msh\"\n" + rest, (dir / "s.toml").string());
  const Scene generated = parse_scene_string(
      kHead + "[mesh]\nn = [3, 2, 2]\ndomain = [0, 1, 0, 0.5, 0, 0.5]\n" + rest, (dir / "s.toml").string());
  ASSERT_EQ(file.dimension(), 3);
  const auto a = app::solve_scene_3d(file);
  const auto b = app::solve_scene_3d(generated);
  ASSERT_TRUE(a.solution.converged() && b.solution.converged());
  EXPECT_NEAR(a.solution.forces.reactions.at(0).force.z(), 0.25, 1e-12);  // the traction on x1 of area 0.25
  EXPECT_NEAR(b.solution.forces.reactions.at(0).force.z(), 0.25, 1e-12);
  EXPECT_NEAR(a.solution.energy, b.solution.energy, 1e-12 * std::abs(b.solution.energy));
  fs::remove_all(dir);
}

// A Gmsh file of hexahedra (tests/data/gmsh3d/cube_hexahedra.msh): its physical surfaces "base" and
// "top" are the groups the selectors name, its volume group 2 the region [[material.region]] sets.
TEST(Scene3D, AGmshFileGivesItsGroupsAndRegions) {
  const fs::path file = test::data_dir() / "gmsh3d" / "cube_hexahedra.msh";
  const std::string head = kHead + "[mesh]\nfile = \"" + file.string() + "\"\n[material]\nE = 10.0\nnu = 0.3\n";
  const std::string rest = "[clamped]\ngroup = \"base\"\n[loads]\n[[loads.traction]]\ngroup = \"top\"\nvalue = [0, 0, -1]\n";
  const Scene s = parse_scene_string(head + "[[material.region]]\nid = 2\nE = 20.0\nnu = 0.3\n" + rest, "g.toml");
  ASSERT_EQ(s.dimension(), 3);
  const auto solved = app::solve_scene_3d(s);
  ASSERT_TRUE(solved.solution.converged()) << solved.solution.message;
  EXPECT_EQ(solved.built->mesh.num_cells(), 27);
  EXPECT_EQ(solved.built->problem.elasticity.dirichlet.at(0).facets.size(), 9u);
  EXPECT_EQ(solved.built->problem.elasticity.materials.lame(2).mu, 20.0 / 2.6);
  const ForceBalance3D& b = solved.solution.forces;
  EXPECT_NEAR(b.applied.z(), -1.0, 1e-12);
  EXPECT_NEAR(b.reactions.at(0).force.z(), 1.0, 1e-12);
  EXPECT_LT(b.residual(), 1e-12);
  // a region the file does not have, a group it does not have: errors naming the key
  EXPECT_TRUE(holds(test::input_error_of([&] {
                      (void)build_problem<3>(parse_scene_string(head + "[[material.region]]\nid = 7\nE = 2.0\nnu = 0.3\n" + rest,
                                                                "g.toml"));
                    }),
                    {"g.toml:8", "material.region[0].id: region 7 matches no cell", "region ids are 2"}));
  EXPECT_TRUE(holds(test::input_error_of([&] {
                      (void)build_problem<3>(parse_scene_string(head + "[contact]\ngroup = \"side\"\n" + rest, "g.toml"));
                    }),
                    {"g.toml:8", "contact.group", "side"}));
}

TEST(Scene3D, ShippedScenesPoseTheirProblemsAndRoundTrip) {
  const Scene ex = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  ASSERT_EQ(ex.dimension(), 3);
  EXPECT_EQ(ex.mesh.cells3(), GridSize3(8, 4, 8));
  EXPECT_EQ(ex.clamped.sides, (std::vector<std::string>{"x0", "x1"}));
  ASSERT_EQ(ex.tractions.size(), 1u);
  EXPECT_EQ(ex.tractions[0].value[2], (SceneScalar{-8.0, {}}));
  ASSERT_TRUE(ex.contact.has_value());
  EXPECT_EQ(ex.contact->law.name, "paper");
  const Scene hertz = parse_scene(test::scenes_dir() / "hertz-sphere-3d.toml");
  ASSERT_EQ(hertz.dimension(), 3);
  ASSERT_TRUE(hertz.contact && hertz.contact->obstacle);
  EXPECT_EQ(hertz.contact->obstacle->shape, "sphere");
  EXPECT_EQ(hertz.contact->obstacle->center, (std::array<double, 3>{0.0, 0.0, 0.99}));
  EXPECT_EQ(hertz.contact->constraint, ConstraintKind::one_sided);
  ASSERT_EQ(hertz.dirichlet.size(), 2u);
  EXPECT_TRUE(hertz.dirichlet[0].ux && !hertz.dirichlet[0].uy && !hertz.dirichlet[0].uz);  // a roller: ux only
  for (const Scene* s : {&ex, &hertz}) {
    const std::string text = to_toml(*s);
    EXPECT_EQ(text.find("model ="), std::string::npos) << "a solid has no plane model";
    EXPECT_EQ(parse_scene_string(text, "again.toml"), *s) << text;
  }
  // the faces each part selects on 8 x 4 x 8 cubes
  const auto built = build_problem<3>(ex);
  const ContactProblem3D& p = built->problem;
  EXPECT_EQ(built->mesh.num_cells(), 8 * 4 * 8);
  ASSERT_EQ(p.elasticity.dirichlet.size(), 1u);
  EXPECT_EQ(p.elasticity.dirichlet[0].facets.size(), 2u * 4 * 8);
  EXPECT_EQ(p.elasticity.tractions.at(0).facets.size(), 8u * 4);
  ASSERT_EQ(p.parts.size(), 1u);
  EXPECT_EQ(p.parts[0].facets.size(), 8u * 4);
  for (int f : p.parts[0].facets) EXPECT_NEAR(built->mesh.face_centroid(f).z(), 0.0, 1e-15);
  ASSERT_TRUE(p.parts[0].gap);
  EXPECT_EQ(p.parts[0].gap(Vec3(0.3, 0.2, 0.0)), 0.02);
  EXPECT_EQ(p.elasticity.tractions[0].traction(Vec3(0.5, 0.25, 1.0)), Vec3(0.0, 0.0, -8.0));
  EXPECT_EQ(p.elasticity.materials.lame(0).mu, 65.0 / (2.0 * 1.29));
  const auto h = build_problem<3>(hertz);
  ASSERT_TRUE(h->problem.parts.at(0).obstacle.has_value());
  EXPECT_EQ(h->problem.parts.at(0).obstacle->shape, Obstacle3D::Shape::sphere);
  EXPECT_EQ(h->problem.elasticity.dirichlet[1].fix, (std::array<bool, 3>{true, false, false}));
  EXPECT_EQ(h->problem.elasticity.dirichlet[2].fix, (std::array<bool, 3>{false, true, false}));
}

TEST(Scene3D, ExpressionsTakeZAndOverridesApply) {
  Scene s = parse_scene_string(kBox + "[clamped]\nside = \"bottom\"\n[loads]\nbody_force = [0, \"x\", \"-2*z\"]\n"
                                      "[[loads.traction]]\nside = \"x1\"\npressure = \"1 + y*z\"\n"
                                      "[[dirichlet]]\nside = \"top\"\nuz = \"-0.01*x\"\n"
                                      "[contact]\nside = \"y0\"\ngap = \"0.01 + 0.5*z\"\n",
                               "z.toml");
  const auto built = build_problem<3>(s);
  const ContactProblem3D& p = built->problem;
  EXPECT_EQ(p.elasticity.body_force(Vec3(0.25, 0.5, 0.75)), Vec3(0.0, 0.25, -1.5));
  EXPECT_EQ(p.elasticity.tractions.at(0).pressure(Vec3(1.0, 0.5, 0.5)), 1.25);
  EXPECT_EQ(p.elasticity.dirichlet.at(1).value(Vec3(0.5, 0.0, 1.0)).z(), -0.005);
  EXPECT_EQ(p.parts.at(0).gap(Vec3(0.0, 0.0, 0.5)), 0.26);
  // the same keys by --set, read back as a whole
  apply_overrides(s, {"mesh.n=[2, 3, 4]", "contact.gap=\"0.02*z\"", "loads.body_force=[1, 0, 0]"});
  EXPECT_EQ(s.dimension(), 3);
  EXPECT_EQ(s.mesh.cells3(), GridSize3(2, 3, 4));
  EXPECT_EQ(build_problem<3>(s)->problem.parts.at(0).gap(Vec3(0.0, 0.0, 0.5)), 0.01);
  EXPECT_EQ(s.body_force[0], (SceneScalar{1.0, {}}));
  // a two-dimensional scene knows no z
  EXPECT_TRUE(holds(scene_error(kHead + "[loads]\nbody_force = [0, \"z\"]\n"),
                    {"solid.toml:3", "loads.body_force: element 1: expression 'z'"}));
}

TEST(Scene3D, BadInputNamesTheKeyAndWhatWasExpected) {
  EXPECT_TRUE(holds(scene_error(kHead + "[mesh]\ndomain = [0, 1, 0, 1, 0]\n"),
                    {"solid.toml:3", "mesh.domain", "[x0, x1, y0, y1, z0, z1]", "got 5 numbers"}));
  EXPECT_TRUE(holds(scene_error(kHead + "[mesh]\ndomain = [0, 1, 0, 1, 1, 0]\n"),
                    {"solid.toml:3", "mesh.domain", "z0 < z1"}));
  EXPECT_TRUE(holds(scene_error(kHead + "[mesh]\ngenerator = \"squares\"\ndomain = [0, 1, 0, 1, 0, 1]\n"),
                    {"solid.toml:3", "mesh.generator", "cubes, tetrahedra"}));
  EXPECT_TRUE(holds(scene_error(kHead + "[mesh]\ngenerator = \"cubes\"\ndomain = [0, 1, 0, 1]\n"),
                    {"solid.toml:3", "mesh.generator", "[x0, x1, y0, y1, z0, z1]"}));
  EXPECT_TRUE(holds(scene_error(kHead + "[mesh]\ndomain = [0, 1, 0, 1, 0, 1]\nn = [2, 3]\n"),
                    {"solid.toml:4", "mesh.n", "[nx, ny, nz]"}));
  EXPECT_TRUE(holds(scene_error(kBox + "[clamped]\nside = \"left\"\n"),
                    {"solid.toml:7", "clamped.side", "unknown side 'left'", "x0, x1, y0, y1, z0, z1, bottom, top"}));
  EXPECT_TRUE(holds(scene_error(kBox + "[clamped]\nsegments = [[0, 0, 1, 0]]\n"),
                    {"solid.toml:7", "clamped.segments", "not available for three-dimensional scenes"}));
  const std::string contact = kBox + "[contact]\nside = \"top\"\n";
  EXPECT_TRUE(holds(scene_error(contact + "[contact.obstacle]\nshape = \"circle\"\ncenter = [0, 0]\nradius = 1\n"),
                    {"solid.toml:9", "contact.obstacle.shape", "'circle'", "plane, sphere, cylinder"}));
  EXPECT_TRUE(holds(scene_error(contact + "[contact.obstacle]\nshape = \"sphere\"\ncenter = [0, 0]\nradius = 1\n"),
                    {"solid.toml:10", "contact.obstacle.center", "[x, y, z]", "got 2"}));
  EXPECT_TRUE(holds(scene_error(contact + "[contact.obstacle]\nshape = \"cylinder\"\ncenter = [0, 0, 2]\nradius = 1\n"),
                    {"solid.toml:8", "contact.obstacle: a cylinder obstacle needs 'axis'"}));
  EXPECT_TRUE(holds(scene_error(contact + "[contact.obstacle]\nshape = \"cylinder\"\ncenter = [0, 0, 2]\n"
                                          "axis = [0, 0, 0]\nradius = 1\n"),
                    {"solid.toml:11", "contact.obstacle.axis", "the cylinder's axis is zero"}));
  EXPECT_TRUE(holds(scene_error(kHead + "[contact]\nside = \"top\"\n[contact.obstacle]\nshape = \"sphere\"\n"
                                        "center = [0, 0]\nradius = 1\n"),
                    {"solid.toml:5", "contact.obstacle.shape", "'sphere' is an obstacle of three-dimensional scenes"}));
  // friction is a solid's as a plane's (tests/test_friction3d.cpp solves it); its laws are checked alike
  EXPECT_EQ(parse_scene_string(contact + "[contact.friction]\nlaw = \"tresca\"\nbound = 0.3\n", "solid.toml")
                .contact->friction->name,
            "tresca");
  EXPECT_TRUE(holds(scene_error(contact + "[contact.friction]\nlaw = \"tresca\"\nbound = -1\n"),
                    {"solid.toml:9", "contact.friction", "friction bound g -1 must be finite and >= 0"}));
  // a loading path is a solid's as a plane's (tests/test_path_solid.cpp solves them)
  EXPECT_EQ(parse_scene_string(kBox + "[path]\nsteps = 4\n", "solid.toml").path->factors().size(), 4u);
  // adaptive refinement is a solid's as a plane's (tests/test_adapt3d.cpp solves them)
  EXPECT_DOUBLE_EQ(parse_scene_string(kBox + "[adapt]\ntarget = 0.1\n", "solid.toml").adapt->target, 0.1);
  EXPECT_TRUE(holds(scene_error(kBox + "[material]\nmodel = \"plane-strain\"\n"),
                    {"solid.toml:7", "material.model", "two-dimensional scenes", "remove the key"}));
  EXPECT_TRUE(holds(scene_error(kBox + "[loads]\nbody_force = [0, -1]\n"),
                    {"solid.toml:7", "loads.body_force", "[fx, fy, fz]", "got 2"}));
  EXPECT_TRUE(holds(scene_error(kBox + "[[loads.traction]]\nside = \"top\"\nvalue = [0, -1]\n"),
                    {"solid.toml:8", "loads.traction[0].value", "[tx, ty, tz]"}));
  EXPECT_TRUE(holds(scene_error(kBox + "[[dirichlet]]\nside = \"x0\"\nvalue = [0, 0, 0]\nuz = 1\n"),
                    {"solid.toml:9", "dirichlet[0].uz", "not used with value = [ux, uy, uz]"}));
  EXPECT_TRUE(holds(scene_error(kHead + "[[dirichlet]]\nside = \"left\"\nuz = 0\n"),
                    {"solid.toml:4", "unknown key 'uz' in [dirichlet[0]]"}));
  // errors found when the problem is built name the key too
  const std::string group = test::input_error_of(
      [&] { (void)build_problem<3>(parse_scene_string(kBox + "[clamped]\ngroup = \"base\"\n", "solid.toml")); });
  EXPECT_TRUE(holds(group, {"solid.toml:7", "clamped.group", "base"}));
  const std::string clamped = test::input_error_of([&] {
    (void)build_problem<3>(parse_scene_string(kBox + "[clamped]\nside = \"top\"\n[contact]\nside = \"top\"\n", "solid.toml"));
  });
  EXPECT_TRUE(holds(clamped, {"solid.toml:8", "contact: every node of the contact part is also clamped"}));
  const std::string unheld = test::input_error_of([&] {
    (void)app::solve_scene_3d(parse_scene_string(kBox + "[[dirichlet]]\nside = \"bottom\"\nuz = 0\n", "solid.toml"));
  });
  EXPECT_TRUE(holds(unheld, {"solid.toml", "rigid motions", "[clamped] and [[dirichlet]]"}));
  // a solve of the other dimension says which one takes the scene
  EXPECT_TRUE(holds(test::input_error_of([&] { (void)build_problem(parse_scene_string(kBox, "solid.toml")); }),
                    {"mesh", "three-dimensional scene"}));
}

// A prism under a uniform pressure on its top, held by three symmetry planes (a roller on each:
// x = 0, y = 0, z = 0): the exact solution is linear, sigma_zz = -p and every other stress 0,
// u = (nu p x / E, nu p y / E, -p z / E). The virtual element reproduces it on cubes and on
// tetrahedra, the balance of forces holds, and the error estimate vanishes.
TEST(Scene3D, UniaxialPressureIsReproducedWithItsStresses) {
  for (const std::string generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(generator);
    const Scene s = parse_scene_string(kHead + "[mesh]\ngenerator = \"" + generator +
                                           "\"\nn = [2, 3, 2]\ndomain = [0, 1, 0, 2, 0, 1]\n"
                                           "[material]\nE = 10.0\nnu = 0.25\n"
                                           "[[dirichlet]]\nside = \"x0\"\nux = 0\n[[dirichlet]]\nside = \"y0\"\nuy = 0\n"
                                           "[[dirichlet]]\nside = \"bottom\"\nuz = 0\n"
                                           "[loads]\n[[loads.traction]]\nside = \"top\"\npressure = 3.0\n",
                                       "prism.toml");
    const auto solved = app::solve_scene_3d(s);
    ASSERT_TRUE(solved.solution.converged()) << solved.solution.message;
    EXPECT_EQ(solved.solution.stages, (std::vector<std::string>{"assembly", "linear_solve", "estimate"}));
    // the discrete solution is exact: so says the error estimate
    ASSERT_TRUE(solved.estimate);
    EXPECT_LT(solved.estimate->relative, 1e-10);
    const Mesh3D& mesh = solved.built->mesh;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const Vec3& x = mesh.vertex(v);
      const Vec3 exact(0.25 * 3.0 * x.x() / 10.0, 0.25 * 3.0 * x.y() / 10.0, -3.0 * x.z() / 10.0);
      EXPECT_LT((solved.solution.u.segment<3>(3 * v) - exact).norm(), 1e-12) << v;
    }
    for (const auto& c : app::cell_stresses(mesh, solved.built->problem.elasticity.materials, solved.solution.u)) {
      EXPECT_NEAR(c.zz, -3.0, 1e-11);
      for (double other : {c.xx, c.yy, c.yz, c.xz, c.xy}) EXPECT_NEAR(other, 0.0, 1e-11);
      EXPECT_NEAR(c.von_mises(), 3.0, 1e-11);
    }
    const ForceBalance3D& b = solved.solution.forces;
    EXPECT_NEAR(b.applied.z(), -3.0 * 2.0, 1e-12);  // the pressure on the top of area 2
    ASSERT_EQ(b.reactions.size(), 3u);
    EXPECT_NEAR(b.reactions[2].force.z(), 6.0, 1e-11);  // the bottom holds the load
    EXPECT_LT(b.residual(), 1e-12);
  }
}

// Example 4.1 in 3D on a coarse box: every bottom vertex off the clamped sides is a contact node,
// the solve converges with its certificate, forces balance, and the contact nodes' forces make
// the contact resultant.
TEST(Scene3D, Example41SolvesAndBalances) {
  Scene s = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  apply_override(s, "mesh.n=[4, 2, 4]");
  const auto solved = app::solve_scene_3d(s);
  const ContactSolution3D& sol = solved.solution;
  ASSERT_TRUE(sol.converged()) << sol.message;
  EXPECT_LE(sol.certificate.dual, 1e-10);
  EXPECT_EQ(sol.contact.size(), 5u * 3 - 2 * 3);  // the bottom's vertices but those on x = 0 and x = 1
  double weight = 0.0;
  Vec3 resultant = Vec3::Zero();
  for (const auto& n : sol.contact) {
    EXPECT_EQ(n.normal, Vec3(0.0, 0.0, -1.0));
    EXPECT_EQ(n.gap, 0.02);
    EXPECT_LE(std::abs(n.u_nu), 0.02 + 1e-12);  // the box constraint
    weight += n.weight;
    resultant -= n.force() * n.normal;
  }
  EXPECT_NEAR(weight, 0.5 * (1.0 - 2.0 * 0.25 / 2.0), 1e-14);  // the bottom's area less the clamped nodes' shares
  EXPECT_LT((resultant - sol.contact_force()).norm(), 1e-14);
  EXPECT_LT(sol.forces.residual(), 1e-10);
  EXPECT_NEAR(sol.forces.applied.z(), -8.0 * 0.5, 1e-12);
  EXPECT_GT(sol.contact_force().z(), 0.0);  // the foundation pushes up
}

// The Hertz scene on a coarse mesh: the sphere presses the top down; the symmetry planes hold
// only their normal component; the nodes in compression lie under the sphere.
TEST(Scene3D, HertzSphereQuarterSolves) {
  Scene s = parse_scene(test::scenes_dir() / "hertz-sphere-3d.toml");
  apply_override(s, "mesh.n=6");
  const auto solved = app::solve_scene_3d(s);
  const ContactSolution3D& sol = solved.solution;
  ASSERT_TRUE(sol.converged()) << sol.message;
  EXPECT_LT(sol.forces.residual(), 1e-10);
  EXPECT_LT(sol.contact_force().z(), 0.0);
  const Mesh3D& mesh = solved.built->mesh;
  bool slides = false;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& x = mesh.vertex(v);
    if (x.x() == 0.0) EXPECT_EQ(sol.u(3 * v), 0.0);
    if (x.y() == 0.0) EXPECT_EQ(sol.u(3 * v + 1), 0.0);
    if (x.x() == 0.0 && x.z() > -0.5 && std::abs(sol.u(3 * v + 1)) > 0.0) slides = true;
  }
  EXPECT_TRUE(slides) << "a roller leaves the tangential components free";
  int pressed = 0;
  for (const auto& n : sol.contact) {
    if (n.force() <= 0.0) continue;
    ++pressed;
    EXPECT_LT(std::hypot(n.x.x(), n.x.y()), 0.2) << "under the sphere";
    EXPECT_GE(n.gap, -0.01 - 1e-12);
  }
  EXPECT_GE(pressed, 1);
}

// The outputs of a 3D solve, written through hemivem::app: the files of wanted_files, and an
// earlier plane run's files of other names removed by the transaction.
TEST(Scene3D, OutputsOfASolve) {
  Scene s = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  apply_override(s, "mesh.n=[2, 2, 2]");
  const auto solved = app::solve_scene_3d(s);
  ASSERT_TRUE(solved.solution.converged());
  EXPECT_EQ(app::wanted_files(s, true),
            (std::vector<std::string>{"result.json", "contact.csv", "displacement.csv", "stress.csv", "history.csv",
                                      "solution.vtu", "contact-surface.vtu", "scene.toml", "deformed.png",
                                      "pressure.png"}));
  EXPECT_EQ(app::wanted_files(s, false), (std::vector<std::string>{"result.json", "displacement.csv", "stress.csv",
                                                                    "solution.vtu", "scene.toml", "deformed.png"}));
  const fs::path dir = test::scratch("outputs3d");
  fs::create_directories(dir);
  std::ofstream(dir / "u_nu.png") << "an earlier plane run's picture";
  std::ofstream(dir / "notes.txt") << "not ours";
  const std::vector<std::string> files{"result.json", "displacement.csv", "solution.vtu", "scene.toml"};
  const app::OutputReport report = app::write_results(dir, s, solved, &files);
  EXPECT_EQ(report.written.size(), 4u);
  EXPECT_EQ(report.removed, (std::vector<std::string>{"u_nu.png"}));
  EXPECT_FALSE(fs::exists(dir / "u_nu.png"));
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  const auto j = nlohmann::json::parse(test::slurp(dir / "result.json"));
  EXPECT_EQ(j.at("dimension"), 3);
  EXPECT_EQ(j.at("files"), nlohmann::json(files));
  EXPECT_EQ(j.at("mesh").at("elements"), 8);
  EXPECT_EQ(j.at("contact").size(), solved.solution.contact.size());
  EXPECT_EQ(parse_scene_string(test::slurp(dir / "scene.toml"), "again.toml"), s);
  // an unknown name or a solution of another mesh: refused before anything is written
  const std::vector<std::string> unknown{"result.json", "u_nu.png"};
  EXPECT_TRUE(holds(test::input_error_of([&] { (void)app::write_results(dir, s, solved, &unknown); }),
                    {"unknown output 'u_nu.png'"}));
  EXPECT_TRUE(fs::exists(dir / "solution.vtu"));
  fs::remove_all(dir);
}
