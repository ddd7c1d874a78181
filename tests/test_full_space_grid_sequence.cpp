// A grid sequence on the full-space route (solver.grid_sequence, docs/full-space.md): values
// carried onto a finer grid, the coarser grids a scene allows, and solves started from them that
// reach the condensed route's answer on the scene's own grid.
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/finer_grid.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/grid_sequence.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "test_support.hpp"

using namespace hemivem;

namespace {

// An affine field of `components` numbers at the points of a grid of `counts` boxes on the unit
// square or cube (counts[2] = 0 in the plane), numbered as the generators number them.
Eigen::VectorXd affine_on_grid(std::array<int, 3> counts, int components) {
  const int px = counts[0] + 1, py = counts[1] + 1, pz = counts[2] + 1;
  Eigen::VectorXd v(static_cast<Eigen::Index>(px) * py * pz * components);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i) {
        const double x = static_cast<double>(i) / counts[0], y = static_cast<double>(j) / counts[1],
                     z = counts[2] ? static_cast<double>(k) / counts[2] : 0.0;
        for (int c = 0; c < components; ++c)
          v((((static_cast<Eigen::Index>(k) * py) + j) * px + i) * components + c) =
              0.5 + (c + 1) * x - 2.0 * y + (3.0 - c) * z;
      }
  return v;
}

TEST(FinerGrid, AnAffineFieldIsCarriedExactlyInThePlane) {
  const Eigen::VectorXd coarse = affine_on_grid({3, 2, 0}, 2);
  const Eigen::VectorXd fine = values_on_finer_grid(coarse, GridSize(3, 2), 2);
  const Eigen::VectorXd expected = affine_on_grid({6, 4, 0}, 2);
  ASSERT_EQ(fine.size(), expected.size());
  EXPECT_LE((fine - expected).cwiseAbs().maxCoeff(), 1e-14);
  // the shared points keep their values bit for bit: coarse (2, 1) is fine (4, 2)
  EXPECT_EQ(fine.segment<2>(2 * (2 * 7 + 4)), coarse.segment<2>(2 * (1 * 4 + 2)));
}

TEST(FinerGrid, AnAffineFieldIsCarriedExactlyInTheSolid) {
  const Eigen::VectorXd coarse = affine_on_grid({2, 3, 2}, 3);
  const Eigen::VectorXd fine = values_on_finer_grid(coarse, GridSize3(2, 3, 2), 3);
  const Eigen::VectorXd expected = affine_on_grid({4, 6, 4}, 3);
  ASSERT_EQ(fine.size(), expected.size());
  EXPECT_LE((fine - expected).cwiseAbs().maxCoeff(), 1e-14);
  // a field that is not affine on a box: the point at a box's centre is the mean of its corners
  Eigen::VectorXd corner = Eigen::VectorXd::Zero(3 * 3 * 3);  // the grid of 2 x 2 x 2 boxes, one number each
  corner(0) = 8.0;                                            // the point (0, 0, 0)
  const Eigen::VectorXd centre = values_on_finer_grid(corner, GridSize3(2, 2, 2), 1);
  EXPECT_DOUBLE_EQ(centre((1 * 5 + 1) * 5 + 1), 1.0) << "the centre of box (0, 0, 0)";
  EXPECT_DOUBLE_EQ(centre(1), 4.0) << "the middle of the edge from (0, 0, 0)";
  EXPECT_DOUBLE_EQ(centre(2), 0.0) << "a point of the coarse grid";
}

TEST(FinerGrid, ValuesOfAnotherSizeAreRefused) {
  EXPECT_THROW(values_on_finer_grid(Eigen::VectorXd::Zero(7), GridSize(2, 2), 1), InputError);
  EXPECT_THROW(values_on_finer_grid(Eigen::VectorXd::Zero(27), GridSize3(2), 2), InputError);
  EXPECT_THROW(values_on_finer_grid(Eigen::VectorXd::Zero(9), GridSize(2), 0), InputError);
}

Scene scene_of(const std::string& file, const std::vector<std::string>& overrides) {
  Scene s = parse_scene(test::scenes_dir() / file);
  apply_overrides(s, overrides);
  return s;
}

