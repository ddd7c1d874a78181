// What the plane has, the solid has, from the same solver (BasicContactSolver<dim>): several
// contact parts, the condition estimate and its warning, warm starts, the solver's stages.
// Each against an independent expectation: a part that never touches changes nothing, a warm
// start from the solution is the solution, the condition estimate of a nearly incompressible
// block exceeds the unreliable bound and that of a compressible one does not.
#include <hemivem/app/run.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "pressed_block3d.hpp"
#include "test_support.hpp"

using namespace hemivem;

namespace {

std::unique_ptr<SparseFactorization> engine() { return test::eigen_engine(); }

/// Example 4.1 in three dimensions (test::example_4_1_3d), its contact part named "foundation".
ContactProblem3D example(const Mesh3D& mesh) {
  ContactProblem3D p = test::example_4_1_3d(mesh);
  p.parts[0].name = "foundation";
  return p;
}

double max_abs(const Eigen::VectorXd& v) { return v.cwiseAbs().maxCoeff(); }

const Box kBox{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};

}  // namespace

TEST(SolidParity, APartThatNeverTouchesChangesNothing) {
  const Mesh3D mesh = make_mesh3d("cubes", {4, 2, 4}, kBox);
  const ContactProblem3D one = example(mesh);
  ContactProblem3D two = example(mesh);
  // a second part on the top, under a rigid plane far above it: the block moves down, away
  ContactPart3D lid;
  lid.name = "lid";
  lid.facets = select_box_side(mesh, kBox, "top");
  Obstacle3D plane;
  plane.point = Vec3(0.0, 0.0, 1.5);
  plane.normal = Vec3(0.0, 0.0, -1.0);
  lid.obstacle = plane;
  lid.law = zero_law();
  lid.constraint = ConstraintKind::one_sided;
  two.parts.push_back(lid);
  const ContactSolution3D a = solve_contact(one, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  const ContactSolution3D b = solve_contact(two, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(a.converged()) << a.message;
  ASSERT_TRUE(b.converged()) << b.message;
  EXPECT_LE(max_abs(a.u - b.u), 1e-9 * max_abs(a.u));
  EXPECT_NEAR(a.energy, b.energy, 1e-9 * std::abs(a.energy));
  ASSERT_EQ(b.contact_parts, (std::vector<std::string>{"foundation", "lid"}));
  int lid_nodes = 0;
  for (const ContactNode3D& n : b.contact) {
    if (n.part != 1) continue;
    ++lid_nodes;
    EXPECT_EQ(n.state, ContactState::separated) << n.vertex;
    EXPECT_EQ(n.force(), 0.0) << n.vertex;
    EXPECT_NEAR(n.gap, 0.5, 1e-15) << n.vertex;
  }
  EXPECT_EQ(lid_nodes, 3 * 3);  // the top's 5 x 3 nodes less the two clamped rows
  // the foundation's nodes carry the same forces as with one part
  ASSERT_EQ(a.contact.size() + 9, b.contact.size());
  EXPECT_LE((a.contact_force() - b.contact_force()).norm(), 1e-9 * a.contact_force().norm());
}

TEST(SolidParity, AFaceInTwoPartsIsRefusedNamingBoth) {
  const Mesh3D mesh = make_mesh3d("cubes", {2, 2, 2}, kBox);
  ContactProblem3D p = example(mesh);
  ContactPart3D again = p.parts[0];
  again.name = "again";
  p.parts.push_back(again);
  try {
    (void)solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    FAIL() << "a face in two parts was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'foundation'"), std::string::npos) << what;
    EXPECT_NE(what.find("'again'"), std::string::npos) << what;
  }
}

TEST(SolidParity, AWarmStartFromTheSolutionNeedsNoNewtonStep) {
  const Mesh3D mesh = make_mesh3d("cubes", {4, 2, 4}, kBox);
  const ContactProblem3D p = example(mesh);
  const ContactSolution3D cold = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(cold.converged());
  ASSERT_GT(cold.iterations(), 1);
  const auto minimizer = make_minimizer("ssn");
  const NonsmoothMinimizer* minimizers[] = {minimizer.get()};
  MinimizerOptions options;
  ContactSolver3D solver(p, engine(), options);
  solver.start_from(&cold.u);
  const ContactSolution3D warm = solver.run(minimizers).front();
  ASSERT_TRUE(warm.converged()) << warm.message;
  EXPECT_LT(warm.iterations(), cold.iterations());
  EXPECT_LE(max_abs(warm.u - cold.u), 1e-9 * max_abs(cold.u));
}

