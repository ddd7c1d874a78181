// Loading paths of solids, from the path solver the plane uses (BasicPathSolver<3>), through the
// one entry point (app::run_scene). Each against an independent expectation: a block on a linear
// foundation between rollers settles by t times load / stiffness at every step (uniaxial
// strain: exact for the lowest-order virtual element); the last step of a path is the static
// solve of the scene at t = 1, along a proportional path, a path whose load is an expression in
// t and a path of a moving obstacle; a path's files hold every step.
#include <gtest/gtest.h>

#include <hemivem/app/run.hpp>
#include <hemivem/error.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace hemivem::app {
namespace {

Scene rollers(const std::vector<std::string>& overrides = {}) {
  Scene s = parse_scene(test::scenes_dir() / "block-between-rollers-3d.toml");
  apply_overrides(s, overrides);
  return s;
}

double max_abs(const Eigen::VectorXd& v) { return v.cwiseAbs().maxCoeff(); }

// The contact nodes of a step of the rollers' block: u_nu = 0.04 t (2 t over the stiffness 50)
// and pressure 2 t, at every node.
void expect_uniaxial(const BasicPathStep<3>& step) {
  ASSERT_TRUE(step.converged()) << step.index << ": " << step.message;
  ASSERT_FALSE(step.contact.empty());
  for (const auto& n : step.contact) {
    EXPECT_NEAR(n.u_nu, 0.04 * step.t, 1e-10) << "step " << step.index << " vertex " << n.vertex;
    EXPECT_NEAR(n.pressure(), 2.0 * step.t, 1e-8) << "step " << step.index << " vertex " << n.vertex;
  }
  // the foundation carries the load: 2 t on an area of 2 x 1.5
  EXPECT_NEAR(step.contact_force.z(), 6.0 * step.t, 1e-8) << step.index;
  EXPECT_NEAR(step.applied.z(), -6.0 * step.t, 1e-12) << step.index;
}

TEST(SolidPath, EveryStepOfABlockOnAFoundationSettlesByTheLoadOverTheStiffness) {
  const SceneRun run = run_scene(rollers({"path.steps=4"}));
  ASSERT_EQ(run.dimension(), 3);
  EXPECT_EQ(run.kind(), RunKind::path);
  const BasicPathSolution<3>* path = run.solid_path();
  ASSERT_NE(path, nullptr);
  EXPECT_EQ(run.path(), nullptr);
  ASSERT_EQ(path->steps.size(), 4u);
  EXPECT_TRUE(path->proportional);
  EXPECT_TRUE(path->converged());
  EXPECT_EQ(path->jumps(), 0);
  for (const auto& step : path->steps) expect_uniaxial(step);
  // held by the foundation alone, at every step as in the static solve
  EXPECT_FALSE(path->last.held_by_contact.empty());
}

TEST(SolidPath, TheLastStepIsTheStaticSolve) {
  const SceneRun statics = run_scene(rollers());
  const SceneRun proportional = run_scene(rollers({"path.steps=3"}));
  // the load written as an expression in t: each step sets the problem's data to t (no scaling)
  const SceneRun general = run_scene(rollers({"path.steps=3", "loads.traction[0].value=[0, 0, \"-2*t\"]"}));
  ASSERT_TRUE(statics.converged());
  const Eigen::VectorXd& u = statics.solid()->solution.u;
  for (const SceneRun* run : {&proportional, &general}) {
    ASSERT_NE(run->solid_path(), nullptr);
    ASSERT_TRUE(run->converged()) << run->solid()->solution.message;
    const auto& last = run->solid()->solution;
    EXPECT_LE(max_abs(last.u - u), 1e-10 * max_abs(u));
    EXPECT_NEAR(last.energy, statics.solid()->solution.energy, 1e-9 * std::abs(statics.solid()->solution.energy));
    for (const auto& step : run->solid_path()->steps) expect_uniaxial(step);
  }
  EXPECT_TRUE(proportional.solid_path()->proportional);
  EXPECT_FALSE(general.solid_path()->proportional);
  // "-2*t" is t times the field at t = 1: the condensation's load serves every step
  EXPECT_EQ(proportional.solid_path()->condensed_loads, 1);
  EXPECT_EQ(general.solid_path()->condensed_loads, 1);
}

// The top's pressure t + t^2 written as two traction entries on one side: one field times a
// function of t, found from the loads themselves (one load condensed), and every step settles
// by its load.
TEST(SolidPath, TwoEntriesOfOneFieldAreOneLoad) {
  Scene scene = rollers({"path.steps=4", "loads.traction[0].value=[0, 0, \"-t\"]"});
  scene.tractions.push_back(scene.tractions.front());
  apply_overrides(scene, {"loads.traction[1].value=[0, 0, \"-(t^2)\"]"});
  const SceneRun run = run_scene(scene);
  ASSERT_NE(run.solid_path(), nullptr);
  ASSERT_TRUE(run.converged()) << run.solid()->solution.message;
  EXPECT_EQ(run.solid_path()->condensed_loads, 1);
  for (const auto& step : run.solid_path()->steps) {
    const double p = step.t + step.t * step.t;  // the pressure: u_nu = p / 50 at every contact node
    for (const auto& n : step.contact) EXPECT_NEAR(n.u_nu, p / 50.0, 1e-10) << "step " << step.index;
    EXPECT_NEAR(step.applied.z(), -3.0 * p, 1e-12) << step.index;
  }
}

// Hertz's sphere (scenes/hertz-sphere-3d.toml, coarse) lowered onto the block by a motion of
// the obstacle: the last step is the static solve with the sphere where the motion ends, and the
// resultant grows with the indentation.
TEST(SolidPath, AMovingObstacleEndsWhereTheStaticSolveIs) {
  Scene statics = parse_scene(test::scenes_dir() / "hertz-sphere-3d.toml");
  apply_overrides(statics, {"mesh.n=6"});
  Scene moving = statics;
  apply_overrides(moving, {"contact.obstacle.center=[0, 0, 1.0]", "contact.obstacle.motion=[0, 0, -0.01]",
                           "path.steps=4"});
  const SceneRun a = run_scene(statics);
  const SceneRun b = run_scene(moving);
  ASSERT_TRUE(a.converged());
  ASSERT_NE(b.solid_path(), nullptr);
  ASSERT_TRUE(b.converged()) << b.solid()->solution.message;
  EXPECT_FALSE(b.solid_path()->proportional);
  const Eigen::VectorXd& u = a.solid()->solution.u;
  EXPECT_LE(max_abs(b.solid()->solution.u - u), 1e-8 * max_abs(u));
  double before = 0.0;  // the sphere pushes the block down: -z grows
  for (const auto& step : b.solid_path()->steps) {
    ASSERT_TRUE(step.converged()) << step.index << ": " << step.message;
    EXPECT_GT(-step.contact_force.z(), before) << step.index;
    before = -step.contact_force.z();
  }
  EXPECT_NEAR(before, -a.solid()->solution.contact_force().z(), 1e-8 * before);
}

TEST(SolidPath, ThePathsFilesHoldEveryStep) {
  const Scene scene = rollers({"path.steps=3", "path.frames=2"});
  const SceneRun run = run_scene(scene);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hemivem-solid-path-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const OutputReport report = run.write(dir);
  for (const char* name : {"path.json", "path-contact.csv", "path-displacement.csv", "solution.pvd"})
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  nlohmann::json path;
  std::ifstream(dir / "path.json") >> path;
  EXPECT_EQ(path, path_json(*run.solid_path()));  // written a step at a time: the whole document
  ASSERT_EQ(path["steps"].size(), 3u);
  EXPECT_EQ(path["steps"][2]["applied_load"].size(), 3u);
  EXPECT_NEAR(path["steps"][2]["contact_force"][2].get<double>(), 6.0, 1e-8);
  nlohmann::json result;
  std::ifstream(dir / "result.json") >> result;
  EXPECT_EQ(result["dimension"], 3);
  EXPECT_EQ(result["path"]["steps"], 3);
  EXPECT_EQ(result["path"]["converged_steps"], 3);
  EXPECT_EQ(result["path"]["condensed_loads"], 1);
  std::ifstream contact(dir / "path-contact.csv");
  std::string header;
  std::getline(contact, header);
  EXPECT_EQ(header.rfind("step,t,vertex,x,y,z,u_nu,", 0), 0u) << header;
  // frames: two of three steps (the last always), each a row per vertex
  std::ifstream displacement(dir / "path-displacement.csv");
  std::getline(displacement, header);
  EXPECT_EQ(header, "step,t,vertex,x,y,z,ux,uy,uz");
  int rows = 0;
  for (std::string line; std::getline(displacement, line);) ++rows;
  EXPECT_EQ(rows, 2 * run.solid()->built->mesh.num_vertices());
  int frames = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    frames += e.path().filename().string().rfind("solution-", 0) == 0 ? 1 : 0;
  EXPECT_EQ(frames, 2);
  std::filesystem::remove_all(dir);
}

TEST(SolidPath, APathAcrossProcessesIsRefusedByItsKey) {
  const Scene scene = rollers({"path.steps=2", "solver.linear=\"mumps-mpi\""});
  try {
    run_scene(scene);
    FAIL() << "a path with mumps-mpi ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("one process"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mumps-mpi"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hemivem::app
