// Supports as a scene poses them (docs/reference/scenes.md): single vertices held by `point` in
// [clamped] and [[dirichlet]], plane and solid, against the exact solution of uniaxial tension;
// supports that meet a frictional contact (a roller drops the node's friction coordinate, a
// pinned normal takes the node out of the contact); and the published plate on a rigid plane
// with Coulomb friction (scenes/plate-friction-benchmark.toml) against its reference values.
#include <gtest/gtest.h>

#include <hemivem/app/run.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>

#include <cmath>
#include <string>

#include "test_support.hpp"

namespace hemivem::app {
namespace {

using test::input_error_key;
using test::input_error_of;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A unit square (cube) pulled by the pressure -p on its right side x = 1, held by a roller
// (ux = 0) on its left side and by point supports that stop the other rigid motions: uniaxial
// stress, whose displacement is linear and so exact in the lowest-order virtual space.
const double E = 200.0, nu = 0.25, p = 3.0;

std::string tension_2d(const std::string& points) {
  return "schema_version = 1\n[mesh]\ngenerator = \"voronoi\"\nn = 6\n[material]\nE = 200\nnu = 0.25\n"
         "model = \"plane-stress\"\n[[dirichlet]]\nside = \"left\"\nux = 0\n" +
         points + "[[loads.traction]]\nside = \"right\"\npressure = -3\n";
}

TEST(PointSupports, APinnedVertexHoldsThePlaneInUniaxialTension) {
  const Scene scene = parse_scene_string(tension_2d("[[dirichlet]]\npoint = [0, 0]\nuy = 0\n"), "tension.toml");
  ASSERT_EQ(scene.dirichlet.size(), 2u);
  EXPECT_EQ(scene.dirichlet[1].boundary.points.size(), 1u);
  EXPECT_EQ(parse_scene_string(to_toml(scene), "again.toml"), scene);  // written back as read
  const SceneRun run = run_scene(scene);
  ASSERT_TRUE(run.converged());
  const auto& built = *run.plane()->built;
  ASSERT_EQ(built.problem.elasticity.dirichlet[1].vertices.size(), 1u);
  EXPECT_TRUE(built.problem.elasticity.dirichlet[1].facets.empty());
  const Eigen::VectorXd& u = run.plane()->solution.u;
  double worst = 0.0;
  for (int v = 0; v < built.mesh.num_vertices(); ++v) {
    const Vec2 x = built.mesh.vertex(v);
    worst = std::max({worst, std::abs(u(2 * v) - p / E * x.x()), std::abs(u(2 * v + 1) + nu * p / E * x.y())});
  }
  EXPECT_LT(worst, 1e-12 * p / E) << "plane stress: ux = p x / E, uy = -nu p y / E";
  // the pin's reaction is zero (nothing pulls along y) and the roller's balances the pull
  const auto& b = run.plane()->solution.forces;
  ASSERT_EQ(b.reactions.size(), 2u);
  EXPECT_NEAR(b.reactions[0].force.x(), -p, 1e-10 * p);
  EXPECT_LT(b.reactions[1].force.norm(), 1e-10 * p);
}

TEST(PointSupports, APointWithoutAVertexOrOfTheWrongShapeIsNamed) {
  const std::string off = tension_2d("[[dirichlet]]\npoint = [0, 0.013]\nuy = 0\n");
  const std::string message = input_error_of([&] { (void)run_scene(parse_scene_string(off, "off.toml")); });
  EXPECT_TRUE(has(message, "dirichlet[1].point: no vertex of the mesh at (0.0, 0.013)")) << message;
  EXPECT_TRUE(has(message, "the nearest, vertex")) << message;
  EXPECT_EQ(input_error_key([&] { (void)run_scene(parse_scene_string(off, "off.toml")); }), "off.toml:13");
  // three numbers in the plane; a point in a contact or a load is no support
  const std::string three = tension_2d("[clamped]\npoint = [0, 0, 0]\n");
  EXPECT_TRUE(has(input_error_of([&] { (void)parse_scene_string(three, "three.toml"); }), "expected [x, y] (2 numbers)"));
  const std::string load = tension_2d("") + "point = [1, 1]\n";
  EXPECT_TRUE(has(input_error_of([&] { (void)parse_scene_string(load, "load.toml"); }), "point"));
  // several points in one entry, and a [clamped] of points only
  const Scene several = parse_scene_string(tension_2d("[clamped]\npoint = [[0, 0], [0, 1]]\n"), "several.toml");
  EXPECT_EQ(several.clamped.points.size(), 2u);
  const SceneRun run = run_scene(several);
  ASSERT_TRUE(run.converged());
  EXPECT_EQ(run.plane()->built->problem.elasticity.dirichlet.front().name, "clamped");
  EXPECT_EQ(run.plane()->built->problem.elasticity.dirichlet.front().vertices.size(), 2u);
}

TEST(PointSupports, ABodyWithoutAnySupportIsRefusedAsTheScenesReferenceSays) {
  const std::string none = "schema_version = 1\n[mesh]\nn = 4\n[contact]\nside = \"bottom\"\n";
  const std::string message = input_error_of([&] { (void)run_scene(parse_scene_string(none, "none.toml")); });
  EXPECT_TRUE(has(message, "the body is not held: no boundary edge or vertex has a prescribed displacement")) << message;
}

TEST(PointSupports, PointsHoldASolidInUniaxialTension) {
  const std::string text =
      "schema_version = 1\n[mesh]\ngenerator = \"cubes\"\nn = 3\ndomain = [0, 1, 0, 1, 0, 1]\n[material]\nE = 200\n"
      "nu = 0.25\n[[dirichlet]]\nside = \"x0\"\nux = 0\n[[dirichlet]]\npoint = [0, 0, 0]\nuy = 0\nuz = 0\n"
      "[[dirichlet]]\npoint = [0, 1, 0]\nuz = 0\n[[loads.traction]]\nside = \"x1\"\npressure = -3\n";
  const SceneRun run = run_scene(parse_scene_string(text, "solid.toml"));
  ASSERT_TRUE(run.converged());
  const auto& built = *run.solid()->built;
  const Eigen::VectorXd& u = run.solid()->solution.u;
  double worst = 0.0;
  for (int v = 0; v < built.mesh.num_vertices(); ++v) {
    const Vec3 x = built.mesh.vertex(v);
    worst = std::max({worst, std::abs(u(3 * v) - p / E * x.x()), std::abs(u(3 * v + 1) + nu * p / E * x.y()),
                      std::abs(u(3 * v + 2) + nu * p / E * x.z())});
  }
  EXPECT_LT(worst, 1e-12 * p / E);
  const std::string off = text.substr(0, text.find("[[dirichlet]]\npoint = [0, 1, 0]")) +
                          "[[dirichlet]]\npoint = [0, 0.5, 0]\nuz = 0\n[[loads.traction]]\nside = \"x1\"\npressure = -3\n";
  EXPECT_TRUE(has(input_error_of([&] { (void)run_scene(parse_scene_string(off, "off.toml")); }),
                  "dirichlet[2].point: no vertex of the mesh at (0.0, 0.5, 0.0)"));
}

// The published plate (scenes/plate-friction-benchmark.toml): the tangential displacement of
// the contact face at t = 1 against the reference values, which are a mean of several codes
// given within 5 %.
TEST(SupportsAtTheContact, ThePublishedPlateWithCoulombFrictionIsPosedAsWrittenAndAgrees) {
  const Scene scene = parse_scene(test::scenes_dir() / "plate-friction-benchmark.toml");
  const SceneRun run = run_scene(scene);
  ASSERT_TRUE(run.converged());
  ASSERT_NE(run.path(), nullptr);
  const auto& solution = run.plane()->solution;
  const double reference[][2] = {{0.0, 2.86e-5}, {0.00125, 2.72e-5}, {0.005, 2.28e-5}, {0.0075, 1.98e-5}, {0.01125, 1.5e-5}};
  for (const auto& [x, ux] : reference) {
    const ContactNode* at = nullptr;
    for (const ContactNode& n : solution.contact)
      if (std::abs(n.x.x() - x) < 1e-12) at = &n;
    ASSERT_NE(at, nullptr) << "no contact node at x = " << x;
    EXPECT_NEAR(at->u_tau, ux, 0.05 * ux) << "x = " << x;  // the tangent of the bottom is +x
  }
  // the corner under the roller and the pin is held by both: not a contact node
  for (const ContactNode& n : solution.contact) EXPECT_LT(n.x.x(), 0.04);
  EXPECT_LT(solution.forces.sum().norm(), 1e-10 * solution.forces.applied.norm());
}

TEST(SupportsAtTheContact, ARollerMeetingAFrictionalContactDropsTheFrictionCoordinate) {
  // without the pin, the corner node keeps its normal unknown under the roller (ux = 0): no
  // friction coordinate; the plane holds the vertical translation
  Scene scene = parse_scene(test::scenes_dir() / "plate-friction-benchmark.toml");
  scene.dirichlet.pop_back();
  const SceneRun run = run_scene(scene);
  ASSERT_TRUE(run.converged());
  const auto& solution = run.plane()->solution;
  const ContactNode* corner = nullptr;
  int with_friction = 0;
  for (const ContactNode& n : solution.contact) {
    if (n.x.x() == 0.04) corner = &n;
    with_friction += n.friction_state != FrictionState::none;
  }
  ASSERT_NE(corner, nullptr) << "the corner under the roller is a contact node";
  EXPECT_EQ(corner->friction_state, FrictionState::none);
  EXPECT_EQ(with_friction, static_cast<int>(solution.contact.size()) - 1);
  EXPECT_EQ(solution.u(2 * corner->vertex), 0.0);
  EXPECT_LT(solution.forces.sum().norm(), 1e-10 * solution.forces.applied.norm());
}

}  // namespace
}  // namespace hemivem::app
