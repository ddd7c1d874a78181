// Adaptive solves (hemivem/app/adapt.hpp): the scene's [adapt] table, the loop's stops, the
// problem re-derived on refined meshes equal to the one built on a mesh made refined, the
// warm start, and every mesh kind a scene can name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <array>
#include <vector>

#include <stdlib.h>

#include <hemivem/app/adapt.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/scene/scene.hpp>

#include "test_support.hpp"

namespace hemivem {
namespace {

using app::AdaptStop;

Scene example(int n) {
  Scene s = default_scene();
  s.mesh.n = n;
  s.solver.linear = "eigen";
  return s;
}

std::string error_of(const std::string& text) {
  try {
    (void)parse_scene_string(text, "adapt.toml");
  } catch (const InputError& e) {
    return e.where() + ": " + e.detail();
  }
  return {};
}

TEST(AdaptScene, TableIsReadWrittenAndChecked) {
  const std::string head = "schema_version = 1\n[clamped]\nside = \"left\"\n";
  EXPECT_FALSE(parse_scene_string(head, "a.toml").adapt);
  const Scene d = parse_scene_string(head + "[adapt]\n", "a.toml");
  ASSERT_TRUE(d.adapt);
  EXPECT_EQ(*d.adapt, SceneAdapt{});
  const Scene s = parse_scene_string(head + "[adapt]\ntarget = 0.02\nmax_unknowns = 5000\nmax_steps = 7\nfraction = 0.3\n",
                                     "a.toml");
  ASSERT_TRUE(s.adapt);
  EXPECT_EQ(s.adapt->target, 0.02);
  EXPECT_EQ(s.adapt->max_unknowns, 5000);
  EXPECT_EQ(s.adapt->max_steps, 7);
  EXPECT_EQ(s.adapt->fraction, 0.3);
  EXPECT_EQ(parse_scene_string(to_toml(s), "b.toml"), s);
  EXPECT_EQ(error_of(head + "[adapt]\ntarget = 2.0\n"), "adapt.toml:5: adapt.target: must be a relative error in (0, 1), got 2.0");
  EXPECT_NE(error_of(head + "[adapt]\nfraction = 0.0\n").find("adapt.toml:5"), std::string::npos);
  EXPECT_NE(error_of(head + "[adapt]\nmax_steps = 0\n").find("between 1 and 1000"), std::string::npos);
  EXPECT_NE(error_of(head + "[adapt]\ntargett = 0.1\n").find("target"), std::string::npos);
  Scene o = parse_scene_string(head, "a.toml");
  apply_override(o, "adapt.target=0.05");
  ASSERT_TRUE(o.adapt);
  EXPECT_EQ(o.adapt->target, 0.05);
}

TEST(Adapt, ReachesItsTargetAndRecordsEveryStep) {
  const Scene s = example(4);
  SceneAdapt a;
  a.target = 0.08;
  std::vector<int> seen;
  const app::AdaptiveSolve r = app::solve_adaptively(s, a, app::SceneSolveOptions{}, [&](const app::AdaptStep& st) { seen.push_back(st.step); });
  ASSERT_TRUE(r.reached_target()) << r.reason;
  ASSERT_GE(r.steps.size(), 3u);
  EXPECT_EQ(seen.size(), r.steps.size());
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const app::AdaptStep& st = r.steps[k];
    EXPECT_EQ(st.step, static_cast<int>(k));
    EXPECT_EQ(st.status, "converged");
    if (k + 1 < r.steps.size()) {
      EXPECT_GT(st.estimate, a.target);
      EXPECT_GT(st.marked, 0);
      EXPECT_GE(st.refined, st.marked);
      EXPECT_GT(r.steps[k + 1].unknowns, st.unknowns);
      EXPECT_GE(r.steps[k + 1].elapsed, st.elapsed);
    }
  }
  EXPECT_LE(r.steps.back().estimate, a.target);
  EXPECT_LT(r.steps.back().potential_energy, r.steps.front().potential_energy);
  // the last solve is the final mesh's, with its own estimate and the sequence's record
  ASSERT_TRUE(r.last.estimate);
  EXPECT_EQ(r.last.estimate->relative, r.steps.back().estimate);
  EXPECT_EQ(r.last.built->mesh.num_elements(), r.steps.back().elements);
  EXPECT_EQ(r.last.adapt.at("stopped"), "target");
  EXPECT_EQ(r.last.adapt.at("steps").size(), r.steps.size());
  EXPECT_NE(r.last.mesh_description.find("refined adaptively"), std::string::npos);
}

TEST(Adapt, StopsAtItsBudgetsAndSaysWhich) {
  const Scene s = example(4);
  SceneAdapt a;
  a.target = 1e-4;
  a.max_steps = 3;
  const app::AdaptiveSolve r = app::solve_adaptively(s, a);
  EXPECT_EQ(r.stopped, AdaptStop::max_steps);
  EXPECT_EQ(r.steps.size(), 3u);
  EXPECT_NE(r.reason.find("max_steps = 3"), std::string::npos) << r.reason;
  EXPECT_FALSE(r.reached_target());
  a.max_steps = 100;
  a.max_unknowns = 400;
  const app::AdaptiveSolve u = app::solve_adaptively(s, a);
  EXPECT_EQ(u.stopped, AdaptStop::max_unknowns);
  EXPECT_NE(u.reason.find("max_unknowns = 400"), std::string::npos) << u.reason;
  for (const auto& st : u.steps) EXPECT_LE(st.unknowns, 400);
}

TEST(Adapt, StopsBeforeAMeshThatWouldNotFitInMemory) {
  // a limit that holds the first mesh's solve and not the refined one's: the sequence stops on
  // the mesh it solved and says why, instead of running out of memory
  const Scene s = example(4);
  const double first = estimate_memory(make_squares(4)).solve_bytes;
  ::setenv("HEMIVEM_MEMORY_LIMIT", std::to_string(static_cast<long long>(first) + 1).c_str(), 1);
  SceneAdapt a;
  a.target = 1e-4;
  const app::AdaptiveSolve r = app::solve_adaptively(s, a);
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_EQ(r.stopped, AdaptStop::memory);
  EXPECT_EQ(r.steps.size(), 1u);
  EXPECT_TRUE(r.last.solution.converged());
  EXPECT_NE(r.reason.find("HEMIVEM_MEMORY_LIMIT"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("the next mesh ("), std::string::npos) << r.reason;
  EXPECT_EQ(r.last.adapt.at("stopped"), "memory");
}

TEST(Adapt, TheMemoryCheckTakesTheRoutesEstimate) {
  // a limit between the condensed and the full-space route's estimates for the second mesh: on
  // the full-space route the sequence goes on where the condensed route's estimate would fit
  // or not, as that route's own estimate says
  Scene s = example(32);
  s.solver.linear = "eigen-cg";
  SceneAdapt a;
  a.target = 1e-4;
  a.max_steps = 2;
  const app::AdaptiveSolve free = app::solve_adaptively(s, a);
  ASSERT_EQ(free.steps.size(), 2u) << free.reason;
  const MemoryEstimate condensed = estimate_memory(free.last.built->mesh);
  const double full = full_space_memory(condensed, full_space_cost(2, s.mesh.generator, "eigen-cg")).solve_bytes;
  ASSERT_GT(std::abs(full - condensed.solve_bytes), 0.01 * full) << full << " " << condensed.solve_bytes;
  const double limit = 0.5 * (full + condensed.solve_bytes);
  ::setenv("HEMIVEM_MEMORY_LIMIT", std::to_string(static_cast<long long>(limit)).c_str(), 1);
  const app::AdaptiveSolve r = app::solve_adaptively(s, a);
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  if (full < limit) {
    EXPECT_EQ(r.stopped, AdaptStop::max_steps) << r.reason;
    EXPECT_EQ(r.steps.size(), 2u);
  } else {
    EXPECT_EQ(r.stopped, AdaptStop::memory);
    EXPECT_EQ(r.steps.size(), 1u);
    EXPECT_NE(r.reason.find("on the full-space route with eigen-cg"), std::string::npos) << r.reason;
  }
}

TEST(Adapt, RunsInOneProcess) {
  Scene s = example(4);
  s.solver.linear = "mumps-mpi";
  const std::string message = test::input_error_of([&] { (void)app::solve_adaptively(s, SceneAdapt{}); });
  EXPECT_NE(message.find("an adaptive solve runs in one process"), std::string::npos) << message;
}

// The problem a scene poses on a mesh refined from its own equals the one it poses on the
// mesh built refined: the same supports, the same contact nodes with the same normals,
// weights and gaps (numbers, expressions and obstacles re-evaluated at the new nodes).
// Per contact node, by position: x, y, weight, gap, normal's y.
using NodeKey = std::array<double, 5>;
std::vector<NodeKey> nodes_of(const Scene& scene, const Mesh& mesh) {
  const ContactProblem p = make_contact_problem(scene, mesh);
  const DofMap dofs = make_dof_map(mesh, p.elasticity.dirichlet);
  const ContactBoundary b = contact_boundary(p, dofs);
  std::vector<NodeKey> out;
  for (int i = 0; i < b.size(); ++i) {
    const Vec2 x = mesh.vertex(b.nodes[static_cast<std::size_t>(i)]);
    out.push_back({x.x(), x.y(), b.weights(i), b.gaps(i), b.normals[static_cast<std::size_t>(i)].y()});
  }
  std::sort(out.begin(), out.end());  // distinct nodes are a mesh size apart: round-off does not reorder them
  return out;
}

// Two node lists are the same nodes with the same data, to round-off.
void expect_same_nodes(const std::vector<NodeKey>& a, const std::vector<NodeKey>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t k = 0; k < 5; ++k)
      if (a[i][k] != b[i][k])  // equal infinities (a gap whose ray misses the obstacle) are equal
        EXPECT_NEAR(a[i][k], b[i][k], 1e-12) << what << ", node " << i << ", entry " << k;
}

int prescribed_dofs(const Scene& scene, const Mesh& mesh) {
  const ContactProblem p = make_contact_problem(scene, mesh);
  const DofMap dofs = make_dof_map(mesh, p.elasticity.dirichlet);
  return dofs.num_dofs() - dofs.num_free();
}

TEST(Adapt, ARefinedMeshPosesTheProblemOfTheMeshBuiltRefined) {
  for (const char* gap : {"contact.gap=0.02", "contact.gap=\"0.02 + 0.01*x*x\""}) {
    Scene coarse = example(4);
    apply_override(coarse, gap);
    Scene fine = coarse;
    fine.mesh.n = 8;
    const auto built_coarse = build_problem(coarse);
    const RefinedMesh refined = refine_uniformly(built_coarse->mesh);
    const auto built_fine = build_problem(fine);
    expect_same_nodes(nodes_of(coarse, refined.mesh), nodes_of(fine, built_fine->mesh), gap);
    EXPECT_EQ(prescribed_dofs(coarse, refined.mesh), prescribed_dofs(fine, built_fine->mesh)) << gap;
  }
  // an obstacle: the gaps of the new nodes are the obstacle's
  Scene hertz = parse_scene(test::scenes_dir() / "hertz.toml");
  hertz.mesh.n = 8;
  Scene hertz_fine = hertz;
  hertz_fine.mesh.n = 16;
  const RefinedMesh refined = refine_uniformly(build_problem(hertz)->mesh);
  expect_same_nodes(nodes_of(hertz, refined.mesh), nodes_of(hertz_fine, build_problem(hertz_fine)->mesh), "hertz");
}

TEST(Adapt, TheWarmStartReachesTheSameSolution) {
  const Scene s = example(8);
  const auto coarse = app::solve_scene(s);
  ASSERT_TRUE(coarse.estimate);
  const RefinedMesh refined = refine_mesh(coarse.built->mesh, dorfler_marking(coarse.estimate->indicators, 0.5));
  app::SceneSolveOptions cold;
  cold.mesh = refined.mesh;
  cold.apply_region_boxes = false;
  app::SceneSolveOptions warm = cold;
  warm.start = prolongate(refined, coarse.solution.u);
  const auto a = app::solve_scene(s, cold);
  const auto b = app::solve_scene(s, warm);
  ASSERT_TRUE(a.solution.converged());
  ASSERT_TRUE(b.solution.converged());
  EXPECT_LE(b.solution.iterations(), a.solution.iterations());
  EXPECT_LT((a.solution.u - b.solution.u).lpNorm<Eigen::Infinity>(), 1e-8 * a.solution.u.lpNorm<Eigen::Infinity>());
  app::SceneSolveOptions wrong = cold;
  wrong.start = Eigen::VectorXd::Zero(3);
  EXPECT_THROW((void)app::solve_scene(s, wrong), InputError);
}

// Every kind of mesh a scene names refines: generators on rectangles and polygons (edge
// groups follow), Gmsh files, an obstacle, friction.
TEST(Adapt, EveryShippedKindOfSceneAdapts) {
  struct Case {
    const char* file;
    std::vector<std::string> overrides;
  };
  const std::vector<Case> cases{
      {"polygon-bracket.toml", {"mesh.n=8"}},
      {"hertz.toml", {"mesh.n=16"}},
      {"paper-example-4.1-voronoi.toml", {"mesh.n=8"}},
      {"friction-tresca.toml", {"mesh.n=[16, 4]"}},
      {"half-disk-on-plane.toml", {}},
  };
  for (const Case& c : cases) {
    Scene s = parse_scene(test::scenes_dir() / c.file);
    if (!c.overrides.empty()) apply_overrides(s, c.overrides);
    SceneAdapt a;
    a.max_steps = 3;
    a.target = 1e-3;
    const app::AdaptiveSolve r = app::solve_adaptively(s, a);
    ASSERT_EQ(r.steps.size(), 3u) << c.file << ": " << r.reason;
    for (const auto& st : r.steps) EXPECT_EQ(st.status, "converged") << c.file;
    EXPECT_GT(r.steps.back().unknowns, r.steps.front().unknowns) << c.file;
    EXPECT_LT(r.steps.back().estimate, r.steps.front().estimate) << c.file;
    EXPECT_LT(r.last.solution.forces.residual(), 1e-9) << c.file;
  }
}

}  // namespace
}  // namespace hemivem
