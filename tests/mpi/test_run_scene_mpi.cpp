// The library's one entry point (run_scene) on the full-space route across processes, given its
// output folder: every process keeps its piece of the mesh for the results where the files the
// scene writes are made from the pieces, and a file that the scene did not ask for before the
// solve, whose records were not gathered, is refused on every process; a path's last step is
// written from the pieces by every process, once.
#include <hemivem/app/run.hpp>
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "krylov_test_main.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hemivem;
using namespace hemivem::app;

/// A fresh folder name of this process's own in the temporary folder.
fs::path own_folder(const std::string& name) {
  return fs::temp_directory_path() / ("hemivem-run-scene-mpi-" + std::to_string(::getpid()) + "-" + name);
}

/// Example 4.1 on 16 x 16 squares, on the full-space route, writing result.json and stress.csv.
Scene example() {
  Scene scene = parse_scene(fs::path(HEMIVEM_SOURCE_DIR) / "scenes" / "paper-example-4.1.toml");
  scene.mesh.n = 16;
  scene.solver.linear = "petsc-gamg";
  scene.outputs = {"result-json", "stress-csv"};
  return scene;
}

TEST(RunSceneMpi, ThePiecesWriteTheWholeMeshsResultsAndRefuseAFigureNotAskedForBeforeTheSolve) {
  const ProcessWorld world = krylov_world();
  const fs::path out = own_folder("out"), other = own_folder("other");
  RunOptions o;
  o.out = out;
  const SceneRun run = run_scene(example(), o);
  ASSERT_TRUE(run.converged());
  // every process keeps its piece; the results say the whole mesh's
  const nlohmann::json r = run.result_json();
  EXPECT_EQ(r["mesh"]["vertices"], 17 * 17);
  EXPECT_EQ(r["mesh"]["elements"], 16 * 16);
  EXPECT_EQ(r["mesh"]["pieces"], world.size);
  const OutputReport written = run.write(out);
  if (world.rank == 0) {
    std::ifstream csv(out / "stress.csv");
    std::string line;
    int rows = -1;  // the header
    while (std::getline(csv, line)) ++rows;
    EXPECT_EQ(rows, 16 * 16);
    EXPECT_FALSE(written.written.empty());
  } else {
    EXPECT_FALSE(fs::exists(out));  // the first writes, the others' pieces are not asked for
  }
  // u_nu.png is drawn from the boundary edges gathered for it alone, which the scene did not ask
  // for: refused on every process
  const std::vector<std::string> files{"result.json", "u_nu.png"};
  try {
    run.write(other, &files);
    ADD_FAILURE() << "a figure written from a piece without the edges it is drawn from";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("u_nu.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(other));
  if (world.rank == 0) fs::remove_all(out);
}

// a loading path of one body given its output folder: the steps' files written as they came, and
// the last step's, with each process's piece of its solution.vtu, by one collective write; a
// second write is refused on the first process, and no process waits for another meanwhile
TEST(RunSceneMpi, APathsLastStepIsWrittenFromThePiecesOnceByEveryProcess) {
  const ProcessWorld world = krylov_world();
  Scene scene = parse_scene(fs::path(HEMIVEM_SOURCE_DIR) / "scenes" / "friction-coulomb.toml");
  scene.mesh.n = 12;
  scene.solver.linear = "petsc-gamg";
  scene.path->t = {0.5, 1.0, 1.5};
  scene.outputs = {"result-json", "vtu"};
  const fs::path out = own_folder("path");
  RunOptions o;
  o.out = out;
  const SceneRun run = run_scene(scene, o);
  ASSERT_TRUE(run.converged());
  const nlohmann::json r = run.result_json();
  EXPECT_EQ(r["mesh"]["vertices"], 13 * 13);
  EXPECT_EQ(r["mesh"]["pieces"], world.size);
  const OutputReport written = run.write(out);
  if (world.rank == 0) {
    EXPECT_FALSE(written.written.empty());
    EXPECT_TRUE(fs::exists(out / "solution.pvtu"));
    EXPECT_FALSE(fs::exists(out / "solution.vtu"));
    for (int k = 0; k < world.size; ++k) EXPECT_TRUE(fs::exists(out / ("solution.piece-" + std::to_string(k) + ".vtu"))) << k;
    EXPECT_TRUE(fs::exists(out / "path.json"));
    EXPECT_TRUE(fs::exists(out / "solution-0003.pvtu"));
  } else {
    EXPECT_TRUE(written.written.empty());
  }
  // written once: refused on the first process, which writes; the others return
  try {
    run.write(out);
    EXPECT_NE(world.rank, 0) << "a path's folder written twice";
  } catch (const InputError& e) {
    EXPECT_EQ(world.rank, 0);
    EXPECT_NE(std::string(e.what()).find("written once"), std::string::npos) << e.what();
  }
  if (world.rank == 0) {
    EXPECT_TRUE(fs::exists(out / "solution.pvtu"));  // the folder as the first write left it
    fs::remove_all(out);
  }
}

}  // namespace

int main(int argc, char** argv) {
  return hemivem::test::run_tests_on_every_process(argc, argv, "run_scene on the full-space route");
}
