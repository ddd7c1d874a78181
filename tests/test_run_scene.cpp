// app::run_scene, the one entry point for a scene: it picks the solve a scene asks for (plane or
// solid; static, path or adaptive), gives the numbers of that solve called directly, and
// refuses by key what a kind of run cannot do; a defect found in the problem names its scene key.
#include <gtest/gtest.h>

#include <hemivem/app/report.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace hemivem::app {
namespace {

Scene small_plane() {
  Scene s = default_scene();
  apply_overrides(s, {"mesh.n=8"});
  return s;
}

Scene small_solid() {
  Scene s = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  apply_overrides(s, {"mesh.n=[4, 2, 4]"});
  return s;
}

// the files of a scene's outputs, in the order of each dimension's list, as its keys, its
// contact, an adaptive solve and a path select them
TEST(RunScene, TheFilesWantedAreTheScenesOutputsInEitherDimension) {
  using Files = std::vector<std::string>;
  const Scene plane = small_plane();
  EXPECT_EQ(wanted_files(plane, true),
            (Files{"result.json", "contact.csv", "displacement.csv", "stress.csv", "history.csv", "solution.vtu",
                   "scene.toml", "u_nu.png", "deformed.png", "error.png"}));
  EXPECT_EQ(wanted_files(plane, false), (Files{"result.json", "displacement.csv", "stress.csv", "solution.vtu",
                                               "scene.toml", "deformed.png", "error.png"}));
  Scene adaptive = small_plane();
  adaptive.adapt = SceneAdapt{};
  EXPECT_EQ(wanted_files(adaptive, true),
            (Files{"result.json", "contact.csv", "displacement.csv", "stress.csv", "history.csv", "solution.vtu",
                   "scene.toml", "mesh.poly2d", "u_nu.png", "deformed.png", "error.png", "mesh.png", "adapt.png",
                   "adapt.pvd"}));
  Scene path = small_plane();
  apply_overrides(path, {"path.steps=3", R"(output.write=["result-json", "vtu"])"});
  EXPECT_EQ(wanted_files(path, true), (Files{"result.json", "solution.vtu", "scene.toml", "path.json",
                                             "path-contact.csv", "solution.pvd", "path.png"}));
  EXPECT_EQ(wanted_files(path, false), (Files{"result.json", "solution.vtu", "scene.toml"}));
  Scene solid = small_solid();
  solid.adapt = SceneAdapt{};
  EXPECT_EQ(wanted_files(solid, true),
            (Files{"result.json", "contact.csv", "displacement.csv", "stress.csv", "history.csv", "solution.vtu",
                   "contact-surface.vtu", "scene.toml", "deformed.png", "adapt.png", "adapt.pvd", "pressure.png"}));
}

TEST(RunScene, KindIsWhatTheSceneAsksFor) {
  EXPECT_EQ(run_kind(small_plane()), RunKind::static_solve);
  Scene path = small_plane();
  apply_overrides(path, {"path.steps=3"});
  EXPECT_EQ(run_kind(path), RunKind::path);
  Scene adaptive = small_plane();
  adaptive.adapt = SceneAdapt{};
  EXPECT_EQ(run_kind(adaptive), RunKind::adaptive);
  path.adapt = SceneAdapt{};
  EXPECT_THROW(run_kind(path), InputError);
  EXPECT_EQ(to_string(RunKind::static_solve), "static");
  EXPECT_EQ(to_string(RunKind::path), "path");
  EXPECT_EQ(to_string(RunKind::adaptive), "adaptive");
}

TEST(RunScene, APlaneStaticSolveIsSolveScene) {
  const Scene scene = small_plane();
  const SceneRun run = run_scene(scene);
  const SceneSolve direct = solve_scene(scene);
  ASSERT_NE(run.plane(), nullptr);
  EXPECT_EQ(run.solid(), nullptr);
  EXPECT_EQ(run.dimension(), 2);
  EXPECT_EQ(run.kind(), RunKind::static_solve);
  EXPECT_TRUE(run.converged());
  EXPECT_TRUE(run.has_contact());
  EXPECT_EQ(run.plane()->solution.energy, direct.solution.energy);
  EXPECT_EQ(run.plane()->solution.u, direct.solution.u);
  EXPECT_EQ(run.path(), nullptr);
  EXPECT_EQ(run.adaptive(), nullptr);
  EXPECT_EQ(run.result_json()["dimension"], 2);
}

TEST(RunScene, ASolidSolveIsSolveScene3D) {
  const Scene scene = small_solid();
  const SceneRun run = run_scene(scene);
  const SceneSolve3D direct = solve_scene_3d(scene);
  ASSERT_NE(run.solid(), nullptr);
  EXPECT_EQ(run.plane(), nullptr);
  EXPECT_EQ(run.dimension(), 3);
  EXPECT_TRUE(run.converged());
  EXPECT_EQ(run.solid()->solution.energy, direct.solution.energy);
  EXPECT_EQ(run.solid()->solution.u, direct.solution.u);
  EXPECT_EQ(run.result_json()["dimension"], 3);
  EXPECT_EQ(run.brief(), brief_report(*run.solid()).substr(0, run.brief().size()));
}

TEST(RunScene, APathRunsEveryStepAndEndsWhereTheStaticSolveIs) {
  Scene scene = small_plane();
  apply_overrides(scene, {"path.steps=4"});
  int steps_seen = 0;
  RunOptions options;
  options.on_path_step = [&](const PathProgress& p) {
    ++steps_seen;
    EXPECT_EQ(p.steps, 4);
    EXPECT_EQ(p.step, steps_seen);
    EXPECT_NE(p.line.find("step " + std::to_string(p.step) + "/4"), std::string::npos) << p.line;
  };
  const SceneRun run = run_scene(scene, std::move(options));
  EXPECT_EQ(run.kind(), RunKind::path);
  ASSERT_NE(run.path(), nullptr);
  EXPECT_EQ(steps_seen, 4);
  EXPECT_EQ(run.path()->steps.size(), 4u);
  EXPECT_TRUE(run.converged());
  // the last step is the static solve of the whole load (a convex law here: one solution)
  const SceneRun once = run_scene(small_plane());
  EXPECT_NEAR(run.plane()->solution.energy, once.plane()->solution.energy,
              1e-9 * std::abs(once.plane()->solution.energy));
  EXPECT_NE(run.report().find("path"), std::string::npos);
}

// A path's frames cost an interior solve and memory each: computed only for a run that writes
// them (displacement-csv, vtu); the last step always has its displacement, the same either way.
TEST(RunScene, APathComputesFramesOnlyWhenAFileOfFramesIsWritten) {
  Scene with = small_plane();
  apply_overrides(with, {"path.steps=4", "output.write=[\"result-json\", \"displacement-csv\"]"});
  Scene without = small_plane();
  apply_overrides(without, {"path.steps=4", "output.write=[\"result-json\"]"});
  const SceneRun a = run_scene(with);
  const SceneRun b = run_scene(without);
  ASSERT_NE(a.path(), nullptr);
  ASSERT_NE(b.path(), nullptr);
  for (int k = 0; k < 4; ++k) {
    EXPECT_GT(a.path()->steps[static_cast<std::size_t>(k)].u.size(), 0) << k;  // 4 steps, 100 frames: every step
    EXPECT_EQ(b.path()->steps[static_cast<std::size_t>(k)].u.size() > 0, k == 3) << k;
  }
  EXPECT_EQ(a.plane()->solution.u, b.plane()->solution.u);
  // a step's energy is that of its full displacement where it has one, else of its contact
  // unknowns: the same number to round-off
  EXPECT_NEAR(a.path()->steps[1].energy, b.path()->steps[1].energy, 1e-12 * std::abs(b.path()->steps[1].energy));
  const auto listed = [](const SceneRun& r, const std::string& name) {
    const auto files = r.wanted_files();
    return std::find(files.begin(), files.end(), name) != files.end();
  };
  EXPECT_TRUE(listed(a, "path-displacement.csv"));
  EXPECT_FALSE(listed(b, "path-displacement.csv"));
  EXPECT_TRUE(listed(b, "path.json"));
}

TEST(RunScene, AnAdaptiveRunKeepsItsSequenceAndEndsOnTheFinalMesh) {
  Scene scene = small_plane();
  scene.adapt = SceneAdapt{};
  scene.adapt->max_steps = 3;
  int steps_seen = 0;
  RunOptions options;
  options.on_adapt_step = [&](const AdaptStep&) { ++steps_seen; };
  const SceneRun run = run_scene(scene, std::move(options));
  ASSERT_NE(run.adaptive(), nullptr);
  EXPECT_EQ(run.kind(), RunKind::adaptive);
  EXPECT_EQ(static_cast<int>(run.adaptive()->steps.size()), steps_seen);
  EXPECT_EQ(run.adaptive()->steps.back().vertices, run.plane()->built->mesh.num_vertices());
  EXPECT_FALSE(run.result_json()["adapt"].is_null());
  EXPECT_NE(run.report().find("adapt"), std::string::npos);
}

TEST(RunScene, RefusesByKeyWhatAKindCannotDo) {
  ReducedProblem reduced;
  Scene path = small_plane();
  apply_overrides(path, {"path.steps=2"});
  RunOptions o;
  o.reduced = &reduced;
  o.reduced_key = "--export-reduced";
  try {
    run_scene(path, std::move(o));
    FAIL() << "a path has no one reduced problem";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "--export-reduced");
  }
  RunOptions m;
  m.mesh = make_squares(2, Rectangle{});
  m.mesh_key = "mesh=";
  try {
    run_scene(small_solid(), std::move(m));
    FAIL() << "a plane mesh for a solid scene";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "mesh=");
  }
  // an adaptive solid is a kind of run as an adaptive plane is
  Scene solid = small_solid();
  solid.adapt = SceneAdapt{};
  solid.adapt->max_steps = 2;
  const SceneRun adaptive = run_scene(solid);
  EXPECT_EQ(adaptive.kind(), RunKind::adaptive);
  ASSERT_NE(adaptive.solid_adaptive(), nullptr);
  EXPECT_EQ(adaptive.solid_adaptive()->steps.size(), 2u);
}