// the message of the InputError grid_sequence_levels throws, which must name the key and its line
std::string refusal(const Scene& s, bool full_space, bool path) {
  try {
    grid_sequence_levels(s, full_space, path);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.grid_sequence"), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "not refused";
  return {};
}

TEST(GridSequence, AutoHalvesTheGridWhileEveryAxisKeepsSixteenBoxesOnTheFullSpaceRoute) {
  const auto levels = [](const std::string& file, const std::string& n, bool full_space = true, bool path = false) {
    return grid_sequence_levels(scene_of(file, {"mesh.n=" + n}), full_space, path);
  };
  EXPECT_EQ(levels("example-4.1-3d.toml", "96"), 2);  // 48, 24
  EXPECT_EQ(levels("example-4.1-3d.toml", "48"), 1);  // 24
  EXPECT_EQ(levels("example-4.1-3d.toml", "32"), 1);  // 16
  EXPECT_EQ(levels("example-4.1-3d.toml", "24"), 0);  // 12 is too few
  EXPECT_EQ(levels("example-4.1-3d.toml", "[64, 64, 32]"), 1);
  EXPECT_EQ(levels("example-4.1-3d.toml", "[64, 64, 30]"), 0);  // 15 along z
  EXPECT_EQ(levels("paper-example-4.1.toml", "256"), 4);  // 128, 64, 32, 16
  EXPECT_EQ(levels("paper-example-4.1-triangles.toml", "64"), 2);
  EXPECT_EQ(levels("paper-example-4.1.toml", "256", false), 0) << "the condensed route";
  EXPECT_EQ(levels("paper-example-4.1.toml", "256", true, true), 0) << "a loading path";
  EXPECT_EQ(levels("paper-example-4.1-voronoi.toml", "256"), 0) << "no grid of boxes";
  EXPECT_EQ(levels("paper-example-4.1-distorted.toml", "256"), 0) << "inner vertices moved at random";
  EXPECT_EQ(levels("paper-example-4.1-nonconvex.toml", "256"), 0) << "mid-points moved with the boxes' size";
  EXPECT_EQ(levels("extreme/bimaterial-1e6.toml", "256"), 0) << "a coarser cell's centroid lies elsewhere in the region boxes";
  // a support at a point or a segment may fall between a coarser grid's vertices
  Scene held = scene_of("paper-example-4.1.toml", {"mesh.n=256"});
  SceneDirichlet point;
  point.boundary.points = {{0.5, 1.0, 0.0}};
  point.ux = SceneScalar{0.0};
  held.dirichlet.push_back(point);
  EXPECT_EQ(grid_sequence_levels(held, true, false), 0) << "a point";
  Scene segment = scene_of("paper-example-4.1.toml", {"mesh.n=256"});
  ASSERT_TRUE(segment.contact);
  segment.contact->boundary = BoundarySelector{};
  segment.contact->boundary.segments = {{0.0, 0.0, 0.3, 0.0}};
  EXPECT_EQ(grid_sequence_levels(segment, true, false), 0) << "a segment";
  held.solver.grid_sequence = 1;
  EXPECT_NE(refusal(held, true, false).find("select sides"), std::string::npos);
  // a count: as many as asked, where every axis halves
  const Scene s = scene_of("example-4.1-3d.toml", {"mesh.n=[8, 8, 4]", "solver.grid_sequence=2"});
  EXPECT_EQ(grid_sequence_levels(s, true, false), 2);
  EXPECT_EQ(grid_sequence_levels(scene_of("paper-example-4.1.toml", {"mesh.n=256", "solver.grid_sequence=0"}), true, false),
            0);
  // the coarser scene: the box halved, nothing else changed
  const Scene coarse = coarser_grid_scene(scene_of("example-4.1-3d.toml", {"mesh.n=[8, 8, 4]"}));
  EXPECT_EQ(coarse.mesh.cells3(), GridSize3(4, 4, 2));
  EXPECT_EQ(coarse.solver.grid_sequence, 0);
  EXPECT_EQ(coarse.mesh.box, scene_of("example-4.1-3d.toml", {}).mesh.box);
}

TEST(GridSequence, ACountTheRouteThePathOrTheMeshDoesNotAllowIsRefusedByKey) {
  const Scene cubes = scene_of("example-4.1-3d.toml", {"mesh.n=[8, 8, 4]", "solver.grid_sequence=2"});
  EXPECT_NE(refusal(cubes, false, false).find("full-space route only"), std::string::npos);
  EXPECT_NE(refusal(cubes, true, true).find("loading path"), std::string::npos);
  const Scene three = scene_of("example-4.1-3d.toml", {"mesh.n=[8, 8, 4]", "solver.grid_sequence=3"});
  EXPECT_NE(refusal(three, true, false).find("mesh.n = [8, 8, 4] halves exactly into 2 coarser grids at most"),
            std::string::npos);
  const Scene odd = scene_of("paper-example-4.1.toml", {"mesh.n=30", "solver.grid_sequence=2"});
  EXPECT_NE(refusal(odd, true, false).find("into 1 coarser grid at most"), std::string::npos);
  const Scene voronoi = scene_of("paper-example-4.1-voronoi.toml", {"solver.grid_sequence=1"});
  EXPECT_NE(refusal(voronoi, true, false).find("grid of boxes"), std::string::npos);
}

TEST(GridSequence, TheKeyIsReadCheckedAndWrittenBack) {
  const Scene s = parse_scene_string("schema_version = 1\n[solver]\ngrid_sequence = 3\n", "count.toml");
  EXPECT_EQ(s.solver.grid_sequence, 3);
  EXPECT_EQ(parse_scene_string(to_toml(s), "again.toml").solver.grid_sequence, 3);
  const Scene a = parse_scene_string("schema_version = 1\n[solver]\ngrid_sequence = \"auto\"\n", "auto.toml");
  EXPECT_EQ(a.solver.grid_sequence, SceneSolver::grid_sequence_auto);
  EXPECT_EQ(parse_scene_string(to_toml(a), "again.toml").solver.grid_sequence, SceneSolver::grid_sequence_auto);
  EXPECT_EQ(parse_scene_string("schema_version = 1\n", "default.toml").solver.grid_sequence, SceneSolver::grid_sequence_auto);
  for (const char* bad : {"\"sometimes\"", "-1", "1.5", "31", "true"}) {
    SCOPED_TRACE(bad);
    try {
      parse_scene_string(std::string("schema_version = 1\n[solver]\ngrid_sequence = ") + bad + "\n", "bad.toml");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad.toml:3"), std::string::npos) << what;
      EXPECT_NE(what.find("grid_sequence"), std::string::npos) << what;
    }
  }
}

// The largest difference of two displacements against the largest of `b`.
double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  EXPECT_EQ(a.size(), b.size());
  if (a.size() != b.size()) return 1.0;
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// what a solve started from its coarser grids records of them: `grids` levels, coarsest first,
// each converged, a stage of the solve's own
template <class Solved>
void expect_sequence_recorded(const Solved& s, const std::vector<std::string>& grids) {
  const nlohmann::json& sequence = s.grid_sequence;
  ASSERT_EQ(sequence.size(), grids.size()) << sequence.dump();
  for (std::size_t l = 0; l < grids.size(); ++l) {
    const nlohmann::json& g = sequence[l];
    EXPECT_EQ(g.at("n"), grids[l]);
    EXPECT_TRUE(g.at("converged").get<bool>());
    EXPECT_GE(g.at("newton_iterations").get<int>(), 1);
    EXPECT_GE(g.at("krylov_iterations").get<int>(), g.at("newton_iterations").get<int>());
    EXPECT_GT(g.at("unknowns").get<int>(), 0);
    if (l > 0) EXPECT_GT(g.at("unknowns").get<int>(), sequence[l - 1].at("unknowns").get<int>());
  }
  EXPECT_LT(sequence.back().at("unknowns").get<int>(), s.solution.unknowns);
  ASSERT_FALSE(s.solution.stages.empty());
  EXPECT_EQ(s.solution.stages.front(), "grid_sequence");
  double seconds = 0.0;
  for (const auto& g : sequence) seconds += g.at("seconds").get<double>();
  EXPECT_GE(s.solution.timings.at("grid_sequence"), seconds);
  EXPECT_GE(s.solution.timings.at("total"), s.solution.timings.at("grid_sequence") + s.solution.timings.at("full_space"));
}

TEST(GridSequence, ThePlaneStartedFromItsCoarserGridsReachesTheCondensedRoutesAnswerInFewerNewtonIterations) {
  const std::vector<std::string> common = {"mesh.n=64", "solver.tolerance=1e-11"};
  auto with = [&](std::vector<std::string> more) {
    more.insert(more.begin(), common.begin(), common.end());
    return app::solve_scene(scene_of("paper-example-4.1.toml", more), app::SceneSolveOptions{});
  };
  const app::SceneSolve condensed = with({"solver.linear=\"eigen\"", "solver.grid_sequence=0"});
  const app::SceneSolve direct = with({"solver.linear=\"petsc-gamg\"", "solver.grid_sequence=0"});
  const app::SceneSolve sequenced = with({"solver.linear=\"petsc-gamg\""});  // auto: 32, 16
  for (const auto* s : {&condensed, &direct, &sequenced}) ASSERT_TRUE(s->solution.converged()) << s->solution.message;
  EXPECT_TRUE(direct.grid_sequence.empty());
  EXPECT_TRUE(condensed.grid_sequence.empty());
  expect_sequence_recorded(sequenced, {"16", "32"});
  EXPECT_LE(relative_difference(sequenced.solution.u, condensed.solution.u), 1e-8);
  EXPECT_LE(relative_difference(direct.solution.u, condensed.solution.u), 1e-8);
  EXPECT_LT(sequenced.solution.full_space->newton_iterations, direct.solution.full_space->newton_iterations);
}

TEST(GridSequence, TheSolidStartedFromItsCoarserGridsReachesTheCondensedRoutesAnswer) {
  const std::vector<std::string> common = {"mesh.n=[8, 8, 8]", "solver.tolerance=1e-11"};
  auto with = [&](std::vector<std::string> more) {
    more.insert(more.begin(), common.begin(), common.end());
    return app::solve_scene_3d(scene_of("example-4.1-3d.toml", more), {});
  };
  const app::SceneSolve3D condensed = with({"solver.linear=\"eigen\""});
  const app::SceneSolve3D sequenced = with({"solver.linear=\"petsc-gamg\"", "solver.grid_sequence=2"});
  ASSERT_TRUE(condensed.solution.converged()) << condensed.solution.message;
  ASSERT_TRUE(sequenced.solution.converged()) << sequenced.solution.message;
  expect_sequence_recorded(sequenced, {"2", "4"});
  EXPECT_LE(relative_difference(sequenced.solution.u, condensed.solution.u), 1e-8);
  EXPECT_NEAR(sequenced.solution.energy, condensed.solution.energy, 1e-9 * std::abs(condensed.solution.energy));
}

// a start or a mesh the caller gives is taken as it is: "auto" runs no grid sequence, a count is refused
TEST(GridSequence, AGivenStartOrMeshRunsNoneAndRefusesACount) {
  Scene scene = scene_of("paper-example-4.1.toml", {"mesh.n=64", "solver.linear=\"petsc-gamg\""});
  app::SceneSolveOptions given_mesh;
  given_mesh.mesh = make_squares(64);
  const app::SceneSolve on_mesh = app::solve_scene(scene, given_mesh);
  ASSERT_TRUE(on_mesh.solution.converged()) << on_mesh.solution.message;
  EXPECT_TRUE(on_mesh.grid_sequence.empty());
  app::SceneSolveOptions given_start;
  given_start.start = on_mesh.solution.u;
  const app::SceneSolve started = app::solve_scene(scene, given_start);
  ASSERT_TRUE(started.solution.converged()) << started.solution.message;
  EXPECT_TRUE(started.grid_sequence.empty());
  EXPECT_LE(started.solution.full_space->newton_iterations, 1) << "started at the answer";
  scene.solver.grid_sequence = 1;
  for (app::SceneSolveOptions* o : {&given_mesh, &given_start}) {
    if (o == &given_mesh) o->mesh = make_squares(64);
    try {
      app::solve_scene(scene, *o);
      ADD_FAILURE() << "a count with a given " << (o == &given_mesh ? "mesh" : "start") << " was taken";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("solver.grid_sequence = 1: this solve "), std::string::npos) << e.what();
    }
  }
}

