// Adaptive refinement of solid scenes (docs/adaptivity.md, "Solids"): the sequence of a plane
// scene on polyhedral meshes, each refined mesh posing the problem of the same mesh built
// refined, warm starts and budgets, through the one entry point and the command.
#include <gtest/gtest.h>

#include <hemivem/app/adapt.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/mesh/refine3d.hpp>
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace hemivem {
namespace {

using app::AdaptStop;

/// The three-dimensional Example 4.1 on n x n/2 x n cubes.
Scene example_3d(int n, std::vector<std::string> overrides = {}) {
  Scene s = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  overrides.insert(overrides.begin(),
                   "mesh.n=[" + std::to_string(n) + "," + std::to_string(std::max(1, n / 2)) + "," + std::to_string(n) + "]");
  apply_overrides(s, overrides);
  return s;
}

// Uniform refinement of 2 x 1 x 2 cubes is 4 x 2 x 4 cubes: the same contact nodes, the same
// prescribed components and the same solution (energy and the displacement at every point).
TEST(Adapt3D, ARefinedMeshPosesTheProblemOfTheMeshBuiltRefined) {
  const Scene coarse = example_3d(2);
  const Scene fine = example_3d(4);
  const auto built = build_problem<3>(coarse);
  const RefinedMesh3D refined = refine_uniformly(built->mesh);
  app::SceneSolve3DOptions o;
  o.mesh = refined.mesh;
  const app::SceneSolve3D a = app::solve_scene_3d(coarse, o);
  const app::SceneSolve3D b = app::solve_scene_3d(fine);
  ASSERT_TRUE(a.solution.converged());
  ASSERT_TRUE(b.solution.converged());
  ASSERT_EQ(a.built->mesh.num_cells(), b.built->mesh.num_cells());
  ASSERT_EQ(a.solution.contact.size(), b.solution.contact.size());
  ASSERT_EQ(a.solution.unknowns, b.solution.unknowns);
  EXPECT_NEAR(a.solution.energy, b.solution.energy, 1e-10 * std::abs(b.solution.energy));
  // the displacement at each vertex of the refined mesh, found by position in the fine one
  const Mesh3D& ma = a.built->mesh;
  const Mesh3D& mb = b.built->mesh;
  double worst = 0.0;
  for (int v = 0; v < ma.num_vertices(); ++v) {
    int w = -1;
    for (int k = 0; k < mb.num_vertices() && w < 0; ++k)
      if ((mb.vertex(k) - ma.vertex(v)).norm() < 1e-12) w = k;
    ASSERT_GE(w, 0) << "vertex " << v;
    worst = std::max(worst, (a.solution.u.segment<3>(3 * v) - b.solution.u.segment<3>(3 * w)).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst, 1e-9 * b.solution.u.lpNorm<Eigen::Infinity>());
}

TEST(Adapt3D, TheWarmStartReachesTheSameSolution) {
  const Scene s = example_3d(4);
  const app::SceneSolve3D coarse = app::solve_scene_3d(s);
  ASSERT_TRUE(coarse.estimate);
  const RefinedMesh3D refined = refine_mesh(coarse.built->mesh, dorfler_marking(coarse.estimate->indicators, 0.5));
  EXPECT_GT(refined.mesh.num_cells(), coarse.built->mesh.num_cells());
  app::SceneSolve3DOptions cold;
  cold.mesh = refined.mesh;
  app::SceneSolve3DOptions warm = cold;
  warm.start = prolongate(refined, coarse.solution.u);
  const app::SceneSolve3D a = app::solve_scene_3d(s, cold);
  const app::SceneSolve3D b = app::solve_scene_3d(s, warm);
  ASSERT_TRUE(a.solution.converged());
  ASSERT_TRUE(b.solution.converged());
  EXPECT_LE(b.solution.iterations(), a.solution.iterations());
  EXPECT_LT((a.solution.u - b.solution.u).lpNorm<Eigen::Infinity>(), 1e-8 * a.solution.u.lpNorm<Eigen::Infinity>());
}

TEST(Adapt3D, RefinesWhereTheEstimateIsLargeAndRecordsEveryStep) {
  const Scene s = example_3d(4, {"adapt.target=0.001", "adapt.max_steps=4", "adapt.fraction=0.3"});
  ASSERT_TRUE(s.adapt);
  std::vector<app::AdaptStep> seen;
  const app::SceneRun run = app::run_scene(s, {.on_adapt_step = [&](const app::AdaptStep& a) { seen.push_back(a); }});
  ASSERT_NE(run.solid_adaptive(), nullptr);
  const app::AdaptiveSolve3D& r = *run.solid_adaptive();
  EXPECT_EQ(r.stopped, AdaptStop::max_steps) << r.reason;
  ASSERT_EQ(r.steps.size(), 4u);
  EXPECT_EQ(seen.size(), r.steps.size());
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const app::AdaptStep& st = r.steps[k];
    EXPECT_EQ(st.status, "converged") << k;
    if (k + 1 < r.steps.size()) {
      EXPECT_GT(st.marked, 0);
      EXPECT_GE(st.refined, st.marked);
      EXPECT_LT(st.marked, st.elements) << "Doerfler marking with fraction 0.3 marks a part of the cells";
      EXPECT_GT(r.steps[k + 1].unknowns, st.unknowns);
      EXPECT_GT(r.steps[k + 1].elements, st.elements);
    }
  }
  EXPECT_LT(r.steps.back().estimate, r.steps.front().estimate);
  ASSERT_NE(run.solid(), nullptr);
  EXPECT_EQ(run.solid()->built->mesh.num_cells(), r.steps.back().elements);
  EXPECT_EQ(run.solid()->adapt.at("steps").size(), 4u);
  EXPECT_NE(run.solid()->mesh_description.find("refined adaptively"), std::string::npos);
  EXPECT_NE(run.report().find("adapt         4 solves"), std::string::npos) << run.report();
  // the balance of forces holds on the final mesh as on the first
  EXPECT_LT(run.solid()->solution.forces.residual(), 1e-8);
}

TEST(Adapt3D, StopsAtItsBudgetsAndBeforeAMeshThatWouldNotFit) {
  const app::SceneRun u = app::run_scene(example_3d(2, {"adapt.target=0.001", "adapt.max_unknowns=400"}));
  ASSERT_NE(u.solid_adaptive(), nullptr);
  EXPECT_EQ(u.solid_adaptive()->stopped, AdaptStop::max_unknowns);
  for (const auto& st : u.solid_adaptive()->steps) EXPECT_LE(st.unknowns, 400);
  ::setenv("HEMIVEM_MEMORY_LIMIT", "40M", 1);
  const app::SceneRun m = app::run_scene(example_3d(4, {"adapt.target=0.001"}));
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  ASSERT_NE(m.solid_adaptive(), nullptr);
  EXPECT_EQ(m.solid_adaptive()->stopped, AdaptStop::memory) << m.solid_adaptive()->reason;
  EXPECT_NE(m.solid_adaptive()->reason.find("the next mesh ("), std::string::npos) << m.solid_adaptive()->reason;
  EXPECT_TRUE(m.converged());
}

// Every shipped kind of solid adapts: an obstacle (a sphere), a Gmsh body of tetrahedra with
// its physical surfaces, boxes; forces balance on the final mesh.
TEST(Adapt3D, EveryShippedKindOfSolidSceneAdapts) {
  for (const char* file : {"hertz-sphere-3d.toml", "gmsh-bracket-3d.toml", "example-4.1-3d.toml"}) {
    Scene s = parse_scene(test::scenes_dir() / file);
    apply_overrides(s, {"adapt.max_steps=2", "adapt.target=0.001"});
    const app::SceneRun run = app::run_scene(s);
    ASSERT_NE(run.solid_adaptive(), nullptr) << file;
    const auto& steps = run.solid_adaptive()->steps;
    ASSERT_EQ(steps.size(), 2u) << file << ": " << run.solid_adaptive()->reason;
    for (const auto& st : steps) EXPECT_EQ(st.status, "converged") << file;
    EXPECT_GT(steps[1].elements, steps[0].elements) << file;
    EXPECT_LT(steps[1].estimate, steps[0].estimate) << file;
    EXPECT_LT(run.solid()->solution.forces.residual(), 1e-10) << file;
    EXPECT_GT(run.solid()->solution.contact.size(), 0u) << file;
  }
}

// The command: --adapt on a solid scene writes the steps as a ParaView series and the figure.
TEST(Adapt3D, TheCommandWritesTheSequence) {
  const std::filesystem::path out = test::scratch("adapt3d");
  std::filesystem::remove_all(out);
  const auto r = test::run_command(std::string(HEMIVEM_BINARY) + " solve " +
                                   (test::scenes_dir() / "example-4.1-3d.toml").string() +
                                   " --set 'mesh.n=[4,2,4]' --adapt --set adapt.max_steps=2 --set "
                                   "'output.write=[\"result-json\",\"vtu\",\"adapt-png\"]' --out " +
                                   out.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("hemivem: adapt step 1:"), std::string::npos) << r.err;
  for (const char* name : {"result.json", "solution.vtu", "adapt.pvd", "adapt-step-0.vtu", "adapt-step-1.vtu"})
    EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
  std::ifstream in(out / "result.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_TRUE(j["adapt"].is_object()) << j.dump(2);
  EXPECT_EQ(j["adapt"]["steps"].size(), 2u);
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace hemivem
