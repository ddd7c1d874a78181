// Scenes of bodies whose surfaces do not coincide (docs/two-bodies.md): a contact part paired by
// projection (pairing = "projection") and the polar meshes of rings, disks and sectors
// (generator = "polar"), read, written back and refused by key; the shipped scene
// scenes/two-cylinders.toml and scenes/shrink-fit.toml solved as the command solves them, against
// Hertz's formulas and Lame's solution.
#include <hemivem/app/run.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "lame_rings.hpp"
#include "test_support.hpp"

using namespace hemivem;

namespace {

/// The shipped scene with `from` replaced by `to`, parsed: the InputError's message.
std::string refusal(const std::string& from, const std::string& to) {
  return test::scene_refusal("two-cylinders.toml", from, to);
}

Scene cylinders() { return parse_scene(test::scenes_dir() / "two-cylinders.toml"); }

}  // namespace

TEST(SceneCurvedBodies, TheShippedSceneReadsAndWritesBack) {
  const Scene s = cylinders();
  ASSERT_EQ(s.bodies.size(), 2u);
  const SceneMesh& m = s.bodies[0].mesh;
  EXPECT_EQ(m.generator, "polar");
  EXPECT_EQ(m.center, (std::array<double, 2>{0.0, 1.0}));
  EXPECT_EQ(m.radii, (std::array<double, 2>{0.0, 1.0}));
  EXPECT_EQ(m.angles, (std::array<double, 2>{180.0, 360.0}));
  ASSERT_TRUE(m.focus);
  EXPECT_EQ(*m.focus, 270.0);
  EXPECT_EQ(m.grading, 1.04);
  EXPECT_EQ(m.cells(), GridSize(96, 192));
  ASSERT_TRUE(s.contact);
  EXPECT_EQ(s.contact->pairing, BodyPairing::projection);
  EXPECT_EQ(scene_mesh_description(s), "upper: polar n=[96, 192]; lower: polar n=[96, 212]");
  EXPECT_TRUE(parse_scene_string(to_toml(s), "again.toml") == s);
  // n = [k, k] is written as a pair and reads back
  Scene square = s;
  apply_override(square, "body[0].mesh.n=[40, 40]");
  EXPECT_TRUE(parse_scene_string(to_toml(square), "again.toml") == square);
}

TEST(SceneCurvedBodies, WhatItRefusesIsNamed) {
  EXPECT_NE(refusal("pairing = \"projection\"", "pairing = \"nearest\"").find("unknown pairing 'nearest'"),
            std::string::npos);
  EXPECT_NE(refusal("focus = 270.0", "focus = 100.0").find("focus"), std::string::npos);
  EXPECT_NE(refusal("radii = [0.0, 1.0]", "radii = [1.0, 0.5]").find("radii"), std::string::npos);
  EXPECT_NE(refusal("angles = [180.0, 360.0]", "angles = [180.0, 600.0]").find("angles"), std::string::npos);
  EXPECT_NE(refusal("grading = 1.04\nn = [96, 192]\n\n[body.material]\nE = 1.0",
                    "grading = 0.5\nn = [96, 192]\n\n[body.material]\nE = 1.0")
                .find("grading"),
            std::string::npos);
  EXPECT_NE(refusal("n = [96, 192]", "n = 48").find("needs n = [cells along the radius, cells around]"),
            std::string::npos);
  EXPECT_NE(refusal("generator = \"polar\"", "generator = \"squares\"").find("used only with generator = \"polar\""),
            std::string::npos);
  EXPECT_NE(refusal("grading = 1.04", "grading = 1.04\ndomain = [0.0, 1.0, 0.0, 1.0]").find("not used with generator"),
            std::string::npos);
  EXPECT_NE(refusal("against = \"lower.outer\"", "gap = 0.0").find("used only with against"), std::string::npos);
}

TEST(SceneCurvedBodies, TheShippedSceneIsHertzsAsTheCommandSolvesIt) {
  const app::SceneRun run = app::run_scene(cylinders());
  ASSERT_TRUE(run.converged());
  const auto* solve = run.plane();
  ASSERT_NE(solve, nullptr);
  double force = 0.0;
  for (const ContactNode& n : solve->solution.contact) force += n.force_on_body().y();
  const double radius = 1.0 * 1.5 / 2.5, modulus = 1.0 / ((1.0 - 0.09) / 1.0 + (1.0 - 0.04) / 2.0);
  const double a = std::sqrt(4.0 * force * radius / (std::numbers::pi * modulus)),
               p0 = 2.0 * force / (std::numbers::pi * a);
  // the upper body's supports carry the force that presses them together
  EXPECT_NEAR(-solve->solution.forces.reactions.front().force.y(), force, 1e-9 * force);
  // p^2 = p0^2 (1 - x^2 / a^2) fitted to the nodes well inside the contact
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  double peak = 0.0, last = 0.0;
  for (const ContactNode& n : solve->solution.contact) {
    peak = std::max(peak, n.pressure());
    if (n.pressure() > 0.0) last = std::max(last, std::abs(n.x.x()));
    if (std::abs(n.x.x()) > 0.8 * a) continue;
    const Eigen::Vector2d row(1.0, n.x.x() * n.x.x());
    m += row * row.transpose();
    rhs += row * n.pressure() * n.pressure();
  }
  const Eigen::Vector2d fit = m.ldlt().solve(rhs);
  EXPECT_NEAR(std::sqrt(fit(0)) / p0, 1.0, 0.01);
  EXPECT_NEAR(std::sqrt(-fit(0) / fit(1)) / a, 1.0, 0.01);
  EXPECT_NEAR(peak / p0, 1.0, 0.01);
  // every node well inside the contact on Hertz's profile
  for (const ContactNode& n : solve->solution.contact)
    if (std::abs(n.x.x()) < 0.8 * a)
      EXPECT_NEAR(n.pressure() / (p0 * std::sqrt(1.0 - n.x.x() * n.x.x() / (a * a))), 1.0, 0.01) << "x = " << n.x.x();
  EXPECT_NEAR(last / a, 1.0, 0.15);  // the last node pressed lies within a cell of the edge
  EXPECT_NEAR(a, 0.0335, 0.001);
  // the estimate sees both sides of the contact
  ASSERT_TRUE(solve->estimate);
  EXPECT_TRUE(std::isfinite(solve->estimate->relative));
}

TEST(SceneCurvedBodies, TheShrinkFitIsLamesAsTheCommandSolvesIt) {
  const app::SceneRun run = app::run_scene(parse_scene(test::scenes_dir() / "shrink-fit.toml"));
  ASSERT_TRUE(run.converged());
  const auto* solve = run.plane();
  ASSERT_NE(solve, nullptr);
  const test::LameRings rings;  // the scene's rings
  const double p = test::lame_interference(rings)[0] * rings.b / (rings.b + rings.delta);
  ASSERT_EQ(solve->solution.contact.size(), 512u);
  for (const ContactNode& n : solve->solution.contact) {
    EXPECT_NEAR(n.pressure() / p, 1.0, 2e-3) << "node at " << n.x.transpose();
    EXPECT_NEAR(n.gap, -rings.delta, 1e-12);
  }
  // the supports hold the rings without a force
  for (const auto& r : solve->solution.forces.reactions) EXPECT_LT(r.force.norm(), 1e-6 * p) << r.name;
}