TEST(GridSequence, TheCommandRecordsTheCoarserGridsAndRefusesACountByKey) {
  const std::filesystem::path out = test::scratch("grid-sequence");
  const test::CommandRun run = test::run_hemivem(
      "solve --n 32 --linear petsc-gamg --set solver.grid_sequence=1 --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.err;
  // the summary names the coarser grid and its time
  EXPECT_NE(run.out.find("\n  coarser grids n = 16: 510 unknowns, "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find(", grid_sequence "), std::string::npos) << run.out;
  // and tells it as it is solved, after the scene's mesh
  const std::size_t announced = run.err.find("hemivem: 1089 vertices");
  const std::size_t told = run.err.find("\nhemivem: coarser grid n = 16: 510 unknowns, ");
  EXPECT_NE(announced, std::string::npos) << run.err;
  EXPECT_NE(told, std::string::npos) << run.err;
  EXPECT_LT(announced, told) << run.err;
  const auto r = nlohmann::json::parse(test::slurp(out / "result.json"));
  ASSERT_EQ(r.at("full_space").at("grid_sequence").size(), 1u) << r["full_space"].dump();
  EXPECT_EQ(r["full_space"]["grid_sequence"][0]["n"], "16");
  EXPECT_EQ(r["stages"], (nlohmann::json{"grid_sequence", "assembly", "posing", "full_space", "estimate"}));
  EXPECT_GT(r["timings"]["grid_sequence"].get<double>(), 0.0);
  EXPECT_NE(test::slurp(out / "scene.toml").find("grid_sequence = 1"), std::string::npos);
  std::filesystem::remove_all(out);
  // the condensed route takes no grid sequence: refused by key before any work, nothing written
  const test::CommandRun refused =
      test::run_hemivem("solve --n 32 --linear eigen -q --set solver.grid_sequence=1 --out " + out.string());
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("solver.grid_sequence = 1: a grid sequence runs on the full-space route only"),
            std::string::npos)
      << refused.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
