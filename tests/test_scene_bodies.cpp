// Scenes of several bodies ([[body]], docs/two-bodies.md): the schema (reading, writing back,
// refusals naming the key), the build (the meshes matched and joined, each body's range), and
// the shipped scene scenes/two-blocks.toml solved as the command solves it: the contact patch
// test exact, its outputs per body.
#include <hemivem/app/run.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/error.hpp>

#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.hpp"

using namespace hemivem;
namespace fs = std::filesystem;

namespace {

/// The shipped scene with `from` replaced by `to`, parsed: the InputError's message.
std::string refusal(const std::string& from, const std::string& to) {
  return test::scene_refusal("two-blocks.toml", from, to);
}

Scene two_blocks() { return parse_scene(test::scenes_dir() / "two-blocks.toml"); }

}  // namespace

TEST(SceneBodies, TheShippedSceneReadsItsBodiesAndWritesThemBack) {
  const Scene s = two_blocks();
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_EQ(s.bodies[0].name, "upper");
  EXPECT_EQ(s.bodies[0].mesh.generator, "voronoi");
  EXPECT_EQ(s.bodies[1].material.young, 4.0);
  ASSERT_EQ(s.bodies[1].dirichlet.size(), 2u);
  ASSERT_TRUE(s.contact);
  EXPECT_EQ(s.contact->body, "upper");
  EXPECT_EQ(s.contact->boundary.sides, std::vector<std::string>{"bottom"});
  ASSERT_TRUE(s.contact->against);
  EXPECT_EQ(s.contact->against_body, "lower");
  EXPECT_EQ(s.contact->against->sides, std::vector<std::string>{"top"});
  // a part against another body: no gap and a one-sided constraint unless it says otherwise
  EXPECT_EQ(s.contact->gap.value, 0.0);
  EXPECT_EQ(s.contact->constraint, ConstraintKind::one_sided);
  EXPECT_EQ(scene_mesh_description(s), "upper: voronoi n=[5, 3]; lower: squares n=[7, 3]");
  const Scene again = parse_scene_string(to_toml(s), "again.toml");
  EXPECT_TRUE(again == s);
  // a key of a body's table is overridden like any other
  Scene finer = s;
  apply_override(finer, "body[1].mesh.n=[9, 4]");
  EXPECT_EQ(finer.bodies[1].mesh.n, 9);
  EXPECT_FALSE(finer == s);
}

TEST(SceneBodies, WhatASceneOfSeveralBodiesRefusesIsNamed) {
  EXPECT_NE(refusal("side = \"upper.bottom\"", "side = \"bottom\"").find("named after its body"), std::string::npos);
  EXPECT_NE(refusal("side = \"upper.bottom\"", "side = \"uper.bottom\"").find("did you mean 'upper'"), std::string::npos);
  EXPECT_NE(refusal("side = \"upper.bottom\"", "side = \"upper.botom\"").find("unknown side 'botom'"), std::string::npos);
  EXPECT_NE(refusal("against = \"lower.top\"", "against = \"upper.top\"").find("the part's own body"), std::string::npos);
  EXPECT_NE(refusal("name = \"lower\"", "name = \"upper\"").find("two bodies are named 'upper'"), std::string::npos);
  EXPECT_NE(refusal("law = \"zero\"", "law = \"zero\"\n[mesh]\nn = 4").find("each [[body]] has its own mesh"),
            std::string::npos);
  EXPECT_NE(refusal("law = \"zero\"", "law = \"zero\"\n[adapt]\ntarget = 0.05").find("[adapt] is not available"),
            std::string::npos);
  EXPECT_NE(refusal("[body.mesh]\ngenerator = \"squares\"", "[body.mesh2]\ngenerator = \"squares\"").find("unknown key"),
            std::string::npos);
  // `against` needs another body
  try {
    parse_scene_string("schema_version = 1\n[contact]\nside = \"bottom\"\nagainst = \"lower.top\"\n", "one.toml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a scene of one body has no other"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("one.toml:4"), std::string::npos) << e.what();
  }
}