TEST(RunScene, WritesWhatTheCommandWrites) {
  const auto dir = std::filesystem::temp_directory_path() / ("hemivem-run-scene-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const SceneRun run = run_scene(small_solid());
  const OutputReport report = run.write(dir);
  EXPECT_FALSE(report.written.empty());
  std::ifstream in(dir / "result.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_EQ(j["potential_energy"].get<double>(), run.solid()->solution.energy);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hemivem::app

namespace hemivem::app {
namespace {

// A defect the solver finds when it sets the problem up carries what it is about as data
// (InputError::about), and the run names the scene's key of it: the same in both dimensions.
TEST(RunScene, ADefectOfTheSupportsOrTheContactNamesItsSceneKey) {
  // a plane body nothing holds horizontally (rollers ux = 0 nowhere, uy = 0 on the bottom)
  Scene plane = parse_scene_string(R"(schema_version = 1
[mesh]
generator = "squares"
n = 2
[[dirichlet]]
side = "bottom"
uy = 0.0
[[loads.traction]]
side = "top"
value = [0.0, -1.0]
)",
                                   "loose.toml");
  try {
    run_scene(plane);
    FAIL() << "a body nothing holds was solved";
  } catch (const InputError& e) {
    EXPECT_EQ(e.about(), ProblemPart::supports);
    EXPECT_EQ(e.where(), plane.where("dirichlet")) << e.what();
  }
  // a solid whose contact node has its normal component prescribed
  Scene solid = small_solid();
  apply_overrides(solid, {"clamped.side=[\"x0\", \"x1\", \"bottom\"]"});
  try {
    run_scene(solid);
    FAIL() << "a clamped contact part was solved";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), solid.where("contact")) << e.what();
    EXPECT_NE(e.detail().find("every node of the contact part is also clamped"), std::string::npos) << e.what();
  }
  // the core marks what a defect is about
  Scene pinned = default_scene();
  apply_overrides(pinned, {"mesh.n=4"});
  auto built = build_problem(pinned);
  built->problem.elasticity.dirichlet.push_back({built->problem.parts[0].facets, {}, {false, true}, "pinned"});
  try {
    (void)solve_contact(built->problem, make_factorization(FactorizationOptions{}), *make_minimizer("ssn"),
                        MinimizerOptions{});
    FAIL() << "a prescribed normal component at the contact was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.about(), ProblemPart::contact) << e.what();
    EXPECT_TRUE(e.where().empty());
  }
}

}  // namespace
}  // namespace hemivem::app