TEST(SolidParity, ASceneWithTwoContactPartsSolvesAndNamesThemInItsOutputs) {
  const std::string text = R"(schema_version = 1
title = "two parts"
[mesh]
generator = "cubes"
n = [4, 2, 4]
domain = [0.0, 1.0, 0.0, 0.5, 0.0, 1.0]
[material]
E = 65.0
nu = 0.29
[clamped]
side = ["x0", "x1"]
[[loads.traction]]
side = "top"
value = [0.0, 0.0, -8.0]
[[contact]]
name = "foundation"
side = "bottom"
law = "paper"
gap = 0.02
[[contact]]
name = "lid"
side = "top"
law = "zero"
constraint = "one-sided"
[contact.obstacle]
shape = "plane"
point = [0.0, 0.0, 1.5]
normal = [0.0, 0.0, -1.0]
)";
  const Scene scene = parse_scene_string(text, "two-parts.toml");
  const app::SceneRun run = app::run_scene(scene);
  ASSERT_NE(run.solid(), nullptr);
  ASSERT_TRUE(run.converged()) << run.solid()->solution.message;
  EXPECT_EQ(run.solid()->solution.contact_parts, (std::vector<std::string>{"foundation", "lid"}));
  // the same as the problem posed in code
  const Mesh3D mesh = make_mesh3d("cubes", {4, 2, 4}, kBox);
  const ContactSolution3D direct = solve_contact(example(mesh), engine(), *make_minimizer("ssn"), MinimizerOptions{});
  EXPECT_NEAR(run.solid()->solution.energy, direct.energy, 1e-9 * std::abs(direct.energy));
  const auto dir = std::filesystem::temp_directory_path() / ("hemivem-solid-parts-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  run.write(dir);
  std::ifstream csv(dir / "contact.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.substr(header.size() - 5), ",part");
  const nlohmann::json j = run.result_json();
  bool lid = false;
  for (const auto& node : j["contact"]) lid = lid || node["part"] == "lid";
  EXPECT_TRUE(lid);
  std::filesystem::remove_all(dir);
}

TEST(SolidParity, TheConditionEstimateWarnsForANearlyIncompressibleBlock) {
  for (const double nu : {0.29, 0.4999999999999}) {
    Scene scene = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
    apply_overrides(scene, {"mesh.n=[2, 2, 2]", nu == 0.29 ? "material.nu=0.29" : "material.nu=0.4999999999999"});
    const app::SceneRun run = app::run_scene(scene);
    const double condition = run.solid()->solution.condition_estimate;
    ASSERT_TRUE(std::isfinite(condition)) << nu;
    bool warned = false;
    for (const auto& w : run.warnings()) warned = warned || w.find("condition number") != std::string::npos;
    if (nu == 0.29) {
      EXPECT_LT(condition, app::unreliable_condition);
      EXPECT_FALSE(warned);
    } else {
      EXPECT_GE(condition, app::unreliable_condition);
      EXPECT_TRUE(warned);
    }
    EXPECT_TRUE(run.result_json()["condition_estimate"].is_number());
  }
}

TEST(SolidParity, ABlockBetweenRollersOnALinearFoundationSettlesByLoadOverStiffness) {
  // rollers on the four sides (the normal component only): nothing but the foundation holds the
  // block vertically; every contact node settles by the pressure over the stiffness, 2 / 50
  const app::SceneRun run = app::run_scene(parse_scene(test::scenes_dir() / "block-between-rollers-3d.toml"));
  const ContactSolution3D& s = run.solid()->solution;
  ASSERT_TRUE(s.converged()) << s.message;
  ASSERT_EQ(s.held_by_contact.size(), 1u);
  EXPECT_NE(s.held_by_contact[0].find("translation along (0, 0, 1)"), std::string::npos) << s.held_by_contact[0];
  ASSERT_EQ(s.contact.size(), 5u * 4u);
  for (const ContactNode3D& n : s.contact) {
    EXPECT_NEAR(n.u_nu, 2.0 / 50.0, 1e-10) << n.vertex;
    EXPECT_NEAR(n.pressure(), 2.0, 1e-9) << n.vertex;
  }
  // the block itself is in uniaxial strain: its top moves by the settlement plus p H / (lambda + 2 mu)
  const double lambda = 100.0 * 0.3 / (1.3 * 0.4), mu = 100.0 / 2.6;
  const double top = -(2.0 / 50.0 + 2.0 * 1.0 / (lambda + 2.0 * mu));
  const Mesh3D& mesh = run.solid()->built->mesh;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.vertex(v).z() == 1.0) EXPECT_NEAR(s.u(3 * v + 2), top, 1e-10) << v;
  // the forces balance: the foundation carries the load
  EXPECT_NEAR(s.contact_force().z(), 2.0 * 2.0 * 1.5, 1e-9);
}

TEST(SolidParity, AMeshOfOnesOwnIsSolvedAsTheScenesOwn) {
  Scene scene = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  apply_overrides(scene, {"mesh.n=[4, 2, 4]"});
  const app::SceneRun own = app::run_scene(scene);
  // the same cubes made by hand, and cubes of another size: the scene's sides are the mesh's
  app::RunOptions same;
  same.mesh = make_mesh3d("cubes", {4, 2, 4}, kBox);
  const app::SceneRun given = app::run_scene(scene, std::move(same));
  ASSERT_TRUE(given.converged());
  EXPECT_EQ(given.solid()->solution.u, own.solid()->solution.u);
  EXPECT_EQ(given.solid()->solution.energy, own.solid()->solution.energy);
  EXPECT_EQ(given.solid()->mesh_description, "a mesh given by the caller");
  app::RunOptions finer;
  finer.mesh = make_mesh3d("tetrahedra", {4, 2, 4}, kBox);
  const app::SceneRun tets = app::run_scene(scene, std::move(finer));
  ASSERT_TRUE(tets.converged());
  EXPECT_EQ(tets.solid()->built->mesh.num_cells(), make_mesh3d("tetrahedra", {4, 2, 4}, kBox).num_cells());
  // a plane mesh for a solid scene is refused by key
  app::RunOptions plane;
  plane.mesh = make_squares(2);
  plane.mesh_key = "mesh";
  try {
    (void)app::run_scene(scene, std::move(plane));
    FAIL() << "a plane mesh was taken for a solid";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "mesh");
  }
}