TEST(SceneBodies, TheBodiesAreMatchedAndJoinedIntoOneMesh) {
  const auto built = build_problem<2>(two_blocks());
  ASSERT_EQ(built->bodies.size(), 2u);
  const BodyRange& upper = built->bodies[0];
  const BodyRange& lower = built->bodies[1];
  EXPECT_EQ(upper.name, "upper");
  EXPECT_EQ(upper.first_vertex, 0);
  EXPECT_EQ(lower.first_vertex, upper.vertices);
  EXPECT_EQ(lower.first_vertex + lower.vertices, built->mesh.num_vertices());
  EXPECT_EQ(lower.cells, 7 * 3);
  EXPECT_EQ(upper.cells + lower.cells, built->mesh.num_cells());
  EXPECT_NEAR(built->mesh.total_area(), 1.0, 1e-12);
  ASSERT_EQ(built->problem.parts.size(), 1u);
  const ContactPart& part = built->problem.parts.front();
  EXPECT_FALSE(part.against.empty());
  // after matching both sides of the interface have the same points: as many edges each
  EXPECT_EQ(part.facets.size(), part.against.size());
  // the supports and loads are each body's, named after it
  ASSERT_EQ(built->problem.elasticity.dirichlet.size(), 3u);
  EXPECT_EQ(built->problem.elasticity.dirichlet[0].name, "upper.dirichlet[0]");
  EXPECT_EQ(built->problem.elasticity.dirichlet[2].name, "lower.dirichlet[1]");
}

TEST(SceneBodies, TheShippedSceneIsTheContactPatchTestAsTheCommandSolvesIt) {
  const app::SceneRun run = app::run_scene(two_blocks());
  ASSERT_TRUE(run.converged());
  const auto* solve = run.plane();
  ASSERT_NE(solve, nullptr);
  const Mesh& mesh = solve->built->mesh;
  const auto& bodies = solve->built->bodies;
  // sigma_yy = -2, sigma_xx = 0 in each block (plane strain), u_x = 0 on x = 0 and u_y = 0 on y = 0
  const auto exact = [](const Vec2& x, bool upper) {
    const auto eps = [](double E, double nu) { return Vec2(2.0 * nu * (1.0 + nu) / E, -2.0 * (1.0 - nu * nu) / E); };
    const Vec2 lo = eps(4.0, 0.1), up = eps(10.0, 0.3);
    return upper ? Vec2(up.x() * x.x(), lo.y() * 0.5 + up.y() * (x.y() - 0.5)) : Vec2(lo.x() * x.x(), lo.y() * x.y());
  };
  double worst = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec2 u(solve->solution.u(2 * v), solve->solution.u(2 * v + 1));
    worst = std::max(worst, (u - exact(mesh.vertex(v), bodies[0].has_vertex(v))).norm());
  }
  EXPECT_LT(worst, 1e-10);
  for (const ContactNode& n : solve->solution.contact) EXPECT_NEAR(n.pressure(), 2.0, 1e-10);
  // the estimate of an exact solution is round-off, the interface's other side included
  ASSERT_TRUE(solve->estimate);
  EXPECT_LT(solve->estimate->relative, 1e-10);
  // the outputs per body
  const fs::path dir = test::scratch("two-blocks");
  run.write(dir);
  const nlohmann::json r = nlohmann::json::parse(test::slurp(dir / "result.json"));
  ASSERT_TRUE(r["bodies"].is_array());
  ASSERT_EQ(r["bodies"].size(), 2u);
  EXPECT_EQ(r["bodies"][0]["name"], "upper");
  for (const auto& b : r["bodies"]) EXPECT_LT(b["forces"]["balance_residual"].get<double>(), 1e-10);
  EXPECT_NEAR(r["bodies"][0]["forces"]["contact"][1].get<double>(), 2.0, 1e-10);
  EXPECT_NEAR(r["bodies"][1]["forces"]["contact"][1].get<double>(), -2.0, 1e-10);
  EXPECT_EQ(r["forces"]["contact"][1].get<double>(), 0.0);
  const std::string csv = test::slurp(dir / "displacement.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "vertex,x,y,ux,uy,body");
  EXPECT_NE(csv.find(",lower\n"), std::string::npos);
  const std::string contact = test::slurp(dir / "contact.csv");
  EXPECT_NE(contact.substr(0, contact.find('\n')).find(",partner"), std::string::npos);
  fs::remove_all(dir);
}

// The same in three dimensions (scenes/two-boxes-3d.toml): tetrahedra on cubes, matched along
// z = 0.5; uniaxial stress sigma_zz = -2 in each box, free lateral expansion.
TEST(SceneBodies, TwoBoxesAreTheContactPatchTestInThreeDimensions) {
  const app::SceneRun run = app::run_scene(parse_scene(test::scenes_dir() / "two-boxes-3d.toml"));
  ASSERT_EQ(run.dimension(), 3);
  ASSERT_TRUE(run.converged());
  const auto* solve = run.solid();
  ASSERT_NE(solve, nullptr);
  const Mesh3D& mesh = solve->built->mesh;
  const auto& bodies = solve->built->bodies;
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[1].cells, 8);
  const auto exact = [](const Vec3& x, bool upper) {
    const auto eps = [](double E, double nu) { return Vec3(2.0 * nu / E, 2.0 * nu / E, -2.0 / E); };
    const Vec3 lo = eps(4.0, 0.1), up = eps(10.0, 0.3);
    if (!upper) return Vec3(lo.x() * x.x(), lo.y() * x.y(), lo.z() * x.z());
    return Vec3(up.x() * x.x(), up.y() * x.y(), lo.z() * 0.5 + up.z() * (x.z() - 0.5));
  };
  double worst = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    worst = std::max(worst, (Vec3(solve->solution.u.segment<3>(3 * v)) - exact(mesh.vertex(v), bodies[0].has_vertex(v))).norm());
  EXPECT_LT(worst, 1e-10);
  ASSERT_FALSE(solve->solution.contact.empty());
  for (const ContactNode3D& n : solve->solution.contact) {
    EXPECT_GE(n.partner, bodies[1].first_vertex);
    EXPECT_NEAR(n.pressure(), 2.0, 1e-10);
  }
  EXPECT_LT(solve->solution.forces.residual(), 1e-10);
}

TEST(SceneBodies, FrictionBetweenTheBodiesHoldsTheUpperBlock) {
  // scenes/two-blocks.toml with the upper block free of supports, pressed by 2 and sheared by
  // 0.5 on its top, Tresca friction of bound 1 at the interface: the contact and its friction
  // alone hold it; the forces on it are the load's opposite, no friction force exceeds its bound
  // (the pairs that slip, at its left end, carry it), every support's reaction closes the balance
  // (the lower block's roller under the upper block's corner carries that pair's friction), and
  // both minimizers find one solution
  std::string text = test::slurp(test::scenes_dir() / "two-blocks.toml");
  const std::string held = "[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n\n[[body.loads.traction]]\nside = \"top\"\npressure = 2.0\n";
  const auto at = text.find(held);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, held.size(),
               "[[body.loads.traction]]\nside = \"top\"\npressure = 2.0\n\n[[body.loads.traction]]\nside = \"top\"\n"
               "value = [0.5, 0.0]\n");
  text += "\n[contact.friction]\nlaw = \"tresca\"\nbound = 1.0\n";
  Eigen::VectorXd first;
  for (const std::string minimizer : {"ssn", "bundle-dca"}) {
    SCOPED_TRACE(minimizer);
    Scene scene = parse_scene_string(text, "two-blocks-friction.toml");
    apply_override(scene, "solver.minimizer=" + minimizer);
    const app::SceneRun run = app::run_scene(scene);
    ASSERT_TRUE(run.converged());
    const auto* solve = run.plane();
    ASSERT_NE(solve, nullptr);
    Vec2 on_upper = Vec2::Zero();
    int slip = 0, stick = 0;
    for (const ContactNode& n : solve->solution.contact) {
      EXPECT_LE(std::abs(n.friction_force), 1.0 * n.weight * (1.0 + 1e-9)) << "node at x = " << n.x.x();
      if (n.friction_state == FrictionState::slip) {
        ++slip;
        EXPECT_NEAR(std::abs(n.friction_force), n.weight, 1e-9) << "node at x = " << n.x.x();
      }
      if (n.friction_state == FrictionState::stick) ++stick;
      on_upper += n.force_on_body();
    }
    EXPECT_GT(stick, 0);
    EXPECT_NEAR(on_upper.x(), -0.5, 1e-9);
    EXPECT_NEAR(on_upper.y(), 2.0, 1e-9);
    EXPECT_LT(solve->solution.forces.residual(), 1e-9);
    if (first.size() == 0) first = solve->solution.u;
    else EXPECT_LT((solve->solution.u - first).lpNorm<Eigen::Infinity>(), 1e-7 * first.lpNorm<Eigen::Infinity>());
  }
}
